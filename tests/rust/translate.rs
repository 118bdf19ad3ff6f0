//! Every shader variant, translated with no device by naga's backends into what each wgpu backend
//! compiles at pipeline creation: SPIR-V (Vulkan), MSL (Metal), HLSL (DX12) and GLSL (the GL
//! backend: desktop GLSL 4.50, as wgpu's GL backend caps Mesa's 4.60, and GLSL ES 3.10 for GLES
//! devices). A translation failure shows up here in `cargo test`, not on a user's Mac or
//! Windows machine. Each variant's resources are also checked against the limits of the
//! backends pomkit claims: `Limits::default()` (WebGPU's, which Vulkan, Metal and DX12 meet) and
//! `Limits::downlevel_defaults()` (GL 4.5 / GLES 3.1).

use naga::back::{glsl, hlsl, msl, spv};
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use pomkit::methods::builtin_variants;
use pomkit::shaders::{SceneDefs, ShaderLib};

fn validate(module: &naga::Module, what: &str) -> ModuleInfo {
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"))
}

/// The GLSL binding map wgpu's GL backend builds: one counter per kind of resource.
fn glsl_bindings(module: &naga::Module) -> glsl::BindingMap {
    let mut map = glsl::BindingMap::default();
    let (mut tex, mut samp, mut buf, mut ssbo, mut img) = (0u8, 0u8, 0u8, 0u8, 0u8);
    for (_, g) in module.global_variables.iter() {
        let Some(br) = g.binding.clone() else {
            continue;
        };
        let counter = match (&g.space, &module.types[g.ty].inner) {
            (naga::AddressSpace::Uniform, _) => &mut buf,
            (naga::AddressSpace::Storage { .. }, _) => &mut ssbo,
            (_, naga::TypeInner::Sampler { .. }) => &mut samp,
            (
                _,
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { .. },
                    ..
                },
            ) => &mut img,
            _ => &mut tex,
        };
        map.insert(br, *counter);
        *counter += 1;
    }
    map
}

fn translate(module: &naga::Module, info: &ModuleInfo, what: &str) -> usize {
    spv::write_vec(module, info, &spv::Options::default(), None)
        .unwrap_or_else(|e| panic!("{what}: SPIR-V: {e:?}"));
    let msl_opts = msl::Options {
        lang_version: (2, 4),
        ..Default::default()
    };
    msl::write_string(module, info, &msl_opts, &msl::PipelineOptions::default())
        .unwrap_or_else(|e| panic!("{what}: MSL: {e:?}"));
    // FXC's shader model 5.1 and DXC's 6.0: wgpu's DX12 backend takes the newest the system has
    for sm in [hlsl::ShaderModel::V5_1, hlsl::ShaderModel::V6_0] {
        let opts = hlsl::Options {
            shader_model: sm,
            ..Default::default()
        };
        let mut out = String::new();
        hlsl::Writer::new(&mut out, &opts, &hlsl::PipelineOptions::default())
            .write(module, info, None)
            .unwrap_or_else(|e| panic!("{what}: HLSL {sm:?}: {e:?}"));
    }
    let mut n = 4;
    for version in [
        glsl::Version::Desktop(450),
        glsl::Version::Embedded {
            version: 310,
            is_webgl: false,
        },
    ] {
        for ep in &module.entry_points {
            let opts = glsl::Options {
                version,
                writer_flags: glsl::WriterFlags::ADJUST_COORDINATE_SPACE,
                binding_map: glsl_bindings(module),
                zero_initialize_workgroup_memory: true,
            };
            let pipe = glsl::PipelineOptions {
                shader_stage: ep.stage,
                entry_point: ep.name.clone(),
                multiview: None,
            };
            let mut out = String::new();
            glsl::Writer::new(&mut out, module, info, &opts, &pipe, Default::default())
                .and_then(|mut w| w.write())
                .unwrap_or_else(|e| panic!("{what}: GLSL {version} ({}): {e:?}", ep.name));
            n += 1;
        }
    }
    n
}

/// Per stage, the resources of each kind the entry points use, against a backend's limits.
fn check_limits(
    module: &naga::Module,
    info: &ModuleInfo,
    limits: &wgpu::Limits,
    backend: &str,
    what: &str,
) {
    for (i, ep) in module.entry_points.iter().enumerate() {
        let used = info.get_entry_point(i);
        let (mut storage, mut uniform, mut sampled, mut samplers, mut images) =
            (0u32, 0u32, 0u32, 0u32, 0u32);
        let mut max_group = 0;
        for (h, g) in module.global_variables.iter() {
            if used[h].is_empty() {
                continue;
            }
            let Some(br) = &g.binding else { continue };
            max_group = max_group.max(br.group + 1);
            match (&g.space, &module.types[g.ty].inner) {
                (naga::AddressSpace::Uniform, _) => uniform += 1,
                (naga::AddressSpace::Storage { .. }, _) => storage += 1,
                (_, naga::TypeInner::Sampler { .. }) => samplers += 1,
                (
                    _,
                    naga::TypeInner::Image {
                        class: naga::ImageClass::Storage { .. },
                        ..
                    },
                ) => images += 1,
                _ => sampled += 1,
            }
        }
        let at = format!("{what}, entry point {} on {backend}", ep.name);
        assert!(
            max_group <= limits.max_bind_groups,
            "{at}: {max_group} bind groups"
        );
        assert!(
            storage <= limits.max_storage_buffers_per_shader_stage,
            "{at}: {storage} storage buffers"
        );
        assert!(
            uniform <= limits.max_uniform_buffers_per_shader_stage,
            "{at}: {uniform} uniform buffers"
        );
        assert!(
            sampled <= limits.max_sampled_textures_per_shader_stage,
            "{at}: {sampled} textures"
        );
        assert!(
            samplers <= limits.max_samplers_per_shader_stage,
            "{at}: {samplers} samplers"
        );
        assert!(
            images <= limits.max_storage_textures_per_shader_stage,
            "{at}: {images} storage textures"
        );
    }
}

fn limits() -> [(&'static str, wgpu::Limits); 2] {
    [
        (
            "Vulkan/Metal/DX12 (WebGPU defaults)",
            wgpu::Limits::default(),
        ),
        (
            "GL (downlevel defaults)",
            wgpu::Limits::downlevel_defaults(),
        ),
    ]
}

#[test]
fn every_variant_translates_to_every_backend() {
    let lib = ShaderLib::new().unwrap();
    let mut outputs = 0;
    let mut variants = 0;
    for m in builtin_variants() {
        let spec = m.spec();
        // plain; with a shadow map; and every frame def on (several transformed objects, sphere
        // lights, the cost and fragment counters)
        for (shadow_map, all) in [(false, false), (true, false), (true, true)] {
            let frame = SceneDefs {
                shadow_map,
                displaced_depth: all,
                count_fetches: all,
                count_fragments: all,
                transformed: all,
                sphere_lights: all,
                prefetch: all,
            };
            let what = format!("{m:?} ({frame:?})");
            let module = lib
                .compose(&spec, spec.pixel.filtering, frame, "method")
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            let info = validate(&module, &what);
            outputs += translate(&module, &info, &what);
            for (backend, l) in limits() {
                check_limits(&module, &info, &l, backend, &what);
            }
            variants += 1;
        }
    }
    for (src, file) in [
        (pomkit::render::mip_builder::MIPS_SHADER, "shaders/mips.wgsl"),
        (
            pomkit::methods::cone_step::CONE_MAP_SHADER,
            "src/methods/cone_step/cone_map.wgsl",
        ),
    ] {
        let module = lib.compose_pass(src, file).unwrap();
        let info = validate(&module, file);
        outputs += translate(&module, &info, file);
        for (backend, l) in limits() {
            check_limits(&module, &info, &l, backend, file);
        }
        variants += 1;
    }
    println!("{variants} shader modules, {outputs} translations (SPIR-V, MSL 2.4, HLSL SM 5.1 and 6.0, GLSL 4.50 and ES 3.10 per entry point)");
    assert!(variants > 80, "{variants} modules");
}

//! The mesh passes' pipelines. Bind groups by how often they change: group 0 the view and
//! frame, group 1 the object and its material (both one layout for every pass), group 2 the
//! method (its `params` and the resources it declares: one layout per declaration). One
//! pipeline per composed shader variant, keyed on the composed shader defs themselves.

use super::aovs::TARGETS;
use super::targets::{DEPTH_FORMAT, VISIBILITY_FORMAT};
use crate::contract::{Filtering, Geometry, Pass, ResourceKind, Spec};
use crate::error::{Error, Result};
use crate::gpu::{layout, Context};
use crate::mesh::Vertex;
use crate::shaders::{SceneDefs, ShaderLib};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// Depth test and write, less-than: the surface pass and the shadow-map pass.
pub fn depth_state() -> Option<wgpu::DepthStencilState> {
    Some(wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    })
}

crate::option_enum!(
    /// The pipeline a Renderer asks for (`pk.Renderer(pipeline=...)`): "raster", "compute", or
    /// "auto" (the adapter's rule: `Renderer::auto_kind`).
    Choice, "pipeline", {
        Auto = "auto",
        Raster = "raster",
        Compute = "compute",
    }
);

/// Which pipeline draws a frame: the fragment stage over the rasterised mesh, or a visibility
/// pass and the surface in compute (shaders/visibility.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Raster,
    Compute,
}

/// A variant's surface pipelines.
pub enum Main {
    Raster(wgpu::RenderPipeline),
    /// the visibility pass (triangle ids) and the surface per pixel
    Compute {
        visibility: wgpu::RenderPipeline,
        surface: wgpu::ComputePipeline,
    },
}

/// A pipeline over a triangle list with the passes' depth test: its vertex entry and buffers,
/// the faces it culls, and its fragment entry and colour targets (None: depth only).
fn mesh_pipeline(
    dev: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    (vs, buffers): (&str, &[Option<wgpu::VertexBufferLayout<'_>>]),
    cull_mode: Option<wgpu::Face>,
    fragment: Option<(&str, &[Option<wgpu::ColorTargetState>])>,
) -> wgpu::RenderPipeline {
    dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode,
            ..Default::default()
        },
        depth_stencil: depth_state(),
        multisample: Default::default(),
        fragment: fragment.map(|(fs, targets)| wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A variant's pipelines: the pass, the shadow-map pass (when the frame has a shadow map), and
/// the method's layout (its bind groups are made with it).
pub struct Variant {
    pub main: Main,
    pub shadow: Option<wgpu::RenderPipeline>,
    pub method: Arc<MethodLayout>,
}


pub struct Pipelines {
    pub lib: ShaderLib,
    /// group 0: the view block, the shadow map and its comparison sampler
    pub view_bgl: wgpu::BindGroupLayout,
    /// group 1: the object block, the height map and its sampler, the albedo and its sampler,
    /// the max pyramid (level 0, the atlas, the children atlas)
    pub object_bgl: wgpu::BindGroupLayout,
    /// group 3 of the visibility pass: the mesh's vertices and indices as storage
    pub visibility_bgl: wgpu::BindGroupLayout,
    /// group 3 of the compute surface pass: the mesh, the visibility target and the targets as
    /// storage textures (shaders/visibility.wgsl)
    pub compute_bgl: wgpu::BindGroupLayout,
    /// group 2 per declaration of a method's resources, with the pipeline layout over all three
    method_layouts: Mutex<HashMap<Vec<ResourceKind>, Arc<MethodLayout>>>,
    cache: Mutex<HashMap<u64, Arc<Variant>>>,
}

/// A method's bind-group layout (group 2) and the pipeline layouts of groups 0-2 (raster) and
/// 0-3 (the compute pipeline's two passes).
pub struct MethodLayout {
    pub bgl: wgpu::BindGroupLayout,
    pipeline: wgpu::PipelineLayout,
    visibility: wgpu::PipelineLayout,
    compute: wgpu::PipelineLayout,
}

/// The key of a shader variant: the composed shader defs themselves (the same `shaders::defs`
/// the composer takes), the module's identity and its `params` names (its source), the vertex
/// layout of its geometry, its resources' layout, and the targets written.
fn variant_key(
    spec: &Spec,
    filtering: Filtering,
    frame: SceneDefs,
    targets: [bool; TARGETS.len()],
    kind: Kind,
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    kind.hash(&mut h);
    let mut defs: Vec<(String, String)> = crate::shaders::defs(spec, filtering, frame)
        .into_iter()
        .map(|(k, v)| (k, format!("{v:?}")))
        .collect();
    defs.sort();
    defs.hash(&mut h);
    targets.hash(&mut h);
    match &spec.pass {
        Pass::Surface { method, marches } => {
            ("surface", method.path.as_str(), marches).hash(&mut h)
        }
        Pass::Own { shader, vs, fs, .. } => ("own", shader.path.as_str(), vs, fs).hash(&mut h),
    }
    for (k, _) in &spec.params {
        k.hash(&mut h);
    }
    format!("{:?}", vertex_layout(&spec.geometry)).hash(&mut h);
    spec.resources.as_ref().map(|r| r.layout()).hash(&mut h);
    h.finish()
}

pub fn vertex_layout(g: &Geometry) -> wgpu::VertexBufferLayout<'static> {
    match g {
        Geometry::Base => Vertex::layout(),
        Geometry::Own(g) => g.vertex_layout(),
    }
}

impl Pipelines {
    pub fn new(ctx: &Context) -> Result<Self> {
        let lib = ShaderLib::new()?;
        let filterable = ctx.caps.float32_filterable;
        ctx.scoped(|| {
            let dev = &ctx.device;
            let vf = wgpu::ShaderStages::FRAGMENT
                | wgpu::ShaderStages::VERTEX
                | wgpu::ShaderStages::COMPUTE;
            let uniform = |b: u32| layout::buffer(b, vf, wgpu::BufferBindingType::Uniform);
            let mut view_entries = vec![
                uniform(0),
                layout::texture(1, vf, wgpu::TextureSampleType::Depth),
                layout::sampler(2, vf, wgpu::SamplerBindingType::Comparison),
            ];
            if ctx.caps.fragment_counters {
                // the `fragments` AOV's counter (shaders/cost.wgsl), bound in every frame
                view_entries.push(layout::buffer(
                    3,
                    wgpu::ShaderStages::FRAGMENT,
                    wgpu::BufferBindingType::Storage { read_only: false },
                ));
            }
            let view_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit view"),
                entries: &view_entries,
            });
            let object_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit object"),
                entries: &super::object_group::layout_entries(filterable),
            });
            let storage = |b: u32, stages| {
                layout::buffer(
                    b,
                    stages,
                    wgpu::BufferBindingType::Storage { read_only: true },
                )
            };
            let visibility_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit visibility"),
                // (an adapter without the compute pipeline never binds it, and may lack
                // storage buffers in vertex shaders)
                entries: &{
                    let vs = if ctx.caps.compute_pipeline() {
                        wgpu::ShaderStages::VERTEX
                    } else {
                        wgpu::ShaderStages::COMPUTE
                    };
                    [storage(0, vs), storage(1, vs)]
                },
            });
            let cs = wgpu::ShaderStages::COMPUTE;
            let mut compute_entries = vec![
                storage(0, cs),
                storage(1, cs),
                layout::texture(2, cs, wgpu::TextureSampleType::Uint),
            ];
            for (i, t) in TARGETS.iter().enumerate() {
                compute_entries.push(layout::storage_texture(3 + i as u32, cs, t.format));
            }
            let compute_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit compute surface"),
                entries: if ctx.caps.compute_pipeline() {
                    &compute_entries
                } else {
                    &compute_entries[..3]
                },
            });
            Ok(Self {
                lib,
                view_bgl,
                object_bgl,
                visibility_bgl,
                compute_bgl,
                method_layouts: Mutex::new(HashMap::new()),
                cache: Mutex::new(HashMap::new()),
            })
        })
    }

    /// Group 2 of a method whose resources are `kinds` (binding 0: `params`), made once.
    pub fn method_layout(
        &self,
        ctx: &Context,
        kinds: &[ResourceKind],
    ) -> Result<Arc<MethodLayout>> {
        let mut g = self
            .method_layouts
            .lock()
            .map_err(|_| Error::Gpu("pipeline cache lock poisoned".into()))?;
        if let Some(l) = g.get(kinds) {
            return Ok(l.clone());
        }
        let vf =
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![layout::buffer(
            crate::shaders::PARAMS_BINDING,
            vf,
            wgpu::BufferBindingType::Uniform,
        )];
        for (i, k) in kinds.iter().enumerate() {
            let b = i as u32 + 1;
            entries.push(match k {
                ResourceKind::Storage => {
                    layout::buffer(b, vf, wgpu::BufferBindingType::Storage { read_only: true })
                }
                ResourceKind::TextureUint => layout::texture(b, vf, wgpu::TextureSampleType::Uint),
                ResourceKind::TextureFloat => {
                    layout::texture(b, vf, wgpu::TextureSampleType::Float { filterable: false })
                }
            });
        }
        let l = ctx.scoped(|| {
            let bgl = ctx
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("pomkit method"),
                    entries: &entries,
                });
            let layout = |label, third: Option<&wgpu::BindGroupLayout>| {
                let mut groups = vec![Some(&self.view_bgl), Some(&self.object_bgl), Some(&bgl)];
                if let Some(t) = third {
                    groups.push(Some(t));
                }
                ctx.device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some(label),
                        bind_group_layouts: &groups,
                        immediate_size: 0,
                    })
            };
            Ok(Arc::new(MethodLayout {
                pipeline: layout("pomkit pass", None),
                visibility: layout("pomkit visibility", Some(&self.visibility_bgl)),
                compute: layout("pomkit compute surface", Some(&self.compute_bgl)),
                bgl,
            }))
        })?;
        g.insert(kinds.to_vec(), l.clone());
        Ok(l)
    }

    /// The variant's pipelines, composed and created on first use. A compile error in a user's
    /// module is an `InvalidArgument` naming `arg`.
    pub fn get(
        &self,
        ctx: &Context,
        spec: &Spec,
        filtering: Filtering,
        frame: SceneDefs,
        written: [bool; TARGETS.len()],
        arg: &str,
        kind: Kind,
    ) -> Result<Arc<Variant>> {
        let key = variant_key(spec, filtering, frame, written, kind);
        if let Some(v) = self
            .cache
            .lock()
            .map_err(|_| Error::Gpu("pipeline cache lock poisoned".into()))?
            .get(&key)
        {
            return Ok(v.clone());
        }
        let module = self.lib.compose(spec, filtering, frame, arg)?;
        let kinds = spec
            .resources
            .as_ref()
            .map(|r| r.layout())
            .unwrap_or_default();
        let layout = self.method_layout(ctx, &kinds)?;
        let v = ctx.scoped(|| {
            let dev = &ctx.device;
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("pomkit pass"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
            let (vs, fs) = match &spec.pass {
                Pass::Surface { .. } => ("vs_main", "fs_main"),
                Pass::Own { vs, fs, .. } => (*vs, *fs),
            };
            // the shadow-map pass: a marched method writes its hit's depth from its fragment
            // stage; a mesh that is its own surface writes its rasterised depth
            let (shadow_vs, shadow_fs) = match &spec.pass {
                Pass::Surface { marches: true, .. } => ("vs_shadow", Some("fs_shadow")),
                Pass::Surface { marches: false, .. } => ("vs_shadow", None),
                Pass::Own {
                    shadow_vs,
                    shadow_fs,
                    ..
                } => (*shadow_vs, Some(*shadow_fs)),
            };
            let vertex_layout = vertex_layout(&spec.geometry);
            // a target no requested AOV needs is left out: its output is discarded
            let last = written.iter().rposition(|&b| b).map_or(0, |i| i + 1);
            let targets: Vec<Option<wgpu::ColorTargetState>> = (0..last)
                .map(|i| {
                    written[i].then_some(wgpu::ColorTargetState {
                        format: TARGETS[i].format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
                })
                .collect();
            let main = match kind {
                Kind::Compute => Main::Compute {
                    visibility: mesh_pipeline(
                        dev,
                        "pomkit visibility",
                        &layout.visibility,
                        &module,
                        ("vs_visibility", &[]),
                        Some(wgpu::Face::Back),
                        Some((
                            "fs_visibility",
                            &[Some(wgpu::ColorTargetState {
                                format: VISIBILITY_FORMAT,
                                blend: None,
                                write_mask: wgpu::ColorWrites::ALL,
                            })],
                        )),
                    ),
                    surface: dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some("pomkit compute surface"),
                        layout: Some(&layout.compute),
                        module: &module,
                        entry_point: Some("cs_main"),
                        compilation_options: Default::default(),
                        cache: None,
                    }),
                },
                Kind::Raster => Main::Raster(mesh_pipeline(
                    dev,
                    "pomkit pass",
                    &layout.pipeline,
                    &module,
                    (vs, &[Some(vertex_layout.clone())]),
                    Some(wgpu::Face::Back),
                    Some((fs, &targets)),
                )),
            };
            let shadow = frame.shadow_map.then(|| {
                mesh_pipeline(
                    dev,
                    "pomkit shadow map",
                    &layout.pipeline,
                    &module,
                    (shadow_vs, &[Some(vertex_layout)]),
                    // a mesh casts from both sides (an open mesh lit from behind), unless its
                    // geometry says otherwise
                    matches!(&spec.geometry, Geometry::Own(g) if g.shadow_cull_back())
                        .then_some(wgpu::Face::Back),
                    shadow_fs.map(|fs| (fs, &[][..])),
                )
            });
            Ok(Arc::new(Variant {
                main,
                shadow,
                method: layout.clone(),
            }))
        })?;
        self.cache
            .lock()
            .map_err(|_| Error::Gpu("pipeline cache lock poisoned".into()))?
            .insert(key, v.clone());
        Ok(v)
    }
}

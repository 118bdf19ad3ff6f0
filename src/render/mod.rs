//! Rendering: a method's pass over its geometry into the targets of the AOV table (aovs.rs), and
//! one readback of the AOVs asked for.
//!
//! - `pipelines`: the bind-group layouts (view, object, method) and one pipeline per composed
//!   shader variant
//! - `resources`: what stays resident (height maps, albedos, meshes, methods' own resources),
//!   keyed by content
//! - `aovs`: the AOV table (what each target holds, how it decodes) and the `Frame`
//! - `targets`: the render targets and their readback
//! - `uniforms`: the `View` and `ObjectUniforms` blocks (checked against the WGSL layout)
//! - `shadow_map`: the shadow-map pass
//! - `test_hooks`: hooks for the tests (the `test-hooks` feature) (a provoked validation error, the GPU's pyramids, a method's
//!   built resources), apart from the Renderer's API
//! - `supersample`: k x k samples per pixel, in one pass or in tiles, reduced to the frame
//! - `choice`: which pipeline draws a frame ("auto"'s probe); `compute`: the compute pipeline's
//!   passes; `limits`: the device's limits, checked before anything reaches the GPU
//!
//! The renderer binds what a method's `Spec` declares (src/contract.rs): its geometry, its
//! `params` and its own resources (and the argument its shader errors name). It names no method.

pub mod aovs;
mod choice;
pub mod mip_builder;
mod compute;
mod limits;
mod object_group;
pub mod pipelines;
pub mod resources;
pub mod shadow_map;
pub mod supersample;
pub mod targets;
#[cfg(any(test, feature = "test-hooks"))]
pub mod test_hooks;
pub mod uniforms;

pub use crate::heightmap::top_maxmip_level;
pub use supersample::SPP_TILE_SAMPLES;
pub use targets::{Aovs, Frame, DEPTH_FORMAT};

use crate::contract::{BuildInputs, Builders, Filtering, Geometry, GpuMesh, Resident, Spec};
use crate::error::{Error, Result};
use crate::gpu::Context;
use mip_builder::MipBuilder;
use crate::methods::Method;
use crate::scene::{HeightMap, Keyed, Scene};
use crate::shaders::SceneDefs;
use pipelines::{Kind, Pipelines};
use resources::{Draw, Resources};
use std::sync::{Arc, Mutex};
use targets::Targets;

/// "auto" draws in compute where the probe's compute time is below this fraction of its raster
/// time (the raster pipeline, the reference, keeps a tie).
pub const AUTO_MARGIN: f64 = 0.9;

/// Samplers, and the stand-in bound where a frame has no shadow map.
struct Fixed {
    height_sampler: wgpu::Sampler,
    albedo_sampler: wgpu::Sampler,
    shadow_sampler: wgpu::Sampler,
    no_shadow: wgpu::TextureView,
    /// the index array bound for a non-indexed mesh in the compute pipeline (one word:
    /// shaders/visibility.wgsl)
    no_indices: wgpu::Buffer,
}

impl Fixed {
    fn new(ctx: &Context) -> Result<Self> {
        ctx.scoped(|| {
            let dev = &ctx.device;
            let filterable = ctx.caps.float32_filterable;
            let filt = if filterable {
                wgpu::FilterMode::Linear
            } else {
                wgpu::FilterMode::Nearest
            };
            let mfilt = if filterable {
                wgpu::MipmapFilterMode::Linear
            } else {
                wgpu::MipmapFilterMode::Nearest
            };
            let repeat = |label, f, mf| {
                dev.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some(label),
                    address_mode_u: wgpu::AddressMode::Repeat,
                    address_mode_v: wgpu::AddressMode::Repeat,
                    address_mode_w: wgpu::AddressMode::Repeat,
                    mag_filter: f,
                    min_filter: f,
                    mipmap_filter: mf,
                    ..Default::default()
                })
            };
            let tex1 = |label, format, usage| {
                ctx.texture_2d(label, (1, 1), format, usage)
                    .create_view(&Default::default())
            };
            Ok(Fixed {
                height_sampler: repeat("height", filt, mfilt),
                albedo_sampler: repeat(
                    "albedo",
                    wgpu::FilterMode::Linear,
                    wgpu::MipmapFilterMode::Linear,
                ),
                shadow_sampler: dev.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("shadow"),
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    compare: Some(wgpu::CompareFunction::LessEqual),
                    ..Default::default()
                }),
                no_indices: ctx.upload("no indices", &[0u8; 4], wgpu::BufferUsages::STORAGE),
                no_shadow: tex1(
                    "no shadow map",
                    DEPTH_FORMAT,
                    wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
                ),
            })
        })
    }
}

pub struct Renderer {
    pub ctx: Arc<Context>,
    /// the pipeline asked for (pipelines::Choice)
    pub pipeline: pipelines::Choice,
    pipelines: Pipelines,
    fixed: Fixed,
    mips: MipBuilder,
    /// methods' compiled builder pipelines (made by the methods on first use)
    builders: Builders,
    resources: Mutex<Resources>,
    /// serialises GPU submissions so that error scopes and timings belong to one render
    submit: Mutex<()>,
    /// the last frame size's targets (used under `submit`)
    targets: Mutex<Vec<Arc<Targets>>>,
    /// the last shadow map's size and depth texture, kept for the next frame (the queue orders a
    /// frame's shadow pass after the previous frame's reads of the map)
    shadow_map: Mutex<Option<(u32, Arc<wgpu::TextureView>)>>,
}

fn poisoned<T>(_: T) -> Error {
    Error::Gpu("renderer lock poisoned".into())
}

impl Renderer {
    pub fn new(ctx: Arc<Context>, pipeline: pipelines::Choice) -> Result<Self> {
        let pipelines = Pipelines::new(&ctx)?;
        Ok(Self {
            pipeline,
            fixed: Fixed::new(&ctx)?,
            mips: MipBuilder::new(&ctx, &pipelines.lib)?,
            builders: Builders::default(),
            pipelines,
            resources: Mutex::new(Resources::new()),
            submit: Mutex::new(()),
            targets: Mutex::new(Vec::new()),
            shadow_map: Mutex::new(None),
            ctx,
        })
    }

    /// What an object's draw binds, from the caches or built: its height map, its mesh (the
    /// base mesh or the method's own geometry) and the method's own resources.
    #[allow(clippy::type_complexity)]
    fn object_resources(
        &self,
        res: &mut Resources,
        obj: &crate::scene::Object,
        spec: &Spec,
    ) -> Result<(
        Arc<crate::heightmap::GpuHeight>,
        Arc<GpuMesh>,
        Option<Arc<Vec<Resident>>>,
    )> {
        let height = res.height(&self.ctx, &self.mips, &obj.material.height)?;
        let mesh = res.mesh(&self.ctx, obj, &spec.geometry)?;
        let own = match &spec.resources {
            Some(r) => {
                let inputs = BuildInputs {
                    ctx: &self.ctx,
                    composer: &self.pipelines.lib,
                    builders: &self.builders,
                    object: obj,
                    height_size: (height.width, height.height),
                    height_max: [&height.max0_view, &height.max_atlas_view],
                    mesh: &mesh,
                };
                Some(res.method(r.as_ref(), &inputs)?)
            }
            None => None,
        };
        Ok((height, mesh, own))
    }

    /// The filtering a method actually gets: exact where the adapter cannot filter float32.
    pub fn effective_filtering(&self, f: Filtering) -> Filtering {
        if self.ctx.caps.float32_filterable {
            f
        } else {
            Filtering::Exact
        }
    }

    /// Dynamic height fields: write `new` into the GPU texture that holds `old` (same size),
    /// rebuild both pyramids on the GPU, and re-key the cache entry. No pipeline is rebuilt and
    /// nothing is allocated. Returns false when `old` was not resident (it will upload on the
    /// next render instead).
    pub fn update_height(&self, old: &Keyed<HeightMap>, new: &Keyed<HeightMap>) -> Result<bool> {
        let mut res = self.resources.lock().map_err(poisoned)?;
        let old_key = old.key;
        let Some(g) = res.heights.get(old_key) else {
            return Ok(false);
        };
        if g.width != new.width || g.height != new.height {
            return Ok(false);
        }
        let _guard = self.submit.lock().map_err(poisoned)?;
        self.mips.update(&self.ctx, &g, new)?;
        self.ctx.wait()?;
        // methods' resources are keyed by what they are built from: those of the new map build
        // from the updated pyramid on their next use
        Ok(res.heights.rekey(old_key, new.key))
    }

    /// Render every AOV of one frame.
    pub fn render(&self, scene: &Scene, method: &Method) -> Result<Frame> {
        self.render_aovs(scene, method, Aovs::STANDARD)
    }

    /// Render one frame with the AOVs in `aovs`.
    pub fn render_aovs(&self, scene: &Scene, method: &Method, aovs: Aovs) -> Result<Frame> {
        let mut frames = self.render_many(std::slice::from_ref(scene), method, aovs)?;
        Ok(frames.pop().expect("one frame"))
    }

    /// Render many frames with one method, pipelined: frame i+1 is submitted before frame i is
    /// read back and unpacked, so that the unpacking overlaps the GPU's work. Each frame is the
    /// one `render_aovs` would give.
    pub fn render_many(&self, scenes: &[Scene], method: &Method, aovs: Aovs) -> Result<Vec<Frame>> {
        self.render_with(scenes, method, aovs, self.pipeline)
    }

    /// `render_many` with the pipeline `choice` (the Renderer's, or the probe's).
    fn render_with(
        &self,
        scenes: &[Scene],
        method: &Method,
        aovs: Aovs,
        choice: pipelines::Choice,
    ) -> Result<Vec<Frame>> {
        method.validate()?;
        // "auto"'s verdict is measured before the submission lock (the probe renders)
        let auto = choice == pipelines::Choice::Auto && self.auto_compute();
        self.ctx.check_alive()?;
        if aovs.counts_fragments() && !self.ctx.caps.fragment_counters {
            return Err(Error::arg(
                "aovs",
                format!(
                    "the `fragments` AOV counts with an atomic add in the fragment shader, and this adapter ({}) has no writable storage buffers in fragment shaders; leave `fragments` out, or use another adapter (python -m pomkit info lists what each has)",
                    self.ctx.info.name
                ),
            ));
        }
        let spec = method.spec();
        let filtering = self.effective_filtering(spec.pixel.filtering);
        let arg = spec.shader_arg;
        let mut frames = Vec::with_capacity(scenes.len());
        let _guard = self.submit.lock().map_err(poisoned)?;
        let mut pending: Option<Pending> = None;
        for scene in scenes {
            scene.validate()?;
            self.check_limits(scene)?;
            let shadow = shadow_map::setup(scene, &spec, self.ctx.limits.max_texture_dimension_2d);
            // the targets read back (one object: no object target, its id is 0 wherever hit),
            // and the ones the pass writes: those, or (where attachments cannot have gaps)
            // every target up to the last one read
            let read = aovs.targets_for(scene.objects.len());
            let kind = self.kind(choice, auto, scene, &spec, aovs)?;
            let written = match kind {
                // the compute pass stores every target
                Kind::Compute => [true; aovs::TARGETS.len()],
                Kind::Raster => aovs::written(read, self.ctx.caps.sparse_attachments),
            };
            let variant = self.pipelines.get(
                &self.ctx,
                &spec,
                filtering,
                SceneDefs {
                    shadow_map: shadow.is_some(),
                    displaced_depth: scene.objects.len() > 1,
                    count_fetches: aovs.counts_fetches(),
                    count_fragments: aovs.counts_fragments(),
                    transformed: scene.objects.iter().any(|o| !o.transform.is_identity()),
                    sphere_lights: scene
                        .lights
                        .iter()
                        .any(|l| matches!(l, crate::scene::Light::Sphere(_))),
                    prefetch: self.ctx.caps.prefetch,
                },
                written,
                arg,
                kind,
            )?;
            let shadow_view = shadow
                .as_ref()
                .map(|s| self.shadow_target(s.size))
                .transpose()?;
            let shadow_view = shadow_view.as_deref();
            let tg = self.targets(scene.camera.width, scene.camera.height)?;
            let (binds, draws) =
                self.draws(scene, &spec, &variant, shadow.as_ref(), shadow_view, &tg)?;
            let next = self.submit(
                tg,
                &variant,
                shadow_view,
                &binds,
                &draws,
                aovs,
                (read, written),
            )?;
            if let Some(p) = pending.replace(next) {
                frames.push(self.finish(p)?);
            }
        }
        if let Some(p) = pending {
            frames.push(self.finish(p)?);
        }
        Ok(frames)
    }

    /// Read back a submitted frame once its submission has finished.
    fn finish(&self, p: Pending) -> Result<Frame> {
        self.ctx.scoped(|| {
            self.ctx.wait_for(Some(p.submission.clone()))?;
            let wall_ms = p.t0.elapsed().as_secs_f64() * 1e3;
            p.targets
                .read(&self.ctx, p.submission, p.aovs, p.read, wall_ms)
        })
    }

    /// Render targets and readback buffers for a w x h frame that no pending frame is using
    /// (kept for the next frames of that size; a pipelined batch uses two).
    fn targets(&self, w: u32, h: u32) -> Result<Arc<Targets>> {
        let mut pool = self.targets.lock().map_err(poisoned)?;
        if let Some(t) = pool
            .iter()
            .find(|t| t.w == w && t.h == h && Arc::strong_count(t) == 1)
        {
            return Ok(t.clone());
        }
        // the pool holds the free ones of other sizes too, up to a few
        if pool.len() >= 4 {
            if let Some(i) = pool.iter().position(|t| Arc::strong_count(t) == 1) {
                pool.remove(i);
            }
        }
        let t = Arc::new(Targets::new(&self.ctx, w, h));
        pool.push(t.clone());
        Ok(t)
    }

    /// The shadow map's depth texture of `size` texels, made when the size changes.
    fn shadow_target(&self, size: u32) -> Result<Arc<wgpu::TextureView>> {
        let mut kept = self.shadow_map.lock().map_err(poisoned)?;
        if let Some((n, v)) = kept.as_ref() {
            if *n == size {
                return Ok(v.clone());
            }
        }
        let v = Arc::new(shadow_map::target(&self.ctx, size)?);
        *kept = Some((size, v.clone()));
        Ok(v)
    }

    /// Group 0 of a frame: the view block, the shadow map (or its stand-in) and, where the
    /// adapter has them, the targets' fragment counter.
    fn view_bind_group(
        &self,
        view: &wgpu::Buffer,
        shadow: &wgpu::TextureView,
        targets: &Targets,
    ) -> wgpu::BindGroup {
        use wgpu::BindingResource as R;
        let mut entries = vec![
            view.as_entire_binding(),
            R::TextureView(shadow),
            R::Sampler(&self.fixed.shadow_sampler),
        ];
        if let Some((c, _)) = &targets.counter {
            entries.push(c.as_entire_binding());
        }
        self.ctx
            .bind_group("view", &self.pipelines.view_bgl, entries)
    }

    /// The frame's view bind groups and every object's draw: its resources (made or found in
    /// the caches), its uniform block and its object and method bind groups.
    fn draws(
        &self,
        scene: &Scene,
        spec: &Spec,
        variant: &pipelines::Variant,
        shadow: Option<&shadow_map::ShadowSetup>,
        shadow_view: Option<&wgpu::TextureView>,
        targets: &Targets,
    ) -> Result<(FrameBinds, Vec<Draw>)> {
        let ctx = &self.ctx;
        let f = &self.fixed;
        let (params, binds) = ctx.scoped(|| {
            let params = ctx.upload(
                "method params",
                &crate::shaders::params_bytes(&spec.params),
                wgpu::BufferUsages::UNIFORM,
            );
            let view = ctx.upload(
                "view",
                bytemuck::bytes_of(&uniforms::view(scene, shadow)),
                wgpu::BufferUsages::UNIFORM,
            );
            let binds = FrameBinds {
                view: self.view_bind_group(&view, shadow_view.unwrap_or(&f.no_shadow), targets),
                // the shadow-map pass cannot sample the map it writes
                shadow: shadow_view.map(|_| self.view_bind_group(&view, &f.no_shadow, targets)),
            };
            Ok((params, binds))
        })?;
        let mut draws = Vec::with_capacity(scene.objects.len());
        let contacts = match &spec.geometry {
            Geometry::Own(g) if g.uses_contacts() && scene.objects.len() > 1 => {
                Some(self.resources.lock().map_err(poisoned)?.contacts(&scene.objects)?)
            }
            _ => None,
        };
        for (id, obj) in scene.objects.iter().enumerate() {
            let with_contacts;
            let obj = match &contacts {
                Some(c) => {
                    with_contacts = crate::scene::Object {
                        contacts: c[id].clone(),
                        ..obj.clone()
                    };
                    &with_contacts
                }
                None => obj,
            };
            let (height, albedo, mesh, own) = {
                let mut res = self.resources.lock().map_err(poisoned)?;
                let albedo = res.albedo(ctx, obj.material.albedo.as_deref())?;
                let (height, mesh, own) = self.object_resources(&mut res, obj, spec)?;
                (height, albedo, mesh, own)
            };
            let globals = uniforms::object_uniforms(scene, id, spec);
            let d = ctx.scoped(|| {
                let g = ctx.upload(
                    "globals",
                    bytemuck::bytes_of(&globals),
                    wgpu::BufferUsages::UNIFORM,
                );
                let object = ctx.bind_group(
                    "object",
                    &self.pipelines.object_bgl,
                    object_group::ObjectBindings {
                        globals: g.as_entire_binding(),
                        height: &height.view,
                        height_sampler: &f.height_sampler,
                        albedo: &albedo,
                        albedo_sampler: &f.albedo_sampler,
                        max0: &height.max0_view,
                        max_atlas: &height.max_atlas_view,
                        max_children: &height.max_children_view,
                    }
                    .resources(),
                );
                let mut m = vec![params.as_entire_binding()];
                if let Some(own) = &own {
                    m.extend(own.iter().map(Resident::binding));
                }
                let method = ctx.bind_group("method", &variant.method.bgl, m);
                Ok(Draw {
                    object,
                    method,
                    mesh: mesh.clone(),
                })
            })?;
            draws.push(d);
        }
        Ok((binds, draws))
    }

    fn submit(
        &self,
        tg: Arc<Targets>,
        variant: &pipelines::Variant,
        shadow_view: Option<&wgpu::TextureView>,
        binds: &FrameBinds,
        draws: &[Draw],
        aovs: Aovs,
        (read, written): ([bool; aovs::TARGETS.len()], [bool; aovs::TARGETS.len()]),
    ) -> Result<Pending> {
        let ctx = &self.ctx;
        ctx.scoped(|| {
            let mut enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("render"),
                });
            if let (Some(v), Some(p)) = (shadow_view, &variant.shadow) {
                shadow_map::encode(
                    &mut enc,
                    v,
                    p,
                    binds.shadow.as_ref().unwrap_or(&binds.view),
                    draws,
                );
            }
            if aovs.counts_fragments() {
                tg.encode_counter_clear(&mut enc);
            }
            match &variant.main {
                pipelines::Main::Compute {
                    visibility,
                    surface,
                } => self.encode_compute(&mut enc, &tg, (visibility, surface), binds, draws)?,
                pipelines::Main::Raster(main) => {
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("surface"),
                        color_attachments: &tg.attachments(written),
                        depth_stencil_attachment: Some(tg.depth_attachment()),
                        timestamp_writes: tg.queries.as_ref().map(|q| {
                            wgpu::RenderPassTimestampWrites {
                                query_set: q,
                                beginning_of_pass_write_index: Some(0),
                                end_of_pass_write_index: Some(1),
                            }
                        }),
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    pass.set_pipeline(main);
                    pass.set_bind_group(0, &binds.view, &[]);
                    for d in draws {
                        pass.set_bind_group(1, &d.object, &[]);
                        pass.set_bind_group(2, &d.method, &[]);
                        d.mesh.draw(&mut pass);
                    }
                }
            }
            tg.encode_readback(&mut enc, read, aovs.counts_fragments());
            let t0 = std::time::Instant::now();
            let submission = ctx.queue.submit([enc.finish()]);
            Ok(Pending {
                targets: tg,
                submission,
                t0,
                aovs,
                read,
            })
        })
    }
}

/// A frame's view bind groups (group 0): with its shadow map, and (when it has one) without it
/// for the shadow-map pass.
pub struct FrameBinds {
    pub view: wgpu::BindGroup,
    pub shadow: Option<wgpu::BindGroup>,
}

/// A submitted frame: its targets, its submission and when it was submitted.
struct Pending {
    targets: Arc<Targets>,
    submission: wgpu::SubmissionIndex,
    t0: std::time::Instant,
    aovs: Aovs,
    /// the targets read back
    read: [bool; aovs::TARGETS.len()],
}

//! The mesh passes' pipelines: one bind-group layout for every variant, and one pipeline per
//! composed shader variant (the method's module or pass, its shader defs, shadows, filtering).

use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::contract::{Filtering, Geometry, Pass, Spec};
use crate::error::{Error, Result};
use crate::geometry::prisms::PrismVertex;
use crate::gpu::{layout, Context};
use crate::mesh::Vertex;
use crate::shaders::{FrameDefs, ShaderLib};
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

/// A variant's pipelines: the pass, and (Tessellated with shadows) the shadow-map pass.
pub struct Variant {
    pub main: wgpu::RenderPipeline,
    pub shadow: Option<wgpu::RenderPipeline>,
}

pub struct Pipelines {
    pub lib: ShaderLib,
    pub bgl: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    cache: Mutex<HashMap<u64, Arc<Variant>>>,
}

/// The key of a shader variant: everything that shapes the composed module.
fn variant_key(
    spec: &Spec,
    filtering: Filtering,
    frame: FrameDefs,
    targets: (bool, bool, bool),
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    targets.hash(&mut h);
    frame.hash(&mut h);
    match &spec.pass {
        Pass::Surface { march } => {
            ("surface", march.as_ref().map(|m| m.path.as_str())).hash(&mut h)
        }
        Pass::Own { shader, .. } => ("own", shader.path.as_str()).hash(&mut h),
    }
    spec.defs.hash(&mut h);
    spec.pixel.shadows.hash(&mut h);
    filtering.hash(&mut h);
    // the params block is part of the module's source
    for (k, _) in &spec.params {
        k.hash(&mut h);
    }
    h.finish()
}

impl Pipelines {
    pub fn new(ctx: &Context) -> Result<Self> {
        let lib = ShaderLib::new()?;
        let filterable = ctx.caps.float32_filterable;
        ctx.scoped(|| {
            let dev = &ctx.device;
            let vf = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::VERTEX;
            let tex = |b: u32, filterable: bool| {
                layout::texture(b, vf, wgpu::TextureSampleType::Float { filterable })
            };
            let samp = |b: u32, filtering: bool| {
                layout::sampler(
                    b,
                    vf,
                    if filtering {
                        wgpu::SamplerBindingType::Filtering
                    } else {
                        wgpu::SamplerBindingType::NonFiltering
                    },
                )
            };
            let uint = |b: u32| layout::texture(b, vf, wgpu::TextureSampleType::Uint);
            let storage = |b: u32| {
                layout::buffer(b, vf, wgpu::BufferBindingType::Storage { read_only: true })
            };
            let uniform = |b: u32| layout::buffer(b, vf, wgpu::BufferBindingType::Uniform);
            // the bindings of shaders/globals.wgsl, then NCS's frame map, the prisms, the params,
            // the cone map
            let bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit surface"),
                entries: &[
                    uniform(0),
                    tex(1, filterable),
                    samp(2, filterable),
                    tex(3, true),
                    samp(4, true),
                    layout::texture(5, vf, wgpu::TextureSampleType::Depth),
                    layout::sampler(6, vf, wgpu::SamplerBindingType::Comparison),
                    storage(7),
                    uint(8),
                    storage(9),
                    uniform(crate::shaders::PARAMS_BINDING),
                    storage(11),
                ],
            });
            let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("pomkit surface"),
                bind_group_layouts: &[Some(&bgl)],
                immediate_size: 0,
            });
            Ok(Self {
                lib,
                bgl,
                layout,
                cache: Mutex::new(HashMap::new()),
            })
        })
    }

    /// The variant's pipelines, composed and created on first use. A compile error in a user's
    /// module is an `InvalidArgument` naming `arg`.
    pub fn get(
        &self,
        ctx: &Context,
        spec: &Spec,
        filtering: Filtering,
        frame: FrameDefs,
        (color, geo, id): (bool, bool, bool),
        arg: &str,
    ) -> Result<Arc<Variant>> {
        let key = variant_key(spec, filtering, frame, (color, geo, id));
        if let Some(v) = self
            .cache
            .lock()
            .map_err(|_| Error::Gpu("pipeline cache lock poisoned".into()))?
            .get(&key)
        {
            return Ok(v.clone());
        }
        let module = self.lib.compose(spec, filtering, frame, arg)?;
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
                Pass::Surface { march: Some(_) } => ("vs_shadow", Some("fs_shadow")),
                Pass::Surface { march: None } => ("vs_shadow", None),
                Pass::Own {
                    shadow_vs,
                    shadow_fs,
                    ..
                } => (*shadow_vs, Some(*shadow_fs)),
            };
            let vertex_layout = match spec.geometry {
                Geometry::Prisms { .. } => PrismVertex::layout(),
                _ => Vertex::layout(),
            };
            let target = Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            });
            let main = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("pomkit pass"),
                layout: Some(&self.layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout.clone())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: depth_state(),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    // a target no requested AOV needs is left out: its output is discarded
                    targets: &[
                        color.then(|| target.clone()).flatten(),
                        geo.then_some(target).flatten(),
                        id.then_some(wgpu::ColorTargetState {
                            format: super::targets::ID_FORMAT,
                            blend: None,
                            write_mask: wgpu::ColorWrites::ALL,
                        }),
                    ],
                }),
                multiview_mask: None,
                cache: None,
            });
            let shadow = frame.shadow_map.then(|| {
                dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("pomkit shadow map"),
                    layout: Some(&self.layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(shadow_vs),
                        compilation_options: Default::default(),
                        buffers: &[Some(vertex_layout)],
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        // a mesh casts from both sides (an open mesh lit from behind); the
                        // prisms' walks start where the light enters the shell
                        cull_mode: matches!(spec.geometry, Geometry::Prisms { .. })
                            .then_some(wgpu::Face::Back),
                        ..Default::default()
                    },
                    depth_stencil: depth_state(),
                    multisample: Default::default(),
                    fragment: shadow_fs.map(|fs| wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            });
            Ok(Arc::new(Variant { main, shadow }))
        })?;
        self.cache
            .lock()
            .map_err(|_| Error::Gpu("pipeline cache lock poisoned".into()))?
            .insert(key, v.clone());
        Ok(v)
    }
}

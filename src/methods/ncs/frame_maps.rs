//! Texture-space maps of the base mesh's frame for NCS (Chen & Chang 2008, Algorithm 1),
//! rendered on the GPU once per mesh and dilated past the chart borders.

use crate::contract::Composer;
use crate::error::Result;
use crate::gpu::{layout, Context};
use crate::mesh::Vertex;

pub const TEXSPACE_SHADER: &str = include_str!("texspace.wgsl");

/// Size of the maps (texels per side).
pub const MAP_SIZE: u32 = 512;
/// GPU bytes of one mesh's packed frame map: two Rgba32Uint texels (32 bytes) per map texel.
pub const MAP_BYTES: u64 = MAP_SIZE as u64 * MAP_SIZE as u64 * 32;
/// Dilation passes: each extends the charts by one texel.
pub const DILATE_PASSES: u32 = 8;

pub struct TexSpace {
    bake: wgpu::RenderPipeline,
    dilate: wgpu::ComputePipeline,
    dilate_layout: wgpu::BindGroupLayout,
    pack: wgpu::ComputePipeline,
    pack_layout: wgpu::BindGroupLayout,
}

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

impl TexSpace {
    pub fn new(ctx: &Context, lib: &dyn Composer) -> Result<Self> {
        let dev = &ctx.device;
        lib.register(&super::frame_map_unit())?;
        let naga_module = lib.compose_pass(TEXSPACE_SHADER, "src/methods/ncs/texspace.wgsl")?;
        ctx.scoped(|| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("pomkit texspace"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(naga_module)),
            });
            let bake_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("bake"),
                bind_group_layouts: &[],
                immediate_size: 0,
            });
            let target = Some(wgpu::ColorTargetState {
                format: FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            });
            let bake = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("ncs bake"),
                layout: Some(&bake_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_bake"),
                    compilation_options: Default::default(),
                    buffers: &[Some(Vertex::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_bake"),
                    compilation_options: Default::default(),
                    targets: &[target.clone(), target],
                }),
                multiview_mask: None,
                cache: None,
            });
            let cs = wgpu::ShaderStages::COMPUTE;
            let tex = |b: u32| layout::texture(b, cs, wgpu::TextureSampleType::Uint);
            let sto = |b: u32| layout::storage_texture(b, cs, FORMAT);
            let dilate_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("dilate"),
                entries: &[tex(0), tex(1), sto(2), sto(3)],
            });
            let dilate = ctx.compute_pipeline("dilate", &module, "dilate", &dilate_layout);
            let pack_layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pack"),
                entries: &[tex(0), tex(1), sto(2)],
            });
            let pack = ctx.compute_pipeline("pack", &module, "pack", &pack_layout);
            Ok(Self {
                bake,
                dilate,
                dilate_layout,
                pack,
                pack_layout,
            })
        })
    }

    /// Bake, dilate and pack the frame map of a mesh (32 bytes per texel, frame_map.wgsl).
    pub fn maps(
        &self,
        ctx: &Context,
        vbuf: &wgpu::Buffer,
        ibuf: &wgpu::Buffer,
        count: u32,
    ) -> Result<wgpu::TextureView> {
        let dev = &ctx.device;
        ctx.scoped(|| {
            let make = |label, width| {
                dev.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height: MAP_SIZE,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: FORMAT,
                    // COPY_SRC: the tests read the packed map back (tests/rust/ncs_frame_map.rs)
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                })
            };
            let a = [make("ncs N a", MAP_SIZE), make("ncs T a", MAP_SIZE)];
            let b = [make("ncs N b", MAP_SIZE), make("ncs T b", MAP_SIZE)];
            let va: Vec<wgpu::TextureView> = a
                .iter()
                .map(|t| t.create_view(&Default::default()))
                .collect();
            let vb: Vec<wgpu::TextureView> = b
                .iter()
                .map(|t| t.create_view(&Default::default()))
                .collect();
            let mut enc = dev.create_command_encoder(&Default::default());
            {
                let att = |v| {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("ncs bake"),
                    color_attachments: &[att(&va[0]), att(&va[1])],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.bake);
                pass.set_vertex_buffer(0, vbuf.slice(..));
                pass.set_index_buffer(ibuf.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..count, 0, 0..1);
            }
            for k in 0..DILATE_PASSES {
                let (src, dst) = if k % 2 == 0 { (&va, &vb) } else { (&vb, &va) };
                use wgpu::BindingResource::TextureView as V;
                let bg = ctx.bind_group(
                    "dilate",
                    &self.dilate_layout,
                    vec![V(&src[0]), V(&src[1]), V(&dst[0]), V(&dst[1])],
                );
                Context::dispatch_8x8(
                    &mut enc,
                    "dilate",
                    &self.dilate,
                    0,
                    &bg,
                    (MAP_SIZE, MAP_SIZE),
                );
            }
            // DILATE_PASSES is even: the result is back in `a`; pack it into one map, two texels
            // per frame-map texel (frame_map.wgsl)
            let packed = make("ncs frame map", 2 * MAP_SIZE);
            let pv = packed.create_view(&Default::default());
            use wgpu::BindingResource::TextureView as V;
            let bg = ctx.bind_group(
                "pack",
                &self.pack_layout,
                vec![V(&va[0]), V(&va[1]), V(&pv)],
            );
            Context::dispatch_8x8(&mut enc, "pack", &self.pack, 0, &bg, (MAP_SIZE, MAP_SIZE));
            ctx.queue.submit([enc.finish()]);
            Ok(pv)
        })
    }
}

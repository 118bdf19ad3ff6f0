//! The GPU's pyramids: compute pipelines (shaders/mips.wgsl) that fill a height map's mean mips,
//! its max-mip levels and the children atlas from level 0.

use crate::error::{Error, Result};
use crate::gpu::{layout, Context};
use crate::heightmap::*;
use crate::gpu::texels::{read_r32, read_texel_bytes};

/// Compute pipelines that fill the pyramids.
pub struct MipBuilder {
    layout: wgpu::BindGroupLayout,
    max_layout: wgpu::BindGroupLayout,
    mean: wgpu::ComputePipeline,
    max_cells: wgpu::ComputePipeline,
    max_reduce: wgpu::ComputePipeline,
    children_layout: wgpu::BindGroupLayout,
    max_children: wgpu::ComputePipeline,
}

pub const MIPS_SHADER: &str = include_str!("../../shaders/mips.wgsl");

impl MipBuilder {
    pub fn new(ctx: &Context, lib: &crate::shaders::ShaderLib) -> Result<Self> {
        let dev = &ctx.device;
        let naga_module = lib.compose_pass(MIPS_SHADER, "shaders/mips.wgsl")?;
        ctx.scoped(|| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("pomkit mips"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(naga_module)),
            });
            let cs = wgpu::ShaderStages::COMPUTE;
            let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
            let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("mips"),
                entries: &[
                    layout::texture(0, cs, unfilterable),
                    layout::storage_texture(1, cs, wgpu::TextureFormat::R32Float),
                ],
            });
            let mean = ctx.compute_pipeline("mips mean", &module, "reduce", &layout);
            // a level pass's group: its source, its destination (`format`) and its uniform
            let level_layout = |label: &str, format: wgpu::TextureFormat| {
                dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(label),
                    entries: &[
                        layout::texture(0, cs, unfilterable),
                        layout::storage_texture(1, cs, format),
                        layout::buffer(2, cs, wgpu::BufferBindingType::Uniform),
                    ],
                })
            };
            let max_layout = level_layout("max pyramid", wgpu::TextureFormat::R32Float);
            let mpl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("max pyramid"),
                bind_group_layouts: &[None, Some(&max_layout)],
                immediate_size: 0,
            });
            let make_in = |pl: &wgpu::PipelineLayout, entry: &str| {
                dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(pl),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let make = |entry: &str| make_in(&mpl, entry);
            let children_layout = level_layout("max children", CHILD_MAX_FORMAT);
            let cpl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("max children"),
                bind_group_layouts: &[None, None, Some(&children_layout)],
                immediate_size: 0,
            });
            let max_children = make_in(&cpl, "max_children");
            Ok(Self {
                mean,
                max_cells: make("max_cells"),
                max_reduce: make("max_reduce"),
                layout,
                max_layout,
                children_layout,
                max_children,
            })
        })
    }

    fn texture(ctx: &Context, label: &str, map: &HeightMap) -> wgpu::Texture {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: map.width,
                height: map.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: mip_count(map.width, map.height),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }

    /// Upload a height map and build both pyramids.
    pub fn create(&self, ctx: &Context, map: &HeightMap) -> Result<GpuHeight> {
        let g = ctx.scoped(|| {
            let tex = Self::texture(ctx, "height", map);
            use wgpu::TextureUsages as U;
            let r32 = wgpu::TextureFormat::R32Float;
            let (_, atlas) = max_atlas(map.width, map.height);
            let max0 = ctx.texture_2d(
                "height max level 0",
                (map.width, map.height),
                r32,
                U::TEXTURE_BINDING | U::STORAGE_BINDING | U::COPY_SRC,
            );
            let max_atlas = ctx.texture_2d(
                "height max atlas",
                atlas,
                r32,
                U::TEXTURE_BINDING | U::COPY_DST | U::COPY_SRC,
            );
            let max_children = ctx.texture_2d(
                "height max children",
                children_atlas(map.width, map.height).1,
                CHILD_MAX_FORMAT,
                U::TEXTURE_BINDING | U::STORAGE_BINDING | U::COPY_SRC,
            );
            let max_scratch = ctx.texture_2d(
                "height max scratch",
                level_size(map.width, map.height, 1),
                r32,
                U::STORAGE_BINDING | U::COPY_SRC,
            );
            let scratch = if ctx.caps.storage_mip_views {
                Vec::new()
            } else {
                (1..mip_count(map.width, map.height))
                    .map(|k| {
                        ctx.texture_2d(
                            "height mip scratch",
                            level_size(map.width, map.height, k),
                            wgpu::TextureFormat::R32Float,
                            wgpu::TextureUsages::TEXTURE_BINDING
                                | wgpu::TextureUsages::STORAGE_BINDING
                                | wgpu::TextureUsages::COPY_SRC,
                        )
                    })
                    .collect()
            };
            Ok(GpuHeight {
                width: map.width,
                height: map.height,
                mips: mip_count(map.width, map.height),
                view: tex.create_view(&Default::default()),
                tex,
                max0_view: max0.create_view(&Default::default()),
                max0,
                max_atlas_view: max_atlas.create_view(&Default::default()),
                max_atlas,
                max_children_view: max_children.create_view(&Default::default()),
                max_children,
                max_scratch,
                scratch,
            })
        })?;
        self.update(ctx, &g, map)?;
        Ok(g)
    }

    /// Read a pyramid back (tests): `max` selects the max-mip texture, else the sampling one.
    pub fn read_back(&self, ctx: &Context, g: &GpuHeight, max: bool) -> Result<Vec<Vec<f32>>> {
        if max {
            let (offs, (aw, ah)) = max_atlas(g.width, g.height);
            let mut out = vec![read_r32(ctx, &g.max0, 0, (g.width, g.height))?];
            if g.mips > 1 {
                let atlas = read_r32(ctx, &g.max_atlas, 0, (aw, ah))?;
                for k in 1..g.mips {
                    let (w, h) = level_size(g.width, g.height, k);
                    let x0 = offs[k as usize] as usize;
                    let mut lvl = Vec::with_capacity((w * h) as usize);
                    for y in 0..h as usize {
                        let row = y * aw as usize + x0;
                        lvl.extend_from_slice(&atlas[row..row + w as usize]);
                    }
                    out.push(lvl);
                }
            }
            return Ok(out);
        }
        (0..g.mips)
            .map(|k| read_r32(ctx, &g.tex, k, level_size(g.width, g.height, k)))
            .collect()
    }
    /// Read the children atlas back (tests): for each level k in 1 ..= top (index k - 1), each
    /// node's texel as its four unorm8 codes (`CHILD_MAX_CODES`), row-major (x: child (0, 1),
    /// y: (1, 1), z: (1, 0), w: (0, 0)).
    pub fn read_children(&self, ctx: &Context, g: &GpuHeight) -> Result<Vec<Vec<[u8; 4]>>> {
        let (offs, (aw, ah)) = children_atlas(g.width, g.height);
        let all = read_texel_bytes(ctx, &g.max_children, 0, (aw, ah), 4)?;
        Ok((1..offs.len())
            .map(|k| {
                let (w, h) = level_size(g.width, g.height, k as u32);
                let (ox, oy) = offs[k];
                (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| {
                        let i = 4 * ((oy + y) * aw + ox + x) as usize;
                        [all[i], all[i + 1], all[i + 2], all[i + 3]]
                    })
                    .collect()
            })
            .collect())
    }

    /// Replace the map's texels (same size) and rebuild both pyramids on the GPU.
    pub fn update(&self, ctx: &Context, g: &GpuHeight, map: &HeightMap) -> Result<()> {
        if map.width != g.width || map.height != g.height {
            return Err(Error::arg(
                "height",
                format!(
                    "update needs the same size: {}x{} vs {}x{}",
                    map.width, map.height, g.width, g.height
                ),
            ));
        }
        ctx.scoped(|| {
            ctx.queue.write_texture(
                g.tex.as_image_copy(),
                bytemuck::cast_slice(&map.data),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * map.width),
                    rows_per_image: Some(map.height),
                },
                wgpu::Extent3d {
                    width: map.width,
                    height: map.height,
                    depth_or_array_layers: 1,
                },
            );
            let dev = &ctx.device;
            let level = |t: &wgpu::Texture, k: u32| {
                t.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: k,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            };
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("mips"),
            });
            let mut dispatch = |pipe: &wgpu::ComputePipeline,
                                src: wgpu::TextureView,
                                dst: wgpu::TextureView,
                                k: u32| {
                use wgpu::BindingResource::TextureView as V;
                let bg = ctx.bind_group("mips", &self.layout, vec![V(&src), V(&dst)]);
                let wh = level_size(map.width, map.height, k);
                Context::dispatch_8x8(&mut enc, "reduce", pipe, 0, &bg, wh);
            };
            if g.scratch.is_empty() {
                for k in 1..g.mips {
                    dispatch(&self.mean, level(&g.tex, k - 1), level(&g.tex, k), k);
                }
            } else {
                // the same reduce, level by level through single-level textures (each read at
                // its level 0), each copied into its mip level of the sampling texture
                for k in 1..g.mips {
                    let src = if k == 1 {
                        level(&g.tex, 0)
                    } else {
                        g.scratch[k as usize - 2].create_view(&Default::default())
                    };
                    let dst = &g.scratch[k as usize - 1];
                    dispatch(&self.mean, src, dst.create_view(&Default::default()), k);
                }
                for k in 1..g.mips {
                    let (w, h) = level_size(map.width, map.height, k);
                    enc.copy_texture_to_texture(
                        g.scratch[k as usize - 1].as_image_copy(),
                        wgpu::TexelCopyTextureInfo {
                            texture: &g.tex,
                            mip_level: k,
                            origin: wgpu::Origin3d::ZERO,
                            aspect: wgpu::TextureAspect::All,
                        },
                        wgpu::Extent3d {
                            width: w,
                            height: h,
                            depth_or_array_layers: 1,
                        },
                    );
                }
            }
            // the max pyramid: cell maxima into level 0, then each 2x2 max level into the
            // scratch texture and from there into its place in the atlas
            let (offs, _) = max_atlas(map.width, map.height);
            let scratch_view = g.max_scratch.create_view(&Default::default());
            for k in 0..g.mips {
                let (sw, sh) = level_size(map.width, map.height, k.saturating_sub(1));
                let (dw, dh) = level_size(map.width, map.height, k);
                let src_off = if k >= 2 { offs[k as usize - 1] } else { 0 };
                let params: [u32; 8] = [sw, sh, dw, dh, src_off, 0, 0, 0];
                let ubuf = ctx.upload(
                    "max level",
                    bytemuck::cast_slice(&params),
                    wgpu::BufferUsages::UNIFORM,
                );
                use wgpu::BindingResource as R;
                let (src, dst, pipe) = match k {
                    0 => (level(&g.tex, 0), &g.max0_view, &self.max_cells),
                    1 => (g.max0_view.clone(), &scratch_view, &self.max_reduce),
                    _ => (g.max_atlas_view.clone(), &scratch_view, &self.max_reduce),
                };
                let bg = ctx.bind_group(
                    "max level",
                    &self.max_layout,
                    vec![
                        R::TextureView(&src),
                        R::TextureView(dst),
                        ubuf.as_entire_binding(),
                    ],
                );
                Context::dispatch_8x8(&mut enc, "max level", pipe, 1, &bg, (dw, dh));
                if k >= 1 {
                    enc.copy_texture_to_texture(
                        g.max_scratch.as_image_copy(),
                        wgpu::TexelCopyTextureInfo {
                            texture: &g.max_atlas,
                            mip_level: 0,
                            origin: wgpu::Origin3d {
                                x: offs[k as usize],
                                y: 0,
                                z: 0,
                            },
                            aspect: wgpu::TextureAspect::All,
                        },
                        wgpu::Extent3d {
                            width: dw,
                            height: dh,
                            depth_or_array_layers: 1,
                        },
                    );
                }
            }
            // the children atlas, from level 0 and the finished atlas
            let (coffs, _) = children_atlas(map.width, map.height);
            for k in 1..=top_maxmip_level(map.width, map.height) {
                let (dw, dh) = level_size(map.width, map.height, k);
                let src_off = if k >= 2 { offs[k as usize - 1] } else { 0 };
                let (ox, oy) = coffs[k as usize];
                let params: [u32; 8] = [src_off, 0, ox, oy, dw, dh, 0, 0];
                let ubuf = ctx.upload(
                    "max children level",
                    bytemuck::cast_slice(&params),
                    wgpu::BufferUsages::UNIFORM,
                );
                use wgpu::BindingResource as R;
                let src = if k == 1 {
                    &g.max0_view
                } else {
                    &g.max_atlas_view
                };
                let bg = ctx.bind_group(
                    "max children level",
                    &self.children_layout,
                    vec![
                        R::TextureView(src),
                        R::TextureView(&g.max_children_view),
                        ubuf.as_entire_binding(),
                    ],
                );
                Context::dispatch_8x8(
                    &mut enc,
                    "max children",
                    &self.max_children,
                    2,
                    &bg,
                    (dw, dh),
                );
            }
            ctx.queue.submit([enc.finish()]);
            Ok(())
        })
    }
}

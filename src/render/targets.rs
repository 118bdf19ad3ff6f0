//! The frame's render targets and their readback; the `Frame` is decoded from them as the AOV
//! table says (aovs.rs). Targets hold float32 bits in Rgba32Uint (exact on every backend; GL
//! cannot render to Rgba32Float): colour + steps|flags, uv + distance + lod, and the object id.

use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::gpu::Context;

use super::aovs::Texels;
pub use super::aovs::{Aovs, Frame};

/// The render targets and readback buffers of one frame size, kept for the next frame.
pub struct Targets {
    pub w: u32,
    pub h: u32,
    pub color_t: wgpu::Texture,
    pub geo_t: wgpu::Texture,
    pub color_v: wgpu::TextureView,
    pub geo_v: wgpu::TextureView,
    pub depth_v: wgpu::TextureView,
    pub id_t: wgpu::Texture,
    pub id_v: wgpu::TextureView,
    pub color_buf: wgpu::Buffer,
    pub geo_buf: wgpu::Buffer,
    pub id_buf: wgpu::Buffer,
    pub queries: Option<wgpu::QuerySet>,
    pub ts_resolve: Option<wgpu::Buffer>,
    pub ts_read: Option<wgpu::Buffer>,
}

/// Bytes per row of a readback buffer of the colour and geo targets (256-aligned).
pub fn row_bytes(w: u32) -> u64 {
    texel_row_bytes(w, 16)
}

/// Bytes per row of a readback buffer of `texel` bytes per pixel (256-aligned).
fn texel_row_bytes(w: u32, texel: u64) -> u64 {
    (w as u64 * texel).div_ceil(256) * 256
}

/// The object-id target's format: one u32 per pixel.
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

impl Targets {
    pub fn new(ctx: &Context, w: u32, h: u32) -> Self {
        let dev = &ctx.device;
        let tex = |label, format, usage| ctx.texture_2d(label, (w, h), format, usage);
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let color_t = tex("color", COLOR_FORMAT, rt);
        let geo_t = tex("geo", COLOR_FORMAT, rt);
        let id_t = tex("object", ID_FORMAT, rt);
        let depth_t = tex(
            "depth",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let buf = |label, size, usage| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let rb = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let ts = ctx.caps.timestamps;
        Targets {
            w,
            h,
            color_v: color_t.create_view(&Default::default()),
            geo_v: geo_t.create_view(&Default::default()),
            depth_v: depth_t.create_view(&Default::default()),
            color_buf: buf("color readback", row_bytes(w) * h as u64, rb),
            geo_buf: buf("geo readback", row_bytes(w) * h as u64, rb),
            id_v: id_t.create_view(&Default::default()),
            id_buf: buf("object readback", texel_row_bytes(w, 4) * h as u64, rb),
            id_t,
            queries: ts.then(|| {
                dev.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass time"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                })
            }),
            ts_resolve: ts.then(|| {
                buf(
                    "ts resolve",
                    16,
                    wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                )
            }),
            ts_read: ts.then(|| buf("ts read", 16, rb)),
            color_t,
            geo_t,
        }
    }

    /// The colour attachments, cleared: no hit is marked by distance -1.0 (as float32 bits).
    pub fn attachments(&self, aovs: Aovs) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 3] {
        let att = |view, clear| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        [
            aovs.color_target()
                .then(|| att(&self.color_v, wgpu::Color::TRANSPARENT))
                .flatten(),
            aovs.geo_target()
                .then(|| {
                    att(
                        &self.geo_v,
                        wgpu::Color {
                            r: 0.0,
                            g: 0.0,
                            b: (-1.0f32).to_bits() as f64,
                            a: 0.0,
                        },
                    )
                })
                .flatten(),
            aovs.id_target()
                .then(|| {
                    att(
                        &self.id_v,
                        wgpu::Color {
                            r: u32::MAX as f64,
                            g: 0.0,
                            b: 0.0,
                            a: 0.0,
                        },
                    )
                })
                .flatten(),
        ]
    }

    /// Copy the targets and the pass's timestamps into the readback buffers.
    pub fn encode_readback(&self, enc: &mut wgpu::CommandEncoder, aovs: Aovs) {
        for (t, b, used, texel) in [
            (&self.color_t, &self.color_buf, aovs.color_target(), 16),
            (&self.geo_t, &self.geo_buf, aovs.geo_target(), 16),
            (&self.id_t, &self.id_buf, aovs.id_target(), 4),
        ] {
            if !used {
                continue;
            }
            enc.copy_texture_to_buffer(
                t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: b,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(texel_row_bytes(self.w, texel) as u32),
                        rows_per_image: Some(self.h),
                    },
                },
                wgpu::Extent3d {
                    width: self.w,
                    height: self.h,
                    depth_or_array_layers: 1,
                },
            );
        }
        if let (Some(q), Some(res), Some(read)) = (&self.queries, &self.ts_resolve, &self.ts_read) {
            enc.resolve_query_set(q, 0..2, res, 0);
            enc.copy_buffer_to_buffer(res, 0, read, 0, 16);
        }
    }

    /// The Frame from the readback buffers once `submission` has finished.
    pub fn read(
        &self,
        ctx: &Context,
        submission: wgpu::SubmissionIndex,
        aovs: Aovs,
        wall_ms: f64,
    ) -> crate::Result<Frame> {
        // one wait for every buffer the frame reads
        let mut bufs: Vec<&wgpu::Buffer> = Vec::with_capacity(4);
        let (color, geo, id) = (aovs.color_target(), aovs.geo_target(), aovs.id_target());
        for (used, b) in [
            (color, &self.color_buf),
            (geo, &self.geo_buf),
            (id, &self.id_buf),
        ] {
            if used {
                bufs.push(b);
            }
        }
        if let Some(b) = &self.ts_read {
            bufs.push(b);
        }
        let (w, h) = (self.w as usize, self.h as usize);
        let period = ctx.queue.get_timestamp_period() as f64;
        ctx.map_read_all(&bufs, Some(submission), |raw| {
            let mut k = 0;
            let mut next = |used: bool| -> Option<&[u8]> {
                used.then(|| {
                    k += 1;
                    raw[k - 1]
                })
            };
            // rows of `texel` bytes per pixel, 256-aligned, into one pixel array
            fn rows<T: bytemuck::Pod + Copy>(
                raw: &[u8],
                w: usize,
                h: usize,
                texel: usize,
            ) -> Vec<T> {
                let rb = (w * texel).div_ceil(256) * 256;
                let mut out = Vec::with_capacity(w * h);
                for y in 0..h {
                    out.extend_from_slice(bytemuck::cast_slice::<u8, T>(
                        &raw[y * rb..y * rb + w * texel],
                    ));
                }
                out
            }
            let t = Texels {
                color: next(color).map(|r| rows::<[u32; 4]>(r, w, h, 16)),
                geo: next(geo).map(|r| rows::<[f32; 4]>(r, w, h, 16)),
                id: next(id).map(|r| rows::<u32>(r, w, h, 4)),
            };
            let gpu_ms = self.ts_read.as_ref().and_then(|_| {
                let t: &[u64] = bytemuck::cast_slice(&raw[k][..16]);
                (t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period / 1e6)
            });
            Frame::decode(self.w, self.h, aovs, &t, gpu_ms, wall_ms)
        })
    }
}

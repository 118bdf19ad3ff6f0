//! The frame's render targets, their readback, and the `Frame` unpacked from them. Targets hold
//! float32 bits in Rgba32Uint (exact on every backend; GL cannot render to Rgba32Float):
//! colour + steps|flags, and uv + distance + lod.

use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::gpu::Context;

/// Per-pixel results of one render. Arrays are row-major (H, W, ...), row 0 at the top.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// linear RGB, H*W*3
    pub color: Vec<f32>,
    /// hit uv in mesh uv space (unwrapped), H*W*2, NaN where no hit
    pub uv: Vec<f32>,
    /// distance eye -> hit, NaN where no hit
    pub depth: Vec<f32>,
    pub mask: Vec<bool>,
    /// height-map samples taken (view + shadow rays)
    pub steps: Vec<u32>,
    /// mip level used, NaN where no hit
    pub lod: Vec<f32>,
    /// bit 0: the march hit its iteration bound; bit 1: NCS early termination
    pub flags: Vec<u8>,
    /// GPU time of the render pass from timestamp queries, if the adapter has them
    pub gpu_ms: Option<f64>,
    /// wall time of submit-and-wait, always measured
    pub wall_ms: f64,
}

/// The render targets and readback buffers of one frame size, kept for the next frame.
pub struct Targets {
    pub w: u32,
    pub h: u32,
    pub color_t: wgpu::Texture,
    pub geo_t: wgpu::Texture,
    pub color_v: wgpu::TextureView,
    pub geo_v: wgpu::TextureView,
    pub depth_v: wgpu::TextureView,
    pub color_buf: wgpu::Buffer,
    pub geo_buf: wgpu::Buffer,
    pub queries: Option<wgpu::QuerySet>,
    pub ts_resolve: Option<wgpu::Buffer>,
    pub ts_read: Option<wgpu::Buffer>,
}

/// Bytes per row of a readback buffer (256-aligned).
pub fn row_bytes(w: u32) -> u64 {
    (w as u64 * 16).div_ceil(256) * 256
}

impl Targets {
    pub fn new(ctx: &Context, w: u32, h: u32) -> Self {
        let dev = &ctx.device;
        let tex = |label, format, usage| ctx.texture_2d(label, (w, h), format, usage);
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let color_t = tex("color", COLOR_FORMAT, rt);
        let geo_t = tex("geo", COLOR_FORMAT, rt);
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
        let ts = ctx.timestamps;
        Targets {
            w,
            h,
            color_v: color_t.create_view(&Default::default()),
            geo_v: geo_t.create_view(&Default::default()),
            depth_v: depth_t.create_view(&Default::default()),
            color_buf: buf("color readback", row_bytes(w) * h as u64, rb),
            geo_buf: buf("geo readback", row_bytes(w) * h as u64, rb),
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
    pub fn attachments(&self) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 2] {
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
            att(&self.color_v, wgpu::Color::TRANSPARENT),
            att(
                &self.geo_v,
                wgpu::Color {
                    r: 0.0,
                    g: 0.0,
                    b: (-1.0f32).to_bits() as f64,
                    a: 0.0,
                },
            ),
        ]
    }

    /// Copy the targets and the pass's timestamps into the readback buffers.
    pub fn encode_readback(&self, enc: &mut wgpu::CommandEncoder) {
        for (t, b) in [
            (&self.color_t, &self.color_buf),
            (&self.geo_t, &self.geo_buf),
        ] {
            enc.copy_texture_to_buffer(
                t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: b,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row_bytes(self.w) as u32),
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

    /// The Frame from the readback buffers (after the submission finished).
    pub fn read(&self, ctx: &Context, wall_ms: f64) -> crate::Result<Frame> {
        let mut frame = Frame::empty(self.w, self.h);
        frame.gpu_ms = match &self.ts_read {
            Some(b) => {
                let raw = ctx.read_buffer(b)?;
                let t: &[u64] = bytemuck::cast_slice(&raw);
                let period = ctx.queue.get_timestamp_period() as f64;
                (t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period / 1e6)
            }
            None => None,
        };
        let rb = row_bytes(self.w) as usize;
        ctx.map_read(&self.geo_buf, |g| frame.unpack_geo(rb, g))?;
        ctx.map_read(&self.color_buf, |c| frame.unpack_color(rb, c))?;
        frame.wall_ms = wall_ms;
        Ok(frame)
    }
}

impl Frame {
    fn empty(w: u32, h: u32) -> Self {
        let n = (w * h) as usize;
        Frame {
            width: w,
            height: h,
            color: vec![0.0; n * 3],
            uv: vec![f32::NAN; n * 2],
            depth: vec![f32::NAN; n],
            mask: vec![false; n],
            steps: vec![0; n],
            lod: vec![f32::NAN; n],
            flags: vec![0; n],
            gpu_ms: None,
            wall_ms: 0.0,
        }
    }

    /// uv, distance and lod from the geo target (distance < 0: no hit); sets the mask.
    fn unpack_geo(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        for y in 0..self.height as usize {
            let g: &[f32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 16]);
            for (x, px) in g.chunks_exact(4).enumerate() {
                if px[2] >= 0.0 {
                    let i = y * w + x;
                    self.mask[i] = true;
                    self.uv[2 * i] = px[0];
                    self.uv[2 * i + 1] = px[1];
                    self.depth[i] = px[2];
                    self.lod[i] = px[3];
                }
            }
        }
    }

    /// Colour, steps and flags from the colour target (steps and flags only where hit).
    fn unpack_color(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        for y in 0..self.height as usize {
            let c: &[u32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 16]);
            for (x, px) in c.chunks_exact(4).enumerate() {
                let i = y * w + x;
                self.color[3 * i] = f32::from_bits(px[0]);
                self.color[3 * i + 1] = f32::from_bits(px[1]);
                self.color[3 * i + 2] = f32::from_bits(px[2]);
                if self.mask[i] {
                    self.steps[i] = px[3] & 0x0fff_ffff;
                    self.flags[i] = (px[3] >> 28) as u8;
                }
            }
        }
    }
}

//! The frame's render targets and their readback; the `Frame` is decoded from them as the AOV
//! table says (aovs.rs). Targets hold float32 bits in uint formats (exact on every backend; GL
//! cannot render to Rgba32Float): colour + steps|flags, uv + distance + lod, the object id, and
//! the cost counters (aovs::TARGETS).

use crate::gpu::Context;

use super::aovs::Texels;

/// The depth target's format, in every pass that tests depth.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The visibility target's format: the nearest triangle's index + 1, 0 where none.
pub const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
pub use super::aovs::{Aovs, Frame, TARGETS};

/// One render target and its readback buffer.
pub struct Target {
    pub t: wgpu::Texture,
    pub v: wgpu::TextureView,
    pub buf: wgpu::Buffer,
}

/// The render targets and readback buffers of one frame size, kept for the next frame.
pub struct Targets {
    pub w: u32,
    pub h: u32,
    /// aligned with `TARGETS`
    pub targets: Vec<Target>,
    pub depth_v: wgpu::TextureView,
    /// the compute pipeline's visibility target (VISIBILITY_FORMAT), where the
    /// adapter has that pipeline
    pub visibility: Option<wgpu::TextureView>,
    pub queries: Option<wgpu::QuerySet>,
    pub ts_resolve: Option<wgpu::Buffer>,
    pub ts_read: Option<wgpu::Buffer>,
    /// the `fragments` AOV's counter (one u32 a pixel, shaders/cost.wgsl) and its readback,
    /// where the adapter has writable storage in fragment shaders (`fragment_counters`)
    pub counter: Option<(wgpu::Buffer, wgpu::Buffer)>,
}

/// Bytes per row of a readback buffer of the widest target (256-aligned).
pub fn row_bytes(w: u32) -> u64 {
    texel_row_bytes(w, 16)
}

/// Bytes per row of a readback buffer of `texel` bytes per pixel (256-aligned).
fn texel_row_bytes(w: u32, texel: u64) -> u64 {
    (w as u64 * texel).div_ceil(256) * 256
}

impl Targets {
    pub fn new(ctx: &Context, w: u32, h: u32) -> Self {
        let dev = &ctx.device;
        let buf = |label, size, usage| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let rb = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let compute = ctx.caps.compute_pipeline();
        let mut rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        if compute {
            // the compute pipeline stores into the same targets
            rt |= wgpu::TextureUsages::STORAGE_BINDING;
        }
        let targets = TARGETS
            .iter()
            .map(|d| {
                let t = ctx.texture_2d(d.label, (w, h), d.format, rt);
                Target {
                    v: t.create_view(&Default::default()),
                    t,
                    buf: buf(
                        d.label,
                        texel_row_bytes(w, 4 * d.words as u64) * h as u64,
                        rb,
                    ),
                }
            })
            .collect();
        let depth_t = ctx.texture_2d(
            "depth",
            (w, h),
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let ts = ctx.caps.timestamps;
        Targets {
            w,
            h,
            targets,
            depth_v: depth_t.create_view(&Default::default()),
            visibility: compute.then(|| {
                ctx.texture_2d(
                    "visibility",
                    (w, h),
                    VISIBILITY_FORMAT,
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                )
                .create_view(&Default::default())
            }),
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
            counter: ctx.caps.fragment_counters.then(|| {
                let size = (w as u64 * h as u64 * 4).max(4);
                (
                    buf(
                        "fragment counter",
                        size,
                        wgpu::BufferUsages::STORAGE
                            | wgpu::BufferUsages::COPY_SRC
                            | wgpu::BufferUsages::COPY_DST,
                    ),
                    buf("fragment counter read", size, rb),
                )
            }),
        }
    }

    /// The depth buffer of a frame's mesh pass (the raster pass, or the visibility pass): cleared
    /// to the far plane, not kept.
    pub fn depth_attachment(&self) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth_v,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }
    }

    /// The colour attachments of the targets `written`: the colour target cleared, the others
    /// loaded (`TargetDesc::clear`).
    pub fn attachments(
        &self,
        written: [bool; TARGETS.len()],
    ) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
        let last = written.iter().rposition(|&b| b).map_or(0, |i| i + 1);
        (0..last)
            .map(|i| {
                written[i].then(|| wgpu::RenderPassColorAttachment {
                    view: &self.targets[i].v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: match TARGETS[i].clear {
                            Some(c) => wgpu::LoadOp::Clear(wgpu::Color {
                                r: c[0] as f64,
                                g: c[1] as f64,
                                b: c[2] as f64,
                                a: c[3] as f64,
                            }),
                            None => wgpu::LoadOp::Load,
                        },
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect()
    }

    /// Zero the fragment counter before a pass that counts (COUNT_FRAGMENTS).
    pub fn encode_counter_clear(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some((c, _)) = &self.counter {
            enc.clear_buffer(c, 0, None);
        }
    }

    /// Copy the targets `read`, the fragment counter when `fragments`, and the pass's
    /// timestamps into the readback buffers.
    pub fn encode_readback(
        &self,
        enc: &mut wgpu::CommandEncoder,
        read: [bool; TARGETS.len()],
        fragments: bool,
    ) {
        if let (true, Some((c, r))) = (fragments, &self.counter) {
            enc.copy_buffer_to_buffer(c, 0, r, 0, c.size());
        }
        for ((tg, d), used) in self.targets.iter().zip(&TARGETS).zip(read) {
            if !used {
                continue;
            }
            enc.copy_texture_to_buffer(
                tg.t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &tg.buf,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(texel_row_bytes(self.w, 4 * d.words as u64) as u32),
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
        used: [bool; TARGETS.len()],
        wall_ms: f64,
    ) -> crate::Result<Frame> {
        // one wait for every buffer the frame reads
        let mut bufs: Vec<&wgpu::Buffer> = self
            .targets
            .iter()
            .zip(used)
            .filter(|(_, u)| *u)
            .map(|(t, _)| &t.buf)
            .collect();
        let n_targets = bufs.len();
        let fragments = aovs.counts_fragments() && self.counter.is_some();
        if let (true, Some((_, r))) = (fragments, &self.counter) {
            bufs.push(r);
        }
        if let Some(b) = &self.ts_read {
            bufs.push(b);
        }
        let (w, h) = (self.w as usize, self.h as usize);
        let period = ctx.queue.get_timestamp_period() as f64;
        ctx.map_read_all(&bufs, Some(submission), |raw| {
            let mut k = 0;
            let texels = std::array::from_fn(|i| {
                used[i].then(|| {
                    // rows of `words` u32 per pixel, 256-aligned, into one pixel array
                    let texel = 4 * TARGETS[i].words;
                    let rb = (w * texel).div_ceil(256) * 256;
                    let r = raw[k];
                    k += 1;
                    let mut out = Vec::with_capacity(w * h * TARGETS[i].words);
                    for y in 0..h {
                        out.extend_from_slice(bytemuck::cast_slice::<u8, u32>(
                            &r[y * rb..y * rb + w * texel],
                        ));
                    }
                    out
                })
            });
            let fragments = fragments
                .then(|| bytemuck::cast_slice::<u8, u32>(&raw[n_targets][..w * h * 4]).to_vec());
            let ts = n_targets + fragments.is_some() as usize;
            let gpu_ms = self.ts_read.as_ref().and_then(|_| {
                let t: &[u64] = bytemuck::cast_slice(&raw[ts][..16]);
                (t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period / 1e6)
            });
            Frame::decode(
                self.w,
                self.h,
                aovs,
                &Texels(texels, fragments),
                gpu_ms,
                wall_ms,
            )
        })
    }
}

//! The frame's render targets, their readback, and the `Frame` unpacked from them. Targets hold
//! float32 bits in Rgba32Uint (exact on every backend; GL cannot render to Rgba32Float):
//! colour + steps|flags, and uv + distance + lod.

use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::error::{Error, Result};
use crate::gpu::Context;

/// The AOVs a render returns, as a set. Targets that no requested AOV needs are neither written
/// nor read back: the colour target holds color, steps and flags; the geo target holds uv,
/// depth, lod and the mask (which steps and flags need too, to blank the pixels without a hit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Aovs(u8);

impl Aovs {
    pub const NAMES: [&'static str; 8] = [
        "color", "uv", "depth", "mask", "steps", "lod", "flags", "object",
    ];
    pub const ALL: Aovs = Aovs(0xff);

    fn bit(name: &str) -> Option<u8> {
        Self::NAMES.iter().position(|n| *n == name).map(|i| 1 << i)
    }
    /// The set of the named AOVs; at least one.
    pub fn parse<S: AsRef<str>>(names: &[S]) -> Result<Aovs> {
        let mut bits = 0;
        for n in names {
            bits |= Self::bit(n.as_ref()).ok_or_else(|| {
                Error::arg(
                    "aovs",
                    format!(
                        "unknown AOV {:?}; the AOVs are {}",
                        n.as_ref(),
                        Self::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if bits == 0 {
            return Err(Error::arg(
                "aovs",
                "name at least one AOV, e.g. aovs=(\"color\",)",
            ));
        }
        Ok(Aovs(bits))
    }
    pub fn has(self, name: &str) -> bool {
        Self::bit(name).is_some_and(|b| self.0 & b != 0)
    }
    fn any(self, names: &[&str]) -> bool {
        names.iter().any(|n| self.has(n))
    }
    /// Whether the colour target (colour, steps | flags) is written and read.
    pub fn color_target(self) -> bool {
        self.any(&["color", "steps", "flags"])
    }
    /// Whether the geo target (uv, distance, lod; the mask) is written and read.
    pub fn geo_target(self) -> bool {
        self.any(&["uv", "depth", "mask", "lod", "steps", "flags", "object"])
    }
    /// The AOVs whose targets a pass writes when the adapter cannot leave a gap in its colour
    /// attachments (`Capabilities::sparse_attachments` false): the targets before the last
    /// requested one are written too (and cleared), though not read back.
    pub fn dense(self) -> Aovs {
        let mut a = self;
        if a.id_target() {
            a.0 |= Self::bit("uv").unwrap_or(0);
        }
        if a.geo_target() {
            a.0 |= Self::bit("color").unwrap_or(0);
        }
        a
    }
    /// Whether the object-id target is written and read.
    pub fn id_target(self) -> bool {
        self.has("object")
    }
}

/// Per-pixel results of one render. Arrays are row-major (H, W, ...), row 0 at the top. The
/// AOVs not in `aovs` are empty.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub aovs: Aovs,
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
    /// bit 0: the march hit its iteration bound; bit 1: the march ended early, still inside the
    /// shell (the curved-silhouette method's early termination)
    pub flags: Vec<u8>,
    /// the index of the object hit in the scene's objects, -1 where no hit
    pub object: Vec<i32>,
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
        let mut frame = Frame::empty(self.w, self.h, aovs);
        // one wait for every buffer the frame reads
        let mut bufs: Vec<&wgpu::Buffer> = Vec::with_capacity(3);
        if aovs.geo_target() {
            bufs.push(&self.geo_buf);
        }
        if aovs.color_target() {
            bufs.push(&self.color_buf);
        }
        if aovs.id_target() {
            bufs.push(&self.id_buf);
        }
        if let Some(b) = &self.ts_read {
            bufs.push(b);
        }
        let rb = row_bytes(self.w) as usize;
        let period = ctx.queue.get_timestamp_period() as f64;
        ctx.map_read_all(&bufs, Some(submission), |raw| {
            let mut k = 0;
            if aovs.geo_target() {
                frame.unpack_geo(rb, raw[k]);
                k += 1;
            }
            if aovs.color_target() {
                frame.unpack_color(rb, raw[k]);
                k += 1;
            }
            if aovs.id_target() {
                frame.unpack_object(texel_row_bytes(self.w, 4) as usize, raw[k]);
                k += 1;
            }
            if self.ts_read.is_some() {
                let t: &[u64] = bytemuck::cast_slice(&raw[k][..16]);
                frame.gpu_ms = (t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period / 1e6);
            }
        })?;
        frame.wall_ms = wall_ms;
        Ok(frame)
    }
}

impl Frame {
    fn empty(w: u32, h: u32, aovs: Aovs) -> Self {
        let n = (w * h) as usize;
        fn sized<T: Clone>(on: bool, len: usize, v: T) -> Vec<T> {
            if on {
                vec![v; len]
            } else {
                Vec::new()
            }
        }
        Frame {
            width: w,
            height: h,
            aovs,
            color: sized(aovs.has("color"), n * 3, 0.0),
            uv: sized(aovs.has("uv"), n * 2, f32::NAN),
            depth: sized(aovs.has("depth"), n, f32::NAN),
            // the mask is kept whenever the geo target is read: steps and flags need it
            mask: sized(aovs.geo_target(), n, false),
            steps: sized(aovs.has("steps"), n, 0),
            lod: sized(aovs.has("lod"), n, f32::NAN),
            flags: sized(aovs.has("flags"), n, 0),
            object: sized(aovs.has("object"), n, -1),
            gpu_ms: None,
            wall_ms: 0.0,
        }
    }

    /// uv, distance and lod from the geo target (distance < 0: no hit); sets the mask.
    fn unpack_geo(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        let (uv, depth, lod) = (
            self.aovs.has("uv"),
            self.aovs.has("depth"),
            self.aovs.has("lod"),
        );
        for y in 0..self.height as usize {
            let g: &[f32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 16]);
            for (x, px) in g.chunks_exact(4).enumerate() {
                if px[2] >= 0.0 {
                    let i = y * w + x;
                    self.mask[i] = true;
                    if uv {
                        self.uv[2 * i] = px[0];
                        self.uv[2 * i + 1] = px[1];
                    }
                    if depth {
                        self.depth[i] = px[2];
                    }
                    if lod {
                        self.lod[i] = px[3];
                    }
                }
            }
        }
    }

    /// The object ids from the id target, where hit (the mask).
    fn unpack_object(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        for y in 0..self.height as usize {
            let ids: &[u32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 4]);
            for (x, id) in ids.iter().enumerate() {
                let i = y * w + x;
                if self.mask[i] {
                    self.object[i] = *id as i32;
                }
            }
        }
    }

    /// Colour, steps and flags from the colour target (steps and flags only where hit).
    fn unpack_color(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        let (color, steps, flags) = (
            self.aovs.has("color"),
            self.aovs.has("steps"),
            self.aovs.has("flags"),
        );
        for y in 0..self.height as usize {
            let row = &raw[y * row_bytes..y * row_bytes + w * 16];
            if color {
                let c: &[f32] = bytemuck::cast_slice(row);
                let out = &mut self.color[3 * y * w..3 * (y + 1) * w];
                for (o, px) in out.chunks_exact_mut(3).zip(c.chunks_exact(4)) {
                    o.copy_from_slice(&px[..3]);
                }
            }
            if steps || flags {
                let c: &[u32] = bytemuck::cast_slice(row);
                for (x, px) in c.chunks_exact(4).enumerate() {
                    let i = y * w + x;
                    if self.mask[i] {
                        if steps {
                            self.steps[i] = px[3] & 0x0fff_ffff;
                        }
                        if flags {
                            self.flags[i] = (px[3] >> 28) as u8;
                        }
                    }
                }
            }
        }
    }
}

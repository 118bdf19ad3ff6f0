//! Supersampling: k x k stratified samples per pixel, rendered as one pass at k² the pixels or,
//! past `SPP_TILE_SAMPLES` a side, in tiles (windows of the full camera), and reduced to the
//! frame: colour the mean of a pixel's samples (Mitsuba's `box` rfilter), coverage the fraction
//! that hit, every other AOV from a one-sample pass at the pixel centres.

use super::aovs::{AovData, Aovs, Source, AOVS};
use super::{Frame, Renderer};
use crate::error::{Error, Result};
use crate::methods::Method;
use crate::scene::Scene;

/// Samples a side of one supersampled pass at most: larger frames render their samples in tiles
/// (`Renderer::render_many_spp`). 4096² samples are 320 MiB of targets and readback.
pub const SPP_TILE_SAMPLES: u32 = 4096;

impl Renderer {
    /// Render many frames at `spp` samples per pixel: a square number, k x k stratified samples
    /// on a regular grid in each pixel (k = 1: `render_many` itself, bit for bit). The samples
    /// are one pass at k² the pixels (the camera's width and height times k: one pass measured
    /// cheaper here than k² jittered passes, whose fixed cost per pass, a frame's clears,
    /// uploads and readback, repeats), reduced by `Frame::supersampled`: colour box-filtered as the
    /// Mitsuba reference's `box` rfilter, coverage the fraction of samples that hit, the other
    /// AOVs from the sample at (k/2, k/2). Each sample's LOD is its own footprint's.
    pub fn render_many_spp(
        &self,
        scenes: &[Scene],
        method: &Method,
        aovs: Aovs,
        spp: u32,
    ) -> Result<Vec<Frame>> {
        let k = (spp as f64).sqrt().round() as u32;
        if spp == 0 || k * k != spp || k > 16 {
            return Err(Error::arg(
                "spp",
                format!("must be a square number of samples per pixel from 1 to 256 (1, 4, 9, 16, ...: k x k per pixel), got {spp}"),
            ));
        }
        if k == 1 {
            return self.render_many(scenes, method, aovs);
        }
        // colour and coverage from the samples; the other AOVs from a one-sample pass
        let (ss, rest) = aovs.split_supersampled();
        let plain: Vec<Option<Frame>> = match rest {
            Some(a) => self
                .render_many(scenes, method, a)?
                .into_iter()
                .map(Some)
                .collect(),
            None => vec![None; scenes.len()],
        };
        let Some(ss) = ss else {
            return Ok(plain.into_iter().flatten().collect());
        };
        let tile = self.spp_tile(k);
        let untiled = scenes
            .iter()
            .all(|s| s.camera.width <= tile && s.camera.height <= tile);
        if untiled {
            let big: Vec<Scene> = scenes.iter().map(|s| Self::samples(s, k, None)).collect();
            let bigs = self.render_many(&big, method, ss)?;
            return Ok(bigs
                .into_iter()
                .zip(plain)
                .map(|(b, p)| Frame::supersampled(b, k, p))
                .collect());
        }
        // past the tile's size: the samples in tiles of at most `tile` pixels a side (windows
        // of the full camera), each reduced to its pixels before the next, so that memory is
        // bounded by one tile's k² samples whatever the frame's size
        scenes
            .iter()
            .zip(plain)
            .map(|(s, p)| Ok(self.render_tiled(s, method, ss, k, tile)?.with_plain(p)))
            .collect()
    }

    /// The supersampled colour and coverage (`aovs`) of `scene` at k x k samples per pixel,
    /// rendered in tiles of `tile` pixels a side (windows of the full camera), each reduced to
    /// its pixels before the next: memory is bounded by one tile's k² samples whatever the
    /// frame's size. Equal to one pass over the whole frame up to rasterisation rounding.
    pub fn render_tiled(
        &self,
        scene: &Scene,
        method: &Method,
        aovs: Aovs,
        k: u32,
        tile: u32,
    ) -> Result<Frame> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        let tile = tile.max(1);
        let mut tiles = Vec::new();
        for y0 in (0..h).step_by(tile as usize) {
            for x0 in (0..w).step_by(tile as usize) {
                let rect = (x0, y0, tile.min(w - x0), tile.min(h - y0));
                let big = Self::samples(scene, k, Some(rect));
                let f = self
                    .render_many(std::slice::from_ref(&big), method, aovs)?
                    .pop()
                    .expect("one frame");
                tiles.push(((x0, y0), Frame::reduced(f, k)));
            }
        }
        Ok(Frame::tiled(w, h, tiles))
    }

    /// Pixels a side of one supersampled pass at k x k samples per pixel: its k² samples within
    /// `SPP_TILE_SAMPLES` (and the device's texture limit) a side.
    fn spp_tile(&self, k: u32) -> u32 {
        (SPP_TILE_SAMPLES.min(self.ctx.limits.max_texture_dimension_2d) / k).max(1)
    }

    /// The scene of `s`'s samples at k x k per pixel: its camera k times as fine, over the whole
    /// image or over the window `rect` (x, y, w, h in pixels).
    fn samples(s: &Scene, k: u32, rect: Option<(u32, u32, u32, u32)>) -> Scene {
        let mut s = s.clone();
        s.camera.samples = k;
        let (w, h) = (s.camera.width, s.camera.height);
        if let Some((x0, y0, tw, th)) = rect {
            s.camera.window = Some(crate::scene::Window {
                full: (w * k, h * k),
                origin: (x0 * k, y0 * k),
            });
            (s.camera.width, s.camera.height) = (tw * k, th * k);
        } else {
            (s.camera.width, s.camera.height) = (w * k, h * k);
        }
        s
    }
}

impl Frame {
    /// A supersampled frame: `big`, a frame of `k` x `k` samples per pixel rendered as one
    /// (k w) x (k h) frame, gives colour as the mean of each pixel's samples (a box filter over
    /// the pixel, as the Mitsuba reference's `box` rfilter) and coverage as the fraction that hit;
    /// every other AOV (uv, depth, mask, steps, lod, flags, object, fetches, bytes) is `plain`'s,
    /// the one-sample frame's (its pixel centre), so that they keep their per-pixel meaning
    /// exactly. GPU and wall time are the two passes' sums.
    pub fn supersampled(big: Frame, k: u32, plain: Option<Frame>) -> Frame {
        Frame::reduced(big, k).with_plain(plain)
    }

    /// `big` (k x k samples per pixel) reduced to its pixels: colour the mean of each pixel's
    /// samples, coverage the fraction that hit; AOVs of another source are dropped.
    pub fn reduced(big: Frame, k: u32) -> Frame {
        let (k, bw) = (k as usize, big.width as usize);
        let (w, h) = (bw / k, big.height as usize / k);
        let mean = |v: &[f32], comps: usize| -> Vec<f32> {
            let mut out = vec![0.0f64; w * h * comps];
            for y in 0..h * k {
                for x in 0..w * k {
                    let o = ((y / k) * w + x / k) * comps;
                    let i = (y * bw + x) * comps;
                    for ch in 0..comps {
                        out[o + ch] += v[i + ch] as f64;
                    }
                }
            }
            let n = (k * k) as f64;
            out.into_iter().map(|x| (x / n) as f32).collect()
        };
        let mut aovs = Aovs(0);
        let data = AOVS
            .iter()
            .enumerate()
            .zip(big.data)
            .map(|((i, a), d)| match (a.source, d) {
                (Source::ColorRgb | Source::Coverage, Some(AovData::F32(v))) => {
                    aovs.0 |= 1 << i;
                    Some(AovData::F32(mean(&v, a.comps)))
                }
                _ => None,
            })
            .collect();
        Frame {
            width: w as u32,
            height: h as u32,
            aovs,
            data,
            gpu_ms: big.gpu_ms,
            wall_ms: big.wall_ms,
        }
    }

    /// This frame's AOVs with `plain`'s added where this frame has none (the one-sample pass of
    /// a supersampled frame); GPU and wall time are the sums.
    pub fn with_plain(mut self, plain: Option<Frame>) -> Frame {
        if let Some(p) = plain {
            debug_assert_eq!((p.width, p.height), (self.width, self.height));
            self.aovs = Aovs(self.aovs.0 | p.aovs.0);
            self.gpu_ms = self.gpu_ms.zip(p.gpu_ms).map(|(a, b)| a + b);
            self.wall_ms += p.wall_ms;
            for (d, r) in self.data.iter_mut().zip(p.data) {
                if d.is_none() {
                    *d = r;
                }
            }
        }
        self
    }

    /// A `width` x `height` frame from float AOVs rendered in tiles, each tile at its pixel
    /// origin (x, y); GPU and wall time are the tiles' sums.
    pub fn tiled(width: u32, height: u32, tiles: Vec<((u32, u32), Frame)>) -> Frame {
        let (w, h) = (width as usize, height as usize);
        let mut data: Vec<Option<AovData>> = vec![None; AOVS.len()];
        let mut aovs = Aovs(0);
        let (mut gpu, mut wall) = (Some(0.0), 0.0);
        for ((x0, y0), t) in tiles {
            aovs = Aovs(aovs.0 | t.aovs.0);
            gpu = gpu.zip(t.gpu_ms).map(|(a, b)| a + b);
            wall += t.wall_ms;
            let tw = t.width as usize;
            for ((a, d), src) in AOVS.iter().zip(data.iter_mut()).zip(t.data) {
                let Some(src) = src else { continue };
                let AovData::F32(v) = src else {
                    panic!("Frame::tiled pastes float AOVs only ({})", a.name)
                };
                let c = a.comps;
                let dst = match d.get_or_insert_with(|| AovData::F32(vec![0.0; w * h * c])) {
                    AovData::F32(dst) => dst,
                    _ => unreachable!(),
                };
                for (r, row) in v.chunks(tw * c).enumerate() {
                    let o = ((y0 as usize + r) * w + x0 as usize) * c;
                    dst[o..o + row.len()].copy_from_slice(row);
                }
            }
        }
        Frame {
            width,
            height,
            aovs,
            data,
            gpu_ms: gpu,
            wall_ms: wall,
        }
    }
}

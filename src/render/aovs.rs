//! The AOVs: one table (`AOVS`) says each one's name, type, size and where the shaders leave it
//! in the render targets (shaders/aov.wgsl). The set a render asks for, the targets it writes
//! and reads, the `Frame` it returns, the Python arrays (src/python/frame.rs) and Python's
//! `AOV_NAMES` all follow the table. Adding an AOV: a row here, and the shader line that writes
//! its channel (a new way of packing adds a `Source`).

use crate::error::{Error, Result};

/// Where an AOV is in the render targets, and how it is read back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// the colour target's channels 0..3 (float bits), every pixel
    ColorRgb,
    /// the colour target's channel 3, low 28 bits, where hit (0 elsewhere)
    ColorLow28,
    /// the colour target's channel 3, bits 28-30, where hit (0 elsewhere)
    ColorHigh4,
    /// the geo target's channels from `c` (float bits), where hit (NaN elsewhere)
    Geo(usize),
    /// the colour target's channel 3, bit 31 (`HIT_BIT`): the pixel shows a surface
    Hit,
    /// the fraction of the pixel's samples that hit (the hit bit; 0 or 1 at one sample per
    /// pixel, averaged by `Frame::supersampled`)
    Coverage,
    /// the id target, where hit (-1 elsewhere)
    Id,
    /// the cost target's channel `c` (shaders/cost.wgsl), where hit (0 elsewhere); written only
    /// when asked for (shader def COUNT_FETCHES)
    Cost(usize),
    /// the fragment counter (shaders/cost.wgsl: a storage buffer, `Targets::counter`), every
    /// pixel, hit or not; counted only when asked for (shader def COUNT_FRAGMENTS). It needs
    /// no render target: `target` names the colour target, which every frame reads.
    Fragments,
}

/// The colour target's bit that marks a hit (channel 3, bit 31; shaders/aov.wgsl).
pub const HIT_BIT: u32 = 1 << 31;

/// The render targets, in location order (shaders/aov.wgsl's `FsOut`): the format, its u32
/// words per texel, and the clear value. Only the colour target is cleared (black, no hit
/// bit): every other target is read only where the hit bit is set, so its stale texels are
/// never seen and clearing them would cost every frame their size in writes.
pub struct TargetDesc {
    pub label: &'static str,
    pub format: wgpu::TextureFormat,
    pub words: usize,
    pub clear: Option<[u32; 4]>,
}

pub const TARGETS: [TargetDesc; 4] = [
    TargetDesc {
        label: "color",
        format: wgpu::TextureFormat::Rgba32Uint,
        words: 4,
        clear: Some([0; 4]),
    },
    TargetDesc {
        label: "geo",
        format: wgpu::TextureFormat::Rgba32Uint,
        words: 4,
        clear: None,
    },
    TargetDesc {
        label: "object",
        format: wgpu::TextureFormat::R32Uint,
        words: 1,
        clear: None,
    },
    TargetDesc {
        label: "cost",
        // x, y: the counters; Rgba32Uint (not Rg32Uint) so that the compute pipeline can store
        // it on every adapter (wgpu's GL backend has no Rg32Uint storage textures)
        format: wgpu::TextureFormat::Rgba32Uint,
        words: 4,
        clear: None,
    },
];

impl Source {
    /// The target the AOV is read from.
    pub const fn target(self) -> usize {
        match self {
            Source::ColorRgb | Source::ColorLow28 | Source::ColorHigh4 => 0,
            Source::Hit | Source::Coverage | Source::Fragments => 0,
            Source::Geo(_) => 1,
            Source::Id => 2,
            Source::Cost(_) => 3,
        }
    }
}

/// An AOV's element type (numpy's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    F32,
    U32,
    U8,
    I32,
    Bool,
}

/// One AOV: its name, per-pixel components (1: an (H, W) array, else (H, W, n)), element type,
/// where it lives, and what it means (Python's `Frame` documents it with this).
#[derive(Clone, Copy, Debug)]
pub struct Aov {
    pub name: &'static str,
    pub comps: usize,
    pub dtype: Dtype,
    pub source: Source,
    pub doc: &'static str,
}

/// Every AOV, in the order of `Frame.aovs` and Python's `AOV_NAMES`.
pub const AOVS: [Aov; 13] = [
    Aov {
        name: "color",
        comps: 3,
        dtype: Dtype::F32,
        source: Source::ColorRgb,
        doc: "linear RGB radiance",
    },
    Aov {
        name: "uv",
        comps: 2,
        dtype: Dtype::F32,
        source: Source::Geo(0),
        doc: "hit uv in the mesh's uv space (not wrapped), NaN where no hit",
    },
    Aov {
        name: "depth",
        comps: 1,
        dtype: Dtype::F32,
        source: Source::Geo(2),
        doc: "distance from the eye to the hit, NaN where no hit",
    },
    Aov {
        name: "mask",
        comps: 1,
        dtype: Dtype::Bool,
        source: Source::Hit,
        doc: "the pixel shows a surface (at its centre sample)",
    },
    Aov {
        name: "coverage",
        comps: 1,
        dtype: Dtype::F32,
        source: Source::Coverage,
        doc: "fraction of the pixel's samples that hit a surface (spp > 1; 0 or 1 at one sample)",
    },
    Aov {
        name: "steps",
        comps: 1,
        dtype: Dtype::U32,
        source: Source::ColorLow28,
        doc: "height-map samples taken (view ray + shadow rays)",
    },
    Aov {
        name: "lod",
        comps: 1,
        dtype: Dtype::F32,
        source: Source::Geo(3),
        doc: "mip level the LOD system used, NaN where no hit",
    },
    Aov {
        name: "flags",
        comps: 1,
        dtype: Dtype::U8,
        source: Source::ColorHigh4,
        doc: "bit 0: the march hit its iteration bound; bit 1: it ended early, inside the shell; bit 2: the walk lost the surface away from a silhouette and the base mesh's point covers the pixel (NCS, CurvedRelief)",
    },
    Aov {
        name: "object",
        comps: 1,
        dtype: Dtype::I32,
        source: Source::Id,
        doc: "index of the object hit in the scene's objects, -1 where no hit",
    },
    Aov {
        name: "fetches",
        comps: 1,
        dtype: Dtype::U32,
        source: Source::Cost(0),
        doc: "texel fetches of the search (view and light rays): a load or a storage read 1, a gather 4, a filtered sample 1; 0 where no hit",
    },
    Aov {
        name: "bytes",
        comps: 1,
        dtype: Dtype::U32,
        source: Source::Cost(1),
        doc: "bytes those fetches read (a filtered sample: 4 bytes per texel its filter reads); 0 where no hit",
    },
    Aov {
        name: "chain",
        comps: 1,
        dtype: Dtype::U32,
        source: Source::Cost(2),
        doc: "the longest chain of dependent fetches: rounds of fetches whose addresses wait on a value the round before read (1 where every address follows from the ray); 0 where no hit",
    },
    Aov {
        name: "fragments",
        comps: 1,
        dtype: Dtype::U32,
        source: Source::Fragments,
        doc: "fragment invocations of the surface pass at the pixel (overdraw), whether they wrote or discarded: Flat on a plane 1, Prism every prism face tested, Tessellated every triangle fragment; counted everywhere, hit or not",
    },
];

const fn names() -> [&'static str; AOVS.len()] {
    let mut out = [""; AOVS.len()];
    let mut i = 0;
    while i < AOVS.len() {
        out[i] = AOVS[i].name;
        i += 1;
    }
    out
}

const fn standard_bits() -> u32 {
    let mut bits = 0;
    let mut i = 0;
    while i < AOVS.len() {
        if !matches!(AOVS[i].source, Source::Cost(_) | Source::Fragments) {
            bits |= 1 << i;
        }
        i += 1;
    }
    bits
}

/// The AOVs a render returns, as a set. Targets that no requested AOV needs are neither written
/// nor read back.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Aovs(pub(super) u32);

impl Aovs {
    pub const NAMES: [&'static str; AOVS.len()] = names();
    pub const ALL: Aovs = Aovs((1 << AOVS.len()) - 1);
    /// `aovs="all"`, a render's default: every AOV but the cost counters (`fetches`, `bytes`),
    /// which are counted only when named (counting costs the search a little).
    pub const STANDARD: Aovs = Aovs(standard_bits());

    fn bit(name: &str) -> Option<u32> {
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
    /// (the AOVs a supersampled pass averages: colour and coverage; the rest, each None when
    /// empty)
    pub fn split_supersampled(self) -> (Option<Aovs>, Option<Aovs>) {
        let ss: u32 = AOVS
            .iter()
            .enumerate()
            .filter(|(_, a)| matches!(a.source, Source::ColorRgb | Source::Coverage))
            .map(|(i, _)| 1 << i)
            .sum();
        let some = |b: u32| (b != 0).then_some(Aovs(b));
        (some(self.0 & ss), some(self.0 & !ss))
    }
    pub fn has(self, name: &str) -> bool {
        Self::bit(name).is_some_and(|b| self.0 & b != 0)
    }
    fn sources(self) -> impl Iterator<Item = Source> {
        AOVS.iter()
            .enumerate()
            .filter(move |(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, a)| a.source)
    }
    /// The targets the AOVs are read from (aligned with `TARGETS`). Every AOV that is blanked
    /// where nothing is hit needs the colour target too (its hit bit).
    pub fn targets(self) -> [bool; TARGETS.len()] {
        let mut t = [false; TARGETS.len()];
        for s in self.sources() {
            t[s.target()] = true;
            if s != Source::ColorRgb {
                t[Source::Hit.target()] = true;
            }
        }
        t
    }
    /// The targets a frame of `objects` objects reads: `targets`, without the object target
    /// when there is one object (its id is 0 wherever hit: `Frame::decode` fills it in, and
    /// the pass writes 20 bytes a pixel, not 24, for every AOV).
    pub fn targets_for(self, objects: usize) -> [bool; TARGETS.len()] {
        let mut t = self.targets();
        if objects == 1 {
            t[Source::Id.target()] = false;
        }
        t
    }
    /// Whether the frame asks for the cost counters (shader def COUNT_FETCHES).
    pub fn counts_fetches(self) -> bool {
        self.targets()[Source::Cost(0).target()]
    }
    /// Whether the frame asks for the fragment counter (shader def COUNT_FRAGMENTS).
    pub fn counts_fragments(self) -> bool {
        self.has("fragments")
    }
}

/// The targets a pass writes: `read`, or, when the adapter cannot leave a gap in its colour
/// attachments (`Capabilities::sparse_attachments` false), every target up to the last one read
/// (written and cleared, not read back).
pub fn written(read: [bool; TARGETS.len()], sparse: bool) -> [bool; TARGETS.len()] {
    if sparse {
        return read;
    }
    let last = read.iter().rposition(|&b| b).unwrap_or(0);
    std::array::from_fn(|i| i <= last)
}

/// One AOV's values, row-major (H, W, comps).
#[derive(Clone, Debug, PartialEq)]
pub enum AovData {
    F32(Vec<f32>),
    U32(Vec<u32>),
    U8(Vec<u8>),
    I32(Vec<i32>),
    Bool(Vec<bool>),
}

/// Per-pixel results of one render: the AOVs in `aovs`, in the order of `AOVS`.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub aovs: Aovs,
    /// aligned with `AOVS`; None for the AOVs not asked for
    pub data: Vec<Option<AovData>>,
    /// GPU time of the render pass from timestamp queries, if the adapter has them
    pub gpu_ms: Option<f64>,
    /// wall time of submit-and-wait, always measured
    pub wall_ms: f64,
}

/// The targets' texels as read back, aligned with `TARGETS` (None when not read): each pixel's
/// `words` u32 words, row-major; and the fragment counter, one u32 a pixel (None when not read).
pub struct Texels(pub [Option<Vec<u32>>; TARGETS.len()], pub Option<Vec<u32>>);

impl Texels {
    /// Pixel `i`'s words of target `t` (the target was read).
    fn px(&self, t: usize, i: usize) -> &[u32] {
        let w = TARGETS[t].words;
        let v = self.0[t].as_ref().expect("the target was read");
        &v[i * w..(i + 1) * w]
    }
}

impl Frame {
    /// The AOV `name`, if the frame holds it.
    pub fn get(&self, name: &str) -> Option<&AovData> {
        let i = AOVS.iter().position(|a| a.name == name)?;
        self.data[i].as_ref()
    }
    /// A float AOV's values (empty when the frame does not hold it).
    pub fn f32s(&self, name: &str) -> &[f32] {
        match self.get(name) {
            Some(AovData::F32(v)) => v,
            _ => &[],
        }
    }
    /// The hit mask (empty when the frame does not hold it).
    pub fn mask(&self) -> &[bool] {
        match self.get("mask") {
            Some(AovData::Bool(v)) => v,
            _ => &[],
        }
    }

    /// Decode every requested AOV from the targets' texels, as `AOVS` says.
    pub fn decode(
        width: u32,
        height: u32,
        aovs: Aovs,
        t: &Texels,
        gpu_ms: Option<f64>,
        wall_ms: f64,
    ) -> Frame {
        let n = (width * height) as usize;
        let c = Source::Hit.target();
        let hit: Vec<bool> = match &t.0[c] {
            Some(_) => (0..n).map(|i| t.px(c, i)[3] & HIT_BIT != 0).collect(),
            None => vec![true; n],
        };
        let data = AOVS
            .iter()
            .map(|a| {
                if !aovs.has(a.name) {
                    return None;
                }
                let where_hit = |f: &dyn Fn(usize) -> u32, none: u32| -> Vec<u32> {
                    (0..n).map(|i| if hit[i] { f(i) } else { none }).collect()
                };
                let k = a.source.target();
                Some(match a.source {
                    Source::ColorRgb => AovData::F32(
                        (0..n)
                            .flat_map(|i| {
                                let p = t.px(k, i);
                                [0, 1, 2].map(|c| f32::from_bits(p[c]))
                            })
                            .collect(),
                    ),
                    Source::ColorLow28 => {
                        AovData::U32(where_hit(&|i| t.px(k, i)[3] & 0x0fff_ffff, 0))
                    }
                    Source::ColorHigh4 => AovData::U8(
                        where_hit(&|i| (t.px(k, i)[3] & !HIT_BIT) >> 28, 0)
                            .into_iter()
                            .map(|x| x as u8)
                            .collect(),
                    ),
                    Source::Geo(c0) => {
                        let mut v = vec![f32::NAN; n * a.comps];
                        for i in (0..n).filter(|&i| hit[i]) {
                            for (c, x) in t.px(k, i)[c0..c0 + a.comps].iter().enumerate() {
                                v[i * a.comps + c] = f32::from_bits(*x);
                            }
                        }
                        AovData::F32(v)
                    }
                    Source::Hit => AovData::Bool(hit.clone()),
                    Source::Coverage => {
                        AovData::F32(hit.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect())
                    }
                    // not read (one object): 0 wherever hit
                    Source::Id => AovData::I32(
                        where_hit(&|i| t.0[k].as_ref().map_or(0, |_| t.px(k, i)[0]), u32::MAX)
                            .into_iter()
                            .map(|x| x as i32)
                            .collect(),
                    ),
                    Source::Cost(c) => AovData::U32(where_hit(&|i| t.px(k, i)[c], 0)),
                    Source::Fragments => AovData::U32(t.1.clone().unwrap_or_else(|| vec![0; n])),
                })
            })
            .collect();
        Frame {
            width,
            height,
            aovs,
            data,
            gpu_ms,
            wall_ms,
        }
    }
}

#[cfg(test)]
#[path = "aovs_tests.rs"]
mod tests;

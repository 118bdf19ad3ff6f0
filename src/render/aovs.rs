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
    /// the colour target's channel 3, high 4 bits, where hit (0 elsewhere)
    ColorHigh4,
    /// the geo target's channels from `c` (float bits), where hit (NaN elsewhere)
    Geo(usize),
    /// the geo target's distance >= 0: the pixel shows a surface
    GeoHit,
    /// the id target, where hit (-1 elsewhere)
    Id,
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
pub const AOVS: [Aov; 8] = [
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
        source: Source::GeoHit,
        doc: "the pixel shows a surface",
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
        doc: "bit 0: the march hit its iteration bound; bit 1: it ended early, inside the shell",
    },
    Aov {
        name: "object",
        comps: 1,
        dtype: Dtype::I32,
        source: Source::Id,
        doc: "index of the object hit in the scene's objects, -1 where no hit",
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

/// The AOVs a render returns, as a set. Targets that no requested AOV needs are neither written
/// nor read back.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Aovs(u32);

impl Aovs {
    pub const NAMES: [&'static str; AOVS.len()] = names();
    pub const ALL: Aovs = Aovs((1 << AOVS.len()) - 1);

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
    pub fn has(self, name: &str) -> bool {
        Self::bit(name).is_some_and(|b| self.0 & b != 0)
    }
    fn sources(self) -> impl Iterator<Item = Source> {
        AOVS.iter()
            .enumerate()
            .filter(move |(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, a)| a.source)
    }
    /// Whether the colour target (colour, channel 3's packed integers) is written and read.
    pub fn color_target(self) -> bool {
        self.sources().any(|s| {
            matches!(
                s,
                Source::ColorRgb | Source::ColorLow28 | Source::ColorHigh4
            )
        })
    }
    /// Whether the geo target (uv, distance, lod; the hit mask) is written and read: every AOV
    /// that is blanked where nothing is hit needs it.
    pub fn geo_target(self) -> bool {
        self.sources().any(|s| !matches!(s, Source::ColorRgb))
    }
    /// Whether the object-id target is written and read.
    pub fn id_target(self) -> bool {
        self.sources().any(|s| s == Source::Id)
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

/// The targets' texels as read back (each None when not read): colour (4 x u32 bits), geo (4 x
/// f32), object id.
pub struct Texels {
    pub color: Option<Vec<[u32; 4]>>,
    pub geo: Option<Vec<[f32; 4]>>,
    pub id: Option<Vec<u32>>,
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
        let hit: Vec<bool> = match &t.geo {
            Some(g) => g.iter().map(|p| p[2] >= 0.0).collect(),
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
                Some(match a.source {
                    Source::ColorRgb => {
                        let c = t.color.as_ref().expect("the colour target was read");
                        AovData::F32(
                            c.iter()
                                .flat_map(|p| [0, 1, 2].map(|k| f32::from_bits(p[k])))
                                .collect(),
                        )
                    }
                    Source::ColorLow28 => {
                        let c = t.color.as_ref().expect("the colour target was read");
                        AovData::U32(where_hit(&|i| c[i][3] & 0x0fff_ffff, 0))
                    }
                    Source::ColorHigh4 => {
                        let c = t.color.as_ref().expect("the colour target was read");
                        AovData::U8(
                            where_hit(&|i| c[i][3] >> 28, 0)
                                .into_iter()
                                .map(|x| x as u8)
                                .collect(),
                        )
                    }
                    Source::Geo(c0) => {
                        let g = t.geo.as_ref().expect("the geo target was read");
                        let mut v = vec![f32::NAN; n * a.comps];
                        for i in (0..n).filter(|&i| hit[i]) {
                            v[i * a.comps..(i + 1) * a.comps]
                                .copy_from_slice(&g[i][c0..c0 + a.comps]);
                        }
                        AovData::F32(v)
                    }
                    Source::GeoHit => AovData::Bool(hit.clone()),
                    Source::Id => {
                        let ids = t.id.as_ref().expect("the id target was read");
                        AovData::I32(
                            where_hit(&|i| ids[i], u32::MAX)
                                .into_iter()
                                .map(|x| x as i32)
                                .collect(),
                        )
                    }
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
mod tests {
    use super::*;

    #[test]
    fn every_aov_decodes_to_its_declared_type_and_size() {
        let (w, h) = (3u32, 2u32);
        let n = 6;
        let t = Texels {
            color: Some(vec![
                [
                    1.0f32.to_bits(),
                    0.5f32.to_bits(),
                    0.25f32.to_bits(),
                    7 | (2 << 28)
                ];
                n
            ]),
            // pixel 0 misses (distance -1)
            geo: Some(
                (0..n)
                    .map(|i| [0.1, 0.2, if i == 0 { -1.0 } else { 2.0 }, 0.5])
                    .collect(),
            ),
            id: Some(vec![4; n]),
        };
        let f = Frame::decode(w, h, Aovs::ALL, &t, None, 0.0);
        for (a, d) in AOVS.iter().zip(&f.data) {
            let d = d.as_ref().expect("every AOV");
            let (len, ty) = match d {
                AovData::F32(v) => (v.len(), Dtype::F32),
                AovData::U32(v) => (v.len(), Dtype::U32),
                AovData::U8(v) => (v.len(), Dtype::U8),
                AovData::I32(v) => (v.len(), Dtype::I32),
                AovData::Bool(v) => (v.len(), Dtype::Bool),
            };
            assert_eq!((len, ty), (n * a.comps, a.dtype), "{}", a.name);
        }
        assert_eq!(f.mask(), &[false, true, true, true, true, true]);
        assert!(f.f32s("depth")[0].is_nan() && f.f32s("depth")[1] == 2.0);
        assert_eq!(f.get("steps"), Some(&AovData::U32(vec![0, 7, 7, 7, 7, 7])));
        assert_eq!(f.get("flags"), Some(&AovData::U8(vec![0, 2, 2, 2, 2, 2])));
        assert_eq!(
            f.get("object"),
            Some(&AovData::I32(vec![-1, 4, 4, 4, 4, 4]))
        );
        assert_eq!(&f.f32s("color")[..3], &[1.0, 0.5, 0.25]);
    }
}

//! The methods and their parameters. Each maps onto the shared surface pipeline by its
//! override constants (METHOD, SHADOWS, FILTERING) and a few uniform parameters.

use crate::error::{Error, Result};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Flat,
    Bump,
    Pom,
    Parallax,
    SteepParallax,
    Relief,
    /// the displaced mesh itself (Chen & Chang's ground-truth model), rasterised
    Tessellated,
    /// maximum mipmaps (Tevs et al. 2008)
    Exact,
    /// normal-based curved silhouettes (Chen & Chang 2008)
    Ncs,
    /// prism POM (Dachsbacher & Tatarchuk 2007)
    Prism,
}

impl Kind {
    pub const ALL: [Kind; 10] = [
        Kind::Flat,
        Kind::Bump,
        Kind::Pom,
        Kind::Parallax,
        Kind::SteepParallax,
        Kind::Relief,
        Kind::Tessellated,
        Kind::Exact,
        Kind::Ncs,
        Kind::Prism,
    ];

    pub fn shader_id(self) -> u32 {
        match self {
            Kind::Flat => 0,
            Kind::Bump => 1,
            Kind::Pom => 2,
            Kind::Parallax => 3,
            Kind::SteepParallax => 4,
            Kind::Relief => 5,
            Kind::Tessellated => 6,
            Kind::Exact => 7,
            Kind::Ncs => 8,
            Kind::Prism => 9,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Kind::Flat => "Flat",
            Kind::Bump => "Bump",
            Kind::Pom => "POM",
            Kind::Parallax => "Parallax",
            Kind::SteepParallax => "SteepParallax",
            Kind::Relief => "Relief",
            Kind::Tessellated => "Tessellated",
            Kind::Exact => "Exact",
            Kind::Ncs => "NCS",
            Kind::Prism => "Prism",
        }
    }
    /// Methods that march a ray per pixel (and so take shadows and AO).
    pub fn per_pixel(self) -> bool {
        matches!(self, Kind::Pom | Kind::Parallax | Kind::SteepParallax | Kind::Relief | Kind::Exact | Kind::Ncs | Kind::Prism)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shadows {
    None,
    Hard,
    Soft,
    Horizon,
    Exact,
}

impl Shadows {
    pub fn id(self) -> u32 {
        match self {
            Shadows::None => 0,
            Shadows::Hard => 1,
            Shadows::Soft => 2,
            Shadows::Horizon => 3,
            Shadows::Exact => 4,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filtering {
    Hardware,
    Exact,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Method {
    pub kind: Kind,
    pub min_steps: u32,
    /// POM: n_max; SteepParallax: steps; Relief: linear_steps
    pub max_steps: u32,
    /// POM: sample count moves with N.V (Tatarchuk 2006); false: always max_steps
    pub adaptive: bool,
    pub shadows: Shadows,
    pub shadow_steps: u32,
    pub lod_threshold: f32,
    pub filtering: Filtering,
    /// sample the height field at the footprint's mip level (Tatarchuk's tex2Dgrad, default);
    /// false: level 0, the exact bilinear field (aliases under minification)
    pub mip_filtering: bool,
    /// Tessellated: lattice spacing in texels (1 = one vertex per texel centre)
    pub texels_per_vertex: f64,
    /// Parallax: s += (scale * (1 - h) + bias) * P
    pub scale: f32,
    pub bias: f32,
    pub offset_limiting: bool,
    /// Relief
    pub binary_steps: u32,
    pub depth_bias: bool,
    /// Exact: bound on traversal iterations per ray
    pub max_iterations: u32,
    /// horizon AO directions (0 = off) and horizon samples (2^k texels, k < horizon_samples)
    pub ao_directions: u32,
    pub horizon_samples: u32,
    /// Prism: extrude outward (the paper's shell) instead of inward
    pub outward: bool,
    /// Prism: march between entry and exit with the max-mip traversal
    pub exact: bool,
}

pub const MAX_STEPS_LIMIT: u32 = 4096;

impl Default for Method {
    fn default() -> Self {
        Self::pom()
    }
}

impl Method {
    pub fn flat() -> Self {
        Self { kind: Kind::Flat, shadows: Shadows::None, ..Self::pom() }
    }
    pub fn bump() -> Self {
        Self { kind: Kind::Bump, shadows: Shadows::None, ..Self::pom() }
    }
    /// POM with the paper's defaults: 8..50 samples, soft shadows, LOD threshold 4.
    pub fn pom() -> Self {
        Self {
            kind: Kind::Pom,
            min_steps: 8,
            max_steps: 50,
            adaptive: true,
            shadows: Shadows::Soft,
            shadow_steps: 8,
            lod_threshold: 4.0,
            filtering: Filtering::Hardware,
            mip_filtering: true,
            texels_per_vertex: 1.0,
            scale: 1.0,
            bias: 0.0,
            offset_limiting: true,
            binary_steps: 6,
            depth_bias: false,
            max_iterations: 4096,
            ao_directions: 0,
            horizon_samples: 8,
            outward: false,
            exact: false,
        }
    }
    pub fn exact() -> Self {
        Self { kind: Kind::Exact, shadows: Shadows::None, ..Self::pom() }
    }

    /// Parse a method from its name and parameters (the Python layer's representation).
    pub fn from_params(kind: &str, num: &HashMap<String, f64>, text: &HashMap<String, String>) -> Result<Self> {
        let k = Kind::ALL
            .into_iter()
            .find(|k| k.name() == kind)
            .ok_or_else(|| Error::arg("method", format!("unknown method {kind:?}")))?;
        let mut m = Self { kind: k, ..Self::pom() };
        m.shadows = match k {
            Kind::Pom | Kind::Prism => Shadows::Soft,
            Kind::Tessellated => Shadows::Hard,
            _ => Shadows::None,
        };
        let int = |name: &str, default: u32, lo: u32, hi: u32| -> Result<u32> {
            match num.get(name) {
                None => Ok(default),
                Some(x) if x.is_finite() && x.fract() == 0.0 && *x >= lo as f64 && *x <= hi as f64 => Ok(*x as u32),
                Some(x) => Err(Error::arg(name, format!("must be an integer in [{lo}, {hi}], got {x}"))),
            }
        };
        let flag = |name: &str, default: bool| num.get(name).map(|x| *x != 0.0).unwrap_or(default);
        let real = |name: &str, default: f32| -> Result<f32> {
            match num.get(name) {
                None => Ok(default),
                Some(x) if x.is_finite() && x.abs() < 1e6 => Ok(*x as f32),
                Some(x) => Err(Error::arg(name, format!("must be a finite number, got {x}"))),
            }
        };
        m.min_steps = int("min_steps", m.min_steps, 1, MAX_STEPS_LIMIT)?;
        m.max_steps = int("max_steps", m.max_steps, 1, MAX_STEPS_LIMIT)?;
        m.max_steps = int("steps", m.max_steps, 1, MAX_STEPS_LIMIT)?;
        m.max_steps = int("linear_steps", m.max_steps, 1, MAX_STEPS_LIMIT)?;
        if k == Kind::SteepParallax && !num.contains_key("steps") {
            m.max_steps = 32;
        }
        if k == Kind::Relief && !num.contains_key("linear_steps") {
            m.max_steps = 16;
        }
        if k == Kind::Ncs {
            // P_{i+1} = P_i + c * delta * S * TBN * V: c is `step_scale` (the paper's 2.5)
            if !num.contains_key("max_steps") {
                m.max_steps = 64;
            }
            m.scale = match num.get("step_scale") {
                None => 2.5,
                Some(x) if x.is_finite() && *x > 0.0 && *x <= 1000.0 => *x as f32,
                Some(x) => return Err(Error::arg("step_scale", format!("must lie in (0, 1000], got {x}"))),
            };
        }
        m.shadow_steps = int("shadow_steps", m.shadow_steps, 1, MAX_STEPS_LIMIT)?;
        m.binary_steps = int("binary_steps", m.binary_steps, 0, 64)?;
        m.max_iterations = int("max_iterations", m.max_iterations, 1, 1 << 24)?;
        m.ao_directions = int("ao_directions", m.ao_directions, 0, 64)?;
        m.horizon_samples = int("horizon_samples", m.horizon_samples, 1, 16)?;
        if k == Kind::Pom && m.min_steps > m.max_steps {
            return Err(Error::arg("min_steps", format!("min_steps ({}) must not exceed max_steps ({})", m.min_steps, m.max_steps)));
        }
        m.adaptive = flag("adaptive", m.adaptive);
        m.mip_filtering = flag("mip_filtering", m.mip_filtering);
        m.offset_limiting = flag("offset_limiting", m.offset_limiting);
        m.depth_bias = flag("depth_bias", m.depth_bias);
        m.outward = flag("outward", m.outward);
        m.exact = flag("exact", m.exact);
        m.lod_threshold = real("lod_threshold", m.lod_threshold)?;
        if k != Kind::Ncs {
            m.scale = real("scale", m.scale)?;
        }
        m.bias = real("bias", m.bias)?;
        if let Some(t) = num.get("texels_per_vertex") {
            if !(t.is_finite() && (1.0 / 64.0..=1024.0).contains(t)) {
                return Err(Error::arg("texels_per_vertex", format!("must lie in [1/64, 1024], got {t}")));
            }
            m.texels_per_vertex = *t;
        }
        if let Some(s) = text.get("shadows") {
            m.shadows = match s.as_str() {
                "none" => Shadows::None,
                "hard" => Shadows::Hard,
                "soft" => Shadows::Soft,
                "horizon" => Shadows::Horizon,
                "exact" => Shadows::Exact,
                o => return Err(Error::arg("shadows", format!("must be 'none', 'hard', 'soft', 'horizon' or 'exact', got {o:?}"))),
            };
        }
        if let Some(s) = text.get("filtering") {
            m.filtering = match s.as_str() {
                "hardware" => Filtering::Hardware,
                "exact" => Filtering::Exact,
                o => return Err(Error::arg("filtering", format!("must be 'hardware' or 'exact', got {o:?}"))),
            };
        }
        match k {
            Kind::Tessellated if !matches!(m.shadows, Shadows::None | Shadows::Hard) => {
                return Err(Error::arg("shadows", "Tessellated has 'none' or 'hard' (a shadow map of the displaced mesh)"));
            }
            Kind::Flat | Kind::Bump => m.shadows = Shadows::None,
            _ => {}
        }
        if m.shadows == Shadows::Exact && k != Kind::Exact {
            return Err(Error::arg("shadows", "'exact' shadows traverse the max-mip pyramid: only the Exact method has them"));
        }
        Ok(m)
    }

    pub fn shadow_id(&self) -> u32 {
        self.shadows.id()
    }
}

//! The methods and their parameters. Each method maps onto the shared surface pipeline by
//! its override constants (METHOD, SHADOWS, FILTERING) and a few uniform parameters.

use crate::error::{Error, Result};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Flat,
    Bump,
    Pom,
    /// the displaced mesh itself (Chen & Chang's ground-truth model), rasterised
    Tessellated,
}

impl Kind {
    pub fn shader_id(self) -> u32 {
        match self {
            Kind::Flat => 0,
            Kind::Bump => 1,
            Kind::Pom => 2,
            Kind::Tessellated => 6,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Kind::Flat => "Flat",
            Kind::Bump => "Bump",
            Kind::Pom => "POM",
            Kind::Tessellated => "Tessellated",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shadows {
    None,
    Hard,
    Soft,
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
}

pub const MAX_STEPS_LIMIT: u32 = 4096;

impl Method {
    pub fn flat() -> Self {
        Self { kind: Kind::Flat, ..Self::pom() }
    }
    pub fn bump() -> Self {
        Self { kind: Kind::Bump, ..Self::pom() }
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
        }
    }

    /// Parse a method from its name and parameters (the Python layer's representation).
    pub fn from_params(kind: &str, num: &HashMap<String, f64>, text: &HashMap<String, String>) -> Result<Self> {
        let mut m = match kind {
            "Flat" => Self::flat(),
            "Bump" => Self::bump(),
            "POM" => Self::pom(),
            "Tessellated" => Self { kind: Kind::Tessellated, shadows: Shadows::Hard, ..Self::pom() },
            other => return Err(Error::arg("method", format!("unknown method {other:?}"))),
        };
        let steps = |name: &str, default: u32| -> Result<u32> {
            match num.get(name) {
                None => Ok(default),
                Some(x) if x.is_finite() && x.fract() == 0.0 && *x >= 1.0 && *x <= MAX_STEPS_LIMIT as f64 => Ok(*x as u32),
                Some(x) => Err(Error::arg(name, format!("must be an integer in [1, {MAX_STEPS_LIMIT}], got {x}"))),
            }
        };
        m.min_steps = steps("min_steps", m.min_steps)?;
        m.max_steps = steps("max_steps", m.max_steps)?;
        m.shadow_steps = steps("shadow_steps", m.shadow_steps)?;
        if m.min_steps > m.max_steps {
            return Err(Error::arg("min_steps", format!("min_steps ({}) must not exceed max_steps ({})", m.min_steps, m.max_steps)));
        }
        if let Some(a) = num.get("adaptive") {
            m.adaptive = *a != 0.0;
        }
        if let Some(t) = num.get("texels_per_vertex") {
            if !(t.is_finite() && (1.0 / 64.0..=1024.0).contains(t)) {
                return Err(Error::arg("texels_per_vertex", format!("must lie in [1/64, 1024], got {t}")));
            }
            m.texels_per_vertex = *t;
        }
        if let Some(a) = num.get("mip_filtering") {
            m.mip_filtering = *a != 0.0;
        }
        if let Some(t) = num.get("lod_threshold") {
            if !t.is_finite() {
                return Err(Error::arg("lod_threshold", format!("must be finite, got {t}")));
            }
            m.lod_threshold = *t as f32;
        }
        if let Some(s) = text.get("shadows") {
            m.shadows = match s.as_str() {
                "none" => Shadows::None,
                "hard" => Shadows::Hard,
                "soft" => Shadows::Soft,
                o => return Err(Error::arg("shadows", format!("must be 'none', 'hard' or 'soft', got {o:?}"))),
            };
        }
        if let Some(s) = text.get("filtering") {
            m.filtering = match s.as_str() {
                "hardware" => Filtering::Hardware,
                "exact" => Filtering::Exact,
                o => return Err(Error::arg("filtering", format!("must be 'hardware' or 'exact', got {o:?}"))),
            };
        }
        if m.kind == Kind::Tessellated && m.shadows == Shadows::Soft {
            return Err(Error::arg("shadows", "Tessellated has 'none' or 'hard' (a shadow map of the displaced mesh)"));
        }
        if !matches!(m.kind, Kind::Pom | Kind::Tessellated) {
            m.shadows = Shadows::None;
        }
        Ok(m)
    }

    pub fn shadow_id(&self) -> u32 {
        match self.shadows {
            Shadows::None => 0,
            Shadows::Hard => 1,
            Shadows::Soft => 2,
        }
    }
}

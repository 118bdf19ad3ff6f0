//! The renderer-method contract, at the bottom of the crate: what a method declares (its shader,
//! its shader defs, its geometry, its uniform block, the per-pixel options it takes) and what the
//! renderer runs from it. `shaders`, `render` and `methods` all depend on this module; it depends
//! on none of them (tests/test_layers.py holds the module graph acyclic).

use crate::error::{Error, Result};

/// Loops a shader may run per pixel: more would risk the driver's watchdog.
pub const MAX_STEPS_LIMIT: u32 = 4096;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shadows {
    None,
    Hard,
    Soft,
    Horizon,
    Exact,
}

impl Shadows {
    /// The value of the SHADOWS shader def.
    pub fn def(self) -> u32 {
        match self {
            Shadows::None => 0,
            Shadows::Hard => 1,
            Shadows::Soft => 2,
            Shadows::Horizon => 3,
            Shadows::Exact => 4,
        }
    }
    pub fn parse(s: &str) -> Result<Self> {
        Ok(match s {
            "none" => Shadows::None,
            "hard" => Shadows::Hard,
            "soft" => Shadows::Soft,
            "horizon" => Shadows::Horizon,
            "exact" => Shadows::Exact,
            o => {
                return Err(Error::arg(
                    "shadows",
                    format!("must be 'none', 'hard', 'soft', 'horizon' or 'exact', got {o:?}"),
                ))
            }
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filtering {
    Hardware,
    Exact,
}

impl Filtering {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "hardware" => Ok(Filtering::Hardware),
            "exact" => Ok(Filtering::Exact),
            o => Err(Error::arg(
                "filtering",
                format!("must be 'hardware' or 'exact', got {o:?}"),
            )),
        }
    }
}

/// The options every per-pixel method shares (shadows, filtering, AO).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct PerPixel {
    pub shadows: Shadows,
    pub shadow_steps: u32,
    pub filtering: Filtering,
    /// sample the footprint's mip level (Tatarchuk's tex2Dgrad); false: level 0
    pub mip_filtering: bool,
    /// horizon AO directions (0 = off)
    pub ao_directions: u32,
    /// horizon samples at 2^k texels, k < horizon_samples ("horizon" shadows and AO)
    pub horizon_samples: u32,
}

impl PerPixel {
    /// No shadows, no AO, hardware filtering of the footprint's level. (The user-facing
    /// defaults live in the Python dataclasses.)
    pub fn off() -> Self {
        PerPixel {
            shadows: Shadows::None,
            shadow_steps: 8,
            filtering: Filtering::Hardware,
            mip_filtering: true,
            ao_directions: 0,
            horizon_samples: 8,
        }
    }
    pub fn with_shadows(self, shadows: Shadows) -> Self {
        PerPixel { shadows, ..self }
    }
    pub fn validate(&self) -> Result<()> {
        check_range("shadow_steps", self.shadow_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("ao_directions", self.ao_directions, 0, 64)?;
        check_range("horizon_samples", self.horizon_samples, 1, 16)
    }
}

pub fn check_range(name: &str, v: u32, lo: u32, hi: u32) -> Result<()> {
    if v < lo || v > hi {
        return Err(Error::arg(
            name,
            format!("must lie in [{lo}, {hi}], got {v}"),
        ));
    }
    Ok(())
}

/// A WGSL source the composer registers under an import path.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderUnit {
    /// naga_oil import path, e.g. `pomkit::methods::pom`
    pub path: String,
    /// the file name shown in compile errors
    pub file: String,
    pub source: std::borrow::Cow<'static, str>,
}

impl ShaderUnit {
    pub fn builtin(path: &str, file: &str, source: &'static str) -> Self {
        ShaderUnit {
            path: path.to_string(),
            file: file.to_string(),
            source: std::borrow::Cow::Borrowed(source),
        }
    }
}

/// Which pass draws the method.
#[derive(Clone, Debug, PartialEq)]
pub enum Pass {
    /// surface.wgsl; `march` (when given) is imported as `method` and must define
    /// `fn march(r: Ray) -> Hit`
    Surface { march: Option<ShaderUnit> },
    /// a top-level shader of the method's own with entry points `vs_prism`/`fs_prism`-style names
    Own {
        shader: ShaderUnit,
        vs: &'static str,
        fs: &'static str,
        /// the shadow-map pass's entry points (depth only: the fragment writes the hit's depth)
        shadow_vs: &'static str,
        shadow_fs: &'static str,
    },
}

/// The mesh the pass rasterises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    /// the base mesh
    Base,
    /// the displaced mesh on a lattice `texels_per_vertex` texels apart
    Tessellated { texels_per_vertex: f64 },
    /// one prism per base triangle, inward or outward
    Prisms { outward: bool },
}

/// Everything the renderer needs to run a method.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    pub pass: Pass,
    /// boolean shader defs (MARCH, LOD_BLEND, FLAT, BUMP, TESSELLATED)
    pub defs: Vec<&'static str>,
    pub geometry: Geometry,
    /// NCS's texture-space frame maps
    pub frame_maps: bool,
    /// ConeStep's cone map (binding 11)
    pub cone_map: Option<Cones>,
    /// the uniform block `params` (binding 10), field by field, all f32
    pub params: Vec<(String, f32)>,
    pub pixel: PerPixel,
    /// LOD_BLEND's threshold (POM)
    pub lod_threshold: f32,
    /// bound of every max-mip traversal (Exact, exact shadows, Prism(exact=True))
    pub max_iterations: u32,
}

impl Spec {
    /// A per-pixel method of the surface pass, marching with `march`.
    pub fn surface(march: ShaderUnit, pixel: &PerPixel, params: &[(&str, f32)]) -> Self {
        Spec {
            pass: Pass::Surface { march: Some(march) },
            defs: vec!["MARCH"],
            geometry: Geometry::Base,
            frame_maps: false,
            cone_map: None,
            params: params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            pixel: pixel.clone(),
            lod_threshold: 0.0,
            max_iterations: 4096,
        }
    }
    /// A surface-pass method without a march (Flat, Bump, Tessellated).
    pub fn shade_only(def: &'static str, pixel: PerPixel, geometry: Geometry) -> Self {
        Spec {
            pass: Pass::Surface { march: None },
            defs: vec![def],
            geometry,
            frame_maps: false,
            cone_map: None,
            params: Vec::new(),
            pixel,
            lod_threshold: 0.0,
            max_iterations: 4096,
        }
    }
}

pub fn flag(b: bool) -> f32 {
    if b {
        1.0
    } else {
        0.0
    }
}

pub fn check_finite(name: &str, v: f32) -> Result<()> {
    if !v.is_finite() {
        return Err(Error::arg(
            name,
            format!("must be a finite number, got {v}"),
        ));
    }
    Ok(())
}

/// Which cones: conservative against the bilinear field, or relaxed (wider, refined).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cones {
    Conservative,
    Relaxed,
}

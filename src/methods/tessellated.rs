//! The displaced mesh itself (Chen & Chang 2008's "ground truth model"), rasterised by the
//! surface pass and shaded the same way; shadows from a shadow map of itself.
use super::{Geometry, PerPixel, Shadows, Spec, Unit};
use crate::error::{Error, Result};

#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct Tessellated {
    pub texels_per_vertex: f64,
    /// None or Hard (the shadow map)
    pub shadows: Shadows,
}

impl Unit for Tessellated {
    const PER_PIXEL: bool = false;
    fn spec(&self, _: &PerPixel) -> Spec {
        Spec::shade_only(
            "TESSELLATED",
            PerPixel::off().with_shadows(self.shadows),
            Geometry::Tessellated {
                texels_per_vertex: self.texels_per_vertex,
            },
        )
    }
    fn validate(&self) -> Result<()> {
        if !(self.texels_per_vertex.is_finite()
            && (1.0 / 64.0..=1024.0).contains(&self.texels_per_vertex))
        {
            return Err(Error::arg(
                "texels_per_vertex",
                format!("must lie in [1/64, 1024], got {}", self.texels_per_vertex),
            ));
        }
        if !matches!(self.shadows, Shadows::None | Shadows::Hard) {
            return Err(Error::arg(
                "shadows",
                "Tessellated has 'none' or 'hard' (a shadow map of the displaced mesh)",
            ));
        }
        Ok(())
    }
}

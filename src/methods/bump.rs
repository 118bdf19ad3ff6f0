//! Bump mapping (Blinn 1978): the shading normal from the height field, the uv unchanged.
use super::{Filtering, Geometry, PerPixel, Spec};

#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct Bump {
    pub filtering: Filtering,
}

impl Bump {
    pub fn spec(&self) -> Spec {
        Spec::shade_only(
            "BUMP",
            PerPixel {
                filtering: self.filtering,
                ..PerPixel::off()
            },
            Geometry::Base,
        )
    }
}

//! Flat: the texture at the rasterised uv, the base normal, no displacement.
use super::{Geometry, PerPixel, Spec};

#[derive(Clone, Debug, PartialEq, Default)]
pub struct Flat {}

impl Flat {
    pub fn spec(&self) -> Spec {
        Spec::shade_only("FLAT", PerPixel::off(), Geometry::Base)
    }
}

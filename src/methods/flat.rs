//! Flat: the texture at the rasterised uv, the base normal, no displacement.
use crate::contract::{Geometry, PerPixel, Spec, Unit};

crate::params! {
    pub struct Flat {}
}

impl Unit for Flat {
    fn examples() -> Vec<Self> {
        vec![Flat {}]
    }
    const PER_PIXEL: bool = false;
    fn spec(&self, _: &PerPixel) -> Spec {
        Spec::shade_only(crate::method_shader!("flat"), PerPixel::off(), Geometry::Base)
    }
}

//! Bump mapping (Blinn 1978): the shading normal from the height field, the uv unchanged.
use crate::contract::{Filtering, Geometry, PerPixel, Spec, Unit};

crate::params! {
    pub struct Bump {
        pub filtering: Filtering,
    }
}

impl Unit for Bump {
    fn examples() -> Vec<Self> {
        vec![
            Bump {
                filtering: Filtering::Hardware,
            },
            Bump {
                filtering: Filtering::Exact,
            },
        ]
    }
    const PER_PIXEL: bool = false;
    fn spec(&self, _: &PerPixel) -> Spec {
        Spec::shade_only(
            crate::method_shader!("bump"),
            PerPixel {
                filtering: self.filtering,
                ..PerPixel::off()
            },
            Geometry::Base,
        )
    }
}

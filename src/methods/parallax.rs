//! Parallax mapping (Kaneko 2001) with optional offset limiting (Welsh 2004): parallax.wgsl.
use crate::contract::{flag, PerPixel, Spec, Unit};
use crate::error::Result;

crate::params! {
    pub struct Parallax {
        pub offset_limiting: bool,
        pub scale: f32,
        pub bias: f32,
    }
}

impl Unit for Parallax {
    fn examples() -> Vec<Self> {
        vec![Parallax {
            offset_limiting: true,
            scale: 1.0,
            bias: 0.0,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("parallax");
        Spec::surface(
            wgsl,
            o,
            &[
                ("scale", self.scale),
                ("bias", self.bias),
                ("offset_limiting", flag(self.offset_limiting)),
            ],
        )
    }
    fn validate(&self) -> Result<()> {
        crate::contract::check_finite("scale", self.scale)?;
        crate::contract::check_finite("bias", self.bias)
    }
}

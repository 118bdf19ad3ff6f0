//! Parallax occlusion mapping (Brawley & Tatarchuk 2004; Tatarchuk 2006): pom.wgsl, with the
//! surface pass's LOD blend toward bump mapping.
use crate::contract::{check_range, flag, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::Result;

crate::params! {
    pub struct Pom {
        pub min_steps: u32,
        pub max_steps: u32,
        pub lod_threshold: f32,
        /// the sample count moves with N.V (Tatarchuk 2006); false: always max_steps
        pub adaptive: bool,
    }
}

impl Unit for Pom {
    fn examples() -> Vec<Self> {
        vec![Pom {
            min_steps: 8,
            max_steps: 50,
            lod_threshold: 4.0,
            adaptive: true,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("pom");
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("min_steps", self.min_steps as f32),
                ("max_steps", self.max_steps as f32),
                ("adaptive", flag(self.adaptive)),
            ],
        );
        s.defs.push("LOD_BLEND");
        s.lod_threshold = self.lod_threshold;
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("min_steps", self.min_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)?;
        crate::contract::check_finite("lod_threshold", self.lod_threshold)
    }
}

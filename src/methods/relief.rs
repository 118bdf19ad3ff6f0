//! Relief mapping (Policarpo, Oliveira & Comba 2005): relief.wgsl.
use crate::contract::{check_range, flag, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::Result;

crate::params! {
    pub struct Relief {
        pub linear_steps: u32,
        pub binary_steps: u32,
        pub depth_bias: bool,
    }
}

impl Unit for Relief {
    fn examples() -> Vec<Self> {
        vec![Relief {
            linear_steps: 16,
            binary_steps: 6,
            depth_bias: false,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("relief");
        Spec::surface(
            wgsl,
            o,
            &[
                ("linear_steps", self.linear_steps as f32),
                ("binary_steps", self.binary_steps as f32),
                ("depth_bias", flag(self.depth_bias)),
            ],
        )
    }
    fn validate(&self) -> Result<()> {
        check_range("linear_steps", self.linear_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)
    }
}

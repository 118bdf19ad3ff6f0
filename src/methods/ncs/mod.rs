//! Normal-based curved silhouettes (Chen & Chang 2008): ncs.wgsl, marching in texture space across
//! the base mesh's triangles (the walk, src/methods/walk): the basis at each step is the mesh's
//! own there, and seams, mirror axes and open borders are followed as the mesh defines them.

use super::walk::{walk_data, walk_unit, WalkMesh};
use crate::contract::{check_range, Geometry, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::{Error, Result};
use std::sync::Arc;

crate::params! {
    pub struct Ncs {
        /// c of P_{i+1} = P_i + c * delta * S * TBN * V (the paper's 2.5)
        pub step_scale: f32,
        pub max_steps: u32,
        /// steps of at least POM's layer density (by the local N.V), up to one shell depth long
        pub adaptive: bool,
    }
}

impl Unit for Ncs {
    fn examples() -> Vec<Self> {
        vec![Ncs {
            step_scale: 2.5,
            max_steps: 64,
            adaptive: true,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("ncs").with_deps(vec![walk_unit()]);
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("step_scale", self.step_scale),
                ("max_steps", self.max_steps as f32),
                ("adaptive", crate::contract::flag(self.adaptive)),
            ],
        );
        let mesh = WalkMesh { quadrics: false };
        s.defs.push("VERTEX_EXTRA");
        s.geometry = Geometry::Own(Arc::new(mesh));
        s.resources = Some(Arc::new(walk_data(mesh)));
        s
    }
    fn validate(&self) -> Result<()> {
        if !(self.step_scale.is_finite() && self.step_scale > 0.0) {
            return Err(Error::arg(
                "step_scale",
                format!("must be a positive number, got {}", self.step_scale),
            ));
        }
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)
    }
}

//! Curved relief mapping (Oliveira & Policarpo 2005), one of the two baselines of Chen & Chang
//! 2008 (the NCS paper): curved_relief.wgsl, on the base mesh with per-vertex quadric
//! coefficients (src/mesh/quadrics.rs) as the method's own vertex attribute (VERTEX_EXTRA), its search
//! walking across the mesh's triangles (src/methods/walk): across seams into the neighbouring
//! chart, and off the surface at open borders.
use super::walk::{walk_data, walk_unit, WalkMesh};
use crate::contract::{check_range, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::Geometry;
use crate::error::Result;
use std::sync::Arc;

crate::params! {
    pub struct CurvedRelief {
        pub linear_steps: u32,
        pub binary_steps: u32,
    }
}

impl Unit for CurvedRelief {
    fn examples() -> Vec<Self> {
        vec![CurvedRelief {
            linear_steps: 32,
            binary_steps: 6,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("curved_relief").with_deps(vec![walk_unit()]);
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("linear_steps", self.linear_steps as f32),
                ("binary_steps", self.binary_steps as f32),
            ],
        );
        s.defs.push("VERTEX_EXTRA");
        let mesh = WalkMesh { quadrics: true };
        s.geometry = Geometry::Own(Arc::new(mesh));
        s.resources = Some(Arc::new(walk_data(mesh)));
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("linear_steps", self.linear_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)
    }
}

//! Cone step mapping (Dummer 2006; relaxed cones: Policarpo & Oliveira 2007; conservative under
//! bilinear interpolation: Ban & Valasek 2024): cone_step.wgsl, over a cone map the method builds
//! on the GPU from the max-mip pyramid (cone_map.rs, cone_map.wgsl) and binds as its own resource.
mod cone_map;

use crate::contract::{check_range, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::{BuildInputs, MethodResources, Resident, ResourceKind};
use crate::error::Result;
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;

pub use cone_map::{read_cone_map, Cones, CONE_MAP_SHADER};

crate::option_enum!(
    /// How the march ends: the max-mip walk with the exact patch intersection from where the
    /// cones stop, a binary search between the last point above and the first below the
    /// surface, or the raw cone march.
    Refine, "refine", {
        Exact = "exact",
        Binary = "binary",
        None = "none",
    }
);

/// The cone map of an object's height map: one (base, w) pair of f32 per cell, two textures at
/// group 2, bindings 1 and 2 (`cone_base`, `cone_w` in cone_step.wgsl). Keyed by the map's
/// content and the kind of cones, so a height update (a new key) builds it anew.
#[derive(Debug)]
pub struct ConeMapResource(pub Cones);

impl MethodResources for ConeMapResource {
    fn layout(&self) -> Vec<ResourceKind> {
        vec![ResourceKind::TextureFloat, ResourceKind::TextureFloat]
    }
    fn key(&self, object: &Object) -> u64 {
        hash_bytes(&[
            b"cone map",
            &object.material.height.key.to_le_bytes(),
            &[self.0 as u8],
        ])
    }
    fn build(&self, inputs: &BuildInputs<'_>) -> Result<Vec<Resident>> {
        let pass = inputs
            .builders
            .get("cone map", || cone_map::pass(inputs.ctx, inputs.composer))?;
        let maps = cone_map::build(&pass, inputs, self.0, self.key(inputs.object))?;
        Ok(maps.into_iter().map(Resident::Texture).collect())
    }
}

crate::params! {
    pub struct ConeStep {
        pub cones: Cones,
        pub refine: Refine,
        /// cone steps before the refinement takes over (or the march stops, flagged)
        pub max_steps: u32,
        /// bisections of `refine = Binary`
        pub binary_steps: u32,
        /// bound of the max-mip walk of `refine = Exact`
        pub max_iterations: u32,
    }
}

impl Unit for ConeStep {
    fn examples() -> Vec<Self> {
        [
            (Cones::Conservative, Refine::Exact),
            (Cones::Relaxed, Refine::Binary),
            (Cones::Conservative, Refine::None),
        ]
        .into_iter()
        .map(|(cones, refine)| ConeStep {
            cones,
            refine,
            max_steps: 64,
            binary_steps: 8,
            max_iterations: 4096,
        })
        .collect()
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("cone_step");
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("max_steps", self.max_steps as f32),
                ("binary_steps", self.binary_steps as f32),
            ],
        );
        s.defs.push(self.refine.shader_def());
        s.resources = Some(Arc::new(ConeMapResource(self.cones)));
        s.max_iterations = self.max_iterations;
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)?;
        check_range("max_iterations", self.max_iterations, 1, 1 << 24)
    }
}

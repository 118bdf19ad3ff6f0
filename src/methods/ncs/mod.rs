//! Normal-based curved silhouettes (Chen & Chang 2008): ncs.wgsl, reading the texture-space
//! frame map of the base mesh that the method bakes on the GPU (frame_maps.rs, texspace.wgsl,
//! frame_map.wgsl) and binds as its own resource.
mod frame_maps;

use super::{check_range, PerPixel, ShaderUnit, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::{BuildInputs, MethodResources, Resident, ResourceKind};
use crate::error::{Error, Result};
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;

pub use frame_maps::{MAP_BYTES, MAP_SIZE, TEXSPACE_SHADER};

/// The packed frame map library module (`pomkit::frame_map`), imported by the march and the bake.
pub fn frame_map_unit() -> ShaderUnit {
    ShaderUnit::builtin(
        "pomkit::frame_map",
        "src/methods/ncs/frame_map.wgsl",
        include_str!("frame_map.wgsl"),
    )
}

/// The base mesh's frame map (normal, tangent and the scale factors per texel of the uv
/// square, packed into one Rgba32Uint texture, `frame_map` at group 2, binding 1). Keyed by the
/// mesh's content: every object with that mesh shares it.
#[derive(Debug)]
pub struct FrameMapResource;

impl MethodResources for FrameMapResource {
    fn layout(&self) -> Vec<ResourceKind> {
        vec![ResourceKind::TextureUint]
    }
    fn key(&self, object: &Object) -> u64 {
        hash_bytes(&[b"ncs frame map", &object.mesh.key.to_le_bytes()])
    }
    fn build(&self, inputs: &BuildInputs<'_>) -> Result<Vec<Resident>> {
        let b = inputs.builders.get("ncs frame map", || {
            frame_maps::TexSpace::new(inputs.ctx, inputs.composer)
        })?;
        let m = inputs.mesh;
        let ibuf = m
            .ibuf
            .as_ref()
            .ok_or_else(|| Error::Gpu("the NCS bake needs an indexed base mesh".into()))?;
        Ok(vec![Resident::Texture(
            b.maps(inputs.ctx, &m.vbuf, ibuf, m.count)?,
        )])
    }
}

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
        let wgsl = crate::method_shader!("ncs").with_deps(vec![frame_map_unit()]);
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("step_scale", self.step_scale),
                ("max_steps", self.max_steps as f32),
                ("adaptive", super::flag(self.adaptive)),
            ],
        );
        s.resources = Some(Arc::new(FrameMapResource));
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

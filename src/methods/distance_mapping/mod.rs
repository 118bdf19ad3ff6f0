//! Distance mapping (Donnelly 2005, GPU Gems 2 ch. 8), the space-leaping baseline of the NCS
//! paper (Chen & Chang 2008, fig. 1g): distance_mapping.wgsl sphere-traces a 3-D distance
//! texture over the shell, which the method builds on the GPU from the max pyramid (volume.rs,
//! distance_volume.wgsl) and binds as its own resource. Keyed by the height map's content: a
//! height update (a new key) builds it anew.
mod volume;

use crate::contract::{check_range, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::{BuildInputs, MethodResources, Resident, ResourceKind};
use crate::error::{Error, Result};
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;

pub use volume::{Layout, VOLUME_SHADER};

/// Voxels a side at most: finer maps are read at the max-pyramid level that fits.
pub const MAX_VOXELS: u32 = 128;
/// How far (in voxels) the build looks for the nearest surface: farther distances are stored as
/// this (an underestimate, so still a safe step).
pub const RADIUS: u32 = 8;

crate::params! {
    pub struct DistanceMapping {
        pub max_steps: u32,
        pub binary_steps: u32,
        /// the volume's slices over the shell's height
        pub slices: u32,
    }
}

/// The distance volume of an object's height map (a storage buffer: a 4-float header, then the
/// voxels).
#[derive(Debug)]
pub struct DistanceVolume {
    pub slices: u32,
}

impl MethodResources for DistanceVolume {
    fn layout(&self) -> Vec<ResourceKind> {
        vec![ResourceKind::Storage]
    }
    fn key(&self, object: &Object) -> u64 {
        hash_bytes(&[
            b"distance volume",
            &object.material.height.key.to_le_bytes(),
            &self.slices.to_le_bytes(),
        ])
    }
    fn build(&self, inputs: &BuildInputs<'_>) -> Result<Vec<Resident>> {
        let pass = inputs.builders.get("distance volume", || {
            volume::pass(inputs.ctx, inputs.composer)
        })?;
        let (w, h) = inputs.height_size;
        let l = Layout::of(w, h, self.slices, MAX_VOXELS);
        let lim = inputs.ctx.limits.max_storage_buffer_binding_size as u64;
        if l.bytes() > lim {
            // only maps whose sides no power of two divides are read at level 0
            return Err(Error::limit(
                "height",
                format!(
                    "DistanceMapping's volume of a {w}x{h} map is {}x{}x{} voxels ({} bytes), over the device's max_storage_buffer_binding_size = {lim}: a map whose sides no power of two divides is read at full resolution. Resample it to even sides (pk.textures.fit(height, {})) or lower slices",
                    l.size.0,
                    l.size.1,
                    l.slices,
                    l.bytes(),
                    (w.max(h) / 2 * 2).max(2)
                ),
            ));
        }
        Ok(vec![Resident::Buffer(volume::build(
            &pass, inputs, l, RADIUS,
        )?)])
    }
}

impl Unit for DistanceMapping {
    fn examples() -> Vec<Self> {
        vec![DistanceMapping {
            max_steps: 64,
            binary_steps: 6,
            slices: 16,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("distance_mapping");
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("max_steps", self.max_steps as f32),
                ("binary_steps", self.binary_steps as f32),
            ],
        );
        s.resources = Some(Arc::new(DistanceVolume {
            slices: self.slices,
        }));
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)?;
        check_range("slices", self.slices, 2, 256)
    }
}

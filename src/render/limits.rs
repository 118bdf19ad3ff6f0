//! The device's limits, checked before anything of a frame reaches the GPU.

use super::{targets, Renderer};
use crate::error::{Error, Result};
use crate::scene::Scene;

impl Renderer {
    /// Refuse sizes over the device's limits before anything reaches the GPU.
    pub fn check_limits(&self, scene: &Scene) -> Result<()> {
        let lim = &self.ctx.limits;
        let maxd = lim.max_texture_dimension_2d;
        let dims = |arg: &str, what: &str, w: u32, h: u32| -> Result<()> {
            if w > maxd || h > maxd {
                let way_out = if arg == "width" {
                    "lower the resolution (spp= renders its samples in tiles)".to_string()
                } else {
                    format!("crop it to at most {maxd} a side, or resample it: pk.textures.fit({arg}, {}) gives its centred square at that size", w.min(h).min(maxd))
                };
                return Err(Error::limit(
                    arg,
                    format!(
                        "{what} {w}x{h} exceeds the device's max_texture_dimension_2d = {maxd}; {way_out}"
                    ),
                ));
            }
            Ok(())
        };
        let cam = &scene.camera;
        dims("width", "frame", cam.width, cam.height)?;
        let bytes = targets::row_bytes(cam.width) * cam.height as u64;
        if bytes > lim.max_buffer_size {
            return Err(Error::limit(
                "width",
                format!("frame {}x{} needs a {bytes}-byte readback buffer; the device's max_buffer_size is {}: lower the resolution (spp= renders its samples in tiles)", cam.width, cam.height, lim.max_buffer_size),
            ));
        }
        for o in &scene.objects {
            let hm = &o.material.height;
            dims("height", "height map", hm.width, hm.height)?;
            if let Some(a) = &o.material.albedo {
                dims("albedo", "albedo", a.width, a.height)?;
            }
            let vbytes =
                o.mesh.positions.len() as u64 * std::mem::size_of::<crate::mesh::Vertex>() as u64;
            if vbytes > lim.max_buffer_size {
                return Err(Error::limit(
                    "mesh",
                    format!(
                        "vertex buffer of {vbytes} bytes exceeds the device's max_buffer_size = {}: split the mesh into several pk.Object, or decimate it",
                        lim.max_buffer_size
                    ),
                ));
            }
        }
        Ok(())
    }
}

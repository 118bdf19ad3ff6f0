//! The CPU float64 oracle: the exact first hit of each pixel's ray against the displaced surface
//! of any mesh (`shell`), and the cell walk it rests on (`field`).
//!
//! In each prism of the shell the ray's path in texture space is cut into chords, and each chord
//! is walked cell by cell (a 2-D DDA over the cells between texel centres): in each cell the
//! bilinear patch along the ray is a quadratic in the ray parameter, solved in closed form; no
//! step size, no missed features. The surface has one definition on every mesh
//! (docs/conventions.md, "The displaced surface"): it ends at open borders (a plane's too), and
//! a step at a uv seam whose heights disagree is closed by a wall. `planar` (tests only) is the
//! closed form under one planar object, which the shell must match inside a plane's border.
//!
//! The same walk, upward, gives the exact visibility of the scene's first directional light at
//! each hit: the fraction of the light's disk (`angular_diameter`, sampled on a stratified 8x8
//! grid; one direction for a zero diameter) whose ray from the hit leaves the shell (reaches
//! h = 1) without passing below the bilinear field. It is the ground truth for the per-pixel
//! methods' self-shadowing (`pk.metrics.shadow_error`).

pub mod field;
pub mod image;
pub mod shading;
#[cfg(test)]
pub(crate) mod planar;
pub(crate) mod shell;

mod rows;
pub(crate) mod trace;

pub use field::{light_ray_free, march_height_field, Field, MAX_CELLS};
pub use shell::Shells;
pub use trace::OracleHits;
use rows::interrupted;
use trace::hits_of;

use crate::error::{Error, Result};
use crate::scene::Scene;

/// The exact tracer of a scene: the shell walk, on every mesh (planes included: the surface
/// ends at their open border, docs/conventions.md, "The displaced surface"), its objects'
/// geometry from the caller's `shells`.
pub(crate) fn tracer<'a>(scene: &'a Scene, shells: &Shells) -> Result<shell::Shell<'a>> {
    scene.validate()?;
    shell::Shell::new(scene, shells)
}

/// The oracle's frame. `light_bias` (shell depths, >= 0) raises the light rays: a blocker must
/// rise more than it above the ray (0: the exact field; the GPU's exact shadows use 1e-4).
/// `shells` keeps the objects' shells for later calls on the same meshes and depths.
pub fn hits(scene: &Scene, light_bias: f64, shells: &Shells) -> Result<OracleHits> {
    if !(0.0..0.5).contains(&light_bias) {
        return Err(Error::arg(
            "light_bias",
            format!("must lie in [0, 0.5) shell depths, got {light_bias}"),
        ));
    }
    let out = hits_of(scene, &tracer(scene, shells)?, light_bias);
    interrupted()?;
    Ok(out)
}

#[cfg(test)]
mod tests;

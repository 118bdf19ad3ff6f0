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
#[cfg(test)]
pub(crate) mod planar;
pub(crate) mod shell;

pub use field::{light_ray_free, march_height_field, Field};

use crate::error::{Error, Result};
use crate::scene::Scene;
use glam::{DVec2, DVec3};

#[derive(Clone, Debug)]
pub struct OracleHits {
    pub width: u32,
    pub height: u32,
    /// H*W*2, NaN where the ray misses the mesh
    pub uv: Vec<f64>,
    /// distance eye -> hit
    pub depth: Vec<f64>,
    pub mask: Vec<bool>,
    /// cells visited per pixel
    pub cells: Vec<u32>,
    /// the first directional light's visibility at the hit (fraction of its disk unblocked by
    /// the height field), NaN where no hit or the scene has no directional light
    pub visibility: Vec<f64>,
    /// the index of the object hit, -1 where none
    pub object: Vec<i32>,
}

/// One exact hit: what the frame and the shading read, and the oracle's own place of it.
pub(crate) struct Hit<A> {
    /// mesh uv
    pub(crate) uv: DVec2,
    /// distance along the unit ray
    pub(crate) dist: f64,
    pub(crate) cells: u32,
    pub(crate) object: usize,
    /// texture-space point (uv * tiling) and height (the planar closed form's light rays start
    /// from it)
    pub(crate) s: DVec2,
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) h: f64,
    pub(crate) at: A,
}

/// An exact ray caster against the displaced surface: the shell walk (`shell::Shell`, any mesh),
/// or in tests the planar closed form (`planar::Oracle`) it is checked against.
pub(crate) trait Tracer: Sync {
    type At;
    /// The exact first hit of the ray from `eye` along the unit `dir`.
    fn trace(&self, eye: DVec3, dir: DVec3) -> Option<Hit<Self::At>>;
    /// Whether the ray from the hit along the world direction `l` leaves the displaced surface
    /// unblocked (a blocker must rise more than `bias` shell depths above it).
    fn reaches(&self, hit: &Hit<Self::At>, l: DVec3, bias: f64) -> bool;
    /// How many of the world directions `dirs` (a light's disk about the unit `axis`) reach
    /// from the hit, each as `reaches` answers it.
    fn reaches_all(&self, hit: &Hit<Self::At>, axis: DVec3, dirs: &[DVec3], bias: f64) -> usize {
        let _ = axis;
        dirs.iter().filter(|l| self.reaches(hit, **l, bias)).count()
    }
    /// The reference shading normal at the hit (docs/conventions.md), world space.
    fn normal(&self, hit: &Hit<Self::At>) -> DVec3;
    fn material(&self, object: usize) -> &crate::scene::Material;
}

/// Upper bound on cells walked per ray (a ray at 89.99 degrees over a 4k map stays below it).
pub const MAX_CELLS: u32 = 4_000_000;

/// The exact tracer of a scene: the shell walk, on every mesh (planes included: the surface
/// ends at their open border, docs/conventions.md, "The displaced surface").
pub(crate) fn exact(scene: &Scene) -> Result<shell::Shell<'_>> {
    scene.validate()?;
    shell::Shell::new(scene)
}

/// The oracle's frame. `light_bias` (shell depths, >= 0) raises the light rays: a blocker must
/// rise more than it above the ray (0: the exact field; the GPU's exact shadows use 1e-4).
pub fn exact_hits(scene: &Scene, light_bias: f64) -> Result<OracleHits> {
    if !(0.0..0.5).contains(&light_bias) {
        return Err(Error::arg(
            "light_bias",
            format!("must lie in [0, 0.5) shell depths, got {light_bias}"),
        ));
    }
    let out = oracle_hits(scene, &exact(scene)?, light_bias);
    interrupted()?;
    Ok(out)
}

/// Error::Interrupted where the computation was asked to stop (its rows are then incomplete).
pub(crate) fn interrupted() -> Result<()> {
    if crate::progress::stop_requested() {
        return Err(Error::Interrupted);
    }
    Ok(())
}

/// `exact_hits` with the tracer built (render_exact builds it once for both).
pub(crate) fn oracle_hits<T: Tracer>(scene: &Scene, oracle: &T, light_bias: f64) -> OracleHits {
    let cam = &scene.camera;
    let basis = cam.basis();
    let (w, h) = (cam.width, cam.height);
    let n = (w * h) as usize;
    let mut out = OracleHits {
        width: w,
        height: h,
        uv: vec![f64::NAN; n * 2],
        depth: vec![f64::NAN; n],
        mask: vec![false; n],
        cells: vec![0; n],
        visibility: vec![f64::NAN; n],
        object: vec![-1; n],
    };
    let light_dirs = first_light_directions(scene);
    let axis = light_dirs.iter().sum::<DVec3>().normalize_or_zero();
    let light_bias = light_bias.max(0.0);
    // per pixel of each row: (uv, distance, cells, visibility, object) where it hits
    let rows = par_rows(h as usize, |i| {
        (0..w)
            .map(|j| {
                let dir = cam.ray_dir(&basis, i as u32, j);
                let hit = oracle.trace(basis.eye, dir)?;
                let vis = if light_dirs.is_empty() {
                    f64::NAN
                } else {
                    let lit = oracle.reaches_all(&hit, axis, &light_dirs, light_bias);
                    lit as f64 / light_dirs.len() as f64
                };
                Some((hit.uv, hit.dist, hit.cells, vis, hit.object))
            })
            .collect::<Vec<_>>()
    });
    for (idx, px) in rows.into_iter().flatten().enumerate() {
        if let Some((uv, dist, cells, vis, object)) = px {
            out.uv[idx * 2] = uv.x;
            out.uv[idx * 2 + 1] = uv.y;
            out.depth[idx] = dist;
            out.mask[idx] = true;
            out.cells[idx] = cells;
            out.visibility[idx] = vis;
            out.object[idx] = object as i32;
        }
    }
    out
}

/// `f(row)` for every row in 0..rows, on the machine's cores (at most 8 threads, each taking
/// the next row not yet taken), in row order.
pub(crate) fn par_rows<T: Send>(rows: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let threads = std::thread::available_parallelism()
        .map(|x| x.get())
        .unwrap_or(1)
        .clamp(1, 8)
        .min(rows.max(1));
    let next = AtomicUsize::new(0);
    let (f, next) = (&f, &next);
    let mut done: Vec<(usize, T)> = std::thread::scope(|sc| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                sc.spawn(move || {
                    let mut mine = Vec::new();
                    loop {
                        let r = next.fetch_add(1, Ordering::Relaxed);
                        // rows past the end, or a request to stop (the caller then answers
                        // Error::Interrupted: `interrupted`)
                        if r >= rows || crate::progress::stop_requested() {
                            break mine;
                        }
                        mine.push((r, f(r)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|b| b.join().expect("a row worker panicked"))
            .collect()
    });
    done.sort_by_key(|(r, _)| *r);
    done.into_iter().map(|(_, t)| t).collect()
}

/// Directions toward the scene's first directional light (unit, world space): one for a zero
/// angular diameter, else 64 over its disk (a stratified 8x8 grid, concentric map), spread on
/// the plane perpendicular to the light as the penumbra estimates assume. Empty without one.
fn first_light_directions(scene: &Scene) -> Vec<DVec3> {
    use crate::scene::Light;
    let Some((dir, diameter)) = scene.lights.iter().find_map(|l| match l {
        Light::Directional(l) => Some((DVec3::from(l.direction), l.angular_diameter)),
        _ => None,
    }) else {
        return Vec::new();
    };
    let to_light = -dir.normalize();
    if diameter <= 0.0 {
        return vec![to_light];
    }
    disk_directions(to_light, (0.5 * diameter).to_radians().tan())
}

/// 64 directions over a disk of angular radius atan(`tan_r`) about the unit `to_light` (a
/// stratified 8x8 grid, concentric map), spread on the plane perpendicular to it.
pub(crate) fn disk_directions(to_light: DVec3, tan_r: f64) -> Vec<DVec3> {
    let (e1, e2) = perpendiculars(to_light, to_light.y.abs() < 0.9);
    stratified_disk()
        .into_iter()
        .map(|d| (to_light + (e1 * d.x + e2 * d.y) * tan_r).normalize())
        .collect()
}

/// A unit vector's two perpendiculars (e1 = v x a, e2 = v x e1, with a = Y or X), chosen as
/// shaders/shadows.wgsl's `perpendiculars` chooses them.
pub(crate) fn perpendiculars(v: DVec3, pick_y: bool) -> (DVec3, DVec3) {
    let a = if pick_y { DVec3::Y } else { DVec3::X };
    let e1 = v.cross(a).normalize();
    (e1, v.cross(e1))
}

/// 64 points on the unit disk: the centres of a stratified 8x8 grid, by Shirley and Chiu's
/// concentric map (their density uniform, their order row by row).
pub(crate) fn stratified_disk() -> Vec<DVec2> {
    let k = 8;
    let mut out = Vec::with_capacity(k * k);
    for i in 0..k {
        for j in 0..k {
            let a = 2.0 * (i as f64 + 0.5) / k as f64 - 1.0;
            let b = 2.0 * (j as f64 + 0.5) / k as f64 - 1.0;
            let (r, phi) = if a.abs() > b.abs() {
                (a, std::f64::consts::FRAC_PI_4 * (b / a))
            } else {
                (
                    b,
                    std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (a / b),
                )
            };
            out.push(DVec2::new(r * phi.cos(), r * phi.sin()));
        }
    }
    out
}

#[cfg(test)]
mod tests;

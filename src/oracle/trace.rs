//! What the oracle's tracers answer (`Tracer`, `Hit`), and the oracle's frame from any of them
//! (`hits_of`): per pixel the first hit and the first directional light's visibility there.

use super::rows::par_rows;
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

/// `hits` with the tracer built (`image::render` builds it once for both).
pub(crate) fn hits_of<T: Tracer>(scene: &Scene, oracle: &T, light_bias: f64) -> OracleHits {
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

//! The CPU float64 oracle: the exact first hit of each pixel's ray against the bilinear,
//! repeating height field under a planar base mesh.
//!
//! Each pixel's ray is intersected with the base mesh (the nearest front-facing triangle). From
//! there the ray is expressed in texture space (s = uv * tiling, h) using the triangle's exact
//! affine frame dP/du, dP/dv, N, and walked cell by cell (a 2-D DDA over the cells between
//! texel centres). In each cell the bilinear patch along the ray is a quadratic in the ray
//! parameter, solved in closed form; no step size, no missed features. The base plane is taken
//! as infinite under the hit triangle, which is what the per-pixel methods assume too.
//!
//! The same walk, upward, gives the exact visibility of the scene's first directional light at
//! each hit: the fraction of the light's disk (`angular_diameter`, sampled on a stratified 8x8
//! grid; one direction for a zero diameter) whose ray from the hit leaves the shell (reaches
//! h = 1) without passing below the bilinear field. It is the ground truth for the per-pixel
//! methods' self-shadowing (`pk.metrics.shadow_error`).

pub mod field;
pub mod image;
pub(crate) mod shell;

pub use field::{light_ray_free, march_height_field, Field};

use crate::error::{Error, Result};
use crate::scene::Scene;
use glam::{DMat3, DVec2, DVec3};

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
    /// texture-space point (uv * tiling) and height
    pub(crate) s: DVec2,
    pub(crate) h: f64,
    pub(crate) at: A,
}

/// An exact ray caster against the displaced surface: the planar oracle (`Oracle`, one planar
/// object) or the shell walk (`shell::Shell`, any mesh).
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

pub(crate) struct Tri {
    p0: DVec3,
    e1: DVec3,
    e2: DVec3,
    pub(crate) n: DVec3,
    pub(crate) dpdu: DVec3,
    pub(crate) dpdv: DVec3,
    uv0: DVec2,
    d1: DVec2,
    d2: DVec2,
    /// world direction -> (du, dv, dn) per unit world length
    to_tex: DMat3,
}

/// Upper bound on cells walked per ray (a ray at 89.99 degrees over a 4k map stays below it).
pub const MAX_CELLS: u32 = 4_000_000;

/// A planar scene's one object, ready for exact rays: its triangles' affine frames and its
/// material. Shared by the oracle's frame (`exact_hits`) and the exact image
/// (`oracle::image::render_exact`).
pub(crate) struct Oracle<'a> {
    pub(crate) tris: Vec<Tri>,
    pub(crate) mat: &'a crate::scene::Material,
    /// the height field with its max pyramid
    field: Field<'a>,
}

impl<'a> Oracle<'a> {
    pub(crate) fn new(scene: &'a Scene, what: &str) -> Result<Oracle<'a>> {
        scene.validate()?;
        let obj = scene.only_object(what)?;
        if !obj.transform.is_identity() {
            return Err(Error::arg(
                "transform",
                format!("{what} takes an untransformed object; bake the transform into the mesh"),
            ));
        }
        let m = &obj.mesh;
        planar(m, what)?;
        let (p, q) = (|i: u32| m.position_f64(i), |i: u32| m.uv_f64(i));
        let mut tris = Vec::new();
        for t in m.indices.chunks_exact(3) {
            let (p0, p1, p2) = (p(t[0]), p(t[1]), p(t[2]));
            let (e1, e2) = (p1 - p0, p2 - p0);
            let mut n = e1.cross(e2);
            if n.length() < 1e-14 {
                continue;
            }
            n = n.normalize();
            let vn = m.normal_f64(t[0]);
            if n.dot(vn) < 0.0 {
                n = -n;
            }
            let (d1, d2) = (q(t[1]) - q(t[0]), q(t[2]) - q(t[0]));
            let Some((dpdu, dpdv)) = crate::mesh::uv_derivatives(e1, e2, d1, d2) else {
                continue;
            };
            // columns dP/du, dP/dv, N: its inverse maps a world direction to (du, dv, dn)
            let basis = DMat3::from_cols(dpdu, dpdv, n);
            if basis.determinant().abs() < 1e-18 {
                continue;
            }
            tris.push(Tri {
                p0,
                e1,
                e2,
                n,
                dpdu,
                dpdv,
                uv0: q(t[0]),
                d1,
                d2,
                to_tex: basis.inverse(),
            });
        }
        if tris.is_empty() {
            return Err(Error::arg(
                "mesh",
                "no triangle with usable positions and uvs",
            ));
        }
        Ok(Oracle {
            tris,
            mat: &obj.material,
            field: Field::new(&obj.material.height),
        })
    }
}

impl Tracer for Oracle<'_> {
    type At = usize;

    fn trace(&self, eye: DVec3, dir: DVec3) -> Option<Hit<usize>> {
        let m = self.mat;
        trace(
            eye,
            dir,
            &self.tris,
            &self.field,
            m.depth as f64,
            m.tiling as f64,
        )
    }

    fn reaches(&self, hit: &Hit<usize>, l: DVec3, bias: f64) -> bool {
        let m = self.mat;
        let t = &self.tris[hit.at];
        light_reaches(
            hit,
            t,
            l,
            &self.field,
            m.depth as f64,
            m.tiling as f64,
            bias,
        )
    }

    fn normal(&self, hit: &Hit<usize>) -> DVec3 {
        let hm = &self.mat.height;
        let (depth, tiling) = (self.mat.depth as f64, self.mat.tiling as f64);
        let (ex, ey) = (1.0 / hm.width as f64, 1.0 / hm.height as f64);
        let s = hit.s;
        // dh/du = tiling dh/ds, by central differences one texel apart
        let hu = tiling * (hm.sample(s.x + ex, s.y) - hm.sample(s.x - ex, s.y)) / (2.0 * ex);
        let hv = tiling * (hm.sample(s.x, s.y + ey) - hm.sample(s.x, s.y - ey)) / (2.0 * ey);
        let t = &self.tris[hit.at];
        let n = (t.dpdu + t.n * (depth * hu)).cross(t.dpdv + t.n * (depth * hv));
        let n = n.normalize_or_zero();
        if n.dot(t.n) < 0.0 {
            -n
        } else {
            n
        }
    }

    fn material(&self, _object: usize) -> &crate::scene::Material {
        self.mat
    }
}

/// Each triangle with area and its unit normal (by its winding).
fn face_normals(m: &crate::mesh::Mesh) -> impl Iterator<Item = (&[u32], DVec3)> {
    m.indices.chunks_exact(3).filter_map(|t| {
        let p = |i: u32| m.position_f64(i);
        let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        (n.length() >= 1e-14).then(|| (t, n.normalize()))
    })
}

/// Whether every triangle of the mesh lies in one plane with every vertex normal its normal.
fn flat(m: &crate::mesh::Mesh) -> bool {
    if planar(m, "").is_err() {
        return false;
    }
    let mut first: Option<(DVec3, DVec3)> = None;
    let (lo, hi) = m.bounds();
    let tol = 1e-9 * (hi - lo).max_element().max(1e-30);
    let p = |i: u32| m.position_f64(i);
    for (t, n) in face_normals(m) {
        match first {
            None => first = Some((p(t[0]), n)),
            Some((p0, n0)) => {
                if n.dot(n0) < 1.0 - 1e-9 || t.iter().any(|&i| (p(i) - p0).dot(n0).abs() > tol) {
                    return false;
                }
            }
        }
    }
    true
}

/// A curved mesh's triangles are not its surface (the surface follows the interpolated normals):
/// the oracle, which takes each triangle's plane as the base under it, answers for planar meshes
/// only, every vertex normal its triangle's normal (a plane, a cube, a flat mesh).
fn planar(m: &crate::mesh::Mesh, what: &str) -> Result<()> {
    for (t, n) in face_normals(m) {
        for &i in t {
            if m.normal_f64(i).normalize_or_zero().dot(n).abs() < 1.0 - 1e-6 {
                let p = m.positions[i as usize];
                return Err(Error::arg(
                    "mesh",
                    format!("{what} answers for planar meshes only (every vertex normal its triangle's normal: a plane, a cube, a flat mesh); this mesh is curved (vertex {i} at ({}, {}, {}) has a normal off its triangle's), and there the displaced surface follows the interpolated normals, not the triangles; for a curved mesh, pk.reference.render_exact casts against the displaced mesh with Mitsuba, and pk.Tessellated renders it", p[0], p[1], p[2]),
                ));
            }
        }
    }
    Ok(())
}

/// The exact tracer a scene takes: the planar oracle for one untransformed flat object (a
/// plane: its plane extended under each hit, past the border too, as the per-pixel methods take
/// it), the shell walk for everything else (curved meshes, hard edges, several objects,
/// transforms).
pub(crate) enum Exact<'a> {
    Planar(Oracle<'a>),
    Shell(shell::Shell<'a>),
}

impl<'a> Exact<'a> {
    pub(crate) fn new(scene: &'a Scene, what: &str) -> Result<Exact<'a>> {
        scene.validate()?;
        let planar_one =
            matches!(scene.objects.as_slice(), [o] if o.transform.is_identity() && flat(&o.mesh));
        Ok(if planar_one {
            Exact::Planar(Oracle::new(scene, what)?)
        } else {
            Exact::Shell(shell::Shell::new(scene)?)
        })
    }
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
    Ok(match Exact::new(scene, "the CPU oracle (exact_uv)")? {
        Exact::Planar(o) => oracle_hits(scene, &o, light_bias),
        Exact::Shell(o) => oracle_hits(scene, &o, light_bias),
    })
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
                        if r >= rows {
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

fn trace(
    eye: DVec3,
    dir: DVec3,
    tris: &[Tri],
    field: &Field,
    depth: f64,
    tiling: f64,
) -> Option<Hit<usize>> {
    // nearest front-facing triangle (Moller-Trumbore)
    let mut best: Option<(f64, usize, f64, f64)> = None;
    for (ti, t) in tris.iter().enumerate() {
        if dir.dot(t.n) >= 0.0 {
            continue;
        }
        let pv = dir.cross(t.e2);
        let det = t.e1.dot(pv);
        if det.abs() < 1e-18 {
            continue;
        }
        let inv = 1.0 / det;
        let tv = eye - t.p0;
        let b1 = tv.dot(pv) * inv;
        if !(-1e-12..=1.0 + 1e-12).contains(&b1) {
            continue;
        }
        let qv = tv.cross(t.e1);
        let b2 = dir.dot(qv) * inv;
        if b2 < -1e-12 || b1 + b2 > 1.0 + 1e-12 {
            continue;
        }
        let d = t.e2.dot(qv) * inv;
        if d > 0.0 && best.is_none_or(|b| d < b.0) {
            best = Some((d, ti, b1, b2));
        }
    }
    let (d0, ti, b1, b2) = best?;
    let t = &tris[ti];
    let uv0 = t.uv0 + t.d1 * b1 + t.d2 * b2;
    let c = t.to_tex * dir; // (du, dv, dn) per unit world length
    let dh = c.z / depth.max(1e-300);
    let s0 = uv0 * tiling;
    if depth <= 0.0 {
        return Some(Hit {
            uv: uv0,
            dist: d0,
            cells: 0,
            object: 0,
            s: s0,
            h: 1.0,
            at: ti,
        });
    }
    let ds = DVec2::new(c.x, c.y) * tiling;
    let (lam, cells) = march_height_field(field, s0, ds, dh)?;
    let s = s0 + ds * lam;
    let h = (1.0 + dh * lam).clamp(0.0, 1.0);
    Some(Hit {
        uv: s / tiling,
        dist: d0 + lam,
        cells,
        object: 0,
        s,
        h,
        at: ti,
    })
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

/// Whether the ray from the hit toward the light (world direction `l`) leaves the shell: it
/// rises from the hit's height to h = 1 without passing below the bilinear field. A light below
/// the base tangent plane is blocked (the tiled field continues under it), as on the GPU.
fn light_reaches(
    hit: &Hit<usize>,
    tri: &Tri,
    l: DVec3,
    field: &Field,
    depth: f64,
    tiling: f64,
    bias: f64,
) -> bool {
    let c = tri.to_tex * l;
    if depth <= 0.0 {
        return c.z > 0.0;
    }
    if c.z <= 0.0 {
        return false;
    }
    light_ray_free(
        field,
        hit.s,
        hit.h,
        DVec2::new(c.x, c.y) * tiling,
        c.z / depth,
        bias,
    )
}

#[cfg(test)]
mod tests;

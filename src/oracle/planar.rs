//! The planar closed form: the exact first hit against the bilinear field under one planar
//! object, each triangle's plane taken as infinite under its hit (no border). The shell walk
//! (`shell`) answers for every mesh, planes included (their open border ends the surface); this
//! closed form checks it inside a plane's border, where both must agree.

use super::field::{light_ray_free, march_height_field, Field};
use super::trace::{Hit, Tracer};
use crate::error::{Error, Result};
use crate::scene::Scene;
use glam::{DMat3, DVec2, DVec3};

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

/// A planar scene's one object, ready for exact rays: its triangles' affine frames and its
/// material. Shared by the oracle's frame (`hits`) and the exact image
/// (`oracle::image::render`).
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

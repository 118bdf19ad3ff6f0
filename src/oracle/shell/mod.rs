//! The float64 oracle on any mesh: the exact first hit of a ray with the displaced surface
//! S = P + depth (h - 1) N of every object of a scene (curved, several, transformed), P and N
//! interpolated over each base triangle as the tessellator and the shaders define them (N the
//! normalised interpolated vertex normal).
//!
//! A ray enters the shell through its top, the base mesh (a bounding volume hierarchy finds the
//! triangles it crosses going in), and walks from prism to prism (prism.rs): through a side
//! into the triangle across it (the same side where positions and normals agree, across uv
//! seams too), out through the top, or out through an open border's side. In each prism the
//! ray's path in texture space, (uv(b) * tiling, h), is a smooth curve: it is cut into chords,
//! each bounded by its deviation from the curve at its middle, and a chord whose box of cells
//! lies under the ray (the max pyramid's bound) holds no hit; elsewhere chords are halved until
//! they deviate by at most `TOL_TEXELS` from the curve, and then walked exactly by the planar
//! oracle's cell walk (field.rs). Hits are therefore exact to within `TOL_TEXELS` along the
//! surface (in height, to what that distance along the ray makes).
//!
//! Light rays are the same walk from the hit: a light is visible where its ray leaves the shell
//! without meeting the surface and meets no object's shell again (every object occludes, as in
//! the world and in Mitsuba's reference).

mod bvh;
pub(crate) mod prism;

use super::field::{walk_cells, Field};
use super::{Hit, Tracer};
use crate::error::{Error, Result};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::scene::{Material, Scene};
use bvh::Bvh;
use glam::{DMat3, DMat4, DVec2, DVec3};
use prism::{Crossing, Local, Prism};

/// The largest deviation, in texels, of a walked chord from the ray's path in texture space
/// (the hit it finds is then moved onto the path itself).
pub const TOL_TEXELS: f64 = 1e-2;

/// A hit's place: its object-space point and where in which prism.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShellAt {
    tri: u32,
    at: Local,
    x: DVec3,
}

struct Object<'a> {
    mesh: &'a Mesh,
    mat: &'a Material,
    field: Field<'a>,
    prisms: Vec<Option<Prism>>,
    /// per triangle and side k (corners k, k+1): the triangle across it where the two shells
    /// share the side (the same positions and normals); None at a wall (an open border, a hard
    /// edge), where a ray may enter the shell from the side
    across: Vec<[Option<u32>; 3]>,
    /// the triangles with a wall
    walled: Vec<bool>,
    /// welded id per vertex (the same position)
    weld: Vec<u32>,
    bvh: Bvh,
    to_obj: DMat4,
    to_world: DMat4,
    normal_to_world: DMat3,
    depth: f64,
    tiling: f64,
    /// object-space size of the whole mesh (for tolerances)
    extent: f64,
}

/// A ray's walk through one object's shell: a hit, or where it left.
enum Walk {
    Hit {
        tri: u32,
        lam: f64,
        at: Local,
        cells: u32,
    },
    Left {
        lam: f64,
        cells: u32,
    },
}

/// A point of the ray's path in a prism: texture point s = uv * tiling, height h.
#[derive(Clone, Copy, Debug)]
struct Sample {
    lam: f64,
    at: Local,
    s: DVec2,
    h: f64,
    /// s in cells (for bounds and deviations)
    c: DVec2,
}

/// The scene's objects, ready for exact rays on any mesh.
pub(crate) struct Shell<'a> {
    objects: Vec<Object<'a>>,
}

impl<'a> Shell<'a> {
    pub(crate) fn new(scene: &'a Scene) -> Result<Shell<'a>> {
        scene.validate()?;
        let mut objects = Vec::new();
        for o in &scene.objects {
            objects.push(Object::new(&o.mesh, &o.material, o.transform.m)?);
        }
        if objects.is_empty() {
            return Err(Error::arg("scene", "has no objects; add one"));
        }
        Ok(Shell { objects })
    }

    /// The first hit of the ray eye + lam dir over lam > lam_min with any object's displaced
    /// surface (with `any`, the first found): object, triangle, lam, point, cells walked.
    fn first(
        &self,
        eye: DVec3,
        dir: DVec3,
        lam_min: f64,
        any: bool,
    ) -> Option<(usize, u32, f64, Local, u32)> {
        let mut entries: Vec<(f64, usize, u32, Local)> = Vec::new();
        let mut found: Option<(usize, u32, f64, Local, u32)> = None;
        for (oi, ob) in self.objects.iter().enumerate() {
            let o = ob.to_obj.transform_point3(eye);
            let d = ob.to_obj.transform_vector3(dir);
            // a start of the walk: walked at once for `any`, else kept in order
            let mut start = |t: u32, lam: f64, at: Local| -> bool {
                if !(lam > lam_min) {
                    return true;
                }
                if !any {
                    entries.push((lam, oi, t, at));
                    return true;
                }
                match ob.walk(o, d, t, lam, at, 0.0) {
                    Walk::Hit {
                        tri,
                        lam,
                        at,
                        cells,
                    } => {
                        found = Some((oi, tri, lam, at, cells));
                        false
                    }
                    Walk::Left { .. } => true,
                }
            };
            ob.bvh.visit(o, d, lam_min, f64::INFINITY, |t| {
                let Some(p) = ob.prisms[t as usize].as_ref() else {
                    return true;
                };
                if let Some((lam, b)) = p.entry(o, d) {
                    if !start(t, lam, entry_at(b)) {
                        return false;
                    }
                }
                if !ob.walled[t as usize] {
                    return true;
                }
                // through a wall, into the shell and above the surface
                let mut walls: [Option<Crossing>; 6] = [None; 6];
                let mut i = 0;
                for k in 0..3 {
                    if ob.across[t as usize][k].is_none() {
                        p.crossings(o, d, k, false, &mut |c: Crossing| {
                            let off = p.offset(c.at);
                            if off <= 0.0 && off >= -ob.depth && ob.above(p, c.at) {
                                walls[i] = Some(c);
                                i += 1;
                            }
                        });
                    }
                }
                walls.iter().flatten().all(|c| start(t, c.lam, c.at))
            });
            if found.is_some() {
                return found;
            }
        }
        entries.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<(usize, u32, f64, Local)> = None;
        let mut cells = 0u32;
        for (lam, oi, t, start) in entries {
            if best.is_some_and(|h| h.2 <= lam) {
                break;
            }
            let ob = &self.objects[oi];
            let (o, d) = (
                ob.to_obj.transform_point3(eye),
                ob.to_obj.transform_vector3(dir),
            );
            match ob.walk(o, d, t, lam, start, 0.0) {
                Walk::Hit {
                    tri,
                    lam,
                    at,
                    cells: c,
                } => {
                    cells += c;
                    if best.is_none_or(|h| lam < h.2) {
                        best = Some((oi, tri, lam, at));
                    }
                }
                Walk::Left { cells: c, .. } => cells += c,
            }
        }
        best.map(|(oi, tri, lam, at)| (oi, tri, lam, at, cells))
    }
}

/// A ray's point on a prism's top where it enters.
fn entry_at(b: DVec2) -> Local {
    Local {
        b: b.clamp(DVec2::ZERO, DVec2::ONE),
        s: 0.0,
    }
}

impl Tracer for Shell<'_> {
    type At = ShellAt;

    fn trace(&self, eye: DVec3, dir: DVec3) -> Option<Hit<ShellAt>> {
        let (oi, tri, lam, at, cells) = self.first(eye, dir, 0.0, false)?;
        let ob = &self.objects[oi];
        let p = ob.prisms[tri as usize].as_ref().expect("a hit's prism");
        let uv = p.uv(at.b);
        let h = if ob.depth > 0.0 {
            (1.0 + p.offset(at) / ob.depth).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let x = ob.to_obj.transform_point3(eye + dir * lam);
        Some(Hit {
            uv,
            dist: lam,
            cells,
            object: oi,
            s: uv * ob.tiling,
            h,
            at: ShellAt { tri, at, x },
        })
    }

    fn reaches(&self, hit: &Hit<ShellAt>, l: DVec3, bias: f64) -> bool {
        let ob = &self.objects[hit.object];
        let d = ob.to_obj.transform_vector3(l);
        let lift = bias.max(1e-9);
        match ob.walk(hit.at.x, d, hit.at.tri, 0.0, hit.at.at, lift) {
            Walk::Hit { .. } => false,
            Walk::Left { lam, .. } => {
                // where it left, in the world: the rest of the ray meets no shell again
                let eye = ob.to_world.transform_point3(hit.at.x);
                let eps = 1e-9 * (1.0 + lam.abs());
                self.first(eye, l, lam + eps, true).is_none()
            }
        }
    }

    fn normal(&self, hit: &Hit<ShellAt>) -> DVec3 {
        let ob = &self.objects[hit.object];
        let p = ob.prisms[hit.at.tri as usize]
            .as_ref()
            .expect("a hit's prism");
        let m = ob.mesh;
        let w = Prism::weights(hit.at.at.b);
        let (mut n, mut t, mut sc) = (DVec3::ZERO, DVec3::ZERO, DVec2::ZERO);
        for (k, &v) in p.v.iter().enumerate() {
            let tg = m.tangents[v as usize];
            n += p.n[k] * w[k];
            t += DVec3::new(tg[0] as f64, tg[1] as f64, tg[2] as f64) * w[k];
            sc += DVec2::new(
                m.uv_scale[v as usize][0] as f64,
                m.uv_scale[v as usize][1] as f64,
            ) * w[k];
        }
        use crate::methods::tessellated::tessellate::{base_frame, displaced_normal};
        let (n, t, bt) = base_frame(
            n.normalize_or_zero(),
            t,
            m.tangents[p.v[0] as usize][3] as f64,
        );
        let sn = displaced_normal(ob.mat, hit.s, n, t, bt, sc);
        (ob.normal_to_world * sn).normalize_or_zero()
    }

    fn material(&self, object: usize) -> &Material {
        self.objects[object].mat
    }
}

impl<'a> Object<'a> {
    fn new(mesh: &'a Mesh, mat: &'a Material, m: DMat4) -> Result<Object<'a>> {
        let n = mesh.indices.len() / 3;
        let prisms: Vec<Option<Prism>> = (0..n).map(|t| Prism::new(mesh, t)).collect();
        if prisms.iter().all(Option::is_none) {
            return Err(Error::arg(
                "mesh",
                "no triangle with usable positions and uvs",
            ));
        }
        let topo = Topology::quantised(mesh);
        let across: Vec<[Option<u32>; 3]> = (0..n)
            .map(|t| {
                std::array::from_fn(|k| {
                    let e = topo.tri_edges[t][k] as usize;
                    let p = prisms[t].as_ref()?;
                    // (a triangle without area, as at a sphere's poles, is looked through)
                    let other = topo.edges[e]
                        .1
                        .iter()
                        .find(|s| s.tri as usize != t && prisms[s.tri as usize].is_some())?;
                    let q = prisms[other.tri as usize].as_ref()?;
                    // the same side only where both ends carry the same normal on both
                    let same = [k, (k + 1) % 3].iter().all(|&c| {
                        (0..3).any(|j| {
                            topo.weld[q.v[j] as usize] == topo.weld[p.v[c] as usize]
                                && (q.n[j] - p.n[c]).length() <= 1e-5
                        })
                    });
                    same.then_some(other.tri)
                })
            })
            .collect();
        let walled: Vec<bool> = (0..n)
            .map(|t| prisms[t].is_some() && across[t].iter().any(Option::is_none))
            .collect();
        let (lo, hi) = mesh.bounds();
        let extent = (hi - lo).max_element().max(1e-30);
        let depth = mat.depth as f64;
        // each prism's box: its top and its floor (depth along each corner's normal, and as
        // much again for the floor's bulge between corners, where |n(b)| < 1)
        let boxes: Vec<Option<(DVec3, DVec3)>> = prisms
            .iter()
            .map(|p| {
                let p = p.as_ref()?;
                let (mut lo, mut hi) = (p.p[0], p.p[0]);
                for k in 0..3 {
                    for x in [p.p[k], p.p[k] - p.n[k] * (2.0 * depth)] {
                        lo = lo.min(x);
                        hi = hi.max(x);
                    }
                }
                let pad = DVec3::splat(1e-9 * extent);
                Some((lo - pad, hi + pad))
            })
            .collect();
        // a ray enters a prism through its top against its normal; through a wall, any way
        let facing: Vec<Option<DVec3>> = (0..n)
            .map(|t| prisms[t].as_ref().filter(|_| !walled[t]).map(|p| p.ng))
            .collect();
        let lin = DMat3::from_mat4(m);
        Ok(Object {
            mesh,
            mat,
            field: Field::new(&mat.height),
            prisms,
            across,
            walled,
            weld: topo.weld,
            bvh: Bvh::new(&boxes, &facing),
            to_obj: m.inverse(),
            to_world: m,
            normal_to_world: lin.inverse().transpose(),
            depth,
            tiling: mat.tiling as f64,
            extent,
        })
    }

    /// Whether a point of prism `p` lies above the surface.
    fn above(&self, p: &Prism, at: Local) -> bool {
        let s = p.uv(at.b) * self.tiling;
        1.0 + p.offset(at) / self.depth > self.mat.height.sample(s.x, s.y)
    }

    fn sample(&self, p: &Prism, lam: f64, at: Local, lift: f64) -> Sample {
        let s = p.uv(at.b) * self.tiling;
        let hm = &self.mat.height;
        Sample {
            lam,
            at,
            s,
            h: 1.0 + p.offset(at) / self.depth + lift,
            c: DVec2::new(s.x * hm.width as f64, s.y * hm.height as f64),
        }
    }

    /// The walk of the ray o + lam d (object space) from `at` in prism `tri` at `lam0`.
    fn walk(&self, o: DVec3, d: DVec3, tri: u32, lam0: f64, at: Local, lift: f64) -> Walk {
        let (mut tri, mut lam, mut at) = (tri, lam0, at);
        if !(self.depth > 0.0) {
            // no shell: the base surface itself
            let p = self.prisms[tri as usize].as_ref().expect("a walked prism");
            return if lift > 0.0 && d.dot(p.normal(at.b)) > 0.0 {
                Walk::Left { lam, cells: 0 }
            } else {
                Walk::Hit {
                    tri,
                    lam,
                    at,
                    cells: 0,
                }
            };
        }
        let mut cells = 0u32;
        let eps = 1e-12 * self.extent / d.length().max(1e-300);
        for _ in 0..100_000 {
            let p = self.prisms[tri as usize].as_ref().expect("a walked prism");
            // the first side crossing ahead (those above the top do not bound the prism)
            let mut side: Option<Crossing> = None;
            for k in 0..3 {
                p.crossings(o, d, k, true, &mut |c: Crossing| {
                    if c.lam >= lam - eps
                        && p.offset(c.at) <= 1e-9 * self.depth
                        && side.is_none_or(|s| c.lam < s.lam)
                    {
                        side = Some(c);
                    }
                });
            }
            let top = p.top_exit(o, d).filter(|(l, _)| *l >= lam - eps);
            // where the prism ends along the ray (far below the floor where nothing bounds it:
            // the surface is met first)
            let (end, via): (Sample, Option<Crossing>) = match (top, side) {
                (Some((lt, bt)), s) if s.is_none_or(|s| lt <= s.lam) => {
                    (self.sample(p, lt, bt, lift), None)
                }
                (_, Some(s)) => (self.sample(p, s.lam, s.at, lift), Some(s)),
                _ => {
                    let far = lam + 4.0 * (self.extent + self.depth) / d.length().max(1e-300);
                    match p.locate(o + d * far, at) {
                        Some(a) => (self.sample(p, far, a, lift), None),
                        None => return Walk::Left { lam: far, cells },
                    }
                }
            };
            let start = self.sample(p, lam, at, lift);
            if let Some((l, a)) = self.chord(p, o, d, (start, end), lift, 0, &mut cells) {
                return Walk::Hit {
                    tri,
                    lam: l,
                    at: a,
                    cells,
                };
            }
            let Some(c) = via else {
                return Walk::Left {
                    lam: end.lam,
                    cells,
                };
            };
            // into the triangle across the side, at the same point
            let Some(next) = self.across[tri as usize][c.side] else {
                return Walk::Left {
                    lam: end.lam,
                    cells,
                };
            };
            let q = self.prisms[next as usize]
                .as_ref()
                .expect("a neighbour with area");
            let x = o + d * c.lam;
            let w = Prism::weights(c.at.b);
            // the same corners in the neighbour, by position
            let mut wq = [0.0; 3];
            for k in 0..3 {
                if let Some(j) =
                    (0..3).find(|&j| self.weld[q.v[j] as usize] == self.weld[p.v[k] as usize])
                {
                    wq[j] = w[k];
                }
            }
            let guess = Local {
                b: DVec2::new(wq[1], wq[2]),
                s: c.at.s,
            };
            match q.locate(x, guess) {
                Some(a) if Prism::inside(a.b, 1e-7) => {
                    (tri, lam, at) = (next, c.lam, a);
                }
                // a hard edge: the neighbour's shell does not begin here
                _ => {
                    return Walk::Left {
                        lam: end.lam,
                        cells,
                    }
                }
            }
        }
        Walk::Left { lam, cells }
    }

    /// The first hit on the path from `a` to `b` in prism `p`: its lam and point.
    #[allow(clippy::too_many_arguments)]
    fn chord(
        &self,
        p: &Prism,
        o: DVec3,
        d: DVec3,
        (a, b): (Sample, Sample),
        lift: f64,
        level: u32,
        cells: &mut u32,
    ) -> Option<(f64, Local)> {
        *cells += 1;
        let lm = 0.5 * (a.lam + b.lam);
        let guess = Local {
            b: 0.5 * (a.at.b + b.at.b),
            s: 0.5 * (a.at.s + b.at.s),
        };
        let Some(located) = p.locate(o + d * lm, guess) else {
            // the middle lies where the normals cross, far below the floor: the surface is met
            // before it
            let m = self.sample(p, lm, guess, lift);
            return if level >= 48 {
                None
            } else {
                self.chord(p, o, d, (a, m), lift, level + 1, cells)
            };
        };
        let m = self.sample(p, lm, located, lift);
        let (mid_c, mid_h) = (0.5 * (a.c + b.c), 0.5 * (a.h + b.h));
        let (dev_c, dev_h) = ((m.c - mid_c).length(), (m.h - mid_h).abs());
        // the path's bounds: the chord's, widened by twice its deviation at the middle
        let (ec, eh) = (2.0 * dev_c + 1e-6, 2.0 * dev_h + 1e-9);
        let low = a.h.min(b.h).min(m.h) - eh;
        let (clo, chi) = (a.c.min(b.c).min(m.c) - ec, a.c.max(b.c).max(m.c) + ec);
        // cells: texel centres at integers (x - 0.5)
        let top = self
            .field
            .max_in((clo.x - 0.5, chi.x - 0.5), (clo.y - 0.5, chi.y - 0.5));
        if low > top + 1e-12 {
            return None;
        }
        let run = (b.c - a.c).length();
        let tol_h = (TOL_TEXELS * (b.h - a.h).abs() / run.max(1e-300)).clamp(1e-9, 1e-3);
        if (dev_c <= TOL_TEXELS && dev_h <= tol_h) || level >= 48 {
            for (u, v) in [(a, m), (m, b)] {
                let (hit, n) = walk_cells(&self.field, u.s, u.h, v.s - u.s, v.h - u.h, 1.0);
                *cells += n;
                if let Some(mu) = hit {
                    let lam = u.lam + mu * (v.lam - u.lam);
                    let g = Local {
                        b: u.at.b + (v.at.b - u.at.b) * mu,
                        s: u.at.s + (v.at.s - u.at.s) * mu,
                    };
                    let at = p.locate(o + d * lam, g).unwrap_or(g);
                    return Some(self.refine(p, o, d, (lam, at), (u, v), lift));
                }
            }
            return None;
        }
        self.chord(p, o, d, (a, m), lift, level + 1, cells)
            .or_else(|| self.chord(p, o, d, (m, b), lift, level + 1, cells))
    }

    /// The chord's hit `(lam, at)` moved onto the path itself: bisection on the path between a
    /// point above the field and one at or below it, within the chord `(u, v)` and near the
    /// chord's answer (where no such pair is found, the chord's answer stands).
    fn refine(
        &self,
        p: &Prism,
        o: DVec3,
        d: DVec3,
        (lam, at): (f64, Local),
        (u, v): (Sample, Sample),
        lift: f64,
    ) -> (f64, Local) {
        let hm = &self.mat.height;
        // field above the path at lam: >= 0 where met
        let g = |l: f64, guess: Local| -> Option<(f64, Local)> {
            let a = p.locate(o + d * l, guess)?;
            let x = self.sample(p, l, a, lift);
            Some((hm.sample(x.s.x, x.s.y) - x.h, a))
        };
        let span = (v.lam - u.lam).abs();
        let mut delta = 1e-6 * span + 1e-15;
        while delta <= span {
            let (lo, hi) = ((lam - delta).max(u.lam), (lam + delta).min(v.lam));
            match (g(lo, at), g(hi, at)) {
                (Some((glo, alo)), Some((ghi, ahi))) if glo < 0.0 && ghi >= 0.0 => {
                    // Illinois: regula falsi that halves a stale end's weight
                    let (mut lo, mut hi) = ((lo, glo, alo), (hi, ghi, ahi));
                    let mut side = 0;
                    for _ in 0..60 {
                        if hi.0 - lo.0 <= 1e-13 * (1.0 + hi.0.abs()) {
                            break;
                        }
                        let t = lo.0 + (hi.0 - lo.0) * (lo.1 / (lo.1 - hi.1)).clamp(0.0, 1.0);
                        let mid = if t > lo.0 && t < hi.0 {
                            t
                        } else {
                            0.5 * (lo.0 + hi.0)
                        };
                        let Some((gm, am)) = g(mid, hi.2) else { break };
                        if gm >= 0.0 {
                            hi = (mid, gm, am);
                            if side == 1 {
                                lo.1 *= 0.5;
                            }
                            side = 1;
                        } else {
                            lo = (mid, gm, am);
                            if side == -1 {
                                hi.1 *= 0.5;
                            }
                            side = -1;
                        }
                    }
                    return (hi.0, hi.2);
                }
                _ => delta *= 8.0,
            }
        }
        (lam, at)
    }
}

#[cfg(test)]
mod tests;

//! One base triangle's shell (its prism) in object space: the points P(b) + s n(b), with b the
//! barycentrics, P and the vertex normals n interpolated linearly and s along the unnormalised
//! n(b). The displaced surface is the level set h(b, s) = H(uv(b)), h = 1 + s |n(b)| / depth.
//!
//! The prism's top is the base triangle (s = 0); its sides are the ruled surfaces over its
//! edges along the interpolated normals, which neighbours with the same positions and normals
//! share (so that the shells of a smooth mesh tile space without gaps or overlaps).

use crate::mesh::Mesh;
use glam::{DVec2, DVec3};

/// A base triangle in object space.
#[derive(Clone, Debug)]
pub(crate) struct Prism {
    pub(crate) v: [u32; 3],
    pub(crate) p: [DVec3; 3],
    pub(crate) n: [DVec3; 3],
    pub(crate) uv: [DVec2; 3],
    /// the plane's unit normal, on the side the vertex normals point to
    pub(crate) ng: DVec3,
    /// the longer of the edges from corner 0 (for `locate`'s tolerance)
    size: f64,
    /// the plane's dual basis: a point x of the plane has barycentrics
    /// ((x - p0) . dual[0], (x - p0) . dual[1])
    dual: [DVec3; 2],
    /// the edges from corner 0 (p1 - p0, p2 - p0), and the same differences of n and uv
    e: [DVec3; 2],
    pub(crate) dn: [DVec3; 2],
    pub(crate) duv: [DVec2; 2],
}

/// A point of a prism: barycentrics of corners 1 and 2, and s along n(b).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Local {
    pub(crate) b: DVec2,
    pub(crate) s: f64,
}

/// A ray's place in one object's shell: the prism (its base triangle), the ray's parameter and
/// the point there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Place {
    pub(crate) tri: u32,
    pub(crate) lam: f64,
    pub(crate) at: Local,
}

/// A ray's crossing of one of a prism's sides: where, and the point there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Crossing {
    pub(crate) lam: f64,
    pub(crate) side: usize,
    pub(crate) at: Local,
}

impl Prism {
    /// Triangle `t` of `m`, or None where it has no area.
    pub(crate) fn new(m: &Mesh, t: usize) -> Option<Prism> {
        let v = [m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]];
        let p = v.map(|i| m.position_f64(i));
        let n = v.map(|i| m.normal_f64(i).normalize_or_zero());
        let ng = (p[1] - p[0]).cross(p[2] - p[0]);
        if !(ng.length() > 1e-14 * (p[1] - p[0]).length_squared().max(1e-300)) {
            return None;
        }
        let mut ng = ng.normalize();
        if ng.dot(n[0] + n[1] + n[2]) < 0.0 {
            ng = -ng;
        }
        let (u, w) = (p[1] - p[0], p[2] - p[0]);
        let (uu, uw, ww) = (u.dot(u), u.dot(w), w.dot(w));
        let det = uu * ww - uw * uw;
        let uv = v.map(|i| m.uv_f64(i));
        Some(Prism {
            e: [u, w],
            dn: [n[1] - n[0], n[2] - n[0]],
            duv: [uv[1] - uv[0], uv[2] - uv[0]],
            size: u.length().max(w.length()),
            dual: [(u * ww - w * uw) / det, (w * uu - u * uw) / det],
            v,
            p,
            n,
            uv,
            ng,
        })
    }

    pub(crate) fn weights(b: DVec2) -> [f64; 3] {
        [1.0 - b.x - b.y, b.x, b.y]
    }

    /// The unnormalised interpolated normal n(b).
    pub(crate) fn normal(&self, b: DVec2) -> DVec3 {
        self.n[0] + self.dn[0] * b.x + self.dn[1] * b.y
    }

    #[cfg(test)]
    pub(crate) fn point(&self, at: Local) -> DVec3 {
        self.point_along(at, self.normal(at.b))
    }

    /// The point at `at`, given n(b) there.
    fn point_along(&self, at: Local, n: DVec3) -> DVec3 {
        self.p[0] + self.e[0] * at.b.x + self.e[1] * at.b.y + n * at.s
    }

    pub(crate) fn uv(&self, b: DVec2) -> DVec2 {
        self.uv[0] + self.duv[0] * b.x + self.duv[1] * b.y
    }

    /// The displacement along the unit normal: s |n(b)| (world units of the object).
    pub(crate) fn offset(&self, at: Local) -> f64 {
        at.s * self.normal(at.b).length()
    }

    /// Whether the offset at `at` is at most `eps` >= 0 (at or below the top, within `eps`).
    pub(crate) fn offset_at_most(&self, at: Local, eps: f64) -> bool {
        at.s <= 0.0 || self.offset(at) <= eps
    }

    /// The prism's point at `x` by Newton's method from `guess`: None where it does not
    /// converge (a point far outside the shell, where the normals cross).
    pub(crate) fn locate(&self, x: DVec3, guess: Local) -> Option<Local> {
        let ([e1, e2], [d1, d2]) = (self.e, self.dn);
        // (1e-13 (1 + size + |x|))², within a factor of two, without a square root
        let tol2 = 1e-26 * ((1.0 + self.size).powi(2) + x.length_squared());
        let mut at = guess;
        for _ in 0..40 {
            let n = self.normal(at.b);
            let f = self.point_along(at, n) - x;
            if f.length_squared() <= tol2 {
                return Some(at);
            }
            // the Newton step: the Jacobian's columns c0, c1, c2 solved by Cramer's rule
            let (c0, c1) = (e1 + d1 * at.s, e2 + d2 * at.s);
            let c12 = c1.cross(n);
            let det = c0.dot(c12);
            if !(det.abs() > 1e-300) {
                return None;
            }
            let inv = 1.0 / det;
            at.b.x -= f.dot(c12) * inv;
            at.b.y -= c0.dot(f.cross(n)) * inv;
            at.s -= c0.dot(c1.cross(f)) * inv;
            if !(at.b.is_finite() && at.s.is_finite()) {
                return None;
            }
        }
        None
    }

    /// The Jacobian of (b1, b2, s) by the point at `at`, as rows: the change of each per unit
    /// displacement δ is row . δ; None where it is singular.
    pub(crate) fn rows(&self, at: Local) -> Option<[DVec3; 3]> {
        let c0 = self.e[0] + self.dn[0] * at.s;
        let c1 = self.e[1] + self.dn[1] * at.s;
        let n = self.normal(at.b);
        let c12 = c1.cross(n);
        let det = c0.dot(c12);
        if !(det.abs() > 1e-300) {
            return None;
        }
        Some([c12 / det, n.cross(c0) / det, c0.cross(c1) / det])
    }

    /// The ray's crossings of side k (corners k and k+1) leaving the prism (entering it, with
    /// `leaving` false), over the whole ray: up to two, with the point there.
    pub(crate) fn crossings(
        &self,
        o: DVec3,
        d: DVec3,
        k: usize,
        leaving: bool,
        out: &mut impl FnMut(Crossing),
    ) {
        let (ka, kb, kc) = (k, (k + 1) % 3, (k + 2) % 3);
        let a = self.p[ka];
        let e = self.p[kb] - a;
        let na = self.n[ka];
        let dn = self.n[kb] - na;
        // a point of the side: A(u) + s N(u); the ray meets the line at u where
        // (A(u) - o) . (d x N(u)) = 0, a quadratic in u
        let w = a - o;
        let (dxn, dxdn) = (d.cross(na), d.cross(dn));
        let c2 = e.dot(dxdn);
        let c1 = e.dot(dxn) + w.dot(dxdn);
        let c0 = w.dot(dxn);
        let mut roots = [f64::NAN; 2];
        let big = c0.abs().max(c1.abs()).max(c2.abs());
        if !(big > 0.0) {
            return;
        }
        if c2.abs() <= 1e-12 * big {
            if c1.abs() > 1e-300 {
                roots[0] = -c0 / c1;
            }
        } else {
            let disc = c1 * c1 - 4.0 * c2 * c0;
            if disc >= 0.0 {
                let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
                roots = [q / c2, if q != 0.0 { c0 / q } else { f64::NAN }];
            }
        }
        for u in roots {
            if !(-1e-9..=1.0 + 1e-9).contains(&u) {
                continue;
            }
            let u = u.clamp(0.0, 1.0);
            let nu = na + dn * u;
            let au = a + e * u;
            let dn_ = d.cross(nu);
            let den = dn_.length_squared();
            if !(den > 1e-300) {
                continue;
            }
            let lam = (au - o).cross(nu).dot(dn_) / den;
            let s = (au - o).cross(d).dot(dn_) / den;
            // leaving: the ray crosses the side away from the opposite corner
            let m = (e + dn * s).cross(nu);
            let inward = self.p[kc] - au;
            if (d.dot(m) * inward.dot(m) < 0.0) != leaving {
                continue;
            }
            let mut w3 = [0.0; 3];
            w3[ka] = 1.0 - u;
            w3[kb] = u;
            out(Crossing {
                lam,
                side: k,
                at: Local {
                    b: DVec2::new(w3[1], w3[2]),
                    s,
                },
            });
        }
    }

    /// Where the ray leaves through the top (the base triangle's plane, going out), if it does.
    pub(crate) fn top_exit(&self, o: DVec3, d: DVec3) -> Option<(f64, Local)> {
        let dn = d.dot(self.ng);
        if !(dn > 0.0) {
            return None;
        }
        let lam = (self.p[0] - o).dot(self.ng) / dn;
        Some((
            lam,
            Local {
                b: self.plane_barycentrics(o + d * lam),
                s: 0.0,
            },
        ))
    }

    /// Barycentrics (b1, b2) of a point of the triangle's plane.
    pub(crate) fn plane_barycentrics(&self, x: DVec3) -> DVec2 {
        let r = x - self.p[0];
        DVec2::new(r.dot(self.dual[0]), r.dot(self.dual[1]))
    }

    /// The ray's crossing of the top going in (front-facing: against the plane's normal), with
    /// the hit inside the triangle: its lam and barycentrics.
    pub(crate) fn entry(&self, o: DVec3, d: DVec3) -> Option<(f64, DVec2)> {
        if !(d.dot(self.ng) < 0.0) {
            return None;
        }
        let [e1, e2] = self.e;
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if !(det.abs() > 1e-300) {
            return None;
        }
        let inv = 1.0 / det;
        let tv = o - self.p[0];
        let b1 = tv.dot(pv) * inv;
        if !(-1e-12..=1.0 + 1e-12).contains(&b1) {
            return None;
        }
        let qv = tv.cross(e1);
        let b2 = d.dot(qv) * inv;
        if b2 < -1e-12 || b1 + b2 > 1.0 + 1e-12 {
            return None;
        }
        Some((e2.dot(qv) * inv, DVec2::new(b1, b2)))
    }

    /// Whether barycentrics lie in the triangle, within `eps`.
    pub(crate) fn inside(b: DVec2, eps: f64) -> bool {
        b.x >= -eps && b.y >= -eps && b.x + b.y <= 1.0 + eps
    }

    /// How far outside, in barycentrics, a point of a side shared with a neighbour may be
    /// located in this prism at offsets down to `depth`: a shared side's normals agree to 1e-5
    /// (Geometry's test, which float32 normals of a flat-shaded quad's two halves need), so the
    /// two walls part by up to 1e-5 of the offset there.
    pub(crate) fn shared_side_slack(&self, depth: f64) -> f64 {
        1e-7 + 4e-5 * depth / self.size.max(1e-300)
    }

    /// `b` moved into the triangle (the nearest weights that are all >= 0, to first order).
    pub(crate) fn clamp_inside(b: DVec2) -> DVec2 {
        let b = b.max(DVec2::ZERO);
        let sum = b.x + b.y;
        if sum > 1.0 {
            b / sum
        } else {
            b
        }
    }
}

//! A light's disk from one hit, as one bundle. The rays of a directional or sphere light's disk
//! leave a hit within a narrow cone. Near the hit each is walked along its own tangent; beyond,
//! one walk of the cone's axis, its chords' boxes widened by as far as the rays part, shows
//! that none of them meets the surface before it leaves the shell.

use super::bundle_shows::Bundle;
use super::*;

/// The allowance on what the axis shows of every ray's path: on the deviations from chords
/// (a path's higher terms, the rays' paths beside the axis's) and on how far the rays part
/// (the Jacobian between the points where it is taken, and across a side, the neighbour's
/// coordinates beside the prism's).
pub(super) const SLACK: f64 = 1.25;

impl Object<'_> {
    /// The Jacobian of (texture point, height) by the object-space point in prism `p` at
    /// `at`: its rows for s.x, s.y and h.
    pub(super) fn jacobian(&self, p: &Prism, at: Local) -> Option<[DVec3; 3]> {
        let [r1, r2, rs] = p.rows(at)?;
        let (du1, du2) = (p.duv[0] * self.tiling, p.duv[1] * self.tiling);
        let n = p.normal(at.b);
        let nl = n.length();
        let rh = (rs * nl + (r1 * n.dot(p.dn[0]) + r2 * n.dot(p.dn[1])) * (at.s / nl)) / self.depth;
        Some([r1 * du1.x + r2 * du2.x, r1 * du1.y + r2 * du2.y, rh])
    }

    /// How far (in cells, on either axis, and in height) two points of prism `p` part per unit
    /// of object-space distance between them, near the points `ats`: the Jacobian's largest
    /// rows there.
    pub(super) fn spread(&self, p: &Prism, ats: [Local; 2]) -> Option<(f64, f64)> {
        let hm = &self.mat.height;
        let (w, h) = (hm.width as f64, hm.height as f64);
        let (mut gc, mut gh) = (0.0f64, 0.0f64);
        for at in ats {
            let [sx, sy, rh] = self.jacobian(p, at)?;
            gc = gc.max(sx.length() * w).max(sy.length() * h);
            gh = gh.max(rh.length());
        }
        Some((gc, gh))
    }
}

impl Object<'_> {
    /// Whether every ray from the hit (object-space `o`) whose direction differs from `da` by
    /// at most `part` meets the surface: the axis's walk from `start` (the hit, or as far as the
    /// bundle cleared the way) meets it, and a quarter to two texels past
    /// that its point lies below the field's lowest within how far the rays part there, by
    /// more than they part in height. A ray that began on the surface and is under it has met
    /// it; the object must be closed (no wall), and the point's triangle free of uv seams.
    fn all_blocked(&self, start: Place, o: DVec3, da: DVec3, part: f64, lift: f64) -> bool {
        if !self.closed {
            return false;
        }
        let ray = Ray {
            o,
            d: da,
            lift,
            want: Want::Near,
            part: 0.0,
        };
        let Walk::Hit {
            tri: t,
            lam,
            at: ah,
            ..
        } = self.walk(&ray, start.tri, start.lam, start.at)
        else {
            return false;
        };
        if !self.seam_free[t as usize] {
            return false;
        }
        let q = self.prisms[t as usize].as_ref().expect("a walked prism");
        let hm = &self.mat.height;
        // steps of a quarter to two texels along the axis past the hit
        let Some((gc, _)) = self.spread(q, [ah, ah]) else {
            return false;
        };
        let texel = 1.0 / (gc * da.length()).max(1e-300);
        for k in [0.25, 0.5, 1.0, 2.0] {
            let l = lam + k * texel;
            let Some(x) = q.locate(o + da * l, ah) else {
                return false;
            };
            if !Prism::inside(x.b, 0.0) {
                return false;
            }
            let smp = self.sample(q, l, x, lift);
            let Some((gc, gh)) = self.spread(q, [ah, x]) else {
                return false;
            };
            let far = SLACK * part * l;
            let (ec, eh) = (gc * far + 1e-6, gh * far + 1e-9);
            // the field's lowest within ec of the point: its value there less its steepest
            // texel step on each axis (the bilinear field's slope bound) times ec, over the
            // cells the box meets (cell (i, j) spans texel centres i..i+1)
            let (lo, hi) = (smp.c - (ec + 0.5), smp.c + (ec - 0.5));
            let (x0, x1) = (lo.x.floor() as i64, hi.x.floor() as i64 + 1);
            let (y0, y1) = (lo.y.floor() as i64, hi.y.floor() as i64 + 1);
            if x1 - x0 > 8 || y1 - y0 > 8 {
                return false;
            }
            let (mut sx, mut sy) = (0.0f64, 0.0f64);
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let t = hm.texel(i, j);
                    if i < x1 {
                        sx = sx.max((hm.texel(i + 1, j) - t).abs());
                    }
                    if j < y1 {
                        sy = sy.max((hm.texel(i, j + 1) - t).abs());
                    }
                }
            }
            let low = hm.sample(smp.s.x, smp.s.y) - (sx + sy) * ec;
            if smp.h + eh < low {
                return true;
            }
        }
        false
    }
}

impl Shell<'_> {
    /// Whether every ray from the hit along the world directions `dirs` (a disk about the unit
    /// `axis`, at most 64), walked `lift` above the field, leaves the hit's object's shell
    /// without meeting the surface, or meets it, shown for all of them at once; None where
    /// the bundle shows nothing.
    ///
    /// - The rays share the start. Over the first fraction f of the axis's way through the hit's
    ///   prism, each follows its own tangent (the Jacobian at the start, applied to its
    ///   direction) within 4 f² of the axis's deviation from that chord, as on a quadratic path:
    ///   f keeps this within `TOL_TEXELS` (in height, what that makes along the chord), and each
    ///   tangent is walked cell by cell.
    /// - From there the axis is walked as one ray whose chords' boxes are widened by twice
    ///   their deviation and by how far the rays part by the chord's end (their directions'
    ///   largest difference times lam, through the Jacobian's largest rows at the chord's ends).
    ///   It must leave through a top with every box clear, and meet no triangle that a uv seam
    ///   meets (rays beside the axis could cross the seam where it does not).
    /// - Where a tangent meets the field or leaves the triangle before l0, or the axis's walk
    ///   does not clear, the bundle shows that every ray is blocked where
    ///   `Object::all_blocked` does. Else each ray is walked on its own: from the start of the
    ///   axis's first chord that did not clear, where the axis's walk got past the tangents
    ///   (`Bundle::Cleared`: no ray meets the surface before it), or from the hit. Its chords
    ///   then differ from those of a walk from the hit (and a tangent lies on the other side of
    ///   the path from a walk's chords), so that a ray that passes within the chords'
    ///   tolerance of the surface may be answered otherwise.
    pub(super) fn bundle(
        &self,
        hit: &Hit<ShellAt>,
        axis: DVec3,
        dirs: &[DVec3],
        lift: f64,
    ) -> Option<Bundle> {
        let ob = &self.objects[hit.object];
        let (tri, at, o) = (hit.at.tri, hit.at.at, hit.at.x);
        if !(ob.depth > 0.0) || dirs.len() > 64 {
            return None;
        }
        let da = ob.to_obj.transform_vector3(axis);
        let mut ds = [DVec3::ZERO; 64];
        let mut part = 0.0f64;
        for (d, l) in ds.iter_mut().zip(dirs) {
            *d = ob.to_obj.transform_vector3(*l);
            part = part.max((*d - da).length());
        }
        let ds = &ds[..dirs.len()];
        let mut cleared = None;
        self.bundle_left(hit, da, ds, part, lift, &mut cleared)
            .map(Bundle::Left)
            .or_else(|| {
                ob.all_blocked(
                    cleared.unwrap_or(Place { tri, lam: 0.0, at }),
                    o,
                    da,
                    part,
                    lift,
                )
                .then_some(Bundle::Blocked)
            })
            .or(cleared.map(Bundle::Cleared))
    }

    /// `bundle`'s answer where every ray leaves: whether the object must still be searched.
    fn bundle_left(
        &self,
        hit: &Hit<ShellAt>,
        da: DVec3,
        ds: &[DVec3],
        part: f64,
        lift: f64,
        cleared: &mut Option<Place>,
    ) -> Option<bool> {
        let ob = &self.objects[hit.object];
        let (tri, at, o) = (hit.at.tri, hit.at.at, hit.at.x);
        if !ob.seam_free[tri as usize] {
            return None;
        }
        let p = ob.prisms[tri as usize].as_ref().expect("a hit's prism");
        // where the axis leaves the prism: through the top inside the triangle, or else the
        // first side below the top
        let eps = 1e-12 * ob.extent / da.length().max(1e-300);
        let mut end = p
            .top_exit(o, da)
            .filter(|(l, b)| *l >= -eps && Prism::inside(b.b, 0.0))
            .map(|(l, b)| (l, b, None));
        if end.is_none() {
            for k in 0..3 {
                p.crossings(o, da, k, true, &mut |c: Crossing| {
                    if c.lam >= -eps
                        && p.offset_at_most(c.at, 1e-9 * ob.depth)
                        && end.is_none_or(|(l, _, _)| c.lam < l)
                    {
                        end = Some((c.lam, c.at, Some(k)));
                    }
                });
            }
        }
        let (le, guess_e, side) = end?;
        if !(le > 0.0) {
            return None;
        }
        let a = ob.sample(p, 0.0, at, lift);
        let e_at = p.locate(o + da * le, guess_e)?;
        let e = ob.sample(p, le, e_at, lift);
        let mid = Local {
            b: 0.5 * (at.b + e_at.b),
            s: 0.5 * (at.s + e_at.s),
        };
        let m_at = p.locate(o + da * (0.5 * le), mid)?;
        let m = ob.sample(p, 0.5 * le, m_at, lift);
        let dev_c = SLACK * (m.c - 0.5 * (a.c + e.c)).length();
        let dev_h = SLACK * (m.h - 0.5 * (a.h + e.h)).abs();
        let run = (e.c - a.c).length();
        let tol_h = (TOL_TEXELS * (e.h - a.h).abs() / run.max(1e-300)).clamp(1e-9, 1e-3);
        let r = (dev_c / TOL_TEXELS).max(dev_h / tol_h);
        let f = if r > 0.0 {
            (0.4 / r.sqrt()).min(1.0)
        } else {
            1.0
        };
        let l0 = f * le;
        let [sx, sy, sh] = ob.jacobian(p, at)?;
        let [rb1, rb2, _] = p.rows(at)?;
        // each ray's tangent, from the start to l0: inside the triangle by more than the
        // path's deviation from it (where it runs to the axis's exit through a side, it may
        // reach past that side where the neighbour's uvs go on from it), and clear of the
        // field cell by cell
        let margin = 3.0 * SLACK * 4.0 * f * f * (m_at.b - mid.b).length() + 1e-12;
        let past = side.filter(|_| f >= 1.0);
        for d in ds {
            let w = Prism::weights(at.b + DVec2::new(rb1.dot(*d), rb2.dot(*d)) * l0);
            // corner c's weight vanishes on side c + 1
            if (0..3).any(|c| w[c] <= margin && past != Some((c + 1) % 3)) {
                return None;
            }
            let step = DVec2::new(sx.dot(*d), sy.dot(*d)) * l0;
            if walk_cells(&ob.field, a.s, a.h, step, sh.dot(*d) * l0, 1.0)
                .0
                .is_some()
            {
                return None;
            }
        }
        // beyond: the axis from its point at l0, as the bundle's
        let q =
            |x: f64, y: f64, z: f64| x + f * (z - x) + 4.0 * f * (1.0 - f) * (y - 0.5 * (x + z));
        let guess = Local {
            b: DVec2::new(q(at.b.x, m_at.b.x, e_at.b.x), q(at.b.y, m_at.b.y, e_at.b.y)),
            s: q(at.s, m_at.s, e_at.s),
        };
        let c_at = if f >= 1.0 {
            e_at
        } else {
            p.locate(o + da * l0, guess)?
        };
        let ray = Ray {
            o,
            d: da,
            lift,
            want: Want::Any,
            part,
        };
        match ob.walk(&ray, tri, l0, c_at) {
            Walk::Left { top: Some(t), .. } => {
                // where anything of the object lies above the triangles it left by or began in,
                // or their neighbours, it is searched
                let near = |t: u32| {
                    ob.overhung(t as usize)
                        || ob.across[t as usize]
                            .iter()
                            .flatten()
                            .any(|&u| ob.overhung(u as usize))
                };
                Some(near(t) || near(tri))
            }
            Walk::Hit { tri, lam, at, .. } => {
                *cleared = Some(Place { tri, lam, at });
                None
            }
            _ => None,
        }
    }
}

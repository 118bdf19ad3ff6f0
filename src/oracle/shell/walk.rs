//! The walk of one ray through an object's shell: prism to prism across shared sides, each
//! prism's stretch of the ray cut into chords that are walked cell by cell against the bilinear
//! field, and the first crossing refined onto the ray itself.

use super::*;

impl<'a> Object<'a> {
    /// The walk of the ray from `at` in prism `tri` at `lam0`.
    pub(super) fn walk(&self, ray: &Ray, tri: u32, lam0: f64, at: Local) -> Walk {
        let (o, d, lift) = (ray.o, ray.d, ray.lift);
        let (mut tri, mut lam, mut at) = (tri, lam0, at);
        if !(self.depth > 0.0) {
            // no shell: the base surface itself
            let p = self.prisms[tri as usize].as_ref().expect("a walked prism");
            return if lift > 0.0 && d.dot(p.normal(at.b)) > 0.0 {
                Walk::Left {
                    lam,
                    cells: 0,
                    top: None,
                }
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
            if ray.part > 0.0 && !self.seam_free[tri as usize] {
                // a bundle's rays may part across a uv seam: it shows nothing there
                return Walk::Hit {
                    tri,
                    lam,
                    at,
                    cells,
                };
            }
            let top = p.top_exit(o, d).filter(|(l, _)| *l >= lam - eps);
            // where the path reaches the top inside the triangle: its middle, and the sides it
            // cannot cross on the way
            let toward = top.and_then(|t| self.toward_top(p, ray, (lam, at), t));
            let safe = toward.map_or([false; 3], |(_, safe)| safe);
            // the first side crossing ahead (those above the top do not bound the prism)
            let mut side: Option<Crossing> = None;
            for k in (0..3).filter(|&k| !safe[k]) {
                p.crossings(o, d, k, true, &mut |c: Crossing| {
                    if c.lam >= lam - eps
                        && p.offset_at_most(c.at, 1e-9 * self.depth)
                        && side.is_none_or(|s| c.lam < s.lam)
                    {
                        side = Some(c);
                    }
                });
            }
            // where the prism ends along the ray: its top, a side, or where the path is below
            // the field's lowest texel (the surface is met by then; a camera ray's walk ends
            // 1e-6 below it, so that its last chord ends under the field and holds the
            // crossing; a bundle's axis, at the floor h = 0). A path (1 + lift - low) depths
            // below the triangle's plane is there (h <= low where the normal leans from the
            // plane's); where nothing bounds it, far below
            let visibility = ray.want != Want::Exact && ray.part == 0.0;
            let low = match (visibility, ray.part > 0.0) {
                (true, _) => self.field.low,
                (false, false) => self.field.low - 1e-6,
                (false, true) => 0.0,
            };
            let at_top = top.is_some_and(|(lt, _)| side.is_none_or(|s| lt <= s.lam));
            let dn = d.dot(p.ng);
            let floor = (!at_top && dn < 0.0)
                .then(|| {
                    ((self.depth * (1.0 + lift - low) - (p.p[0] - o).dot(p.ng)) / -dn).max(lam)
                })
                .filter(|&f| side.is_none_or(|s| f < s.lam))
                .and_then(|f| Some((f, p.locate(o + d * f, at)?)));
            if let Some((f, a)) = floor.filter(|_| visibility) {
                // a visibility ray: it began at or above the field and is below it there, so
                // it meets the surface on the way (where first does not matter)
                return Walk::Hit {
                    tri,
                    lam: f,
                    at: a,
                    cells,
                };
            }
            let (end, via): (Sample, Option<Crossing>) = match (top, side, floor) {
                (Some((lt, bt)), _, _) if at_top => (self.sample(p, lt, bt, lift), None),
                (_, _, Some((f, a))) => (self.sample(p, f, a, lift), None),
                (_, Some(s), _) => (self.sample(p, s.lam, s.at, lift), Some(s)),
                _ => {
                    let far = lam + 4.0 * (self.extent + self.depth) / d.length().max(1e-300);
                    match p.locate(o + d * far, at) {
                        Some(a) => (self.sample(p, far, a, lift), None),
                        None => {
                            return Walk::Left {
                                lam: far,
                                cells,
                                top: None,
                            }
                        }
                    }
                }
            };
            if via.is_some() && self.met(ray, &end) {
                return Walk::Hit {
                    tri,
                    lam: end.lam,
                    at: end.at,
                    cells,
                };
            }
            let start = self.sample(p, lam, at, lift);
            if let Some((l, a)) = self.chord(
                p,
                ray,
                (&start, &end),
                match toward {
                    Some((ref m, _)) if at_top => Middle::Known(m),
                    _ => Middle::Unknown,
                },
                0,
                &mut cells,
            ) {
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
                    top: at_top.then_some(tri),
                };
            };
            // into the triangle across the side, at the same point
            let Some(next) = self.across[tri as usize][c.side] else {
                return Walk::Left {
                    lam: end.lam,
                    cells,
                    top: None,
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
            let slack = q.shared_side_slack(self.depth);
            match q.locate(x, guess) {
                Some(a) if Prism::inside(a.b, slack) => {
                    // (onto the side, where the two walls part by the normals' rounding)
                    let a = Local {
                        b: Prism::clamp_inside(a.b),
                        s: a.s,
                    };
                    if let Some((tri, at)) = self.seam_wall(p, q, ray, (tri, next), (&end, a)) {
                        return Walk::Hit {
                            tri,
                            lam: end.lam,
                            at,
                            cells,
                        };
                    }
                    (tri, lam, at) = (next, c.lam, a);
                }
                // a hard edge: the neighbour's shell does not begin here
                _ => {
                    return Walk::Left {
                        lam: end.lam,
                        cells,
                        top: None,
                    }
                }
            }
        }
        Walk::Left {
            lam,
            cells,
            top: None,
        }
    }

    /// The wall that closes a step at a uv seam (docs/conventions.md, "The displaced surface"):
    /// where the ray crosses from prism `p` into `q` across a side whose uvs differ, above p's
    /// field (the walk through p found no hit) and below q's, it meets the wall between the two
    /// sides' surfaces there. The hit takes the uv of the side whose height at the crossing is
    /// nearer the ray's, as the tessellated mesh's strip beside a welded seam does.
    fn seam_wall(
        &self,
        p: &Prism,
        q: &Prism,
        ray: &Ray,
        (tri, next): (u32, u32),
        (end, a): (&Sample, Local),
    ) -> Option<(u32, Local)> {
        // seam_free: no uv seam meets either triangle's corners
        if ray.part > 0.0 || (self.seam_free[tri as usize] && self.seam_free[next as usize]) {
            return None;
        }
        // the same uv on both sides, to float32's rounding of the vertices' uvs: no seam
        if (p.uv(end.at.b) - q.uv(a.b)).abs().max_element() <= 1e-6 {
            return None;
        }
        let hm = &self.mat.height;
        let inq = self.sample(q, end.lam, a, ray.lift);
        let hq = hm.sample(inq.s.x, inq.s.y);
        if !(hq > inq.h) {
            return None;
        }
        let hp = hm.sample(end.s.x, end.s.y);
        Some(if (inq.h - hp).abs() <= (hq - inq.h).abs() {
            (tri, end.at)
        } else {
            (next, a)
        })
    }

    /// The middle of the path from `(lam, at)` to the top exit `(lt, bt)`, where that lies in
    /// the triangle, and per side (corners k, k+1) whether the path cannot cross it on the way:
    /// where the side's weight at both ends exceeds three times the middle's deviation from
    /// the straight way between them in barycentrics (the chords' bound, twice the deviation at
    /// the middle, on one weight).
    fn toward_top(
        &self,
        p: &Prism,
        ray: &Ray,
        (lam, at): (f64, Local),
        (lt, bt): (f64, Local),
    ) -> Option<(Sample, [bool; 3])> {
        let (wa, wb) = (Prism::weights(at.b), Prism::weights(bt.b));
        if wb.iter().any(|&w| !(w >= 0.0)) {
            return None;
        }
        let lm = 0.5 * (lam + lt);
        let guess = Local {
            b: 0.5 * (at.b + bt.b),
            s: 0.5 * (at.s + bt.s),
        };
        let am = p.locate(ray.o + ray.d * lm, guess)?;
        let margin = 3.0 * (am.b - guess.b).length() + 1e-12;
        // side k is the one where corner k + 2's weight vanishes
        let safe = std::array::from_fn(|k| wa[(k + 2) % 3].min(wb[(k + 2) % 3]) > margin);
        Some((self.sample(p, lm, am, ray.lift), safe))
    }

    /// Whether a ray that wants any hit has met the surface by its point `x`: x lies at or under
    /// the field, and the ray began at or above it (lifted from a hit, or entering through a top
    /// or a wall), so that its path crossed the surface on the way (where first does not matter).
    fn met(&self, ray: &Ray, x: &Sample) -> bool {
        ray.want == Want::Any && ray.part == 0.0 && self.mat.height.sample(x.s.x, x.s.y) >= x.h
    }

    /// The first hit on the path from `a` to `b` in prism `p`: its lam and point.
    pub(super) fn chord(
        &self,
        p: &Prism,
        ray: &Ray,
        (a, b): (&Sample, &Sample),
        mid: Middle<'_>,
        level: u32,
        cells: &mut u32,
    ) -> Option<(f64, Local)> {
        let (o, d, lift) = (ray.o, ray.d, ray.lift);
        *cells += 1;
        if let Middle::Deviates(dev) = mid {
            if let Some(answer) = self.settle(p, ray, (a, b), None, dev, true, level, cells) {
                return answer;
            }
        }
        let located_m;
        let m: &Sample = match mid {
            Middle::Known(m) => m,
            _ => {
                let lm = 0.5 * (a.lam + b.lam);
                let guess = Local {
                    b: 0.5 * (a.at.b + b.at.b),
                    s: 0.5 * (a.at.s + b.at.s),
                };
                let Some(located) = p.locate(o + d * lm, guess) else {
                    // the middle lies where the normals cross, far below the floor: the
                    // surface is met before it
                    let m = self.sample(p, lm, guess, lift);
                    return if level >= 48 {
                        None
                    } else {
                        self.chord(p, ray, (a, &m), Middle::Unknown, level + 1, cells)
                    };
                };
                located_m = self.sample(p, lm, located, lift);
                &located_m
            }
        };
        let (mid_c, mid_h) = (0.5 * (a.c + b.c), 0.5 * (a.h + b.h));
        let dev = ((m.c - mid_c).length(), (m.h - mid_h).abs());
        // a box that holds the one the estimate failed with fails too
        let boxed = match mid {
            Middle::Deviates(e) => dev.0 < e.0 || dev.1 < e.1,
            _ => true,
        };
        if let Some(answer) = self.settle(p, ray, (a, b), Some(m), dev, boxed, level, cells) {
            return answer;
        }
        // each half of a path deviates from its chord about a quarter as much (a quadratic
        // path's): tried before the half's own middle is looked for
        let half = Middle::Deviates((0.25 * dev.0, 0.25 * dev.1));
        self.chord(p, ray, (a, m), half, level + 1, cells)
            .or_else(|| self.chord(p, ray, (m, b), half, level + 1, cells))
    }

    /// The chord from `a` to `b` with the path's middle `m` where known, and the path's
    /// deviation from the chord at the middle: its answer where the chord settles it (its box
    /// of cells, widened by twice that deviation, lies under the path: no hit, tested where
    /// `boxed`; or it lies within `TOL_TEXELS` of the path: the cell walk's hit), or None
    /// where it must be halved.
    #[allow(clippy::too_many_arguments)]
    fn settle(
        &self,
        p: &Prism,
        ray: &Ray,
        (a, b): (&Sample, &Sample),
        m: Option<&Sample>,
        (dev_c, dev_h): (f64, f64),
        boxed: bool,
        level: u32,
        cells: &mut u32,
    ) -> Option<Option<(f64, Local)>> {
        // the path's bounds: the chord's, widened by twice its deviation at the middle (and for
        // a bundle, by how far its rays part by the chord's end)
        let (mut ec, mut eh) = (2.0 * dev_c + 1e-6, 2.0 * dev_h + 1e-9);
        if ray.part > 0.0 {
            let Some((gc, gh)) = self.spread(p, [a.at, b.at]) else {
                return Some(Some((a.lam, a.at)));
            };
            let far = bundle::SLACK * ray.part * a.lam.max(b.lam);
            (ec, eh) = (bundle::SLACK * ec + gc * far, bundle::SLACK * eh + gh * far);
        }
        let (mut low, mut clo, mut chi) = (a.h.min(b.h), a.c.min(b.c), a.c.max(b.c));
        if let Some(m) = m {
            (low, clo, chi) = (low.min(m.h), clo.min(m.c), chi.max(m.c));
        }
        let (low, clo, chi) = (low - eh, clo - ec, chi + ec);
        // a chord from a light or ambient ray's start, on the surface, holds the surface there
        // in its box: its box cannot clear it
        let from_hit = a.lam == 0.0 && ray.lift > 0.0 && eh >= ray.lift;
        // cells: texel centres at integers (x - 0.5)
        if boxed
            && !from_hit
            && low
                > self
                    .field
                    .max_in((clo.x - 0.5, chi.x - 0.5), (clo.y - 0.5, chi.y - 0.5))
                    + 1e-12
        {
            return Some(None);
        }
        let run = (b.c - a.c).length();
        let tol_h = (TOL_TEXELS * (b.h - a.h).abs() / run.max(1e-300)).clamp(1e-9, 1e-3);
        if !((dev_c <= TOL_TEXELS && dev_h <= tol_h) || level >= 48) {
            return None;
        }
        if ray.part > 0.0 {
            return Some(Some((a.lam, a.at)));
        }
        let (u, v) = (a, b);
        let (hit, n) = walk_cells(&self.field, u.s, u.h, v.s - u.s, v.h - u.h, 1.0);
        *cells += n;
        let Some(mu) = hit else {
            return Some(None);
        };
        let lam = u.lam + mu * (v.lam - u.lam);
        let g = Local {
            b: u.at.b + (v.at.b - u.at.b) * mu,
            s: u.at.s + (v.at.s - u.at.s) * mu,
        };
        if ray.want != Want::Exact {
            return Some(Some((lam, g)));
        }
        let at = p.locate(ray.o + ray.d * lam, g).unwrap_or(g);
        Some(Some(self.refine(p, ray, (lam, at), (*u, *v))))
    }

    /// The chord's hit `(lam, at)` (`at` located on the path) moved onto the path itself:
    /// Newton's method along the path from it, or where that does not settle near it, regula
    /// falsi on the path between a point above the field and one at or below it, one of them
    /// the chord's point and the other on the side where the path crosses, within the chord
    /// `(u, v)` (where no such pair is found, the chord's answer stands).
    pub(super) fn refine(
        &self,
        p: &Prism,
        ray: &Ray,
        (lam, at): (f64, Local),
        (u, v): (Sample, Sample),
    ) -> (f64, Local) {
        let (o, d, lift) = (ray.o, ray.d, ray.lift);
        let hm = &self.mat.height;
        // field above the path at lam, at the located point a: >= 0 where met
        let g_at = |l: f64, a: Local| -> f64 {
            let x = self.sample(p, l, a, lift);
            hm.sample(x.s.x, x.s.y) - x.h
        };
        let g = |l: f64, guess: Local| -> Option<(f64, Local)> {
            let a = p.locate(o + d * l, guess)?;
            Some((g_at(l, a), a))
        };
        let span = (v.lam - u.lam).abs();
        // the chord lies within TOL_TEXELS of the path: its hit is about as near the path's,
        // so the first bracket tried spans twice that (wider ones follow where it does not)
        let run = (v.c - u.c).length();
        let mut delta = (span * 2.0 * TOL_TEXELS / run.max(1e-300))
            .min(span)
            .max(1e-6 * span + 1e-15);
        // Newton's method on the path from the chord's point, kept within that first bracket's
        // reach: where it settles on the surface (|g| <= 1e-12 of the depth), that is the hit
        let slope = |l: f64, a: Local| -> Option<(f64, f64)> {
            let x = self.sample(p, l, a, lift);
            let (hv, hs, ht) = hm.sample_grad(x.s.x, x.s.y);
            let [sx, sy, sh] = self.jacobian(p, a)?;
            Some((hv - x.h, hs * sx.dot(d) + ht * sy.dot(d) - sh.dot(d)))
        };
        let mut cur = (lam, at);
        for _ in 0..4 {
            let Some((gc, sc)) = slope(cur.0, cur.1) else {
                break;
            };
            if gc.abs() <= 1e-12 {
                return cur;
            }
            let t = cur.0 - gc / sc;
            if !(t.is_finite() && (t - lam).abs() <= delta && t >= u.lam && t <= v.lam) {
                break;
            }
            let Some(a) = p.locate(o + d * t, cur.1) else {
                break;
            };
            cur = (t, a);
        }
        // where it does not: regula falsi from the chord's point
        let g0 = g_at(lam, at);
        // on the surface to rounding (1e-12 of the depth): the path's point
        let on = |g: f64| (0.0..=1e-12).contains(&g);
        if on(g0) {
            return (lam, at);
        }
        let below = g0 >= 0.0;
        while delta <= span {
            let other = if below {
                (lam - delta).max(u.lam)
            } else {
                (lam + delta).min(v.lam)
            };
            match g(other, at) {
                Some((go, ao)) if (go >= 0.0) != below => {
                    let (mut lo, mut hi) = if below {
                        ((other, go, ao), (lam, g0, at))
                    } else {
                        ((lam, g0, at), (other, go, ao))
                    };
                    // Illinois: regula falsi that halves a stale end's weight
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
                        // the point between the ends' points, as a guess
                        let f = (mid - lo.0) / (hi.0 - lo.0);
                        let guess = Local {
                            b: lo.2.b + (hi.2.b - lo.2.b) * f,
                            s: lo.2.s + (hi.2.s - lo.2.s) * f,
                        };
                        let Some((gm, am)) = g(mid, guess) else { break };
                        if on(gm) {
                            return (mid, am);
                        }
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

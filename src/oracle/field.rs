//! The oracle's walk of the bilinear, repeating height field: a ray, cell by cell (a 2-D DDA
//! over the cells between texel centres), meets each cell's bilinear patch as a quadratic in
//! the ray parameter, solved in closed form.
//!
//! A max pyramid lets the walk skip: a block of 2^k x 2^k cells whose highest texel lies below
//! the ray over the whole of the ray's way through it holds no hit, so the walk leaves it in one
//! step (the max-mip traversal of the GPU's Exact, in float64). The answer is the cell walk's:
//! a block is skipped only when no point of it can be at or above the ray.

use super::rows::par_rows;
use crate::scene::{floor, HeightMap};
use glam::DVec2;

/// Upper bound on cells walked per ray (a ray at 89.99 degrees over a 4k map stays below it).
pub const MAX_CELLS: u32 = 4_000_000;

/// The height field with its max pyramid: level k (k >= 1) holds, for each block of 2^k x 2^k
/// cells of one period (blocks at the period's right and bottom edges may be narrower), the
/// highest texel among the block's corners. Cell (i, j) spans texel centres i..i+1, j..j+1.
pub struct Field<'a> {
    pub hm: &'a HeightMap,
    /// levels[k - 1] is level k
    levels: Vec<MaxLevel>,
    /// the lowest texel (no point of the bilinear field lies below it)
    pub low: f64,
}

struct MaxLevel {
    w: usize,
    h: usize,
    max: Vec<f32>,
}

impl<'a> Field<'a> {
    pub fn new(hm: &'a HeightMap) -> Field<'a> {
        let (w, h) = (hm.width as usize, hm.height as usize);
        // level 1 from the texels: block (bx, by) covers cells 2bx..2bx+2 (at most w), so
        // texels 2bx..=min(2bx + 2, w) (texel w is texel 0 of the next period); rows in parallel
        let (w1, h1) = (w.div_ceil(2), h.div_ceil(2));
        let wrap = |i: usize, n: usize| if i == n { 0 } else { i };
        // (with each block row, the lowest texel of its own texel rows 2by and 2by + 1)
        let rows = par_rows(h1, |by| {
            let mut out = vec![0f32; w1];
            for y in 2 * by..=(2 * by + 2).min(h) {
                let row = &hm.data[wrap(y, h) * w..][..w];
                for (bx, o) in out.iter_mut().enumerate() {
                    for x in 2 * bx..=(2 * bx + 2).min(w) {
                        *o = o.max(row[wrap(x, w)]);
                    }
                }
            }
            let low = hm.data[2 * by * w..((2 * by + 2).min(h)) * w]
                .iter()
                .copied()
                .fold(f32::INFINITY, f32::min);
            (out, low)
        });
        let (blocks, lows): (Vec<Vec<f32>>, Vec<f32>) = rows.into_iter().unzip();
        let low = lows.into_iter().fold(f32::INFINITY, f32::min) as f64;
        let max = blocks.concat();
        let mut levels = vec![MaxLevel { w: w1, h: h1, max }];
        loop {
            let p = levels.last().expect("level 1");
            if p.w == 1 && p.h == 1 {
                break;
            }
            let (nw, nh) = (p.w.div_ceil(2), p.h.div_ceil(2));
            let mut max = vec![0f32; nw * nh];
            for by in 0..nh {
                for bx in 0..nw {
                    let mut m = 0f32;
                    for y in 2 * by..(2 * by + 2).min(p.h) {
                        for x in 2 * bx..(2 * bx + 2).min(p.w) {
                            m = m.max(p.max[y * p.w + x]);
                        }
                    }
                    max[by * nw + bx] = m;
                }
            }
            levels.push(MaxLevel { w: nw, h: nh, max });
        }
        Field { hm, levels, low }
    }

    /// The highest texel of the cells that meet the box [x0, x1] x [y0, y1] in cell coordinates
    /// (cell (i, j) spans [i, i+1] x [j, j+1]; the field repeats): read from the finest pyramid
    /// level whose blocks the box spans at most three of, on each axis.
    pub fn max_in(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> f64 {
        let (w, h) = (self.hm.width as i64, self.hm.height as i64);
        let whole = || {
            self.levels
                .last()
                .map(|l| l.max.iter().copied().fold(0f32, f32::max) as f64)
                .unwrap_or_else(|| self.hm.data.iter().copied().fold(0f32, f32::max) as f64)
        };
        if !(x0.is_finite() && x1.is_finite() && y0.is_finite() && y1.is_finite()) {
            return whole();
        }
        let (cx0, cx1) = (floor(x0), floor(x1));
        let (cy0, cy1) = (floor(y0), floor(y1));
        if cx1 - cx0 >= w || cy1 - cy0 >= h || self.levels.is_empty() {
            return whole();
        }
        let span = (cx1 - cx0).max(cy1 - cy0).max(1) as u64;
        // blocks of 2^k cells, 2^k > span / 2: the box spans at most three on each axis
        let k = ((63 - span.leading_zeros()) as usize).clamp(1, self.levels.len());
        let lv = &self.levels[k - 1];
        if cx0 >= 0 && cx1 < w && cy0 >= 0 && cy1 < h {
            // within one period: cell c lies in block c >> k
            let (bx0, bx1) = ((cx0 >> k) as usize, (cx1 >> k) as usize);
            let mut top = 0f32;
            for by in (cy0 >> k) as usize..=(cy1 >> k) as usize {
                for &m in &lv.max[by * lv.w + bx0..=by * lv.w + bx1] {
                    top = top.max(m);
                }
            }
            return top as f64;
        }
        let block = |c: i64, n: i64| {
            let (p, l) = if (0..n).contains(&c) {
                (0, c)
            } else {
                (c.div_euclid(n), c.rem_euclid(n))
            };
            let b = l >> k;
            (b as usize, p * n + ((b + 1) << k).min(n))
        };
        let mut top = 0f32;
        let mut cy = cy0;
        while cy <= cy1 {
            let (by, ny) = block(cy, h);
            let row = &lv.max[by * lv.w..(by + 1) * lv.w];
            let mut cx = cx0;
            while cx <= cx1 {
                let (bx, nx) = block(cx, w);
                top = top.max(row[bx]);
                cx = nx;
            }
            cy = ny;
        }
        top as f64
    }

    /// The field without its pyramid: the plain cell walk (what the pyramid must agree with).
    #[cfg(test)]
    fn cell_walk_only(hm: &'a HeightMap) -> Field<'a> {
        Field {
            hm,
            levels: Vec::new(),
            low: 0.0,
        }
    }

    /// The skip from cell (ci, cj) at level k for the ray (x0 + dx*lam, y0 + dy*lam, h0 +
    /// dh*lam) in cell space, now at lam = la: when the ray stays above the level-k block
    /// holding the cell until it leaves the block (or reaches lam_max), the lam where it leaves
    /// and the cell it enters there.
    #[allow(clippy::too_many_arguments)]
    fn skip(
        &self,
        k: usize,
        (ci, cj): (i64, i64),
        (x0, y0, h0): (f64, f64, f64),
        (dx, dy, dh): (f64, f64, f64),
        la: f64,
        lam_max: f64,
    ) -> Option<(f64, i64, i64)> {
        let lv = &self.levels[k - 1];
        let (w, h) = (self.hm.width as i64, self.hm.height as i64);
        // the block's cell range in unwrapped cell indices: [lo, hi)
        let range = |c: i64, n: i64| {
            let (p, l) = if (0..n).contains(&c) {
                (0, c)
            } else {
                (c.div_euclid(n), c.rem_euclid(n))
            };
            let b = l >> k;
            (b, p * n + (b << k), p * n + ((b + 1) << k).min(n))
        };
        let (bx, x_lo, x_hi) = range(ci, w);
        let (by, y_lo, y_hi) = range(cj, h);
        let top = lv.max[by as usize * lv.w + bx as usize] as f64;
        let exit = |d: f64, o: f64, lo: i64, hi: i64| {
            if d > 1e-300 {
                (hi as f64 - o) / d
            } else if d < -1e-300 {
                (lo as f64 - o) / d
            } else {
                f64::INFINITY
            }
        };
        let ex = exit(dx, x0, x_lo, x_hi);
        let ey = exit(dy, y0, y_lo, y_hi);
        let l_exit = ex.min(ey);
        if l_exit.is_nan() || l_exit <= la {
            return None;
        }
        // the ray is straight: its lowest point in [la, end] is at one end
        let end = l_exit.min(lam_max);
        let low = if dh > 0.0 {
            h0 + dh * la
        } else {
            h0 + dh * end
        };
        if !(low > top + 1e-12) {
            return None;
        }
        if l_exit >= lam_max {
            return Some((l_exit, ci, cj));
        }
        let cell = |o: f64, d: f64, lo: i64, hi: i64| floor(o + d * l_exit).clamp(lo, hi - 1);
        Some(if ex <= ey {
            let ni = if dx > 0.0 { x_hi } else { x_lo - 1 };
            (l_exit, ni, cell(y0, dy, y_lo, y_hi))
        } else {
            let nj = if dy > 0.0 { y_hi } else { y_lo - 1 };
            (l_exit, cell(x0, dx, x_lo, x_hi), nj)
        })
    }
}

/// The light ray (s0 + ds*lam, h0 + dh*lam), dh > 0, from a point on the surface up to h = 1:
/// true where no point of the bilinear field lies above it. It starts `bias` above the surface
/// (at least 1e-9: the point's own patch) and ends `bias` below the top, so that a blocker must
/// rise more than `bias` above the ray (the GPU's exact shadows use 1e-4); a point at the top
/// (h0 >= 1 - bias) has left the shell.
pub fn light_ray_free(f: &Field, s0: DVec2, h0: f64, ds: DVec2, dh: f64, bias: f64) -> bool {
    let top = 1.0 - bias.max(0.0);
    let h0 = h0 + bias.max(1e-9);
    if h0 >= top {
        return true;
    }
    walk_cells(f, s0, h0, ds, dh, (top - h0) / dh).0.is_none()
}

/// First ray parameter lam >= 0 where the ray (s0 + ds*lam, 1 + dh*lam), dh < 0, meets the
/// bilinear height field. Always found by lam = -1/dh (the floor), heights being >= 0.
pub fn march_height_field(f: &Field, s0: DVec2, ds: DVec2, dh: f64) -> Option<(f64, u32)> {
    if dh >= 0.0 {
        return None;
    }
    let lam_max = -1.0 / dh;
    let (hit, cells) = walk_cells(f, s0, 1.0, ds, dh, lam_max);
    Some((hit.unwrap_or(lam_max), cells))
}

/// The cell walk of the ray (s0 + ds*lam, h0 + dh*lam) over lam in [0, lam_max]: the first lam
/// at which the bilinear field is at or above the ray (None if there is none: for a descending
/// ray, the floor at lam_max is the caller's to report), and the steps taken (cells walked plus
/// blocks skipped). A walk that reaches MAX_CELLS steps stops there and reports lam_max.
pub(crate) fn walk_cells(
    f: &Field,
    s0: DVec2,
    h0: f64,
    ds: DVec2,
    dh: f64,
    lam_max: f64,
) -> (Option<f64>, u32) {
    let hm = f.hm;
    let (wf, hf) = (hm.width as f64, hm.height as f64);
    // texel space: cell (i, j) spans [i, i+1] x [j, j+1] between texel centres
    let x0 = s0.x * wf - 0.5;
    let y0 = s0.y * hf - 0.5;
    let dx = ds.x * wf;
    let dy = ds.y * hf;
    let mut ci = floor(x0);
    let mut cj = floor(y0);
    let step_i: i64 = if dx > 0.0 { 1 } else { -1 };
    let step_j: i64 = if dy > 0.0 { 1 } else { -1 };
    // ray parameter of the next x / y cell boundary
    let next_x = |ci: i64| -> f64 {
        if dx.abs() < 1e-300 {
            f64::INFINITY
        } else {
            let b = if dx > 0.0 { (ci + 1) as f64 } else { ci as f64 };
            (b - x0) / dx
        }
    };
    let next_y = |cj: i64| -> f64 {
        if dy.abs() < 1e-300 {
            f64::INFINITY
        } else {
            let b = if dy > 0.0 { (cj + 1) as f64 } else { cj as f64 };
            (b - y0) / dy
        }
    };
    let mut la = 0.0f64;
    let mut cells = 0u32;
    // the level to try first: one above the last that skipped
    let mut k_first = 1usize;
    'walk: loop {
        cells += 1;
        if cells >= MAX_CELLS {
            return (Some(lam_max), cells);
        }
        for k in (1..=k_first.min(f.levels.len())).rev() {
            if let Some((l, ni, nj)) = f.skip(k, (ci, cj), (x0, y0, h0), (dx, dy, dh), la, lam_max)
            {
                if l >= lam_max {
                    return (None, cells);
                }
                (la, ci, cj, k_first) = (l, ni, nj, k + 1);
                continue 'walk;
            }
        }
        k_first = 1;
        let tx = next_x(ci);
        let ty = next_y(cj);
        let lb = tx.min(ty).min(lam_max);
        if let Some(l) = cell_hit(hm, ci, cj, x0, y0, h0, dx, dy, dh, la, lb) {
            return (Some(l), cells);
        }
        if lb >= lam_max {
            return (None, cells);
        }
        if tx <= ty {
            ci += step_i;
        } else {
            cj += step_j;
        }
        la = lb;
    }
}

#[allow(clippy::too_many_arguments)]
fn cell_hit(
    hm: &HeightMap,
    ci: i64,
    cj: i64,
    x0: f64,
    y0: f64,
    h0: f64,
    dx: f64,
    dy: f64,
    dh: f64,
    la: f64,
    lb: f64,
) -> Option<f64> {
    let h00 = hm.texel(ci, cj);
    let h10 = hm.texel(ci + 1, cj);
    let h01 = hm.texel(ci, cj + 1);
    let h11 = hm.texel(ci + 1, cj + 1);
    let a1 = h10 - h00;
    let a2 = h01 - h00;
    let a3 = h00 - h10 - h01 + h11;
    let xa = x0 + dx * la - ci as f64;
    let ya = y0 + dy * la - cj as f64;
    let hra = h0 + dh * la;
    // f(tau) = H(x, y) - h_ray = A tau^2 + B tau + C on tau in [0, len]
    let c = h00 + a1 * xa + a2 * ya + a3 * xa * ya - hra;
    let b = a1 * dx + a2 * dy + a3 * (xa * dy + ya * dx) - dh;
    let a = a3 * dx * dy;
    let len = (lb - la).max(0.0);
    if c >= 0.0 {
        return Some(la);
    }
    let f = |t: f64| (a * t + b) * t + c;
    let mut roots = [f64::INFINITY; 2];
    if a.abs() < 1e-14 * (b.abs() + c.abs() + 1e-300) {
        if b.abs() > 0.0 {
            roots[0] = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let sq = disc.sqrt();
            // numerically stable pair
            let qq = -0.5 * (b + b.signum() * sq);
            let r1 = qq / a;
            let r2 = if qq != 0.0 { c / qq } else { f64::INFINITY };
            roots = [r1.min(r2), r1.max(r2)];
        }
    }
    for r in roots {
        if r >= 0.0 && r <= len {
            return Some(la + r);
        }
    }
    // tangent or rounding at the far end
    if f(len) >= 0.0 {
        // bisection on [0, len]
        let (mut lo, mut hi) = (0.0, len);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if f(mid) >= 0.0 {
                hi = mid
            } else {
                lo = mid
            }
        }
        return Some(la + hi);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (the tests need no crate for it).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Maps of odd and even sizes: noise, plateaus at exactly 0 and 1, a lone spike, cliffs.
    fn maps() -> Vec<HeightMap> {
        let mut r = Lcg(7);
        let mut out = Vec::new();
        for (w, h) in [(1u32, 1u32), (2, 3), (7, 13), (64, 64), (33, 17), (100, 36)] {
            let n = (w * h) as usize;
            out.push(HeightMap::new(w, h, (0..n).map(|_| r.next() as f32).collect()).unwrap());
            let plateaus = (0..n)
                .map(|i| {
                    if (i / 5) % 3 == 0 {
                        1.0
                    } else if (i / 3) % 2 == 0 {
                        0.0
                    } else {
                        0.5
                    }
                })
                .collect();
            out.push(HeightMap::new(w, h, plateaus).unwrap());
            let mut spike = vec![0.0f32; n];
            spike[n / 2] = 1.0;
            out.push(HeightMap::new(w, h, spike).unwrap());
            let cliffs = (0..n)
                .map(|i| if (i as u32 % w) < w / 2 { 0.9 } else { 0.05 })
                .collect();
            out.push(HeightMap::new(w, h, cliffs).unwrap());
        }
        out
    }

    /// `max_in` bounds the texels of every cell a box meets, within one period, across its
    /// edges and over several; and it is the field's lowest texel that `low` holds.
    #[test]
    fn max_in_bounds_the_cells_of_a_box() {
        let mut r = Lcg(5);
        for hm in maps() {
            let f = Field::new(&hm);
            let (w, h) = (hm.width as f64, hm.height as f64);
            let lowest = hm.data.iter().copied().fold(f32::INFINITY, f32::min) as f64;
            assert_eq!(f.low, lowest);
            for _ in 0..300 {
                // boxes from under a cell to a few periods, anywhere from one period before
                let (x0, y0) = (w * (3.0 * r.next() - 1.0), h * (3.0 * r.next() - 1.0));
                let size = (1.0 + w.max(h)) * r.next().powi(3) * 2.5;
                let (x1, y1) = (x0 + size * r.next(), y0 + size * r.next());
                let mut want = 0f64;
                for j in floor(y0)..=floor(y1) + 1 {
                    for i in floor(x0)..=floor(x1) + 1 {
                        want = want.max(hm.texel(i, j));
                    }
                }
                let got = f.max_in((x0, x1), (y0, y1));
                assert!(
                    got >= want,
                    "box ({x0}, {y0})..({x1}, {y1}): {got} < {want}"
                );
                assert!(got <= 1.0);
            }
        }
    }

    #[test]
    fn the_pyramid_changes_no_answer() {
        let mut r = Lcg(11);
        let mut skipped = 0u64;
        for hm in maps() {
            let (fast, slow) = (Field::new(&hm), Field::cell_walk_only(&hm));
            for i in 0..400 {
                let s0 = DVec2::new(r.next() * 3.0 - 1.0, r.next() * 3.0 - 1.0);
                let a = r.next() * std::f64::consts::TAU;
                // from steep to grazing; now and then exactly along an axis
                let run = 0.02 + 40.0 * r.next() * r.next();
                let mut ds = DVec2::new(a.cos(), a.sin()) * run / hm.width.max(hm.height) as f64;
                if i % 17 == 0 {
                    ds.y = 0.0;
                }
                if i % 23 == 0 {
                    ds = DVec2::ZERO;
                }
                let dh = 0.05 + r.next();
                let down = (
                    march_height_field(&fast, s0, ds, -dh),
                    march_height_field(&slow, s0, ds, -dh),
                );
                let (Some((lf, cf)), Some((ls, cs))) = down else {
                    panic!("a descending ray always ends")
                };
                assert!((lf - ls).abs() <= 1e-9 * (1.0 + ls), "down: {lf} vs {ls}");
                skipped += cs.saturating_sub(cf) as u64;
                let h0 = r.next();
                for bias in [0.0, 1e-6, 3e-5] {
                    assert_eq!(
                        light_ray_free(&fast, s0, h0, ds, dh, bias),
                        light_ray_free(&slow, s0, h0, ds, dh, bias),
                        "up from h0 = {h0}"
                    );
                }
            }
        }
        // the pyramid is used at all
        assert!(skipped > 10_000, "{skipped}");
    }
}

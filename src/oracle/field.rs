//! The oracle's walk of the bilinear, repeating height field: a ray, cell by cell (a 2-D DDA
//! over the cells between texel centres), meets each cell's bilinear patch as a quadratic in
//! the ray parameter, solved in closed form.

use super::MAX_CELLS;
use crate::scene::HeightMap;
use glam::DVec2;

/// The light ray (s0 + ds*lam, h0 + dh*lam), dh > 0, from a point on the surface up to h = 1:
/// true where no point of the bilinear field lies above it. It starts `bias` above the surface
/// (at least 1e-9: the point's own patch) and ends `bias` below the top, so that a blocker must
/// rise more than `bias` above the ray (the GPU's exact shadows use 1e-4); a point at the top
/// (h0 >= 1 - bias) has left the shell.
pub fn light_ray_free(hm: &HeightMap, s0: DVec2, h0: f64, ds: DVec2, dh: f64, bias: f64) -> bool {
    let top = 1.0 - bias.max(0.0);
    let h0 = h0 + bias.max(1e-9);
    if h0 >= top {
        return true;
    }
    walk_cells(hm, s0, h0, ds, dh, (top - h0) / dh).0.is_none()
}

/// First ray parameter lam >= 0 where the ray (s0 + ds*lam, 1 + dh*lam), dh < 0, meets the
/// bilinear height field. Always found by lam = -1/dh (the floor), heights being >= 0.
pub fn march_height_field(hm: &HeightMap, s0: DVec2, ds: DVec2, dh: f64) -> Option<(f64, u32)> {
    if dh >= 0.0 {
        return None;
    }
    let lam_max = -1.0 / dh;
    let (hit, cells) = walk_cells(hm, s0, 1.0, ds, dh, lam_max);
    Some((hit.unwrap_or(lam_max), cells))
}

/// The cell walk of the ray (s0 + ds*lam, h0 + dh*lam) over lam in [0, lam_max]: the first lam
/// at which the bilinear field is at or above the ray (None if there is none: for a descending
/// ray, the floor at lam_max is the caller's to report), and the cells walked. A walk that
/// reaches MAX_CELLS stops there and reports lam_max.
fn walk_cells(
    hm: &HeightMap,
    s0: DVec2,
    h0: f64,
    ds: DVec2,
    dh: f64,
    lam_max: f64,
) -> (Option<f64>, u32) {
    let (wf, hf) = (hm.width as f64, hm.height as f64);
    // texel space: cell (i, j) spans [i, i+1] x [j, j+1] between texel centres
    let x0 = s0.x * wf - 0.5;
    let y0 = s0.y * hf - 0.5;
    let dx = ds.x * wf;
    let dy = ds.y * hf;
    let mut ci = x0.floor() as i64;
    let mut cj = y0.floor() as i64;
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
    loop {
        cells += 1;
        let tx = next_x(ci);
        let ty = next_y(cj);
        let lb = tx.min(ty).min(lam_max);
        if let Some(l) = cell_hit(hm, ci, cj, x0, y0, h0, dx, dy, dh, la, lb) {
            return (Some(l), cells);
        }
        if lb >= lam_max {
            return (None, cells);
        }
        if cells >= MAX_CELLS {
            return (Some(lam_max), cells);
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
    let len = lb - la;
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

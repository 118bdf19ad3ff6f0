// maxmip.wgsl: maximum mipmaps (Tevs, Ihrke & Seidel 2008). The ray walks the max-mip pyramid
// of the cells between texel centres: where it passes above a node's max it skips the node and
// ascends; where it dips below it descends; at level 0 it meets the bilinear patch of the cell
// exactly (a quadratic along the ray). No step count to tune, no feature missed; iterations are
// bounded by `max_iterations` (rays that hit the bound are flagged).
//
// The pyramid is not a mipmapped texture: each lane reads a different level, and on lavapipe
// (Mesa 22.3) textureLoad/textureDimensions with a level that varies across the lanes of a SIMD
// vector returned other lanes' levels (rays then skipped whole regions). Level 0 is a texture
// and the levels above sit side by side in an atlas (globals.wgsl), each read at mip level 0.
//
// Cell space: X = s.x * W - 0.5, Y = s.y * H - 0.5; cell (i, j) spans texel centres i..i+1,
// j..j+1 (wrapping). The pyramid is used up to the highest level whose size divides the map
// (all levels for power-of-two maps), so that nodes tile the map exactly.

#define_import_path pomkit::maxmip

#import pomkit::globals::{G, height_tex, height_samp}
#import pomkit::height::max_at
#import pomkit::cost::fetched

// A point in cell space as a whole cell index and the offset within that cell ([0, 1) each).
// Kept apart, positions relative to a cell are taken as an exact integer difference plus a small
// offset: one f32 for the whole (X ~ several hundred once moved by whole periods) left 3e-5 cell
// of rounding, which on steep slopes put a light ray's start below its own patch.
struct CellPoint {
    base: vec2<i32>,
    frac: vec2<f32>,
}

fn cell_point(p: vec2<f32>) -> CellPoint {
    let b = floor(p);
    return CellPoint(vec2<i32>(b), p - b);
}

// A whole-cell position x (a cell's or node's corner, a middle face) less the start: the whole
// part taken in f32, where both (below 2^24) and their difference are exact, then the offset.
// (In i32, node * size - base came out wrong on lavapipe in the traversal's loop.)
fn from_start(st: CellPoint, x: vec2<f32>) -> vec2<f32> {
    return (x - vec2<f32>(st.base)) - st.frac;
}

// First t in [t0, t1] where the ray (x(t), y(t), h(t)) = (X0 + dX t, Y0 + dY t, h0 + dh t),
// (X0, Y0) = `st`, meets the bilinear patch of cell c, or -1.
fn cell_intersect(c: vec2<i32>, st: CellPoint, h0: f32, dx: f32, dy: f32, dh: f32, t0: f32, t1: f32) -> f32 {
    // the cell's four corners in one gather (level 0, wrapped by the repeating sampler): at the
    // point between the four texel centres c .. c + 1 the gather's footprint is exactly them
    // (w: (c.x, c.y), z: (c.x + 1, c.y), x: (c.x, c.y + 1), y: (c.x + 1, c.y + 1))
    let q = textureGather(0, height_tex, height_samp, (vec2<f32>(c) + 1.0) / G.map_size);
    fetched(4u, 16u);
    let a = q.w;
    let b = q.z;
    let cc = q.x;
    let d = q.y;
    let a1 = b - a;
    let a2 = cc - a;
    let a3 = a - b - cc + d;
    let o = from_start(st, vec2<f32>(c));
    let xa = dx * t0 - o.x;
    let ya = dy * t0 - o.y;
    let hra = h0 + dh * t0;
    let qc = a + a1 * xa + a2 * ya + a3 * xa * ya - hra;
    let qb = a1 * dx + a2 * dy + a3 * (xa * dy + ya * dx) - dh;
    let qa = a3 * dx * dy;
    let len = t1 - t0;
    if (qc >= 0.0) {
        return t0;
    }
    var r = 1e30;
    if (abs(qa) < 1e-9 * (abs(qb) + 1e-12)) {
        if (qb > 0.0) {
            r = -qc / qb;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            let sq = sqrt(disc);
            let q = -0.5 * (qb + select(-sq, sq, qb >= 0.0));
            let r1 = q / qa;
            let r2 = select(1e30, qc / q, q != 0.0);
            let lo = min(r1, r2);
            let hi = max(r1, r2);
            if (lo >= 0.0) {
                r = lo;
            } else {
                r = hi;
            }
        }
    }
    if (r >= 0.0 && r <= len) {
        return t0 + r;
    }
    // tangent or rounding at the far end
    let fe = (qa * len + qb) * len + qc;
    if (fe >= 0.0) {
        return t1;
    }
    return -1.0;
}

struct Traversal {
    hit: bool,
    t: f32,
    iters: f32,
    bound: bool,
}

// Walk the ray from (X0, Y0, h0) with per-t slope (dX, dY) and dh = -1 (view ray, down to the
// floor) or +1 (light ray, up to the top of the shell). The current node is integer state:
// a skipped node hands over to its neighbour across the face the ray leaves by, and a descent
// picks the child that holds the ray, clamped to the parent, so that no boundary case depends on
// floating-point rounding of the ray's position.
// `t_max` shortens the walk (a prism's segment); a view ray reports a floor hit only when it
// is allowed to reach the floor.
fn maxmip_traverse(st: CellPoint, h0: f32, dx: f32, dy: f32, dh: f32, t_max: f32, max_iterations: f32) -> Traversal {
    var r: Traversal;
    r.hit = false;
    r.bound = false;
    r.iters = 0.0;
    let t_full = select(1.0 - h0, h0, dh < 0.0);
    let t_end = min(t_full, t_max);
    let top = i32(G.top_max_level);
    var t = 0.0;
    let max_it = u32(max_iterations);
    let step = vec2<i32>(select(-1, 1, dx >= 0.0), select(-1, 1, dy >= 0.0));
    // The walk starts bottom-up, at the cell the ray starts in, and ascends as it skips nodes:
    // most rays meet the surface within a few cells of where they enter the shell, and a
    // top-down start paid a descent through every level for each of them. Exactness does not
    // depend on where the walk starts.
    var level = 0;
    var node = st.base;
    var it = 0u;
    var found = false;
    var t_hit = 0.0;
    // The cell the ray starts in, first: where the ray starts on or just above the surface (a
    // plateau, the top of a prism segment) this is the hit, found in one step instead of a
    // descent through every level. Exact either way: it is the first cell the ray crosses.
    {
        var tx0 = 1e30;
        if (dx != 0.0) {
            tx0 = (select(0.0, 1.0, dx > 0.0) - st.frac.x) / dx;
        }
        var ty0 = 1e30;
        if (dy != 0.0) {
            ty0 = (select(0.0, 1.0, dy > 0.0) - st.frac.y) / dy;
        }
        let t_exit0 = clamp(min(tx0, ty0), 0.0, t_end);
        it = 1u;
        let th = cell_intersect(node, st, h0, dx, dy, dh, 0.0, t_exit0);
        if (th >= 0.0) {
            found = true;
            t_hit = th;
        }
        // on to the next cell, and up from there
        t = t_exit0;
        if (tx0 <= ty0) {
            node.x = node.x + step.x;
        }
        if (ty0 <= tx0) {
            node.y = node.y + step.y;
        }
        if (top > 0) {
            level = 1;
            node = vec2<i32>(floor(vec2<f32>(node) * 0.5));
        }
    }
    loop {
        if (found) {
            break;
        }
        if (t >= t_end) {
            break;
        }
        if (it >= max_it) {
            r.bound = true;
            break;
        }
        it = it + 1u;
        let size = f32(1 << u32(level));
        // the node's faces, from the start
        let lo = from_start(st, vec2<f32>(node) * size);
        let hi = from_start(st, (vec2<f32>(node) + 1.0) * size);
        var tx = 1e30;
        if (dx > 0.0) {
            tx = hi.x / dx;
        } else if (dx < 0.0) {
            tx = lo.x / dx;
        }
        var ty = 1e30;
        if (dy > 0.0) {
            ty = hi.y / dy;
        } else if (dy < 0.0) {
            ty = lo.y / dy;
        }
        let t_exit = clamp(min(tx, ty), t, t_end);
        let m = max_at(node, level);
        // the ray's lowest point over [t, t_exit]
        let low = min(h0 + dh * t, h0 + dh * t_exit);
        // 0: skip the node, 1: descend into it, 2: intersect the cell (level 0)
        var action = 0u;
        if (low <= m) {
            if (dh < 0.0) {
                // descending: jump to where the ray dips below the node's max
                t = max(t, h0 - m);
            }
            action = select(2u, 1u, level > 0);
        }
        if (action == 2u) {
            let th = cell_intersect(node, st, h0, dx, dy, dh, t, t_exit);
            if (th >= 0.0) {
                found = true;
                t_hit = th;
                break;
            }
            action = 0u;
        }
        if (action == 1u) {
            level = level - 1;
            let cs = f32(1 << u32(level));
            // the child the ray is in at t (on the middle face, the one ahead), decided by the
            // t at which it crosses the middle face, taken as the faces' t are: a position
            // rounded on its own could name the child the ray just left
            let mid = from_start(st, (vec2<f32>(2 * node) + 1.0) * cs);
            var up = vec2<bool>(mid.x <= 0.0, mid.y <= 0.0);
            if (dx > 0.0) {
                up.x = t >= mid.x / dx;
            } else if (dx < 0.0) {
                up.x = t < mid.x / dx;
            }
            if (dy > 0.0) {
                up.y = t >= mid.y / dy;
            } else if (dy < 0.0) {
                up.y = t < mid.y / dy;
            }
            node = 2 * node + select(vec2<i32>(0, 0), vec2<i32>(1, 1), up);
        } else {
            // leave the node across the face the ray exits by, then look at the coarser level
            t = t_exit;
            if (tx <= ty) {
                node.x = node.x + step.x;
            }
            if (ty <= tx) {
                node.y = node.y + step.y;
            }
            if (level < top) {
                level = level + 1;
                // the parent: floor(node / 2), in f32 (see wrap_i in common.wgsl)
                node = vec2<i32>(floor(vec2<f32>(node) * 0.5));
            }
        }
    }
    if (found) {
        r.hit = true;
        r.t = t_hit;
        r.iters = f32(it);
        return r;
    }
    r.iters = f32(it);
    r.t = t_end;
    // a view ray always meets the floor (heights >= 0) at t_end
    r.hit = dh < 0.0 && t_end >= t_full;
    return r;
}

// The ray's start in cell space, moved by whole periods of the (repeating) map so that every
// node it visits over its whole length has non-negative indices. With negative indices the
// traversal looped to its bound on lavapipe (integer ops on negative i32 in lane-divergent
// loops); with non-negative ones every index operation is plain.
fn positive_start(s0: vec2<f32>, d: vec2<f32>) -> CellPoint {
    let p = s0 * G.map_size - 0.5;
    let b = floor(p);
    // whole numbers below 2^24: exact in f32
    let wrapped = b - floor(b / G.map_size) * G.map_size;
    let periods = floor(abs(d) / G.map_size) + 2.0;
    return CellPoint(vec2<i32>(wrapped + periods * G.map_size), p - b);
}

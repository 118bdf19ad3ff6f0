// maxmip.wgsl: maximum mipmaps (Tevs, Ihrke & Seidel 2008). The ray walks the max-mip pyramid
// of the cells between texel centres: where it passes above a node's max it skips the node and
// ascends; where it dips below it descends; at level 0 it meets the bilinear patch of the cell
// exactly (a quadratic along the ray). No step count to tune, no feature missed; iterations are
// bounded by `max_iterations` (rays that hit the bound are flagged).
//
// The pyramid is not a mipmapped texture: each lane reads a different level, and on lavapipe
// (Mesa 22.3) textureLoad/textureDimensions with a level that varies across the lanes of a SIMD
// vector returned other lanes' levels (rays then skipped whole regions). Level 0 is a texture
// and the levels above sit side by side in an atlas (object.wgsl), each read at mip level 0.
//
// Cell space: X = s.x * W - 0.5, Y = s.y * H - 0.5; cell (i, j) spans texel centres i..i+1,
// j..j+1 (wrapping). The pyramid is used up to the highest level whose size divides the map
// (all levels for power-of-two maps), so that nodes tile the map exactly.

#define_import_path pomkit::maxmip

#import pomkit::object::{G, height_tex, height_samp, max_children}
#import pomkit::height::max_at
#import pomkit::cost::{fetched, chained}

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
// (X0, Y0) = `st`, meets the bilinear patch of cell c, or -1. (Custom methods import it with an
// i32 cell: docs/custom_methods.md.)
fn cell_intersect(c: vec2<i32>, st: CellPoint, h0: f32, dx: f32, dy: f32, dh: f32, t0: f32, t1: f32) -> f32 {
    return cell_intersect_f(vec2<f32>(c), st, h0, dx, dy, dh, t0, t1);
}

// `cell_intersect` for a cell held as a whole number in f32 (exact below 2^24), as the walk
// holds its node.
fn cell_intersect_f(c: vec2<f32>, st: CellPoint, h0: f32, dx: f32, dy: f32, dh: f32, t0: f32, t1: f32) -> f32 {
    // the cell's four corners in one gather (level 0, wrapped by the repeating sampler): at the
    // point between the four texel centres c .. c + 1 the gather's footprint is exactly them
    // (w: (c.x, c.y), z: (c.x + 1, c.y), x: (c.x, c.y + 1), y: (c.x + 1, c.y + 1))
    let q = textureGather(0, height_tex, height_samp, (c + 1.0) / G.map_size);
    fetched(4u, 16u);
    let a = q.w;
    let b = q.z;
    let cc = q.x;
    let d = q.y;
    let a1 = b - a;
    let a2 = cc - a;
    let a3 = a - b - cc + d;
    let o = from_start(st, c);
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

// The four children's maxes of node `node` of a level k >= 1 (nodes of `size` = 2^k cells;
// `inv_cells` = 1 / (map size in cells)), from the children atlas, for k <= the top level
// (whose size divides the map): x child (0, 1), y (1, 1), z (1, 0), w (0, 0), each rounded up
// to a unorm8 code (mips.wgsl's max_children: never below the true max). One load of one
// 32-bit texel (counted so). No integer division, no table: on lavapipe vector
// integer division is scalarised, and a uniform array indexed per lane (G.max_offsets) cost
// 7 % of Exact's march.
// - The wrap: floor((n + 0.5) / dims) by the reciprocal is exact for 0 <= n < 2^22 (the
//   quotient lies >= 0.5 / (n + 0.5) of itself from a whole number; the product's rounding is
//   below 2^-23 of it). Nodes are non-negative (positive_start) and below 2^22 for any ray that
//   crosses fewer than 4 million cells.
// - The offset: level 1 at (0, 0), level k >= 2 at (W / 2, H / 2 - 2 H / 2^k) (the heights of
//   levels 2 .. k - 1 above it sum to that when 2^(k - 1) divides H, as it does up to the top
//   level: src/heightmap/mod.rs's children_atlas and its test).
fn node_children(nf: vec2<f32>, size: f32, isize: f32, inv_cells: vec2<f32>) -> vec4<f32> {
    let dims = G.map_size * isize;
    let p = nf - floor((nf + 0.5) * (size * inv_cells)) * dims;
    fetched(1u, 4u);
    let off = select(vec2<f32>(0.0), vec2<f32>(0.5 * G.map_size.x, 0.5 * G.map_size.y - 2.0 * dims.y), size > 2.0);
    return textureLoad(max_children, vec2<i32>(p + off), 0);
}

// The node across the face a ray leaves `node` by (both faces at a corner), from the t at which
// it crosses each face.
fn across_exit(node: vec2<f32>, step: vec2<f32>, tf: vec2<f32>) -> vec2<f32> {
    return node + select(vec2<f32>(0.0), step, vec2<bool>(tf.x <= tf.y, tf.y <= tf.x));
}

// The t at which the ray crosses each exit face of node `node` (nodes of `size` cells), from the
// start; `exit_face` is 1 on an axis the ray moves up along, else 0.
fn exit_faces(st: CellPoint, node: vec2<f32>, size: f32, exit_face: vec2<f32>, inv: vec2<f32>) -> vec2<f32> {
    return from_start(st, (node + exit_face) * size) * inv;
}

// Walk the ray from (X0, Y0, h0) with per-t slope (dX, dY) and dh = -1 (view ray, down to the
// floor) or +1 (light ray, up to the top of the shell). The current node is a whole number
// (held in f32: exact below 2^22, and no conversion a trip): a skipped node hands over to its
// neighbour across the face the ray leaves by (+-1), its parent is floor(node / 2), and a descent
// picks the child that holds the ray, so that no boundary case depends on floating-point
// rounding of the ray's position.
// `t_max` shortens the walk (a prism's segment); a view ray reports a floor hit only when it
// is allowed to reach the floor.
//
// Two loops. The inner one walks the levels k >= 1, one read a trip: a node's four children's
// maxes (`node_children`). The ray crosses at most three of the children, split at the t where
// it crosses the node's middle faces; it descends straight into the first of them it dips below
// (at the t it dips below that child's max), or, dipping below none, skips the node, across the
// face it leaves by and up a level where it clears the node by enough (`clear_per_size`). A
// descent to level 0 ends the trip with a candidate cell whose max the ray is known to dip
// below. The outer loop meets the candidate's bilinear patch (its four corners in one gather): a
// hit ends the walk, a miss moves on to the next cell's parent, at level 1. On a SIMD machine
// (lavapipe runs both sides of every branch a lane of the group takes, and a group leaves the
// inner loop only when every lane has its candidate) the patch arithmetic runs once per
// candidate, not once per step, and the children's maxes spare the patch tests of cells the ray
// passes above: 20-40 % fewer on rough content than reading one node's max a trip, which held
// gravel at 70° to 1.37 x POM's march (docs/cost_journal_2026.md).
fn maxmip_traverse(st: CellPoint, h0: f32, dx: f32, dy: f32, dh: f32, t_max: f32, max_iterations: f32) -> Traversal {
    var r: Traversal;
    r.hit = false;
    r.bound = false;
    let t_full = select(1.0 - h0, h0, dh < 0.0);
    let t_end = min(t_full, t_max);
    let top = i32(G.top_max_level);
    let max_it = u32(max_iterations);
    let step = vec2<f32>(select(-1.0, 1.0, dx >= 0.0), select(-1.0, 1.0, dy >= 0.0));
    // the top level's node size, exactly (exp2 may be approximate on a GPU, and a size above
    // it would read past the top level)
    let top_size = f32(1u << u32(top));
    // per axis: 1 / slope (1e30 parallel to the axis), and which face the ray leaves a node by
    let ahead = vec2<bool>(dx > 0.0, dy > 0.0);
    let behind = vec2<bool>(dx < 0.0, dy < 0.0);
    // (an axis the ray does not move along takes the far face: a positive distance times 1e30,
    // never the nearer exit)
    let moves = vec2<bool>(dx != 0.0, dy != 0.0);
    let inv = select(vec2<f32>(1e30), vec2<f32>(1.0) / vec2<f32>(dx, dy), moves);
    let exit_face = select(vec2<f32>(0.0), vec2<f32>(1.0), vec2<bool>(dx >= 0.0, dy >= 0.0));
    let inv_cells = vec2<f32>(1.0) / G.map_size;
    // A skipped node hands over to its parent only where the ray passes its max by more than
    // the height the ray falls (or rises) over two node widths along its faster axis: on rough
    // content a ray that only just clears a node dips below the parent's max too, and the
    // ascent and the descent back cost two trips for nothing. Either choice covers the ray with
    // nodes and meets the same first hit (docs/cost_journal_2026.md).
    let clear_per_size = 2.0 * abs(dh) * min(abs(inv.x), abs(inv.y));
    var size = 1.0;
    // 1 / size (both powers of two: exact)
    var isize = 1.0;
    var node = vec2<f32>(st.base);
    var t = 0.0;
    var it = 1u;
    var found = false;
    var t_hit = 0.0;
    // the current node's exit: t across each face, and the t at which the ray leaves
    var tf = (exit_face - st.frac) * inv;
    var t_exit = clamp(min(tf.x, tf.y), 0.0, t_end);
    // The cell the ray starts in is a candidate if the ray dips below its max there (a plateau
    // at the top of the shell, a light ray's start on the surface, a prism segment's start):
    // the hit is then found without a walk. Otherwise the walk starts at the next cell's
    // parent: most rays meet the surface within a few cells of where they enter, and a top-down
    // start paid a descent through every level for each of them.
    var cand = min(h0, h0 + dh * t_exit) <= max_at(st.base, 0);
#ifdef PREFETCH
    // the children of the node the walk goes on to next, read a round early: with the start
    // cell's max here (the next cell's parent, where a start cell that is no candidate walks
    // on), with a candidate's patch below
    var pre = vec4<f32>(0.0);
    var have_pre = top > 0;
    if (have_pre) {
        pre = node_children(floor(across_exit(node, step, tf) * 0.5), 2.0, 0.5, inv_cells);
    }
#endif
    loop {
        if (!cand) {
            // on from the current cell (its patch missed, or the start cell): across the face
            // the ray leaves by, to that cell's parent (a map with no level above 0 walks cells)
            t = t_exit;
            node = across_exit(node, step, tf);
            if (top > 0) {
                size = 2.0;
                isize = 0.5;
                node = floor(node * 0.5);
            }
            tf = exit_faces(st, node, size, exit_face, inv);
            t_exit = clamp(min(tf.x, tf.y), t, t_end);
            loop {
                if (t >= t_end) {
                    break;
                }
                if (it >= max_it) {
                    r.bound = true;
                    break;
                }
                if (size == 1.0) {
                    // a map with no level above 0: every cell is a candidate
                    cand = true;
                    break;
                }
                it = it + 1u;
#ifdef PREFETCH
                var c4 = pre;
                if (have_pre) {
                    have_pre = false;
                } else {
                    // the node's address follows from the last node's verdict
                    chained();
                    c4 = node_children(node, size, isize, inv_cells);
                }
#else
                // the node's address follows from the last node's verdict
                chained();
                let c4 = node_children(node, size, isize, inv_cells);
#endif
                let m = max(max(c4.x, c4.y), max(c4.z, c4.w));
                // The children the ray crosses over [t, t_exit], in order: the one it is in at t
                // (which side of each middle face, decided by the t at which it crosses that face,
                // taken as the exit faces' t are: a position rounded on its own could name the
                // child the ray just left), then one more across each middle face it crosses.
                let mid = from_start(st, (node + 0.5) * size);
                let tm = mid * inv;
                let u0 = select(select(mid <= vec2<f32>(0.0), vec2<bool>(t < tm.x, t < tm.y), behind),
                                vec2<bool>(t >= tm.x, t >= tm.y), ahead);
                let crosses = moves & vec2<bool>((tm.x > t) && (tm.x < t_exit), (tm.y > t) && (tm.y < t_exit));
                let ex = select(t_exit, tm.x, crosses.x);
                let ey = select(t_exit, tm.y, crosses.y);
                let e1 = min(ex, ey);
                let e2 = max(ex, ey);
                let x_first = ex <= ey;
                let flip1 = vec2<bool>(crosses.x && x_first, crosses.y && !x_first);
                let u1 = u0 != flip1;
                let u2 = u1 != vec2<bool>(crosses.x && !flip1.x, crosses.y && !flip1.y);
                let m0 = select(select(c4.w, c4.z, u0.x), select(c4.x, c4.y, u0.x), u0.y);
                let m1 = select(select(c4.w, c4.z, u1.x), select(c4.x, c4.y, u1.x), u1.y);
                let m2 = select(select(c4.w, c4.z, u2.x), select(c4.x, c4.y, u2.x), u2.y);
                // the ray's height where it enters each child and where it leaves the node; it is
                // linear, so its lowest point in a child is at one end
                let h_t = h0 + dh * t;
                let h_1 = h0 + dh * e1;
                let h_2 = h0 + dh * e2;
                let h_x = h0 + dh * t_exit;
                let d0 = min(h_t, h_1) <= m0;
                let d1 = e2 > e1 && min(h_1, h_2) <= m1;
                let d2 = t_exit > e2 && min(h_2, h_x) <= m2;
                let below = d0 || d1 || d2;
                let uc = select(select(u2, u1, d1), u0, d0);
                let mc = select(select(m2, m1, d1), m0, d0);
                let tc = select(select(e2, e1, d1), t, d0);
                let child = 2.0 * node + select(vec2<f32>(0.0), vec2<f32>(1.0), uc);
                // both moves, then one select. Descend into that child, where a descending ray
                // dips below its max; or skip: across the exit face, and up a level unless the
                // ray passes the node's max by less than it falls over two of its widths
                let td = select(tc, max(tc, h0 - mc), dh < 0.0);
                let next = across_exit(node, step, tf);
                let clears = min(h_t, h_x) - m > clear_per_size * size;
                let asc = size < top_size && clears;
                node = select(select(next, floor(next * 0.5), asc), child, below);
                size = select(select(size, size * 2.0, asc), size * 0.5, below);
                isize = select(select(isize, isize * 0.5, asc), isize * 2.0, below);
                t = select(t_exit, td, below);
                // the new node's exit faces, from the start; a cell is the candidate at once
                tf = exit_faces(st, node, size, exit_face, inv);
                t_exit = clamp(min(tf.x, tf.y), t, t_end);
                if (size == 1.0 && t < t_end) {
                    cand = true;
                    break;
                }
            }
            if (!cand) {
                break;
            }
        }
        cand = false;
        // the candidate was found by a max read before: its patch is a round of its own
        chained();
#ifdef PREFETCH
        // Latency hiding: the node a miss walks on to (the next cell's parent, as the walk above
        // takes it) is known now, so its children are read in the same round as the patch. A
        // miss then starts its next trip without waiting; a hit wastes one read.
        if (top > 0) {
            pre = node_children(floor(across_exit(node, step, tf) * 0.5), 2.0, 0.5, inv_cells);
            have_pre = true;
        }
#endif
        let th = cell_intersect_f(node, st, h0, dx, dy, dh, t, t_exit);
        if (th >= 0.0) {
            found = true;
            t_hit = th;
            break;
        }
    }
    r.iters = f32(it);
    if (found) {
        r.hit = true;
        r.t = t_hit;
        return r;
    }
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

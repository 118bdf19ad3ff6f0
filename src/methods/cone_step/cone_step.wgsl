// Cone step mapping over the cone map (cone_map.wgsl beside this file): from a point of the ray at height
// hr above the cell's cone (base, w), the ray may drop by (hr - base) w / (w + a) (a: the ray's
// horizontal run in cells per unit of height, L-inf) without meeting the surface. With
// conservative cones no step crosses the bilinear surface.
//   REFINE_EXACT: a walk through the cells the ray crosses, each tested with the exact patch
//     intersection (maxmip.wgsl's cell_intersect), where after every cell the cone of the next
//     one skips the empty space ahead: far from the surface the cones carry the ray many cells
//     a step, near it the walk goes cell by cell (one step, not a descent and ascent of the
//     pyramid per cell). Exact: conservative cones only skip space the surface does not enter.
//     After `max_steps` cells the max-mip walk finishes the ray (still exact).
//   REFINE_BINARY: cone steps (at least half a cell each) until the ray is below the surface,
//     then `binary_steps` bisections between the last point above and the first below.
//   REFINE_NONE: the raw cone march: it stops below the surface or when the steps vanish.
// A ray still marching after `max_steps` (BINARY, NONE) or a walk at its bound (EXACT) is
// flagged (FLAG_BOUND).
#define_import_path pomkit::methods::cone_step

#import pomkit::cost::{fetched, chained}
#import pomkit::object::G
#import pomkit::aov::FLAG_BOUND
#import pomkit::march::{Ray, Hit, planar_hit, does_not_descend}
#import pomkit::maxmip::{cell_intersect, cell_point, maxmip_traverse, positive_start}
#import pomkit::height::{height_at, wrap_i}

// the method's own resources (group 2, bindings 1 and 2): the cone map, base and w per cell, in
// two textures of the map's size (cone_map.wgsl)
@group(2) @binding(1) var cone_base: texture_2d<f32>;
@group(2) @binding(2) var cone_w: texture_2d<f32>;

// the cell the ray at p travels through next (on a boundary: the one ahead along dir)
fn cell_ahead(p: vec2<f32>, dir: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(select(ceil(p) - 1.0, floor(p), dir >= vec2<f32>(0.0)));
}

// (base, w) of a cell
fn cone_of(c: vec2<i32>) -> vec2<f32> {
    let d = vec2<i32>(G.map_size);
    let p = vec2<i32>(wrap_i(c.x, d.x), wrap_i(c.y, d.y));
    fetched(2u, 8u);
    return vec2<f32>(textureLoad(cone_base, p, 0).r, textureLoad(cone_w, p, 0).r);
}

// how far (in height drop) the ray at height 1 - t may go under the cone without meeting the
// surface (negative: the ray is below the cone's base)
fn cone_step(cone: vec2<f32>, t: f32, a: f32, top: f32) -> f32 {
    return (top - t - cone.x) * cone.y / (cone.y + a);
}

// the ray is at or below the surface at height drop t
fn below(r: Ray, t: f32) -> bool {
    return r.top - t <= height_at(r.s + r.dsdh * t, 0.0);
}

fn march(r: Ray) -> Hit {
    if (does_not_descend(r)) {
        var entry = planar_hit(r, r.s, 1.0, 0.0, 0u);
        entry.lod = 0.0;
        return entry;
    }
    // cell space, per unit of height drop t (the ray is at height 1 - t)
    let d = r.dsdh * G.map_size;
    let a = max(abs(d.x), abs(d.y));
    let st = positive_start(r.s, d);
    let p0 = vec2<f32>(st.base) + st.frac;
    let n = u32(params.max_steps);
    // the search descends from the window's top (1 but for Hybrid's fine method) to h = 0
    let top = r.top;
    var t = 0.0;
    var i = 0u;
    var flags = 0u;
#ifdef REFINE_EXACT
    var found = false;
    loop {
        if (i >= n || t >= top) {
            break;
        }
        i = i + 1u;
        // each step's cell follows from the last cone read
        chained();
        let p = p0 + d * t;
        let c = cell_ahead(p, d);
        let edge = vec2<f32>(c) + select(vec2<f32>(0.0), vec2<f32>(1.0), d > vec2<f32>(0.0));
        var t_exit = top;
        if (d.x != 0.0) {
            t_exit = min(t_exit, t + (edge.x - p.x) / d.x);
        }
        if (d.y != 0.0) {
            t_exit = min(t_exit, t + (edge.y - p.y) / d.y);
        }
        t_exit = max(t_exit, t);
        let th = cell_intersect(c, st, top, d.x, d.y, -1.0, t, t_exit);
        if (th >= 0.0) {
            t = th;
            found = true;
            break;
        }
        t = t_exit;
        // the next cell's cone skips the empty space ahead
        let q = p0 + d * t;
        t = min(t + max(cone_step(cone_of(cell_ahead(q, d)), t, a, top), 0.0), top);
    }
    var steps = f32(i);
    if (!found && t < top) {
        // max_steps cells walked: the max-mip walk finishes the ray, still exact
        let p = p0 + d * t;
        let tr = maxmip_traverse(cell_point(p), top - t, d.x, d.y, -1.0, 2.0, G.max_iterations);
        t = t + tr.t;
        steps = steps + tr.iters;
        flags = select(0u, FLAG_BOUND, tr.bound);
    }
#else
    var t_prev = 0.0;
    var inside = false;
    var converged = false;
    loop {
        if (i >= n || t >= top) {
            break;
        }
        // each step's cell follows from the last cone read
        chained();
        if (below(r, t)) {
            inside = true;
            break;
        }
        var dt = cone_step(cone_of(vec2<i32>(floor(p0 + d * t))), t, a, top);
#ifdef REFINE_BINARY
        // relaxed cones may stop short of the surface: a minimum step of half a cell
        dt = max(dt, min(0.5 / max(a, 1e-6), 1.0 / 32.0));
#else
        if (dt * max(a, 1.0) < 1e-3) {
            converged = true;
            break;
        }
#endif
        i = i + 1u;
        t_prev = t;
        t = min(t + dt, top);
    }
    var steps = f32(i);
#ifdef REFINE_BINARY
    if (inside) {
        var lo = t_prev;
        var hi = t;
        for (var k = 0u; k < u32(params.binary_steps); k = k + 1u) {
            let mid = 0.5 * (lo + hi);
            chained();
            if (below(r, mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        t = hi;
        steps = steps + params.binary_steps;
    }
#endif
    if (!inside && !converged && t < top) {
        flags = FLAG_BOUND;
    }
#endif
    var hit = planar_hit(r, r.s + r.dsdh * t, clamp(top - t, 0.0, 1.0), steps, flags);
    hit.lod = 0.0;
    return hit;
}

// Exact: maximum mipmaps (Tevs, Ihrke & Seidel 2008), the traversal of maxmip.wgsl from the base
// surface to the floor, at level 0 with the exact patch intersection. No step count to tune;
// `max_iterations` (G.max_iterations) bounds it and flags the rays that reach the bound.
#define_import_path pomkit::methods::exact

#import pomkit::object::G
#import pomkit::aov::FLAG_BOUND
#import pomkit::march::{Ray, Hit, planar_hit, does_not_descend}
#import pomkit::maxmip::{maxmip_traverse, positive_start}

fn march(r: Ray) -> Hit {
    if (does_not_descend(r)) {
        var entry = planar_hit(r, r.s, 1.0, 0.0, 0u);
        entry.lod = 0.0;
        return entry;
    }
    let d = r.dsdh * G.map_size;
    let p0 = positive_start(r.s, d);
    let tr = maxmip_traverse(p0, r.top, d.x, d.y, -1.0, 2.0, G.max_iterations);
    var hit = planar_hit(r, r.s + r.dsdh * tr.t, clamp(r.top - tr.t, 0.0, 1.0), tr.iters, select(0u, FLAG_BOUND, tr.bound));
    // the exact field: level 0, also for shading
    hit.lod = 0.0;
    return hit;
}

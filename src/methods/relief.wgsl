// Relief mapping (Policarpo, Oliveira & Comba 2005): the shared linear search in
// `linear_steps` fixed steps, then `binary_steps` bisections between the last sample above the
// surface and the first one below it.
//
// depth_bias (Policarpo's listing, Tatarchuk 2006 fig. 2b): the parallax vector is scaled by
// 1 - (1 - N.V)^8, shortening the search toward the horizon: it flattens the surface at grazing
// angles in exchange for fewer artefacts.
#define_import_path pomkit::methods::relief

#import pomkit::march::{Ray, Hit, Segment, planar_hit, view_search, segment_h}
#import pomkit::height::height_at
#import pomkit::cost::chained

fn relief_depth_bias(ndotv: f32) -> f32 {
    var db = 1.0 - clamp(ndotv, 0.0, 1.0);
    db = db * db;
    db = db * db;
    return 1.0 - db * db;
}

fn march(r: Ray) -> Hit {
    var dsdh = r.dsdh;
    if (params.depth_bias > 0.5) {
        dsdh = dsdh * relief_depth_bias(r.ndotv);
    }
    let span = r.top - r.floor;
    let g = Segment(r.s, dsdh * span, r.top, -span);
    let b = view_search(g, params.linear_steps, r.lod);
    var steps = b.steps;
    var hi = segment_h(g, b.t_prev); // ray height above the surface
    var lo = segment_h(g, b.t_cur);  // ray height at or below the surface
    if (b.d_cur <= 0.0 && hi > lo) {
        let nb = i32(params.binary_steps);
        for (var i = 0; i < nb; i = i + 1) {
            let mid = 0.5 * (hi + lo);
            // each midpoint follows from the last verdict
            chained();
            let d = mid - height_at(r.s + dsdh * (r.top - mid), r.lod);
            steps = steps + 1.0;
            if (d <= 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    return planar_hit(r, r.s + dsdh * (r.top - lo), lo, steps, 0u);
}

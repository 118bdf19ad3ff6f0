// relief.wgsl: relief mapping (Policarpo, Oliveira & Comba 2005): the linear search of pom.wgsl
// with `linear_steps` fixed steps, then `binary_steps` bisections between the last sample above
// the surface and the first one below it.
//
// depth_bias (Policarpo's listing, Tatarchuk 2006 fig. 2b): the parallax vector is scaled by
// 1 - (1 - N.V)^8, shortening the search toward the horizon: it flattens the surface at grazing
// angles in exchange for fewer artefacts.

fn relief_depth_bias(ndotv: f32) -> f32 {
    var db = 1.0 - clamp(ndotv, 0.0, 1.0);
    db = db * db;
    db = db * db;
    return 1.0 - db * db;
}

fn relief_march(s0: vec2<f32>, dsdh_in: vec2<f32>, ndotv: f32, lod: f32) -> Hit {
    var dsdh = dsdh_in;
    if (G.params2.y > 0.5) {
        dsdh = dsdh * relief_depth_bias(ndotv);
    }
    let b = linear_search(s0, dsdh, G.march.y, lod);
    var hit: Hit;
    hit.steps = b.steps;
    var hi = b.h_prev; // ray height above the surface
    var lo = b.h_cur;  // ray height at or below the surface
    if (b.d_cur <= 0.0 && b.h_prev > b.h_cur) {
        let nb = i32(G.params2.x);
        for (var i = 0; i < nb; i = i + 1) {
            let mid = 0.5 * (hi + lo);
            let d = mid - height_at(s0 + dsdh * (1.0 - mid), lod);
            hit.steps = hit.steps + 1.0;
            if (d <= 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    hit.h = lo;
    hit.s = s0 + dsdh * (1.0 - lo);
    return hit;
}

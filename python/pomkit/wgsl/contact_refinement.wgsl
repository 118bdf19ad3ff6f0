// QGIS's contact-refinement parallax mapping (qgis/QGIS #65955, April 2026: metalrough.frag's
// applyContactRefinementParallaxCoordsAndHeight, after Andrea Riccardi's description), in
// pomkit's interface: a coarse linear search of `steps` taps, 1/(steps + 1) of the shell apart
// (the entry itself is not tapped: the search starts as if the field stood at the top there),
// then, from the last tap above the field, the one coarse interval walked again in steps of
// 1/(steps left) of it, until a tap lies at or below the field; the hit is where the line
// through the last tap above and the first below meets the ray, as POM's refinement. The
// refinement is finer the earlier the coarse search stops. Where no coarse tap lies below, the
// floor (h = 0) is tapped and closes the bracket. One mip level for every tap (the footprint's,
// with mip_filtering).
//
// QGIS slides the ray along V.xy (2 - N.V), not the exact V.xy / N.V: offset limiting, which
// keeps the slide within two depths at grazing angles (params.offset_limiting = 1). Not rebuilt:
// QGIS's zero level at mid-grey (pomkit's h = 1 is the mesh's surface, `heightMapBase` = 1).
// Parameters: params.steps (QGIS: 15), params.offset_limiting.
#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at
#import pomkit::cost::chained

fn march(r: Ray) -> Hit {
    var span = r.dsdh;
    if (params.offset_limiting > 0.5) {
        let c = clamp(r.ndotv, 0.0, 1.0);
        span = r.dsdh * c * (2.0 - c);
    }
    let n = max(round(params.steps), 1.0);
    var left = n;
    var dt = 1.0 / (n + 1.0);
    // the last tap above the field (t: the shell's depth descended; d: ray height minus field)
    var t_above = 0.0;
    var d_above = 0.0;
    var t_below = 1.0;
    var d_below = 0.0;
    var found = false;
    var refine = false;
    var steps = 0.0;
    let most = 2 * i32(n) + 1;
    for (var i = 0; i < most && left > 0.0; i = i + 1) {
        let t = t_above + dt;
        let d = (1.0 - t) - height_at(r.s + span * t, r.lod);
        steps = steps + 1.0;
        if (d <= 0.0) {
            t_below = t;
            d_below = d;
            found = true;
            if (refine) {
                break;
            }
            // the refinement's taps follow from where the coarse search stopped
            chained();
            refine = true;
            dt = dt / left;
            continue;
        }
        t_above = t;
        d_above = d;
        left = left - 1.0;
    }
    if (!found) {
        d_below = -height_at(r.s + span, r.lod);
        steps = steps + 1.0;
    }
    var t_hit = t_below;
    let denom = d_above - d_below;
    if (denom > 1e-12) {
        t_hit = t_above + (t_below - t_above) * (d_above / denom);
    }
    return planar_hit(r, r.s + span * t_hit, clamp(1.0 - t_hit, 0.0, 1.0), steps, 0u);
}

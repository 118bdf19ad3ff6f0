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
//
// Windowed (pk.Custom(windowed=True)): the search spans the Ray's window, from r.s at r.top
// down to r.floor, so that pk.Hybrid can take it as its fine method. In a window (WINDOW) the
// window's top is tapped (alone the entry is taken to lie on the field), the coarse taps lie on
// the shell's lattice (march.wgsl, `window_lattice`, for steps + 1 intervals) and then the floor,
// and the interval that holds the crossing is walked in as many taps as the search alone would
// have left at its height. With offset limiting the search leaves the view ray, so that a
// window that holds the field along the ray need not hold it along the search (docs/hybrid.md).
#import pomkit::march::{Ray, Hit, planar_hit, window_lattice}
#import pomkit::height::height_at
#import pomkit::cost::chained

fn march(r: Ray) -> Hit {
    // the window's depth in heights (1 alone) and its slide in texture units
    let depth = r.top - r.floor;
    // the slide per height: the view ray's, or offset-limited
    var slide = r.dsdh;
    if (params.offset_limiting > 0.5) {
        let c = clamp(r.ndotv, 0.0, 1.0);
        slide = r.dsdh * c * (2.0 - c);
    }
    // from the view ray's entry into the window (r.s at r.top): offset limiting bends the
    // search off the view ray from there, by less the narrower the window
    let span = slide * depth;
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
    var most = 2 * i32(n) + 1;
#ifdef WINDOW
    // the window's top is tapped: the field lies below it, where alone the search takes it to
    // stand at the top of the shell, the base surface
    d_above = r.top - height_at(r.s, r.lod);
    steps = steps + 1.0;
    // the window's top, its lattice taps and its floor, then the refinement
    most = most + 2;
    let lattice = window_lattice(r.top, depth, n + 1.0);
    var k = lattice.y;
#endif
    for (var i = 0; i < most && left > 0.0; i = i + 1) {
        var t = t_above + dt;
#ifdef WINDOW
        if (!refine) {
            t = min((r.top - (1.0 - k * lattice.x)) / max(depth, 1e-6), 1.0);
            k = k + 1.0;
        }
#endif
        let d = (r.top - depth * t) - height_at(r.s + span * t, r.lod);
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
#ifdef WINDOW
            // as many refinement taps as the search alone has left at this height (the taps of
            // the whole shell above it spent), over this lattice interval
            let h_above = r.top - depth * t_above;
            left = max(n - floor((1.0 - h_above) * (n + 1.0) + 1e-4), 1.0);
            dt = (t - t_above) / left;
#else
            dt = dt / left;
#endif
            continue;
        }
        t_above = t;
        d_above = d;
        left = left - 1.0;
#ifdef WINDOW
        if (t >= 1.0) {
            // the floor lies above the field: nothing below in this window
            break;
        }
#endif
    }
    if (!found) {
        d_below = r.floor - height_at(r.s + span, r.lod);
        steps = steps + 1.0;
    }
    var t_hit = t_below;
    let denom = d_above - d_below;
    if (denom > 1e-12) {
        t_hit = t_above + (t_below - t_above) * (d_above / denom);
    }
    return planar_hit(r, r.s + span * t_hit, clamp(r.top - depth * t_hit, 0.0, 1.0), steps, 0u);
}

// PlayCanvas v2.22's marched parallax (StandardMaterial.parallaxMode = PARALLAX_OCCLUSION),
// rebuilt in pomkit's interface from the engine's public pull-request descriptions, not from its
// code: playcanvas/engine #9213 (a linear search for the first step below the field, then five
// halvings that resample inside the bracketing step; the step count follows the distance
// marched, capped at parallaxSamples = 16, and is not rounded), #9219 (one mip level for every
// tap, chosen before the loop from the footprint; the count is one step per couple of texels of
// that level; the offset fades out as the march covers barely a texel, and the march is skipped
// where the fade is zero) and #9223 (the march capped at parallaxMaxSlope = 5 times the relief's
// depth along the surface). The height reads as depth below the surface (heightMapBase = 1,
// pomkit's convention). Not rebuilt: its soft self-shadows (parallaxShadowSamples). The fade's
// exact ramp is not in those descriptions: here from 0.5 to 1.5 texels (params.fade_lo, fade_hi).
// Parameters: params.samples, params.texels_per_step, params.max_slope, params.fade_lo, params.fade_hi.
#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at
#import pomkit::object::G

fn march(r: Ray) -> Hit {
    let lod = r.lod;
    let c = clamp(r.ndotv, 1e-4, 1.0);
    let tan_view = sqrt(max(1.0 - c * c, 0.0)) / c;
    // the slide along the surface, at most max_slope times the depth
    let span = r.dsdh * min(1.0, params.max_slope / max(tan_view, 1e-6));
    let texels = length(span * G.map_size) / exp2(lod);
    let fade = smoothstep(params.fade_lo, params.fade_hi, texels);
    if (fade <= 0.0) {
        return planar_hit(r, r.s, 1.0, 0.0, 0u);
    }
    let n = clamp(texels / params.texels_per_step, 1.0, params.samples);
    let dt = 1.0 / n;
    // d: the ray's height (1 - t) above the field at s + span t
    var t = 0.0;
    var t_prev = 0.0;
    var d = 1.0 - height_at(r.s, lod);
    var steps = 1.0;
    loop {
        if (d <= 0.0 || t >= 1.0) {
            break;
        }
        t_prev = t;
        t = min(t + dt, 1.0);
        d = (1.0 - t) - height_at(r.s + span * t, lod);
        steps = steps + 1.0;
    }
    var lo = t_prev;
    var hi = t;
    if (t > 0.0) {
        for (var i = 0; i < 5; i = i + 1) {
            let m = 0.5 * (lo + hi);
            let dm = (1.0 - m) - height_at(r.s + span * m, lod);
            steps = steps + 1.0;
            if (dm > 0.0) {
                lo = m;
            } else {
                hi = m;
            }
        }
    }
    let th = 0.5 * (lo + hi) * fade;
    return planar_hit(r, r.s + span * th, 1.0 - th, steps, 0u);
}

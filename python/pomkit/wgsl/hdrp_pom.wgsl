// Unity HDRP's pixel displacement (Lit, Displacement Mode: Pixel displacement), in pomkit's
// interface: our own writing after the render pipeline's public sources (the core library's
// PerPixelDisplacement.hlsl and the Lit material's displacement code, Unity-Technologies/
// Graphics). The step count runs linearly in the view angle from params.min_samples head-on
// to params.max_samples at grazing (HDRP's defaults 5 and 15), truncated to a whole number; a
// linear search from one step below the top; then up to three secant iterations (Risser's
// "Faster Relief Mapping Using the Secant Method"), stopping within 0.01 of the field; every tap
// at the footprint's mip level; the offset faded out over the one level above
// params.lod_threshold (5), as HDRP fades it before a mesh LOD switch.
// Parameters: params.min_samples, params.max_samples, params.lod_threshold.
#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at

const HALF_PI: f32 = 1.5707963;

fn march(r: Ray) -> Hit {
    let angle = acos(clamp(r.ndotv, 0.0, 1.0)) / HALF_PI;
    let n = max(floor(mix(params.min_samples, params.max_samples, angle)), 1.0);
    let step = 1.0 / n;
    let off_step = r.dsdh * step;
    var off = off_step;
    var prev_h = height_at(r.s, r.lod);
    var cur_h = height_at(r.s + off, r.lod);
    var ray_h = 1.0 - step;
    var steps = 2.0;
    for (var i = 0; i < i32(n); i = i + 1) {
        if (cur_h > ray_h) {
            break;
        }
        prev_h = cur_h;
        ray_h = ray_h - step;
        off = off + off_step;
        cur_h = height_at(r.s + off, r.lod);
        steps = steps + 1.0;
    }
    // the bracket: the ray above the field at pt0, below it at pt1
    var pt0 = ray_h + step;
    var pt1 = ray_h;
    var d0 = pt0 - prev_h;
    var d1 = pt1 - cur_h;
    var hh = pt1;
    for (var i = 0; i < 3; i = i + 1) {
        let den = d1 - d0;
        if (abs(den) < 1e-12) {
            break;
        }
        hh = (pt0 * d1 - pt1 * d0) / den;
        let d = hh - height_at(r.s + (1.0 - hh) * r.dsdh, r.lod);
        steps = steps + 1.0;
        if (abs(d) <= 0.01) {
            break;
        }
        if (d < 0.0) {
            d1 = d;
            pt1 = hh;
        } else {
            d0 = d;
            pt0 = hh;
        }
    }
    let fade = 1.0 - clamp(r.lod - params.lod_threshold, 0.0, 1.0);
    let t = clamp(1.0 - hh, 0.0, 1.0) * fade;
    return planar_hit(r, r.s + t * r.dsdh, 1.0 - t, steps, 0u);
}

// shadows.wgsl: self-shadowing of the height field toward a light, for the per-pixel methods.
//   hard: the horizon test. `shadow_steps` samples along the light ray from the displaced point
//         up to the top of the shell; shadowed if any height sample lies above the ray.
//   soft: Tatarchuk 2006's penumbra estimate. The same samples, each giving the fraction of the
//         light's disk hidden behind a blocker edge at that sample: the blocker's height above
//         the ray, perpendicular to it, divided by the penumbra width at the sample's distance
//         (distance * tan(angular radius)); each sample is so weighted by its distance and the
//         maximum occlusion wins. With a zero angular diameter it is the hard test.
// Both run only where N.L > 0 (the caller checks).

struct ShadowResult {
    visibility: f32,
    steps: f32,
}

// Fraction of a disk of unit radius hidden behind a straight edge at signed offset x
// (x = -1: nothing hidden, x = 1: all hidden).
fn disk_occlusion(x: f32) -> f32 {
    let c = clamp(x, -1.0, 1.0);
    return 1.0 - (acos(c) - c * sqrt(max(1.0 - c * c, 0.0))) / PI;
}

fn shadow_march(f: Frame, s: vec2<f32>, h: f32, ls: LightSample, lod: f32) -> ShadowResult {
    var r: ShadowResult;
    r.visibility = 1.0;
    r.steps = 0.0;
    let l_ts = to_texture_space(f, ls.dir);
    if (l_ts.z <= 1e-7) {
        // light at or below the base tangent plane: the tiled height field blocks it
        r.visibility = 0.0;
        return r;
    }
    if (h >= 1.0) {
        return r;
    }
    let n = max(G.march.z, 1.0);
    let dsdh = l_ts.xy / l_ts.z;
    let depth = G.tex.w;
    let cos_elev = sqrt(max(1.0 - dot(ls.dir, f.n) * dot(ls.dir, f.n), 0.0));
    // small bias so that the surface does not shadow itself through filtering noise
    let bias = 1e-4;
    var occl = 0.0;
    let ni = i32(n);
    for (var i = 1; i <= ni; i = i + 1) {
        let h_ray = h + (1.0 - h) * f32(i) / n;
        let hs = height_at(s + dsdh * (h_ray - h), lod);
        r.steps = r.steps + 1.0;
        let above = hs - h_ray - bias;
        if (SHADOWS == 1u || ls.tan_radius <= 1e-6) {
            if (above > 0.0) {
                occl = 1.0;
                break;
            }
        } else {
            // world distance along the light ray to the sample, and the blocker's offset
            // perpendicular to the ray
            let dist = (h_ray - h) / l_ts.z;
            let offset = above * depth * cos_elev;
            occl = max(occl, disk_occlusion(offset / max(dist * ls.tan_radius, 1e-12)));
            if (occl >= 1.0) {
                break;
            }
        }
    }
    r.visibility = 1.0 - occl;
    return r;
}

// pom.wgsl: the view-ray search against the height field, shared by the per-pixel methods.
// A ray starts on the base surface (h = 1) at s0 and descends with `dsdh` texture units per unit
// of height; it reaches the floor (h = 0) at s0 + dsdh.

struct Hit {
    s: vec2<f32>,   // texture coordinate of the hit (tiled units)
    h: f32,         // height of the hit in [0, 1]
    steps: f32,     // height-map samples (or max-mip fetches) taken
    flags: u32,
}

struct Bracket {
    // the last sample above the surface and the first one below it
    h_prev: f32,    // ray height at the previous sample
    d_prev: f32,    // ray height minus surface height there (> 0)
    h_cur: f32,
    d_cur: f32,     // <= 0 when the bracket holds an intersection
    steps: f32,
}

// POM's sample count: n = n_max + (N.V)(n_min - n_max), i.e. n_max at grazing angles and
// n_min head-on. Tatarchuk 2006 prints eq. 1 with the operands swapped, but the text ("we
// increase the sampling rate along the steep viewing angles") and Figure 4 need this form.
fn pom_sample_count(ndotv: f32) -> f32 {
    let n_min = G.march.x;
    let n_max = G.march.y;
    if (G.extra.x < 0.5) {
        return n_max; // fixed-count profile (Brawley & Tatarchuk 2004)
    }
    return max(round(n_max + clamp(ndotv, 0.0, 1.0) * (n_min - n_max)), 1.0);
}

// Linear search from h = 1 to h = 0 in n equal height steps with an early out at the first
// sample at or below the surface. The sample at the start point (h = 1) is taken too, so a
// surface at the base level is hit where the ray enters.
fn linear_search(s0: vec2<f32>, dsdh: vec2<f32>, n: f32, lod: f32) -> Bracket {
    var b: Bracket;
    let dh = 1.0 / n;
    var h_ray = 1.0;
    var d = h_ray - height_at(s0, lod);
    b.steps = 1.0;
    b.h_prev = h_ray;
    b.d_prev = d;
    b.h_cur = h_ray;
    b.d_cur = d;
    if (d <= 0.0) {
        return b;
    }
    let ni = i32(n);
    for (var i = 1; i <= ni; i = i + 1) {
        // computed from i, not accumulated, so that the last sample is exactly at h = 0
        let h_next = 1.0 - f32(i) * dh;
        let d_next = h_next - height_at(s0 + dsdh * (1.0 - h_next), lod);
        b.steps = b.steps + 1.0;
        b.h_prev = h_ray;
        b.d_prev = d;
        b.h_cur = h_next;
        b.d_cur = d_next;
        if (d_next <= 0.0) {
            return b;
        }
        h_ray = h_next;
        d = d_next;
    }
    return b;
}

// POM's refinement: intersect the ray with the piecewise-linear height profile between the
// last two samples (a line-line intersection at full float precision).
fn refine_linear(s0: vec2<f32>, dsdh: vec2<f32>, b: Bracket) -> Hit {
    var hit: Hit;
    hit.steps = b.steps;
    var h = b.h_cur;
    let denom = b.d_prev - b.d_cur;
    if (b.d_cur <= 0.0 && denom > 1e-12) {
        let t = b.d_prev / denom;
        h = b.h_prev + t * (b.h_cur - b.h_prev);
    }
    h = clamp(h, 0.0, 1.0);
    hit.h = h;
    hit.s = s0 + dsdh * (1.0 - h);
    return hit;
}

fn pom_march(s0: vec2<f32>, dsdh: vec2<f32>, ndotv: f32, lod: f32) -> Hit {
    let n = pom_sample_count(ndotv);
    let b = linear_search(s0, dsdh, n, lod);
    return refine_linear(s0, dsdh, b);
}

// Steep parallax mapping (McGuire & McGuire 2005): the same fixed-step search, stopping at the
// first sample below the surface, with no refinement: its stair-steps are the baseline.
fn steep_march(s0: vec2<f32>, dsdh: vec2<f32>, lod: f32) -> Hit {
    let b = linear_search(s0, dsdh, G.march.y, lod);
    var hit: Hit;
    hit.steps = b.steps;
    hit.h = b.h_cur;
    hit.s = s0 + dsdh * (1.0 - b.h_cur);
    return hit;
}

// Parallax mapping (Kaneko 2001): one sample, s += (scale * (1 - h) + bias) * P. P is the exact
// parallax vector per unit of height (exact for a constant height with scale 1, bias 0). With
// offset limiting (Welsh 2004) P is not divided by V.z: the offset is multiplied by N.V, which
// bounds it by the height difference at grazing angles.
fn parallax_offset(s0: vec2<f32>, dsdh: vec2<f32>, ndotv: f32, lod: f32) -> Hit {
    let h0 = height_at(s0, lod);
    var d = G.params.x * (1.0 - h0) + G.params.y;
    var p = dsdh;
    if (G.params.z > 0.5) {
        p = dsdh * clamp(ndotv, 0.0, 1.0);
    }
    var hit: Hit;
    hit.steps = 1.0;
    hit.h = clamp(1.0 - d, 0.0, 1.0);
    hit.s = s0 + p * d;
    return hit;
}

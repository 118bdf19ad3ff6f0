// horizon.wgsl: horizon-based shadows and ambient occlusion from the max-mip pyramid
// (Dachsbacher & Tatarchuk 2007). Toward a direction, k = 0..K-1 samples at 2^k texels read mip
// level k of the max pyramid: the highest point of a 2^k-texel footprint at that distance, so
// small distant detail merges into its neighbourhood while near detail is read at full
// resolution. The horizon is the largest elevation angle seen from the point.
#define_import_path pomkit::horizon

#import pomkit::view::PI
#import pomkit::object::G
#import pomkit::basis::{Basis, to_texture_space}
#import pomkit::height::max_at
#import pomkit::lights::LightSample
#import pomkit::shadows::{ShadowResult, disk_occlusion}

// tan of the horizon's elevation above the base tangent plane, along texture-space direction
// `dir` (unit, in texel units), from the point (s, h).
fn horizon_tan(f: Basis, s: vec2<f32>, h: f32, dir: vec2<f32>) -> f32 {
    let k_max = min(i32(G.horizon_samples), i32(G.top_max_level) + 1);
    // world length of one texel step along dir
    let texel_world = length(vec2<f32>(dir.x * f.scale.x / G.map_size.x, dir.y * f.scale.y / G.map_size.y)) / G.tiling;
    var best = -1e30;
    let x0 = s.x * G.map_size.x - 0.5;
    let y0 = s.y * G.map_size.y - 0.5;
    for (var k = 0; k < k_max; k = k + 1) {
        let dist = f32(1 << u32(k));
        let p = vec2<f32>(x0, y0) + dir * dist;
        let size = dist;
        let m = max_at(vec2<i32>(floor(p / size)), k);
        let t = (m - h) * G.depth / (dist * texel_world);
        best = max(best, t);
    }
    return best;
}

fn horizon_shadow(f: Basis, s: vec2<f32>, h: f32, ls: LightSample) -> ShadowResult {
    var r: ShadowResult;
    r.steps = G.horizon_samples;
    let l_ts = to_texture_space(f, ls.dir);
    let lxy = vec2<f32>(l_ts.x * G.map_size.x, l_ts.y * G.map_size.y);
    let ln = length(lxy);
    let elev = asin(clamp(dot(ls.dir, f.n), -1.0, 1.0));
    if (ln < 1e-9) {
        r.visibility = select(0.0, 1.0, elev > 0.0);
        return r;
    }
    let hz = atan(horizon_tan(f, s, h, lxy / ln));
    let radius = atan(ls.tan_radius);
    if (radius <= 1e-6) {
        r.visibility = select(0.0, 1.0, elev > hz);
    } else {
        r.visibility = 1.0 - disk_occlusion((hz - elev) / radius);
    }
    return r;
}

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation that hides the directions'
// regular structure.
fn ign(px: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(px, vec2<f32>(0.06711056, 0.00583715))));
}

// Ambient occlusion: the cosine-weighted visible fraction of the hemisphere over `n` directions;
// in a slice whose horizon rises alpha above the tangent plane the visible fraction is cos^2(alpha).
fn horizon_ao(f: Basis, s: vec2<f32>, h: f32, px: vec2<f32>) -> vec2<f32> {
    let n = i32(G.ao_directions);
    if (n <= 0) {
        return vec2<f32>(1.0, 0.0);
    }
    let rot = ign(px) * 2.0 * PI / f32(n);
    var acc = 0.0;
    for (var i = 0; i < n; i = i + 1) {
        let a = rot + f32(i) * 2.0 * PI / f32(n);
        let t = max(horizon_tan(f, s, h, vec2<f32>(cos(a), sin(a))), 0.0);
        acc = acc + 1.0 / (1.0 + t * t);
    }
    return vec2<f32>(acc / f32(n), f32(n) * G.horizon_samples);
}

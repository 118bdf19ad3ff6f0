// shadows.wgsl: self-shadowing of the height field toward a light, for the per-pixel methods.
//   hard: the horizon test. `shadow_steps` samples along the light ray from the displaced point
//         up to the top of the shell; shadowed if any height sample lies above the ray.
//   soft: Tatarchuk 2006's penumbra estimate. The same samples, each giving the fraction of the
//         light's disk hidden behind a blocker edge at that sample: the blocker's height above
//         the ray, perpendicular to it, divided by the penumbra width at the sample's distance
//         (distance * tan(angular radius)); each sample is so weighted by its distance and the
//         maximum occlusion wins. With a zero angular diameter it is the hard test.
//   exact: the max-mip traversal along the light ray (maxmip.wgsl); visible if it leaves the shell.
//   ("horizon" lives in horizon.wgsl.) All run only where N.L > 0 (the caller checks).
//
// Shader defs: one of SHADOWS_HARD, _SOFT, _HORIZON, _EXACT (`Shadows::shader_def`).
#define_import_path pomkit::shadows

#import pomkit::view::{V, shadow_tex, shadow_samp, PI}
#import pomkit::object::G
#import pomkit::basis::{Basis, to_texture_space}
#import pomkit::height::{height_at, height_exact_level}
#import pomkit::cost::fetched
#import pomkit::lights::LightSample
#import pomkit::maxmip::{maxmip_traverse, positive_start}
#import pomkit::object::dir_to_object

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

fn shadow_march(f: Basis, s: vec2<f32>, h_march: f32, ls: LightSample, lod: f32) -> ShadowResult {
    var r: ShadowResult;
    r.visibility = 1.0;
    r.steps = 0.0;
    let l_ts = to_texture_space(f, ls.dir);
    if (l_ts.z <= 1e-7) {
        // light at or below the base tangent plane: the tiled height field blocks it
        r.visibility = 0.0;
        return r;
    }
    // The light ray starts on the height field at s, not at the march's h: an approximate
    // march (POM's secant, a steep stair-step) can stop below the surface, and every sample
    // near the start then lies above the ray: a false shadow line along each slope and edge.
    let h = max(h_march, height_at(s, lod));
    if (h >= 1.0) {
        return r;
    }
    let n = max(G.shadow_steps, 1.0);
    let dsdh = l_ts.xy / l_ts.z;
    let depth = G.depth;
    let cos_elev = sqrt(max(1.0 - dot(ls.dir, f.n) * dot(ls.dir, f.n), 0.0));
    // small bias so that the surface does not shadow itself through filtering noise
    let bias = 1e-4;
    var occl = 0.0;
    // soft: the largest blocker offset over the penumbra width; disk_occlusion is increasing, so
    // the largest occlusion is that of the largest ratio, evaluated once after the loop (its
    // acos and sqrt per sample cost more than the sample on a SIMD rasteriser)
    var x_max = -1e30;
    var soft = false;
    let ni = i32(n);
    for (var i = 1; i <= ni; i = i + 1) {
        let h_ray = h + (1.0 - h) * f32(i) / n;
        let hs = height_at(s + dsdh * (h_ray - h), lod);
        r.steps = r.steps + 1.0;
        let above = hs - h_ray - bias;
#ifdef SHADOWS_HARD
        let hard = true;
#else
        let hard = ls.tan_radius <= 1e-6;
#endif
        if (hard) {
            if (above > 0.0) {
                occl = 1.0;
                break;
            }
        } else {
            // world distance along the light ray to the sample, and the blocker's offset
            // perpendicular to the ray
            let dist = (h_ray - h) / l_ts.z;
            let offset = above * depth * cos_elev;
            x_max = max(x_max, offset / max(dist * ls.tan_radius, 1e-12));
            soft = true;
            if (x_max >= 1.0) {
                break;
            }
        }
    }
    if (soft) {
        occl = max(occl, disk_occlusion(x_max));
    }
    r.visibility = 1.0 - occl;
    return r;
}

// Tessellated: a shadow map of the displaced mesh itself, rendered from the first directional
// light (orthographic, fitted to the mesh's bounding sphere). 3x3 percentage-closer filtering
// of hardware 2x2 comparisons; the lookup point is offset along the surface normal by 1.5
// shadow-map texels to avoid acne. Its own error: shadow boundaries are placed to within about
// one and a half shadow-map texels (V.shadow_texel world units) and penumbrae of area lights are not
// modelled (the PCF kernel is a fixed ~3 texels wide).
fn shadow_map_visibility(light: u32, p: vec3<f32>, n: vec3<f32>, bias: f32) -> f32 {
    if (i32(V.shadow_light) != i32(light)) {
        return 1.0;
    }
    let q = V.shadow_vp * vec4<f32>(p + n * (1.5 * V.shadow_texel), 1.0);
    let ndc = q.xyz / q.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    let texel = 1.0 / V.shadow_size;
    var sum = 0.0;
    for (var dy = -1; dy <= 1; dy = dy + 1) {
        for (var dx = -1; dx <= 1; dx = dx + 1) {
            sum = sum + textureSampleCompareLevel(shadow_tex, shadow_samp, uv + vec2<f32>(f32(dx), f32(dy)) * texel, ndc.z - bias);
        }
    }
    return sum / 9.0;
}

// Exact shadows: the same traversal along the light ray; visible if it leaves the shell.
// The light ray starts EXACT_SHADOW_BIAS above the hit (the hit's own patch must not block it)
// and leaves the shell EXACT_SHADOW_BIAS below its top: a blocker must rise more than the bias
// above the ray. On the bilinear field this misses no blocker taller than 1e-6 of the shell.
// The bias only has to cover float32 rounding at the start, which is small since the walk keeps
// its start as a whole cell and an offset (maxmip.wgsl's CellPoint). Under a grazing light (the
// gravel photograph at 70°, a 19° light), FLIP from render_exact: 1e-4: 0.0072; 3e-5: 0.0040;
// 1e-6: 0.0009. (With the start as one f32 several hundred cells out, 1e-5 let rounding shadow
// a cobblestone's own slope.)
const EXACT_SHADOW_BIAS: f32 = 1e-6;
// One exact ray from the surface at (s, h_march) along the object-space direction `dir`:
// visibility 1 if it leaves the shell, 0 if the field blocks it (or it points below the base
// plane, where the tiled field continues).
fn exact_ray(f: Basis, s: vec2<f32>, h_march: f32, dir: vec3<f32>) -> ShadowResult {
    var r: ShadowResult;
    let l_ts = to_texture_space(f, dir);
    if (l_ts.z <= 1e-7) {
        r.visibility = 0.0;
        r.steps = 0.0;
        return r;
    }
    let dsdh = l_ts.xy / l_ts.z;
    // start a hair above the surface at s (the exact field: an approximate march may stop below
    // it), so that the hit point does not shadow itself
    fetched(4u, 16u);
    let h0 = max(h_march, height_exact_level(s, 0)) + EXACT_SHADOW_BIAS;
    r.visibility = 1.0;
    r.steps = 0.0;
    // The ray has left the shell once it is within the bias of its top: no height lies above
    // h = 1, so nothing there can block it. (Walked to h = 1 itself, a plateau at exactly 1 met
    // the ray at its end, or at its start for a point on the plateau, and counted as a blocker:
    // every h = 1 plateau rendered black.) The walk stops the same bias short of the top.
    if (h0 >= 1.0 - EXACT_SHADOW_BIAS) {
        return r;
    }
    let d = dsdh * G.map_size;
    let p0 = positive_start(s, d);
    let tr = maxmip_traverse(p0, h0, d.x, d.y, 1.0, (1.0 - EXACT_SHADOW_BIAS) - h0, G.max_iterations);
    r.visibility = select(1.0, 0.0, tr.hit);
    r.steps = tr.iters;
    return r;
}

// ---- the reference's direction sets (src/oracle/mod.rs, src/oracle/image.rs; docs/conventions.md,
// "The reference shading"): 64 points of a stratified 8 x 8 grid on the unit disk (Shirley and
// Chiu's concentric map), and a pixel's samples sharing them ----

const REFERENCE_DIRECTIONS: u32 = 64u;

fn stratified_disk(i: u32) -> vec2<f32> {
    let a = 2.0 * (f32(i / 8u) + 0.5) / 8.0 - 1.0;
    let b = 2.0 * (f32(i % 8u) + 0.5) / 8.0 - 1.0;
    var r = b;
    var phi = 0.5 * PI - 0.25 * PI * (a / b);
    if (abs(a) > abs(b)) {
        r = a;
        phi = 0.25 * PI * (b / a);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// The directions this sample traces of a set of 64: (first, stride). Sample q of a pixel's n
// (a supersampled pass knows its k x k grid: V.spp_k; the sample is the fragment's place in it)
// traces the indices d = q mod n, so that a pixel averages every direction once.
fn sample_share(px: vec2<f32>) -> vec2<u32> {
    let k = u32(max(V.spp_k, 1.0));
    let n = k * k;
    let q = (u32(px.y) % k) * k + (u32(px.x) % k);
    if (n >= REFERENCE_DIRECTIONS) {
        return vec2<u32>(q % REFERENCE_DIRECTIONS, REFERENCE_DIRECTIONS);
    }
    return vec2<u32>(q, n);
}

// A unit vector's two perpendiculars, chosen as src/oracle/mod.rs chooses them (the disk's axes).
fn perpendiculars(v: vec3<f32>, pick_y: bool) -> mat2x3<f32> {
    var a = vec3<f32>(1.0, 0.0, 0.0);
    if (pick_y) {
        a = vec3<f32>(0.0, 1.0, 0.0);
    }
    let e1 = normalize(cross(v, a));
    return mat2x3<f32>(e1, cross(v, e1));
}

// Exact shadows: the traversal along the light ray; visible if it leaves the shell. A light with
// a disk (a directional light's angular diameter, a sphere light's apparent radius) is the
// fraction of the reference's 64 directions over it that leave the shell, this sample tracing
// its share (`sample_share`).
fn exact_shadow(f: Basis, s: vec2<f32>, h_march: f32, ls: LightSample, px: vec2<f32>) -> ShadowResult {
    if (ls.tan_radius <= 0.0) {
        return exact_ray(f, s, h_march, ls.dir);
    }
    let e = perpendiculars(ls.dir, abs(ls.dir.y) < 0.9);
    let sh = sample_share(px);
    var r: ShadowResult;
    r.steps = 0.0;
    var lit = 0.0;
    var all = 0.0;
    for (var d = sh.x; d < REFERENCE_DIRECTIONS; d = d + sh.y) {
        let o = stratified_disk(d) * ls.tan_radius;
        let one = exact_ray(f, s, h_march, normalize(ls.dir + e[0] * o.x + e[1] * o.y));
        lit = lit + one.visibility;
        all = all + 1.0;
        r.steps = r.steps + one.steps;
    }
    r.visibility = lit / max(all, 1.0);
    return r;
}

// Exact ambient occlusion: the fraction of the reference's 64 cosine-weighted directions about
// the world shading normal `n` (the disk lifted to the hemisphere) that leave the shell, this
// sample tracing its share. (visibility, steps)
fn exact_ao(f: Basis, s: vec2<f32>, h_march: f32, n: vec3<f32>, px: vec2<f32>) -> vec2<f32> {
    let e = perpendiculars(n, !(abs(n.x) < 0.9));
    let sh = sample_share(px);
    var open = 0.0;
    var all = 0.0;
    var steps = 0.0;
    for (var d = sh.x; d < REFERENCE_DIRECTIONS; d = d + sh.y) {
        let o = stratified_disk(d);
        let z = sqrt(max(1.0 - dot(o, o), 0.0));
        let one = exact_ray(f, s, h_march, dir_to_object(normalize(e[0] * o.x + e[1] * o.y + n * z)));
        open = open + one.visibility;
        all = all + 1.0;
        steps = steps + one.steps;
    }
    return vec2<f32>(open / max(all, 1.0), steps);
}

// shading.wgsl: Lambertian shading with the shared light model (docs/conventions.md):
//     L = albedo/pi * sum(E * max(0, N.L) * visibility) + albedo * ambient * ao
// with the visibility from the method's shadow kind and the AO from the horizon estimate.
//
// Shader defs: SHADOWS (0 none, 1 hard, 2 soft, 3 horizon, 4 exact); TESSELLATED (the displaced
// mesh: visibility from the shadow map, no AO).
#define_import_path pomkit::shading

#import pomkit::globals::{G, PI, MAX_LIGHTS}
#import pomkit::frame::Frame
#import pomkit::height::albedo_at
#import pomkit::lights::{LightSample, light_sample}
#import pomkit::shadows::{ShadowResult, shadow_march, exact_shadow, shadow_map_visibility}
#import pomkit::horizon::{horizon_shadow, horizon_ao}

fn light_visibility(f: Frame, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, i: u32, ls: LightSample, lod: f32) -> ShadowResult {
    var r: ShadowResult;
    r.visibility = 1.0;
    r.steps = 0.0;
#ifdef TESSELLATED
    r.visibility = shadow_map_visibility(i, p, n);
#else
#if SHADOWS == 3
    r = horizon_shadow(f, s, h, ls);
#else
#if SHADOWS == 4
    r = exact_shadow(f, s, h, ls);
#else
    r = shadow_march(f, s, h, ls, lod);
#endif
#endif
#endif
    return r;
}

struct Shaded {
    color: vec3<f32>,
    steps: f32,
}

fn shade(f: Frame, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, lod: f32, with_shadows: bool, px: vec2<f32>) -> Shaded {
    var o: Shaded;
    o.steps = 0.0;
    let albedo = albedo_at(s, lod);
    var sum = vec3<f32>(0.0);
    let nl = u32(G.light_count);
    for (var i = 0u; i < min(nl, MAX_LIGHTS); i = i + 1u) {
        let ls = light_sample(i, p);
        let ndl = dot(n, ls.dir);
        if (ndl <= 0.0) {
            continue;
        }
        var vis = 1.0;
#if SHADOWS != 0
        if (with_shadows) {
            let r = light_visibility(f, s, h, p, n, i, ls, lod);
            vis = r.visibility;
            o.steps = o.steps + r.steps;
        }
#endif
        sum = sum + ls.e * ndl * vis;
    }
    var ao = 1.0;
#ifndef TESSELLATED
    if (with_shadows && G.ao_directions > 0.0 && any(G.ambient > vec3<f32>(0.0))) {
        let a = horizon_ao(f, s, h, px);
        ao = a.x;
        o.steps = o.steps + a.y;
    }
#endif
    o.color = albedo / PI * sum + albedo * G.ambient * ao;
    return o;
}

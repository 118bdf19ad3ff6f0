// shading.wgsl: Lambertian shading with the shared light model (docs/conventions.md):
//     L = albedo/pi * sum(E * max(0, N.L) * visibility) + albedo * ambient * ao
// with the visibility from the method's shadow kind and the AO from the horizon estimate, or,
// with exact shadows, both by exact traversals over the reference's direction sets
// (docs/conventions.md, "The reference shading").
//
// Shader defs: one of SHADOWS_NONE, _HARD, _SOFT, _HORIZON, _EXACT; MESH_SURFACE (the rasterised
// mesh is the displaced surface: its hard self-shadows are the shadow map of itself, and it has
// no horizon AO).
#define_import_path pomkit::shading

#import pomkit::view::{V, PI, MAX_LIGHTS}
#import pomkit::object::G
#import pomkit::basis::Basis
#import pomkit::height::albedo_at
#import pomkit::lights::{LightSample, light_sample}
#import pomkit::shadows::{ShadowResult, shadow_march, exact_shadow, exact_ao, shadow_map_visibility}
#import pomkit::horizon::{horizon_shadow, horizon_ao}
#import pomkit::object::dir_to_object
#import pomkit::cost::chained

// The visibility of light i at the hit: the method's self-shadowing (when `self_shadows`), times
// the scene's shadow map where it has one for this light (CAST_SHADOWS; Tessellated's own
// shadows are that map). `p` and `n` are in world space; the self-shadow marches run in the
// object's texture space, so the light's direction goes to object space first.
fn light_visibility(f: Basis, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, i: u32, ls: LightSample, lod: f32, self_shadows: bool, px: vec2<f32>) -> ShadowResult {
    var r: ShadowResult;
    r.visibility = 1.0;
    r.steps = 0.0;
#ifdef MESH_SURFACE
    if (self_shadows) {
#ifdef SHADOWS_EXACT
        // the mesh's exact self-shadows: the traversal from its point of the field
        var lo = ls;
        lo.dir = dir_to_object(ls.dir);
        r = exact_shadow(f, s, h, lo, px);
#else
        r.visibility = shadow_map_visibility(i, p, n, 1e-5);
#endif
    }
#else
#ifndef SHADOWS_NONE
    if (self_shadows) {
        // the light ray starts at the hit the view ray's search read
        chained();
        var lo = ls;
        lo.dir = dir_to_object(ls.dir);
#ifdef SHADOWS_HORIZON
        r = horizon_shadow(f, s, h, lo);
#else
#ifdef SHADOWS_EXACT
        r = exact_shadow(f, s, h, lo, px);
#else
        r = shadow_march(f, s, h, lo, lod);
#endif
#endif
    }
#endif
#ifdef CAST_SHADOWS
    // a marched surface meets its own displaced depth in the map: a larger bias than the mesh's
    r.visibility = r.visibility * shadow_map_visibility(i, p, n, V.shadow_bias);
#endif
#endif
    return r;
}

struct Shaded {
    color: vec3<f32>,
    steps: f32,
}

// `f` is the object-space tangent basis at the hit, `p` the world hit point, `n` the world
// shading normal.
fn shade(f: Basis, s: vec2<f32>, h: f32, p: vec3<f32>, n: vec3<f32>, lod: f32, with_shadows: bool, px: vec2<f32>) -> Shaded {
    var o: Shaded;
    o.steps = 0.0;
    let albedo = albedo_at(s, lod);
    var sum = vec3<f32>(0.0);
    let nl = u32(V.light_count);
    for (var i = 0u; i < min(nl, MAX_LIGHTS); i = i + 1u) {
        let ls = light_sample(i, p);
        let ndl = dot(n, ls.dir);
        if (ndl <= 0.0) {
            continue;
        }
        let r = light_visibility(f, s, h, p, n, i, ls, lod, with_shadows, px);
        o.steps = o.steps + r.steps;
        sum = sum + ls.e * ndl * r.visibility;
    }
    var ao = 1.0;
    if (with_shadows && G.ao_directions > 0.0 && any(V.ambient > vec3<f32>(0.0))) {
#ifdef SHADOWS_EXACT
        // exact shadows come with the reference's exact AO (64 cosine-weighted directions)
        let a = exact_ao(f, s, h, n, px);
#else
#ifdef MESH_SURFACE
        let a = vec2<f32>(1.0, 0.0);
#else
        let a = horizon_ao(f, s, h, px);
#endif
#endif
        ao = a.x;
        o.steps = o.steps + a.y;
    }
    o.color = albedo / PI * sum + albedo * V.ambient * ao;
    return o;
}

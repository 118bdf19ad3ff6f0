// surface.wgsl: the mesh pass. It rasterises the base mesh (or, for Tessellated, the displaced
// mesh), builds the view ray in the fragment's tangent frame, calls the method's
// `method::march` (src/methods/*.wgsl or a user's pk.Custom; the composer imports it as
// `method`), and shades the hit. One pipeline per method and shader-def combination.
//
// Shader defs (set by the method's Rust spec, src/methods/):
//   MARCH        a per-pixel method: `method` is imported and marched
//   LOD_BLEND    Tatarchuk 2006's in-shader LOD: full march at levels <= lod_threshold - 1,
//                bump mapping above lod_threshold, blended by the fractional level (POM)
//   FLAT, BUMP   no march: the base normal, or the height field's normal, at the rasterised uv
//   TESSELLATED  the displaced mesh itself, shaded with the height field's level-0 normal
//   DISPLACED_DEPTH  the marched hit's depth is written as the fragment's (src/shaders.rs)
//   VERTEX_EXTRA  the method's own vertex attribute (NCS, CurvedRelief), passed to its march
//   SHADOWS, FILTERING  see shading.wgsl and height.wgsl

#import pomkit::globals::{G, V}
#import pomkit::vertex::{VertexIn, VertexOut, pass_through}
#import pomkit::aov::{FsOut, write_aovs}
#import pomkit::frame::{TangentFrame, make_frame, to_texture_space}
#import pomkit::height::{height_normal, height_lod, compute_lod}
#import pomkit::march::{Ray, Hit}
#import pomkit::shading::shade
#import pomkit::cost::count_fragment
#import pomkit::object::{to_world, to_clip, normal_to_world, stretch, clip_depth, shadow_depth, shadow_light_object}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return pass_through(v, to_clip(v.position, V.view_proj));
}

// The shadow-map pass: the scene seen from the shadowing light (orthographic). Meshes that are
// their own surface (Flat, Bump, Tessellated) write their rasterised depth; the per-pixel methods
// march each fragment along the light's direction (fs_shadow) and write the hit's depth, so that
// every object casts with its displaced surface.
@vertex
fn vs_shadow(v: VertexIn) -> VertexOut {
    return pass_through(v, to_clip(v.position, V.shadow_vp));
}

// The ray of a fragment along `view` (object space, unit) in its tangent frame.
fn make_ray(in: VertexOut, f: TangentFrame, s0: vec2<f32>, lod: f32, view: vec3<f32>, uv: vec2<f32>) -> Ray {
    var r: Ray;
#ifdef VERTEX_EXTRA
    r.extra = in.extra;
#endif
    r.v_ts = to_texture_space(f, view);
    r.s = s0;
    r.dsdh = r.v_ts.xy / max(-r.v_ts.z, 1e-6);
    r.ndotv = -dot(view, f.n);
    r.lod = height_lod(lod);
    r.uv = uv;
    r.view = view;
    r.f = f;
    return r;
}

#ifdef MARCH
@fragment
fn fs_shadow(in: VertexOut) -> @builtin(frag_depth) f32 {
    let f = make_frame(in.normal, in.tangent, in.uv_scale);
    let s0 = in.uv * G.tiling;
    let lod = compute_lod(s0);
    let view = shadow_light_object();
    if (dot(view, f.n) >= 0.0) {
        // a face the light reaches from behind (open meshes): its base surface casts
        return in.clip.z;
    }
    let hit = method::march(make_ray(in, f, s0, lod, view, in.uv));
    if (hit.exited) {
        discard;
    }
    return shadow_depth(to_world(in.world + view * hit.len));
}
#endif

// 0: full march, 1: bump only; in between, the weight of bump mapping (Tatarchuk 2006's
// listing: the transition ends at the threshold, so a plane receding to the horizon shows no
// seam where it crosses it).
fn lod_bump_weight(lod: f32) -> f32 {
    let thr = G.lod_threshold;
    return clamp(lod - (thr - 1.0), 0.0, 1.0);
}

@fragment
fn fs_main(in: VertexOut) -> FsOut {
    count_fragment(in.clip.xy);
    let f = make_frame(in.normal, in.tangent, in.uv_scale);
    let tiling = G.tiling;
    let s0 = in.uv * tiling;
    // explicit LOD, from derivatives taken here in uniform control flow
    let lod = compute_lod(s0);
    // the mesh, its frame and the march live in object space (`in.world` is the object-space
    // position); distances along the view ray scale to world space by `stretch`
    let to_p = in.world - G.eye_object;
    let base_dist = length(to_p);
    let view = to_p / max(base_dist, 1e-20);
    let px = in.clip.xy;
    let p_base = to_world(in.world);
    let k = stretch(view);
    var frag_depth = in.clip.z;

    var color = vec3<f32>(0.0);
    var steps = 0.0;
    var flags = 0u;
    var s_hit = s0;
    var dist = base_dist * k;

#ifdef FLAT
    color = shade(f, s0, 1.0, p_base, normal_to_world(f.n), lod, false, px).color;
#endif
#ifdef BUMP
    // Blinn 1978: the normal from the height field, uv unchanged
    color = shade(f, s0, 1.0, p_base, normal_to_world(height_normal(f, s0, lod)), lod, false, px).color;
#endif
#ifdef TESSELLATED
    // base frame, height-field normal at the rasterised uv, level 0: this is the true surface
    // (h = 0: the exact shadows start from the field's own height at s0)
    let sh = shade(f, s0, 0.0, p_base, normal_to_world(height_normal(f, s0, 0.0)), lod, true, px);
    color = sh.color;
    steps = sh.steps;
#endif
#ifdef MARCH
    var w_bump = 0.0;
#ifdef LOD_BLEND
    w_bump = lod_bump_weight(lod);
#endif
    var c_march = vec3<f32>(0.0);
    if (w_bump < 1.0) {
        let hit = method::march(make_ray(in, f, s0, lod, view, in.uv));
        if (hit.exited) {
            discard;
        }
        let p = to_world(in.world + view * hit.len);
        let sh = shade(hit.f, hit.s, hit.h, p, normal_to_world(height_normal(hit.f, hit.s, hit.lod)), hit.lod, true, px);
        c_march = sh.color;
        steps = hit.steps + sh.steps;
        flags = hit.flags;
        s_hit = hit.s;
        dist = (base_dist + hit.len) * k;
        frag_depth = clip_depth(p);
    }
    var c_bump = vec3<f32>(0.0);
    if (w_bump > 0.0) {
        c_bump = shade(f, s0, 1.0, p_base, normal_to_world(height_normal(f, s0, lod)), lod, false, px).color;
    }
    color = mix(c_march, c_bump, w_bump);
#endif
    var o = write_aovs(color, u32(steps), flags, s_hit / tiling, dist, lod);
#ifdef DISPLACED_DEPTH
    o.depth = frag_depth;
#endif
    return o;
}

// surface.wgsl: the mesh pass. It rasterises the base mesh (or, for Tessellated, the displaced
// mesh), builds the view ray in the fragment's tangent basis, calls the method's
// `method::march` (src/methods/*.wgsl or a user's pk.Custom; the composer imports it as
// `method`), and shades the hit; or a method without a march shades the rasterised surface. One pipeline per method and shader-def combination.
//
// Shader defs (set by the method's Rust spec, src/methods/):
//   MARCH        a per-pixel method: `method` is imported and marched
//   LOD_BLEND    Tatarchuk 2006's in-shader LOD: full march at levels <= lod_threshold - 1,
//                bump mapping above lod_threshold, blended by the fractional level (POM)
//   SHADE        no march: `method::shade_surface` shades the rasterised surface (the base mesh,
//                or a mesh that is the displaced surface itself)
//   DISPLACED_DEPTH  the marched hit's depth is written as the fragment's (src/shaders.rs)
//   VERTEX_EXTRA  the method's own vertex attribute (NCS, CurvedRelief), passed to its march
//   WINDOW       the vertex attribute is the window of the shell the march searches (Ray's
//                floor and top: a coarse mesh displaced at its vertices, src/methods/hybrid)
//   SHADOWS_*, FILTERING_*  the options by name; see shading.wgsl and height.wgsl
//
// Entry points: vs_main/fs_main (the raster pipeline), vs_visibility/fs_visibility then cs_main
// (the compute pipeline: visibility.wgsl), vs_shadow/fs_shadow (the shadow map).

#import pomkit::view::V
#import pomkit::object::G
#import pomkit::vertex::{VertexIn, VertexOut, pass_through}
#import pomkit::aov::{FsOut, Packed, pack_aovs, write_aovs}
#import pomkit::basis::{Basis, make_basis, to_texture_space}
#import pomkit::height::{height_normal, height_lod, compute_lod, footprint_lod}
#import pomkit::march::{Ray, Hit, does_not_descend}
#import pomkit::shading::shade
#import pomkit::cost::count_fragment
#import pomkit::visibility::{VisibilityOut, visibility_vertex, rasterise, footprint_point, tile_pixel, visibility_tex, store_color, store_geo, store_id, store_cost}
#import pomkit::object::{to_world, to_clip, normal_to_world, stretch, clip_depth, shadow_depth, shadow_light_object}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return pass_through(v, to_clip(v.position, V.view_proj));
}

// The shadow-map pass: the scene seen from the shadowing light (orthographic). Methods without a
// march (SHADE) write their mesh's rasterised depth; the per-pixel methods
// march each fragment along the light's direction (fs_shadow) and write the hit's depth, so that
// every object casts with its displaced surface.
@vertex
fn vs_shadow(v: VertexIn) -> VertexOut {
    return pass_through(v, to_clip(v.position, V.shadow_vp));
}

#ifdef WINDOW
// the share of a window's reach within which its nearest floor holds (src/contract.rs:
// WINDOW_NEAR_SHARE_DIV, a def)
const NEAR_SHARE: f32 = 1.0 / f32(#{WINDOW_NEAR_SHARE_DIV}u);
#endif

// The ray of a fragment along `view` (object space, unit) in its tangent basis.
fn make_ray(in: VertexOut, f: Basis, s0: vec2<f32>, lod: f32, view: vec3<f32>, uv: vec2<f32>) -> Ray {
    var r: Ray;
#ifdef VERTEX_EXTRA
    r.extra = in.extra;
#endif
    r.v_ts = to_texture_space(f, view);
    r.s = s0;
    r.dsdh = r.v_ts.xy / max(-r.v_ts.z, 1e-6);
    if (does_not_descend(r)) {
        // no descent along the ray: the searches fall straight down at the entry (march.wgsl)
        r.dsdh = vec2<f32>(0.0);
    }
    r.ndotv = -dot(view, f.n);
    r.lod = height_lod(lod);
    r.uv = uv;
    r.view = view;
    r.p = in.world;
    r.f = f;
    r.top = 1.0;
    r.floor = 0.0;
    r.lead = 0.0;
#ifdef WINDOW
    // the coarse mesh's window at the fragment (src/methods/hybrid): (nearest floor, top, near
    // floor, reach). The nearest floor holds for a ray whose descent to it stays within
    // NEAR_SHARE * reach of the fragment (s units), the near one within reach.
    let top = in.extra.y;
    let descends = r.v_ts.z < 0.0;
    let slope = select(1e30, length(r.dsdh), descends);
    var near = false;
    var fl = 0.0;
    if (slope * (top - in.extra.z) <= in.extra.w) {
        near = true;
        fl = in.extra.z;
    }
    if (slope * (top - in.extra.x) <= NEAR_SHARE * in.extra.w) {
        near = true;
        fl = in.extra.x;
    }
    if (!descends && in.extra.w > 0.0) {
        // a coarse face seen where the base normal turns away: `surface` draws nothing there;
        // a shadow ray (fs_shadow) takes the surface at the entry
        r.top = top;
        r.floor = top;
    } else if (near || in.extra.w <= 0.0) {
        // the field lies below h = 1: a fragment above it starts where the ray comes down to
        // h = 1 (never a wider window than the method's own; a flat coarse mesh, reach 0, is
        // the base mesh: the method as alone)
        let above = select(0.0, max(top - 1.0, 0.0), descends);
        r.s = s0 + r.dsdh * above;
        r.lead = above / max(-r.v_ts.z, 1e-12);
        r.top = top - above;
        r.floor = max(fl, 0.0);
    } else {
        // a ray that travels farther than either reach: the method's own window [0, 1] along
        // the same ray, from where it passes h = 1 (on a plane the very samples of the method
        // alone; the ray lies above the field until it enters the coarse mesh)
        let back = 1.0 - top;
        r.s = s0 - r.dsdh * back;
        r.lead = -back / max(-r.v_ts.z, 1e-12);
        r.top = 1.0;
        r.floor = 0.0;
    }
#endif
    return r;
}

#ifdef MARCH
@fragment
fn fs_shadow(in: VertexOut) -> @builtin(frag_depth) f32 {
    let f = make_basis(in.normal, in.tangent, in.uv_scale);
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

// What the surface pass puts at a fragment: its targets' texels, or nothing (`hit` false: the
// march left the shell, a silhouette).
struct Surfaced {
    hit: bool,
    aovs: Packed,
    frag_depth: f32,
}

// The surface at fragment `in` whose footprint's mip level is `lod`: the fragment stage's and
// the compute pipeline's one body.
fn surface(in: VertexOut, lod: f32) -> Surfaced {
    var out: Surfaced;
    out.hit = true;
    let f = make_basis(in.normal, in.tangent, in.uv_scale);
    let tiling = G.tiling;
    let s0 = in.uv * tiling;
    // the mesh, its basis and the march live in object space (`in.world` is the object-space
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

#ifdef SHADE
    // the method shades the rasterised surface itself
    let sh = method::shade_surface(f, s0, p_base, lod, px);
    color = sh.color;
    steps = sh.steps;
#endif
#ifdef MARCH
    var w_bump = 0.0;
#ifdef LOD_BLEND
    w_bump = lod_bump_weight(lod);
#endif
    var c_march = vec3<f32>(0.0);
#ifdef WINDOW
    // a coarse face seen where the base normal turns away (past the base mesh's outline, or
    // where a thin part's averaged normals face away from its face): the ray does not enter the
    // shell in the base's basis, so the displaced surface is not there; what lies behind shows
    // (taking the coarse face's entry drew thin wings' parts in front of the surface the oracle
    // hits: Erwin.ac 129 texels uv p95 at 4 texels a vertex, now 4.4-5.7 as Tessellated's fold)
    if (in.extra.w > 0.0 && to_texture_space(f, view).z >= 0.0) {
        out.hit = false;
        return out;
    }
#endif
    if (w_bump < 1.0) {
        let hit = method::march(make_ray(in, f, s0, lod, view, in.uv));
        if (hit.exited) {
            out.hit = false;
            return out;
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
    out.aovs = pack_aovs(color, u32(steps), flags, s_hit / tiling, dist, lod);
    out.frag_depth = frag_depth;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> FsOut {
    count_fragment(in.clip.xy);
    // explicit LOD, from derivatives taken here in uniform control flow
    let lod = compute_lod(footprint_point(in, G.tiling));
    let sf = surface(in, lod);
    if (!sf.hit) {
        discard;
    }
    var o = write_aovs(sf.aovs);
#ifdef DISPLACED_DEPTH
    o.depth = sf.frag_depth;
#endif
    return o;
}

// The compute pipeline (visibility.wgsl): the visibility pass, then the surface per pixel.
@vertex
fn vs_visibility(@builtin(vertex_index) vi: u32) -> VisibilityOut {
    return visibility_vertex(vi);
}

@fragment
fn fs_visibility(in: VisibilityOut) -> @location(0) u32 {
    return in.triangle;
}

@compute @workgroup_size(64, 1, 1)
fn cs_main(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let dims = textureDimensions(visibility_tex);
    let px = tile_pixel(wg.xy, li);
    if (px.x >= dims.x || px.y >= dims.y) {
        return;
    }
    let r = rasterise(px, dims, G.tiling);
    var sf: Surfaced;
    sf.hit = false;
    if (r.covered) {
        sf = surface(r.v, footprint_lod(r.ds_dx, r.ds_dy));
    }
    if (!sf.hit) {
        // the colour target is the one a reader trusts for the hit bit (aovs.rs)
        store_color(px, vec4<u32>(0u));
        return;
    }
    store_color(px, sf.aovs.color);
    store_geo(px, sf.aovs.geo);
    store_id(px, sf.aovs.id);
#ifdef COUNT_FETCHES
    store_cost(px, sf.aovs.cost);
#endif
}

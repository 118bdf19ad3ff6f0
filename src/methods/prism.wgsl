// Prism POM (Dachsbacher & Tatarchuk 2007). The rasteriser draws the front faces of
// each prism extruded from a base triangle; a fragment is where the view ray enters the prism,
// with its (uv, h) interpolated from the corners. The exit is the farthest intersection of the
// ray with the prism's eight boundary triangles; between entry and exit the ray is marched with
// a constant texture gradient (march.wgsl's segment search and POM's refinement). No hit in
// this prism: discard (a neighbouring prism may have it). The hit's depth is written as the
// fragment depth, so that overlapping prisms resolve by the depth buffer. A prism whose highest
// height (under its triangle) lies below the ray's lowest point in it is rejected at once.
//
// The method's own pass (a top-level shader, not a `march` module): its geometry is the prisms
// (geometry::prisms). Outward shells (the paper's set-up) put h = 0 on the base mesh and h = 1 `depth` above it.

#import pomkit::globals::G
#import pomkit::vertex::{VertexIn, VertexOut, pass_through}
#import pomkit::aov::write_aovs
#import pomkit::frame::{Frame, make_frame}
#import pomkit::height::{height_normal, height_lod, compute_lod}
#import pomkit::march::{Segment, linear_search, refine_linear, pom_sample_count}
#import pomkit::maxmip::{maxmip_traverse, positive_start}
#import pomkit::shading::shade
#import pomkit::object::{to_world, normal_to_world, stretch, clip_depth, shadow_depth, shadow_light_object}

struct PrismData {
    top: array<vec4<f32>, 3>,
    bottom: array<vec4<f32>, 3>,
    uv: array<vec4<f32>, 3>,
    info: vec4<f32>,
}

@group(0) @binding(10) var<storage, read> prisms: array<PrismData>;

// A prism corner seen through `clip_from_world` (the camera's or the light's): its entry height
// and its prism (24 vertices per prism).
fn prism_vertex(v: VertexIn, h: f32, index: u32, clip_from_world: mat4x4<f32>) -> VertexOut {
    var o = pass_through(v, clip_from_world * (G.model * vec4<f32>(v.position, 1.0)));
    o.h = h;
    o.prism = index / 24u;
    return o;
}

@vertex
fn vs_prism(v: VertexIn, @location(5) h: f32, @builtin(vertex_index) index: u32) -> VertexOut {
    return prism_vertex(v, h, index, G.view_proj);
}

struct PrismFsOut {
    @location(0) color: vec4<u32>,
    @location(1) geo: vec4<u32>,
    @location(2) id: u32,
    @builtin(frag_depth) depth: f32,
}

// Ray (o + t d) against triangle (a, b, c): (t, barycentrics u, v) or t < 0.
fn ray_tri(o: vec3<f32>, d: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let e1 = b - a;
    let e2 = c - a;
    let p = cross(d, e2);
    let det = dot(e1, p);
    if (abs(det) < 1e-12) {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = dot(s, p) * inv;
    let q = cross(s, e1);
    let v = dot(d, q) * inv;
    let eps = 1e-5;
    if (u < -eps || v < -eps || u + v > 1.0 + eps) {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    return vec3<f32>(dot(e2, q) * inv, u, v);
}

struct Corner {
    p: vec3<f32>,
    st: vec3<f32>, // (u, v, h)
}

fn corner(pd: PrismData, k: u32, on_top: bool) -> Corner {
    var c: Corner;
    c.p = select(pd.bottom[k].xyz, pd.top[k].xyz, on_top);
    c.st = vec3<f32>(pd.uv[k].xy, select(0.0, 1.0, on_top));
    return c;
}

// The exit of the ray from the prism: (t, u, v, h) with t the farthest boundary hit.
fn prism_exit(pd: PrismData, o: vec3<f32>, d: vec3<f32>) -> vec4<f32> {
    var best = vec4<f32>(-1.0, 0.0, 0.0, 0.0);
    for (var f = 0u; f < 8u; f = f + 1u) {
        var a: Corner;
        var b: Corner;
        var c: Corner;
        if (f == 0u) {
            a = corner(pd, 0u, true); b = corner(pd, 1u, true); c = corner(pd, 2u, true);
        } else if (f == 1u) {
            a = corner(pd, 0u, false); b = corner(pd, 1u, false); c = corner(pd, 2u, false);
        } else {
            let k = (f - 2u) / 2u;
            let j = (k + 1u) % 3u;
            if ((f - 2u) % 2u == 0u) {
                a = corner(pd, k, true); b = corner(pd, j, true); c = corner(pd, j, false);
            } else {
                a = corner(pd, k, true); b = corner(pd, j, false); c = corner(pd, k, false);
            }
        }
        let r = ray_tri(o, d, a.p, b.p, c.p);
        if (r.x > best.x) {
            let st = a.st * (1.0 - r.y - r.z) + b.st * r.y + c.st * r.z;
            best = vec4<f32>(r.x, st);
        }
    }
    return best;
}

// The march through the prism a fragment enters, along `view` (object space, unit): whether it
// hits, the hit's distance from the entry, its texture point and height, the level sampled, and
// the steps taken.
struct PrismHit {
    ok: bool,
    t: f32,
    s: vec2<f32>,
    h: f32,
    hl: f32,
    steps: f32,
}

fn prism_hit(in: VertexOut, f: Frame, view: vec3<f32>, lod: f32) -> PrismHit {
    var o: PrismHit;
    o.ok = false;
    let tiling = G.tiling;
    let ndotv = -dot(view, f.n);
    let pd = prisms[in.prism];
    let ex = prism_exit(pd, in.world, view);
    if (ex.x <= 1e-7) {
        return o;
    }
    let s_e = in.uv * tiling;
    let h_e = clamp(in.h, 0.0, 1.0);
    let s_x = ex.yz * tiling;
    let h_x = clamp(ex.w, 0.0, 1.0);
    // early rejection: the ray's lowest point in the prism is above every height under it
    if (min(h_e, h_x) > pd.info.x) {
        return o;
    }
    let exact = params.exact > 0.5;
    var hl = height_lod(lod);
    if (exact) {
        hl = 0.0;
    }
    var steps = 1.0;
    var hit = -1.0;
    let dh_seg = h_x - h_e;
    if (exact && abs(dh_seg) > 1e-4) {
        // exact=True: the max-mip traversal along the segment, parameterised by height
        let slope = (s_x - s_e) / abs(dh_seg) * G.map_size;
        let p0 = positive_start(s_e, slope);
        let tr = maxmip_traverse(p0.x, p0.y, h_e, slope.x, slope.y, sign(dh_seg), abs(dh_seg), G.max_iterations);
        steps = tr.iters;
        if (tr.hit) {
            hit = tr.t / abs(dh_seg);
        }
    } else {
        // the shared linear search from entry to exit, at POM's layer density: a segment
        // spanning dh of the shell's height gets n * dh layers (>= 2)
        let n = max(ceil(pom_sample_count(ndotv, params.min_steps, params.max_steps, true) * abs(dh_seg)), 2.0);
        let b = linear_search(Segment(s_e, s_x - s_e, h_e, dh_seg), n, hl);
        steps = b.steps;
        if (b.d_cur <= 0.0) {
            hit = refine_linear(b);
        }
    }
    o.steps = steps;
    if (hit < 0.0) {
        return o;
    }
    o.ok = true;
    o.t = ex.x * hit;
    o.s = mix(s_e, s_x, hit);
    o.h = mix(h_e, h_x, hit);
    o.hl = hl;
    return o;
}

@fragment
fn fs_prism(in: VertexOut) -> PrismFsOut {
    let f = make_frame(in.normal, in.tangent, in.uv_scale);
    let tiling = G.tiling;
    let lod = compute_lod(in.uv * tiling);
    // object space, as in surface.wgsl
    let to_p = in.world - G.eye_object;
    let base_dist = length(to_p);
    let view = to_p / max(base_dist, 1e-20);
    let px = in.clip.xy;
    let ph = prism_hit(in, f, view, lod);
    if (!ph.ok) {
        discard;
    }
    let s_hit = ph.s;
    let p_obj = in.world + view * ph.t;
    let p = to_world(p_obj);
    let sh = shade(f, s_hit, ph.h, p, normal_to_world(height_normal(f, s_hit, ph.hl)), ph.hl, true, px);
    var dist = length(p - G.eye);
    if (G.transformed > 0.5) {
        dist = length(p_obj - G.eye_object) * stretch(view);
    }
    let aov = write_aovs(sh.color, u32(ph.steps + sh.steps), 0u, s_hit / tiling, dist, lod);
    var o: PrismFsOut;
    o.color = aov.color;
    o.geo = aov.geo;
    o.id = aov.id;
    o.depth = clip_depth(p);
    return o;
}

// The shadow-map pass: the prisms seen from the light, each fragment marched along the light's
// direction; the hit's depth in the light's projection.
@vertex
fn vs_prism_shadow(v: VertexIn, @location(5) h: f32, @builtin(vertex_index) index: u32) -> VertexOut {
    return prism_vertex(v, h, index, G.shadow_vp);
}

@fragment
fn fs_prism_shadow(in: VertexOut) -> @builtin(frag_depth) f32 {
    let f = make_frame(in.normal, in.tangent, in.uv_scale);
    let lod = compute_lod(in.uv * G.tiling);
    let view = shadow_light_object();
    let ph = prism_hit(in, f, view, lod);
    if (!ph.ok) {
        discard;
    }
    return shadow_depth(to_world(in.world + view * ph.t));
}

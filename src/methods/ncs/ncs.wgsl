// NCS: normal-based curved silhouettes (Chen & Chang 2008, Algorithm 2). The view ray is
// marched from the rasterised point in texture space (u, v, h), and at every step the local
// frame is looked up in the texture-space maps (texspace.wgsl), so the ray follows the curved
// base surface: P_{i+1} = P_i + c * delta * S * TBN * V with delta = depth / max_steps (world
// length) and c = step_scale. Leaving the shell through its top discards the pixel (that makes
// the silhouette); falling below the height field refines between the last two steps; still
// inside after max_steps is an early termination (flags & 2; the paper's fig. 7 shows them red).
//
// Seams and poles: the maps repeat in u and v; a ray crossing a uv seam of a mesh whose uvs are
// periodic (torus, sphere in u) continues on the other side; across a seam that is not periodic
// (the sphere's poles) the frame is that of the dilated texels beyond the chart.

#define_import_path pomkit::methods::ncs

#import pomkit::cost::fetched
#import pomkit::globals::G
#import pomkit::aov::FLAG_EARLY
#import pomkit::frame::{TangentFrame, make_frame}
#import pomkit::height::{height_at, bilinear_taps, bilerp}
#import pomkit::march::{Ray, Hit, pom_sample_count}
#import pomkit::frame_map::{FrameTexel, unpack_frame, frame_b}

// the method's own resource (src/methods/ncs: group 2, binding 1): two texels per frame-map
// texel (frame_map.wgsl)
@group(2) @binding(1) var frame_map: texture_2d<u32>;

fn frame_texel(x: i32, y: i32) -> FrameTexel {
    fetched(2u, 32u);
    return unpack_frame(textureLoad(frame_map, vec2<i32>(2 * x, y), 0), textureLoad(frame_map, vec2<i32>(2 * x + 1, y), 0));
}

// The frame map's size in frame-map texels.
fn frame_dims() -> vec2<i32> {
    let d = vec2<i32>(textureDimensions(frame_map));
    return vec2<i32>(d.x / 2, d.y);
}

// A texel's frame as the old map stored it: (t, S_tangent) and (n, sign * S_binormal).
fn texel_frame(f: FrameTexel) -> array<vec4<f32>, 2> {
    let s_t = 1.0 / max(length(f.a), 1e-30);
    return array<vec4<f32>, 2>(vec4<f32>(f.a * s_t, s_t), vec4<f32>(f.n, s_t / f.k));
}

// The base frame at mesh uv, bilinear between texel centres of the map (four texels).
fn frame_at(uv: vec2<f32>) -> TangentFrame {
    let q = bilinear_taps(uv, frame_dims());
    let a = texel_frame(frame_texel(q.xa, q.ya));
    let b = texel_frame(frame_texel(q.xb, q.ya));
    let c = texel_frame(frame_texel(q.xa, q.yb));
    let d = texel_frame(frame_texel(q.xb, q.yb));
    let t = bilerp(q, a[0], b[0], c[0], d[0]);
    let n = bilerp(q, a[1], b[1], c[1], d[1]);
    return make_frame(n.xyz, vec4<f32>(t.xyz, n.w), vec2<f32>(t.w, abs(n.w)));
}

// The map texel a uv falls in (wrapped): the frame the march steps with, fetched again only when
// the ray enters another texel (the hit's frame is the bilinear one).
fn frame_texel_at(uv: vec2<f32>, dims: vec2<i32>) -> vec2<i32> {
    return min(vec2<i32>(fract(uv) * vec2<f32>(dims)), dims - 1);
}

fn ncs_hit(r: Ray, uv: vec2<f32>, h: f32, len: f32, steps: f32, flags: u32, f: TangentFrame) -> Hit {
    var hit: Hit;
    hit.s = uv * G.tiling;
    hit.h = h;
    hit.len = len;
    hit.steps = steps;
    hit.flags = flags;
    hit.lod = r.lod;
    hit.f = f;
    hit.exited = false;
    return hit;
}

// adaptive steps: the fewest layers per shell height (head-on), as POM's default min_steps
const MIN_LAYERS: f32 = 8.0;

// The world length of a step whose view ray meets the base surface at N.V = ndv: the paper's
// c * delta, or (adaptive) at least POM's layer density: each step descends one of the shell's
// pom_sample_count(N.V, 8, N) layers (N.V local), and at most one shell depth along the ray, so
// that the step still follows the surface's curvature.
fn ncs_step_length(ndv_in: f32, n: f32, dl0: f32) -> f32 {
    if (params.adaptive > 0.5) {
        let ndv = max(ndv_in, 1e-3);
        let layers = pom_sample_count(ndv, MIN_LAYERS, n, true);
        return clamp(G.depth / (ndv * layers), dl0, max(G.depth, dl0));
    }
    return dl0;
}

// One step of length dl along the view in a map texel's frame, in (u, v, h): S * TBN * V * dl.
fn texel_step(f: FrameTexel, view: vec3<f32>, n: f32, dl0: f32, inv_depth: f32) -> vec4<f32> {
    let vn = dot(view, f.n);
    let dl = ncs_step_length(-vn, n, dl0);
    return vec4<f32>(vec3<f32>(dot(view, f.a), dot(view, frame_b(f)), vn * inv_depth) * dl, dl);
}

fn march(r: Ray) -> Hit {
    let n = max(params.max_steps, 1.0);
    // the paper's step: c * delta, delta = depth / N (world length)
    let dl0 = params.step_scale * G.depth / n;
    let tiling = G.tiling;
    let view = r.view;
    var uv = r.uv;
    var h = 1.0;
    var len = 0.0;
    var d = h - height_at(uv * tiling, r.lod);
    var steps = 1.0;
    if (d <= 0.0) {
        return ncs_hit(r, uv, h, 0.0, steps, 0u, frame_at(uv));
    }
    // the first step goes along the rasterised frame
    let f = r.f;
    let dims = frame_dims();
    var cell = frame_texel_at(uv, dims);
    // the last two points when the ray falls below the height field (the crossing between them
    // is taken after the loop)
    var uv1 = uv;
    var h1 = h;
    var d1 = d;
    let ni = i32(n);
    // the step, a function of the frame alone: taken again only when the frame changes
    let inv_depth = 1.0 / max(G.depth, 1e-12);
    var dl = ncs_step_length(-dot(view, f.n), n, dl0);
    var step = vec3<f32>(dot(view, f.t) / f.scale.x, dot(view, f.b) / f.scale.y, dot(view, f.n) * inv_depth) * dl;
    // the loop only marches; the crossing and the hit's bilinear frame (four map texels) are taken
    // once after it, in control flow all lanes share again (inside the loop a SIMD group would
    // run them at every step: lavapipe runs every branch any lane takes)
    var flags = FLAG_EARLY;
    var exited = false;
    for (var i = 0; i < ni; i = i + 1) {
        uv1 = uv + step.xy;
        h1 = h + step.z;
        steps = steps + 1.0;
        if (h1 > 1.0) {
            exited = true;
            break;
        }
        d1 = h1 - height_at(uv1 * tiling, r.lod);
        if (d1 <= 0.0) {
            flags = 0u;
            break;
        }
        uv = uv1;
        h = h1;
        len = len + dl;
        d = d1;
        // the frame changes slowly (a map texel spans several steps): fetched again only when
        // the ray enters another cell of the map
        let c = frame_texel_at(uv, dims);
        if (any(c != cell)) {
            cell = c;
            let st = texel_step(frame_texel(c.x, c.y), view, n, dl0, inv_depth);
            step = st.xyz;
            dl = st.w;
        }
    }
    if (exited) {
        var out: Hit;
        out.exited = true;
        out.steps = steps;
        return out;
    }
    if (flags == 0u) {
        // the crossing between the last two points
        let t = d / max(d - d1, 1e-12);
        uv = mix(uv, uv1, t);
        h = mix(h, h1, t);
        len = len + dl * t;
    }
    return ncs_hit(r, uv, h, len, steps, flags, frame_at(uv));
}

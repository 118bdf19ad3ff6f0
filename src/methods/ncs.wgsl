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

#import pomkit::globals::G
#import pomkit::aov::FLAG_EARLY
#import pomkit::frame::{Frame, make_frame}
#import pomkit::height::{height_at, bilinear_taps, bilerp}
#import pomkit::march::{Ray, Hit}

@group(0) @binding(8) var frame_n: texture_2d<u32>;
@group(0) @binding(9) var frame_t: texture_2d<u32>;

fn frame_texel(m: texture_2d<u32>, x: i32, y: i32) -> vec4<f32> {
    return bitcast<vec4<f32>>(textureLoad(m, vec2<i32>(x, y), 0));
}

// The base frame at mesh uv, bilinear between texel centres of the maps.
fn frame_at(uv: vec2<f32>) -> Frame {
    let k = bilinear_taps(uv, vec2<i32>(textureDimensions(frame_n)));
    let n = bilerp(k, frame_texel(frame_n, k.xa, k.ya), frame_texel(frame_n, k.xb, k.ya),
                   frame_texel(frame_n, k.xa, k.yb), frame_texel(frame_n, k.xb, k.yb));
    let t = bilerp(k, frame_texel(frame_t, k.xa, k.ya), frame_texel(frame_t, k.xb, k.ya),
                   frame_texel(frame_t, k.xa, k.yb), frame_texel(frame_t, k.xb, k.yb));
    return make_frame(n.xyz, vec4<f32>(t.xyz, select(1.0, -1.0, t.w < 0.0)), vec2<f32>(n.w, abs(t.w)));
}

fn ncs_hit(r: Ray, uv: vec2<f32>, h: f32, len: f32, steps: f32, flags: u32, f: Frame) -> Hit {
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

fn march(r: Ray) -> Hit {
    let n = max(params.max_steps, 1.0);
    let dl = params.step_scale * G.depth / n;
    let tiling = G.tiling;
    let view = r.view;
    var uv = r.uv;
    var h = 1.0;
    var len = 0.0;
    var d = h - height_at(uv * tiling, r.lod);
    var steps = 1.0;
    var f = frame_at(uv);
    if (d <= 0.0) {
        return ncs_hit(r, uv, h, 0.0, steps, 0u, f);
    }
    let ni = i32(n);
    for (var i = 0; i < ni; i = i + 1) {
        let step = vec3<f32>(dot(view, f.t) / f.scale.x, dot(view, f.b) / f.scale.y, dot(view, f.n) / max(G.depth, 1e-12)) * dl;
        let uv1 = uv + step.xy;
        let h1 = h + step.z;
        if (h1 > 1.0) {
            var out: Hit;
            out.exited = true;
            out.steps = steps + 1.0;
            return out;
        }
        let d1 = h1 - height_at(uv1 * tiling, r.lod);
        steps = steps + 1.0;
        if (d1 <= 0.0) {
            let t = d / max(d - d1, 1e-12);
            let uv_hit = mix(uv, uv1, t);
            return ncs_hit(r, uv_hit, mix(h, h1, t), len + dl * t, steps, 0u, frame_at(uv_hit));
        }
        uv = uv1;
        h = h1;
        len = len + dl;
        d = d1;
        f = frame_at(uv);
    }
    return ncs_hit(r, uv, h, len, steps, FLAG_EARLY, f);
}

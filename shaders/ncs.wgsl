// ncs.wgsl: normal-based curved silhouettes (Chen & Chang 2008, Algorithm 2). The view ray is
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

@group(0) @binding(8) var frame_n: texture_2d<u32>;
@group(0) @binding(9) var frame_t: texture_2d<u32>;

const FLAG_EARLY: u32 = 2u;

fn frame_texel(p: vec2<i32>, d: vec2<i32>) -> array<vec4<f32>, 2> {
    let q = vec2<i32>(wrap_i(p.x, d.x), wrap_i(p.y, d.y));
    return array<vec4<f32>, 2>(bitcast<vec4<f32>>(textureLoad(frame_n, q, 0)), bitcast<vec4<f32>>(textureLoad(frame_t, q, 0)));
}

// The base frame at mesh uv, bilinear between texel centres of the maps.
fn frame_at(uv: vec2<f32>) -> Frame {
    let d = vec2<i32>(textureDimensions(frame_n));
    let p = uv * vec2<f32>(d) - 0.5;
    let p0 = floor(p);
    let fr = p - p0;
    let i0 = vec2<i32>(p0);
    let a = frame_texel(i0, d);
    let b = frame_texel(i0 + vec2<i32>(1, 0), d);
    let c = frame_texel(i0 + vec2<i32>(0, 1), d);
    let e = frame_texel(i0 + vec2<i32>(1, 1), d);
    let n = mix(mix(a[0], b[0], fr.x), mix(c[0], e[0], fr.x), fr.y);
    let t = mix(mix(a[1], b[1], fr.x), mix(c[1], e[1], fr.x), fr.y);
    return make_frame(n.xyz, vec4<f32>(t.xyz, select(1.0, -1.0, t.w < 0.0)), vec2<f32>(n.w, abs(t.w)));
}

struct NcsHit {
    uv: vec2<f32>,   // mesh uv of the hit
    h: f32,
    len: f32,        // world length travelled from the rasterised point
    steps: f32,
    flags: u32,
    exited: bool,    // left the shell: discard
    f: Frame,        // the frame at the hit
}

fn ncs_march(uv0: vec2<f32>, view: vec3<f32>, lod: f32) -> NcsHit {
    var r: NcsHit;
    r.exited = false;
    r.flags = 0u;
    let n = max(G.march.y, 1.0);
    let dl = G.params.x * G.tex.w / n;
    let tiling = G.tex.z;
    var uv = uv0;
    var h = 1.0;
    var len = 0.0;
    var d = h - height_at(uv * tiling, lod);
    r.steps = 1.0;
    var f = frame_at(uv);
    if (d <= 0.0) {
        r.uv = uv;
        r.h = h;
        r.len = 0.0;
        r.f = f;
        return r;
    }
    let ni = i32(n);
    for (var i = 0; i < ni; i = i + 1) {
        let step = vec3<f32>(dot(view, f.t) / f.scale.x, dot(view, f.b) / f.scale.y, dot(view, f.n) / max(G.tex.w, 1e-12)) * dl;
        let uv1 = uv + step.xy;
        let h1 = h + step.z;
        if (h1 > 1.0) {
            r.exited = true;
            r.steps = r.steps + 1.0;
            return r;
        }
        let d1 = h1 - height_at(uv1 * tiling, lod);
        r.steps = r.steps + 1.0;
        if (d1 <= 0.0) {
            let t = d / max(d - d1, 1e-12);
            r.uv = mix(uv, uv1, t);
            r.h = mix(h, h1, t);
            r.len = len + dl * t;
            r.f = frame_at(r.uv);
            return r;
        }
        uv = uv1;
        h = h1;
        len = len + dl;
        d = d1;
        f = frame_at(uv);
    }
    r.flags = FLAG_EARLY;
    r.uv = uv;
    r.h = h;
    r.len = len;
    r.f = f;
    return r;
}

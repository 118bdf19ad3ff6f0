// frame_map.wgsl: NCS's texture-space frame map, one Rgba32Uint texel per frame-map texel:
// x = the normal and y = the tangent, octahedral in two snorm16; z = S_tangent (float bits);
// w = sign(bitangent) * S_binormal (float bits). One bilinear frame is four fetches.
#define_import_path pomkit::frame_map

fn oct_encode(v: vec3<f32>) -> vec2<f32> {
    let a = v / max(abs(v.x) + abs(v.y) + abs(v.z), 1e-30);
    if (a.z >= 0.0) {
        return a.xy;
    }
    let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), a.xy >= vec2<f32>(0.0));
    return (1.0 - abs(a.yx)) * s;
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var v = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) {
        let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), v.xy >= vec2<f32>(0.0));
        v = vec3<f32>((1.0 - abs(v.yx)) * s, v.z);
    }
    return normalize(v);
}

fn pack_frame(n: vec3<f32>, t: vec3<f32>, s_t: f32, s_b: f32) -> vec4<u32> {
    return vec4<u32>(pack2x16snorm(oct_encode(n)), pack2x16snorm(oct_encode(t)), bitcast<u32>(s_t), bitcast<u32>(s_b));
}

// One texel: normal, tangent, S_tangent, signed S_binormal.
struct FrameTexel {
    n: vec3<f32>,
    t: vec3<f32>,
    s_t: f32,
    s_b: f32,
}

fn unpack_frame(x: vec4<u32>) -> FrameTexel {
    var f: FrameTexel;
    f.n = oct_decode(unpack2x16snorm(x.x));
    f.t = oct_decode(unpack2x16snorm(x.y));
    f.s_t = bitcast<f32>(x.z);
    f.s_b = bitcast<f32>(x.w);
    return f;
}

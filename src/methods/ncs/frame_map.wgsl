// frame_map.wgsl: NCS's texture-space frame map. Each frame-map texel (x, y) is two Rgba32Uint
// texels, (2x, y) and (2x + 1, y), of float32 bits in the form the march steps with:
//     (n.x, n.y, n.z, k) and (a.x, a.y, a.z, 0)
// n the unit normal, a = t / S_tangent (uv per world length along the unit tangent t) and
// k = sign(bitangent) * S_tangent / S_binormal, so that b / S_binormal = k * cross(n, a). A step
// along a world direction v is then (dot(v, a), dot(v, k * cross(n, a)), dot(v, n)): three dot
// products and a cross product, with no decode, square root or division.
//
// (Until issue 33 the map was one texel of n and t octahedral in snorm16 pairs and the scales
// as floats: its decode, two normalisations and the step's three divisions took 60 % of NCS's
// march on lavapipe, where a branch's body runs for every lane.)
#define_import_path pomkit::frame_map

// One frame-map texel as two Rgba32Uint texels.
struct PackedFrame {
    first: vec4<u32>,
    second: vec4<u32>,
}

// n unit, t unit and orthogonal to n, s_t > 0 and s_b_signed = sign(bitangent) * S_binormal.
fn pack_frame(n: vec3<f32>, t: vec3<f32>, s_t: f32, s_b_signed: f32) -> PackedFrame {
    let s_b = max(abs(s_b_signed), 1e-12);
    let k = select(1.0, -1.0, s_b_signed < 0.0) * s_t / s_b;
    return PackedFrame(bitcast<vec4<u32>>(vec4<f32>(n, k)), bitcast<vec4<u32>>(vec4<f32>(t / s_t, 0.0)));
}

// One texel: the normal, a = t / S_tangent and k (above).
struct FrameTexel {
    n: vec3<f32>,
    a: vec3<f32>,
    k: f32,
}

fn unpack_frame(first: vec4<u32>, second: vec4<u32>) -> FrameTexel {
    let x = bitcast<vec4<f32>>(first);
    return FrameTexel(x.xyz, bitcast<vec4<f32>>(second).xyz, x.w);
}

// b / S_binormal of a texel (uv per world length along the bitangent).
fn frame_b(f: FrameTexel) -> vec3<f32> {
    return f.k * cross(f.n, f.a);
}

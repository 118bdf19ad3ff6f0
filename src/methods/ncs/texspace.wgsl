// texspace.wgsl: the base mesh's frame rendered into texture space for NCS (Chen & Chang 2008,
// Algorithm 1): every triangle drawn at its uvs, writing the interpolated vertex normal and
// tangent and the world-per-uv scale factors S_tangent, S_binormal. Targets are Rgba32Uint
// holding float bits (renderable everywhere): map N = (n.xyz, S_tangent), map T = (t.xyz,
// sign(w) * S_binormal). Texels outside the charts stay zero and are then filled by `dilate`;
// `pack` then writes the one map NCS reads (frame_map.wgsl): two texels per map texel.

#import pomkit::vertex::VertexIn
#import pomkit::frame_map::pack_frame

struct BakeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) tangent: vec4<f32>,
    @location(2) uv_scale: vec2<f32>,
}

@vertex
fn vs_bake(v: VertexIn) -> BakeOut {
    var o: BakeOut;
    // uv (0,0) is texel row 0, column 0: the top-left of the target
    o.clip = vec4<f32>(v.uv.x * 2.0 - 1.0, 1.0 - v.uv.y * 2.0, 0.5, 1.0);
    o.normal = v.normal;
    o.tangent = v.tangent;
    o.uv_scale = v.uv_scale;
    return o;
}

struct BakeTargets {
    @location(0) n: vec4<u32>,
    @location(1) t: vec4<u32>,
}

@fragment
fn fs_bake(i: BakeOut) -> BakeTargets {
    var o: BakeTargets;
    let w = select(1.0, -1.0, i.tangent.w < 0.0);
    o.n = bitcast<vec4<u32>>(vec4<f32>(normalize(i.normal), max(i.uv_scale.x, 1e-12)));
    o.t = bitcast<vec4<u32>>(vec4<f32>(i.tangent.xyz, w * max(i.uv_scale.y, 1e-12)));
    return o;
}

// Dilation: an empty texel (S_tangent == 0) takes the mean of its covered 8-neighbours. Run a
// few times, it extends the charts so that bilinear lookups near chart borders stay valid.
@group(0) @binding(0) var src_n: texture_2d<u32>;
@group(0) @binding(1) var src_t: texture_2d<u32>;
@group(0) @binding(2) var dst_n: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(3) var dst_t: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8)
fn dilate(@builtin(global_invocation_id) id: vec3<u32>) {
    let d = vec2<i32>(textureDimensions(src_n));
    let p = vec2<i32>(id.xy);
    if (p.x >= d.x || p.y >= d.y) {
        return;
    }
    var n = bitcast<vec4<f32>>(textureLoad(src_n, p, 0));
    var t = bitcast<vec4<f32>>(textureLoad(src_t, p, 0));
    if (n.w == 0.0) {
        var sn = vec4<f32>(0.0);
        var st = vec4<f32>(0.0);
        var k = 0.0;
        for (var dy = -1; dy <= 1; dy = dy + 1) {
            for (var dx = -1; dx <= 1; dx = dx + 1) {
                let q = clamp(p + vec2<i32>(dx, dy), vec2<i32>(0), d - 1);
                let a = bitcast<vec4<f32>>(textureLoad(src_n, q, 0));
                if (a.w != 0.0) {
                    sn = sn + a;
                    st = st + bitcast<vec4<f32>>(textureLoad(src_t, q, 0));
                    k = k + 1.0;
                }
            }
        }
        if (k > 0.0) {
            n = sn / k;
            t = st / k;
        }
    }
    textureStore(dst_n, p, bitcast<vec4<u32>>(n));
    textureStore(dst_t, p, bitcast<vec4<u32>>(t));
}

// The packed map (frame_map.wgsl): two texels per frame-map texel, (n, k) and (t / S_tangent, 0).
// It reads the dilated maps through dilate's bindings and writes through dst_n (bindings 0-2),
// which is twice as wide.

@compute @workgroup_size(8, 8)
fn pack(@builtin(global_invocation_id) id: vec3<u32>) {
    let d = vec2<i32>(textureDimensions(src_n));
    let p = vec2<i32>(id.xy);
    if (p.x >= d.x || p.y >= d.y) {
        return;
    }
    let n = bitcast<vec4<f32>>(textureLoad(src_n, p, 0));
    let t = bitcast<vec4<f32>>(textureLoad(src_t, p, 0));
    // orthonormal as stored, so that the march can step with it as it is
    let nn = normalize(n.xyz);
    var tt = t.xyz - nn * dot(t.xyz, nn);
    if (dot(tt, tt) < 1e-12) {
        let a = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(nn.x) > 0.9);
        tt = cross(nn, a);
    }
    let f = pack_frame(nn, normalize(tt), max(n.w, 1e-12), t.w);
    textureStore(dst_n, vec2<i32>(2 * p.x, p.y), f.first);
    textureStore(dst_n, vec2<i32>(2 * p.x + 1, p.y), f.second);
}

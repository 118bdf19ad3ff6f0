// mips.wgsl: the height map's pyramids, built on the GPU so that dynamic height fields need only
// a level-0 upload.
//   reduce:               level k of the sampling pyramid: the mean of each 2x2 footprint of
//                         level k - 1 (clamped at odd edges)
//   max_cells/max_reduce: the max pyramid of Tevs et al. 2008, in two textures (below)

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_dims = textureDimensions(dst);
    if (id.x >= out_dims.x || id.y >= out_dims.y) {
        return;
    }
    let sd = vec2<i32>(textureDimensions(src));
    let q = 2 * vec2<i32>(id.xy);
    let a = textureLoad(src, min(q, sd - 1), 0).r;
    let b = textureLoad(src, min(q + vec2<i32>(1, 0), sd - 1), 0).r;
    let c = textureLoad(src, min(q + vec2<i32>(0, 1), sd - 1), 0).r;
    let d = textureLoad(src, min(q + vec2<i32>(1, 1), sd - 1), 0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>((a + b + c + d) * 0.25, 0.0, 0.0, 0.0));
}

// ---- the max pyramid: level 0 in a texture of the map's size, levels 1.. side by side in an
// atlas (level k at x = its offset, y = 0), so that every level stays within the device's
// texture limits and no buffer exceeds a binding limit. Every load is at mip level 0 of its
// texture: on lavapipe a texel fetch whose level varies across lanes returned other lanes'
// texels (maxmip.wgsl). A level is written to a scratch texture and copied into the atlas, so
// that no dispatch reads and writes one texture.

struct MaxLevel {
    src_w: u32,
    src_h: u32,
    dst_w: u32,
    dst_h: u32,
    // x offset of the source level in the source texture (0: the height map or level 0)
    src_off: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(1) @binding(0) var msrc: texture_2d<f32>;
@group(1) @binding(1) var mdst: texture_storage_2d<r32float, write>;
@group(1) @binding(2) var<uniform> ML: MaxLevel;

// level 0: the max of the four texel centres around each cell (wrapping)
@compute @workgroup_size(8, 8)
fn max_cells(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ML.dst_w || id.y >= ML.dst_h) {
        return;
    }
    let x1 = (id.x + 1u) % ML.dst_w;
    let y1 = (id.y + 1u) % ML.dst_h;
    let v = max(max(textureLoad(msrc, vec2<u32>(id.x, id.y), 0).r, textureLoad(msrc, vec2<u32>(x1, id.y), 0).r),
                max(textureLoad(msrc, vec2<u32>(id.x, y1), 0).r, textureLoad(msrc, vec2<u32>(x1, y1), 0).r));
    textureStore(mdst, vec2<u32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}

// level k from level k - 1: 2x2 max, clamped at odd edges
@compute @workgroup_size(8, 8)
fn max_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ML.dst_w || id.y >= ML.dst_h) {
        return;
    }
    let x0 = ML.src_off + min(2u * id.x, ML.src_w - 1u);
    let x1 = ML.src_off + min(2u * id.x + 1u, ML.src_w - 1u);
    let y0 = min(2u * id.y, ML.src_h - 1u);
    let y1 = min(2u * id.y + 1u, ML.src_h - 1u);
    let v = max(max(textureLoad(msrc, vec2<u32>(x0, y0), 0).r, textureLoad(msrc, vec2<u32>(x1, y0), 0).r),
                max(textureLoad(msrc, vec2<u32>(x0, y1), 0).r, textureLoad(msrc, vec2<u32>(x1, y1), 0).r));
    textureStore(mdst, vec2<u32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}

// ---- the children atlas (src/heightmap/mod.rs's children_atlas): at each node of a level k in
// 1 ..= top, its four children's maxes (level k - 1: level 0, or the finished atlas) in one
// rgba8unorm texel, in textureGather's order: x (0, 1), y (1, 1), z (1, 0), w (0, 0). The max-mip
// walk reads a node's children with one load (maxmip.wgsl). Up to the top level the children of
// every node lie inside their level: no clamping.
// Each max is rounded up to a code (src/heightmap/mod.rs's CHILD_MAX_CODES): the smallest c with
// c / 255 >= m + 0.01 / 255, 0 kept at 0. A max is never understated (the walk only descends
// where it must, and may descend where it need not: a patch test answers exactly), and is
// overstated by at most 1.01 / 255 of the shell. One 32-bit texel, not four float32: lavapipe
// appears to fetch a texel one lane and one 32-bit channel at a time, and the float32 texel's
// load was over a quarter of the walk's instructions (docs/cost_journal_2026.md).

struct ChildLevel {
    // the source level's origin in its texture, the destination level's in the children atlas
    src_off: vec2<u32>,
    dst_off: vec2<u32>,
    dst_w: u32,
    dst_h: u32,
    pad0: u32,
    pad1: u32,
}

@group(2) @binding(0) var csrc: texture_2d<f32>;
@group(2) @binding(1) var cdst: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(2) var<uniform> CL: ChildLevel;

@compute @workgroup_size(8, 8)
fn max_children(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= CL.dst_w || id.y >= CL.dst_h) {
        return;
    }
    let a = CL.src_off + 2u * id.xy;
    let c = vec4<f32>(textureLoad(csrc, a + vec2<u32>(0u, 1u), 0).r, textureLoad(csrc, a + vec2<u32>(1u, 1u), 0).r,
                      textureLoad(csrc, a + vec2<u32>(1u, 0u), 0).r, textureLoad(csrc, a, 0).r);
    let code = select(min(ceil(c * 255.0 + 0.01), vec4<f32>(255.0)), vec4<f32>(0.0), c <= vec4<f32>(0.0));
    // code / 255 converts back to exactly `code` (round to nearest)
    textureStore(cdst, CL.dst_off + id.xy, code / 255.0);
}

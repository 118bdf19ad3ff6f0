// cone_map.wgsl: the cone map of a height map, built on the GPU from its max-mip pyramid
// (the idea of "quick cone maps": box maxima from the pyramid instead of a search over every
// texel pair). One texel per cell of the bilinear field (cell (i, j) spans texel centres
// i..i+1, j..j+1, as in maxmip.wgsl): (base, w).
//
// Conservative cones (the default) bound the bilinear field, not only its texel centres: for a
// point x anywhere in the cell and any point y of the surface at horizontal distance
// rho = |y - x|_inf (in cells),
//     h(y) <= base + rho / w.
// Points within rho <= 1 lie in the 3 x 3 cells around the cell, so base is their max (M_1).
// Points with 2^(j-1) < rho <= 2^j lie in the box of cells within 2^j, whose max is bounded
// by the max-pyramid nodes of level j + 1 that cover it (at most 2 x 2 of them); w is the
// largest ratio that keeps base + rho / w above that bound at the interval's near end. The
// bound is an upper bound of the true maxima, so the cones are narrower than the widest
// conservative ones, never wider (Ban & Valasek 2024: cones at texel centres alone are not
// conservative under bilinear interpolation).
//
// Where the pyramid's top level is too fine for a box (more than 16 nodes a side: maps whose
// sides few powers of two divide), every farther point is bounded by the map's maximum.
//
// Relaxed cones take base = the cell's own max and measure each interval at its far end:
// wider, not conservative (a ray may step into a feature), refined by a binary search.

#import pomkit::max_tables::max_node

struct ConeParams {
    // the first row of this dispatch's band (gpu::TablePass::run)
    band_row: u32,
    top: u32,
    size: vec2<u32>,
    relaxed: u32,
    // the map's maximum (of its texels, so of its bilinear field)
    global_max: f32,
    pad1: u32,
    pad2: u32,
    // x offset of each max-pyramid level in the atlas
    offsets: array<vec4<u32>, 4>,
}

@group(0) @binding(2) var<uniform> P: ConeParams;
// two R32Float textures, not one two-channel texture or a buffer: the GL backend has no
// two-channel storage textures, and a buffer of 8 bytes a cell exceeds the storage binding
// limit (128 MiB here) from 4096² on
@group(0) @binding(3) var cone_base_out: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var cone_w_out: texture_storage_2d<r32float, write>;

fn floor_div(a: vec2<i32>, s: i32) -> vec2<i32> {
    return vec2<i32>(floor(vec2<f32>(a) / f32(s)));
}

// the max of node n (wrapped) at a level of the pyramid
fn node_max(n: vec2<i32>, level: u32) -> f32 {
    let d = vec2<i32>(max(P.size >> vec2<u32>(level), vec2<u32>(1u)));
    let w = n - vec2<i32>(floor(vec2<f32>(n) / vec2<f32>(d))) * d;
    return max_node(w, level, P.offsets[level / 4u][level % 4u]);
}

// an upper bound of the field over the cells within k of c, from the nodes of `level` covering
// them
fn box_max(c: vec2<i32>, k: i32, level: u32) -> f32 {
    let s = 1 << level;
    let lo = floor_div(c - vec2<i32>(k), s);
    let hi = floor_div(c + vec2<i32>(k), s);
    var m = 0.0;
    for (var y = lo.y; y <= hi.y; y = y + 1) {
        for (var x = lo.x; x <= hi.x; x = x + 1) {
            m = max(m, node_max(vec2<i32>(x, y), level));
        }
    }
    return m;
}

@compute @workgroup_size(8, 8)
fn build(@builtin(global_invocation_id) gid: vec3<u32>) {
    let id = vec2<u32>(gid.x, gid.y + P.band_row);
    if (id.x >= P.size.x || id.y >= P.size.y) {
        return;
    }
    let c = vec2<i32>(id);
    let relaxed = P.relaxed == 1u;
    let m1 = box_max(c, 1, 0u);
    let base = select(m1, node_max(c, 0u), relaxed);
    var w = 1e6;
    if (relaxed && m1 > base) {
        w = min(w, 1.0 / (m1 - base));
    }
    let span = i32(max(P.size.x, P.size.y));
    for (var j = 1u; j < 31u; j = j + 1u) {
        let k = 1 << j;
        let level = min(j + 1u, P.top);
        if (2 * k + 1 > 16 * (1 << level)) {
            // more than 16 nodes a side: the pyramid's top level is too fine to bound this box
            // cheaply (maps whose sides few powers of two divide). Bound every farther point by
            // the map's maximum instead: conservative, and the build stays O(1) per cell.
            // Power-of-two maps never come here (their nodes grow with the box).
            let rho_far = select(0.5 * f32(k), f32(k), relaxed);
            if (P.global_max > base) {
                w = min(w, rho_far / (P.global_max - base));
            }
            break;
        }
        let mk = box_max(c, k, level);
        // conservative: the interval's near end 2^(j-1); relaxed: its far end 2^j
        let rho = select(0.5 * f32(k), f32(k), relaxed);
        if (mk > base) {
            w = min(w, rho / (mk - base));
        }
        if (2 * k + 1 >= span) {
            // the box covers the map: mk is the global max, which bounds every farther point
            break;
        }
    }
    textureStore(cone_base_out, c, vec4<f32>(base, 0.0, 0.0, 0.0));
    textureStore(cone_w_out, c, vec4<f32>(w, 0.0, 0.0, 0.0));
}

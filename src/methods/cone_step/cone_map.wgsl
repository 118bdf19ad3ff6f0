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
// Relaxed cones take base = the cell's own max and measure each interval at its far end:
// wider, not conservative (a ray may step into a feature), refined by a binary search.

struct ConeParams {
    size: vec2<u32>,
    top: u32,
    relaxed: u32,
    offsets: array<vec4<u32>, 4>,
}

@group(0) @binding(0) var<storage, read> maxb: array<f32>;
@group(0) @binding(1) var<uniform> P: ConeParams;
// a storage buffer, not an Rg32Float storage texture: the GL backend has no two-channel
// storage textures
@group(0) @binding(2) var<storage, read_write> cones: array<vec2<f32>>;

fn floor_div(a: vec2<i32>, s: i32) -> vec2<i32> {
    return vec2<i32>(floor(vec2<f32>(a) / f32(s)));
}

// the max of node n (wrapped) at a level of the pyramid
fn node_max(n: vec2<i32>, level: u32) -> f32 {
    let d = vec2<i32>(max(P.size >> vec2<u32>(level), vec2<u32>(1u)));
    let w = n - vec2<i32>(floor(vec2<f32>(n) / vec2<f32>(d))) * d;
    let off = P.offsets[level / 4u][level % 4u];
    return maxb[off + u32(w.y * d.x + w.x)];
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
fn build(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= P.size.x || id.y >= P.size.y) {
        return;
    }
    let c = vec2<i32>(id.xy);
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
        let mk = box_max(c, k, min(j + 1u, P.top));
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
    cones[id.y * P.size.x + id.x] = vec2<f32>(base, w);
}

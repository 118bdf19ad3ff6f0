// height.wgsl: sampling the height field (and the albedo), its normal, the mip level of a
// footprint, and the max-mip pyramid. The height field is bilinear between texel centres and
// repeats. The two filtering paths agree up to the adapter's filter-weight precision;
// FILTERING_EXACT (four loads and a float32 lerp) removes that source of error.
//
// Shader defs: FILTERING_HARDWARE or FILTERING_EXACT (`Filtering::shader_def`).
#define_import_path pomkit::height

#import pomkit::object::{G, height_tex, height_samp, albedo_tex, albedo_samp, max0_tex, max_atlas}
#import pomkit::basis::Basis
#import pomkit::cost::fetched

// x mod n in [0, n), also for negative x. Written with f32 floor: on lavapipe (Mesa 22.3)
// integer `%` and `>>` on negative i32 gave wrong results in the max-mip traversal.
fn wrap_i(x: i32, n: i32) -> i32 {
    let q = i32(floor(f32(x) / f32(n)));
    return clamp(x - q * n, 0, n - 1);
}

// The four texels around a point of a repeating grid, and the bilinear weights: the one
// bilinear fetch of pomkit (height field, Exact's cells).
struct Taps {
    xa: i32,
    xb: i32,
    ya: i32,
    yb: i32,
    fr: vec2<f32>,
}

// The texels of cell `c` (texel centres c .. c + 1, wrapped) with weights `fr`.
fn cell_taps(c: vec2<i32>, dims: vec2<i32>, fr: vec2<f32>) -> Taps {
    var t: Taps;
    t.xa = wrap_i(c.x, dims.x);
    t.ya = wrap_i(c.y, dims.y);
    // the next texel, wrapped: the same as wrap_i(c + 1) without a second division
    t.xb = select(t.xa + 1, 0, t.xa + 1 >= dims.x);
    t.yb = select(t.ya + 1, 0, t.ya + 1 >= dims.y);
    t.fr = fr;
    return t;
}

// The taps at texture coordinate `s` (texel centres at (i + 0.5) / dims).
fn bilinear_taps(s: vec2<f32>, dims: vec2<i32>) -> Taps {
    let p = s * vec2<f32>(dims) - 0.5;
    let p0 = floor(p);
    return cell_taps(vec2<i32>(p0), dims, p - p0);
}

fn bilerp(t: Taps, a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32>) -> vec4<f32> {
    return mix(mix(a, b, t.fr.x), mix(c, d, t.fr.x), t.fr.y);
}

fn height_texel(x: i32, y: i32, level: i32) -> vec4<f32> {
    return textureLoad(height_tex, vec2<i32>(x, y), level);
}

fn height_exact_level(s: vec2<f32>, level: i32) -> f32 {
    let t = bilinear_taps(s, vec2<i32>(textureDimensions(height_tex, level)));
    return bilerp(t, height_texel(t.xa, t.ya, level), height_texel(t.xb, t.ya, level),
                  height_texel(t.xa, t.yb, level), height_texel(t.xb, t.yb, level)).r;
}

fn num_mips() -> f32 {
    return G.mip_count;
}

// The height at texture coordinate s (tiled units), at mip level `lod` (trilinear), uncounted
// (the shading normal's samples).
fn sample_height(s: vec2<f32>, lod: f32) -> f32 {
#ifdef FILTERING_EXACT
    let l0 = i32(floor(lod));
    let fl = lod - f32(l0);
    let a = height_exact_level(s, l0);
    if (fl <= 0.0) {
        return a;
    }
    let top = i32(num_mips()) - 1;
    let b = height_exact_level(s, min(l0 + 1, top));
    return mix(a, b, fl);
#else
    return textureSampleLevel(height_tex, height_samp, s, lod).r;
#endif
}

// The height at texture coordinate s (tiled units), at mip level `lod` (trilinear): a sample
// of the search, counted (cost.wgsl). Exact filtering loads 4 texels per level; the hardware
// filter is one fetch reading 4 texels per level.
fn height_at(s: vec2<f32>, lod: f32) -> f32 {
    let levels = select(2u, 1u, lod == floor(lod));
#ifdef FILTERING_EXACT
    fetched(4u * levels, 16u * levels);
#else
    fetched(1u, 16u * levels);
#endif
    return sample_height(s, lod);
}

// Shading normal of the displaced surface, world space, from central differences of the
// height field (one texel of the level in use). Shared by every method and by the tessellated
// reference, so that a shading difference is a geometry difference.
fn height_normal(f: Basis, s: vec2<f32>, lod: f32) -> vec3<f32> {
    let texel = exp2(max(floor(lod), 0.0)) / G.map_size;
    let hx = sample_height(s + vec2<f32>(texel.x, 0.0), lod) - sample_height(s - vec2<f32>(texel.x, 0.0), lod);
    let hy = sample_height(s + vec2<f32>(0.0, texel.y), lod) - sample_height(s - vec2<f32>(0.0, texel.y), lod);
    // d(world height)/d(world distance along t) = depth * dh/ds * ds/du / (world per u)
    let gx = G.depth * hx / (2.0 * texel.x) * G.tiling / f.scale.x;
    let gy = G.depth * hy / (2.0 * texel.y) * G.tiling / f.scale.y;
    return normalize(f.t * (-gx) + f.b * (-gy) + f.n);
}

fn albedo_at(s: vec2<f32>, lod: f32) -> vec3<f32> {
    return textureSampleLevel(albedo_tex, albedo_samp, s, lod).rgb;
}

// The level the height field is sampled at: the footprint's (Tatarchuk's tex2Dgrad) or level 0.
fn height_lod(lod: f32) -> f32 {
    return select(0.0, lod, G.mip_filtering > 0.5);
}

// Mip level from the texture-space footprint; call in uniform control flow (before loops).
fn compute_lod(s: vec2<f32>) -> f32 {
    return footprint_lod(dpdx(s), dpdy(s));
}

// Mip level of the footprint whose texture-space sides are `ds_dx` and `ds_dy` (one pixel right,
// one down).
fn footprint_lod(ds_dx: vec2<f32>, ds_dy: vec2<f32>) -> f32 {
    let px = ds_dx * G.map_size;
    let py = ds_dy * G.map_size;
    let rho = max(dot(px, px), dot(py, py));
    let lod = 0.5 * log2(max(rho, 1e-20));
    return clamp(lod, 0.0, num_mips() - 1.0);
}

// ---- the max-mip pyramid (level 0 and an atlas of the levels above: see object.wgsl) ----

fn max_level_dims(level: i32) -> vec2<i32> {
    return max(vec2<i32>(G.map_size) >> vec2<u32>(u32(level)), vec2<i32>(1));
}

fn max_at(node: vec2<i32>, level: i32) -> f32 {
    let dims = max_level_dims(level);
    let p = vec2<i32>(wrap_i(node.x, dims.x), wrap_i(node.y, dims.y));
    fetched(1u, 4u);
    // every load at mip level 0 of its texture (see maxmip.wgsl)
    if (level == 0) {
        return textureLoad(max0_tex, p, 0).r;
    }
    let off = i32(G.max_offsets[level / 4][level % 4]);
    return textureLoad(max_atlas, p + vec2<i32>(off, 0), 0).r;
}

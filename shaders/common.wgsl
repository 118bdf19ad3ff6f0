// common.wgsl: uniforms, vertex interface, the texture-space frame, height sampling and
// shading shared by every method. Concatenated before the other files (see src/render.rs).
//
// Conventions (docs/conventions.md): h = 1 is the base surface, h = 0 lies `depth` below it
// along the base normal. A texture-space ray is (s, h) with s = uv * tiling in height-map
// uv units; a direction is expressed "per unit of world length" so that distances come out
// in world units.

const PI: f32 = 3.14159265358979;
const MAX_LIGHTS: u32 = 4u;

// ---- pipeline-specialisation constants (one pipeline per combination) ----
// METHOD: 0 Flat, 1 Bump, 2 POM, 3 Parallax, 4 SteepParallax, 5 Relief,
//         6 Tessellated (the displaced mesh, rasterised), 7 Exact (max-mip traversal), 8 NCS
override METHOD: u32 = 0u;
// SHADOWS: 0 none, 1 hard, 2 soft, 3 horizon (max-mip horizon angle), 4 exact (Exact only)
override SHADOWS: u32 = 0u;
// FILTERING: 0 hardware (sampler bilinear/trilinear), 1 exact (4 textureLoads, f32 lerp)
override FILTERING: u32 = 0u;

struct Light {
    // xyz: direction of travel (directional) or position (sphere); w: 0 directional, 1 sphere
    vec: vec4<f32>,
    // rgb: irradiance (directional) or radiant intensity (sphere); w: tan(angular radius)
    // for directional lights, sphere radius for sphere lights
    color: vec4<f32>,
}

struct Globals {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,        // xyz eye, w: number of lights
    tex: vec4<f32>,        // height W, H, tiling, depth
    march: vec4<f32>,      // min_steps, max_steps, shadow_steps, lod_threshold
    extra: vec4<f32>,      // x adaptive(1)/fixed(0), y mip filtering(1)/level 0(0), z ao directions, w horizon samples
    params: vec4<f32>,     // x parallax scale, y parallax bias, z offset limiting, w max iterations (Exact)
    params2: vec4<f32>,    // x binary steps (Relief), y depth bias (Relief), z top max-mip level, w exact (Prism)
    ambient: vec4<f32>,    // rgb constant environment radiance, w: number of mip levels
    lights: array<Light, 4>,
    // Tessellated's shadow map: light view-projection, and x: index of the shadowed light
    // (-1: none), y: world size of a shadow-map texel, z: map size in texels
    shadow_vp: mat4x4<f32>,
    shadow: vec4<f32>,
    // element offset of each max-pyramid level in max_buf
    max_offsets: array<vec4<u32>, 4>,
}

@group(0) @binding(0) var<uniform> G: Globals;
@group(0) @binding(1) var height_tex: texture_2d<f32>;
@group(0) @binding(2) var height_samp: sampler;
@group(0) @binding(3) var albedo_tex: texture_2d<f32>;
@group(0) @binding(4) var albedo_samp: sampler;
@group(0) @binding(5) var shadow_tex: texture_depth_2d;
@group(0) @binding(6) var shadow_samp: sampler_comparison;
// max-mip pyramid, levels back to back: level 0 holds the max of the bilinear field over each
// cell between texel centres (cell (i, j) spans texel centres i..i+1, j..j+1), level k the max
// over 2^k x 2^k cells
@group(0) @binding(7) var<storage, read> max_buf: array<f32>;

fn max_level_dims(level: i32) -> vec2<i32> {
    return max(vec2<i32>(G.tex.xy) >> vec2<u32>(u32(level)), vec2<i32>(1));
}

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    // world length per unit of u and of v (S_tangent, S_binormal of Chen & Chang)
    @location(4) uv_scale: vec2<f32>,
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv_scale: vec2<f32>,
}

// Targets are Rgba32Uint holding float32 bits: exact float32 AOVs on every backend (GL cannot
// render to Rgba32Float). See `write_aovs`.
struct FsOut {
    // rgb: linear radiance (float bits), a: steps (low 28 bits) | flags << 28
    @location(0) color: vec4<u32>,
    // xy: hit uv (mesh space, unwrapped), z: distance eye -> hit, w: mip level used
    @location(1) geo: vec4<u32>,
}

// flags (AOV `flags`): 1 = the march hit its iteration bound (Exact) or ended early
const FLAG_BOUND: u32 = 1u;

fn write_aovs(color: vec3<f32>, steps: u32, flags: u32, uv: vec2<f32>, dist: f32, lod: f32) -> FsOut {
    var o: FsOut;
    let c = bitcast<vec3<u32>>(color);
    o.color = vec4<u32>(c, min(steps, 0x0fffffffu) | (flags << 28u));
    o.geo = bitcast<vec4<u32>>(vec4<f32>(uv, dist, lod));
    return o;
}

// Orthonormal base frame at a fragment and the world-per-uv scale.
struct Frame {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
    scale: vec2<f32>,
}

fn make_frame(n_in: vec3<f32>, t_in: vec4<f32>, scale: vec2<f32>) -> Frame {
    var f: Frame;
    f.n = normalize(n_in);
    var t = t_in.xyz - f.n * dot(t_in.xyz, f.n);
    if (dot(t, t) < 1e-12) {
        // degenerate tangent: any vector orthogonal to n
        let a = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(f.n.x) > 0.9);
        t = cross(f.n, a);
    }
    f.t = normalize(t);
    let w = select(1.0, -1.0, t_in.w < 0.0);
    f.b = w * cross(f.n, f.t);
    f.scale = max(scale, vec2<f32>(1e-12));
    return f;
}

// A world direction expressed in texture space per unit of world length: (ds_u, ds_v, dh).
fn to_texture_space(f: Frame, d: vec3<f32>) -> vec3<f32> {
    let tiling = G.tex.z;
    let depth = max(G.tex.w, 1e-12);
    return vec3<f32>(
        tiling * dot(d, f.t) / f.scale.x,
        tiling * dot(d, f.b) / f.scale.y,
        dot(d, f.n) / depth,
    );
}

fn num_mips() -> f32 {
    return G.ambient.w;
}

// ---- height sampling ----
// The height field is bilinear between texel centres and repeats. Both paths agree up to the
// adapter's filter-weight precision; FILTERING = 1 removes that source of error.

// x mod n in [0, n), also for negative x. Written with f32 floor: on lavapipe (Mesa 22.3)
// integer `%` and `>>` on negative i32 gave wrong results in the max-mip traversal.
fn wrap_i(x: i32, n: i32) -> i32 {
    let q = i32(floor(f32(x) / f32(n)));
    return clamp(x - q * n, 0, n - 1);
}

fn height_exact_level(s: vec2<f32>, level: i32) -> f32 {
    let dims = vec2<i32>(textureDimensions(height_tex, level));
    let p = s * vec2<f32>(dims) - 0.5;
    let p0 = floor(p);
    let fr = p - p0;
    let i0 = vec2<i32>(p0);
    let x0 = wrap_i(i0.x, dims.x);
    let x1 = wrap_i(i0.x + 1, dims.x);
    let y0 = wrap_i(i0.y, dims.y);
    let y1 = wrap_i(i0.y + 1, dims.y);
    let h00 = textureLoad(height_tex, vec2<i32>(x0, y0), level).r;
    let h10 = textureLoad(height_tex, vec2<i32>(x1, y0), level).r;
    let h01 = textureLoad(height_tex, vec2<i32>(x0, y1), level).r;
    let h11 = textureLoad(height_tex, vec2<i32>(x1, y1), level).r;
    return mix(mix(h00, h10, fr.x), mix(h01, h11, fr.x), fr.y);
}

fn height_at(s: vec2<f32>, lod: f32) -> f32 {
    if (FILTERING == 1u) {
        let l0 = i32(floor(lod));
        let fl = lod - f32(l0);
        let a = height_exact_level(s, l0);
        if (fl <= 0.0) {
            return a;
        }
        let top = i32(num_mips()) - 1;
        let b = height_exact_level(s, min(l0 + 1, top));
        return mix(a, b, fl);
    }
    return textureSampleLevel(height_tex, height_samp, s, lod).r;
}

// Shading normal of the displaced surface, world space, from central differences of the
// height field (one texel of the level in use). Shared by every method and by the tessellated
// reference, so that a shading difference is a geometry difference.
fn height_normal(f: Frame, s: vec2<f32>, lod: f32) -> vec3<f32> {
    let texel = exp2(max(floor(lod), 0.0)) / G.tex.xy;
    let hx = height_at(s + vec2<f32>(texel.x, 0.0), lod) - height_at(s - vec2<f32>(texel.x, 0.0), lod);
    let hy = height_at(s + vec2<f32>(0.0, texel.y), lod) - height_at(s - vec2<f32>(0.0, texel.y), lod);
    // d(world height)/d(world distance along t) = depth * dh/ds * ds/du / (world per u)
    let gx = G.tex.w * hx / (2.0 * texel.x) * G.tex.z / f.scale.x;
    let gy = G.tex.w * hy / (2.0 * texel.y) * G.tex.z / f.scale.y;
    return normalize(f.t * (-gx) + f.b * (-gy) + f.n);
}

fn albedo_at(s: vec2<f32>, lod: f32) -> vec3<f32> {
    return textureSampleLevel(albedo_tex, albedo_samp, s, lod).rgb;
}

// The level the height field is sampled at: the footprint's (Tatarchuk's tex2Dgrad) or level 0.
fn height_lod(lod: f32) -> f32 {
    return select(0.0, lod, G.extra.y > 0.5);
}

// Mip level from the texture-space footprint; call in uniform control flow (before loops).
fn compute_lod(s: vec2<f32>) -> f32 {
    let px = dpdx(s) * G.tex.xy;
    let py = dpdy(s) * G.tex.xy;
    let rho = max(dot(px, px), dot(py, py));
    let lod = 0.5 * log2(max(rho, 1e-20));
    return clamp(lod, 0.0, num_mips() - 1.0);
}

// Direction toward light `i` from world point `p`, and the irradiance it delivers on a surface
// facing it (for sphere lights: I / r^2).
struct LightSample {
    dir: vec3<f32>,
    e: vec3<f32>,
    tan_radius: f32,
}

fn light_sample(i: u32, p: vec3<f32>) -> LightSample {
    let l = G.lights[i];
    var ls: LightSample;
    if (l.vec.w < 0.5) {
        ls.dir = normalize(-l.vec.xyz);
        ls.e = l.color.rgb;
        ls.tan_radius = l.color.w;
    } else {
        let d = l.vec.xyz - p;
        let r2 = max(dot(d, d), 1e-12);
        ls.dir = d / sqrt(r2);
        ls.e = l.color.rgb / r2;
        ls.tan_radius = l.color.w / sqrt(max(r2 - l.color.w * l.color.w, 1e-12));
    }
    return ls;
}

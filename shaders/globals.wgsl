// globals.wgsl: the uniform blocks and the bindings every pass of the surface shares.
#define_import_path pomkit::globals

const PI: f32 = 3.14159265358979;
// the size of the light array: src/scene/mod.rs's MAX_LIGHTS, a shader def of this module
const MAX_LIGHTS: u32 = #{MAX_LIGHTS}u;

struct Light {
    // xyz: direction of travel (directional) or position (sphere); w: 0 directional, 1 sphere
    vec: vec4<f32>,
    // rgb: irradiance (directional) or radiant intensity (sphere); w: tan(angular radius)
    // for directional lights, sphere radius for sphere lights
    color: vec4<f32>,
}

// Bind groups by how often they change (as Bevy's): group 0 the view and frame (camera,
// lights, the shadow map), group 1 the object and its material (its transform, its height map
// and pyramids, its albedo), group 2 the method (its `params` block at binding 0, generated
// from the method's Rust parameter list, and its own resources from binding 1, declared in its
// folder under src/methods/). The Rust side is `render::uniforms::{View, ObjectUniforms}`; a test
// (tests/rust/uniform_layout.rs) checks that every field has the same name and
// offset on both sides.

struct View {
    view_proj: mat4x4<f32>,
    eye: vec3<f32>,
    light_count: f32,
    // constant environment radiance
    ambient: vec3<f32>,
    // k of a supersampled pass's k x k samples per pixel (1 otherwise): the exact shadows share
    // their direction sets among a pixel's samples (shadows.wgsl's sample_share)
    spp_k: f32,
    lights: array<Light, MAX_LIGHTS>,
    // the shadow map: light view-projection, index of the shadowed light (-1: none), world size
    // of a shadow-map texel, map size in texels
    shadow_vp: mat4x4<f32>,
    shadow_light: f32,
    shadow_texel: f32,
    shadow_size: f32,
    // depth bias of the cast-shadow lookup: two shadow-map texels, in depth units
    shadow_bias: f32,
    // the pass's width in pixels (the fragment counter's row length: cost.wgsl)
    frame_width: f32,
    pad_va: f32,
    pad_vb: f32,
    pad_vc: f32,
}

struct ObjectUniforms {
    // height map size in texels
    map_size: vec2<f32>,
    tiling: f32,
    depth: f32,
    mip_count: f32,
    // options shared by the per-pixel methods
    shadow_steps: f32,
    lod_threshold: f32,
    // 1: sample the footprint's mip level (tex2Dgrad), 0: level 0
    mip_filtering: f32,
    ao_directions: f32,
    horizon_samples: f32,
    // the highest max-mip level whose nodes tile the map
    top_max_level: f32,
    // bound on the iterations of every max-mip traversal
    max_iterations: f32,
    // x offset of each max-pyramid level k >= 1 in max_atlas (src/heightmap/mod.rs's max_atlas)
    max_offsets: array<vec4<u32>, 4>,
    // the object drawn (one block per object; see object.wgsl): object-to-world matrix, the
    // inverse transpose (normals), the inverse (world-to-object), the eye in object space, the
    // object's index (the `object` AOV), 1 when the transform is not the identity
    model: mat4x4<f32>,
    normal_mat: mat4x4<f32>,
    model_inv: mat4x4<f32>,
    eye_object: vec3<f32>,
    object_id: f32,
    transformed: f32,
    pad_c: f32,
    pad_d: f32,
    pad_e: f32,
}

@group(0) @binding(0) var<uniform> V: View;
@group(0) @binding(1) var shadow_tex: texture_depth_2d;
@group(0) @binding(2) var shadow_samp: sampler_comparison;

@group(1) @binding(0) var<uniform> G: ObjectUniforms;
@group(1) @binding(1) var height_tex: texture_2d<f32>;
@group(1) @binding(2) var height_samp: sampler;
@group(1) @binding(3) var albedo_tex: texture_2d<f32>;
@group(1) @binding(4) var albedo_samp: sampler;
// max-mip pyramid: level 0 holds the max of the bilinear field over each cell between texel
// centres (cell (i, j) spans texel centres i..i+1, j..j+1), level k the max over 2^k x 2^k
// cells. Level 0 is a texture of the map's size, levels 1.. lie side by side in an atlas (level
// k at x = max_offsets[k], y = 0): textures stay within any limit a map within
// max_texture_dimension_2d does, where one buffer of every level exceeded the storage binding
// limit from 8192² on.
@group(1) @binding(5) var max0_tex: texture_2d<f32>;
@group(1) @binding(6) var max_atlas: texture_2d<f32>;
// The same levels 1 ..= top again, each node's texel holding its four children's maxes (x: child
// (0, 1), y: (1, 1), z: (1, 0), w: (0, 0), as a gather), level 1 at (0, 0) and levels 2.. in a
// column to its right (src/heightmap/mod.rs's children_atlas): the max-mip walk reads a node's children
// with one load, and descends only into a child the ray dips below (maxmip.wgsl).
@group(1) @binding(7) var max_children: texture_2d<f32>;

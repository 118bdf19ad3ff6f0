// object.wgsl: the object drawn (bind group 1: its uniforms, its height map and pyramids, its
// albedo) and its transform. Every mesh lives in object space and the methods march
// there (the displacement `depth` is in object units, along the object-space normal); positions
// go to world space for the depth buffer, the lights and the shadow map, normals for the light
// model. An untransformed object skips the arithmetic (a uniform branch), so that its results are
// bit-identical to a scene without transforms; in a frame without transforms (no shader def
// TRANSFORMED) the arithmetic is compiled out, as a branch costs both its sides on lavapipe.
#define_import_path pomkit::object

#import pomkit::view::V

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

// group 1's bindings, in the order and with the names of src/render/object_group.rs's
// OBJECT_GROUP (a test there holds these declarations to it)
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

fn is_transformed() -> bool {
#ifdef TRANSFORMED
    return G.transformed > 0.5;
#else
    return false;
#endif
}

// An object-space position in clip space through `clip_from_world` (the camera's or the light's).
fn to_clip(p: vec3<f32>, clip_from_world: mat4x4<f32>) -> vec4<f32> {
    return clip_from_world * vec4<f32>(to_world(p), 1.0);
}

// An object-space point in world space.
fn to_world(p: vec3<f32>) -> vec3<f32> {
    if (is_transformed()) {
        return (G.model * vec4<f32>(p, 1.0)).xyz;
    }
    return p;
}

// An object-space normal in world space (unit).
fn normal_to_world(n: vec3<f32>) -> vec3<f32> {
    if (is_transformed()) {
        return normalize((G.normal_mat * vec4<f32>(n, 0.0)).xyz);
    }
    return n;
}

// A world direction in object space (unit).
fn dir_to_object(d: vec3<f32>) -> vec3<f32> {
    if (is_transformed()) {
        return normalize((G.model_inv * vec4<f32>(d, 0.0)).xyz);
    }
    return d;
}

// World length of a unit object-space direction: object distances along it times this are
// world distances.
fn stretch(v: vec3<f32>) -> f32 {
    if (is_transformed()) {
        return length((G.model * vec4<f32>(v, 0.0)).xyz);
    }
    return 1.0;
}

// The depth-buffer value of a world point. A grazing ray can march past the mesh's edge (the
// map tiles on), beyond the far plane: such hits keep the largest depth below the cleared 1.0,
// so that they still pass the depth test.
fn clip_depth(p: vec3<f32>) -> f32 {
    let c = V.view_proj * vec4<f32>(p, 1.0);
    return clamp(c.z / c.w, 0.0, 0.99999994);
}

// The shadow map's depth of a world point (the light's orthographic projection).
fn shadow_depth(p: vec3<f32>) -> f32 {
    let c = V.shadow_vp * vec4<f32>(p, 1.0);
    return clamp(c.z / c.w, 0.0, 0.99999994);
}

// The shadow-map pass's view direction: the shadowing light's direction of travel, in object
// space (unit).
fn shadow_light_object() -> vec3<f32> {
    return dir_to_object(V.lights[u32(max(V.shadow_light, 0.0))].vec.xyz);
}

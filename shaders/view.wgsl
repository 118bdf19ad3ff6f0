// view.wgsl: what a pass sees from (bind group 0): the camera, the lights, the shadow map, and
// the light model's constants.
#define_import_path pomkit::view

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
// folder under src/methods/). The Rust side is `render::uniforms::{View, ObjectUniforms}` (ObjectUniforms and group 1: object.wgsl); a test
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

@group(0) @binding(0) var<uniform> V: View;
@group(0) @binding(1) var shadow_tex: texture_depth_2d;
@group(0) @binding(2) var shadow_samp: sampler_comparison;

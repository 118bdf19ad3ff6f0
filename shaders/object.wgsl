// object.wgsl: the object's transform. Every mesh lives in object space and the methods march
// there (the displacement `depth` is in object units, along the object-space normal); positions
// go to world space for the depth buffer, the lights and the shadow map, normals for the light
// model. An untransformed object skips the arithmetic (a uniform branch), so that its results are
// bit-identical to a scene without transforms; in a frame without transforms (no shader def
// TRANSFORMED) the arithmetic is compiled out, as a branch costs both its sides on lavapipe.
#define_import_path pomkit::object

#import pomkit::globals::{G, V}

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

//! The uniform blocks of shaders/view.wgsl and shaders/object.wgsl, filled from the scene and the method's spec:
//! `View` (bind group 0, per frame) and `ObjectUniforms` (bind group 1, per object).
//! `tests/rust/uniform_layout.rs` checks that every field has the same name and offset in Rust and
//! in the composed WGSL.

use crate::contract::Spec;
use crate::heightmap::{max_offset_table, mip_count, top_maxmip_level};
use crate::scene::{Light, Scene, MAX_LIGHTS};
use glam::DVec3;

/// A `#[repr(C)]` Pod struct with a table of its fields' names and offsets.
macro_rules! uniform_struct {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty,)* }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $f: $t,)* }
        impl $name {
            /// (name, byte offset) of every field, for the layout test
            pub const FIELDS: &'static [(&'static str, usize)] = &[$((stringify!($f), std::mem::offset_of!($name, $f)),)*];
        }
    };
}

uniform_struct! {
    pub struct LightU {
        pub vec: [f32; 4],
        pub color: [f32; 4],
    }
}

uniform_struct! {
    /// shaders/view.wgsl's `View` (bind group 0): see the comments there.
    pub struct View {
        pub view_proj: [[f32; 4]; 4],
        pub eye: [f32; 3],
        pub light_count: f32,
        pub ambient: [f32; 3],
        pub spp_k: f32,
        pub lights: [LightU; MAX_LIGHTS],
        pub shadow_vp: [[f32; 4]; 4],
        pub shadow_light: f32,
        pub shadow_texel: f32,
        pub shadow_size: f32,
        pub shadow_bias: f32,
        pub frame_width: f32,
        pub pad_va: f32,
        pub pad_vb: f32,
        pub pad_vc: f32,
    }
}

uniform_struct! {
    /// shaders/object.wgsl's `ObjectUniforms` (bind group 1, one per object): see the comments there.
    pub struct ObjectUniforms {
        pub map_size: [f32; 2],
        pub tiling: f32,
        pub depth: f32,
        pub mip_count: f32,
        pub shadow_steps: f32,
        pub lod_threshold: f32,
        pub mip_filtering: f32,
        pub ao_directions: f32,
        pub horizon_samples: f32,
        pub top_max_level: f32,
        pub max_iterations: f32,
        pub max_offsets: [[u32; 4]; 4],
        pub model: [[f32; 4]; 4],
        pub normal_mat: [[f32; 4]; 4],
        pub model_inv: [[f32; 4]; 4],
        pub eye_object: [f32; 3],
        pub object_id: f32,
        pub transformed: f32,
        pub pad_c: f32,
        pub pad_d: f32,
        pub pad_e: f32,
    }
}

fn light_uniform(light: &Light) -> LightU {
    let e = light.power();
    match light {
        Light::Directional(l) => {
            let d = DVec3::from(l.direction).normalize();
            LightU {
                vec: [d.x as f32, d.y as f32, d.z as f32, 0.0],
                color: [
                    e[0],
                    e[1],
                    e[2],
                    (l.angular_diameter.to_radians() * 0.5).tan() as f32,
                ],
            }
        }
        Light::Sphere(l) => {
            let p = l.position;
            LightU {
                vec: [p[0] as f32, p[1] as f32, p[2] as f32, 1.0],
                color: [e[0], e[1], e[2], l.radius as f32],
            }
        }
    }
}

/// The view block of a frame; `shadow` is the shadow map's set-up (light index,
/// view-projection, texel size, map size) when the pass has one.
pub fn view(scene: &Scene, shadow: Option<&super::shadow_map::ShadowSetup>) -> View {
    let (c, r) = scene.bounding_sphere();
    let d = (DVec3::from(scene.camera.eye) - c).length();
    let far = (d + r) * 1.01 + 1e-3;
    let near = (d - r).max(far * 1e-5);
    let mut lights = [LightU {
        vec: [0.0; 4],
        color: [0.0; 4],
    }; MAX_LIGHTS];
    for (i, l) in scene.lights.iter().enumerate() {
        lights[i] = light_uniform(l);
    }
    let cam = &scene.camera;
    View {
        view_proj: cam.view_proj(near, far).to_cols_array_2d(),
        eye: [cam.eye[0] as f32, cam.eye[1] as f32, cam.eye[2] as f32],
        light_count: scene.lights.len() as f32,
        ambient: scene.ambient,
        spp_k: scene.camera.samples.max(1) as f32,
        lights,
        shadow_vp: shadow.map(|s| s.view_proj).unwrap_or([[0.0; 4]; 4]),
        shadow_light: shadow.map(|s| s.light as f32).unwrap_or(-1.0),
        shadow_texel: shadow.map(|s| s.texel).unwrap_or(0.0),
        shadow_size: shadow.map(|s| s.size as f32).unwrap_or(1.0),
        shadow_bias: shadow.map(|s| s.bias).unwrap_or(0.0),
        frame_width: scene.camera.width as f32,
        pad_va: 0.0,
        pad_vb: 0.0,
        pad_vc: 0.0,
    }
}

/// The object block of object `id` of `scene` drawn with `spec`.
pub fn object_uniforms(scene: &Scene, id: usize, spec: &Spec) -> ObjectUniforms {
    let obj = &scene.objects[id];
    let hm = &obj.material.height;
    let tr = &obj.transform;
    let inv = tr.m.inverse();
    let eye_o = inv.transform_point3(DVec3::from(scene.camera.eye));
    let m4 = |m: glam::DMat4| m.as_mat4().to_cols_array_2d();
    let o = &spec.pixel;
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    let cam = &scene.camera;
    ObjectUniforms {
        map_size: [hm.width as f32, hm.height as f32],
        tiling: obj.material.tiling,
        depth: obj.material.depth,
        mip_count: mip_count(hm.width, hm.height) as f32,
        shadow_steps: o.shadow_steps as f32,
        lod_threshold: spec.lod_threshold,
        mip_filtering: flag(o.mip_filtering),
        ao_directions: o.ao_directions as f32,
        horizon_samples: o.horizon_samples as f32,
        top_max_level: top_maxmip_level(hm.width, hm.height) as f32,
        max_iterations: spec.max_iterations as f32,
        max_offsets: max_offset_table(hm.width, hm.height),
        model: m4(tr.m),
        normal_mat: m4(inv.transpose()),
        model_inv: m4(inv),
        eye_object: if tr.is_identity() {
            [cam.eye[0] as f32, cam.eye[1] as f32, cam.eye[2] as f32]
        } else {
            [eye_o.x as f32, eye_o.y as f32, eye_o.z as f32]
        },
        object_id: id as f32,
        transformed: flag(!tr.is_identity()),
        pad_c: 0.0,
        pad_d: 0.0,
        pad_e: 0.0,
    }
}

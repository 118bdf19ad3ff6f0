// lights.wgsl: the direction toward a light and the irradiance it delivers. Sphere lights only
// in frames that have one (shader def SPHERE_LIGHTS): elsewhere the branch is compiled out.
#define_import_path pomkit::lights

#import pomkit::view::V

struct LightSample {
    dir: vec3<f32>,
    // irradiance on a surface facing the light (sphere lights: I / r^2)
    e: vec3<f32>,
    tan_radius: f32,
}

fn light_sample(i: u32, p: vec3<f32>) -> LightSample {
    let l = V.lights[i];
    var ls: LightSample;
#ifdef SPHERE_LIGHTS
    if (l.vec.w < 0.5) {
#endif
        ls.dir = normalize(-l.vec.xyz);
        ls.e = l.color.rgb;
        ls.tan_radius = l.color.w;
#ifdef SPHERE_LIGHTS
    } else {
        let d = l.vec.xyz - p;
        let r2 = max(dot(d, d), 1e-12);
        ls.dir = d / sqrt(r2);
        ls.e = l.color.rgb / r2;
        ls.tan_radius = l.color.w / sqrt(max(r2 - l.color.w * l.color.w, 1e-12));
    }
#endif
    return ls;
}

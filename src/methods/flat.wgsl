// Flat: the texture at the rasterised uv, lit with the base mesh's normal; no displacement.
#define_import_path pomkit::methods::flat

#import pomkit::basis::Basis
#import pomkit::shading::{shade, Shaded}
#import pomkit::object::normal_to_world

fn shade_surface(f: Basis, s: vec2<f32>, p: vec3<f32>, lod: f32, px: vec2<f32>) -> Shaded {
    return shade(f, s, 1.0, p, normal_to_world(f.n), lod, false, px);
}

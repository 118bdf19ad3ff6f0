// Bump mapping (Blinn 1978): the shading normal from the height field at the rasterised uv, the
// uv unchanged.
#define_import_path pomkit::methods::bump

#import pomkit::basis::Basis
#import pomkit::height::height_normal
#import pomkit::shading::{shade, Shaded}
#import pomkit::object::normal_to_world

fn shade_surface(f: Basis, s: vec2<f32>, p: vec3<f32>, lod: f32, px: vec2<f32>) -> Shaded {
    return shade(f, s, 1.0, p, normal_to_world(height_normal(f, s, lod)), lod, false, px);
}

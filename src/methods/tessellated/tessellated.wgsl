// Tessellated: the rasterised mesh is the displaced surface itself, shaded with the base mesh's
// basis and the height field's level-0 normal at its uv. Its point lies on the field (h = 0 in
// the shading's terms: exact shadows start from the field's own height at s).
#define_import_path pomkit::methods::tessellated

#import pomkit::basis::Basis
#import pomkit::height::height_normal
#import pomkit::shading::{shade, Shaded}
#import pomkit::object::normal_to_world

fn shade_surface(f: Basis, s: vec2<f32>, p: vec3<f32>, lod: f32, px: vec2<f32>) -> Shaded {
    return shade(f, s, 0.0, p, normal_to_world(height_normal(f, s, 0.0)), lod, true, px);
}

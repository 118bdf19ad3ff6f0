// Parallax mapping (Kaneko 2001): one sample, s += (scale * (1 - h) + bias) * P. P is the exact
// parallax vector per unit of height (exact for a constant height with scale 1, bias 0). With
// offset limiting (Welsh 2004) P is not divided by V.z: the offset is multiplied by N.V, which
// bounds it by the height difference at grazing angles.
#define_import_path pomkit::methods::parallax

#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at

fn march(r: Ray) -> Hit {
    let h0 = height_at(r.s, r.lod);
    let d = params.scale * (1.0 - h0) + params.bias;
    var p = r.dsdh;
    if (params.offset_limiting > 0.5) {
        p = r.dsdh * clamp(r.ndotv, 0.0, 1.0);
    }
    return planar_hit(r, r.s + p * d, clamp(1.0 - d, 0.0, 1.0), 1.0, 0u);
}

// A parallax routine as engines ship it, adapted to pomkit's interface: the classic
// "parallax occlusion mapping" loop found in many engines and tutorials (accumulated layer
// depth, a fixed layer count blended by the view angle, one linear interpolation between the
// last two layers), written from the common description rather than copied from any engine.
// Unlike pomkit's POM it accumulates the position (`cur_s -= delta`) instead of computing each
// sample from its index, so rounding grows along the ray, and it always samples level `r.lod`.
// Parameters: params.min_layers, params.max_layers; params.divide_by_z: 1 slides V.xy / V.z per
// unit of depth (the ray's own slope), 0 slides V.xy (the offset limit of Godot 4's shipped
// deep parallax, whose slide stays within one depth however grazing the view).
#import pomkit::march::{Ray, Hit, planar_hit}
#import pomkit::height::height_at

fn march(r: Ray) -> Hit {
    // engines count depth downward: depth = 1 - h
    let layers = mix(params.max_layers, params.min_layers, clamp(r.ndotv, 0.0, 1.0));
    let layer_depth = 1.0 / layers;
    // r.dsdh is V.xy / V.z in texture units per unit of depth; V.z = N.V
    let slide = select(r.dsdh * clamp(r.ndotv, 0.0, 1.0), r.dsdh, params.divide_by_z > 0.5);
    let delta = slide * layer_depth;
    var cur_s = r.s;
    var cur_layer = 0.0;
    var cur_depth = 1.0 - height_at(cur_s, r.lod);
    var steps = 1.0;
    loop {
        if (cur_layer >= cur_depth || steps > params.max_layers + 1.0) {
            break;
        }
        cur_s = cur_s + delta;
        cur_depth = 1.0 - height_at(cur_s, r.lod);
        cur_layer = cur_layer + layer_depth;
        steps = steps + 1.0;
    }
    // interpolate between the last two layers
    let prev_s = cur_s - delta;
    let after = cur_depth - cur_layer;
    let before = (1.0 - height_at(prev_s, r.lod)) - cur_layer + layer_depth;
    let w = select(0.0, after / (after - before), abs(after - before) > 1e-12);
    let s = mix(cur_s, prev_s, w);
    let depth = mix(cur_layer, cur_layer - layer_depth, w);
    return planar_hit(r, s, clamp(1.0 - depth, 0.0, 1.0), steps + 1.0, 0u);
}

// Parallax occlusion mapping (Brawley & Tatarchuk 2004; Tatarchuk 2006): the shared linear
// search in n = n_max + (N.V)(n_min - n_max) steps with an early out, then the intersection
// with the piecewise-linear height profile between the last two samples. The in-shader LOD
// (bump mapping above lod_threshold) is the surface pass's LOD_BLEND, which POM's spec sets.
#define_import_path pomkit::methods::pom

#import pomkit::march::{Ray, Hit, planar_hit, view_segment, view_search, refine_linear, pom_sample_count, segment_s, segment_h}

fn march(r: Ray) -> Hit {
    let n = pom_sample_count(r.ndotv, params.min_steps, params.max_steps, params.adaptive > 0.5);
    let g = view_segment(r);
    let b = view_search(g, n, r.lod);
    let t = refine_linear(b);
    return planar_hit(r, segment_s(g, t), clamp(segment_h(g, t), 0.0, 1.0), b.steps, 0u);
}

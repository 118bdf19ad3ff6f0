// Steep parallax mapping (McGuire & McGuire 2005) written as a pk.Custom method: the same
// shared linear search as the built-in src/methods/steep.wgsl, so it renders bit for bit alike.
// Parameters: params.steps.
#import pomkit::march::{Ray, Hit, planar_hit, view_segment, linear_search, segment_s, segment_h}

fn march(r: Ray) -> Hit {
    let g = view_segment(r);
    let b = linear_search(g, params.steps, r.lod);
    return planar_hit(r, segment_s(g, b.t_cur), segment_h(g, b.t_cur), b.steps, 0u);
}

// Steep parallax mapping (McGuire & McGuire 2005): the shared linear search in `steps` fixed
// height steps, stopping at the first sample below the surface, with no refinement: its
// stair-steps are the baseline.
#define_import_path pomkit::methods::steep

#import pomkit::march::{Ray, Hit, planar_hit, view_segment, view_search, segment_s, segment_h}

fn march(r: Ray) -> Hit {
    let g = view_segment(r);
    let b = view_search(g, params.steps, r.lod);
    return planar_hit(r, segment_s(g, b.t_cur), segment_h(g, b.t_cur), b.steps, 0u);
}

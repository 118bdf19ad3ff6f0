// "Silhouette POM" of the kind that spread through engines in 2026 (three.js PR #33953, closed;
// Terrain3D; several Unity and Unreal packs): parallax occlusion mapping whose hit is discarded
// where it falls outside the texture's [0, 1] uv bounds, so that a planar face's border cuts a
// silhouette without prisms. Our own writing of that description: POM's adaptive linear search
// (params.min_steps to params.max_steps layers by the view angle) and its linear refinement,
// then the clip. It cuts along the uv chart's border only: on a curved mesh the ray still
// marches in the entry's tangent plane (pk.CurvedRelief and pk.NCS bend it).
// Parameters: params.min_steps, params.max_steps.
#import pomkit::march::{Ray, Hit, planar_hit, view_segment, linear_search, refine_linear, segment_s, segment_h, pom_sample_count}
#import pomkit::object::G

fn march(r: Ray) -> Hit {
    let g = view_segment(r);
    let n = pom_sample_count(r.ndotv, params.min_steps, params.max_steps, true);
    let b = linear_search(g, n, r.lod);
    let t = refine_linear(b);
    var hit = planar_hit(r, segment_s(g, t), segment_h(g, t), b.steps, 0u);
    let uv = r.uv + (hit.s - r.s) / G.tiling;
    hit.exited = any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0));
    return hit;
}

// lod.wgsl: Tatarchuk 2006's in-shader level of detail.
// The mip level is computed explicitly from the uv derivatives before any loop (compute_lod in
// common.wgsl). Full POM runs at levels <= lod_threshold; across (threshold - 1, threshold] the
// POM result is blended toward bump mapping by the fractional level; above the threshold only
// bump mapping runs. This is the paper's listing: the transition ends at the threshold, so a
// plane receding to the horizon shows no seam where it crosses it.

// 0: full POM, 1: bump only; in between, the weight of bump mapping.
fn lod_bump_weight(lod: f32) -> f32 {
    let thr = G.march.w;
    return clamp(lod - (thr - 1.0), 0.0, 1.0);
}

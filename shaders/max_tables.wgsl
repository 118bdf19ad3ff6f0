// max_tables.wgsl: the max pyramid (src/heightmap/mod.rs: level 0 and an atlas of the levels above) as
// the compute passes that build a method's tables from it read it (the cone map, the distance
// volume): group 0, bindings 0 and 1; the pass's parameters at 2 and its outputs from 3
// (gpu::TablePass).
#define_import_path pomkit::max_tables

@group(0) @binding(0) var max0_in: texture_2d<f32>;
@group(0) @binding(1) var max_atlas_in: texture_2d<f32>;

// The max of node n (already wrapped) of `level`, whose atlas x offset is `off` (src/heightmap/mod.rs's
// max_atlas). Every load at mip level 0 of its texture (see maxmip.wgsl).
fn max_node(n: vec2<i32>, level: u32, off: u32) -> f32 {
    if (level == 0u) {
        return textureLoad(max0_in, n, 0).r;
    }
    return textureLoad(max_atlas_in, n + vec2<i32>(i32(off), 0), 0).r;
}

// distance_volume.wgsl: the 3-D distance texture of distance mapping (Donnelly 2005), built on
// the GPU from the height map's max pyramid. Voxel space: x, y in nodes of max-pyramid level
// `level` (2^level cells between texel centres each, wrapping), z in slices (the shell's height
// is `slices`). The solid under the surface is bounded, per node column, by the box of the
// node's maximum: [i, i+1] x [j, j+1] x [0, slices * max]. Each voxel stores the distance from
// its centre to the nearest such box within `radius` voxels (radius where there is none): an
// underestimate of the distance to the bilinear field, so a sphere of that radius about any
// point of the voxel, less the voxel's half diagonal, holds no surface.

#import pomkit::max_tables::max_node

struct VolumeParams {
    // the first row of this dispatch's band (gpu::TablePass::run), in rows of y * slices
    band_row: u32,
    slices: u32,
    // volume size in voxels (x, y) and slices (z)
    size: vec2<u32>,
    radius: i32,
    // the level's x offset in the max pyramid's atlas, and the level
    offset: u32,
    level: u32,
    pad0: u32,
}

@group(0) @binding(2) var<uniform> P: VolumeParams;
// 4 header floats (size x, size y, slices, level), then the voxels, x fastest, then y, then z
@group(0) @binding(3) var<storage, read_write> vol: array<f32>;

fn wrap(a: i32, n: i32) -> i32 {
    return ((a % n) + n) % n;
}

@compute @workgroup_size(8, 8)
fn build(@builtin(global_invocation_id) gid: vec3<u32>) {
    let id = vec2<u32>(gid.x, gid.y + P.band_row);
    let w = i32(P.size.x);
    let h = i32(P.size.y);
    let d = i32(P.slices);
    if (i32(id.x) >= w || i32(id.y) >= h * d) {
        return;
    }
    let i = i32(id.x);
    let j = i32(id.y) % h;
    let k = i32(id.y) / h;
    let pz = f32(k) + 0.5;
    let r = P.radius;
    var best = f32(r);
    for (var dj = -r; dj <= r; dj = dj + 1) {
        let dy = max(f32(abs(dj)) - 0.5, 0.0);
        if (dy >= best) {
            continue;
        }
        let row = wrap(j + dj, h);
        for (var di = -r; di <= r; di = di + 1) {
            let dx = max(f32(abs(di)) - 0.5, 0.0);
            let top = max_node(vec2<i32>(wrap(i + di, w), row), P.level, P.offset) * f32(d);
            let dz = max(pz - top, 0.0);
            best = min(best, length(vec3<f32>(dx, dy, dz)));
        }
    }
    vol[4u + (u32(k) * P.size.y + u32(j)) * P.size.x + u32(i)] = best;
}

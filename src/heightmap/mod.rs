//! Mip pyramids of the height map (box-filtered mean for sampling; max-reduced for the
//! hierarchical methods), on the CPU (reference, tests) and on the GPU (what renders use, so
//! that a dynamic height field costs a level-0 upload and a few compute dispatches).

pub mod field;

pub use field::HeightMap;

/// Size of mip level `k` of a `w x h` map (wgpu's rule: halve, floor, at least 1).
pub fn level_size(w: u32, h: u32, k: u32) -> (u32, u32) {
    ((w >> k).max(1), (h >> k).max(1))
}

pub fn mip_count(w: u32, h: u32) -> u32 {
    32 - w.max(h).leading_zeros()
}

/// The one pyramid builder: reduce each level with `op` over its 2x2 footprints (clamped at
/// odd edges), from `level0` of a `w x h` image. Returns all levels, level 0 first. Height maps
/// (mean and max) and albedo mips use it.
pub fn pyramid<T: Copy>(w: u32, h: u32, level0: Vec<T>, op: impl Fn([T; 4]) -> T) -> Vec<Vec<T>> {
    let n = mip_count(w, h);
    let mut levels = vec![level0];
    for k in 1..n {
        let (pw, ph) = level_size(w, h, k - 1);
        let (lw, lh) = level_size(w, h, k);
        let prev = &levels[(k - 1) as usize];
        let at = |x: u32, y: u32| prev[(y.min(ph - 1) * pw + x.min(pw - 1)) as usize];
        let mut out = Vec::with_capacity((lw * lh) as usize);
        for y in 0..lh {
            for x in 0..lw {
                out.push(op([
                    at(2 * x, 2 * y),
                    at(2 * x + 1, 2 * y),
                    at(2 * x, 2 * y + 1),
                    at(2 * x + 1, 2 * y + 1),
                ]));
            }
        }
        levels.push(out);
    }
    levels
}

pub fn mean_pyramid(map: &HeightMap) -> Vec<Vec<f32>> {
    pyramid(map.width, map.height, map.data.clone(), |q| {
        (q[0] + q[1] + q[2] + q[3]) * 0.25
    })
}

pub fn max_pyramid(map: &HeightMap) -> Vec<Vec<f32>> {
    pyramid(map.width, map.height, map.data.clone(), |q| {
        q[0].max(q[1]).max(q[2]).max(q[3])
    })
}

/// Level 0 of the max pyramid: the max of the bilinear field over each cell between texel
/// centres (the four corner texels, wrapping), then 2x2 max reduction above it.
pub fn cell_max_pyramid(map: &HeightMap) -> Vec<Vec<f32>> {
    let (w, h) = (map.width as i64, map.height as i64);
    let mut l0 = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let v = map
                .texel(x, y)
                .max(map.texel(x + 1, y))
                .max(map.texel(x, y + 1))
                .max(map.texel(x + 1, y + 1));
            l0.push(v as f32);
        }
    }
    max_pyramid(&HeightMap {
        width: map.width,
        height: map.height,
        data: l0,
    })
}

/// The height map on the GPU: the sampling texture (mean mips) and the max pyramid.
pub struct GpuHeight {
    pub width: u32,
    pub height: u32,
    pub mips: u32,
    pub tex: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// the max pyramid's level 0 (the map's size)
    pub max0: wgpu::Texture,
    pub max0_view: wgpu::TextureView,
    /// its levels 1.. side by side (`max_atlas`)
    pub max_atlas: wgpu::Texture,
    pub max_atlas_view: wgpu::TextureView,
    /// the max pyramid's levels 1 ..= top again, each node's texel holding its four children's
    /// maxes rounded up to a unorm8 code (`children_atlas`): what the max-mip walk reads
    pub max_children: wgpu::Texture,
    pub max_children_view: wgpu::TextureView,
    /// level k >= 1 of the max pyramid is reduced into this (level 1's size) and copied into the
    /// atlas, so that no dispatch reads and writes one texture
    pub(crate) max_scratch: wgpu::Texture,
    /// Where the adapter cannot write a mip level through a storage view (GL: see
    /// `Capabilities::storage_mip_views`): one single-level texture per level k >= 1, written
    /// by the reduce pass from the previous one and copied into level k. Allocated with the map,
    /// so that `update_height` still allocates nothing.
    pub(crate) scratch: Vec<wgpu::Texture>,
}

/// Where the max pyramid's levels 1.. lie in its atlas: level k at x = `offsets[k]`, y = 0
/// (`offsets[0]` = 0 is level 0's own texture), and the atlas's size. Side by side, the levels
/// of a map within a device's texture limit fit the limit too: their widths sum to less than
/// the map's width plus the number of levels.
pub fn max_atlas(w: u32, h: u32) -> (Vec<u32>, (u32, u32)) {
    let n = mip_count(w, h);
    let mut off = vec![0];
    let mut x = 0;
    for k in 1..n {
        off.push(x);
        x += level_size(w, h, k).0;
    }
    (off, (x.max(1), level_size(w, h, 1).1))
}

/// Where the children atlas (`GpuHeight::max_children`) holds each level k in 1 ..= top
/// (`top_maxmip_level`), and its size: at every node of level k, its four children's maxes
/// (level k - 1) in one `CHILD_MAX_FORMAT` texel, each rounded up to the next code
/// (`CHILD_MAX_CODES`: a max is never understated, so the walk stays exact), so that the max-mip
/// walk reads a node's children with one load of one 32-bit texel. Level 1 at (0, 0), levels
/// 2 .. top in a column to its right, one below the other: level k at (W / 2, H / 2 - 2 H / 2^k), which maxmip.wgsl's `node_children` computes
/// (`offsets[0]` is unused). About 3/8 of the map's texels, 4 bytes each; a map with no level
/// above 0 gets a 1 x 1 texture, never read.
pub fn children_atlas(w: u32, h: u32) -> (Vec<(u32, u32)>, (u32, u32)) {
    let top = top_maxmip_level(w, h);
    let mut off = vec![(0, 0)];
    if top == 0 {
        return (off, (1, 1));
    }
    off.push((0, 0));
    let mut y = 0;
    for k in 2..=top {
        off.push((w >> 1, y));
        y += h >> k;
    }
    let width = (w >> 1) + if top >= 2 { w >> 2 } else { 0 };
    (off, (width, (h >> 1).max(y)))
}

/// The atlas offsets as the uniform table the shaders index (`array<vec4<u32>, 4>`, 16 levels).
pub fn max_offset_table(w: u32, h: u32) -> [[u32; 4]; 4] {
    let mut t = [[0u32; 4]; 4];
    for (k, v) in max_atlas(w, h).0.iter().enumerate().take(16) {
        t[k / 4][k % 4] = *v;
    }
    t
}

/// GPU bytes the height map takes, as a multiple of its float32 level 0: the mean pyramid
/// (4/3), the max pyramid's level 0 (1), its atlas (about 1/2), the scratch level (1/4) and the
/// children atlas (3/8).
pub fn gpu_bytes(w: u32, h: u32) -> u64 {
    let l0 = w as u64 * h as u64 * 4;
    let mean: u64 = (0..mip_count(w, h))
        .map(|k| {
            let (a, b) = level_size(w, h, k);
            a as u64 * b as u64 * 4
        })
        .sum();
    let (_, (aw, ah)) = max_atlas(w, h);
    let (sw, sh) = level_size(w, h, 1);
    let (_, (cw, ch)) = children_atlas(w, h);
    mean + l0 + aw as u64 * ah as u64 * 4 + sw as u64 * sh as u64 * 4 + cw as u64 * ch as u64 * 4
}

/// The codes of the children atlas's unorm8 channels above 0: a child's max m is held as the
/// smallest code c with c / 255 >= m + 0.01 / 255 (0 stays 0; mips.wgsl's `max_children`), so
/// that the decoded max is never below the true one, whatever the decode's rounding, and at most
/// 1.01 / 255 of the shell above it.
pub const CHILD_MAX_CODES: u32 = 255;

/// The children atlas's format: four unorm8 codes (`CHILD_MAX_CODES`) a texel.
pub const CHILD_MAX_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The highest max-mip level whose nodes tile the map exactly (its size divides both sides).
pub fn top_maxmip_level(w: u32, h: u32) -> u32 {
    let mut l = 0;
    while l + 1 < mip_count(w, h) && w % (1 << (l + 1)) == 0 && h % (1 << (l + 1)) == 0 {
        l += 1;
    }
    l
}


#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_means() {
        assert_eq!(mip_count(512, 512), 10);
        assert_eq!(mip_count(1, 1), 1);
        assert_eq!(mip_count(300, 20), 9);
        let m = HeightMap::new(2, 2, vec![0.0, 1.0, 0.5, 0.5]).unwrap();
        let p = mean_pyramid(&m);
        assert_eq!(p.len(), 2);
        assert!((p[1][0] - 0.5).abs() < 1e-7);
        assert_eq!(max_pyramid(&m)[1][0], 1.0);
    }

    /// Map sizes the atlas tests run over: square and not, powers of two and not, 1 to 16384.
    const ATLAS_SIZES: [(u32, u32); 9] = [
        (1, 1),
        (2, 2),
        (4, 2),
        (512, 512),
        (96, 40),
        (100, 36),
        (8192, 8192),
        (16384, 4096),
        (24, 7),
    ];

    /// The max atlas holds levels 1 ..= top at x = W - 2 W / 2^k, and maxmip.wgsl's
    /// `node_children` wraps a node n of level k by floor((n + 0.5) * (2^k * (1 / W))) in f32:
    /// both are this table's, and exact, for every level the walk reads, n < 2^22.
    #[test]
    fn the_traversal_s_atlas_offsets_and_wrap_are_the_table_s() {
        for (w, h) in ATLAS_SIZES {
            let (offs, _) = max_atlas(w, h);
            for k in 1..=top_maxmip_level(w, h) {
                let size = (1u32 << k) as f32;
                let dims = w as f32 / size;
                assert_eq!(
                    w as f32 - 2.0 * dims,
                    offs[k as usize] as f32,
                    "{w}x{h} level {k}"
                );
                let inv = 1.0f32 / w as f32;
                let d = w >> k;
                let mut n = 0u32;
                while n < 1 << 22 {
                    for m in [n, n + 1, n + d - 1, n + d] {
                        let nf = m as f32;
                        let q = ((nf + 0.5) * (size * inv)).floor();
                        assert_eq!((nf - q * dims) as u32, m % d, "{w}x{h} level {k} node {m}");
                    }
                    n += d.max(1) * 97 + 1;
                }
            }
        }
    }

    /// maxmip.wgsl's `node_children` reads level k of 1 ..= top at (0, 0) for k = 1, else at
    /// (W / 2, H / 2 - 2 H / 2^k) in f32: this table's, inside the atlas, the levels apart.
    #[test]
    fn the_walk_s_children_offsets_are_the_table_s() {
        for (w, h) in ATLAS_SIZES {
            let (offs, (aw, ah)) = children_atlas(w, h);
            let top = top_maxmip_level(w, h);
            assert_eq!(offs.len() as u32, top + 1, "{w}x{h}");
            assert!(aw <= w.max(1) && ah <= h.max(1), "{w}x{h}: {aw}x{ah}");
            let mut seen = 0u64;
            for k in 1..=top {
                let size = (1u32 << k) as f32;
                let dims_y = h as f32 / size;
                let want = if k >= 2 {
                    (0.5 * w as f32, 0.5 * h as f32 - 2.0 * dims_y)
                } else {
                    (0.0, 0.0)
                };
                let (ox, oy) = offs[k as usize];
                assert_eq!((ox as f32, oy as f32), want, "{w}x{h} level {k}");
                let (lw, lh) = level_size(w, h, k);
                assert!(ox + lw <= aw && oy + lh <= ah, "{w}x{h} level {k}");
                seen += lw as u64 * lh as u64;
            }
            // no two levels overlap: their areas sum to at most the atlas's
            assert!(seen <= aw as u64 * ah as u64);
        }
    }

    #[test]
    fn the_max_atlas_fits_within_the_map_width_plus_its_levels() {
        for (w, h) in [
            (1, 1),
            (1, 16384),
            (16384, 1),
            (16384, 16384),
            (16383, 9000),
            (3, 5),
        ] {
            let (offs, (aw, ah)) = max_atlas(w, h);
            assert_eq!(offs.len() as u32, mip_count(w, h));
            assert!(
                aw <= w.max(1) + mip_count(w, h) && aw <= 16384,
                "{w}x{h}: {aw}"
            );
            assert_eq!(ah, level_size(w, h, 1).1);
            for k in 1..offs.len() {
                assert_eq!(
                    offs[k] + level_size(w, h, k as u32).0,
                    *offs.get(k + 1).unwrap_or(&aw)
                );
            }
        }
    }
}

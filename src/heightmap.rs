//! Mip pyramids of the height map (box-filtered mean for sampling; max-reduced for the
//! hierarchical methods).

use crate::scene::HeightMap;

/// Size of mip level `k` of a `w x h` map (wgpu's rule: halve, floor, at least 1).
pub fn level_size(w: u32, h: u32, k: u32) -> (u32, u32) {
    ((w >> k).max(1), (h >> k).max(1))
}

pub fn mip_count(w: u32, h: u32) -> u32 {
    32 - w.max(h).leading_zeros()
}

/// Reduce a level with `op` over each 2x2 footprint (clamped at odd edges). Returns all levels,
/// level 0 first.
fn pyramid(map: &HeightMap, op: fn(&[f32]) -> f32) -> Vec<Vec<f32>> {
    let n = mip_count(map.width, map.height);
    let mut levels = vec![map.data.clone()];
    for k in 1..n {
        let (pw, ph) = level_size(map.width, map.height, k - 1);
        let (w, h) = level_size(map.width, map.height, k);
        let prev = &levels[(k - 1) as usize];
        let mut out = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let mut q = [0.0f32; 4];
                let mut i = 0;
                for dy in 0..2 {
                    for dx in 0..2 {
                        let sx = (2 * x + dx).min(pw - 1);
                        let sy = (2 * y + dy).min(ph - 1);
                        q[i] = prev[(sy * pw + sx) as usize];
                        i += 1;
                    }
                }
                out.push(op(&q));
            }
        }
        levels.push(out);
    }
    levels
}

pub fn mean_pyramid(map: &HeightMap) -> Vec<Vec<f32>> {
    pyramid(map, |q| (q[0] + q[1] + q[2] + q[3]) * 0.25)
}

pub fn max_pyramid(map: &HeightMap) -> Vec<Vec<f32>> {
    pyramid(map, |q| q[0].max(q[1]).max(q[2]).max(q[3]))
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
}

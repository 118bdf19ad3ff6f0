//! The cone map against brute force (issue 11): on small random maps, no point of the bilinear
//! surface lies inside any cell's conservative cone, for points of the ray anywhere in the cell.

use pomkit::contract::Resident;
use pomkit::gpu;
use pomkit::mesh::Mesh;
use pomkit::methods::cone_step::read_cone_map;
use pomkit::methods::{ConeStep, Cones, Method, PerPixel, Refine};
use pomkit::render::test_hooks::resource_scene;
use pomkit::render::Renderer;
use pomkit::scene::HeightMap;

/// ConeStep's own resource for a map: its cone map, built as a render builds it, read back.
fn cone_map(r: &Renderer, map: HeightMap, cones: Cones) -> Vec<[f32; 2]> {
    let scene = resource_scene(Mesh::plane(2.0, 1).unwrap(), map).unwrap();
    let m = Method::ConeStep(
        ConeStep {
            cones,
            refine: Refine::Exact,
            max_steps: 64,
            binary_steps: 8,
            max_iterations: 4096,
        },
        PerPixel::off(),
    );
    match pomkit::render::test_hooks::method_resources(r, &scene, &m)
        .unwrap()
        .as_slice()
    {
        [Resident::Texture(b), Resident::Texture(w)] => {
            read_cone_map(&r.ctx, &[b.clone(), w.clone()]).unwrap()
        }
        other => panic!("ConeStep declares two textures, got {other:?}"),
    }
}

/// A deterministic pseudo-random map (an LCG), with some spikes.
fn random_map(w: u32, h: u32, seed: u64) -> HeightMap {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let data = (0..w * h)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (s >> 33) as f32 / (1u64 << 31) as f32;
            if u > 0.97 {
                1.0
            } else {
                0.6 * u
            }
        })
        .collect();
    HeightMap::new(w, h, data).unwrap()
}

/// The bilinear field at cell-space point (x, y) (cell (i, j) spans texel centres i..i+1).
fn field(m: &HeightMap, x: f64, y: f64) -> f64 {
    let (w, h) = (m.width as i64, m.height as i64);
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    let (fx, fy) = (x - i as f64, y - j as f64);
    let at = |a: i64, b: i64| m.data[(b.rem_euclid(h) * w + a.rem_euclid(w)) as usize] as f64;
    let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
    let bot = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bot * fy
}

#[test]
fn conservative_cones_hold_against_brute_force() {
    let r = Renderer::new(
        gpu::shared(None).expect("an adapter (install mesa-vulkan-drivers)"),
        pomkit::render::pipelines::Choice::Raster,
    )
    .unwrap();
    let grid = [0.0, 0.25, 0.5, 0.75, 1.0];
    for (w, h, seed) in [(16u32, 16u32, 1u64), (12, 20, 2), (8, 8, 3)] {
        let map = random_map(w, h, seed);
        let cones = cone_map(&r, map.clone(), Cones::Conservative);
        let mut widest = 0.0f64;
        for j in 0..h as i64 {
            for i in 0..w as i64 {
                let [base, cw] = cones[(j * w as i64 + i) as usize];
                let (base, cw) = (base as f64, cw as f64);
                assert!(
                    cw > 0.0 && base <= 1.0 + 1e-6,
                    "({i}, {j}): cone ({base}, {cw})"
                );
                widest = widest.max(cw);
                // every surface point y within a period of the cell, against points x of the cell
                let (pw, ph) = (w as i64, h as i64);
                for qy in j - ph..=j + ph {
                    for qx in i - pw..=i + pw {
                        for gy in grid {
                            for gx in grid {
                                let (yx, yy) = (qx as f64 + gx, qy as f64 + gy);
                                let hy = field(&map, yx, yy);
                                if hy <= base {
                                    continue;
                                }
                                for sy in grid {
                                    for sx in grid {
                                        let (xx, xy) = (i as f64 + sx, j as f64 + sy);
                                        let rho = (yx - xx).abs().max((yy - xy).abs());
                                        assert!(
                                            hy <= base + rho / cw + 1e-5,
                                            "map {w}x{h}: cell ({i}, {j}) cone ({base}, {cw}) holds the surface point \
                                             ({yx}, {yy}) at height {hy} seen from ({xx}, {xy})"
                                        );
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        // and they are not trivially thin
        assert!(widest > 0.5, "map {w}x{h}: the widest cone is {widest}");
    }
}

//! Rust-only tests of the core: render through wgpu and check against the analytic case and
//! the CPU oracle, without Python.

use pomkit::gpu;
use pomkit::mesh::Mesh;
use pomkit::methods::{Flat, Method, PerPixel, Pom};
use pomkit::oracle::hits;
use pomkit::render::Renderer;
use pomkit::scene::{shared, Camera, DirectionalLight, HeightMap, Light, Material, Scene};
use pomkit::Error;

fn scene(height: HeightMap, theta_deg: f64, size: u32) -> Scene {
    let t = theta_deg.to_radians();
    Scene::single(
        shared(Mesh::plane(2.0, 1).unwrap()).unwrap(),
        Material {
            height: shared(height).unwrap(),
            depth: 0.1,
            tiling: 1.0,
            albedo: None,
        },
        Camera {
            eye: [0.0, 2.0 * t.cos(), 2.0 * t.sin()],
            target: [0.0; 3],
            up: [0.0, 0.0, -1.0],
            fov_y: 30.0,
            width: size,
            height: size,
            window: None,
            samples: 1,
        },
        vec![Light::Directional(DirectionalLight {
            direction: [-0.3, -1.0, -0.2],
            irradiance: [2.0; 3],
            angular_diameter: 1.0,
            cast_shadows: false,
            shadow_map_size: 2048,
            color: [1.0; 3],
        })],
        [0.05; 3],
    )
}

fn renderer() -> Renderer {
    Renderer::new(
        gpu::shared(None).expect("an adapter (install mesa-vulkan-drivers)"),
        pomkit::render::pipelines::Choice::Raster,
    )
    .unwrap()
}

#[test]
fn pom_matches_the_oracle_on_a_constant_height() {
    let r = renderer();
    let hm = HeightMap::new(32, 32, vec![0.3; 32 * 32]).unwrap();
    let s = scene(hm, 60.0, 64);
    let m = Method::Pom(
        Pom {
            min_steps: 8,
            max_steps: 50,
            lod_threshold: 100.0,
            adaptive: true,
        },
        PerPixel::off(),
    );
    let f = r.render(&s, &m).unwrap();
    let o = hits(&s, 0.0, &pomkit::oracle::Shells::default()).unwrap();
    let mut n = 0;
    let (mask, uv) = (f.mask(), f.f32s("uv"));
    for i in 0..(64 * 64) {
        if mask[i] && o.mask[i] {
            let du = (uv[i * 2] as f64 - o.uv[i * 2]).abs() * 32.0;
            let dv = (uv[i * 2 + 1] as f64 - o.uv[i * 2 + 1]).abs() * 32.0;
            // the edge pixels of the plane may rasterise differently: only count inner ones
            let u = o.uv[i * 2];
            if u > 0.02 && u < 0.98 {
                assert!(du < 0.05 && dv < 0.05, "pixel {i}: {du} {dv} texels");
                n += 1;
            }
        }
    }
    assert!(n > 1000, "{n}");
    assert!(f.gpu_ms.is_some() == r.ctx.caps.timestamps);
}

#[test]
fn bad_sizes_are_refused_before_the_gpu() {
    let r = renderer();
    let lim = r.ctx.limits.max_texture_dimension_2d;
    let hm = HeightMap::new(lim + 1, 1, vec![0.5; lim as usize + 1]).unwrap();
    let e = r
        .render(&scene(hm, 30.0, 8), &Method::Flat(Flat {}, PerPixel::off()))
        .unwrap_err();
    assert!(matches!(e, Error::Limit { .. }), "{e}");
    assert!(e.to_string().contains("max_texture_dimension_2d"));
}

#[test]
fn validation_errors_become_errors_and_the_renderer_survives() {
    let r = renderer();
    let e = pomkit::render::test_hooks::provoke_validation_error(&r).unwrap_err();
    assert!(matches!(e, Error::Gpu(_)), "{e}");
    let hm = HeightMap::new(8, 8, vec![0.5; 64]).unwrap();
    assert!(r
        .render(&scene(hm, 30.0, 8), &Method::pom(PerPixel::off()))
        .is_ok());
}

#[test]
fn gpu_pyramids_equal_the_cpu_ones() {
    use pomkit::heightmap::{cell_max_pyramid, mean_pyramid};
    let r = renderer();
    for (w, h) in [(64u32, 64u32), (48, 20)] {
        let map = HeightMap::from_fn(w, h, |u, v| {
            (0.5 + 0.5 * (13.0 * u).sin() * (7.0 * v).cos()).fract()
        });
        let (mean, max) =
            pomkit::render::test_hooks::read_pyramids(&r, &shared(map.clone()).unwrap()).unwrap();
        let (cm, cx) = (mean_pyramid(&map), cell_max_pyramid(&map));
        assert_eq!(mean.len(), cm.len());
        for k in 0..cm.len() {
            for (a, b) in mean[k].iter().zip(&cm[k]) {
                assert!((a - b).abs() < 1e-6, "mean level {k}: {a} vs {b}");
            }
            assert_eq!(max[k], cx[k], "max level {k} of {w}x{h}");
        }
    }
}

#[test]
fn the_children_atlas_holds_each_node_s_children_maxes() {
    // every node of levels 1 ..= top: its four children's maxes of the CPU max pyramid, in
    // gather order, each rounded up to a unorm8 code (CHILD_MAX_CODES): never below the max
    // (with a margin for the decode's rounding), at most 1.01 codes above it, and 0 exactly for
    // a max of 0; on power-of-two, non-power-of-two and odd maps (top 0: nothing to hold), with
    // heights of exactly 0, 1 and on the codes themselves
    use pomkit::heightmap::{cell_max_pyramid, level_size, top_maxmip_level, CHILD_MAX_CODES};
    let r = renderer();
    let n = CHILD_MAX_CODES as f64;
    for (w, h) in [(64u32, 64u32), (48, 20), (96, 40), (7, 5)] {
        let map = HeightMap::from_fn(w, h, |u, v| {
            let x = (0.5 + 0.5 * (11.0 * u).sin() * (5.0 * v).cos()).fract();
            // a band of 0, one of 1, one on the codes (k / 255), the rest smooth
            if v < 0.2 {
                0.0
            } else if v < 0.35 {
                1.0
            } else if v < 0.5 {
                (x * 255.0).round() / 255.0
            } else {
                x
            }
        });
        let ch =
            pomkit::render::test_hooks::read_children(&r, &shared(map.clone()).unwrap()).unwrap();
        let cx = cell_max_pyramid(&map);
        assert_eq!(ch.len() as u32, top_maxmip_level(w, h), "{w}x{h}");
        for (i, lvl) in ch.iter().enumerate() {
            let k = i as u32 + 1;
            let (lw, lh) = level_size(w, h, k);
            let (cw, _) = level_size(w, h, k - 1);
            let below = &cx[k as usize - 1];
            assert_eq!(lvl.len() as u32, lw * lh);
            for y in 0..lh {
                for x in 0..lw {
                    let at = |dx: u32, dy: u32| below[((2 * y + dy) * cw + 2 * x + dx) as usize];
                    let want = [at(0, 1), at(1, 1), at(1, 0), at(0, 0)];
                    let got = lvl[(y * lw + x) as usize];
                    for (c, m) in got.iter().zip(want) {
                        let (c, m) = (*c as f64, m as f64);
                        let at_node =
                            format!("{w}x{h} level {k} node ({x}, {y}): code {c} for max {m}");
                        if m <= 0.0 {
                            assert_eq!(c, 0.0, "{at_node}");
                        } else if c == n {
                            // the top code decodes to exactly 1: never below a height
                            assert!(m <= 1.0 && m + 1.011 / n >= 1.0, "{at_node}");
                        } else {
                            assert!(c / n >= m + 0.005 / n, "{at_node}: below the max");
                            assert!(
                                c / n <= (m + 1.011 / n).min(1.0),
                                "{at_node}: too far above"
                            );
                        }
                    }
                    assert_eq!(
                        want.iter().cloned().fold(0.0f32, f32::max),
                        cx[k as usize][(y * lw + x) as usize]
                    );
                }
            }
        }
    }
}

#[test]
fn a_supersampled_frame_in_tiles_equals_one_pass() {
    // 4 x 4 samples per pixel over a 37 x 37 frame: one pass, and tiles of 10 pixels (windows
    // of the full camera, the last ones partial); colour and coverage agree up to rasterisation
    // rounding (the window's projection is the full one's, scaled and shifted)
    use pomkit::render::Aovs;
    let r = renderer();
    let data = (0..64 * 64)
        .map(|i| 0.5 + 0.4 * (((i % 64) / 8 + (i / 64) / 8) % 2) as f32)
        .collect();
    let s = scene(HeightMap::new(64, 64, data).unwrap(), 50.0, 37);
    let m = Method::Pom(
        Pom {
            min_steps: 8,
            max_steps: 32,
            lod_threshold: 100.0,
            adaptive: true,
        },
        PerPixel::off(),
    );
    let aovs = Aovs::parse(&["color", "coverage"]).unwrap();
    let one = r
        .render_many_spp(std::slice::from_ref(&s), &m, aovs, 16)
        .unwrap()
        .remove(0);
    let tiled = r.render_tiled(&s, &m, aovs, 4, 10).unwrap();
    for name in ["color", "coverage"] {
        let (a, b) = (one.f32s(name), tiled.f32s(name));
        assert_eq!(a.len(), b.len());
        let worst = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        let mean = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs() as f64)
            .sum::<f64>()
            / a.len() as f64;
        assert!(
            worst < 0.1 && mean < 1e-3,
            "{name}: worst {worst}, mean {mean}"
        );
    }
    assert!(one.f32s("coverage").iter().sum::<f32>() > 100.0);
}

#[test]
fn readbacks_from_many_threads_all_complete() {
    // the device is shared: one thread's poll can collect another's mapping callback and run
    // it after that thread's own wait has returned; every readback must still complete
    let r = std::sync::Arc::new(renderer());
    let threads: Vec<_> = (0..6)
        .map(|t| {
            let r = r.clone();
            std::thread::spawn(move || {
                for i in 0..15 {
                    let v = ((t * 15 + i) as f32 + 0.5) / 100.0;
                    let map = HeightMap::new(16, 8, vec![v; 128]).unwrap();
                    let (mean, _) =
                        pomkit::render::test_hooks::read_pyramids(&r, &shared(map).unwrap())
                            .unwrap();
                    assert!(mean[0].iter().all(|&x| x == v), "thread {t}, read {i}");
                }
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
}

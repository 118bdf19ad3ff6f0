use super::*;
use crate::mesh::Mesh;
use glam::DMat4;
use crate::oracle::{hits_of, planar::Oracle};
use crate::scene::{shared, Camera, HeightMap, Light};

fn noise(w: u32, h: u32, seed: u64) -> HeightMap {
    let mut x = seed;
    let data = (0..w * h)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 40) as f32 / (1u64 << 24) as f32
        })
        .collect();
    HeightMap::new(w, h, data).unwrap()
}

fn scene(mesh: Mesh, hm: HeightMap, depth: f32, eye: [f64; 3], size: u32) -> Scene {
    Scene::single(
        shared(mesh).unwrap(),
        Material {
            height: shared(hm).unwrap(),
            depth,
            tiling: 1.0,
            albedo: None,
        },
        Camera {
            eye,
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y: 30.0,
            width: size,
            height: size,
            window: None,
            samples: 1,
        },
        vec![Light::Directional(crate::scene::DirectionalLight {
            direction: [-0.3, -1.0, -0.2],
            irradiance: [2.0; 3],
            angular_diameter: 0.0,
            cast_shadows: false,
            shadow_map_size: 2048,
            color: [1.0; 3],
        })],
        [0.05; 3],
    )
}

/// On a plane, inside its border, the shell walk answers as the planar oracle's closed form.
#[test]
fn on_a_plane_the_shell_answers_as_the_planar_oracle() {
    let t = 55f64.to_radians();
    let s = scene(
        Mesh::plane(2.0, 3).unwrap(),
        noise(32, 32, 3),
        0.1,
        [0.0, 1.6 * t.cos(), 1.6 * t.sin()],
        40,
    );
    let planar = hits_of(&s, &Oracle::new(&s, "test").unwrap(), 0.0);
    let shell = hits_of(&s, &Shell::new(&s, &Shells::default()).unwrap(), 0.0);
    // the planar oracle extends the plane past its border; compare where its hit lies inside
    let inner = |i: usize| {
        (0.05..0.95).contains(&planar.uv[2 * i]) && (0.05..0.95).contains(&planar.uv[2 * i + 1])
    };
    let n = planar.mask.len();
    assert!((0..n).filter(|&i| planar.mask[i] && inner(i)).count() > 800);
    assert!(
        (0..n).all(|i| !(planar.mask[i] && inner(i)) || shell.mask[i]),
        "the shell misses"
    );
    assert!(
        (0..n).all(|i| planar.mask[i] || !shell.mask[i]),
        "the shell hits past the plane"
    );
    let mut worst = 0f64;
    for i in 0..n {
        if planar.mask[i] && inner(i) {
            let du = (planar.uv[2 * i] - shell.uv[2 * i]) * 32.0;
            let dv = (planar.uv[2 * i + 1] - shell.uv[2 * i + 1]) * 32.0;
            worst = worst.max(du.hypot(dv));
        }
    }
    assert!(worst < 1e-3, "worst {worst} texel");
    let differ = (0..planar.mask.len())
        .filter(|&i| planar.mask[i] && inner(i) && planar.visibility[i] != shell.visibility[i])
        .count();
    assert!(differ <= 2, "{differ} pixels' light differs");
}

/// A flat-shaded plane (every triangle its own corners, as a low-poly model's quads are
/// exported) whose triangles' normals agree only to rounding (here 6e-6 apart, under 1e-5): the
/// walk crosses each side as shared (normals within 1e-5), where the two walls part by that
/// difference times the offset. The walk takes the located point onto the side, so no ray is
/// lost there: inside its border, the shell misses no pixel of the planar oracle's.
#[test]
fn a_flat_shaded_plane_whose_normals_differ_by_rounding_loses_no_ray() {
    let t = 60f64.to_radians();
    let base = Mesh::plane(2.0, 6).unwrap();
    let (mut pos, mut nrm, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for (k, tri) in base.indices.chunks_exact(3).enumerate() {
        let e = if k % 2 == 0 { 2e-6f32 } else { -2e-6 };
        for &i in tri {
            pos.push(base.positions[i as usize]);
            nrm.push([e, 1.0, -e]);
            uv.push(base.uvs[i as usize]);
        }
    }
    let idx = (0..pos.len() as u32).collect();
    let (flat, _) = Mesh::from_arrays(pos, nrm, uv, idx, None).unwrap();
    let eye = [0.3, 1.6 * t.cos(), 1.6 * t.sin()];
    let hm = noise(32, 32, 7);
    let planar = scene(Mesh::plane(2.0, 6).unwrap(), hm.clone(), 0.1, eye, 48);
    let s = scene(flat, hm, 0.1, eye, 48);
    let want = hits_of(&planar, &Oracle::new(&planar, "test").unwrap(), 0.0);
    let got = hits_of(&s, &Shell::new(&s, &Shells::default()).unwrap(), 0.0);
    let inner = |i: usize| {
        (0.05..0.95).contains(&want.uv[2 * i]) && (0.05..0.95).contains(&want.uv[2 * i + 1])
    };
    let n = want.mask.len();
    assert!((0..n).filter(|&i| want.mask[i] && inner(i)).count() > 1000);
    let lost = (0..n).filter(|&i| want.mask[i] && inner(i) && !got.mask[i]).count();
    assert_eq!(lost, 0, "{lost} rays lost");
}

/// A hit lies on the surface (h of its point = H(uv), the point P + depth (h - 1) N of its
/// triangle), and no point of the ray before it lies under the surface in any prism.
fn hits_lie_on_the_surface(s: &Scene, want_hits: usize) {
    let shell = Shell::new(s, &Shells::default()).unwrap();
    let ob = &shell.objects[0];
    let depth = ob.depth;
    let hm = &ob.mat.height;
    let cam = &s.camera;
    let basis = cam.basis();
    let mut hits = 0;
    for i in 0..cam.height {
        for j in 0..cam.width {
            let dir = cam.ray_dir(&basis, i, j);
            let Some(hit) = shell.trace(basis.eye, dir) else {
                continue;
            };
            hits += 1;
            let p = ob.prisms[hit.at.tri as usize].as_ref().unwrap();
            let b = hit.at.at.b;
            assert!(Prism::inside(b, 1e-9));
            let x = basis.eye + dir * hit.dist;
            let h = hm.sample(hit.s.x, hit.s.y);
            let want = p.point(Local { b, s: 0.0 }) + p.normal(b).normalize() * (depth * (h - 1.0));
            assert!(
                (x - want).length() < 1e-9,
                "{} off the surface",
                (x - want).length()
            );
            // before the hit: above the surface wherever the point lies in a prism
            for k in 1..100 {
                let y = basis.eye + dir * (hit.dist * k as f64 / 100.0 - 1e-6);
                for q in ob.prisms.iter().flatten() {
                    let g = Local {
                        b: DVec2::splat(1.0 / 3.0),
                        s: 0.0,
                    };
                    if let Some(a) = q.locate(y, g) {
                        let hy = 1.0 + q.offset(a) / depth;
                        let uv = q.uv(a.b);
                        let under = Prism::inside(a.b, -1e-9)
                            && (0.0..1.0).contains(&hy)
                            && hy < hm.sample(uv.x, uv.y) - 1e-7;
                        assert!(
                            !under,
                            "pixel ({i}, {j}) passes under the surface at h = {hy}"
                        );
                    }
                }
            }
        }
    }
    assert!(hits > want_hits, "{hits}");
}

/// The sphere with a constant map: the surface is P + depth (c - 1) N in closed form.
#[test]
fn on_a_sphere_a_constant_map_is_met_where_it_is() {
    let hm = HeightMap::new(8, 8, vec![0.4; 64]).unwrap();
    let s = scene(
        Mesh::sphere(1.0, 12, 8).unwrap(),
        hm,
        0.15,
        [0.3, 0.8, 3.2],
        24,
    );
    hits_lie_on_the_surface(&s, 150);
}

/// The torus with one smooth bump (a raised cosine over the map): met where it is.
#[test]
fn on_a_torus_one_smooth_bump_is_met_where_it_is() {
    let n = 32u32;
    let data = (0..n * n)
        .map(|i| {
            let (x, y) = (
                (i % n) as f64 / n as f64 - 0.5,
                (i / n) as f64 / n as f64 - 0.5,
            );
            let r = (x * x + y * y).sqrt() / 0.35;
            (0.2 + 0.8
                * if r < 1.0 {
                    0.5 + 0.5 * (std::f64::consts::PI * r).cos()
                } else {
                    0.0
                }) as f32
        })
        .collect();
    let hm = HeightMap::new(n, n, data).unwrap();
    let s = scene(
        Mesh::torus(1.0, 0.4, 16, 8).unwrap(),
        hm,
        0.1,
        [0.4, 1.8, 2.6],
        24,
    );
    hits_lie_on_the_surface(&s, 150);
}

/// A light or ambient ray that leaves through the top of a triangle with no part of its
/// object above the triangle's plane skips that object: none of a sphere's triangles has one,
/// the inner half of a torus's has, and on the torus every ray's visibility is that of the
/// search that skips nothing.
#[test]
fn a_ray_that_leaves_above_its_object_skips_it() {
    let sphere = scene(
        Mesh::sphere(1.0, 12, 8).unwrap(),
        noise(16, 16, 5),
        0.1,
        [0.3, 0.8, 3.2],
        8,
    );
    let shell = Shell::new(&sphere, &Shells::default()).unwrap();
    let ob = &shell.objects[0];
    assert!(!(0..ob.prisms.len()).any(|t| ob.overhung(t)));

    let torus = scene(
        Mesh::torus(1.0, 0.4, 16, 8).unwrap(),
        noise(16, 16, 7),
        0.1,
        [0.4, 1.8, 2.6],
        32,
    );
    let shell = Shell::new(&torus, &Shells::default()).unwrap();
    let ob = &shell.objects[0];
    // a triangle faces the hole where its normal points towards the axis
    let (mut inner, mut outer) = (0, 0);
    for (t, p) in ob.prisms.iter().enumerate() {
        let Some(p) = p else { continue };
        let o = ob.overhung(t);
        let c = (p.p[0] + p.p[1] + p.p[2]) / 3.0;
        let radial = DVec3::new(c.x, 0.0, c.z).normalize();
        if p.ng.dot(radial) < -0.2 {
            assert!(o, "a triangle facing the hole is overhung");
            inner += 1;
        } else if p.ng.dot(radial) > 0.2 {
            assert!(!o, "a triangle facing out is not overhung");
            outer += 1;
        }
    }
    assert!(inner > 20 && outer > 20, "{inner} {outer}");
    // visibility against the search over every object
    let cam = &torus.camera;
    let basis = cam.basis();
    let (mut rays, mut blocked) = (0, 0);
    for i in 0..cam.height {
        for j in 0..cam.width {
            let Some(hit) = shell.trace(basis.eye, cam.ray_dir(&basis, i, j)) else {
                continue;
            };
            for l in [
                DVec3::new(0.3, 1.0, 0.2),
                DVec3::new(-0.9, 0.3, 0.1),
                DVec3::new(0.2, -0.2, 1.0),
                DVec3::new(0.7, 0.1, -0.6),
            ] {
                let l = l.normalize();
                let d = ob.to_obj.transform_vector3(l);
                let ray = Ray {
                    o: hit.at.x,
                    d,
                    lift: 1e-9,
                    want: Want::Any,
                    part: 0.0,
                };
                let full = match ob.walk(&ray, hit.at.tri, 0.0, hit.at.at) {
                    Walk::Hit { .. } => false,
                    Walk::Left { lam, .. } => {
                        let eye = ob.to_world.transform_point3(hit.at.x);
                        let eps = 1e-9 * (1.0 + lam.abs());
                        shell.first(eye, l, lam + eps, true, None).is_none()
                    }
                };
                assert_eq!(shell.reaches(&hit, l, 1e-9), full, "pixel ({i}, {j})");
                rays += 1;
                blocked += usize::from(!full);
            }
        }
    }
    assert!(rays > 1000 && blocked > 100, "{rays} {blocked}");
}

/// A search that starts on a triangle's top, walked from its leaf up (`visit_from`), gives
/// every item that the walk from the root gives; any it gives besides are ones that the ray
/// does not enter. Rays from the middle of every triangle of a torus, going out through
/// its top in 16 directions.
#[test]
fn a_search_from_a_triangle_gives_what_the_search_from_the_root_gives() {
    let s = scene(
        Mesh::torus(1.0, 0.4, 24, 12).unwrap(),
        noise(16, 16, 19),
        0.1,
        [0.4, 1.6, 2.4],
        8,
    );
    let shell = Shell::new(&s, &Shells::default()).unwrap();
    let ob = &shell.objects[0];
    let (mut tried, mut extra) = (0, 0);
    for (t, p) in ob.prisms.iter().enumerate() {
        let Some(p) = p else { continue };
        let o = (p.p[0] + p.p[1] + p.p[2]) / 3.0;
        let (a, b) = crate::oracle::trace::perpendiculars(p.ng, p.ng.x.abs() >= 0.9);
        for k in 0..16 {
            let phi = k as f64 * 0.7;
            let d = p.ng * (0.1 + 0.06 * k as f64) + a * phi.cos() + b * phi.sin();
            let lam_min = 1e-9;
            let (mut root, mut near) = (Vec::new(), Vec::new());
            ob.bvh.visit(o, d, lam_min, f64::INFINITY, |i, _| {
                root.push(i);
                true
            });
            ob.bvh
                .visit_from(t as u32, o, d, lam_min, f64::INFINITY, |i, _| {
                    near.push(i);
                    true
                });
            for i in &root {
                assert!(
                    near.contains(i),
                    "triangle {t}, direction {k}: {i} left out"
                );
            }
            for &i in near.iter().filter(|i| !root.contains(i)) {
                extra += 1;
                ob.starts(i, o, d, |lam, _| {
                    assert!(!(lam > lam_min), "triangle {t}: {i} entered at {lam}");
                    true
                });
            }
            tried += 1;
        }
    }
    assert!(tried > 1000, "{tried} {extra}");
}

/// A light or ambient ray that reaches the depth of the field's lowest texel within its prism
/// is answered blocked there; walked on to its first hit as a camera ray is, it meets the
/// surface too. Rays from every hit of a sphere and a torus, heading below, along and above the
/// triangle's plane; the maps are texel noise between 0.45 and 1, and noise with zero texels
/// (where the floor itself is the surface).
#[test]
fn a_ray_below_the_lowest_texel_has_met_the_surface() {
    let remap = |n: HeightMap, f: &dyn Fn(f32) -> f32| {
        let data = n.data.iter().map(|&h| f(h)).collect();
        HeightMap::new(n.width, n.height, data).unwrap()
    };
    let high = remap(noise(32, 32, 5), &|h| 0.45 + 0.55 * h);
    let zeros = remap(noise(24, 24, 11), &|h| if h < 0.4 { 0.0 } else { h });
    let (mut down, mut agreed) = (0, 0);
    for (mesh, hm) in [
        (Mesh::sphere(1.0, 16, 8).unwrap(), high),
        (Mesh::torus(1.0, 0.4, 16, 8).unwrap(), zeros),
    ] {
        let s = scene(mesh, hm, 0.1, [0.4, 1.8, 2.6], 32);
        let shell = Shell::new(&s, &Shells::default()).unwrap();
        let ob = &shell.objects[0];
        let cam = &s.camera;
        let basis = cam.basis();
        for i in 0..cam.height {
            for j in 0..cam.width {
                let Some(hit) = shell.trace(basis.eye, cam.ray_dir(&basis, i, j)) else {
                    continue;
                };
                let p = ob.prisms[hit.at.tri as usize].as_ref().unwrap();
                let (t, b) = crate::oracle::trace::perpendiculars(p.ng, p.ng.x.abs() >= 0.9);
                for (k, z) in [-0.6, -0.2, -0.02, 0.0, 0.05, 0.4].into_iter().enumerate() {
                    let a = 0.7 * k as f64 + 0.1 * (i + j) as f64;
                    let d = (t * a.cos() + b * a.sin() + p.ng * z).normalize();
                    let walk = |exact: bool| {
                        let ray = Ray {
                            o: hit.at.x,
                            d,
                            lift: 1e-9,
                            want: if exact { Want::Exact } else { Want::Any },
                            part: 0.0,
                        };
                        matches!(ob.walk(&ray, hit.at.tri, 0.0, hit.at.at), Walk::Hit { .. })
                    };
                    assert_eq!(walk(false), walk(true), "pixel ({i}, {j}), dir {d}");
                    down += usize::from(z < 0.0);
                    agreed += 1;
                }
            }
        }
    }
    assert!(down > 1000 && agreed > 2000, "{down} {agreed}");
}

/// Over a map of zeros the surface is the shell's floor: a light ray from a hit there that heads
/// below the triangle's plane is under the surface at once, and blocked; one that heads above
/// it leaves. (A ray that reached the floor over zero texels once counted as leaving.)
#[test]
fn a_ray_into_the_floor_is_blocked() {
    let s = scene(
        Mesh::plane(2.0, 3).unwrap(),
        HeightMap::new(8, 8, vec![0.0; 64]).unwrap(),
        0.1,
        [0.3, 1.6, 0.9],
        24,
    );
    let shell = Shell::new(&s, &Shells::default()).unwrap();
    let cam = &s.camera;
    let basis = cam.basis();
    let mut n = 0;
    for i in 0..cam.height {
        for j in 0..cam.width {
            let Some(hit) = shell.trace(basis.eye, cam.ray_dir(&basis, i, j)) else {
                continue;
            };
            for (x, z) in [(0.0, -1.0), (0.6, -0.3), (-0.9, -0.05)] {
                let down = DVec3::new(x, z, 0.3).normalize();
                assert!(
                    !shell.reaches(&hit, down, 0.0),
                    "pixel ({i}, {j}) along {down}"
                );
            }
            assert!(shell.reaches(&hit, DVec3::new(0.2, 1.0, 0.1).normalize(), 0.0));
            n += 1;
        }
    }
    assert!(n > 300, "{n}");
}

mod tiles;

/// The caller's `Shells` keeps a shell per (mesh content, depth), the latest four, and a
/// scene built again from the same mesh finds it there (the same geometry, not a copy).
#[test]
fn the_callers_shells_keep_the_latest_four() {
    let shells = Shells::default();
    let mesh = Mesh::plane(2.0, 4).unwrap();
    let depths = [0.02f32, 0.04, 0.06, 0.08, 0.1];
    let first = scene(mesh.clone(), noise(8, 8, 1), depths[0], [0.3, 1.5, 1.0], 8);
    let a = Shell::new(&first, &shells).unwrap().objects[0].geo.clone();
    let b = Shell::new(&first, &shells).unwrap().objects[0].geo.clone();
    assert!(std::sync::Arc::ptr_eq(&a, &b));
    assert_eq!(shells.len(), 1);
    for &d in &depths[1..] {
        let s = scene(mesh.clone(), noise(8, 8, 1), d, [0.3, 1.5, 1.0], 8);
        Shell::new(&s, &shells).unwrap();
    }
    assert_eq!(shells.len(), 4);
    // the first depth's shell was the oldest, and is built anew
    let c = Shell::new(&first, &shells).unwrap().objects[0].geo.clone();
    assert!(!std::sync::Arc::ptr_eq(&a, &c));
    // a fresh set keeps nothing from the caller's
    assert!(Shells::default().is_empty());
}

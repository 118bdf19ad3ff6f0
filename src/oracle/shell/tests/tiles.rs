//! The camera's tiles and the light's bundles against single rays.
use super::*;

/// The camera's tiles give the hits the bounding volumes give, pixel by pixel; the number of
/// hits per object.
fn tiles_against_bounding_volumes(s: &Scene) -> Vec<usize> {
    let shell = Shell::new(s, &Shells::default()).unwrap();
    let cam = &s.camera;
    let basis = cam.basis();
    let mut hits = vec![0usize; s.objects.len()];
    for i in 0..cam.height {
        for j in 0..cam.width {
            let dir = cam.ray_dir(&basis, i, j);
            assert!(shell.grid.candidates(basis.eye, dir).is_some());
            let a = shell.first(basis.eye, dir, 0.0, false, None);
            let b = shell.search(basis.eye, dir, 0.0, false, None, None);
            match (a, b) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    assert_eq!(
                        (a.object, a.place.tri),
                        (b.object, b.place.tri),
                        "pixel ({i}, {j})"
                    );
                    assert!(
                        (a.place.lam - b.place.lam).abs() <= 1e-12 * b.place.lam,
                        "pixel ({i}, {j})"
                    );
                    hits[a.object] += 1;
                }
                _ => panic!("pixel ({i}, {j}): {a:?} against {b:?}"),
            }
        }
    }
    hits
}

/// A plane that reaches far behind the eye, seen from low above it: its triangles across the
/// eye's plane are clipped there.
#[test]
fn camera_tiles_clip_what_reaches_behind_the_eye() {
    let s = scene(
        Mesh::plane(6.0, 24).unwrap(),
        noise(16, 16, 11),
        0.1,
        [0.3, 0.25, 1.0],
        40,
    );
    let hits = tiles_against_bounding_volumes(&s);
    assert!(hits[0] > 1000, "{hits:?}");
}

/// A second object with the first's material: `mesh` stretched 1.4 times along y, turned 0.5
/// about z and moved to (0.9, y, 0), through the first one's side.
fn through(s: &mut Scene, mesh: Mesh, y: f64) {
    let mut other = s.objects[0].clone();
    other.mesh = shared(mesh).unwrap();
    other.transform.m = DMat4::from_scale_rotation_translation(
        DVec3::new(1.0, 1.4, 1.0),
        glam::DQuat::from_rotation_z(0.5),
        DVec3::new(0.9, y, 0.0),
    );
    s.objects.push(other);
}

/// Camera rays find their starts through the camera's tiles: the same hits as through the
/// bounding volumes, on two transformed objects (a torus through a sphere) seen from close by,
/// where some triangles reach behind the eye.
#[test]
fn camera_tiles_find_what_the_bounding_volumes_find() {
    let mut s = scene(
        Mesh::torus(1.0, 0.4, 16, 8).unwrap(),
        noise(16, 16, 9),
        0.1,
        [0.2, 0.9, 1.3],
        40,
    );
    through(&mut s, Mesh::sphere(0.6, 12, 8).unwrap(), 0.1);
    let hits = tiles_against_bounding_volumes(&s);
    assert!(hits[0] > 200 && hits[1] > 100, "{hits:?}");
}

/// A light's disk walked as one bundle answers as its rays walked one by one: on a sphere, and
/// on a torus with a transformed sphere through it (the bundle's object searched where
/// anything of it lies above, the other object always), for lights from steep to grazing.
/// Where it shows neither, its rays are walked from as far as it cleared the way.
#[test]
fn a_bundle_answers_as_its_rays() {
    // bumps a few texels wide, with the noise's sharp texels on them
    let bumps = |seed: u64| {
        let n = noise(128, 128, seed);
        let data = (0..128 * 128)
            .map(|i| {
                let (x, y) = ((i % 128) as f32 / 128.0, (i / 128) as f32 / 128.0);
                let tau = std::f32::consts::TAU;
                let smooth = 0.5 + 0.25 * ((7.0 * tau * x).sin() + (5.0 * tau * y).cos());
                0.8 * smooth + 0.2 * n.data[i]
            })
            .collect();
        HeightMap::new(128, 128, data).unwrap()
    };
    let sphere = scene(
        Mesh::sphere(1.0, 24, 12).unwrap(),
        bumps(5),
        0.08,
        [0.0, 1.0, 2.8],
        48,
    );
    let mut pair = scene(
        Mesh::torus(1.0, 0.4, 24, 12).unwrap(),
        bumps(7),
        0.08,
        [0.2, 1.6, 2.4],
        48,
    );
    through(&mut pair, Mesh::sphere(0.5, 16, 8).unwrap(), 0.3);
    for s in [&sphere, &pair] {
        let shell = Shell::new(s, &Shells::default()).unwrap();
        let basis = s.camera.basis();
        let (mut bundles, mut tried, mut lit) = (0, 0, 0);
        let (mut shadows, mut dark) = (0, 0);
        let (mut cleared, mut differ, mut off) = (0, 0, 0);
        for axis in [
            DVec3::new(0.3, 1.0, 0.2),
            DVec3::new(-0.9, 0.35, 0.1),
            DVec3::new(0.6, 0.2, 0.8),
        ] {
            let axis = axis.normalize();
            let dirs = crate::oracle::trace::disk_directions(axis, 1f64.to_radians().tan());
            for i in 0..s.camera.height {
                for j in 0..s.camera.width {
                    let dir = s.camera.ray_dir(&basis, i, j);
                    let Some(hit) = shell.trace(basis.eye, dir) else {
                        continue;
                    };
                    for set in [&dirs[..], &dirs[5..21]] {
                        let one = set.iter().filter(|l| shell.reaches(&hit, **l, 0.0)).count();
                        let all = shell.reaches_all(&hit, axis, set, 0.0);
                        tried += 1;
                        let b = shell.bundle(&hit, axis, set, 1e-9);
                        if matches!(b, Some(bundle_shows::Bundle::Cleared { .. })) {
                            cleared += 1;
                            differ += usize::from(all != one);
                            off = off.max(all.abs_diff(one));
                        } else {
                            assert_eq!(all, one, "pixel ({i}, {j}), axis {axis}");
                        }
                        if one == set.len() {
                            lit += 1;
                            bundles += usize::from(matches!(b, Some(bundle_shows::Bundle::Left(_))));
                        }
                        if one == 0 {
                            dark += 1;
                            shadows += usize::from(matches!(b, Some(bundle_shows::Bundle::Blocked)));
                        }
                    }
                }
            }
        }
        // the bundle answers for more than a third of the disks that every ray clears, and of
        // those that none clears (here 45% and 35% of the lit, 84% and 58% of the dark)
        assert!(tried > 3000 && bundles * 3 > lit, "{tried} {lit} {bundles}");
        assert!(dark > 1000 && shadows * 3 > dark, "{dark} {shadows}");
        // most of the rest clear the way part of the way, and their rays are walked from there:
        // as from the hit, but for rays that pass within the chords' tolerance of the surface,
        // where the two walks' chords differ (here 9 and 7 of 5,600 and 5,700 such disks, by
        // at most 2 and 4 of 64 rays; none of 10,700 and 8,700 with TOL_TEXELS at 1e-4)
        assert!(cleared * 2 > tried - bundles - shadows, "{tried} {cleared}");
        assert!(
            differ * 100 < cleared && off <= 8,
            "{cleared} {differ} {off}"
        );
    }
}


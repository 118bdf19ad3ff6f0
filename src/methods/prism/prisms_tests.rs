use super::*;

/// `oct_encode`'s direction back, unit length (as prism.wgsl's `oct_decode` computes it).
fn oct_decode(c: u32) -> [f32; 3] {
    let s = |h: u32| ((h as u16 as i16) as f32 / 32767.0).max(-1.0);
    let (x, y) = (s(c & 0xffff), s(c >> 16));
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    let x = x + if x >= 0.0 { -t } else { t };
    let y = y + if y >= 0.0 { -t } else { t };
    let l = (x * x + y * y + z * z).sqrt();
    [x / l, y / l, z / l]
}

/// a pole's zero-area triangles (corners within rounding of each other)
fn degenerate(d: &PrismData) -> bool {
    let same = |a: [f32; 4], b: [f32; 4]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-6);
    same(d.top[0], d.top[1]) || same(d.top[1], d.top[2]) || same(d.top[2], d.top[0])
}

fn boundary_sides(p: &Prisms) -> usize {
    p.data
        .iter()
        .filter(|d| !degenerate(d))
        .map(|d| d.adj[..3].iter().filter(|&&a| a == NONE).count())
        .sum()
}

/// The texture prism.wgsl reads: each prism's 11 texels at (index mod per_row, index div
/// per_row), per_row a power of two within the device's limit, the adjacency as floats (-1
/// for NONE), and an error naming how many prisms fit when the rows exceed the limit. The
/// shader's PRISM_TEXELS is this file's TEXELS_PER_PRISM.
#[test]
fn the_prism_texture_holds_every_prism_where_the_shader_looks() {
    assert!(include_str!("prism.wgsl")
        .contains(&format!("const PRISM_TEXELS: u32 = {TEXELS_PER_PRISM}u;")));
    let hm = HeightMap::new(4, 4, vec![0.5; 16]).unwrap();
    let mesh = Mesh::plane(2.0, 3).unwrap();
    let p = build(&mesh, 0.1, false, true, &hm, 1.0);
    let n = p.data.len();
    // a limit of 4 prisms a row: 18 prisms in 5 rows
    let (t, (w, h)) = texels(&p.data, 4 * TEXELS_PER_PRISM + 3).unwrap();
    let per_row = w / TEXELS_PER_PRISM;
    assert_eq!(
        (per_row, w, h as usize),
        (4, 4 * TEXELS_PER_PRISM, n.div_ceil(4))
    );
    let adj = |a: u32| if a == NONE { -1.0 } else { a as f32 };
    let f = |v: [u32; 4]| v.map(f32::from_bits);
    for (i, d) in p.data.iter().enumerate() {
        let at = (i / 4) * w as usize + (i % 4) * TEXELS_PER_PRISM as usize;
        for k in 0..3 {
            assert_eq!(f(t[at + k])[..3], d.top[k][..3]);
            assert_eq!(f(t[at + 3 + k]), {
                let mut b = d.bottom[k];
                b[3] = adj(d.adj[k]);
                b
            });
            // the basis: the normal and the tangent within an octahedral code's rounding
            let back = |c: u32, v: [f32; 4]| {
                let o = oct_decode(c);
                (0..3).all(|i| (o[i] - v[i]).abs() < 5e-5)
            };
            assert!(back(t[at + 8 + k][0], d.normal[k]) && back(t[at + 8 + k][1], d.tangent[k]));
            assert_eq!(f32::from_bits(t[at + 8 + k][2]).abs(), d.uv[k][2]);
            assert_eq!(f32::from_bits(t[at + 8 + k][3]), d.uv[k][3]);
        }
        // the highest height; the diagonals, the plateau bit and corner 2's top code; corners
        // 0 and 1's top codes
        assert_eq!(f(t[at])[3], d.info[0]);
        let plateau = (d.info[1] >= d.info[0]) as u32;
        assert_eq!(t[at + 1][3], d.adj[3] | plateau << 3 | d.lift[2] << 16);
        assert_eq!(t[at + 2][3], d.lift[0] | d.lift[1] << 16);
        assert_eq!(
            f(t[at + 6]),
            [d.uv[0][0], d.uv[0][1], d.uv[1][0], d.uv[1][1]]
        );
        assert_eq!(f(t[at + 7])[..2], d.uv[2][..2]);
        // the handedness in the sign of corner 0's u scale
        assert_eq!(t[at + 8][2] >> 31 == 1, d.tangent[0][3] < 0.0);
    }
    assert!(p.data.iter().any(|d| d.adj[..3].contains(&NONE)));
    // the widest rows fit: one row of 32 for 18 prisms under a large limit
    assert_eq!(texels(&p.data, 16384).unwrap().1 .0, 32 * TEXELS_PER_PRISM);
    // rows over the limit: an error with the prisms that fit (one a row, 11 rows, for 18)
    assert_eq!(n, 18);
    assert_eq!(texels(&p.data, TEXELS_PER_PRISM).err(), Some(11));
}

/// Closed meshes make closed shells: every side is shared (across the uv seams and at the
/// poles too), so a ray walks through them and only the tops are drawn. Open and creased
/// meshes keep their edges' sides and draw their bottoms.
#[test]
fn closed_meshes_share_every_side() {
    let hm = HeightMap::new(4, 4, vec![0.5; 16]).unwrap();
    for (name, mesh) in [
        ("sphere", Mesh::sphere(1.0, 48, 24).unwrap()),
        ("torus", Mesh::torus(1.0, 0.35, 48, 24).unwrap()),
    ] {
        for outward in [false, true] {
            let p = build(&mesh, 0.1, outward, true, &hm, 1.0);
            let tris = p.data.iter().filter(|d| !degenerate(d)).count();
            assert_eq!(boundary_sides(&p), 0, "{name}");
            assert_eq!(
                p.vertices.len(),
                tris * 3,
                "{name}: only the tops are drawn"
            );
            // adjacency is symmetric
            for (t, d) in p.data.iter().enumerate().filter(|(_, d)| !degenerate(d)) {
                for &n in &d.adj[..3] {
                    assert!(p.data[n as usize].adj[..3].contains(&(t as u32)), "{name}");
                }
            }
        }
    }
    let plane = build(&Mesh::plane(2.0, 4).unwrap(), 0.1, false, true, &hm, 1.0);
    assert_eq!(boundary_sides(&plane), 16, "a 4x4 plane's rim");
    let cube = build(&Mesh::cube(2.0, 1).unwrap(), 0.1, false, true, &hm, 1.0);
    assert_eq!(boundary_sides(&cube), 24, "every face's rim is a crease");
}

/// A height's unorm16 code is never below it and at most one code above.
#[test]
fn lift_codes_round_up() {
    for i in 0..=20000 {
        let m = i as f64 / 20000.0;
        for m in [m, (m as f32) as f64, m.next_up(), (m - 1e-9).max(0.0)] {
            let c = lift_code(m);
            let v = c as f32 / 65535.0;
            assert!(v >= m.min(1.0) as f32, "{m} -> {c}");
            assert!(
                c == 0 || (c - 1) as f64 / 65535.0 < m,
                "{m} -> {c}: not the least code"
            );
        }
    }
    assert_eq!(
        (lift_code(0.0), lift_code(1.0), lift_code(2.0)),
        (0, 65535, 65535)
    );
}

/// The tight shell: every top at or above the field under its prism and at least MIN_LIFT,
/// on the full shell's vertical edge (the same point, lowered along it), each vertical edge's
/// top one point and one code for every prism on it (so the shell stays closed, across uv
/// seams too), and the full shell's tops all at the depth (code 65535).
#[test]
fn tight_shells_stay_closed_and_above_the_field() {
    // a floor at 0 with sparse spikes at 1 and a ramp: prisms with empty space above them
    let (w, h) = (37usize, 29usize);
    let mut v = vec![0.0f32; w * h];
    for (i, x) in v.iter_mut().enumerate() {
        let (px, py) = (i % w, i / w);
        *x = if px % 12 == 3 && py % 10 == 4 {
            1.0
        } else if px > 30 {
            (py as f32 / h as f32) * 0.6
        } else {
            0.0
        };
    }
    let hm = HeightMap::new(w as u32, h as u32, v).unwrap();
    for (name, mesh) in [
        ("sphere", Mesh::sphere(1.0, 24, 12).unwrap()),
        ("torus", Mesh::torus(1.0, 0.35, 20, 10).unwrap()),
    ] {
        for outward in [false, true] {
            for tiling in [1.0, 2.0] {
                let full = build(&mesh, 0.1, outward, false, &hm, tiling);
                let tight = build(&mesh, 0.1, outward, true, &hm, tiling);
                assert!(
                    full.data.iter().all(|d| d.lift[..3] == [65535; 3]),
                    "{name}"
                );
                let mut lowered = 0;
                let mut at_edge: std::collections::HashMap<[i32; 6], ([f32; 3], u32)> =
                    Default::default();
                for (d, f) in tight
                    .data
                    .iter()
                    .zip(&full.data)
                    .filter(|(d, _)| !degenerate(d))
                {
                    for k in 0..3 {
                        let m = d.lift[k] as f64 / 65535.0;
                        assert!(
                            m as f32 >= d.info[0] && m >= MIN_LIFT - 1e-12,
                            "{name}: a top below the field"
                        );
                        lowered += (d.lift[k] < 65535) as usize;
                        for i in 0..3 {
                            let want = f.bottom[k][i] as f64
                                + (f.top[k][i] as f64 - f.bottom[k][i] as f64) * m;
                            assert!(
                                (d.top[k][i] as f64 - want).abs() < 1e-6,
                                "{name}: off its edge"
                            );
                        }
                        let q = |x: f32| (x * 1e4).round() as i32;
                        let (ft, fb) = (f.top[k], f.bottom[k]);
                        let key = [q(ft[0]), q(ft[1]), q(ft[2]), q(fb[0]), q(fb[1]), q(fb[2])];
                        let top = [d.top[k][0], d.top[k][1], d.top[k][2]];
                        let seen = at_edge.entry(key).or_insert((top, d.lift[k]));
                        assert_eq!(seen.1, d.lift[k], "{name}: an edge with two heights");
                        // one point (a uv seam's repeated vertex differs in its last bits)
                        assert!(
                            (0..3).all(|i| (seen.0[i] - top[i]).abs() < 1e-6),
                            "{name}: an edge with two tops"
                        );
                    }
                }
                assert!(lowered > 0, "{name}: nothing lowered");
            }
        }
    }
}

/// Neighbours split their shared side along the same diagonal.
#[test]
fn shared_sides_split_alike() {
    let hm = HeightMap::new(4, 4, vec![0.5; 16]).unwrap();
    let p = build(
        &Mesh::torus(1.0, 0.35, 12, 8).unwrap(),
        0.1,
        false,
        true,
        &hm,
        1.0,
    );
    let edge = |d: &PrismData, k: usize| {
        let j = (k + 1) % 3;
        let flip = d.adj[3] & (1 << k) != 0;
        // the diagonal's two ends: (top of one corner, bottom of the other)
        if flip {
            (d.top[j], d.bottom[k])
        } else {
            (d.top[k], d.bottom[j])
        }
    };
    let close = |a: [f32; 4], b: [f32; 4]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-5);
    for d in &p.data {
        for k in 0..3 {
            let n = &p.data[d.adj[k] as usize];
            let kn = (0..3)
                .find(|&m| {
                    n.adj[m] == p.data.iter().position(|x| std::ptr::eq(x, d)).unwrap() as u32
                })
                .unwrap();
            let (a, b) = edge(d, k);
            let (c, e) = edge(n, kn);
            assert!(close(a, c) && close(b, e), "diagonals differ");
        }
    }
}

use super::*;

fn quad(uv_right: [[f32; 2]; 2]) -> Mesh {
    // two triangles sharing the edge x = 1; the right one's uvs are given at that edge's
    // ends (y = 0, y = 1), its far corner at (2, 0.5)
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.5, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let uvs = vec![
        [0.0, 0.0],
        [0.5, 0.0],
        [0.5, 0.5],
        uv_right[0],
        [
            uv_right[0][0] + 0.5,
            0.5 * (uv_right[0][1] + uv_right[1][1]),
        ],
        uv_right[1],
    ];
    let normals = vec![[0.0, 0.0, 1.0]; 6];
    Mesh::from_arrays(positions, normals, uvs, vec![0, 1, 2, 3, 4, 5], None)
        .unwrap()
        .0
}

#[test]
fn a_border_that_another_runs_along_is_a_crack() {
    // triangle 0's side x = 1 (corners 1, 2) against two triangles whose sides on x = 1
    // meet at y = 0.5 (a T-junction: no edge is shared); every other side is a border
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.25, 0.0],
        [1.0, 0.5, 0.0],
        [1.0, 0.5, 0.0],
        [2.0, 0.75, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let uvs: Vec<[f32; 2]> = positions.iter().map(|p| [p[0] / 2.0, p[1]]).collect();
    let normals = vec![[0.0, 0.0, 1.0]; 9];
    let (m, _) = Mesh::from_arrays(positions, normals, uvs, (0..9).collect(), None).unwrap();
    let w = build(&m, &[]);
    assert!(w.iter().all(|t| t.across.iter().all(Option::is_none)));
    let cracked = |t: usize| w[t].crack.map(|c| c.is_some());
    assert_eq!(cracked(0), [false, true, false]);
    // the two small triangles' sides on x = 1: corners 2 -> 0 (side 2) of each
    assert_eq!(cracked(1), [false, false, true]);
    assert_eq!(cracked(2), [false, false, true]);
    // the plane across: z = 0 (all three lie in it)
    let q = w[0].crack[1].unwrap();
    assert!((q[2].abs() - 1.0).abs() < 1e-12 && q[3].abs() < 1e-12, "{q:?}");
    // the records name it apart from a border
    let r = records(&m, &w);
    // (triangle 0's records: side k's neighbour in the w of record 2 + 2k)
    assert_eq!(r[4][3], CRACK);
    assert_eq!(r[2][3], NO_NEIGHBOUR);
}

#[test]
fn inside_a_chart_the_walk_keeps_the_uvs() {
    let m = quad([[0.5, 0.0], [0.5, 0.5]]);
    let w = build(&m, &[]);
    let (nb, a) = w[0].across[1].unwrap();
    assert_eq!(nb, 1);
    assert_eq!(a, Affine::IDENTITY);
    assert!(w[0].across[0].is_none() && w[0].across[2].is_none());
    // corner 2 of triangle 0 at uv (0.5, 0.5): b2 = 1
    let b = w[0].to_bary.apply(DVec2::new(0.5, 0.5));
    assert!((b - DVec2::new(0.0, 1.0)).length() < 1e-12);
}

#[test]
fn across_a_seam_the_walk_continues_in_the_other_chart() {
    // the right triangle's chart elsewhere in the atlas and at another scale
    let m = quad([[0.9, 0.2], [0.9, 0.45]]);
    let w = build(&m, &[]);
    let (nb, a) = w[0].across[1].unwrap();
    assert_eq!(nb, 1);
    // the side's ends land on the other chart's uvs
    let d = a.apply(DVec2::new(0.5, 0.0)) - DVec2::new(0.9, 0.2);
    assert!(d.length() < 1e-6, "{d}");
    let d = a.apply(DVec2::new(0.5, 0.5)) - DVec2::new(0.9, 0.45);
    assert!(d.length() < 1e-6, "{d}");
    // a point of the right triangle (world (1.5, 0.5)), continued in the left triangle's
    // chart (uv 0.5 per world unit), lands at its uv in the right chart
    let into = a.apply(DVec2::new(0.75, 0.25));
    let bary = w[1].to_bary.apply(into);
    let b = [1.0 - bary.x - bary.y, bary.x, bary.y];
    // world (1.5, 0.5) is the midpoint between the edge's midpoint and the far corner
    let expect = [0.25, 0.5, 0.25];
    for k in 0..3 {
        assert!((b[k] - expect[k]).abs() < 1e-6, "{b:?}");
    }
    // and back again
    let (_, back) = w[1].across[2].unwrap();
    let p = back.apply(into);
    assert!((p - DVec2::new(0.75, 0.25)).length() < 1e-6);
}

#[test]
fn across_a_mirror_axis_the_walk_reflects() {
    // the right triangle's uvs fold back onto the left one's: a mirrored chart
    let mut m = quad([[0.5, 0.0], [0.5, 0.5]]);
    m.uvs[4] = [0.0, 0.25];
    let w = build(&m, &[]);
    let (_, a) = w[0].across[1].unwrap();
    // the axis stays, the far side reflects
    assert!((a.apply(DVec2::new(0.5, 0.3)) - DVec2::new(0.5, 0.3)).length() < 1e-6);
    assert!((a.apply(DVec2::new(0.75, 0.25)) - DVec2::new(0.25, 0.25)).length() < 1e-6);
}

#[test]
fn the_texture_holds_every_triangle_where_the_shader_looks() {
    assert!(include_str!("walk.wgsl")
        .contains(&format!("const RECORDS: u32 = {RECORDS_PER_TRIANGLE}u;")));
    let m = Mesh::plane(1.0, 3).unwrap();
    let r = records(&m, &build(&m, &[]));
    let n = m.indices.len() / 3;
    assert_eq!(r.len(), n * RECORDS_PER_TRIANGLE);
    // at most 4 triangles a row: 18 triangles in 5 rows
    let (t, (w, h)) = texels(&r, 4 * RECORDS_PER_TRIANGLE as u32 + 3).unwrap();
    assert_eq!((w, h), (4 * RECORDS_PER_TRIANGLE as u32, 5));
    for i in 0..n {
        let at = (i / 4) * w as usize + (i % 4) * RECORDS_PER_TRIANGLE;
        assert_eq!(
            t[at..at + RECORDS_PER_TRIANGLE],
            r[i * RECORDS_PER_TRIANGLE..(i + 1) * RECORDS_PER_TRIANGLE]
        );
    }
    // rows beyond the limit: an error naming how many fit
    assert_eq!(texels(&r, RECORDS_PER_TRIANGLE as u32), Err(14));
}

mod contacts {
    use crate::mesh::borders::{contacts, open_borders, Part};
    use crate::mesh::topology::Topology;
    use crate::mesh::Mesh;
    use crate::methods::walk::cracks;
    use glam::{DMat4, DVec3};
    use std::sync::Arc;

    fn part(p: [[f32; 3]; 3], to_world: DMat4) -> (Mesh, Part) {
        let uvs = p.iter().map(|q| [q[0], q[1]]).collect();
        let (m, _) =
            Mesh::from_arrays(p.to_vec(), vec![[0.0, 0.0, 1.0]; 3], uvs, vec![0, 1, 2], None)
                .unwrap();
        let part = Part {
            borders: Arc::new(open_borders(&m, &Topology::quantised(&m))),
            bounds: m.bounds(),
            to_world,
        };
        (m, part)
    }

    #[test]
    fn two_objects_that_split_a_square_meet_at_its_diagonal() {
        // the unit square's two halves as two objects: the second modelled 4 to the right
        // at twice the size, placed back by its transform; a third far away touches neither
        let (ma, a) = part([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]], DMat4::IDENTITY);
        let (mb, b) = part(
            [[4.0, 0.0, 0.0], [6.0, 2.0, 0.0], [4.0, 2.0, 0.0]],
            DMat4::from_scale(DVec3::splat(0.5))
                * DMat4::from_translation(DVec3::new(-4.0, 0.0, 0.0)),
        );
        let (_, far) = part([[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [5.0, 6.0, 0.0]], DMat4::IDENTITY);
        let c = contacts(&[a, b, far]);
        assert!(c[2].borders.is_empty() && c[2].key == 0);
        let sides = |m: &Mesh, i: usize| cracks(m, &Topology::quantised(m), &c[i].borders)[0];
        // a's diagonal is its side 2 (corner 2 -> 0), b's its side 0 (corner 0 -> 1)
        let (sa, sb) = (sides(&ma, 0), sides(&mb, 1));
        assert_eq!(sa.map(|s| s.is_some()), [false, false, true]);
        assert_eq!(sb.map(|s| s.is_some()), [true, false, false]);
        // the plane across, in each object's own space: z = 0, facing +z as both do
        for q in [sa[2].unwrap(), sb[0].unwrap()] {
            assert!((q[2] - 1.0).abs() < 1e-12 && q[3].abs() < 1e-12, "{q:?}");
        }
        // alone, neither has a crack
        assert!(cracks(&ma, &Topology::quantised(&ma), &[]).iter().flatten().all(Option::is_none));
        assert_ne!(c[0].key, c[1].key);
    }
}

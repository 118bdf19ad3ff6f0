use super::*;

#[test]
fn plane_basis_points_along_u_and_v() {
    let m = Mesh::plane(2.0, 1).unwrap();
    for i in 0..m.positions.len() {
        let t = m.tangents[i];
        assert!((t[0] - 1.0).abs() < 1e-6, "tangent {t:?}");
        // bitangent = w * cross(N, T) = w * cross(Y, X) = w * (-Z) must be +Z
        assert_eq!(t[3], -1.0);
        assert!((m.uv_scale[i][0] - 2.0).abs() < 1e-6 && (m.uv_scale[i][1] - 2.0).abs() < 1e-6);
    }
}

#[test]
fn no_usable_uvs_is_an_error() {
    let r = Mesh::from_arrays(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        vec![[0.0, 1.0, 0.0]; 3],
        vec![[0.5, 0.5]; 3],
        vec![0, 1, 2],
        None,
    );
    assert!(matches!(r, Err(Error::InvalidArgument { ref arg, .. }) if arg == "uvs"));
}

#[test]
fn one_degenerate_triangle_gets_a_fallback() {
    let (_, rep) = Mesh::from_arrays(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [5.0, 0.0, 5.0],
            [6.0, 0.0, 5.0],
            [5.0, 0.0, 6.0],
        ],
        vec![[0.0, 1.0, 0.0]; 6],
        vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.3, 0.3],
            [0.3, 0.3],
            [0.3, 0.3],
        ],
        vec![0, 2, 1, 3, 5, 4],
        None,
    )
    .unwrap();
    assert_eq!(rep.degenerate_uv_triangles, 1);
    assert_eq!(rep.fallback_vertices, 3);
}

#[test]
fn generated_meshes_have_outward_ccw_winding() {
    for m in [
        Mesh::sphere(1.0, 16, 8).unwrap(),
        Mesh::torus(1.0, 0.35, 16, 8).unwrap(),
        Mesh::cube(1.5, 1).unwrap(),
    ] {
        let (lo, hi) = m.bounds();
        let c = (lo + hi) * 0.5;
        let mut outward = 0;
        let mut total = 0;
        for tri in m.indices.chunks_exact(3) {
            let p = |i: u32| {
                DVec3::new(
                    m.positions[i as usize][0] as f64,
                    m.positions[i as usize][1] as f64,
                    m.positions[i as usize][2] as f64,
                )
            };
            let g = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            if g.length() < 1e-12 {
                continue;
            }
            let n = m.normals[tri[0] as usize];
            total += 1;
            if g.dot(DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)) > 0.0 {
                outward += 1;
            }
        }
        assert_eq!(outward, total);
        let _ = c;
    }
}

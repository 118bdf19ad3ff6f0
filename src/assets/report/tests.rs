use super::*;

/// Two quads side by side sharing an edge in space; the right one's uvs are a mirrored copy
/// of the left one's about the shared edge (as a symmetric asset's): no seam, a mirror axis,
/// two charts of which one is mirrored, six open edges.
#[test]
fn a_mirrored_pair_of_quads() {
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
        [2.0, 0.0, 1.0],
    ];
    let uvs = vec![
        [0.1, 0.1],
        [0.4, 0.1],
        [0.1, 0.4],
        [0.4, 0.4],
        [0.4, 0.1],
        [0.1, 0.1],
        [0.4, 0.4],
        [0.1, 0.4],
    ];
    let (m, _) = Mesh::from_arrays(
        positions,
        vec![[0.0, 1.0, 0.0]; 8],
        uvs,
        vec![0, 2, 1, 1, 2, 3, 4, 6, 5, 5, 6, 7],
        None,
    )
    .unwrap();
    let r = check_asset(&m, None, 1.0, None);
    assert_eq!(r.charts, 2);
    assert_eq!(r.mirrored_charts, 1);
    assert_eq!(r.mirrored_triangles, 2);
    assert_eq!(r.seam_edges, 0);
    assert_eq!(r.mirror_edges, 1);
    assert_eq!(r.open_edges, 6);
    assert_eq!(r.hard_edges, 0);
    assert_eq!(r.welded_vertices, 6);
    // the mirrored chart maps the same texels: its uvs overlap the first's entirely
    let hm = HeightMap::new(10, 10, (0..100).map(|k| (k % 10) as f32 / 9.0).collect()).unwrap();
    let r = check_asset(&m, Some(&hm), 1.0, None);
    assert_eq!(r.overlapping_texels, Some(9));
    // named at a triangle of the second chart (x in [1, 2]), not at the origin
    let (_, at) = r
        .examples
        .iter()
        .find(|(w, _)| w == "overlapping charts")
        .unwrap();
    assert!(at[0] > 1.0 && at[0] < 2.0, "{at:?}");
    assert_eq!(r.seam_height_max, None);
    assert_eq!(r.min_chart_gap_texels, Some(0));
    assert_eq!(r.max_clean_mip, None);
}

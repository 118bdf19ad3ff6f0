//! glTF assets read by the core: arrays as the file stores them, the tangent's handedness turned
//! into pomkit's, MikkTSpace where the file has no tangents, flat normals where it has no normals,
//! node transforms, and errors that name the file and the fix.

use pomkit::assets::{load_gltf, TangentSource};
use std::path::PathBuf;

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

struct Prim {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    tangents: Option<Vec<[f32; 4]>>,
    indices: Vec<u32>,
}

/// A .gltf with its buffer as a data URI: one mesh, one node with `matrix` (column-major).
fn write_gltf(name: &str, p: &Prim, matrix: Option<[f64; 16]>) -> PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut attrs = Vec::new();
    let mut add =
        |bin: &mut Vec<u8>, data: Vec<f32>, kind: &str, count: usize, attr: Option<&str>| {
            let off = bin.len();
            for x in &data {
                bin.extend_from_slice(&x.to_le_bytes());
            }
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{off},"byteLength":{}}}"#,
                data.len() * 4
            ));
            let i = accessors.len();
            let minmax = if kind == "VEC3" && attr == Some("POSITION") {
                let lo: Vec<f32> = (0..3)
                    .map(|k| {
                        data.iter()
                            .skip(k)
                            .step_by(3)
                            .cloned()
                            .fold(f32::MAX, f32::min)
                    })
                    .collect();
                let hi: Vec<f32> = (0..3)
                    .map(|k| {
                        data.iter()
                            .skip(k)
                            .step_by(3)
                            .cloned()
                            .fold(f32::MIN, f32::max)
                    })
                    .collect();
                format!(r#","min":{lo:?},"max":{hi:?}"#)
            } else {
                String::new()
            };
            accessors.push(format!(
            r#"{{"bufferView":{i},"componentType":5126,"count":{count},"type":"{kind}"{minmax}}}"#
        ));
            if let Some(a) = attr {
                attrs.push(format!(r#""{a}":{i}"#));
            }
        };
    let n = p.positions.len();
    add(&mut bin, p.positions.concat(), "VEC3", n, Some("POSITION"));
    if let Some(v) = &p.normals {
        add(&mut bin, v.concat(), "VEC3", n, Some("NORMAL"));
    }
    if let Some(v) = &p.uvs {
        add(&mut bin, v.concat(), "VEC2", n, Some("TEXCOORD_0"));
    }
    if let Some(v) = &p.tangents {
        add(&mut bin, v.concat(), "VEC4", n, Some("TANGENT"));
    }
    let off = bin.len();
    for i in &p.indices {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    views.push(format!(
        r#"{{"buffer":0,"byteOffset":{off},"byteLength":{}}}"#,
        p.indices.len() * 4
    ));
    let iv = views.len() - 1;
    accessors.push(format!(
        r#"{{"bufferView":{iv},"componentType":5125,"count":{},"type":"SCALAR"}}"#,
        p.indices.len()
    ));
    let ia = accessors.len() - 1;
    let node = match matrix {
        Some(m) => format!(r#"{{"mesh":0,"name":"rock","matrix":{m:?}}}"#),
        None => r#"{"mesh":0,"name":"rock"}"#.to_string(),
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{node}],
"meshes":[{{"primitives":[{{"attributes":{{{}}},"indices":{ia}}}]}}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
"bufferViews":[{}],"accessors":[{}]}}"#,
        attrs.join(","),
        bin.len(),
        base64(&bin),
        views.join(","),
        accessors.join(",")
    );
    let dir = std::env::temp_dir().join(format!("pomkit-assets-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

fn quad() -> Prim {
    // a bent quad (two triangles at an angle), normals not the face normals, counter-clockwise
    Prim {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.1, 1.0],
            [1.0, 0.3, 1.0],
        ],
        normals: Some(vec![
            [0.0, 1.0, 0.0],
            [0.1, 0.99, 0.0],
            [0.0, 0.98, -0.2],
            [0.05, 0.97, -0.25],
        ]),
        uvs: Some(vec![[0.1, 0.2], [0.7, 0.2], [0.1, 0.9], [0.7, 0.9]]),
        tangents: None,
        indices: vec![0, 2, 1, 1, 2, 3],
    }
}

#[test]
fn arrays_arrive_as_the_file_stores_them() {
    let mut q = quad();
    q.tangents = Some(vec![
        [1.0, 0.0, 0.0, 1.0],
        [0.99, -0.1, 0.0, 1.0],
        [1.0, 0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0, 1.0],
    ]);
    let nodes = load_gltf(&write_gltf("tangents.gltf", &q, None), Default::default())
        .unwrap()
        .nodes;
    assert_eq!(nodes.len(), 1);
    assert_eq!(nodes[0].name, "rock");
    let n = &nodes[0].parts[0];
    assert_eq!(n.tangents, TangentSource::File);
    assert_eq!(n.mesh.positions, q.positions);
    assert_eq!(n.mesh.normals, q.normals.clone().unwrap());
    assert_eq!(n.mesh.uvs, q.uvs.clone().unwrap());
    assert_eq!(n.mesh.indices, q.indices);
    // xyz as stored; w is pomkit's handedness, minus glTF's
    for (a, b) in n.mesh.tangents.iter().zip(q.tangents.as_ref().unwrap()) {
        assert_eq!(a[..3], b[..3]);
        assert_eq!(a[3], -b[3]);
    }
    assert_eq!(nodes[0].transform, glam::DMat4::IDENTITY);
}

#[test]
fn without_tangents_mikktspace_gives_pomkit_s_handedness() {
    let q = quad();
    let n = &load_gltf(&write_gltf("mikk.gltf", &q, None), Default::default())
        .unwrap()
        .nodes[0]
        .parts[0];
    assert_eq!(n.tangents, TangentSource::MikkTSpace);
    // u runs along +X, v along +Z: the bitangent w * cross(N, T) must point along +Z
    for (t, nn) in n.mesh.tangents.iter().zip(&n.mesh.normals) {
        let (t3, n3) = (glam::Vec3::from_slice(&t[..3]), glam::Vec3::from(*nn));
        assert!(t3.x > 0.9, "tangent {t:?}");
        assert!((n3.cross(t3) * t[3]).z > 0.9, "bitangent of {t:?}");
    }
}

#[test]
fn no_normals_become_flat_and_transforms_compose() {
    let mut q = quad();
    q.normals = None;
    let m = [
        2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.5, 0.0, -1.0, 1.0,
    ];
    let node = &load_gltf(&write_gltf("flat.gltf", &q, Some(m)), Default::default())
        .unwrap()
        .nodes[0];
    let n = &node.parts[0];
    assert_eq!(n.flat_normals, 1);
    assert_eq!(n.mesh.positions.len(), 6);
    for tri in n.mesh.indices.chunks_exact(3) {
        assert_eq!(
            n.mesh.normals[tri[0] as usize],
            n.mesh.normals[tri[1] as usize]
        );
    }
    let n = node;
    assert_eq!(n.transform.w_axis, glam::DVec4::new(0.5, 0.0, -1.0, 1.0));
    assert_eq!(n.transform.x_axis.x, 2.0);
}

#[test]
fn a_primitive_without_uvs_is_kept_apart_and_a_missing_file_is_named() {
    let mut q = quad();
    q.uvs = None;
    let f = load_gltf(&write_gltf("nouv.gltf", &q, None), Default::default()).unwrap();
    let part = &f.nodes[0].parts[0];
    assert!(!part.uvs);
    // unindexed, each triangle with uvs of its own that have area
    assert_eq!(part.mesh.indices.len(), q.indices.len());
    assert_eq!(part.mesh.positions.len(), q.indices.len());
    for t in part.mesh.indices.chunks_exact(3) {
        let uv = |k: usize| glam::Vec2::from(part.mesh.uvs[t[k] as usize]);
        assert!((uv(1) - uv(0)).perp_dot(uv(2) - uv(0)).abs() > 1e-3);
    }
    let e = load_gltf(
        std::path::Path::new("/nonexistent/rock.glb"),
        Default::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("path:") && e.contains("rock.glb"), "{e}");
}

#[test]
fn a_node_graph_with_a_cycle_is_refused_at_once() {
    // node 0 -> 1 -> 0, as in a public importer's test suite: the walk must end, with an error
    let q = quad();
    let p = write_gltf("cycle-src.gltf", &q, None);
    let json = std::fs::read_to_string(&p).unwrap().replace(
        r#""nodes":[{"mesh":0,"name":"rock"}]"#,
        r#""nodes":[{"mesh":0,"name":"rock","children":[1]},{"children":[0]}]"#,
    );
    assert!(json.contains(r#""children":[0]"#));
    let path = p.with_file_name("cycle.gltf");
    std::fs::write(&path, json).unwrap();
    let t = std::time::Instant::now();
    let e = load_gltf(&path, Default::default())
        .unwrap_err()
        .to_string();
    assert!(t.elapsed().as_secs_f64() < 2.0);
    assert!(
        e.contains("node 0 is reached twice") && e.contains("cycle"),
        "{e}"
    );
}

#[test]
fn zero_normals_are_refused_naming_the_vertex_or_repaired_on_request() {
    use pomkit::mesh::normals::NormalsMode;
    let mut q = quad();
    q.normals.as_mut().unwrap()[2] = [0.0, 0.0, 0.0];
    let path = write_gltf("zero-normals.gltf", &q, None);
    let e = load_gltf(&path, NormalsMode::File).unwrap_err().to_string();
    assert!(
        e.starts_with("normals:")
            && e.contains("primitive 0")
            && e.contains("vertex 2")
            && e.contains("normals=\"repair\""),
        "{e}"
    );
    let n = &load_gltf(&path, NormalsMode::Repair).unwrap().nodes[0].parts[0];
    assert_eq!(n.replaced_normals, 1);
    let r = n.mesh.normals[2];
    assert!(
        (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - 1.0).abs() < 1e-5,
        "{r:?}"
    );
    assert!(r[1] > 0.9, "{r:?}");
    // the others are the file's, bit for bit
    assert_eq!(n.mesh.normals[1], q.normals.as_ref().unwrap()[1]);
}

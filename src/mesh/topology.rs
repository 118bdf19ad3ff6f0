//! A mesh's surface as one surface: vertices welded by position (bit-equal floats), and each
//! geometric edge with the triangle sides that lie on it. A seam is an edge whose sides carry
//! other uvs; a hard edge one whose sides carry other normals; an open border an edge with one
//! side; a non-manifold edge one with more than two.

use super::Mesh;
use std::collections::HashMap;

/// One triangle's side on a geometric edge: the triangle, which of its sides (k: corners k and
/// k+1), and whether it runs from the edge's first welded vertex to its second.
#[derive(Clone, Copy, Debug)]
pub struct Side {
    pub tri: u32,
    pub k: u8,
    pub forward: bool,
}

#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// welded id of each vertex
    pub weld: Vec<u32>,
    /// number of welded positions
    pub welded: usize,
    /// edge (welded ids, lower first) -> its index in `sides`
    pub edge_of: HashMap<(u32, u32), u32>,
    /// each edge's welded ends and its sides
    pub edges: Vec<((u32, u32), Vec<Side>)>,
    /// each triangle's three edges (side k joins corners k and k+1)
    pub tri_edges: Vec<[u32; 3]>,
}

impl Topology {
    /// Vertices welded where their positions are bit-equal (a file's split vertices).
    pub fn new(mesh: &Mesh) -> Topology {
        Self::welded_by(mesh, |p| {
            p.map(|x| if x == 0.0 { 0 } else { x.to_bits() as i64 })
        })
    }

    /// Vertices welded where their positions agree to a millionth of the mesh's extent: also
    /// the seams of generated meshes, whose two sides' positions differ in the last bits.
    pub fn quantised(mesh: &Mesh) -> Topology {
        let (lo, hi) = mesh.positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(mut a, mut b), p| {
                for i in 0..3 {
                    a[i] = a[i].min(p[i] as f64);
                    b[i] = b[i].max(p[i] as f64);
                }
                (a, b)
            },
        );
        let extent = (0..3).map(|i| (hi[i] - lo[i]).max(0.0)).fold(0.0, f64::max);
        let quantum = extent.max(1e-30) * 1e-6;
        Self::welded_by(mesh, |p| p.map(|x| (x as f64 / quantum).round() as i64))
    }

    fn welded_by(mesh: &Mesh, key: impl Fn([f32; 3]) -> [i64; 3]) -> Topology {
        let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
        let weld: Vec<u32> = mesh
            .positions
            .iter()
            .map(|p| {
                let n = ids.len() as u32;
                *ids.entry(key(*p)).or_insert(n)
            })
            .collect();
        let mut t = Topology {
            welded: ids.len(),
            weld,
            ..Default::default()
        };
        for (ti, tri) in mesh.indices.chunks_exact(3).enumerate() {
            let mut te = [0u32; 3];
            for k in 0..3 {
                let a = t.weld[tri[k] as usize];
                let b = t.weld[tri[(k + 1) % 3] as usize];
                let key = (a.min(b), a.max(b));
                let n = t.edges.len() as u32;
                let e = *t.edge_of.entry(key).or_insert(n);
                if e == n {
                    t.edges.push((key, Vec::new()));
                }
                t.edges[e as usize].1.push(Side {
                    tri: ti as u32,
                    k: k as u8,
                    forward: a <= b,
                });
                te[k] = e;
            }
            t.tri_edges.push(te);
        }
        t
    }

    /// The mesh vertices at side `s`'s two ends, ordered as the edge's welded ends.
    pub fn side_vertices(&self, mesh: &Mesh, s: Side) -> (u32, u32) {
        let tri = &mesh.indices[s.tri as usize * 3..s.tri as usize * 3 + 3];
        let (a, b) = (tri[s.k as usize], tri[(s.k as usize + 1) % 3]);
        if s.forward {
            (a, b)
        } else {
            (b, a)
        }
    }
}

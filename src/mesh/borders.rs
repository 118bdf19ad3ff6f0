//! A mesh's open borders (sides with no triangle across them, by welded position), and the
//! borders of other objects that run along them: a model split into primitives by material, or
//! parts modelled apart and left unwelded, meets itself at such borders, and the surface goes on
//! across them in a triangle of another mesh.

use super::topology::Topology;
use super::Mesh;
use glam::{DMat4, DVec3};
use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// One open border side: its triangle, the side (corners k and k+1), its ends, and the plane
/// (unit face normal by the winding, offset) of its triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Border {
    pub tri: u32,
    pub side: u8,
    pub a: DVec3,
    pub b: DVec3,
    pub plane: [f64; 4],
}

/// A border of another object, in this object's space: its ends and its triangle's plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForeignBorder {
    pub a: DVec3,
    pub b: DVec3,
    pub plane: [f64; 4],
}

fn corners(mesh: &Mesh, t: usize) -> [DVec3; 3] {
    std::array::from_fn(|k| mesh.position_f64(mesh.indices[3 * t + k]))
}

/// The plane through three points: unit normal along (c1 - c0) x (c2 - c0), and offset (zero
/// where they are collinear).
pub fn plane_through(c: [DVec3; 3]) -> [f64; 4] {
    let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero();
    [n.x, n.y, n.z, n.dot(c[0])]
}

/// Every open border side of the mesh, in triangle and side order.
pub fn open_borders(mesh: &Mesh, topo: &Topology) -> Vec<Border> {
    let n = mesh.indices.len() / 3;
    let mut out = Vec::new();
    for t in 0..n {
        for k in 0..3 {
            if topo.edges[topo.tri_edges[t][k] as usize].1.len() != 1 {
                continue;
            }
            let c = corners(mesh, t);
            out.push(Border {
                tri: t as u32,
                side: k as u8,
                a: c[k],
                b: c[(k + 1) % 3],
                plane: plane_through(c),
            });
        }
    }
    out
}

impl Border {
    /// Its ends and plane, as another object's contacts hold it.
    pub fn segment(&self) -> ForeignBorder {
        ForeignBorder {
            a: self.a,
            b: self.b,
            plane: self.plane,
        }
    }
}

impl ForeignBorder {
    /// Carried by `m` (an affine map that keeps orientation): its ends mapped, and its plane's
    /// normal by the inverse transpose.
    pub fn carried(&self, m: &DMat4) -> ForeignBorder {
        let a = m.transform_point3(self.a);
        let n = glam::DMat3::from_mat4(*m).inverse().transpose()
            * DVec3::new(self.plane[0], self.plane[1], self.plane[2]);
        let n = n.normalize_or_zero();
        ForeignBorder {
            a,
            b: m.transform_point3(self.b),
            plane: [n.x, n.y, n.z, n.dot(a)],
        }
    }
}

/// How far apart, as a share of a mesh's size, two borders may lie and still run along each
/// other (the walk's crack test, and the boxes `contacts` compares).
pub const TOLERANCE: f64 = 1e-5;

/// An object's contacts: the open borders of the scene's other objects within its box (grown
/// by `TOLERANCE` of its size), in its own space. A model split into primitives by material,
/// or parts modelled apart and left unwelded, has sides with no triangle across them in its own
/// mesh where the surface goes on in another object's; the methods that walk the mesh (NCS,
/// curved relief) tell such a crack from the surface's edge by these. Empty where an object
/// meets no other.
#[derive(Clone, Debug, Default)]
pub struct Contacts {
    pub borders: Arc<Vec<ForeignBorder>>,
    /// the borders' content key (0 where there are none)
    pub key: u64,
}

/// One object as `contacts` sees it: its mesh's open borders and box, and its object-to-world
/// map.
pub struct Part {
    pub borders: Arc<Vec<Border>>,
    pub bounds: (DVec3, DVec3),
    pub to_world: DMat4,
}

fn grown((lo, hi): (DVec3, DVec3)) -> (DVec3, DVec3) {
    let t = TOLERANCE * (hi - lo).max_element().max(1e-30);
    (lo - t, hi + t)
}

fn overlap((a0, a1): (DVec3, DVec3), (b0, b1): (DVec3, DVec3)) -> bool {
    a0.cmple(b1).all() && b0.cmple(a1).all()
}

/// The world box of a local box under `m` (its eight corners').
fn world_box((lo, hi): (DVec3, DVec3), m: &DMat4) -> (DVec3, DVec3) {
    (0..8).fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), k| {
        let c = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let w = m.transform_point3(c);
        (a.min(w), b.max(w))
    })
}

/// Every part's contacts: the other parts' borders, carried into its space, that fall within
/// its grown box.
pub fn contacts(parts: &[Part]) -> Vec<Contacts> {
    let mut out = vec![Contacts::default(); parts.len()];
    if parts.len() < 2 {
        return out;
    }
    let world: Vec<(Vec<ForeignBorder>, (DVec3, DVec3))> = parts
        .iter()
        .map(|p| {
            let w = p.borders.iter().map(|b| b.segment().carried(&p.to_world)).collect();
            (w, grown(world_box(p.bounds, &p.to_world)))
        })
        .collect();
    for (i, p) in parts.iter().enumerate() {
        let to_local = p.to_world.inverse();
        let local_box = grown(p.bounds);
        let near: Vec<ForeignBorder> = world
            .iter()
            .enumerate()
            .filter(|&(j, (_, bx))| j != i && overlap(*bx, world[i].1))
            .flat_map(|(_, (w, _))| w.iter().map(|b| b.carried(&to_local)))
            .filter(|l| overlap((l.a.min(l.b), l.a.max(l.b)), local_box))
            .collect();
        if near.is_empty() {
            continue;
        }
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for b in &near {
            for x in [b.a.to_array(), b.b.to_array()].into_iter().flatten().chain(b.plane) {
                x.to_bits().hash(&mut h);
            }
        }
        out[i] = Contacts {
            key: h.finish().max(1),
            borders: Arc::new(near),
        };
    }
    out
}

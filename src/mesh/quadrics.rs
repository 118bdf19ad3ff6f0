//! Per-vertex quadrics of the base mesh (Oliveira & Policarpo 2005): near each vertex the surface
//! is taken as z = a x² + b y² in the vertex's basis (x along the tangent, y along the bitangent,
//! z along the normal, world units), fitted by least squares to the vertex's neighbours: the
//! other corners of the triangles around it on its side of any hard edge (welded across uv seams
//! by position, where the corners' normals agree). Across a hard edge the other side is not the
//! vertex's surface (each side is displaced along its own normals, docs/conventions.md), so a
//! flat face of a hard-edged box gets no curvature from the faces beside it.

use crate::mesh::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// (a, b) per vertex: the curvature terms along the tangent and the bitangent (a sphere of
/// radius R seen from outside: a = b = -1 / 2R). Zero where the neighbours do not determine
/// them (fewer than two independent directions).
pub fn fit(mesh: &Mesh) -> Vec<[f32; 2]> {
    let p = |i: usize| DVec3::from(mesh.positions[i].map(f64::from));
    // weld vertices that share a position (uv seams, poles) so that they share neighbours
    let quant = |v: DVec3| {
        let q = 1e6;
        [
            (v.x * q).round() as i64,
            (v.y * q).round() as i64,
            (v.z * q).round() as i64,
        ]
    };
    let mut group: HashMap<[i64; 3], usize> = HashMap::new();
    let ids: Vec<usize> = (0..mesh.positions.len())
        .map(|i| {
            let n = group.len();
            *group.entry(quant(p(i))).or_insert(n)
        })
        .collect();
    let normal = |i: usize| DVec3::from(mesh.normals[i].map(f64::from)).normalize_or_zero();
    // the corners at each welded position: (the vertex, its triangle's other two vertices)
    let mut corners: Vec<Vec<(usize, [usize; 2])>> = vec![Vec::new(); group.len()];
    for t in mesh.indices.chunks_exact(3) {
        for k in 0..3 {
            let (a, b, c) = (
                t[k] as usize,
                t[(k + 1) % 3] as usize,
                t[(k + 2) % 3] as usize,
            );
            corners[ids[a]].push((a, [b, c]));
        }
    }
    // a vertex's ring: the other corners of the triangles whose corner at its position has its
    // normal (a smooth side: split normals that agree to float32's rounding count as one)
    let ring: Vec<Vec<DVec3>> = (0..mesh.positions.len())
        .map(|i| {
            let ni = normal(i);
            let mut r: Vec<DVec3> = Vec::new();
            for &(v, others) in &corners[ids[i]] {
                if normal(v).dot(ni) < 1.0 - 1e-6 {
                    continue;
                }
                for o in others {
                    let q = p(o);
                    if !r.iter().any(|x| (*x - q).length_squared() < 1e-18) {
                        r.push(q);
                    }
                }
            }
            r
        })
        .collect();
    (0..mesh.positions.len())
        .map(|i| {
            let n = normal(i);
            let t4 = mesh.tangents[i];
            let mut t = DVec3::new(t4[0] as f64, t4[1] as f64, t4[2] as f64);
            t = (t - n * t.dot(n)).normalize_or_zero();
            let b = n.cross(t) * if t4[3] < 0.0 { -1.0 } else { 1.0 };
            // least squares of z = a x² + b y²: the 2x2 normal equations
            let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for q in &ring[i] {
                let d = *q - p(i);
                let (x2, y2, z) = (d.dot(t).powi(2), d.dot(b).powi(2), d.dot(n));
                sxx += x2 * x2;
                sxy += x2 * y2;
                syy += y2 * y2;
                sxz += x2 * z;
                syz += y2 * z;
            }
            let det = sxx * syy - sxy * sxy;
            if det.abs() <= 1e-12 * (sxx * syy).max(1e-300) || !det.is_finite() {
                return [0.0, 0.0];
            }
            let a = (sxz * syy - syz * sxy) / det;
            let bb = (syz * sxx - sxz * sxy) / det;
            [a as f32, bb as f32]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_and_plane_and_cylinder() {
        // a sphere of radius 1: a = b = -1/2 away from the poles
        let s = Mesh::sphere(1.0, 48, 24).unwrap();
        let q = fit(&s);
        let mid = (0..s.positions.len())
            .filter(|&i| s.positions[i][1].abs() < 0.5)
            .collect::<Vec<_>>();
        assert!(!mid.is_empty());
        for i in mid {
            assert!(
                (q[i][0] + 0.5).abs() < 0.03 && (q[i][1] + 0.5).abs() < 0.03,
                "{:?}",
                q[i]
            );
        }
        // a plane: zero
        let p = Mesh::plane(2.0, 4).unwrap();
        assert!(fit(&p)
            .iter()
            .all(|c| c[0].abs() < 1e-9 && c[1].abs() < 1e-9));
        // a cube of split normals (every edge hard): each face is flat on its side, zero
        let c = Mesh::cube(1.0, 2).unwrap();
        assert!(fit(&c)
            .iter()
            .all(|q| q[0].abs() < 1e-9 && q[1].abs() < 1e-9));
    }
}

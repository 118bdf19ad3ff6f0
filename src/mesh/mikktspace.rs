//! MikkTSpace tangents (the `bevy_mikktspace` crate), as the glTF specification asks where a file
//! has none, so that maps baked against MikkTSpace line up.
//!
//! MikkTSpace runs on pomkit's uvs (v down): its bitangent `w * cross(N, T)` then points along
//! +dP/dv, which is pomkit's handedness. Its answer is per triangle corner; a vertex takes its
//! first corner's. MikkTSpace gives a vertex's corners one answer except where the vertex is
//! shared across a mirror axis (its corners' handedness differs); `check_asset` reports those
//! (`mirror_shared_edges`), and exporters split such vertices.

use bevy_mikktspace::{Geometry, TangentSpace};

struct Corners<'a> {
    positions: &'a [[f32; 3]],
    normals: &'a [[f32; 3]],
    uvs: &'a [[f32; 2]],
    indices: &'a [u32],
    out: Vec<Option<[f32; 4]>>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.indices[face * 3 + vert] as usize
    }
}

impl Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)]
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)]
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.vertex(face, vert)]
    }
    fn set_tangent(&mut self, t: Option<TangentSpace>, face: usize, vert: usize) {
        let v = self.vertex(face, vert);
        if let (Some(t), None) = (t, self.out[v]) {
            self.out[v] = Some(t.tangent_encoded());
        }
    }
}

/// Per-vertex MikkTSpace tangents in pomkit's handedness; None for a vertex MikkTSpace left
/// without one (only degenerate triangles touch it).
pub fn mikktspace(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    indices: &[u32],
) -> Vec<Option<[f32; 4]>> {
    let mut g = Corners {
        positions,
        normals,
        uvs,
        indices,
        out: vec![None; positions.len()],
    };
    // the crate's error type has no variant: generation cannot fail
    let _ = bevy_mikktspace::generate_tangents(&mut g);
    g.out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit quad in the XZ plane (normal +Y) with the given corner uvs: each vertex's tangent.
    fn quad(uv: [[f32; 2]; 4]) -> Vec<[f32; 4]> {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
        ];
        let n = [[0.0, 1.0, 0.0]; 4];
        mikktspace(&p, &n, &uv, &[0, 2, 1, 1, 2, 3])
            .into_iter()
            .map(Option::unwrap)
            .collect()
    }

    /// u along +X, v along +Z: the tangent is +X and the bitangent w * cross(Y, X) = -w Z must
    /// point along +Z: w = -1, as pomkit's own bases say. A mirrored chart (u reversed) flips
    /// both the tangent and w.
    #[test]
    fn the_plane_s_basis_is_pomkit_s_and_a_mirror_flips_it() {
        for (uv, x, w) in [
            ([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]], 1.0, -1.0),
            ([[1.0, 0.0], [0.0, 0.0], [1.0, 1.0], [0.0, 1.0]], -1.0, 1.0),
        ] {
            for t in quad(uv) {
                assert!(
                    (t[0] - x).abs() < 1e-6 && t[1].abs() < 1e-6 && t[2].abs() < 1e-6,
                    "{t:?}"
                );
                assert_eq!(t[3], w);
            }
        }
    }
}

//! Vertex normals as a file or a caller gives them, and what a loader may do about bad ones.
//!
//! `NormalsMode::File` (the default) keeps every normal as given and refuses a mesh with an
//! unusable one (NaN, Inf or zero length), naming the first such vertex and the option that fixes
//! it. `Repair` recomputes only the unusable ones; `Recompute` recomputes all. A recomputed normal
//! is the area-weighted sum of the face normals around the vertex's position (every vertex at that
//! position, so that both sides of a uv seam get the same normal), over the faces within
//! `CREASE_DEGREES` of the vertex's own faces, so that a hard edge (split normals) stays hard.

use crate::error::{Error, Result};
use glam::DVec3;
use std::collections::HashMap;

/// The angle between face normals past which a recomputed normal keeps an edge hard.
pub const CREASE_DEGREES: f64 = 60.0;

/// What to do with a mesh's vertex normals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalsMode {
    /// keep them; refuse unusable ones (NaN, Inf, zero length)
    #[default]
    File,
    /// recompute every normal from the faces
    Recompute,
    /// recompute only the unusable ones
    Repair,
}

impl NormalsMode {
    pub const NAMES: [&'static str; 3] = ["file", "recompute", "repair"];

    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "file" => Ok(Self::File),
            "recompute" => Ok(Self::Recompute),
            "repair" => Ok(Self::Repair),
            o => Err(Error::arg(
                "normals",
                format!("unknown mode {o:?}: give \"file\", \"recompute\" or \"repair\""),
            )),
        }
    }
}

/// A normal a renderer cannot use: a NaN or Inf component, or (nearly) zero length.
pub fn unusable(n: &[f32; 3]) -> bool {
    n.iter().any(|x| !x.is_finite())
        || DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64).length() < 1e-12
}

/// Apply `mode` to `normals` in place. Returns how many normals were replaced. With
/// `NormalsMode::File` an unusable normal is an error naming its vertex (`what` says where the
/// arrays came from, e.g. a file's mesh and primitive) and the modes that fix it.
pub fn apply(
    mode: NormalsMode,
    positions: &[[f32; 3]],
    normals: &mut [[f32; 3]],
    indices: &[u32],
    what: &str,
) -> Result<usize> {
    if normals.len() != positions.len() {
        return Err(Error::arg(
            "normals",
            format!(
                "{what}expected {} normals (one per position), got {}",
                positions.len(),
                normals.len()
            ),
        ));
    }
    if let Some(i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(Error::arg(
            "indices",
            format!(
                "{what}index {i} is out of range for {} vertices",
                positions.len()
            ),
        ));
    }
    let bad: Vec<usize> = (0..normals.len())
        .filter(|&i| unusable(&normals[i]))
        .collect();
    let targets: Vec<usize> = match mode {
        NormalsMode::File => {
            if let Some(&first) = bad.first() {
                let n = normals[first];
                let more = match bad.len() - 1 {
                    0 => String::new(),
                    k => format!(" (and {k} more)"),
                };
                return Err(Error::arg(
                    "normals",
                    format!(
                        "{what}vertex {first} has an unusable normal {n:?} (NaN, Inf or zero length){more}; \
                         load with normals=\"repair\" to recompute only those from the faces, or normals=\"recompute\" for all"
                    ),
                ));
            }
            return Ok(0);
        }
        NormalsMode::Repair => bad,
        NormalsMode::Recompute => (0..normals.len()).collect(),
    };
    if targets.is_empty() {
        return Ok(0);
    }
    let fresh = recomputed(positions, indices, &targets);
    for (&i, n) in targets.iter().zip(fresh) {
        normals[i] = n;
    }
    Ok(targets.len())
}

/// Recomputed normals for the vertices `targets` (see the module's text). A vertex no face
/// with area touches gets +Z, so that the mesh stays renderable; such a vertex draws nothing.
fn recomputed(positions: &[[f32; 3]], indices: &[u32], targets: &[usize]) -> Vec<[f32; 3]> {
    let p = |i: u32| DVec3::from(positions[i as usize].map(f64::from));
    // area-weighted face normals (twice the area)
    let faces: Vec<DVec3> = indices
        .chunks_exact(3)
        .map(|t| (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])))
        .collect();
    let key = |i: usize| positions[i].map(f32::to_bits);
    let mut by_position: HashMap<[u32; 3], Vec<usize>> = HashMap::new();
    let mut own: Vec<Vec<usize>> = vec![Vec::new(); positions.len()];
    for (f, t) in indices.chunks_exact(3).enumerate() {
        for &v in t {
            own[v as usize].push(f);
        }
    }
    for (f, t) in indices.chunks_exact(3).enumerate() {
        for &v in t {
            by_position.entry(key(v as usize)).or_default().push(f);
        }
    }
    let cos_crease = CREASE_DEGREES.to_radians().cos();
    targets
        .iter()
        .map(|&v| {
            let around = by_position.get(&key(v)).map_or(&[][..], |f| &f[..]);
            let mine = own[v].iter().fold(DVec3::ZERO, |s, &f| s + faces[f]);
            let mut sum = DVec3::ZERO;
            let mut seen: Vec<usize> = Vec::new();
            for &f in around {
                if seen.contains(&f) {
                    continue;
                }
                seen.push(f);
                let n = faces[f];
                let keep = match (mine.try_normalize(), n.try_normalize()) {
                    (Some(m), Some(u)) => m.dot(u) >= cos_crease,
                    _ => true,
                };
                if keep {
                    sum += n;
                }
            }
            let n = sum
                .try_normalize()
                .or_else(|| mine.try_normalize())
                .unwrap_or(DVec3::Z);
            [n.x as f32, n.y as f32, n.z as f32]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles folded 90 degrees along the x axis, the fold's vertices split (a hard edge)
    /// and one of them shared: a seam that must not crease, and a hard edge that must stay hard.
    fn fold() -> (Vec<[f32; 3]>, Vec<u32>) {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0], // flat face in XZ (normal +Y with this winding)
            [0.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0], // vertical face in XY, its own copies of the fold's vertices
        ];
        (p, vec![0, 1, 2, 3, 4, 5])
    }

    #[test]
    fn file_refuses_naming_the_vertex_and_the_fix() {
        let (p, i) = fold();
        let mut n = vec![[0.0, 1.0, 0.0]; 6];
        n[4] = [0.0, 0.0, 0.0];
        n[5] = [f32::NAN, 0.0, 0.0];
        let e = apply(
            NormalsMode::File,
            &p,
            &mut n,
            &i,
            "mesh \"m\", primitive 0: ",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("vertex 4"), "{e}");
        assert!(e.contains("and 1 more"), "{e}");
        assert!(e.contains("normals=\"repair\""), "{e}");
        assert!(e.contains("primitive 0"), "{e}");
    }

    #[test]
    fn repair_replaces_only_the_bad_and_keeps_hard_edges() {
        let (p, i) = fold();
        let mut n = vec![
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0; 3],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ];
        let k = apply(NormalsMode::Repair, &p, &mut n, &i, "").unwrap();
        assert_eq!(k, 1);
        // vertex 3 sits on the fold with the vertical face: the flat face is 90 degrees away,
        // past the crease, so it gets the vertical face's normal alone
        let z = n[3];
        assert!(
            (z[2].abs() - 1.0).abs() < 1e-6 && z[1].abs() < 1e-6,
            "{z:?}"
        );
        assert_eq!(n[0], [0.0, 1.0, 0.0]);
    }

    #[test]
    fn recompute_smooths_across_a_seam() {
        // a flat quad whose diagonal's vertices are split (a uv seam): every normal is the plane's
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, -1.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
        ];
        let i = vec![0, 1, 2, 3, 4, 5];
        let mut n = vec![[1.0, 0.0, 0.0]; 6];
        assert_eq!(
            apply(NormalsMode::Recompute, &p, &mut n, &i, "").unwrap(),
            6
        );
        for v in n {
            assert!((v[1] - 1.0).abs() < 1e-6, "{v:?}");
        }
    }
}

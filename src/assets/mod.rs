//! Users' assets: glTF 2.0 read as the file says (the `gltf` crate; MikkTSpace tangents where a
//! file has none, from `mesh::mikktspace`), and the asset report (`report`).
//!
//! A glTF primitive keeps its positions, normals and `TEXCOORD_0` bit for bit. glTF's uv origin
//! (top-left, v down) is pomkit's. A file's `TANGENT` keeps its xyz; its handedness is glTF's,
//! whose bitangent `w * cross(N, T)` points toward decreasing v (up the image), and pomkit's
//! bitangent points along +dP/dv, so pomkit's w is minus the file's. A primitive without normals
//! gets flat normals (its triangles' vertices split), as the glTF specification asks.

pub mod report;

use crate::error::{Error, Result};
use crate::mesh::normals::{self, NormalsMode};
use crate::mesh::{Mesh, TangentBases};
use glam::DMat4;
use std::path::Path;

/// Where a loaded mesh's tangents came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangentSource {
    /// the file's `TANGENT` attribute
    File,
    /// MikkTSpace, computed from the positions, normals and uvs
    MikkTSpace,
}

/// One mesh node of a glTF scene: its primitives merged into one mesh in the mesh's own space,
/// and the node's world transform.
#[derive(Clone, Debug)]
pub struct AssetNode {
    pub name: String,
    pub mesh: Mesh,
    pub transform: DMat4,
    pub tangents: TangentSource,
    /// primitives whose normals were missing and made flat
    pub flat_normals: usize,
    /// normals replaced by `NormalsMode::Repair` or `Recompute`
    pub replaced_normals: usize,
}

fn gltf_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::arg(
        "path",
        format!("{}: not a readable glTF 2.0 file ({e})", path.display()),
    )
}

/// Every mesh node of the file's default scene (or of its first scene, or of every root node
/// when it names none), depth first, with world transforms; `normals` says what to do with the
/// file's normals (`mesh::normals`). A node graph that is not a forest (a node reached twice: a
/// cycle, or a node with two parents) is refused, so every walk visits each node at most once.
pub fn load_gltf(path: &Path, normals: NormalsMode) -> Result<Vec<AssetNode>> {
    let doc = gltf::Gltf::open(path).map_err(|e| gltf_err(path, e))?;
    let buffers = gltf::import_buffers(&doc.document, path.parent(), doc.blob.clone())
        .map_err(|e| gltf_err(path, e))?;
    let mut out = Vec::new();
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => doc.nodes().collect(),
    };
    let mut reached: Vec<Option<usize>> = vec![None; doc.nodes().len()];
    let mut stack: Vec<(gltf::Node, DMat4, Option<usize>)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY, None))
        .collect();
    while let Some((node, parent, from)) = stack.pop() {
        let i = node.index();
        if let Some(before) = reached[i] {
            let was = match before {
                usize::MAX => "a root of the scene".to_string(),
                p => format!("a child of node {p}"),
            };
            let now = match from {
                None => "a root of the scene".to_string(),
                Some(p) => format!("a child of node {p}"),
            };
            return Err(Error::arg(
                "path",
                format!(
                    "{}: the node graph is not a tree: node {i} is reached twice ({was}, and {now}){}; glTF requires every node to have at most one parent (re-export the asset, or remove the loop)",
                    path.display(),
                    if ancestors(&reached, from).any(|a| a == i) { ": the graph has a cycle" } else { "" },
                ),
            ));
        }
        reached[i] = Some(from.unwrap_or(usize::MAX));
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        if let Some(m) = node.mesh() {
            let name = node
                .name()
                .or(m.name())
                .map(str::to_string)
                .unwrap_or_else(|| format!("node {}", node.index()));
            out.push(read_mesh(path, &m, &buffers, name, world, normals)?);
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, Some(i)));
        }
    }
    if out.is_empty() {
        return Err(Error::arg(
            "path",
            format!("{}: the file's scene holds no mesh", path.display()),
        ));
    }
    Ok(out)
}

/// The chain of parents from `node` up to its root, as `reached` records them (each node once,
/// so the chain ends within as many steps as there are nodes).
fn ancestors(reached: &[Option<usize>], node: Option<usize>) -> impl Iterator<Item = usize> + '_ {
    let mut at = node;
    let mut left = reached.len() + 1;
    std::iter::from_fn(move || {
        let n = at.filter(|_| left > 0)?;
        left -= 1;
        at = reached[n].filter(|&p| p != usize::MAX);
        Some(n)
    })
}

fn read_mesh(
    path: &Path,
    m: &gltf::Mesh,
    buffers: &[gltf::buffer::Data],
    name: String,
    transform: DMat4,
    normals_mode: NormalsMode,
) -> Result<AssetNode> {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut tangents: Vec<[f32; 4]> = Vec::new();
    let mut indices = Vec::new();
    let mut all_tangents = true;
    let mut flat_normals = 0;
    let mut replaced_normals = 0;
    let at =
        |what: &str, p: usize| format!("{}: mesh {name:?}, primitive {p}: {what}", path.display());
    for (pi, prim) in m.primitives().enumerate() {
        if prim.mode() != gltf::mesh::Mode::Triangles {
            return Err(Error::arg(
                "path",
                at(&format!("mode {:?}; pomkit renders triangles only (re-export the asset as triangles)", prim.mode()), pi),
            ));
        }
        let r = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let p: Vec<[f32; 3]> = r
            .read_positions()
            .ok_or_else(|| Error::arg("path", at("has no POSITION", pi)))?
            .collect();
        let uv: Vec<[f32; 2]> = r
            .read_tex_coords(0)
            .ok_or_else(|| {
                Error::arg(
                    "path",
                    at("has no TEXCOORD_0; displacement needs a uv parameterisation (unwrap the mesh, e.g. with xatlas)", pi),
                )
            })?
            .into_f32()
            .collect();
        let idx: Vec<u32> = match r.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..p.len() as u32).collect(),
        };
        if let Some(i) = idx.iter().find(|i| **i as usize >= p.len()) {
            return Err(Error::arg(
                "path",
                at(
                    &format!("index {i} is out of range for {} vertices", p.len()),
                    pi,
                ),
            ));
        }
        let base = positions.len() as u32;
        match r.read_normals() {
            Some(n) => {
                let mut n: Vec<[f32; 3]> = n.collect();
                if n.len() != p.len() {
                    return Err(Error::arg(
                        "path",
                        at(
                            &format!("NORMAL has {} entries for {} positions", n.len(), p.len()),
                            pi,
                        ),
                    ));
                }
                replaced_normals += normals::apply(
                    normals_mode,
                    &p,
                    &mut n,
                    &idx,
                    &format!("{}: mesh {name:?}, primitive {pi}: ", path.display()),
                )
                .map_err(|e| match e {
                    Error::InvalidArgument { msg, .. } => Error::arg("normals", msg),
                    e => e,
                })?;
                let t: Option<Vec<[f32; 4]>> = r.read_tangents().map(|t| t.collect());
                all_tangents &= t.is_some();
                if let Some(t) = t {
                    tangents.extend(t.iter().map(|t| [t[0], t[1], t[2], -t[3]]));
                }
                positions.extend(p);
                normals.extend(n);
                uvs.extend(uv);
                indices.extend(idx.iter().map(|i| i + base));
            }
            None => {
                // flat normals: each triangle's corners get their own vertices
                flat_normals += 1;
                all_tangents = false;
                for tri in idx.chunks_exact(3) {
                    let q = [0, 1, 2].map(|k| glam::Vec3::from(p[tri[k] as usize]));
                    let nn = (q[1] - q[0]).cross(q[2] - q[0]).normalize_or_zero();
                    for &i in tri {
                        indices.push(positions.len() as u32);
                        positions.push(p[i as usize]);
                        normals.push(nn.to_array());
                        uvs.push(uv[i as usize]);
                    }
                }
            }
        }
    }
    let frames = if all_tangents {
        TangentBases::Given(tangents)
    } else {
        TangentBases::MikkTSpace
    };
    let (mesh, _) =
        Mesh::from_arrays_with(positions, normals, uvs, indices, frames).map_err(|e| match e {
            Error::InvalidArgument { arg, msg } => Error::arg(
                "path",
                format!("{}: mesh {name:?}: {arg}: {msg}", path.display()),
            ),
            e => e,
        })?;
    Ok(AssetNode {
        name,
        mesh,
        transform,
        tangents: if all_tangents {
            TangentSource::File
        } else {
            TangentSource::MikkTSpace
        },
        flat_normals,
        replaced_normals,
    })
}

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

/// One mesh node of a glTF scene: its primitives grouped into parts (one per material, and the
/// primitives without `TEXCOORD_0` apart), each part one mesh in the node's own space, and the
/// node's world transform.
#[derive(Clone, Debug)]
pub struct AssetNode {
    pub name: String,
    pub parts: Vec<AssetPart>,
    pub transform: DMat4,
    /// primitives left out: (primitive index, why): points and lines (their mode), and
    /// primitives whose every triangle has no area
    pub skipped: Vec<(usize, String)>,
}

/// Primitives of one node that share a material (and whether they have uvs), merged into one mesh.
#[derive(Clone, Debug)]
pub struct AssetPart {
    pub mesh: Mesh,
    /// the glTF material's index, None for the default material
    pub material: Option<usize>,
    /// false: primitives without `TEXCOORD_0` (or whose uvs are all degenerate), kept unindexed
    /// with uvs projected per triangle (`project_uvs`); they have no parameterisation to
    /// displace, and are drawn undisplaced (depth 0)
    pub uvs: bool,
    /// the node's primitive indices in this part
    pub primitives: Vec<usize>,
    pub tangents: TangentSource,
    /// primitives whose normals were missing and made flat
    pub flat_normals: usize,
    /// normals replaced by `NormalsMode::Repair` or `Recompute`
    pub replaced_normals: usize,
}

/// A glTF material's base colour: `baseColorFactor` (linear RGBA) and `baseColorTexture`
/// decoded to sRGB RGBA8, with its sampler's wrap modes. Other inputs are ignored (docs/assets.md).
#[derive(Clone, Debug)]
pub struct AssetMaterial {
    pub name: Option<String>,
    pub base_color_factor: [f32; 4],
    pub base_color_texture: Option<BaseColorTexture>,
}

#[derive(Clone, Debug)]
pub struct BaseColorTexture {
    pub width: u32,
    pub height: u32,
    /// row-major RGBA8, sRGB-encoded as glTF stores base colour
    pub rgba: Vec<u8>,
    /// the sampler's wrapS, wrapT: "repeat", "clamp" or "mirror"
    pub wrap: [&'static str; 2],
    /// the TEXCOORD_n set it reads (pomkit reads TEXCOORD_0 only)
    pub tex_coord: u32,
}

/// What a glTF file holds for pomkit: its mesh nodes and its materials (by glTF index).
#[derive(Clone, Debug)]
pub struct AssetFile {
    pub nodes: Vec<AssetNode>,
    pub materials: Vec<AssetMaterial>,
    /// materials whose baseColorTexture could not be decoded: (material, why)
    pub texture_errors: Vec<(usize, String)>,
}

fn gltf_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::arg(
        "path",
        format!(
            "{}: not a readable glTF 2.0 file ({e}); a valid one comes from re-exporting it \
             (Blender's glTF exporter, or `assimp export <file> out.glb -f glb2`)",
            path.display()
        ),
    )
}

/// Every mesh node of the file's default scene (or of its first scene, or of every root node
/// when it names none), depth first, with world transforms; `normals` says what to do with the
/// file's normals (`mesh::normals`). A node graph that is not a forest (a node reached twice: a
/// cycle, or a node with two parents) is refused, so every walk visits each node at most once.
pub fn load_gltf(path: &Path, normals: NormalsMode) -> Result<AssetFile> {
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
            let node = read_mesh(path, &m, &buffers, name, world, normals)?;
            if !node.parts.is_empty() {
                out.push(node);
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, Some(i)));
        }
    }
    if out.is_empty() {
        return Err(Error::arg(
            "path",
            format!("{}: the file's scene holds no mesh of triangles", path.display()),
        ));
    }
    let (materials, texture_errors) = read_materials(path, &doc.document, &buffers);
    Ok(AssetFile {
        nodes: out,
        materials,
        texture_errors,
    })
}

fn wrap_name(w: gltf::texture::WrappingMode) -> &'static str {
    match w {
        gltf::texture::WrappingMode::Repeat => "repeat",
        gltf::texture::WrappingMode::ClampToEdge => "clamp",
        gltf::texture::WrappingMode::MirroredRepeat => "mirror",
    }
}

/// Every material's base colour, its texture decoded by the `image` crate (PNG, JPEG, TGA, BMP,
/// DDS, embedded or beside the file). A texture that cannot be read leaves the factor alone and
/// is listed with the reason.
fn read_materials(
    path: &Path,
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> (Vec<AssetMaterial>, Vec<(usize, String)>) {
    let mut errors = Vec::new();
    let mats = doc
        .materials()
        .enumerate()
        .map(|(mi, m)| {
            let pbr = m.pbr_metallic_roughness();
            let texture = pbr.base_color_texture().and_then(|info| {
                let t = info.texture();
                let s = t.sampler();
                match decode_image(path, t.source().source(), buffers) {
                    Ok(img) => Some(BaseColorTexture {
                        width: img.width(),
                        height: img.height(),
                        rgba: img.into_raw(),
                        wrap: [wrap_name(s.wrap_s()), wrap_name(s.wrap_t())],
                        tex_coord: info.tex_coord(),
                    }),
                    Err(e) => {
                        errors.push((mi, e));
                        None
                    }
                }
            });
            AssetMaterial {
                name: m.name().map(str::to_string),
                base_color_factor: pbr.base_color_factor(),
                base_color_texture: texture,
            }
        })
        .collect();
    (mats, errors)
}

fn decode_image(
    path: &Path,
    src: gltf::image::Source,
    buffers: &[gltf::buffer::Data],
) -> std::result::Result<image::RgbaImage, String> {
    let bytes: Vec<u8> = match src {
        gltf::image::Source::View { view, .. } => {
            let data = &buffers
                .get(view.buffer().index())
                .ok_or("its buffer view names a missing buffer")?
                .0;
            data.get(view.offset()..view.offset() + view.length())
                .ok_or("its buffer view lies outside its buffer")?
                .to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => {
            if let Some(rest) = uri.strip_prefix("data:") {
                let b64 = rest
                    .split_once(";base64,")
                    .ok_or("a data URI that is not base64")?
                    .1;
                base64::decode(b64).map_err(|e| format!("a data URI whose base64 does not decode ({e})"))?
            } else {
                let rel = urlencoding::decode(uri).map_or_else(|_| uri.to_string(), |c| c.into_owned());
                let file = path.parent().unwrap_or(Path::new(".")).join(&rel);
                std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?
            }
        }
    };
    let img = image::load_from_memory(&bytes).map_err(|e| format!("cannot decode the image ({e})"))?;
    Ok(img.to_rgba8())
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

/// Whether triangle `t` has a tangent frame from its uvs, as `Mesh::compute_bases` decides it.
fn uv_usable(p: &[[f32; 3]], uv: &[[f32; 2]], t: &[u32]) -> bool {
    let q = |k: usize| glam::DVec3::from(p[t[k] as usize].map(f64::from));
    let w = |k: usize| glam::DVec2::from(uv[t[k] as usize].map(f64::from));
    let (e1, e2) = (q(1) - q(0), q(2) - q(0));
    e1.cross(e2).length() > 0.0 && crate::mesh::uv_derivatives(e1, e2, w(1) - w(0), w(2) - w(0)).is_some()
}

/// A primitive without uvs, unindexed: each triangle's corners with uvs from its projection
/// onto the coordinate plane its face normal is most nearly perpendicular to, scaled by the
/// primitive's extent (a triangle without area gets the unit uv triangle).
#[allow(clippy::type_complexity)]
fn project_uvs(
    p: &[[f32; 3]],
    idx: &[u32],
    n: Option<&[[f32; 3]]>,
) -> (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>, Option<Vec<[f32; 3]>>) {
    let v = |i: u32| glam::DVec3::from(p[i as usize].map(f64::from));
    let (lo, hi) = p.iter().fold(
        (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
        |(lo, hi), q| {
            let q = glam::DVec3::from(q.map(f64::from));
            (lo.min(q), hi.max(q))
        },
    );
    let scale = 1.0 / (hi - lo).max_element().max(1e-30);
    let (mut pos, mut uvs, mut nrm) = (Vec::new(), Vec::new(), Vec::new());
    for t in idx.chunks_exact(3) {
        let c = [v(t[0]), v(t[1]), v(t[2])];
        let f = (c[1] - c[0]).cross(c[2] - c[0]).abs();
        let (a, b) = if f.x >= f.y && f.x >= f.z {
            (1, 2)
        } else if f.y >= f.z {
            (2, 0)
        } else {
            (0, 1)
        };
        let mut tri: [[f32; 2]; 3] =
            c.map(|q| [((q[a] - lo[a]) * scale) as f32, ((q[b] - lo[b]) * scale) as f32]);
        let area = {
            let (d1, d2) = (
                [tri[1][0] - tri[0][0], tri[1][1] - tri[0][1]],
                [tri[2][0] - tri[0][0], tri[2][1] - tri[0][1]],
            );
            (d1[0] * d2[1] - d1[1] * d2[0]).abs()
        };
        if !(area > 0.0) {
            tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        }
        for (k, &i) in t.iter().enumerate() {
            pos.push(p[i as usize]);
            uvs.push(tri[k]);
            if let Some(n) = n {
                nrm.push(n[i as usize]);
            }
        }
    }
    let idx = (0..pos.len() as u32).collect();
    (pos, uvs, idx, n.map(|_| nrm))
}

/// Arrays of the primitives of one part, gathered before the part's mesh is built.
#[derive(Default)]
struct Gather {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    tangents: Vec<[f32; 4]>,
    indices: Vec<u32>,
    all_tangents: bool,
    primitives: Vec<usize>,
    flat_normals: usize,
    replaced_normals: usize,
}

fn read_mesh(
    path: &Path,
    m: &gltf::Mesh,
    buffers: &[gltf::buffer::Data],
    name: String,
    transform: DMat4,
    normals_mode: NormalsMode,
) -> Result<AssetNode> {
    let at =
        |what: &str, p: usize| format!("{}: mesh {name:?}, primitive {p}: {what}", path.display());
    // parts by (material, has uvs), in the order the primitives first name them
    let mut parts: Vec<((Option<usize>, bool), Gather)> = Vec::new();
    let mut skipped = Vec::new();
    for (pi, prim) in m.primitives().enumerate() {
        use gltf::mesh::Mode;
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            // points and lines are no surface: left out and reported
            skipped.push((pi, format!("{mode:?}")));
            continue;
        }
        let r = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let p: Vec<[f32; 3]> = r
            .read_positions()
            .ok_or_else(|| Error::arg("path", at("has no POSITION", pi)))?
            .collect();
        let uv: Option<Vec<[f32; 2]>> = r.read_tex_coords(0).map(|t| t.into_f32().collect());
        let has_uvs = uv.is_some();
        let uv = uv.unwrap_or_else(|| vec![[0.0, 0.0]; p.len()]);
        if uv.len() != p.len() {
            return Err(Error::arg(
                "path",
                at(&format!("TEXCOORD_0 has {} entries for {} positions", uv.len(), p.len()), pi),
            ));
        }
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
        let idx: Vec<u32> = match mode {
            Mode::TriangleStrip => (2..idx.len())
                .flat_map(|k| {
                    if k % 2 == 0 {
                        [idx[k - 2], idx[k - 1], idx[k]]
                    } else {
                        [idx[k - 1], idx[k - 2], idx[k]]
                    }
                })
                .collect(),
            Mode::TriangleFan => (2..idx.len())
                .flat_map(|k| [idx[0], idx[k - 1], idx[k]])
                .collect(),
            _ => idx[..idx.len() / 3 * 3].to_vec(),
        };
        if idx.is_empty() || p.is_empty() {
            continue;
        }
        let area = |t: &[u32]| {
            let q = |k: usize| glam::DVec3::from(p[t[k] as usize].map(f64::from));
            (q(1) - q(0)).cross(q(2) - q(0)).length()
        };
        if !idx.chunks_exact(3).any(|t| area(t) > 0.0) {
            // every triangle without area: nothing to draw
            skipped.push((pi, "no triangle with area".to_string()));
            continue;
        }
        // a primitive whose uvs are all degenerate has no parameterisation either
        let has_uvs = has_uvs && idx.chunks_exact(3).any(|t| uv_usable(&p, &uv, t));
        let normals_read: Option<Vec<[f32; 3]>> = r.read_normals().map(|n| n.collect());
        // without uvs: every triangle its own corners, with uvs from its projection onto the
        // plane of its normal's largest axis, so that every triangle has a tangent frame (at
        // depth 0 they displace nothing)
        let (p, uv, idx, normals_read) = if has_uvs {
            (p, uv, idx, normals_read)
        } else {
            project_uvs(&p, &idx, normals_read.as_deref())
        };
        let key = (prim.material().index(), has_uvs);
        let g = match parts.iter().position(|(k, _)| *k == key) {
            Some(i) => &mut parts[i].1,
            None => {
                parts.push((
                    key,
                    Gather {
                        all_tangents: true,
                        ..Gather::default()
                    },
                ));
                &mut parts.last_mut().expect("just pushed").1
            }
        };
        g.primitives.push(pi);
        let base = g.positions.len() as u32;
        match normals_read {
            Some(n) => {
                let mut n = n;
                if n.len() != p.len() {
                    return Err(Error::arg(
                        "path",
                        at(
                            &format!("NORMAL has {} entries for {} positions", n.len(), p.len()),
                            pi,
                        ),
                    ));
                }
                g.replaced_normals += normals::apply(
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
                let t: Option<Vec<[f32; 4]>> =
                    r.read_tangents().map(|t| t.collect()).filter(|_| has_uvs);
                g.all_tangents &= t.is_some() && has_uvs;
                if let Some(t) = t {
                    g.tangents.extend(t.iter().map(|t| [t[0], t[1], t[2], -t[3]]));
                }
                g.positions.extend(p);
                g.normals.extend(n);
                g.uvs.extend(uv);
                g.indices.extend(idx.iter().map(|i| i + base));
            }
            None => {
                // flat normals: each triangle's corners get their own vertices
                g.flat_normals += 1;
                g.all_tangents = false;
                for tri in idx.chunks_exact(3) {
                    let q = [0, 1, 2].map(|k| glam::Vec3::from(p[tri[k] as usize]));
                    let nn = (q[1] - q[0]).cross(q[2] - q[0]).normalize_or_zero();
                    let nn = if nn == glam::Vec3::ZERO { glam::Vec3::Z } else { nn };
                    for &i in tri {
                        g.indices.push(g.positions.len() as u32);
                        g.positions.push(p[i as usize]);
                        g.normals.push(nn.to_array());
                        g.uvs.push(uv[i as usize]);
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    for ((material, uvs), g) in parts {
        let frames = if g.all_tangents {
            TangentBases::Given(g.tangents)
        } else {
            TangentBases::MikkTSpace
        };
        let (mesh, _) = Mesh::from_arrays_with(g.positions, g.normals, g.uvs, g.indices, frames)
            .map_err(|e| match e {
                Error::InvalidArgument { arg, msg } => Error::arg(
                    "path",
                    format!("{}: mesh {name:?}: {arg}: {msg}", path.display()),
                ),
                e => e,
            })?;
        out.push(AssetPart {
            mesh,
            material,
            uvs,
            primitives: g.primitives,
            tangents: if g.all_tangents {
                TangentSource::File
            } else {
                TangentSource::MikkTSpace
            },
            flat_normals: g.flat_normals,
            replaced_normals: g.replaced_normals,
        });
    }
    Ok(AssetNode {
        name,
        parts: out,
        transform,
        skipped,
    })
}

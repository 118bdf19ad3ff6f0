//! The base mesh as a surface a texture-space ray walks across (walk.wgsl): NCS and curved
//! relief march in uv, and on an atlas a ray leaves its triangle, its chart, or the surface.
//! Each triangle carries what the walk needs to follow it:
//! - the affine map from uv to its barycentrics (the test "still inside");
//! - for each side, the triangle across it (welded by position, mesh::topology) and the affine
//!   map from this triangle's uv to the neighbour's: the identity inside a chart, and across a
//!   seam or a mirror axis the map that lays the neighbour beside this triangle as the surface
//!   unfolds (two points of the edge to their uvs on the other side, the neighbour's far corner,
//!   unfolded into this triangle's plane, to its uv). An open border has no neighbour: a ray
//!   that walks out through it has left the surface, unless another open border of the mesh
//!   runs along it (a crack: a T-junction, or an edge whose two sides were not welded, as
//!   hand-made low-poly models have), where the surface goes on in a triangle the walk cannot
//!   reach, and the method's fallback covers the pixel;
//! - its corners' bases (normal, tangent with handedness, uv scales), interpolated as the
//!   rasteriser interpolates them, so that the basis at any point is the one the mesh defines,
//!   also where mirrored charts share texels;
//! - its plane (unit face normal and offset), so that a march can tell a ray that left the base
//!   mesh from one whose interpolated normals, not the mesh, turned it out of the shell.
//!
//! The triangle a fragment starts in reaches the shader as `Ray::extra.z`: the method draws the
//! base mesh unindexed, three vertices a triangle, each carrying its triangle's index.

use crate::contract::{GeometryData, GpuMesh, MethodGeometry, Resident, ResourceKind, ShaderUnit};
use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::mesh::borders::{open_borders, plane_through, ForeignBorder, TOLERANCE};
use crate::mesh::topology::Topology;
use crate::mesh::{Mesh, Vertex};
use crate::scene::{hash_bytes, Object};
use glam::{DMat2, DVec2, DVec3};

/// vec4 records per triangle (walk.wgsl's layout).
pub const RECORDS_PER_TRIANGLE: usize = 14;
/// GPU bytes of one triangle's walk data.
pub const WALK_BYTES_PER_TRIANGLE: usize = RECORDS_PER_TRIANGLE * 16;
/// The neighbour index of a side on an open border.
pub const NO_NEIGHBOUR: f32 = -1.0;
/// The neighbour index of a side on a crack (an open border that another one runs along).
pub const CRACK: f32 = -2.0;

/// The walk's library module (`pomkit::walk`), imported by the methods that walk.
pub fn walk_unit() -> ShaderUnit {
    ShaderUnit::builtin(
        "pomkit::walk",
        "src/methods/walk/walk.wgsl",
        include_str!("walk.wgsl"),
    )
}

/// An affine map of the plane, x -> l x + o.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    pub l: DMat2,
    pub o: DVec2,
}

impl Affine {
    pub const IDENTITY: Affine = Affine {
        l: DMat2::IDENTITY,
        o: DVec2::ZERO,
    };
    pub fn apply(&self, x: DVec2) -> DVec2 {
        self.l * x + self.o
    }
    /// The map taking a0, a1, a2 to b0, b1, b2; None where a0, a1, a2 are collinear.
    fn through(a: [DVec2; 3], b: [DVec2; 3]) -> Option<Affine> {
        let s = DMat2::from_cols(a[1] - a[0], a[2] - a[0]);
        let det = s.determinant();
        let scale = (a[1] - a[0])
            .length_squared()
            .max((a[2] - a[0]).length_squared());
        if !(det.abs() > 1e-12 * scale) {
            return None;
        }
        let l = DMat2::from_cols(b[1] - b[0], b[2] - b[0]) * s.inverse();
        Some(Affine {
            l,
            o: b[0] - l * a[0],
        })
    }
}

/// One triangle's walk data, in float64 (the tests read it; `records` packs it).
#[derive(Clone, Debug)]
pub struct WalkTriangle {
    /// uv -> (b1, b2), the barycentrics of corners 1 and 2 (b0 = 1 - b1 - b2)
    pub to_bary: Affine,
    /// per side k (corners k and k+1): the triangle across it and the map of uvs into it
    pub across: [Option<(u32, Affine)>; 3],
    /// per side: on an open border that another open border of the mesh runs along (`cracks`),
    /// the plane (unit face normal, offset) of the triangle across the crack
    pub crack: [Option<[f64; 4]>; 3],
}

fn tri_corners(mesh: &Mesh, t: usize) -> [u32; 3] {
    [
        mesh.indices[3 * t],
        mesh.indices[3 * t + 1],
        mesh.indices[3 * t + 2],
    ]
}

/// The map from triangle `a`'s uv to triangle `b`'s across their shared side (a's side `k`).
fn transfer(mesh: &Mesh, topo: &Topology, a: usize, k: usize, b: usize) -> Affine {
    let ca = tri_corners(mesh, a);
    let cb = tri_corners(mesh, b);
    let (a0, a1, a2) = (ca[k], ca[(k + 1) % 3], ca[(k + 2) % 3]);
    // b's corners at a0's and a1's positions, and its far corner
    let find = |w: u32| cb.iter().copied().find(|&v| topo.weld[v as usize] == w);
    let (Some(b0), Some(b1)) = (find(topo.weld[a0 as usize]), find(topo.weld[a1 as usize])) else {
        return Affine::IDENTITY;
    };
    let Some(b2) = cb.iter().copied().find(|&v| v != b0 && v != b1) else {
        return Affine::IDENTITY;
    };
    let uv = |v: u32| mesh.uv_f64(v);
    let uva = [uv(a0), uv(a1), uv(a2)];
    let uvb = [uv(b0), uv(b1), uv(b2)];
    // inside a chart the uvs agree at the side's ends and the other triangle lies across the
    // side in uv: the uvs continue as they are (a mirror axis folds the other triangle back
    // onto this side, and takes the map below)
    let e = uva[1] - uva[0];
    let b_beyond = e.perp_dot(uva[2] - uva[0]).signum() != e.perp_dot(uvb[2] - uva[0]).signum();
    if uva[0] == uvb[0] && uva[1] == uvb[1] && b_beyond {
        return Affine::IDENTITY;
    }
    // b's far corner unfolded into a's plane, across the side
    let p = |v: u32| mesh.position_f64(v);
    let (p0, p1, p2) = (p(a0), p(a1), p(a2));
    let e = p1 - p0;
    let ee = e.length_squared();
    if !(ee > 0.0) {
        return Affine::IDENTITY;
    }
    let inward = {
        let r = p2 - p0;
        let w = r - e * (r.dot(e) / ee);
        w.normalize_or_zero()
    };
    let q = p(b2) - p0;
    let s = q.dot(e) / ee;
    let d = (q - e * s).length();
    let x: DVec3 = p0 + e * s - inward * d;
    // its uv in a's (affine) parameterisation: barycentrics of x in a's plane
    let (u, v) = (p1 - p0, p2 - p0);
    let g = DMat2::from_cols(
        DVec2::new(u.dot(u), u.dot(v)),
        DVec2::new(u.dot(v), v.dot(v)),
    );
    if !(g.determinant().abs() > 1e-300) {
        return Affine::IDENTITY;
    }
    let bc = g.inverse() * DVec2::new((x - p0).dot(u), (x - p0).dot(v));
    let uvx = uva[0] + (uva[1] - uva[0]) * bc.x + (uva[2] - uva[0]) * bc.y;
    Affine::through([uva[0], uva[1], uvx], uvb).unwrap_or(Affine::IDENTITY)
}

/// A triangle's plane: its unit face normal (by its winding, as the records' own) and offset.
fn face_plane(mesh: &Mesh, t: usize) -> [f64; 4] {
    plane_through(tri_corners(mesh, t).map(|v| mesh.position_f64(v)))
}

/// Per triangle and side: where the side is an open border that another open border runs
/// along, overlapping it by more than `borders::TOLERANCE` of the mesh's size and within that
/// of its line (a T-junction, two triangles whose shared edge was not welded, or another
/// object's border in `foreign`, in this mesh's space), the plane of the other border's
/// triangle. The border edges are binned in a grid of about one edge a cell, each compared with
/// those of its cells.
pub fn cracks(
    mesh: &Mesh,
    topo: &Topology,
    foreign: &[ForeignBorder],
) -> Vec<[Option<[f64; 4]>; 3]> {
    let n = mesh.indices.len() / 3;
    let mut out = vec![[None; 3]; n];
    let own = open_borders(mesh, topo);
    // own borders first (their index is their place in `own`), then the other objects'
    let border: Vec<ForeignBorder> = own
        .iter()
        .map(|b| b.segment())
        .chain(foreign.iter().copied())
        .collect();
    if border.len() < 2 || own.is_empty() {
        return out;
    }
    let (lo, hi) = mesh.bounds();
    let extent = (hi - lo).max_element().max(1e-30);
    let tol = TOLERANCE * extent;
    let cell = extent / (border.len() as f64).cbrt().max(1.0);
    let dims = ((hi - lo) / cell).floor().as_ivec3() + 1;
    let at = |x: DVec3| ((x - lo) / cell).floor().as_ivec3().clamp(glam::IVec3::ZERO, dims - 1);
    let mut grid: std::collections::HashMap<glam::IVec3, Vec<u32>> = Default::default();
    let cells_of = |a: DVec3, b: DVec3| {
        let (c0, c1) = (at(a.min(b) - tol), at(a.max(b) + tol));
        (c0.x..=c1.x).flat_map(move |x| {
            (c0.y..=c1.y).flat_map(move |y| (c0.z..=c1.z).map(move |z| glam::IVec3::new(x, y, z)))
        })
    };
    for (i, f) in border.iter().enumerate() {
        for c in cells_of(f.a, f.b) {
            grid.entry(c).or_default().push(i as u32);
        }
    }
    for (i, o) in own.iter().enumerate() {
        let (a, b) = (o.a, o.b);
        let len = (b - a).length();
        if !(len > tol) {
            continue;
        }
        let d = (b - a) / len;
        let off_line = |x: DVec3| {
            let v = x - a;
            (v - d * v.dot(d)).length()
        };
        let runs_along = |j: u32| {
            let f = &border[j as usize];
            if j as usize == i || off_line(f.a) > tol || off_line(f.b) > tol {
                return false;
            }
            let (s0, s1) = {
                let (u, w) = ((f.a - a).dot(d), (f.b - a).dot(d));
                (u.min(w), u.max(w))
            };
            s1.min(len) - s0.max(0.0) > tol
        };
        out[o.tri as usize][o.side as usize] = cells_of(a, b)
            .find_map(|c| grid.get(&c).and_then(|v| v.iter().copied().find(|&j| runs_along(j))))
            .map(|j| border[j as usize].plane);
    }
    out
}

/// Every triangle's walk data, with the open borders of other objects that meet this mesh
/// (`mesh::borders::contacts`, in its space).
pub fn build(mesh: &Mesh, foreign: &[ForeignBorder]) -> Vec<WalkTriangle> {
    let topo = Topology::quantised(mesh);
    let crack = cracks(mesh, &topo, foreign);
    let n = mesh.indices.len() / 3;
    (0..n)
        .map(|t| {
            let c = tri_corners(mesh, t);
            let uv = [mesh.uv_f64(c[0]), mesh.uv_f64(c[1]), mesh.uv_f64(c[2])];
            // degenerate uvs: every point counts as inside (the walk stays)
            let to_bary = Affine::through(
                uv,
                [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)],
            )
            .unwrap_or(Affine {
                l: DMat2::ZERO,
                o: DVec2::ZERO,
            });
            let across = std::array::from_fn(|k| {
                let e = topo.tri_edges[t][k] as usize;
                let sides = &topo.edges[e].1;
                // the other side (on a non-manifold edge, the first other one)
                let other = sides.iter().find(|s| s.tri as usize != t)?;
                let b = other.tri as usize;
                Some((b as u32, transfer(mesh, &topo, t, k, b)))
            });
            WalkTriangle {
                to_bary,
                across,
                crack: crack[t],
            }
        })
        .collect()
}

/// The walk data as walk.wgsl reads it: RECORDS_PER_TRIANGLE vec4 per triangle, in triangle
/// order.
pub fn records(mesh: &Mesh, walk: &[WalkTriangle]) -> Vec<[f32; 4]> {
    let mut out = Vec::with_capacity(walk.len() * RECORDS_PER_TRIANGLE);
    let row = |a: &Affine, r: usize| [a.l.col(0)[r] as f32, a.l.col(1)[r] as f32, a.o[r] as f32];
    for (t, w) in walk.iter().enumerate() {
        // the plane n . x = d (zero where the triangle has no area), in the w of records 0, 1,
        // 3 and 5
        let plane = face_plane(mesh, t).map(|x| x as f32);
        let [a, b, c] = row(&w.to_bary, 0);
        out.push([a, b, c, plane[0]]);
        let [a, b, c] = row(&w.to_bary, 1);
        out.push([a, b, c, plane[1]]);
        for k in 0..3 {
            let own = if k < 2 { plane[2 + k] } else { 0.0 };
            let (r0, r1) = match (&w.across[k], w.crack[k]) {
                // a crack: the plane of the triangle across it in place of the map
                (None, Some(q)) => {
                    let q = q.map(|x| x as f32);
                    ([q[0], q[1], q[2], CRACK], [q[3], 0.0, 0.0, own])
                }
                (across, _) => {
                    let (nb, m) = across.map_or((NO_NEIGHBOUR, Affine::IDENTITY), |(nb, m)| (nb as f32, m));
                    let ([a, b, c], [d, e, f]) = (row(&m, 0), row(&m, 1));
                    ([a, b, c, nb], [d, e, f, own])
                }
            };
            out.push(r0);
            out.push(r1);
        }
        for v in tri_corners(mesh, t) {
            let v = v as usize;
            let (n, tg, s) = (mesh.normals[v], mesh.tangents[v], mesh.uv_scale[v]);
            let sign = if tg[3] < 0.0 { -1.0 } else { 1.0 };
            out.push([n[0], n[1], n[2], s[0]]);
            out.push([tg[0], tg[1], tg[2], sign * s[1]]);
        }
    }
    out
}

/// The records as the texture walk.wgsl reads: triangle i's at (i mod per_row, i div per_row),
/// RECORDS_PER_TRIANGLE texels each, per_row a power of two within `max_dim`; Err(the most
/// triangles that fit) where the rows exceed it.
pub fn texels(
    records: &[[f32; 4]],
    max_dim: u32,
) -> std::result::Result<(Vec<[f32; 4]>, (u32, u32)), usize> {
    let per = RECORDS_PER_TRIANGLE;
    let (per_row, rows) = crate::gpu::record_rows(records.len() / per, per as u32, max_dim)?;
    let width = per_row as usize * per;
    let mut t = vec![[0.0f32; 4]; width * rows];
    for (i, r) in records.chunks_exact(per).enumerate() {
        let (row, col) = (i / per_row as usize, i % per_row as usize);
        let at = row * width + col * per;
        t[at..at + per].copy_from_slice(r);
    }
    Ok((t, (width as u32, rows as u32)))
}

/// The base mesh drawn unindexed, each vertex with (a, b, triangle, 0) at location 5: the
/// quadric coefficients of curved relief (zero for NCS) and the index of its triangle. The walk
/// data is built beside it (`GpuMesh::extra[0]`).
#[derive(Debug, Clone, Copy)]
pub struct WalkMesh {
    pub quadrics: bool,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct WalkVertex {
    vertex: Vertex,
    extra: [f32; 4],
}

const ATTRIBUTES: [wgpu::VertexAttribute; 6] =
    Vertex::with_location5(wgpu::VertexFormat::Float32x4);

impl MethodGeometry for WalkMesh {
    fn key(&self, object: &Object) -> u64 {
        hash_bytes(&[
            b"walk mesh",
            &object.mesh.key.to_le_bytes(),
            &[self.quadrics as u8],
            &object.contacts.key.to_le_bytes(),
        ])
    }
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh> {
        let mesh = &object.mesh;
        let ntri = mesh.indices.len() / 3;
        if ntri as u64 >= 1 << 24 {
            return Err(Error::limit(
                "mesh",
                format!("the texture-space walk indexes triangles as float32 and takes at most 2^24 of them; this mesh has {ntri}: split it into several pk.Object"),
            ));
        }
        let q = if self.quadrics {
            crate::mesh::quadrics::fit(mesh)
        } else {
            vec![[0.0, 0.0]; mesh.positions.len()]
        };
        let vertices = mesh.vertices();
        let verts: Vec<WalkVertex> = mesh
            .indices
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let [a, b] = q[v as usize];
                WalkVertex {
                    vertex: vertices[v as usize],
                    extra: [a, b, (i / 3) as f32, 0.0],
                }
            })
            .collect();
        let data = records(mesh, &build(mesh, &object.contacts.borders));
        let max_dim = ctx.limits.max_texture_dimension_2d;
        let (texels, size) = texels(&data, max_dim).map_err(|most| {
            Error::limit(
                "mesh",
                format!("the walk data of {ntri} triangles takes {RECORDS_PER_TRIANGLE} texels a triangle in textures of at most {max_dim} texels a side (at most {most} triangles): split the mesh into several pk.Object"),
            )
        })?;
        ctx.scoped(|| {
            let tex = ctx.texture_2d(
                "walk data",
                size,
                wgpu::TextureFormat::Rgba32Float,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            );
            crate::gpu::texels::write_texels(ctx, &tex, bytemuck::cast_slice(&texels), size, 16);
            Ok(GpuMesh {
                vbuf: ctx.upload(
                    "walk vertices",
                    bytemuck::cast_slice(&verts),
                    wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
                ),
                ibuf: None,
                count: verts.len() as u32,
                extra: vec![Resident::Texture(tex.create_view(&Default::default()))],
            })
        })
    }
    fn uses_contacts(&self) -> bool {
        true
    }
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<WalkVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRIBUTES,
        }
    }
}

/// The walk data (`walk_tex` in walk.wgsl, group 2, binding 1), made with the method's geometry.
pub fn walk_data(mesh: WalkMesh) -> GeometryData<WalkMesh> {
    GeometryData {
        geometry: mesh,
        kind: ResourceKind::TextureFloat,
        what: "walk data",
    }
}

#[cfg(test)]
mod tests;

//! The coarse mesh of `Hybrid` (src/methods/mod.rs): the base mesh tessellated on a lattice
//! `texels_per_vertex` texels apart (tessellated/tessellate.rs), displaced at its vertices, and
//! the window each vertex carries for the per-pixel method that marches the rest (`WINDOW` in
//! surface.wgsl: the Ray's `floor` and `top`).
//!
//! Over each coarse triangle the residual, the height field minus the coarse surface's
//! interpolated height, lies within [r_min, r_max] (taken at every texel centre inside the
//! triangle, where the bilinear residual's extremes over a cell's inside lie, and along its
//! edges every 1/8 texel, where a cell's restriction is quadratic). A vertex carries
//! top = h_c + the largest r_max of its triangles (and of every vertex at its base point: across
//! a seam both sides take the same), so that over each triangle the interpolated top lies above
//! the field (a top may pass 1: a clamped vertex would pull its triangles' top in). The mesh is
//! rasterised at its top: each fragment is the view ray's entry into the window, and the fine
//! method marches from `top` down to `floor`, the least h_c + r_min over the whole object: a
//! vertex's own bound holds only over its triangles, which a ray at a grazing angle leaves
//! before it descends that far.
//!
//! Without a lattice (`texels_per_vertex` None: a flat coarse mesh) the mesh is the base mesh
//! with the window [0, 1]: the fine method as it runs alone.

use crate::contract::{GpuMesh, MethodGeometry};
use crate::error::Result;
use crate::gpu::Context;
use crate::mesh::Vertex;
use crate::methods::tessellated::tessellate::{tessellate, Pattern};
use crate::scene::{hash_bytes, Object};
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// A margin on every window (heights): the bounds are sampled, and a float32 march compares
/// against them.
const MARGIN: f64 = 1e-3;

#[derive(Debug)]
pub struct WindowMesh {
    /// None: the base mesh itself, the window [0, 1]
    pub texels_per_vertex: Option<f64>,
    pub pattern: Pattern,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct WindowVertex {
    vertex: Vertex,
    /// (floor, top, 0, 0): the window's heights at the vertex
    window: [f32; 4],
}

const ATTRIBUTES: [wgpu::VertexAttribute; 6] =
    Vertex::with_location5(wgpu::VertexFormat::Float32x4);

/// The coarse mesh's vertices (at the top of their windows) and triangles.
fn window_mesh(
    mesh: &crate::mesh::Mesh,
    mat: &crate::scene::Material,
    tpv: f64,
    pattern: Pattern,
) -> Result<(Vec<WindowVertex>, Vec<u32>)> {
    let t = tessellate(mesh, mat, tpv, pattern)?;
    let hm = &mat.height;
    let tiling = mat.tiling as f64;
    let depth = mat.depth as f64;
    let v3 = |a: [f32; 3]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    let s_of = |v: usize| DVec2::new(t.uvs[v][0] as f64, t.uvs[v][1] as f64) * tiling;
    let hc: Vec<f64> = (0..t.uvs.len()).map(|v| {
        let s = s_of(v);
        hm.sample(s.x, s.y)
    }).collect();
    let n = t.uvs.len();
    // the residual is 0 at a vertex: every triangle's bounds hold it
    let (mut rmax, mut rmin) = (vec![0.0f64; n], vec![0.0f64; n]);
    let (w, h) = (hm.width as f64, hm.height as f64);
    for tri in t.indices.chunks_exact(3) {
        let (a, b, c) = (tri[0] as usize, tri[1] as usize, tri[2] as usize);
        let (sa, sb, sc) = (s_of(a), s_of(b), s_of(c));
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        let mut at = |l: [f64; 3]| {
            let s = sa * l[0] + sb * l[1] + sc * l[2];
            let r = hm.sample(s.x, s.y) - (hc[a] * l[0] + hc[b] * l[1] + hc[c] * l[2]);
            lo = lo.min(r);
            hi = hi.max(r);
        };
        // the edges, every 1/8 texel
        for (p, q, k) in [(sa, sb, 0), (sb, sc, 1), (sc, sa, 2)] {
            let texels = ((q - p) * DVec2::new(w, h)).length();
            let m = (texels * 8.0).ceil().max(1.0) as usize;
            for j in 0..=m {
                let u = j as f64 / m as f64;
                let mut l = [0.0; 3];
                l[k] = 1.0 - u;
                l[(k + 1) % 3] = u;
                at(l);
            }
        }
        // the texel centres inside
        let (x0, x1) = (sa.x.min(sb.x).min(sc.x) * w, sa.x.max(sb.x).max(sc.x) * w);
        let (y0, y1) = (sa.y.min(sb.y).min(sc.y) * h, sa.y.max(sb.y).max(sc.y) * h);
        let det = (sb - sa).perp_dot(sc - sa);
        if det.abs() > 1e-300 {
            for iy in (y0 - 0.5).floor() as i64..=(y1 - 0.5).ceil() as i64 {
                for ix in (x0 - 0.5).floor() as i64..=(x1 - 0.5).ceil() as i64 {
                    let s = DVec2::new((ix as f64 + 0.5) / w, (iy as f64 + 0.5) / h);
                    let l1 = (s - sa).perp_dot(sc - sa) / det;
                    let l2 = (sb - sa).perp_dot(s - sa) / det;
                    if l1 >= 0.0 && l2 >= 0.0 && l1 + l2 <= 1.0 {
                        at([1.0 - l1 - l2, l1, l2]);
                    }
                }
            }
        }
        for v in [a, b, c] {
            rmax[v] = rmax[v].max(hi);
            rmin[v] = rmin[v].min(lo);
        }
    }
    // one window per base point: the sides of a seam take the same one
    let mut groups: HashMap<[u32; 3], (f64, f64)> = HashMap::new();
    let key = |v: usize| t.base_positions[v].map(f32::to_bits);
    for v in 0..n {
        let e = groups.entry(key(v)).or_insert((f64::MIN, f64::MAX));
        e.0 = e.0.max(hc[v] + rmax[v]);
        e.1 = e.1.min(hc[v] + rmin[v]);
    }
    // the floor is the object's lowest: a vertex's own holds the field only over its triangles,
    // and a ray at a grazing angle leaves them before it gets that low
    let floor = groups.values().fold(f64::MAX, |m, g| m.min(g.1)) - MARGIN;
    // the sides of an edge whose normals differ (a hard edge) meet at the mean of their points,
    // as the tessellated mesh's do: one surface
    let mut points: HashMap<[u32; 3], (DVec3, f64)> = HashMap::new();
    for v in 0..n {
        let top = groups[&key(v)].0 + MARGIN;
        let e = points.entry(key(v)).or_insert((DVec3::ZERO, 0.0));
        e.0 += v3(t.base_positions[v]) + v3(t.base_normals[v]) * (depth * (top - 1.0));
        e.1 += 1.0;
    }
    let verts: Vec<WindowVertex> = (0..n)
        .map(|v| {
            // not clamped to 1: a clamped vertex would pull its triangles' window in
            let top = groups[&key(v)].0 + MARGIN;
            let (sum, count) = points[&key(v)];
            let p = sum / count;
            WindowVertex {
                vertex: Vertex {
                    position: [p.x as f32, p.y as f32, p.z as f32],
                    normal: t.base_normals[v],
                    uv: t.uvs[v],
                    tangent: t.tangents[v],
                    uv_scale: t.uv_scale[v],
                },
                window: [floor as f32, top as f32, 0.0, 0.0],
            }
        })
        .collect();
    Ok((verts, t.indices))
}

impl MethodGeometry for WindowMesh {
    fn key(&self, object: &Object) -> u64 {
        let m = &object.material;
        hash_bytes(&[
            b"window mesh",
            &object.mesh.key.to_le_bytes(),
            &m.height.key.to_le_bytes(),
            &m.depth.to_le_bytes(),
            &m.tiling.to_le_bytes(),
            &self.texels_per_vertex.unwrap_or(0.0).to_le_bytes(),
            self.pattern.name().as_bytes(),
        ])
    }
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh> {
        let (verts, indices) = match self.texels_per_vertex {
            Some(tpv) => window_mesh(&object.mesh, &object.material, tpv, self.pattern)?,
            None => (
                object
                    .mesh
                    .vertices()
                    .into_iter()
                    .map(|vertex| WindowVertex {
                        vertex,
                        window: [0.0, 1.0, 0.0, 0.0],
                    })
                    .collect(),
                object.mesh.indices.clone(),
            ),
        };
        GpuMesh::upload_indexed(ctx, &verts, &indices, "coarse")
    }
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<WindowVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRIBUTES,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{HeightMap, Material};

    /// Over every coarse triangle, the interpolated window holds the field: floor <= h <= top.
    #[test]
    fn the_window_holds_the_field() {
        let n = 64u32;
        let data: Vec<f32> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
                0.5 + 0.5 * (6.283 * 4.0 * x).sin() * (6.283 * 4.0 * y).cos()
            })
            .collect();
        let hm = HeightMap::new(n, n, data).unwrap();
        let mat = Material {
            height: crate::scene::shared(hm).unwrap(),
            depth: 0.1,
            tiling: 1.0,
            albedo: None,
        };
        let hm = &mat.height;
        for pattern in [Pattern::Fan, Pattern::Grid] {
            let m = crate::mesh::Mesh::plane(2.0, 1).unwrap();
            let (v, idx) = window_mesh(&m, &mat, 8.0, pattern).unwrap();
            let mut worst = 0.0f64;
            for tri in idx.chunks_exact(3) {
                let c: Vec<&WindowVertex> = tri.iter().map(|&i| &v[i as usize]).collect();
                for i in 0..=20 {
                    for j in 0..=(20 - i) {
                        let l = [i as f64 / 20.0, j as f64 / 20.0, (20 - i - j) as f64 / 20.0];
                        let uv = (0..3).fold(DVec2::ZERO, |a, k| {
                            a + DVec2::new(c[k].vertex.uv[0] as f64, c[k].vertex.uv[1] as f64) * l[k]
                        });
                        let top: f64 = (0..3).map(|k| c[k].window[1] as f64 * l[k]).sum();
                        let floor: f64 = (0..3).map(|k| c[k].window[0] as f64 * l[k]).sum();
                        let h = hm.sample(uv.x, uv.y);
                        worst = worst.max(h - top).max(floor - h);
                    }
                }
            }
            assert!(worst <= 0.0, "{pattern:?}: the field leaves the window by {worst}");
        }
    }
}

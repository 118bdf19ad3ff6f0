//! The coarse mesh of `Hybrid` (src/methods/mod.rs): the base mesh tessellated on a lattice
//! `texels_per_vertex` texels apart that also holds the base mesh's own vertices and grid lines
//! (tessellate_on_base: never coarser than the base mesh), displaced at its vertices, and the
//! window each vertex carries for the per-pixel method that marches the rest (`WINDOW` in
//! surface.wgsl: the Ray's `floor` and `top`).
//!
//! Over each coarse triangle the residual, the height field minus the coarse surface's
//! interpolated height, lies within [r_min, r_max] (taken at every texel centre inside the
//! triangle, where the bilinear residual's extremes over a cell's inside lie, and along its
//! edges every 1/8 texel, where a cell's restriction is quadratic). A vertex carries
//! top = h_c + the largest r_max of its triangles (and of every vertex at its base point: across
//! a seam both sides take the same), so that over each triangle the interpolated top lies above
//! the field. The mesh is rasterised at its top: each fragment is the view ray's entry into the
//! window; above h = 1 the search starts where the ray comes down to it.
//!
//! Hard edges follow docs/conventions.md: each side is displaced along its own normals. The
//! points where sides of different normals meet stay on the base mesh at h = 1 (the top of the
//! shell, above the field everywhere: "pinned"), so the sides meet there without a crack, and
//! each fragment searches in its own side's basis; the free vertices beside a pinned one take
//! the top that keeps the interpolated top above the field (`TriangleBounds::beside`).
//!
//! The floor holds along the ray, not only at the fragment: each vertex carries two floors, the
//! lowest texel within a box of half-width (reach + its longest edge) about it, for two reaches
//! (`reach` and NEAR_SHARE of it, s units). A ray whose descent to a floor stays within that
//! floor's reach of its fragment cannot meet the field below it; one that goes farther searches
//! the method's own window [0, 1] along the same ray, from where it passes h = 1. The fine
//! method spends its steps over that window.
//!
//! Without a lattice (`texels_per_vertex` None: a flat coarse mesh) the mesh is the base mesh
//! with the window [0, 1]: the fine method as it runs alone.

use crate::contract::{GpuMesh, MethodGeometry};
use crate::error::Result;
use crate::gpu::Context;
use crate::mesh::Vertex;
use crate::methods::tessellated::tessellate::{tessellate_on_base, Pattern};
use crate::scene::{hash_bytes, Object};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// A margin on every window (heights): the bounds are sampled, and a float32 march compares
/// against them.
const MARGIN: f64 = 1e-3;

/// The nearer of the window's two floors holds for rays that stay within this share of `reach`
/// of their fragment (the contract's WINDOW_NEAR_SHARE_DIV, which surface.wgsl reads as a def).
const NEAR_SHARE: f64 = 1.0 / crate::contract::WINDOW_NEAR_SHARE_DIV as f64;

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
    /// (nearest floor, top, near floor, reach): the window's top at the vertex, and the floors that
    /// hold for a ray that stays within NEAR_SHARE * reach, and within reach (s units), of its
    /// fragment; a ray that goes farther searches [0, 1] from where it passes h = 1
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
    let t = tessellate_on_base(mesh, mat, tpv, pattern)?;
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
    // the base points where the sides of a hard edge meet (their vertices carry different
    // normals): the coarse mesh keeps them on the base mesh, at the top of the shell (h = 1,
    // which holds the field everywhere), so that each side is displaced along its own normals
    // and the sides still meet at the edge's points, as the base mesh's do
    let key = |v: usize| t.base_positions[v].map(f32::to_bits);
    let mut normal_at: HashMap<[u32; 3], ([f32; 3], bool)> = HashMap::new();
    for v in 0..n {
        let e = normal_at.entry(key(v)).or_insert((t.base_normals[v], false));
        let d = v3(e.0) - v3(t.base_normals[v]);
        e.1 |= d.length() > 1e-6;
    }
    let pinned: Vec<bool> = (0..n).map(|v| normal_at[&key(v)].1).collect();
    // the residual is 0 at a vertex: every triangle's bounds hold it
    let (mut rmax, mut rmin) = (vec![0.0f64; n], vec![0.0f64; n]);
    // the least top a free vertex needs beside pinned ones (see `TriangleBounds::beside`)
    let mut beside = vec![f64::MIN; n];
    let (w, h) = (hm.width as f64, hm.height as f64);
    // each triangle's residual bounds, on every core (src/parallel.rs)
    crate::parallel::init();
    let bounds: Vec<TriangleBounds> = t
        .indices
        .par_chunks_exact(3)
        .map(|tri| {
            let (a, b, c) = (tri[0] as usize, tri[1] as usize, tri[2] as usize);
            let (sa, sb, sc) = (s_of(a), s_of(b), s_of(c));
            let pin = [pinned[a], pinned[b], pinned[c]];
            let mut out = TriangleBounds { lo: 0.0, hi: 0.0, beside: f64::MIN };
            let mut at = |l: [f64; 3]| {
                let s = sa * l[0] + sb * l[1] + sc * l[2];
                let f = hm.sample(s.x, s.y);
                let r = f - (hc[a] * l[0] + hc[b] * l[1] + hc[c] * l[2]);
                out.lo = out.lo.min(r);
                out.hi = out.hi.max(r);
                let (pinned_w, free_w) = (0..3).fold((0.0, 0.0), |(p, q), k| {
                    if pin[k] { (p + l[k], q) } else { (p, q + l[k]) }
                });
                if pin.iter().any(|&x| x) && free_w > 1e-9 {
                    out.beside = out.beside.max((f - pinned_w) / free_w);
                }
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
            out
        })
        .collect();
    for (tri, b) in t.indices.chunks_exact(3).zip(&bounds) {
        for &v in tri {
            let v = v as usize;
            rmax[v] = rmax[v].max(b.hi);
            rmin[v] = rmin[v].min(b.lo);
            beside[v] = beside[v].max(b.beside);
        }
    }
    // one window per base point: the sides of a seam take the same one
    let mut groups: HashMap<[u32; 3], (f64, f64)> = HashMap::new();
    for v in 0..n {
        let e = groups.entry(key(v)).or_insert((f64::MIN, f64::MAX));
        e.0 = e.0.max(hc[v] + rmax[v]).max(beside[v]);
        e.1 = e.1.min(hc[v] + rmin[v]);
    }
    // the object's lowest (the floors' least)
    let floor = groups.values().fold(f64::MAX, |m, g| m.min(g.1)) - MARGIN;
    // the near floor, for rays that stay near their fragment: over a box of half-width
    // REACH + (the vertex's longest incident edge) about each vertex (s units), every fragment of
    // its triangles sees the field above it within REACH of itself, and so does their
    // interpolation (each vertex's floor lies below the field there)
    let reach = (4.0 * tpv + 32.0) / w.max(h);
    let mut edge = vec![0.0f64; n];
    for tri in t.indices.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            let l = (s_of(a) - s_of(b)).length();
            edge[a] = edge[a].max(l);
            edge[b] = edge[b].max(l);
        }
    }
    // two reaches: `reach` and NEAR_SHARE of it (the floor closest to the surface, for rays that
    // stay closest to their fragment)
    let blocks = MinBlocks::new(hm);
    let floors: Vec<(f64, f64)> = (0..n)
        .into_par_iter()
        .map(|v| {
            let at = |r: f64| blocks.lowest_in_box(s_of(v), r + edge[v]).max(floor + MARGIN) - MARGIN;
            (at(reach * NEAR_SHARE), at(reach))
        })
        .collect();
    let verts: Vec<WindowVertex> = (0..n)
        .map(|v| {
            // not clamped to 1: a clamped vertex would pull its triangles' window in; a pinned
            // point sits at h = 1 exactly, on the base mesh's point (bit-equal on every side)
            let top = if pinned[v] { 1.0 } else { groups[&key(v)].0 + MARGIN };
            let b = v3(t.base_positions[v]);
            let p = b + v3(t.base_normals[v]) * (depth * (top - 1.0));
            WindowVertex {
                vertex: Vertex {
                    position: [p.x as f32, p.y as f32, p.z as f32],
                    normal: t.base_normals[v],
                    uv: t.uvs[v],
                    tangent: t.tangents[v],
                    uv_scale: t.uv_scale[v],
                },
                window: [floors[v].0 as f32, top as f32, floors[v].1 as f32, reach as f32],
            }
        })
        .collect();
    Ok((verts, t.indices))
}

/// Each level's blocks: the least texel of 2^k x 2^k texels (the last block of a row or column
/// holds the rest), so that a box of any size is covered by at most 3 x 3 blocks of one level.
struct MinBlocks {
    levels: Vec<(usize, usize, Vec<f32>)>,
}

impl MinBlocks {
    fn new(hm: &crate::scene::HeightMap) -> MinBlocks {
        let mut levels = vec![(hm.width as usize, hm.height as usize, hm.data.clone())];
        loop {
            let (w, h, d) = levels.last().expect("level 0");
            if *w == 1 && *h == 1 {
                break;
            }
            let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
            let mut out = vec![f32::INFINITY; nw * nh];
            for y in 0..*h {
                for x in 0..*w {
                    let o = &mut out[(y / 2) * nw + x / 2];
                    *o = o.min(d[y * w + x]);
                }
            }
            levels.push((nw, nh, out));
        }
        MinBlocks { levels }
    }

    /// The least texel that the bilinear field reads anywhere in the box of half-width `r`
    /// about `s` (tiled s units, repeating): a floor of the field over it.
    fn lowest_in_box(&self, s: DVec2, r: f64) -> f64 {
        let (w, h, _) = self.levels[0];
        let span = |c: f64, n: usize| {
            let n = n as f64;
            (((c - r) * n - 0.5).floor() as i64, ((c + r) * n - 0.5).floor() as i64 + 1)
        };
        // the box's texels on one axis as ranges inside [0, n) (two where it wraps)
        let pieces = |(a, b): (i64, i64), n: usize| -> Vec<(usize, usize)> {
            let n = n as i64;
            if b - a + 1 >= n {
                return vec![(0, n as usize - 1)];
            }
            let a0 = a.rem_euclid(n);
            let b0 = a0 + (b - a);
            if b0 < n {
                vec![(a0 as usize, b0 as usize)]
            } else {
                vec![(a0 as usize, n as usize - 1), (0, (b0 - n) as usize)]
            }
        };
        let (xs, ys) = (span(s.x, w), span(s.y, h));
        let len = (xs.1 - xs.0 + 1).max(ys.1 - ys.0 + 1).max(1) as u64;
        // blocks of 2^k with len <= 2^(k+1): at most 3 along each axis
        let k = (64 - (len - 1).leading_zeros() as usize).saturating_sub(1).min(self.levels.len() - 1);
        let (lw, _, d) = &self.levels[k];
        let mut lo = f32::INFINITY;
        for &(x0, x1) in &pieces(xs, w) {
            for &(y0, y1) in &pieces(ys, h) {
                for by in y0 >> k..=y1 >> k {
                    for bx in x0 >> k..=x1 >> k {
                        lo = lo.min(d[by * lw + bx]);
                    }
                }
            }
        }
        lo as f64
    }
}

/// A coarse triangle's residual bounds (the field minus the interpolated coarse height) and,
/// where some of its vertices are pinned at h = 1, `beside`: the least common top of its free
/// vertices under which the interpolated top still holds the field, the largest
/// (f - sum of the pinned weights) / (sum of the free weights) over the samples (at most 1, as
/// f <= 1: the free vertices at h = 1 always do).
struct TriangleBounds {
    lo: f64,
    hi: f64,
    beside: f64,
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

    /// The blocks' floor of a box is at most every texel the box reads (wrapping), and is one
    /// of the texels near it.
    #[test]
    fn the_blocks_floor_every_box() {
        let (w, h) = (37u32, 20u32);
        let data: Vec<f32> = (0..w * h).map(|i| ((i * 7919) % 1009) as f32 / 1009.0).collect();
        let hm = HeightMap::new(w, h, data).unwrap();
        let b = MinBlocks::new(&hm);
        for (i, r) in [0.01, 0.05, 0.2, 0.6].iter().enumerate() {
            for j in 0..40 {
                let s = DVec2::new(j as f64 * 0.173 - 1.3, j as f64 * 0.091 + i as f64 * 0.3);
                let lo = b.lowest_in_box(s, *r);
                let (x0, x1) = (((s.x - r) * w as f64 - 0.5).floor() as i64, ((s.x + r) * w as f64 - 0.5).floor() as i64 + 1);
                let (y0, y1) = (((s.y - r) * h as f64 - 0.5).floor() as i64, ((s.y + r) * h as f64 - 0.5).floor() as i64 + 1);
                let mut brute = f64::INFINITY;
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        brute = brute.min(hm.texel(x, y));
                    }
                }
                assert!(lo <= brute, "box {s:?} {r}: {lo} > {brute}");
            }
        }
    }

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
        let meshes = [
            ("plane", crate::mesh::Mesh::plane(2.0, 1).unwrap(), 8.0),
            ("cube", crate::mesh::Mesh::cube(1.0, 2).unwrap(), 8.0),
            ("torus", crate::mesh::Mesh::torus(1.0, 0.35, 16, 8).unwrap(), 64.0),
        ];
        for ((name, m, tpv), pattern) in meshes
            .iter()
            .flat_map(|m| [(m, Pattern::Fan), (m, Pattern::Grid)])
        {
            let (v, idx) = window_mesh(m, &mat, *tpv, pattern).unwrap();
            // the sides of a hard edge (the cube's) meet: one point per base point
            let t = tessellate_on_base(m, &mat, *tpv, pattern).unwrap();
            let mut at: HashMap<[u32; 3], [f32; 3]> = HashMap::new();
            for (i, wv) in v.iter().enumerate() {
                let p = *at.entry(t.base_positions[i].map(f32::to_bits)).or_insert(wv.vertex.position);
                assert_eq!(p, wv.vertex.position, "{name}: a crack at a base point");
            }
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
                        let h = hm.sample(uv.x, uv.y);
                        // both floors lie below the field at the fragment itself
                        for f in [0, 2] {
                            let floor: f64 = (0..3).map(|k| c[k].window[f] as f64 * l[k]).sum();
                            worst = worst.max(floor - h);
                        }
                        worst = worst.max(h - top);
                    }
                }
            }
            assert!(worst <= 0.0, "{name} {pattern:?}: the field leaves the window by {worst}");
        }
    }
}

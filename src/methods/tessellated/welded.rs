//! The displaced mesh of a mesh from arrays: each triangle subdivided barycentrically, with the
//! points of every geometric edge (vertices welded by position) placed once for all its sides.

use super::samples::{lerp_vertex, v3, BaseSample, Tessellation};
use crate::error::Result;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Where a vertex of a subdivided triangle lies on the welded surface: a mesh corner (welded id),
/// point j of a geometric edge cut in m, or inside the triangle.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Place {
    Corner(u32),
    Edge(u32, u32),
    Inside,
}

/// Meshes from arrays: each triangle cut barycentrically at level n, the most segments any of
/// its edges needs, where an edge is cut into the most segments either of its sides needs so
/// that no sub-edge spans more than tpv texels. A side cut into fewer segments than its
/// triangle's level has its lattice points snapped (monotonically) to the edge's points, and the
/// triangles that collapse are dropped. The vertices of a geometric edge (welded by position) are
/// then the same points for every triangle on it; where its sides carry other uvs or normals (a
/// seam, a hard edge), each side keeps its own vertex for its uv and basis, and all of them take
/// the mean of their displaced positions, so that the displaced surface is one surface.
#[allow(clippy::too_many_arguments)]
pub(super) fn arrays_mesh(
    mesh: &Mesh,
    tpv: f64,
    tiling: f64,
    width: u32,
    height: u32,
    out: &mut Tessellation,
    push: &dyn Fn(&mut Tessellation, BaseSample, DVec2),
    check: &dyn Fn(usize) -> Result<()>,
) -> Result<()> {
    let kw = width as f64 * tiling / tpv;
    let kh = height as f64 * tiling / tpv;
    let topo = Topology::new(mesh);
    let uv = |i: u32| {
        DVec2::new(
            mesh.uvs[i as usize][0] as f64,
            mesh.uvs[i as usize][1] as f64,
        )
    };
    let need = |a: u32, b: u32| {
        let d = uv(b) - uv(a);
        (d.x.abs() * kw).max(d.y.abs() * kh).ceil().max(1.0) as u32
    };
    let cuts: Vec<u32> = topo
        .edges
        .iter()
        .map(|(_, sides)| {
            sides
                .iter()
                .map(|&s| {
                    let (a, b) = topo.side_vertices(mesh, s);
                    need(a, b)
                })
                .max()
                .unwrap_or(1)
        })
        .collect();
    let levels: Vec<u32> = topo
        .tri_edges
        .iter()
        .map(|e| {
            cuts[e[0] as usize]
                .max(cuts[e[1] as usize])
                .max(cuts[e[2] as usize])
        })
        .collect();
    check(
        levels
            .iter()
            .map(|&n| (n as usize + 1) * (n as usize + 2) / 2)
            .sum(),
    )?;
    // output vertex of a place on the welded surface, seen from one side (its mesh vertices)
    let mut shared: HashMap<(Place, u32, u32), u32> = HashMap::new();
    // the output vertices of each shared place, to average their displaced positions
    let mut groups: HashMap<Place, Vec<u32>> = HashMap::new();
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let n = levels[t];
        let corner = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let te = topo.tri_edges[t];
        // the place of lattice point (a, b): weights w1 = a/n on corner 1, w2 = b/n on corner 2
        let place = |a: u32, b: u32| -> (Place, [(usize, f64); 3]) {
            let c = n - a - b; // weight of corner 0, in n-ths
            let on_side = if b == 0 {
                Some((0usize, a)) // corner 0 -> corner 1, t = a/n
            } else if c == 0 {
                Some((1, b)) // corner 1 -> corner 2, t = b/n
            } else if a == 0 {
                Some((2, c)) // corner 2 -> corner 0, t = c/n
            } else {
                None
            };
            let Some((k, num)) = on_side else {
                let (w1, w2) = (a as f64 / n as f64, b as f64 / n as f64);
                return (
                    Place::Inside,
                    [(corner[0], 1.0 - w1 - w2), (corner[1], w1), (corner[2], w2)],
                );
            };
            let e = te[k];
            let m = cuts[e as usize];
            // snapped to the edge's m points, counted from the side's first corner
            let j = ((num as u64 * m as u64 * 2 + n as u64) / (2 * n as u64)) as u32;
            let (v0, v1) = (corner[k], corner[(k + 1) % 3]);
            let (w0, w1) = (topo.weld[v0], topo.weld[v1]);
            // from the edge's lower welded end, so that both sides compute the same point
            let (lo, hi, jl) = if w0 <= w1 {
                (v0, v1, j)
            } else {
                (v1, v0, m - j)
            };
            let s = jl as f64 / m as f64;
            let pl = if jl == 0 {
                Place::Corner(topo.weld[lo])
            } else if jl == m {
                Place::Corner(topo.weld[hi])
            } else {
                Place::Edge(e, jl)
            };
            (pl, [(lo, 1.0 - s), (hi, s), (lo, 0.0)])
        };
        let mut local: Vec<u32> = Vec::with_capacity(((n + 1) * (n + 2) / 2) as usize);
        for a in 0..=n {
            for b in 0..=(n - a) {
                let (pl, ws) = place(a, b);
                let key = match pl {
                    Place::Inside => None,
                    _ => {
                        let mut pair = [ws[0].0 as u32, ws[1].0 as u32];
                        if ws[1].1 == 0.0 {
                            pair[1] = pair[0];
                        } else if ws[0].1 == 0.0 {
                            pair[0] = pair[1];
                        }
                        Some((pl, pair[0], pair[1]))
                    }
                };
                if let Some(&v) = key.as_ref().and_then(|k| shared.get(k)) {
                    local.push(v);
                    continue;
                }
                let v = out.positions.len() as u32;
                let bs = lerp_vertex(mesh, ws);
                let puv = uv(ws[0].0 as u32) * ws[0].1
                    + uv(ws[1].0 as u32) * ws[1].1
                    + uv(ws[2].0 as u32) * ws[2].1;
                push(out, bs, puv);
                if let Some(k) = key {
                    shared.insert(k, v);
                    groups.entry(k.0).or_default().push(v);
                }
                local.push(v);
            }
        }
        // lattice index of (a, b) in the row-by-row layout
        let row_start: Vec<usize> = (0..=n as usize)
            .scan(0usize, |acc, a| {
                let s = *acc;
                *acc += n as usize + 1 - a;
                Some(s)
            })
            .collect();
        // every sub-triangle is wound as its base triangle, and that one counter-clockwise about
        // the sum of its corners' normals (the oracle's rule at depth 0, `Mesh::wound_against_normals`;
        // tessellate.rs rewinds them with depth): at depth 0, not about its own interpolated
        // normals, which turn against the face where a corner's normal does (openarena's
        // fan.md3: a cap's centre normal opposite to its face flipped the sub-triangles around
        // it, and the rasteriser culled them)
        let flip = mesh.wound_against_normals(t);
        let mut emit = |p: usize, q: usize, r: usize| {
            let (p, q, r) = (local[p], local[q], local[r]);
            if p != q && q != r && r != p {
                // (p, r, q): the lattice's order, the base triangle's winding
                if flip {
                    out.indices.extend_from_slice(&[p, q, r]);
                } else {
                    out.indices.extend_from_slice(&[p, r, q]);
                }
            }
        };
        let n = n as usize;
        for a in 0..n {
            for b in 0..(n - a) {
                let p = row_start[a] + b;
                let r = row_start[a + 1] + b;
                emit(p, p + 1, r);
                if b + 1 < n - a {
                    emit(p + 1, r + 1, r);
                }
            }
        }
    }
    for vs in groups.values().filter(|vs| vs.len() > 1) {
        let mean = vs
            .iter()
            .fold(DVec3::ZERO, |acc, &v| acc + v3(out.positions[v as usize]))
            / vs.len() as f64;
        for &v in vs {
            out.positions[v as usize] = [mean.x as f32, mean.y as f32, mean.z as f32];
        }
    }
    Ok(())
}

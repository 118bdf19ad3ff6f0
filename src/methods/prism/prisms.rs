//! Prism POM (Dachsbacher & Tatarchuk 2007): each base triangle extruded along its vertex
//! normals into a prism (top, bottom and three side slabs of two triangles each, wound outward),
//! built once per (mesh, map, depth, tiling, shell direction, tightness) on the CPU.

use crate::mesh::{Mesh, Vertex};
use crate::scene::HeightMap;
use glam::{DVec2, DVec3};

/// A vertex of a prism's boundary face: the shared vertex (`pomkit::vertex::VertexIn`, locations
/// 0-4), the index of its prism (location 5) and the centre of its face (location 6: prism.wgsl's
/// `walk_origin` moves a fragment within rounding of an edge toward it).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PrismVertex {
    pub vertex: Vertex,
    pub prism: u32,
    pub centre: [f32; 3],
}

impl PrismVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 7] = {
        let a = Vertex::with_location5(wgpu::VertexFormat::Uint32);
        [
            a[0],
            a[1],
            a[2],
            a[3],
            a[4],
            a[5],
            wgpu::VertexAttribute {
                format: wgpu::VertexFormat::Float32x3,
                offset: std::mem::size_of::<Vertex>() as u64 + 4,
                shader_location: 6,
            },
        ]
    };
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<PrismVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// Per prism, for the fragment shader's walk: the six corners (top 0..3, bottom 0..3), the base
/// triangle's uvs (zw: uv_scale), normals and tangents (the basis at a hit is interpolated from
/// them), `info`: the highest (x) and lowest (y) height under the triangle's uv box
/// (`height_range_under`), and `adj`: the prism
/// across side k (corners k, k+1) or `NONE` where the side is the shell's boundary; `adj[3]`
/// has bit k set when side k is split along top(k+1)-bottom(k) rather than top(k)-bottom(k+1).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PrismData {
    pub top: [[f32; 4]; 3],
    pub bottom: [[f32; 4]; 3],
    pub uv: [[f32; 4]; 3],
    pub normal: [[f32; 4]; 3],
    pub tangent: [[f32; 4]; 3],
    pub info: [f32; 4],
    pub adj: [u32; 4],
    /// the tight shell: corner k's top as a unorm16 code of the height there (`lift_code`)
    pub lift: [u32; 4],
}

/// No prism across a side.
pub const NONE: u32 = u32::MAX;

/// A direction as octahedral snorm16 (x in the low half, y in the high half), the form WGSL's
/// `unpack2x16snorm` reads (prism.wgsl's `oct_decode`); zero maps to +z.
pub fn oct_encode(v: DVec3) -> u32 {
    let l1 = v.x.abs() + v.y.abs() + v.z.abs();
    let (mut x, mut y) = if l1 > 0.0 {
        (v.x / l1, v.y / l1)
    } else {
        (0.0, 0.0)
    };
    if l1 > 0.0 && v.z < 0.0 {
        let sx = if x >= 0.0 { 1.0 } else { -1.0 };
        let sy = if y >= 0.0 { 1.0 } else { -1.0 };
        (x, y) = ((1.0 - y.abs()) * sx, (1.0 - x.abs()) * sy);
    }
    let q = |a: f64| ((a.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    q(x) | (q(y) << 16)
}

/// Texels (rgba32uint) of one prism in the texture prism.wgsl reads (`PRISM_TEXELS` there).
/// 0-5: top[3], bottom[3] (f32 bits); what the walk needs at every prism it crosses rides in
/// their w, so that a span reads six texels: top[0].w the highest height (`info[0]`, f32),
/// top[1].w the diagonal bits (0-2), the plateau bit (3: the lowest height equals the highest)
/// and corner 2's top height (`lift[2]`, unorm16 in bits 16-31), top[2].w corners 0 and 1's
/// (unorm16 x 2, `unpack2x16unorm`), bottom[k].w the prism across side k (f32, -1 for `NONE`;
/// exact below 2^24 prisms). 6: uv0, uv1; 7: uv2 (a candidate's
/// segment reads these two). 8-10, corner k's basis, the hit's three texels: its normal and
/// tangent (`oct_encode`) and its uv scale (f32 bits; corner 0's x carries the tangent's
/// handedness in its sign, a scale being positive). On lavapipe a texel fetch costs about the
/// same whatever its format (docs/cost_journal_2026.md), so the basis is packed into as few as it fits.
pub const TEXELS_PER_PRISM: u32 = 11;

/// The per-prism data as a texture, and its size: a power-of-two number of prisms a row (the
/// shader finds a prism's texels with a shift and a mask), each `TEXELS_PER_PRISM` texels wide.
/// On lavapipe a storage buffer read at an index that differs between the lanes of a SIMD
/// vector is a scalar loop over the lanes, and Prism's walk reads six of them per prism
/// crossed; a texel fetch is one vector gather. Err: the rows exceed `max_dim`.
pub fn texels(
    data: &[PrismData],
    max_dim: u32,
) -> std::result::Result<(Vec<[u32; 4]>, (u32, u32)), usize> {
    let (per_row, rows) = crate::gpu::record_rows(data.len(), TEXELS_PER_PRISM, max_dim)?;
    let width = per_row * TEXELS_PER_PRISM;
    let mut t = vec![[0u32; 4]; width as usize * rows];
    let adj = |a: u32| if a == NONE { -1.0f32 } else { a as f32 };
    let f = |v: [f32; 4]| v.map(f32::to_bits);
    let dir = |v: [f32; 4]| oct_encode(DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64));
    for (i, d) in data.iter().enumerate() {
        let (row, col) = (i / per_row as usize, i % per_row as usize);
        let at = row * width as usize + col * TEXELS_PER_PRISM as usize;
        for k in 0..3 {
            t[at + k] = f(d.top[k]);
            t[at + 3 + k] = f(d.bottom[k]);
            t[at + 3 + k][3] = adj(d.adj[k]).to_bits();
        }
        let [c0, c1, c2, _] = d.lift;
        let plateau = (d.info[1] >= d.info[0]) as u32;
        t[at][3] = d.info[0].to_bits();
        t[at + 1][3] = (d.adj[3] & 7) | plateau << 3 | c2 << 16;
        t[at + 2][3] = c0 | c1 << 16;
        let uv = d.uv;
        t[at + 6] = f([uv[0][0], uv[0][1], uv[1][0], uv[1][1]]);
        t[at + 7] = f([uv[2][0], uv[2][1], 0.0, 0.0]);
        for k in 0..3 {
            let mut sx = uv[k][2].abs();
            if k == 0 && d.tangent[0][3] < 0.0 {
                sx = -sx;
            }
            t[at + 8 + k] = [
                dir(d.normal[k]),
                dir(d.tangent[k]),
                sx.to_bits(),
                uv[k][3].to_bits(),
            ];
        }
    }
    Ok((t, (width, rows as u32)))
}

/// The prisms of a mesh: the vertices of their boundary faces (the shell's surface: every top,
/// the sides no other prism shares, and the bottoms where the shell is open) and the per-prism
/// data.
pub struct Prisms {
    pub vertices: Vec<PrismVertex>,
    pub data: Vec<PrismData>,
}

/// A vertical edge of the shell (top and bottom corner), quantised so that the corners of
/// neighbouring prisms compare equal across a uv seam (where a mesh repeats a vertex with
/// positions that differ in the last bits).
type EdgeKey = [i64; 6];

/// The prisms of `mesh`: inward (top = base surface at h = 1, bottom `depth` below, pomkit's
/// convention) or outward (bottom = base surface, top `depth` above along the normals: the
/// paper's set-up, where features rise above the base mesh). Neighbouring prisms share their
/// side: they split it along the same diagonal, so that a ray leaving one enters the other.
/// `tight`: each vertical edge's top lowered to the highest height under the prisms beside it
/// (`PrismData::lift`); else every top at the full depth, the paper's shell.
pub fn build(
    mesh: &Mesh,
    depth: f32,
    outward: bool,
    tight: bool,
    height: &HeightMap,
    tiling: f32,
) -> Prisms {
    let ntri = mesh.indices.len() / 3;
    let p = |i: u32| DVec3::from_array(mesh.positions[i as usize].map(|x| x as f64));
    let n =
        |i: u32| DVec3::from_array(mesh.normals[i as usize].map(|x| x as f64)).normalize_or_zero();
    // the quantum: a millionth of the shell's extent
    let (lo, hi) = mesh.positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(a, b), q| {
            let q = DVec3::from_array(q.map(|x| x as f64));
            (a.min(q), b.max(q))
        },
    );
    // depth 0: the displaced surface is the base mesh. The shell gets `FLAT_SHELL` of the mesh's
    // extent (a prism with no volume has no faces a ray can cross) and every prism is a plateau
    // at h = 1 (below), so the walk meets the base surface where it enters the top.
    let flat = !(depth > 0.0);
    let d = if flat {
        (hi - lo).length().max(1e-30) * FLAT_SHELL
    } else {
        depth as f64
    };
    let quantum = ((hi - lo).length() + d).max(1e-30) * 1e-6;
    let q = |v: DVec3| [v.x, v.y, v.z].map(|x| (x / quantum).round() as i64);
    let mut corners: Vec<([DVec3; 3], [DVec3; 3], [EdgeKey; 3])> = Vec::with_capacity(ntri);
    for tri in mesh.indices.chunks_exact(3) {
        let base = [p(tri[0]), p(tri[1]), p(tri[2])];
        let off = [n(tri[0]), n(tri[1]), n(tri[2])].map(|v| v * d);
        let (top, bot) = if outward {
            ([0, 1, 2].map(|k| base[k] + off[k]), base)
        } else {
            (base, [0, 1, 2].map(|k| base[k] - off[k]))
        };
        let keys = [0, 1, 2].map(|k| {
            let (a, b) = (q(top[k]), q(bot[k]));
            [a[0], a[1], a[2], b[0], b[1], b[2]]
        });
        corners.push((top, bot, keys));
    }
    // each vertical edge's number, in order of first use: the diagonal rule below depends on the
    // mesh's topology only, so that a moved mesh splits its sides as the unmoved one
    let mut edge_ids: std::collections::HashMap<EdgeKey, u32> = std::collections::HashMap::new();
    let ids: Vec<[u32; 3]> = corners
        .iter()
        .map(|(_, _, keys)| {
            keys.map(|k| {
                let next = edge_ids.len() as u32;
                *edge_ids.entry(k).or_insert(next)
            })
        })
        .collect();
    // the tight shell: each vertical edge's top lowered to the highest height any prism on it has
    // under it (rounded up to a unorm16 code), so that rays cross no empty space above the field.
    // Neighbours share the edge and its height, so the shell stays closed; every prism's top
    // stays at or above its own highest height, never below `MIN_LIFT` (no flat prisms).
    let ranges: Vec<(f64, f64)> = mesh
        .indices
        .chunks_exact(3)
        .map(|tri| {
            if flat {
                (1.0, 1.0)
            } else {
                height_range_under(mesh, tri, height, tiling)
            }
        })
        .collect();
    // the full shell (the paper's): every top at the depth
    let mut lift = vec![if tight { MIN_LIFT } else { 1.0 }; edge_ids.len()];
    for (t, id) in ids.iter().enumerate() {
        for &e in id {
            lift[e as usize] = lift[e as usize].max(ranges[t].1);
        }
    }
    let lift: Vec<u16> = lift.into_iter().map(lift_code).collect();
    for (t, (top, bot, _)) in corners.iter_mut().enumerate() {
        for k in 0..3 {
            let m = lift[ids[t][k] as usize] as f64 / 65535.0;
            top[k] = bot[k] + (top[k] - bot[k]) * m;
        }
    }
    // adjacency: a side is shared when exactly two prisms have its two vertical edges
    let mut sides: std::collections::HashMap<(EdgeKey, EdgeKey), Vec<(u32, usize)>> =
        std::collections::HashMap::with_capacity(ntri * 3);
    // a base triangle with two corners in one place (a pole's fan) has no volume: it is neither
    // drawn nor anyone's neighbour
    let degenerate: Vec<bool> = corners
        .iter()
        .map(|(_, _, k)| k[0] == k[1] || k[1] == k[2] || k[2] == k[0])
        .collect();
    for (t, (_, _, keys)) in corners.iter().enumerate() {
        if degenerate[t] {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (keys[k], keys[(k + 1) % 3]);
            sides
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((t as u32, k));
        }
    }
    let mut adj = vec![[NONE; 4]; ntri];
    for v in sides.values() {
        if let [(t0, k0), (t1, k1)] = v.as_slice() {
            if t0 != t1 {
                adj[*t0 as usize][*k0] = *t1;
                adj[*t1 as usize][*k1] = *t0;
            }
        }
    }
    // a closed shell is entered only through its top from outside: its bottoms (the inner
    // surface) are drawn only where the shell is open (an edge, a crease), where a ray can reach them
    let open = adj
        .iter()
        .zip(&degenerate)
        .any(|(a, &deg)| !deg && a[..3].contains(&NONE));
    let mut vertices = Vec::with_capacity(ntri * 24);
    let mut data = Vec::with_capacity(ntri);
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let (top, bot, _) = &corners[t];
        let centre = (top.iter().chain(bot.iter()).copied().sum::<DVec3>()) / 6.0;
        let corner = |k: usize, on_top: bool| {
            let i = tri[k] as usize;
            let pos = if on_top { top[k] } else { bot[k] };
            PrismVertex {
                vertex: Vertex {
                    position: pos.as_vec3().to_array(),
                    normal: mesh.normals[i],
                    uv: mesh.uvs[i],
                    tangent: mesh.tangents[i],
                    uv_scale: mesh.uv_scale[i],
                },
                prism: t as u32,
                centre: [0.0; 3],
            }
        };
        let mut push_tri = |mut a: PrismVertex, mut b: PrismVertex, mut c: PrismVertex| {
            let pa = DVec3::from_array(a.vertex.position.map(|x| x as f64));
            let pb = DVec3::from_array(b.vertex.position.map(|x| x as f64));
            let pc = DVec3::from_array(c.vertex.position.map(|x| x as f64));
            let mid = (pa + pb + pc) / 3.0;
            let mid32 = mid.as_vec3().to_array();
            (a.centre, b.centre, c.centre) = (mid32, mid32, mid32);
            let g = (pb - pa).cross(pc - pa);
            // outward: the face's normal points away from the prism's centre
            if g.dot(mid - centre) >= 0.0 {
                vertices.extend_from_slice(&[a, b, c]);
            } else {
                vertices.extend_from_slice(&[a, c, b]);
            }
        };
        if !degenerate[t] {
            push_tri(corner(0, true), corner(1, true), corner(2, true));
        }
        if open && !degenerate[t] {
            let bottom = |k: usize| {
                let mut v = corner(k, false);
                v.prism |= BOTTOM;
                v
            };
            push_tri(bottom(0), bottom(1), bottom(2));
        }
        let mut diagonals = 0u32;
        for k in 0..3 {
            let j = (k + 1) % 3;
            // both prisms of a shared side split it along the diagonal from the top of the edge
            // numbered first
            let flip = ids[t][j] < ids[t][k];
            if flip {
                diagonals |= 1 << k;
            }
            if adj[t][k] != NONE || degenerate[t] {
                continue;
            }
            let wall = |c: usize, on_top: bool| {
                let mut v = corner(c, on_top);
                v.prism |= WALL;
                v
            };
            if flip {
                push_tri(wall(k, true), wall(j, true), wall(k, false));
                push_tri(wall(j, true), wall(j, false), wall(k, false));
            } else {
                push_tri(wall(k, true), wall(j, true), wall(j, false));
                push_tri(wall(k, true), wall(j, false), wall(k, false));
            }
        }
        adj[t][3] = diagonals;
        let v4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
        data.push(PrismData {
            top: top.map(v4),
            bottom: bot.map(v4),
            uv: [0, 1, 2].map(|k| {
                let i = tri[k] as usize;
                let (u, s) = (mesh.uvs[i], mesh.uv_scale[i]);
                [u[0], u[1], s[0], s[1]]
            }),
            normal: [0, 1, 2].map(|k| {
                let nn = mesh.normals[tri[k] as usize];
                [nn[0], nn[1], nn[2], 0.0]
            }),
            tangent: [0, 1, 2].map(|k| mesh.tangents[tri[k] as usize]),
            info: {
                let (mn, mx) = ranges[t];
                [mx as f32, mn as f32, 0.0, 0.0]
            },
            lift: {
                let c = [0, 1, 2].map(|k| lift[ids[t][k] as usize] as u32);
                [c[0], c[1], c[2], 0]
            },
            adj: adj[t],
        });
    }
    Prisms { vertices, data }
}

/// The bit of `PrismVertex::prism` that marks a wall: a side no neighbouring prism shares (an
/// open border of the surface, or a crease, where two prisms with other normals meet). A view
/// ray that enters the shell there below the height field passes under the surface (no hit),
/// as `pk.oracle.hits` does (docs/conventions.md, "Open borders"): prism.wgsl reads it.
pub const WALL: u32 = 1 << 31;

/// The bit of `PrismVertex::prism` that marks a prism's bottom. A view ray that enters the shell
/// there comes from behind the surface (below the field), which shows nothing from that side
/// (docs/conventions.md, "The displaced surface"): prism.wgsl discards it. The light's pass walks
/// it, since the back of a surface casts a shadow too.
pub const BOTTOM: u32 = 1 << 30;

/// The lowest top a tight shell gives a vertical edge, as a fraction of the depth: no prism is
/// flat, so that a ray entering one always finds its way out.
const MIN_LIFT: f64 = 1.0 / 256.0;

/// The shell's thickness at depth 0, as a fraction of the mesh's extent (its bounding box's
/// diagonal): thick enough for the prisms' float32 faces, and every prism a plateau at h = 1.
pub const FLAT_SHELL: f64 = 1e-4;

/// A height in [0, 1] as the unorm16 code WGSL's `unpack2x16unorm` reads, rounded up: the code's
/// value (code / 65535) is never below it.
fn lift_code(m: f64) -> u16 {
    let c = (m.clamp(0.0, 1.0) * 65535.0).ceil();
    let c = if (c / 65535.0) as f32 >= m as f32 {
        c
    } else {
        c + 1.0
    };
    c.min(65535.0) as u16
}

/// The lowest and the highest height of the texels a bilinear sample in a triangle's uv box
/// reads: the highest rejects prisms the ray passes above; where both are equal the field under
/// the prism is that plateau, and the walk meets it without a march.
fn height_range_under(mesh: &Mesh, tri: &[u32], height: &HeightMap, tiling: f32) -> (f64, f64) {
    let uvs: Vec<DVec2> = tri
        .iter()
        .map(|&i| DVec2::from_array(mesh.uvs[i as usize].map(|x| x as f64)) * tiling as f64)
        .collect();
    let lo = uvs
        .iter()
        .fold(DVec2::splat(f64::INFINITY), |a, b| a.min(*b));
    let hi = uvs
        .iter()
        .fold(DVec2::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
    let (w, h) = (height.width as f64, height.height as f64);
    let (x0, x1) = (
        (lo.x * w - 1.5).floor() as i64,
        (hi.x * w + 0.5).ceil() as i64,
    );
    let (y0, y1) = (
        (lo.y * h - 1.5).floor() as i64,
        (hi.y * h + 0.5).ceil() as i64,
    );
    if (x1 - x0) * (y1 - y0) > (height.width as i64 * height.height as i64) {
        return (0.0, 1.0);
    }
    let (mut mn, mut mx) = (f64::INFINITY, 0.0f64);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let v = height.texel(x, y);
            mn = mn.min(v);
            mx = mx.max(v);
        }
    }
    (mn.min(mx), mx)
}

#[cfg(test)]
#[path = "prisms_tests.rs"]
mod tests;

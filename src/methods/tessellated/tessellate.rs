//! The displaced surface as a triangle mesh: `S = P + depth * (h - 1) * N`, with h sampled from
//! the bilinear, repeating height field exactly as the shaders sample it (level 0).
//!
//! On meshes made of regular uv grids (every generated mesh), vertices lie on a lattice in
//! texture space with spacing tpv/W x tpv/H (tpv = texels per vertex, 0.5 for the references),
//! offset so that it contains every texel centre (for tpv = 1/k or a whole number): the bilinear field's creases between texel centres are
//! then edges of the mesh. P and N are interpolated inside the base triangle that contains each
//! lattice point, as the rasteriser would. On meshes from arrays each triangle is subdivided
//! barycentrically so that no edge spans more than tpv texels (vertices are not on texel centres
//! there); the points of an edge shared in space are placed once for all its sides (welded.rs).
//!
//! The lattice's quads are cut into triangles by `Pattern`: `Fan` adds a vertex at each quad's
//! centre (on the field) and cuts the quad into four triangles about it; `Grid` cuts it along one
//! diagonal into two. Inside a texel cell the field is bilinear, h = a + b x + c y + d x y, and
//! a quad of side L in texels leaves a chord error of |d| L^2 / 4 cut in two, |d| L^2 / 16 cut
//! in four about its centre: the fan matches the grid at half the spacing with half the
//! triangles (docs/conventions.md, "The tessellated mesh").

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::oracle::shading::{basis, displaced_normal};
use crate::scene::Material;
pub use super::samples::Tessellation;
use super::samples::{lerp_vertex, v3, BaseSample};
use glam::DVec2;

crate::option_enum!(
    /// How the displaced mesh cuts each quad of its lattice: four triangles about a centre vertex
    /// (four times less chord error than two), or two along a diagonal (a regular grid, as an
    /// engine's tessellator would). Meshes from arrays are subdivided barycentrically either way.
    Pattern, "pattern", {
        Fan = "fan",
        Grid = "grid",
    }
);

/// At most this many vertices (a 4096^2 map at k = 2 is 67M: refuse rather than exhaust memory).
pub const MAX_VERTICES: usize = 40_000_000;

/// Lattice coordinates along one axis of a chart: s = 0.5/texels + m * step (step = tpv/texels,
/// so texel centres are lattice points whenever tpv divides 1 or is a whole number), plus the
/// chart's ends s = 0 and s = tiling; returned as mesh-uv values in [0, 1].
fn lattice(tiling: f64, texels: u32, tpv: f64) -> Vec<f64> {
    let step = tpv / texels as f64;
    let first = (0.5 / texels as f64) % step;
    let mut out = vec![0.0];
    let mut m = 0usize;
    loop {
        let s = first + m as f64 * step;
        if s >= tiling - 1e-9 * step {
            break;
        }
        if s > 1e-9 * step {
            out.push(s / tiling);
        }
        m += 1;
    }
    out.push(1.0);
    out
}

/// `texels_per_vertex`: lattice spacing in texels (0.5 = two lattice vertices per texel);
/// `pattern`: how each lattice quad is cut (`Pattern`).
pub fn tessellate(
    mesh: &Mesh,
    mat: &Material,
    texels_per_vertex: f64,
    pattern: Pattern,
) -> Result<Tessellation> {
    tessellate_with(mesh, mat, texels_per_vertex, pattern, false)
}

/// `tessellate` whose lattice on a uv grid also holds the base grid's own lines, so that no
/// triangle spans two base cells: the mesh is never coarser than the base mesh, however wide
/// the spacing (Hybrid's coarse mesh: a lattice 64 texels apart on a torus of 4-texel cells
/// would cut chords through the tube). Meshes from arrays keep their vertices either way.
pub fn tessellate_on_base(
    mesh: &Mesh,
    mat: &Material,
    texels_per_vertex: f64,
    pattern: Pattern,
) -> Result<Tessellation> {
    tessellate_with(mesh, mat, texels_per_vertex, pattern, true)
}

/// The sorted union of `lattice` and the base grid's lines k / cells (k = 0..=cells).
fn with_base_lines(mut l: Vec<f64>, cells: u32) -> Vec<f64> {
    l.extend((0..=cells).map(|k| k as f64 / cells as f64));
    l.sort_by(f64::total_cmp);
    l.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
    l
}

fn tessellate_with(
    mesh: &Mesh,
    mat: &Material,
    texels_per_vertex: f64,
    pattern: Pattern,
    keep_base: bool,
) -> Result<Tessellation> {
    if !(texels_per_vertex.is_finite() && (1.0 / 64.0..=1024.0).contains(&texels_per_vertex)) {
        return Err(Error::arg(
            "texels_per_vertex",
            format!("must lie in [1/64, 1024], got {texels_per_vertex}"),
        ));
    }
    let tpv = texels_per_vertex;
    let hm = &mat.height;
    let tiling = mat.tiling as f64;
    let mut out = Tessellation::default();
    let push = |out: &mut Tessellation, b: BaseSample, uv: DVec2| {
        let s = uv * tiling;
        let h = hm.sample(s.x, s.y);
        let p = b.p + b.n * (mat.depth as f64 * (h - 1.0));
        // the base mesh's basis, orthonormalised as the shader does
        let (n, t, bt) = basis(b.n, b.t, b.w);
        let sn = displaced_normal(mat, s, n, t, bt, b.scale);
        out.positions.push([p.x as f32, p.y as f32, p.z as f32]);
        out.normals.push([sn.x as f32, sn.y as f32, sn.z as f32]);
        out.uvs.push([uv.x as f32, uv.y as f32]);
        out.base_normals.push([n.x as f32, n.y as f32, n.z as f32]);
        out.base_positions
            .push([b.p.x as f32, b.p.y as f32, b.p.z as f32]);
        out.tangents.push([
            t.x as f32,
            t.y as f32,
            t.z as f32,
            if b.w < 0.0 { -1.0 } else { 1.0 },
        ]);
        out.uv_scale.push([b.scale.x as f32, b.scale.y as f32]);
    };
    let check = |n: usize| -> Result<()> {
        if n > MAX_VERTICES {
            // vertices grow as 1/tpv²: the least tpv that fits, rounded up to 2 decimals
            let fit = (tpv * (n as f64 / MAX_VERTICES as f64).sqrt() * 100.0).ceil() / 100.0;
            return Err(Error::limit(
                "texels_per_vertex",
                format!(
                    "the displaced mesh of a {}x{} map at {tpv} texels per vertex needs {n} vertices, over pomkit's limit of {MAX_VERTICES}; use at least {fit} texels per vertex (pk.Tessellated(texels_per_vertex={fit}), or resolution={:.4} for pk.reference), or resample the map with pk.textures.fit",
                    hm.width,
                    hm.height,
                    1.0 / fit
                ),
            ));
        }
        Ok(())
    };
    if !mesh.charts.is_empty() {
        let (lu, lv) = (lattice(tiling, hm.width, tpv), lattice(tiling, hm.height, tpv));
        let axes = |nu: u32, nv: u32| match keep_base {
            true => (with_base_lines(lu.clone(), nu), with_base_lines(lv.clone(), nv)),
            false => (lu.clone(), lv.clone()),
        };
        let count = |(us, vs): &(Vec<f64>, Vec<f64>)| {
            let quads = (us.len() - 1) * (vs.len() - 1);
            us.len() * vs.len() + if pattern == Pattern::Fan { quads } else { 0 }
        };
        check(mesh.charts.iter().map(|&[nu, nv, _]| count(&axes(nu, nv))).sum())?;
        for &[nu, nv, first] in &mesh.charts {
            let (us, vs) = axes(nu, nv);
            let base = out.positions.len() as u32;
            let row = nu as usize + 1;
            // the base mesh's point at chart uv (u, v), as the rasteriser interpolates it
            let sample = |u: f64, v: f64| {
                let x = u * nu as f64;
                let y = v * nv as f64;
                let i = (x.floor() as usize).min(nu as usize - 1);
                let j = (y.floor() as usize).min(nv as usize - 1);
                let (fx, fy) = (x - i as f64, y - j as f64);
                let a = first as usize + j * row + i;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                if fx + fy <= 1.0 {
                    lerp_vertex(mesh, [(a, 1.0 - fx - fy), (b, fx), (c, fy)])
                } else {
                    lerp_vertex(mesh, [(d, fx + fy - 1.0), (c, 1.0 - fx), (b, 1.0 - fy)])
                }
            };
            for &v in &vs {
                for &u in &us {
                    push(&mut out, sample(u, v), DVec2::new(u, v));
                }
            }
            let w = us.len() as u32;
            for j in 0..vs.len() - 1 {
                for i in 0..us.len() - 1 {
                    let a = base + j as u32 * w + i as u32;
                    let (b, c, d) = (a + 1, a + w, a + w + 1);
                    match pattern {
                        Pattern::Grid => out.indices.extend_from_slice(&[a, c, b, b, c, d]),
                        Pattern::Fan => {
                            let (u, v) = (0.5 * (us[i] + us[i + 1]), 0.5 * (vs[j] + vs[j + 1]));
                            let e = out.positions.len() as u32;
                            push(&mut out, sample(u, v), DVec2::new(u, v));
                            out.indices
                                .extend_from_slice(&[a, e, b, b, e, d, d, e, c, c, e, a]);
                        }
                    }
                }
            }
        }
    } else {
        super::welded::arrays_mesh(
            mesh, tpv, tiling, hm.width, hm.height, &mut out, &push, &check,
        )?;
    }
    // The winding. At depth 0 the displaced mesh is the base mesh: each sub-triangle is wound as
    // its base triangle (arrays_mesh emits them so; a chart's lattice is wound below, its normals
    // smooth). With depth, each is wound counter-clockwise about its own interpolated base
    // normals: S = P + depth (h - 1) N is met from above where a ray crosses it against N (the
    // oracle's rule), and N turns against the face inside a triangle where a corner's normal
    // does (normals averaged across a thin wing)
    if mat.depth > 0.0 || !mesh.charts.is_empty() {
        for tri in out.indices.chunks_exact_mut(3) {
            let p = |i: u32| v3(out.positions[i as usize]);
            let g = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            let nb = v3(out.base_normals[tri[0] as usize])
                + v3(out.base_normals[tri[1] as usize])
                + v3(out.base_normals[tri[2] as usize]);
            if g.dot(nb) < 0.0 {
                tri.swap(1, 2);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::HeightMap;

    #[test]
    fn plane_vertices_sit_on_texel_centres_and_displace_by_depth() {
        let mut data = vec![0.0f32; 16];
        data[5] = 1.0; // texel (row 1, col 1)
        let hm = HeightMap::new(4, 4, data).unwrap();
        let mat = Material {
            height: crate::scene::shared(hm).unwrap(),
            depth: 0.5,
            tiling: 1.0,
            albedo: None,
        };
        let m = Mesh::plane(2.0, 1).unwrap();
        let t = tessellate(&m, &mat, 0.5, Pattern::Grid).unwrap();
        assert_eq!(t.positions.len(), 9 * 9);
        // the vertex at texel centre (1.5/4, 1.5/4) is at full height (y = 0), others below
        let k = t
            .uvs
            .iter()
            .position(|uv| (uv[0] - 0.375).abs() < 1e-6 && (uv[1] - 0.375).abs() < 1e-6)
            .unwrap();
        assert!(t.positions[k][1].abs() < 1e-6);
        let k2 = t
            .uvs
            .iter()
            .position(|uv| (uv[0] - 0.875).abs() < 1e-6 && (uv[1] - 0.875).abs() < 1e-6)
            .unwrap();
        assert!((t.positions[k2][1] + 0.5).abs() < 1e-6);
        // x of that vertex is the base position: (u - 0.5) * 2
        assert!((t.positions[k][0] - (-0.25)).abs() < 1e-6);
    }

    #[test]
    fn arrays_mesh_is_subdivided() {
        let (m, _) = Mesh::from_arrays(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            vec![[0.0, 1.0, 0.0]; 3],
            vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            vec![0, 2, 1],
            None,
        )
        .unwrap();
        let hm = HeightMap::new(4, 4, vec![1.0; 16]).unwrap();
        let mat = Material {
            height: crate::scene::shared(hm).unwrap(),
            depth: 0.5,
            tiling: 1.0,
            albedo: None,
        };
        let t = tessellate(&m, &mat, 0.5, Pattern::Fan).unwrap();
        assert_eq!(t.positions.len(), 9 * 10 / 2);
        assert_eq!(t.indices.len() / 3, 64);
        assert!(t.positions.iter().all(|p| p[1].abs() < 1e-6));
    }

    /// The chord error's analytic values on a checkerboard (every cell's twist |d| = 2): a
    /// quad of one texel cut in two leaves |d| / 4, cut in four about its centre |d| / 16.
    #[test]
    fn the_fan_leaves_a_quarter_of_the_grid_s_chord_error() {
        let data: Vec<f32> = (0..16).map(|k| ((k % 4 + k / 4) % 2) as f32).collect();
        let hm = HeightMap::new(4, 4, data).unwrap();
        let depth = 0.5;
        let mat = Material {
            height: crate::scene::shared(hm).unwrap(),
            depth: depth as f32,
            tiling: 1.0,
            albedo: None,
        };
        let m = Mesh::plane(2.0, 1).unwrap();
        let worst = |pattern| {
            let t = tessellate(&m, &mat, 1.0, pattern).unwrap();
            let mut worst = 0.0f64;
            for tri in t.indices.chunks_exact(3) {
                let k = 8;
                for a in 0..=k {
                    for b in 0..=(k - a) {
                        let w = [(k - a - b) as f64, a as f64, b as f64].map(|x| x / k as f64);
                        let (mut y, mut u, mut v) = (0.0, 0.0, 0.0);
                        for (&i, w) in tri.iter().zip(w) {
                            y += t.positions[i as usize][1] as f64 * w;
                            u += t.uvs[i as usize][0] as f64 * w;
                            v += t.uvs[i as usize][1] as f64 * w;
                        }
                        let field = depth * (mat.height.sample(u, v) - 1.0);
                        worst = worst.max((y - field).abs());
                    }
                }
            }
            (worst, t.indices.len() / 3)
        };
        let (grid, n_grid) = worst(Pattern::Grid);
        let (fan, n_fan) = worst(Pattern::Fan);
        assert!((grid - depth * 2.0 / 4.0).abs() < 1e-6, "grid {grid}");
        assert!((fan - depth * 2.0 / 16.0).abs() < 1e-6, "fan {fan}");
        assert_eq!(n_fan, 2 * n_grid);
    }

    /// A seam: a unit quad whose two triangles sit in different charts of the atlas, one drawn
    /// three times larger (so cut into more segments), over a map whose heights differ between the
    /// charts. The displaced mesh is still one surface: welded by position, its only open edges
    /// are the quad's border (no T-junction, no crack along the diagonal).
    #[test]
    fn a_seam_is_welded_without_t_junctions() {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ];
        let uvs = vec![
            [0.05, 0.05],
            [0.25, 0.05],
            [0.05, 0.25],
            [0.9, 0.3],
            [0.9, 0.9],
            [0.3, 0.9],
        ];
        let (m, _) = Mesh::from_arrays(
            positions,
            vec![[0.0, 1.0, 0.0]; 6],
            uvs,
            vec![0, 2, 1, 3, 5, 4],
            None,
        )
        .unwrap();
        let data: Vec<f32> = (0..64 * 64)
            .map(|k| ((k * 7919) % 101) as f32 / 100.0)
            .collect();
        let mat = Material {
            height: crate::scene::shared(HeightMap::new(64, 64, data).unwrap()).unwrap(),
            depth: 0.2,
            tiling: 1.0,
            albedo: None,
        };
        for tpv in [0.5, 1.0, 3.0] {
            let t = tessellate(&m, &mat, tpv, Pattern::Fan).unwrap();
            let key = |i: u32| t.positions[i as usize].map(f32::to_bits);
            let mut edges: std::collections::HashMap<([u32; 3], [u32; 3]), u32> =
                Default::default();
            for tri in t.indices.chunks_exact(3) {
                for k in 0..3 {
                    let (a, b) = (key(tri[k]), key(tri[(k + 1) % 3]));
                    *edges
                        .entry(if a < b { (a, b) } else { (b, a) })
                        .or_default() += 1;
                }
            }
            let mut border = 0.0;
            for ((a, b), n) in &edges {
                assert!(*n <= 2, "an edge with {n} triangles");
                if *n == 1 {
                    let (a, b) = (a.map(f32::from_bits), b.map(f32::from_bits));
                    let mid = [(a[0] + b[0]) * 0.5, (a[2] + b[2]) * 0.5];
                    assert!(
                        (mid[0] + mid[1] - 1.0).abs() > 1e-4,
                        "an open edge on the diagonal at {mid:?} (tpv {tpv})"
                    );
                    border += ((a[0] - b[0]).powi(2) + (a[2] - b[2]).powi(2)).sqrt() as f64;
                }
            }
            assert!(
                (border - 4.0).abs() < 1e-5,
                "border length {border} (tpv {tpv})"
            );
            // no triangle folded over: the uv areas add up to the base triangles'
            let area: f64 = t
                .indices
                .chunks_exact(3)
                .map(|tri| {
                    let p = [tri[0], tri[1], tri[2]].map(|i| {
                        DVec2::new(
                            t.positions[i as usize][0] as f64,
                            t.positions[i as usize][2] as f64,
                        )
                    });
                    0.5 * (p[1] - p[0]).perp_dot(p[2] - p[0]).abs()
                })
                .sum();
            assert!((area - 1.0).abs() < 1e-6, "area {area} (tpv {tpv})");
        }
    }
}

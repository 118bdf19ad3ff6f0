//! The asset report: what in a mesh (and its height map) changes what the methods can do, with
//! where it is. Charts, seams and how far their two sides' heights disagree, mirrored charts,
//! degenerate triangles, open borders, hard edges, non-manifold edges; with a height map, the
//! texels each chart covers, charts that overlap, and the gutter between charts against the mip
//! levels a method samples.

use crate::mesh::topology::Topology;
use crate::mesh::{uv_derivatives, Mesh};
use crate::scene::HeightMap;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::collections::VecDeque;

/// How many places the report names for each finding.
pub const EXAMPLES: usize = 5;

/// The Python type of a report field's value (its stub's spelling), and how the pyo3 layer
/// receives it (`ReportVisitor`).
pub trait ReportValue {
    const PY_TYPE: &'static str;
    fn accept(&self, name: &'static str, v: &mut dyn ReportVisitor);
}

/// What receives a report's fields one by one (the pyo3 layer's dict).
pub trait ReportVisitor {
    fn count(&mut self, name: &'static str, v: Option<i64>);
    fn real(&mut self, name: &'static str, v: Option<f64>);
    fn flag(&mut self, name: &'static str, v: bool);
    fn places(&mut self, name: &'static str, v: &[(String, [f32; 3])]);
}

macro_rules! report_value {
    ($t:ty, $py:literal, |$s:ident, $n:ident, $v:ident| $body:expr) => {
        impl ReportValue for $t {
            const PY_TYPE: &'static str = $py;
            fn accept(&self, $n: &'static str, $v: &mut dyn ReportVisitor) {
                let $s = self;
                $body
            }
        }
    };
}
report_value!(usize, "int", |s, n, v| v.count(n, Some(*s as i64)));
report_value!(Option<usize>, "Optional[int]", |s, n, v| v.count(n, s.map(|x| x as i64)));
report_value!(Option<u32>, "Optional[int]", |s, n, v| v.count(n, s.map(|x| x as i64)));
report_value!(Option<i32>, "Optional[int]", |s, n, v| v.count(n, s.map(|x| x as i64)));
report_value!(f64, "float", |s, n, v| v.real(n, Some(*s)));
report_value!(Option<f64>, "Optional[float]", |s, n, v| v.real(n, *s));
report_value!(bool, "bool", |s, n, v| v.flag(n, *s));
report_value!(Vec<(String, [f32; 3])>, "list[tuple[str, tuple[float, float, float]]]", |s, n, v| v.places(n, s));

/// The report declared once: the struct, its field table (`AssetReport::FIELDS`: name, Python
/// type, doc) and its visit, from which the pyo3 layer, the stub and `pk.AssetReport` follow.
macro_rules! report {
    (
        $(#[$m:meta])*
        pub struct $name:ident {
            $( $(#[doc = $doc:literal])* pub $f:ident : $t:ty, )*
        }
    ) => {
        $(#[$m])*
        pub struct $name {
            $( $(#[doc = $doc])* pub $f: $t, )*
        }

        impl $name {
            /// (name, Python type, doc) per field, in order.
            pub const FIELDS: &'static [(&'static str, &'static str, &'static str)] = &[
                $( (stringify!($f), <$t as ReportValue>::PY_TYPE, concat!($($doc, "\n",)*)), )*
            ];
            /// Every field to `v`, in order.
            pub fn visit(&self, v: &mut dyn ReportVisitor) {
                $( ReportValue::accept(&self.$f, stringify!($f), v); )*
            }
        }
    };
}

report! {
    #[derive(Clone, Debug, Default)]
    pub struct AssetReport {
    pub vertices: usize,
    pub triangles: usize,
    /// distinct positions
    pub welded_vertices: usize,
    /// groups of triangles joined by edges whose uvs and handedness agree
    pub charts: usize,
    /// charts whose uv map is mirrored (most of their triangles have handedness w = +1)
    pub mirrored_charts: usize,
    pub mirrored_triangles: usize,
    /// triangles with zero uv area (no tangent basis of their own)
    pub degenerate_uv_triangles: usize,
    /// triangles with zero area in space
    pub degenerate_triangles: usize,
    /// geometric edges whose sides carry other uvs
    pub seam_edges: usize,
    /// edges whose sides share their uvs but not their handedness (a mirror axis inside a chart
    /// folded onto itself: the tangent basis flips there)
    pub mirror_edges: usize,
    /// mirror-axis edges whose two sides share a vertex (not only its position): one tangent
    /// serves both handednesses there, and the frame between the sides' corners collapses
    pub mirror_shared_edges: usize,
    /// edges with one side: the displaced surface ends there
    pub open_edges: usize,
    pub open_length: f64,
    /// edges whose sides carry other normals (split normals)
    pub hard_edges: usize,
    /// edges with more than two sides
    pub nonmanifold_edges: usize,
    /// any uv outside [0, 1] (the map repeats there)
    pub uvs_outside_unit_square: bool,
    /// with a height map: the lowest and highest height it holds (of 0..1; h = 1 is the mesh's
    /// surface, 0 lies the material's depth below it)
    pub height_min: Option<f64>,
    pub height_max: Option<f64>,
    /// with a height map and the material's depth: the relief's own depth, depth × (max − min).
    /// A map that holds less than 0..1 spends the shell's depth on heights it never takes:
    /// `pk.textures.normalize` stretches it to 0..1, and this depth then keeps the relief
    pub relief_depth: Option<f64>,
    /// with a height map: the largest and mean difference of the height field across a seam
    /// (in height units, 0..1), sampled along each seam edge on its sides
    pub seam_height_max: Option<f64>,
    pub seam_height_mean: Option<f64>,
    /// texels (of the height map) covered by two or more charts
    pub overlapping_texels: Option<usize>,
    /// the fewest empty texels between two charts (the map repeats)
    pub min_chart_gap_texels: Option<u32>,
    /// the highest mip level whose bilinear footprint stays within a chart's half of the
    /// narrowest gap (None: charts touch, even level 0 reads a neighbour)
    pub max_clean_mip: Option<i32>,
    /// triangles with a vertex normal more than 60 degrees from the face's normal (normals averaged
    /// across a thin part or a sharp edge): the shell leans far from the surface there
    pub normals_off_faces: usize,
    /// triangles with a vertex normal more than 90 degrees from the face's (flipped): the shell
    /// turns inside out there
    pub normals_flipped: usize,
    /// with the material's depth: prisms whose bottom (the corners sunk by the depth along their
    /// normals) is turned over against their top, where the depth exceeds the local radius of
    /// curvature or the normals cross: the shell folds there
    pub folded_prisms: Option<usize>,
    /// (finding, position in the mesh's space) for up to `EXAMPLES` places of each finding
    pub examples: Vec<(String, [f32; 3])>,
}
}

/// What a triangle's normals do to its shell: a normal more than 90 degrees from the face
/// (flipped) or more than 60 (off its face), and with a depth, whether the prism folds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShellTriangle {
    pub flipped: bool,
    pub off_face: bool,
    pub folded: bool,
}

/// `ShellTriangle` of the (non-degenerate) triangle `tri`: the normals against the face (wound
/// toward the normals' side by `orient_outward`); the layer s below the top, (P - s N) over the
/// triangle, must keep an area along the face's normal (a quadratic in s) that does not reach zero
/// (the layers collapse, then turn over or pass through each other) for s in (0, depth].
pub fn shell_triangle(mesh: &Mesh, tri: &[u32], depth: Option<f64>) -> ShellTriangle {
    let p: Vec<DVec3> = tri.iter().map(|&i| mesh.position_f64(i)).collect();
    let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    let n: Vec<DVec3> = tri
        .iter()
        .map(|&i| mesh.normal_f64(i).normalize_or_zero())
        .collect();
    let worst = n.iter().map(|v| v.dot(nf)).fold(1.0f64, f64::min);
    let folded = depth.filter(|d| *d > 0.0).is_some_and(|d| {
        let area = |s: f64| {
            let b: Vec<DVec3> = (0..3).map(|k| p[k] - n[k] * s).collect();
            (b[1] - b[0]).cross(b[2] - b[0]).dot(nf)
        };
        let a0 = area(0.0);
        (1..=64).any(|k| area(d * k as f64 / 64.0) <= 1e-3 * a0)
    });
    ShellTriangle {
        flipped: worst < 0.0,
        off_face: (0.0..0.5).contains(&worst),
        folded,
    }
}

/// The triangles of `mesh` whose shell the methods that build or walk one (Prism, NCS,
/// CurvedRelief) are not held to at `depth`: (flipped normals, folded prisms).
pub fn shell_findings(mesh: &Mesh, depth: f64) -> (usize, usize) {
    let (mut flipped, mut folded) = (0, 0);
    for tri in mesh.indices.chunks_exact(3) {
        let p: Vec<DVec3> = tri.iter().map(|&i| mesh.position_f64(i)).collect();
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        if e1.cross(e2).length() <= 1e-12 * (e1.length_squared() + e2.length_squared()) {
            continue;
        }
        let s = shell_triangle(mesh, tri, Some(depth));
        flipped += s.flipped as usize;
        folded += s.folded as usize;
    }
    (flipped, folded)
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

/// `height`, with the material's `tiling`: the map the report samples across seams and rasterises
/// the charts into; `depth`, the material's, for the shell's folds. One function per phase, each
/// filling its part of the report: the triangles, the edges and charts, the charts' handedness,
/// and with a map the seams' heights, the texels the charts cover and the gap between them.
pub fn check_asset(
    mesh: &Mesh,
    height: Option<&HeightMap>,
    tiling: f64,
    depth: Option<f64>,
) -> AssetReport {
    let topo = Topology::new(mesh);
    let mut r = AssetReport {
        vertices: mesh.positions.len(),
        triangles: mesh.indices.len() / 3,
        welded_vertices: topo.welded,
        folded_prisms: depth.filter(|d| *d > 0.0).map(|_| 0),
        uvs_outside_unit_square: mesh.uvs.iter().flatten().any(|&x| !(0.0..=1.0).contains(&x)),
        ..Default::default()
    };
    let mirrored = triangles(mesh, depth, &mut r);
    let (chart_of, seam_edges) = edges_and_charts(mesh, &topo, &mirrored, &mut r);
    chart_handedness(mesh, &chart_of, &mirrored, &mut r);
    let Some(hm) = height else { return r };
    let (lo, hi) = hm
        .data
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x as f64), b.max(x as f64)));
    r.height_min = Some(lo);
    r.height_max = Some(hi);
    r.relief_depth = depth.map(|d| d * (hi - lo));
    seam_heights(mesh, &topo, &seam_edges, hm, tiling, &mut r);
    let label = chart_texels(mesh, &chart_of, hm, tiling, &mut r);
    chart_gap(label, hm, &mut r);
    r
}

impl AssetReport {
    /// An example of `what` at `p`, up to `EXAMPLES` of each finding.
    fn example(&mut self, what: &str, p: DVec3) {
        if self.examples.iter().filter(|(w, _)| w == what).count() < EXAMPLES {
            self.examples
                .push((what.to_string(), [p.x as f32, p.y as f32, p.z as f32]));
        }
    }
}

/// The triangles: degeneracy, normals against their faces, folds, uv degeneracy and handedness
/// (each triangle's shell on every core, src/parallel.rs). Returns which triangles are mirrored.
fn triangles(mesh: &Mesh, depth: Option<f64>, r: &mut AssetReport) -> Vec<bool> {
    let ntri = mesh.indices.len() / 3;
    let uv = |i: u32| mesh.uv_f64(i);
    crate::parallel::init();
    let shells: Vec<ShellTriangle> = mesh
        .indices
        .par_chunks_exact(3)
        .map(|tri| shell_triangle(mesh, tri, depth))
        .collect();
    let mut mirrored = vec![false; ntri];
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let p = tri
            .iter()
            .map(|&i| mesh.position_f64(i))
            .collect::<Vec<_>>();
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let ng = e1.cross(e2);
        if ng.length() <= 1e-12 * (e1.length_squared() + e2.length_squared()) {
            r.degenerate_triangles += 1;
            r.example("degenerate triangle", c);
            continue;
        }
        let shell = &shells[t];
        if shell.flipped {
            r.normals_flipped += 1;
            r.example("flipped normal", c);
        } else if shell.off_face {
            r.normals_off_faces += 1;
            r.example("normal far from its face", c);
        }
        if shell.folded {
            *r.folded_prisms.get_or_insert(0) += 1;
            r.example("folded shell", c);
        }
        match uv_derivatives(e1, e2, uv(tri[1]) - uv(tri[0]), uv(tri[2]) - uv(tri[0])) {
            None => {
                r.degenerate_uv_triangles += 1;
                r.example("degenerate uv triangle", c);
            }
            Some((dpdu, dpdv)) => {
                // pomkit's unmirrored handedness is w = -1 (the plane: u along +X, v along +Z)
                if ng.cross(dpdu).dot(dpdv) > 0.0 {
                    mirrored[t] = true;
                    r.mirrored_triangles += 1;
                }
            }
        }
    }

    mirrored
}

/// The edges: open borders, non-manifold edges, seams, mirror axes, hard edges; the charts by
/// union over the uv-continuous edges. Returns each triangle's chart and the seam edges.
fn edges_and_charts(
    mesh: &Mesh,
    topo: &Topology,
    mirrored: &[bool],
    r: &mut AssetReport,
) -> (Vec<u32>, Vec<usize>) {
    let ntri = mesh.indices.len() / 3;
    let mut parent: Vec<u32> = (0..ntri as u32).collect();
    let mut seam_edges: Vec<usize> = Vec::new();
    for (ei, (_, sides)) in topo.edges.iter().enumerate() {
        let ends: Vec<(u32, u32)> = sides.iter().map(|&s| topo.side_vertices(mesh, s)).collect();
        let (a0, b0) = ends[0];
        let mid = (mesh.position_f64(a0) + mesh.position_f64(b0)) * 0.5;
        match sides.len() {
            1 => {
                r.open_edges += 1;
                r.open_length += (mesh.position_f64(a0) - mesh.position_f64(b0)).length();
                r.example("open border", mid);
                continue;
            }
            2 => {}
            _ => {
                r.nonmanifold_edges += 1;
                r.example("non-manifold edge", mid);
            }
        }
        let same_uv = |i: u32, j: u32| mesh.uvs[i as usize] == mesh.uvs[j as usize];
        let close_n = |i: u32, j: u32| {
            (mesh.normal_f64(i).normalize() - mesh.normal_f64(j).normalize()).length() < 1e-4
        };
        let mut seam = false;
        let mut mirror = false;
        let mut shared = false;
        let mut hard = false;
        for (k, &(a, b)) in ends.iter().enumerate().skip(1) {
            if !(same_uv(a, a0) && same_uv(b, b0)) {
                seam = true;
            } else if mirrored[sides[k].tri as usize] != mirrored[sides[0].tri as usize] {
                mirror = true;
                shared |= a == a0 || b == b0;
            } else {
                let (x, y) = (
                    find(&mut parent, sides[0].tri),
                    find(&mut parent, sides[k].tri),
                );
                parent[x as usize] = y;
            }
            hard |= !(close_n(a, a0) && close_n(b, b0));
        }
        if seam {
            r.seam_edges += 1;
            seam_edges.push(ei);
            r.example("seam", mid);
        }
        if mirror {
            r.mirror_edges += 1;
            r.example("mirror axis", mid);
        }
        if shared {
            r.mirror_shared_edges += 1;
            r.example("vertex shared across a mirror axis", mid);
        }
        if hard {
            r.hard_edges += 1;
            r.example("hard edge", mid);
        }
    }
    let mut chart_of = vec![0u32; ntri];
    let mut roots = std::collections::HashMap::new();
    for t in 0..ntri {
        let root = find(&mut parent, t as u32);
        let n = roots.len() as u32;
        chart_of[t] = *roots.entry(root).or_insert(n);
    }
    r.charts = roots.len();
    (chart_of, seam_edges)
}

/// The charts mapped mirrored (most of their triangles).
fn chart_handedness(mesh: &Mesh, chart_of: &[u32], mirrored: &[bool], r: &mut AssetReport) {
    let mut votes = vec![(0i64, DVec3::ZERO); r.charts];
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        votes[chart_of[t] as usize].0 += if mirrored[t] { 1 } else { -1 };
        votes[chart_of[t] as usize].1 = mesh.position_f64(tri[0]);
    }
    for (v, p) in votes {
        if v > 0 {
            r.mirrored_charts += 1;
            r.example("mirrored chart", p);
        }
    }

}

/// The height field on each side of every seam, sampled along the edge.
fn seam_heights(
    mesh: &Mesh,
    topo: &Topology,
    seam_edges: &[usize],
    hm: &HeightMap,
    tiling: f64,
    r: &mut AssetReport,
) {
    let uv = |i: u32| mesh.uv_f64(i);
    let (w, h) = (hm.width as f64, hm.height as f64);
    let mut worst = 0.0f64;
    let mut sum = 0.0;
    let mut count = 0usize;
    for &ei in seam_edges {
        let sides = &topo.edges[ei].1;
        let ends: Vec<(u32, u32)> = sides.iter().map(|&s| topo.side_vertices(mesh, s)).collect();
        let span = |(a, b): (u32, u32)| {
            let d = (uv(b) - uv(a)) * tiling;
            (d.x.abs() * w).max(d.y.abs() * h)
        };
        let k = ends.iter().map(|&e| span(e)).fold(1.0f64, f64::max).ceil() as usize * 2 + 1;
        let mut edge_worst = 0.0f64;
        for i in 0..=k {
            let s = i as f64 / k as f64;
            let hs: Vec<f64> = ends
                .iter()
                .map(|&(a, b)| {
                    let q = (uv(a) * (1.0 - s) + uv(b) * s) * tiling;
                    hm.sample(q.x, q.y)
                })
                .collect();
            let d = hs.iter().fold(f64::MIN, |m, &x| m.max(x))
                - hs.iter().fold(f64::MAX, |m, &x| m.min(x));
            edge_worst = edge_worst.max(d);
            sum += d;
            count += 1;
        }
        if edge_worst > worst {
            worst = edge_worst;
        }
        if edge_worst > 1.0 / 255.0 {
            let (a, b) = ends[0];
            r.example(
                "seam heights disagree",
                (mesh.position_f64(a) + mesh.position_f64(b)) * 0.5,
            );
        }
    }
    if count > 0 {
        r.seam_height_max = Some(worst);
        r.seam_height_mean = Some(sum / count as f64);
    }

}

/// Which chart covers each texel centre (the map repeats), and the texels two charts share.
/// Returns the texels' charts (EMPTY where none).
fn chart_texels(
    mesh: &Mesh,
    chart_of: &[u32],
    hm: &HeightMap,
    tiling: f64,
    r: &mut AssetReport,
) -> Vec<u32> {
    let uv = |i: u32| mesh.uv_f64(i);
    let (w, h) = (hm.width as f64, hm.height as f64);
    let (wi, hi) = (hm.width as usize, hm.height as usize);
    let mut label = vec![EMPTY; wi * hi];
    let mut overlap = vec![false; wi * hi];
    let mut overlap_at: Option<DVec3> = None;
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let q: Vec<DVec2> = tri
            .iter()
            .map(|&i| uv(i) * tiling * DVec2::new(w, h))
            .collect();
        let area = (q[1] - q[0]).perp_dot(q[2] - q[0]);
        if area.abs() < 1e-12 {
            continue;
        }
        let lo = q[0].min(q[1]).min(q[2]);
        let hi2 = q[0].max(q[1]).max(q[2]);
        let (x0, x1) = ((lo.x - 0.5).ceil() as i64, (hi2.x - 0.5).floor() as i64);
        let (y0, y1) = ((lo.y - 0.5).ceil() as i64, (hi2.y - 0.5).floor() as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let e = |a: DVec2, b: DVec2| (b - a).perp_dot(c - a) * area.signum();
                if e(q[0], q[1]) < 0.0 || e(q[1], q[2]) < 0.0 || e(q[2], q[0]) < 0.0 {
                    continue;
                }
                let k = y.rem_euclid(hi as i64) as usize * wi + x.rem_euclid(wi as i64) as usize;
                let c = chart_of[t];
                if label[k] == EMPTY {
                    label[k] = c;
                } else if label[k] != c {
                    overlap[k] = true;
                    overlap_at.get_or_insert_with(|| {
                        (mesh.position_f64(tri[0])
                            + mesh.position_f64(tri[1])
                            + mesh.position_f64(tri[2]))
                            / 3.0
                    });
                }
            }
        }
    }
    r.overlapping_texels = Some(overlap.iter().filter(|&&o| o).count());
    if let Some(p) = overlap_at {
        r.example("overlapping charts", p);
    }
    label
}

/// A texel no chart covers.
const EMPTY: u32 = u32::MAX;

/// The gap between charts: a breadth-first distance (8-connected) from every covered texel, and
/// the mip levels it leaves clean.
fn chart_gap(mut label: Vec<u32>, hm: &HeightMap, r: &mut AssetReport) {
    let (wi, hi) = (hm.width as usize, hm.height as usize);
    let mut dist = vec![u32::MAX; wi * hi];
    let mut queue = VecDeque::new();
    for k in 0..wi * hi {
        if label[k] != EMPTY {
            dist[k] = 0;
            queue.push_back(k);
        }
    }
    // charts that share texels have no gap at all
    let mut gap = if r.overlapping_texels != Some(0) {
        0
    } else {
        u32::MAX
    };
    while let Some(k) = queue.pop_front() {
        let (x, y) = ((k % wi) as i64, (k / wi) as i64);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if dx == 0 && dy == 0 {
                    continue;
                }
                let n = (y + dy).rem_euclid(hi as i64) as usize * wi
                    + (x + dx).rem_euclid(wi as i64) as usize;
                if label[n] == EMPTY && dist[n] == u32::MAX {
                    dist[n] = dist[k] + 1;
                    label[n] = label[k];
                    queue.push_back(n);
                } else if label[n] != label[k] && label[n] != EMPTY {
                    gap = gap.min(dist[k] + dist[n]);
                }
            }
        }
    }
    if r.charts > 1 && gap != u32::MAX {
        r.min_chart_gap_texels = Some(gap);
        let half = gap / 2;
        r.max_clean_mip = if half >= 1 {
            Some((half as f64).log2().floor() as i32)
        } else {
            None
        };
    }
}

#[cfg(test)]
mod tests;

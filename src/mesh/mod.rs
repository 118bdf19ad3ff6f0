//! Base meshes and their tangent bases.
//!
//! A tangent is a 4-vector (xyz, w) as in glTF: the bitangent is `w * cross(N, T)`, and it points
//! along dP/dv. `uv_scale` holds the world length per unit of u and of v at each vertex
//! (|dP/du|, |dP/dv|; Chen & Chang's S_tangent and S_binormal), which turns a world direction into
//! a texture-space one.

pub mod mikktspace;
pub mod normals;
pub mod quadrics;
pub mod topology;
pub mod borders;

use crate::error::{Error, Result};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub tangents: Vec<[f32; 4]>,
    pub uv_scale: Vec<[f32; 2]>,
    pub indices: Vec<u32>,
    /// Regular uv grids the mesh is made of, as (nu, nv, first_vertex): (nu+1) x (nv+1) vertices
    /// row-major from uv (0,0) to (1,1), quads split along the (i+1,j)-(i,j+1) diagonal. Empty for
    /// meshes from arrays. Lets the tessellation place vertices exactly on texel centres.
    pub charts: Vec<[u32; 3]>,
}

/// Where a mesh from arrays gets its tangent bases (the uv scales are always computed).
#[derive(Clone, Debug)]
pub enum TangentBases {
    /// the caller's tangents, in pomkit's handedness (bitangent `w * cross(N, T)` along +dP/dv)
    Given(Vec<[f32; 4]>),
    /// MikkTSpace, as glTF asks where a file has none (maps baked against it line up)
    MikkTSpace,
    /// pomkit's own: per-triangle dP/du accumulated per vertex, weighted by area
    Pomkit,
}

/// What `compute_bases` found: triangles whose uvs are degenerate get a fallback basis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BasisReport {
    pub degenerate_uv_triangles: usize,
    pub fallback_vertices: usize,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub tangent: [f32; 4],
    pub uv_scale: [f32; 2],
}

impl Vertex {
    /// The vertex buffer of per-vertex arrays (all of one length).
    pub fn interleave(
        positions: &[[f32; 3]],
        normals: &[[f32; 3]],
        uvs: &[[f32; 2]],
        tangents: &[[f32; 4]],
        uv_scale: &[[f32; 2]],
    ) -> Vec<Vertex> {
        (0..positions.len())
            .map(|i| Vertex {
                position: positions[i],
                normal: normals[i],
                uv: uvs[i],
                tangent: tangents[i],
                uv_scale: uv_scale[i],
            })
            .collect()
    }

    /// The vertex's attributes and one more, at location 5 right after the vertex (a method's
    /// own geometry: the prisms' index, the quadric coefficients).
    pub const fn with_location5(format: wgpu::VertexFormat) -> [wgpu::VertexAttribute; 6] {
        let v = Self::ATTRIBUTES;
        [
            v[0],
            v[1],
            v[2],
            v[3],
            v[4],
            wgpu::VertexAttribute {
                format,
                offset: std::mem::size_of::<Vertex>() as u64,
                shader_location: 5,
            },
        ]
    }

    pub const ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2];

    /// The vertex buffer layout every pipeline (surface, shadow map, NCS bake) uses.
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

impl Mesh {
    /// Vertex `i`'s position, normal and uv in float64 (the oracle and the bases' fitting).
    pub fn position_f64(&self, i: u32) -> DVec3 {
        DVec3::from(self.positions[i as usize].map(f64::from))
    }
    pub fn normal_f64(&self, i: u32) -> DVec3 {
        DVec3::from(self.normals[i as usize].map(f64::from))
    }
    pub fn uv_f64(&self, i: u32) -> DVec2 {
        DVec2::from(self.uvs[i as usize].map(f64::from))
    }

    /// Build a mesh from arrays, validating them and computing the tangent bases (pomkit's)
    /// and the uv scales when `tangents` is None.
    pub fn from_arrays(
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        uvs: Vec<[f32; 2]>,
        indices: Vec<u32>,
        tangents: Option<Vec<[f32; 4]>>,
    ) -> Result<(Self, BasisReport)> {
        let bases = tangents.map_or(TangentBases::Pomkit, TangentBases::Given);
        Self::from_arrays_with(positions, normals, uvs, indices, bases)
    }

    /// Build a mesh from arrays, validating them, with the tangent bases `bases` says.
    pub fn from_arrays_with(
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        uvs: Vec<[f32; 2]>,
        indices: Vec<u32>,
        bases: TangentBases,
    ) -> Result<(Self, BasisReport)> {
        let n = positions.len();
        if n == 0 {
            return Err(Error::arg("positions", "the mesh has no vertices"));
        }
        if normals.len() != n {
            return Err(Error::arg(
                "normals",
                format!(
                    "expected {n} normals (one per position), got {}",
                    normals.len()
                ),
            ));
        }
        if uvs.len() != n {
            return Err(Error::arg(
                "uvs",
                format!("expected {n} uvs (one per position), got {}", uvs.len()),
            ));
        }
        if indices.is_empty() || indices.len() % 3 != 0 {
            return Err(Error::arg(
                "indices",
                format!(
                    "need a non-empty multiple of 3 indices, got {}",
                    indices.len()
                ),
            ));
        }
        if let Some(i) = indices.iter().find(|i| **i as usize >= n) {
            return Err(Error::arg(
                "indices",
                format!("index {i} is out of range for {n} vertices"),
            ));
        }
        if positions.iter().flatten().any(|x| !x.is_finite()) {
            return Err(Error::arg("positions", "contain NaN or Inf"));
        }
        if uvs.iter().flatten().any(|x| !x.is_finite()) {
            return Err(Error::arg("uvs", "contain NaN or Inf"));
        }
        let mut normals = normals;
        normals::apply(
            normals::NormalsMode::File,
            &positions,
            &mut normals,
            &indices,
            "",
        )?;
        if let TangentBases::Given(t) = &bases {
            if t.len() != n {
                return Err(Error::arg(
                    "tangents",
                    format!("expected {n} tangents, got {}", t.len()),
                ));
            }
            if t.iter().flatten().any(|x| !x.is_finite()) {
                return Err(Error::arg("tangents", "contain NaN or Inf"));
            }
        }
        let mut mesh = Mesh {
            positions,
            normals,
            uvs,
            indices,
            ..Default::default()
        };
        // counter-clockwise seen from where the normals point: the pipeline culls back faces
        mesh.orient_outward();
        let report = match bases {
            TangentBases::Given(t) => mesh.compute_bases(Some(t))?,
            TangentBases::Pomkit => mesh.compute_bases(None)?,
            TangentBases::MikkTSpace => {
                let report = mesh.compute_bases(None)?;
                let mikk = mikktspace::mikktspace(
                    &mesh.positions,
                    &mesh.normals,
                    &mesh.uvs,
                    &mesh.indices,
                );
                for (t, m) in mesh.tangents.iter_mut().zip(mikk) {
                    if let Some(m) = m {
                        *t = m;
                    }
                }
                report
            }
        };
        Ok((mesh, report))
    }

    pub fn validate(&self) -> Result<()> {
        let n = self.positions.len();
        if n == 0 || self.indices.is_empty() {
            return Err(Error::arg("mesh", "the mesh is empty"));
        }
        if self.normals.len() != n
            || self.uvs.len() != n
            || self.tangents.len() != n
            || self.uv_scale.len() != n
        {
            return Err(Error::arg("mesh", "per-vertex arrays differ in length"));
        }
        if self.indices.iter().any(|i| *i as usize >= n) {
            return Err(Error::arg("indices", "index out of range"));
        }
        Ok(())
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Tangents (unless given) and uv scales from the per-triangle dP/du, dP/dv, accumulated
    /// per vertex weighted by triangle area. Triangles with degenerate uvs are skipped; vertices
    /// they alone touch get a fallback basis. A mesh where every triangle is degenerate has no
    /// usable uvs and is an error.
    pub fn compute_bases(&mut self, given: Option<Vec<[f32; 4]>>) -> Result<BasisReport> {
        let n = self.positions.len();
        let mut t_acc = vec![DVec3::ZERO; n];
        let mut b_acc = vec![DVec3::ZERO; n];
        let mut su = vec![0.0f64; n];
        let mut sv = vec![0.0f64; n];
        let mut wsum = vec![0.0f64; n];
        let mut report = BasisReport::default();
        let p = |i: u32| self.position_f64(i);
        let t = |i: u32| self.uv_f64(i);
        let mut all_scale = 0.0;
        let mut all_w = 0.0;
        for tri in self.indices.chunks_exact(3) {
            let (p0, p1, p2) = (p(tri[0]), p(tri[1]), p(tri[2]));
            let (t0, t1, t2) = (t(tri[0]), t(tri[1]), t(tri[2]));
            let e1 = p1 - p0;
            let e2 = p2 - p0;
            let d1 = t1 - t0;
            let d2 = t2 - t0;
            let area = e1.cross(e2).length() * 0.5;
            if area <= 0.0 {
                continue; // degenerate in space: contributes nothing
            }
            let Some((dpdu, dpdv)) = uv_derivatives(e1, e2, d1, d2) else {
                report.degenerate_uv_triangles += 1;
                continue;
            };
            for &i in tri {
                let i = i as usize;
                t_acc[i] += dpdu * area;
                b_acc[i] += dpdv * area;
                su[i] += dpdu.length() * area;
                sv[i] += dpdv.length() * area;
                wsum[i] += area;
            }
            all_scale += (dpdu.length() + dpdv.length()) * 0.5 * area;
            all_w += area;
        }
        if all_w <= 0.0 {
            return Err(Error::arg(
                "uvs",
                "the mesh has no usable uvs: every triangle's uvs are degenerate (zero uv area); give the mesh a parameterisation",
            ));
        }
        let fallback_scale = all_scale / all_w;
        let mut tangents = Vec::with_capacity(n);
        let mut scales = Vec::with_capacity(n);
        for i in 0..n {
            let nn = {
                let a = self.normals[i];
                DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64).normalize()
            };
            if wsum[i] > 0.0 {
                scales.push([(su[i] / wsum[i]) as f32, (sv[i] / wsum[i]) as f32]);
                let tv = t_acc[i] - nn * nn.dot(t_acc[i]);
                let tang = if tv.length() > 1e-12 {
                    tv.normalize()
                } else {
                    any_orthogonal(nn)
                };
                let w = if nn.cross(tang).dot(b_acc[i]) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                tangents.push([tang.x as f32, tang.y as f32, tang.z as f32, w as f32]);
            } else {
                report.fallback_vertices += 1;
                scales.push([fallback_scale as f32; 2]);
                let tang = any_orthogonal(nn);
                tangents.push([tang.x as f32, tang.y as f32, tang.z as f32, 1.0]);
            }
        }
        self.tangents = given.unwrap_or(tangents);
        self.uv_scale = scales;
        Ok(report)
    }

    pub fn vertices(&self) -> Vec<Vertex> {
        Vertex::interleave(
            &self.positions,
            &self.normals,
            &self.uvs,
            &self.tangents,
            &self.uv_scale,
        )
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in &self.positions {
            let v = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            lo = lo.min(v);
            hi = hi.max(v);
        }
        (lo, hi)
    }

    fn from_grid(nu: u32, nv: u32, f: impl Fn(f64, f64) -> (DVec3, DVec3)) -> Mesh {
        // (nu + 1) x (nv + 1) vertices; a seam duplicates vertices so that uvs stay continuous
        let mut m = Mesh::default();
        for j in 0..=nv {
            for i in 0..=nu {
                let u = i as f64 / nu as f64;
                let v = j as f64 / nv as f64;
                let (p, n) = f(u, v);
                m.positions.push([p.x as f32, p.y as f32, p.z as f32]);
                let n = n.normalize();
                m.normals.push([n.x as f32, n.y as f32, n.z as f32]);
                m.uvs.push([u as f32, v as f32]);
            }
        }
        let row = nu + 1;
        for j in 0..nv {
            for i in 0..nu {
                let a = j * row + i;
                let b = a + 1;
                let c = a + row;
                let d = c + 1;
                m.indices.extend_from_slice(&[a, c, b, b, c, d]);
            }
        }
        m.orient_outward();
        m.compute_bases(None).expect("generated meshes have uvs");
        m.charts = vec![[nu, nv, 0]];
        m
    }

    /// Whether triangle `t`'s winding disagrees with its vertex normals: its counter-clockwise
    /// geometric normal points away from the sum of its corners' normals.
    pub fn wound_against_normals(&self, t: usize) -> bool {
        let c = [0, 1, 2].map(|k| self.indices[3 * t + k]);
        let geo = (self.position_f64(c[1]) - self.position_f64(c[0]))
            .cross(self.position_f64(c[2]) - self.position_f64(c[0]));
        let ns = c.iter().fold(DVec3::ZERO, |acc, &i| acc + self.normal_f64(i));
        geo.dot(ns) < 0.0
    }

    /// Flip triangle winding where it disagrees with the vertex normals (counter-clockwise
    /// seen from the side the normals point to).
    pub fn orient_outward(&mut self) {
        for t in 0..self.indices.len() / 3 {
            if self.wound_against_normals(t) {
                self.indices.swap(3 * t + 1, 3 * t + 2);
            }
        }
    }

    /// Plane in XZ at y = 0, normal +Y, u along +X, v along +Z, `size` on a side.
    pub fn plane(size: f64, segments: u32) -> Result<Mesh> {
        if !(size.is_finite() && size > 0.0) {
            return Err(Error::arg("size", format!("must be > 0, got {size}")));
        }
        let s = segments.max(1);
        Ok(Self::from_grid(s, s, |u, v| {
            (
                DVec3::new((u - 0.5) * size, 0.0, (v - 0.5) * size),
                DVec3::Y,
            )
        }))
    }

    /// UV sphere of `radius`: u = longitude / 2pi (from +X toward -Z... around +Y), v = polar
    /// angle / pi from the north pole (+Y, v = 0) to the south pole (v = 1). Poles are rows of
    /// coincident vertices and u = 0 / u = 1 is a seam of duplicated vertices.
    pub fn sphere(radius: f64, segments: u32, rings: u32) -> Result<Mesh> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(Error::arg("radius", format!("must be > 0, got {radius}")));
        }
        Ok(Self::from_grid(segments.max(3), rings.max(2), |u, v| {
            let phi = 2.0 * PI * u;
            let th = PI * v;
            let n = DVec3::new(th.sin() * phi.cos(), th.cos(), -th.sin() * phi.sin());
            (n * radius, n)
        }))
    }

    /// Torus around +Y with major radius `major` and tube radius `minor`: u = angle around the
    /// axis / 2pi, v = angle around the tube / 2pi (v = 0 on the outer equator, rising toward
    /// +Y). Continuous and periodic in both.
    pub fn torus(major: f64, minor: f64, segments: u32, tube_segments: u32) -> Result<Mesh> {
        if !(major.is_finite() && minor.is_finite() && minor > 0.0 && major > minor) {
            return Err(Error::arg(
                "minor",
                format!("need major > minor > 0, got major={major}, minor={minor}"),
            ));
        }
        Ok(Self::from_grid(
            segments.max(3),
            tube_segments.max(3),
            |u, v| {
                let phi = 2.0 * PI * u;
                let th = 2.0 * PI * v;
                let radial = DVec3::new(phi.cos(), 0.0, -phi.sin());
                let n = radial * th.cos() + DVec3::Y * th.sin();
                (radial * major + n * minor, n)
            },
        ))
    }

    /// Open cylinder (no caps) around +Y, centred at the origin: u = angle / 2pi, v from the
    /// top (v = 0, y = height/2) to the bottom (v = 1).
    pub fn cylinder(radius: f64, height: f64, segments: u32, rings: u32) -> Result<Mesh> {
        if !(radius.is_finite() && radius > 0.0 && height.is_finite() && height > 0.0) {
            return Err(Error::arg("radius", "radius and height must be > 0"));
        }
        Ok(Self::from_grid(segments.max(3), rings.max(1), |u, v| {
            let phi = 2.0 * PI * u;
            let n = DVec3::new(phi.cos(), 0.0, -phi.sin());
            (n * radius + DVec3::Y * (height * (0.5 - v)), n)
        }))
    }

    /// Cube of edge `size` centred at the origin; each face carries the whole uv square, with
    /// v growing downward as seen from outside (row 0 of the map at the top of each side face).
    pub fn cube(size: f64, segments: u32) -> Result<Mesh> {
        if !(size.is_finite() && size > 0.0) {
            return Err(Error::arg("size", format!("must be > 0, got {size}")));
        }
        let h = size * 0.5;
        let faces: [(DVec3, DVec3, DVec3); 6] = [
            // (normal, u direction, v direction)
            (DVec3::X, -DVec3::Z, -DVec3::Y),
            (-DVec3::X, DVec3::Z, -DVec3::Y),
            (DVec3::Y, DVec3::X, DVec3::Z),
            (-DVec3::Y, DVec3::X, -DVec3::Z),
            (DVec3::Z, DVec3::X, -DVec3::Y),
            (-DVec3::Z, -DVec3::X, -DVec3::Y),
        ];
        let mut out = Mesh::default();
        for (n, du, dv) in faces {
            let f = Self::from_grid(segments.max(1), segments.max(1), |u, v| {
                (n * h + du * ((u - 0.5) * size) + dv * ((v - 0.5) * size), n)
            });
            let base = out.positions.len() as u32;
            out.charts.push([f.charts[0][0], f.charts[0][1], base]);
            out.positions.extend(f.positions);
            out.normals.extend(f.normals);
            out.uvs.extend(f.uvs);
            out.indices.extend(f.indices.iter().map(|i| i + base));
        }
        out.compute_bases(None)?;
        Ok(out)
    }
}

/// dP/du and dP/dv of a triangle with edges e1, e2 and uv edges d1, d2 (exact for its affine
/// map), or None when its uvs are degenerate.
pub fn uv_derivatives(e1: DVec3, e2: DVec3, d1: DVec2, d2: DVec2) -> Option<(DVec3, DVec3)> {
    let det = d1.x * d2.y - d2.x * d1.y;
    if det.abs() < 1e-14 * (1.0 + d1.length_squared() + d2.length_squared()) {
        return None;
    }
    Some(((e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det))
}

fn any_orthogonal(n: DVec3) -> DVec3 {
    let a = if n.x.abs() > 0.9 { DVec3::Z } else { DVec3::X };
    n.cross(a).normalize()
}

#[cfg(test)]
mod tests;

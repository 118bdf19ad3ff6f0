//! Prism POM (Dachsbacher & Tatarchuk 2007): each base triangle extruded along its vertex
//! normals into a prism (top, bottom and three side slabs of two triangles each, wound outward),
//! built once per (mesh, depth, shell direction) on the CPU.

use crate::mesh::{Mesh, Vertex};
use crate::scene::HeightMap;
use glam::{DVec2, DVec3};

/// A prism corner: the shared vertex (`pomkit::vertex::VertexIn`, locations 0-4) and its height
/// coordinate (location 5).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PrismVertex {
    pub vertex: Vertex,
    /// height coordinate of this corner: 1 on the top, 0 on the bottom
    pub h: f32,
}

impl PrismVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 6] = {
        let v = Vertex::ATTRIBUTES;
        [
            v[0],
            v[1],
            v[2],
            v[3],
            v[4],
            wgpu::VertexAttribute {
                format: wgpu::VertexFormat::Float32,
                offset: std::mem::size_of::<Vertex>() as u64,
                shader_location: 5,
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

/// Per prism, for the fragment shader's exit computation: the six corners (top 0..3, bottom
/// 0..3, w unused), the three uvs, and x = the highest height under the triangle's uv box.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PrismData {
    pub top: [[f32; 4]; 3],
    pub bottom: [[f32; 4]; 3],
    pub uv: [[f32; 4]; 3],
    pub meta: [f32; 4],
}

pub const VERTICES_PER_PRISM: u32 = 24;

/// The prisms of `mesh`: inward (top = base surface at h = 1, bottom `depth` below, pomkit's
/// convention) or outward (bottom = base surface, top `depth` above along the normals: the
/// paper's set-up, where features rise above the base mesh).
pub fn build(
    mesh: &Mesh,
    depth: f32,
    outward: bool,
    height: &HeightMap,
    tiling: f32,
) -> (Vec<PrismVertex>, Vec<PrismData>) {
    let mut verts = Vec::with_capacity(mesh.indices.len() / 3 * VERTICES_PER_PRISM as usize);
    let mut data = Vec::with_capacity(mesh.indices.len() / 3);
    let d = depth as f64;
    for tri in mesh.indices.chunks_exact(3) {
        let p = |i: u32| DVec3::from_array(mesh.positions[i as usize].map(|x| x as f64));
        let n = |i: u32| {
            DVec3::from_array(mesh.normals[i as usize].map(|x| x as f64)).normalize_or_zero()
        };
        let (top, bot): (Vec<DVec3>, Vec<DVec3>) = if outward {
            (
                tri.iter().map(|&i| p(i) + n(i) * d).collect(),
                tri.iter().map(|&i| p(i)).collect(),
            )
        } else {
            (
                tri.iter().map(|&i| p(i)).collect(),
                tri.iter().map(|&i| p(i) - n(i) * d).collect(),
            )
        };
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
                h: if on_top { 1.0 } else { 0.0 },
            }
        };
        let mut push_tri = |a: PrismVertex, b: PrismVertex, c: PrismVertex| {
            let pa = DVec3::from_array(a.vertex.position.map(|x| x as f64));
            let pb = DVec3::from_array(b.vertex.position.map(|x| x as f64));
            let pc = DVec3::from_array(c.vertex.position.map(|x| x as f64));
            let g = (pb - pa).cross(pc - pa);
            // outward: the face's normal points away from the prism's centre
            if g.dot((pa + pb + pc) / 3.0 - centre) >= 0.0 {
                verts.extend_from_slice(&[a, b, c]);
            } else {
                verts.extend_from_slice(&[a, c, b]);
            }
        };
        push_tri(corner(0, true), corner(1, true), corner(2, true));
        push_tri(corner(0, false), corner(1, false), corner(2, false));
        for k in 0..3 {
            let j = (k + 1) % 3;
            // each slab as two triangles, split along one diagonal
            push_tri(corner(k, true), corner(j, true), corner(j, false));
            push_tri(corner(k, true), corner(j, false), corner(k, false));
        }
        // the highest height in the triangle's uv box (early rejection of empty prisms)
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
        let mut mx = 0.0f64;
        if (x1 - x0) * (y1 - y0) > (height.width as i64 * height.height as i64) {
            mx = 1.0;
        } else {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    mx = mx.max(height.texel(x, y));
                }
            }
        }
        let v4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
        data.push(PrismData {
            top: [v4(top[0]), v4(top[1]), v4(top[2])],
            bottom: [v4(bot[0]), v4(bot[1]), v4(bot[2])],
            uv: [0, 1, 2].map(|k| {
                let u = mesh.uvs[tri[k] as usize];
                [u[0], u[1], 0.0, 0.0]
            }),
            meta: [mx as f32, 0.0, 0.0, 0.0],
        });
    }
    (verts, data)
}

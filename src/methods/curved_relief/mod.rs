//! Curved relief mapping (Oliveira & Policarpo 2005), one of the two baselines of Chen & Chang
//! 2008 (the NCS paper): curved_relief.wgsl, on the base mesh with per-vertex quadric
//! coefficients (quadrics.rs) as the method's own vertex attribute (VERTEX_EXTRA).
mod quadrics;

use super::{check_range, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::{Geometry, GpuMesh, MethodGeometry};
use crate::error::Result;
use crate::gpu::Context;
use crate::mesh::Vertex;
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;

pub use quadrics::fit as fit_quadrics;

crate::params! {
    pub struct CurvedRelief {
        pub linear_steps: u32,
        pub binary_steps: u32,
    }
}

/// The base mesh with its quadric coefficients (a, b, 0, 0) at location 5.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct QuadricVertex {
    vertex: Vertex,
    quadric: [f32; 4],
}

const ATTRIBUTES: [wgpu::VertexAttribute; 6] =
    Vertex::with_location5(wgpu::VertexFormat::Float32x4);

#[derive(Debug)]
pub struct QuadricMesh;

impl MethodGeometry for QuadricMesh {
    fn key(&self, object: &Object) -> u64 {
        hash_bytes(&[b"quadric mesh", &object.mesh.key.to_le_bytes()])
    }
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh> {
        let mesh = &object.mesh;
        let q = quadrics::fit(mesh);
        let verts: Vec<QuadricVertex> = mesh
            .vertices()
            .into_iter()
            .zip(q)
            .map(|(vertex, [a, b])| QuadricVertex {
                vertex,
                quadric: [a, b, 0.0, 0.0],
            })
            .collect();
        ctx.scoped(|| {
            Ok(GpuMesh {
                vbuf: ctx.upload(
                    "quadric vertices",
                    bytemuck::cast_slice(&verts),
                    wgpu::BufferUsages::VERTEX,
                ),
                ibuf: Some(ctx.upload(
                    "indices",
                    bytemuck::cast_slice(&mesh.indices),
                    wgpu::BufferUsages::INDEX,
                )),
                count: mesh.indices.len() as u32,
                extra: Vec::new(),
            })
        })
    }
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<QuadricVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRIBUTES,
        }
    }
}

impl Unit for CurvedRelief {
    fn examples() -> Vec<Self> {
        vec![CurvedRelief {
            linear_steps: 32,
            binary_steps: 6,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("curved_relief");
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("linear_steps", self.linear_steps as f32),
                ("binary_steps", self.binary_steps as f32),
            ],
        );
        s.defs.push("VERTEX_EXTRA");
        s.geometry = Geometry::Own(Arc::new(QuadricMesh));
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("linear_steps", self.linear_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)
    }
}

//! Prism POM (Dachsbacher & Tatarchuk 2007): a pass of its own (prism.wgsl) over the prisms
//! the method extrudes from the base mesh (prisms.rs): its own geometry (the shell's boundary
//! faces) and its own resource (the per-prism data the walk reads, a texture at group 2,
//! binding 1).
pub mod prisms;

/// GPU bytes of one prism's data (its texels in the prism texture).
pub const PRISM_BYTES: usize = prisms::TEXELS_PER_PRISM as usize * 16;
/// GPU bytes of one vertex of the shell's boundary faces.
pub const PRISM_VERTEX_BYTES: usize = std::mem::size_of::<prisms::PrismVertex>();

use crate::contract::{check_range, Geometry, Pass, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::contract::{GeometryData, GpuMesh, MethodGeometry, Resident, ResourceKind};
use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;

/// The prisms of an object's base mesh, inward or outward: the boundary faces to draw, with the
/// per-prism data built beside them (`GpuMesh::extra[0]`).
#[derive(Debug, Clone, Copy)]
pub struct PrismShell {
    pub outward: bool,
    pub tight: bool,
}

impl MethodGeometry for PrismShell {
    fn key(&self, object: &Object) -> u64 {
        let m = &object.material;
        hash_bytes(&[
            b"prisms",
            &object.mesh.key.to_le_bytes(),
            &m.height.key.to_le_bytes(),
            &m.depth.to_le_bytes(),
            &m.tiling.to_le_bytes(),
            &[self.outward as u8, self.tight as u8],
        ])
    }
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh> {
        let (mesh, m) = (&object.mesh, &object.material);
        let prisms::Prisms {
            vertices: verts,
            data,
        } = prisms::build(mesh, m.depth, self.outward, self.tight, &m.height, m.tiling);
        let vbytes = std::mem::size_of_val(verts.as_slice()) as u64;
        let max_dim = ctx.limits.max_texture_dimension_2d;
        let texels = prisms::texels(&data, max_dim);
        let (texels, size) = match texels {
            Ok(t) if vbytes <= ctx.limits.max_buffer_size => t,
            r => {
                let most = r.err().unwrap_or(data.len());
                return Err(Error::limit(
                    "mesh",
                    format!(
                        "the prisms of {} triangles need {vbytes} bytes of vertices and a prism texture of {} texels a prism; the device takes max_buffer_size = {} and textures up to {max_dim} texels a side (at most {most} prisms); render a mesh with fewer triangles (split it into several pk.Object, or decimate it)",
                        mesh.indices.len() / 3,
                        prisms::TEXELS_PER_PRISM,
                        ctx.limits.max_buffer_size,
                    ),
                ));
            }
        };
        ctx.scoped(|| {
            let vbuf = ctx.upload(
                "prism vertices",
                bytemuck::cast_slice(&verts),
                wgpu::BufferUsages::VERTEX,
            );
            let tex = ctx.texture_2d(
                "prisms",
                size,
                wgpu::TextureFormat::Rgba32Uint,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            );
            crate::gpu::texels::write_texels(ctx, &tex, bytemuck::cast_slice(&texels), size, 16);
            Ok(GpuMesh {
                vbuf,
                ibuf: None,
                count: verts.len() as u32,
                extra: vec![Resident::Texture(tex.create_view(&Default::default()))],
            })
        })
    }
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static> {
        prisms::PrismVertex::layout()
    }
    fn shadow_cull_back(&self) -> bool {
        // the prisms' walks start where the light enters the shell
        true
    }
}

crate::params! {
    pub struct Prism {
        pub min_steps: u32,
        pub max_steps: u32,
        /// the shell above the base mesh (the paper's set-up) instead of below it
        pub outward: bool,
        /// march each segment with the max-mip traversal
        pub exact: bool,
        /// each vertical edge's top at the highest height beside it, not at the full depth
        pub tight: bool,
    }
}

impl Unit for Prism {
    fn examples() -> Vec<Self> {
        vec![Prism {
            min_steps: 8,
            max_steps: 50,
            outward: false,
            exact: false,
            tight: true,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let shader = crate::method_shader!("prism");
        let mut s = Spec::surface(
            shader.clone(),
            o,
            &[
                ("min_steps", self.min_steps as f32),
                ("max_steps", self.max_steps as f32),
            ],
        );
        s.pass = Pass::Own {
            shader,
            vs: "vs_prism",
            fs: "fs_prism",
            shadow_vs: "vs_prism_shadow",
            shadow_fs: "fs_prism_shadow",
        };
        s.defs.clear();
        s.defs.push("PRISM_CORNER");
        if self.exact {
            s.defs.push("PRISM_EXACT");
        }
        let shell = PrismShell {
            outward: self.outward,
            tight: self.tight,
        };
        s.geometry = Geometry::Own(Arc::new(shell));
        // the per-prism data (`prism_tex` in prism.wgsl), made with the shell
        s.resources = Some(Arc::new(GeometryData {
            geometry: shell,
            kind: ResourceKind::TextureUint,
            what: "prism data",
        }));
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("min_steps", self.min_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)
    }
}

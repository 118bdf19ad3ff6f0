//! The displaced mesh itself (Chen & Chang 2008's "ground truth model"), rasterised by the
//! surface pass and shaded the same way; shadows from a shadow map of itself. Its geometry is
//! its own: the tessellation of the displaced surface (tessellate.rs; meshes from arrays in
//! welded.rs), built on the CPU.
mod samples;
pub mod tessellate;
mod welded;

use crate::contract::{Geometry, PerPixel, Shadows, Spec, Unit};
use crate::contract::{GpuMesh, MethodGeometry};
use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::mesh::Vertex;
use crate::scene::{hash_bytes, Object};
use std::sync::Arc;
pub use tessellate::Pattern;

/// The displaced mesh on a lattice `texels_per_vertex` texels apart, with the base mesh's basis per
/// vertex (Tessellated shades with the height field's normal).
#[derive(Debug)]
pub struct DisplacedMesh {
    pub texels_per_vertex: f64,
    pub pattern: Pattern,
}

impl MethodGeometry for DisplacedMesh {
    fn key(&self, object: &Object) -> u64 {
        let m = &object.material;
        hash_bytes(&[
            &object.mesh.key.to_le_bytes(),
            &m.height.key.to_le_bytes(),
            &m.depth.to_le_bytes(),
            &m.tiling.to_le_bytes(),
            &self.texels_per_vertex.to_le_bytes(),
            self.pattern.name().as_bytes(),
        ])
    }
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh> {
        let t = tessellate::tessellate(
            &object.mesh,
            &object.material,
            self.texels_per_vertex,
            self.pattern,
        )?;
        let v = Vertex::interleave(
            &t.positions,
            &t.base_normals,
            &t.uvs,
            &t.tangents,
            &t.uv_scale,
        );
        GpuMesh::upload_indexed(ctx, &v, &t.indices, "texels_per_vertex")
    }
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static> {
        Vertex::layout()
    }
}

crate::params! {
    pub struct Tessellated {
        pub texels_per_vertex: f64,
        /// how each lattice quad is cut into triangles
        pub pattern: Pattern,
        /// None, Hard (the shadow map) or Exact
        pub shadows: Shadows,
    }
}

impl Unit for Tessellated {
    fn examples() -> Vec<Self> {
        vec![
            Tessellated {
                texels_per_vertex: 1.0,
                pattern: Pattern::Fan,
                shadows: Shadows::None,
            },
            Tessellated {
                texels_per_vertex: 1.0,
                pattern: Pattern::Grid,
                shadows: Shadows::Hard,
            },
            Tessellated {
                texels_per_vertex: 1.0,
                pattern: Pattern::Fan,
                shadows: Shadows::Exact,
            },
        ]
    }
    const PER_PIXEL: bool = false;
    fn spec(&self, _: &PerPixel) -> Spec {
        // exact shadows come with the reference's exact AO (shadows.wgsl's exact_ao)
        let ao_directions = if self.shadows == Shadows::Exact {
            64
        } else {
            0
        };
        let mut s = Spec::shade_only(
            crate::method_shader!("tessellated"),
            PerPixel {
                ao_directions,
                ..PerPixel::off().with_shadows(self.shadows)
            },
            Geometry::Own(Arc::new(DisplacedMesh {
                texels_per_vertex: self.texels_per_vertex,
                pattern: self.pattern,
            })),
        );
        s.shadow_map_self = self.shadows == Shadows::Hard;
        s.defs.push("MESH_SURFACE");
        s
    }
    fn validate(&self) -> Result<()> {
        if !(self.texels_per_vertex.is_finite()
            && (1.0 / 64.0..=1024.0).contains(&self.texels_per_vertex))
        {
            return Err(Error::arg(
                "texels_per_vertex",
                format!("must lie in [1/64, 1024], got {}", self.texels_per_vertex),
            ));
        }
        if !matches!(self.shadows, Shadows::None | Shadows::Hard | Shadows::Exact) {
            return Err(Error::arg(
                "shadows",
                "Tessellated has 'none', 'hard' (a shadow map of the displaced mesh) or 'exact' (the max-mip traversal from its points, and exact AO)",
            ));
        }
        Ok(())
    }
}

//! What the tessellations are made of: the displaced mesh with its base mesh's bases (`Tessellation`),
//! and the base mesh interpolated at a point (`BaseSample`).

use crate::mesh::Mesh;
use glam::{DVec2, DVec3};

/// The displaced surface plus, per vertex, the base mesh's basis it was displaced from (for the
/// tessellated GPU reference, which shades with the base mesh's basis like the per-pixel methods).
#[derive(Clone, Debug, Default)]
pub struct Tessellation {
    pub positions: Vec<[f32; 3]>,
    /// shading normals of the displaced surface, from the height field's central differences
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub indices: Vec<u32>,
    /// the base mesh's point each vertex was displaced from
    pub base_positions: Vec<[f32; 3]>,
    pub base_normals: Vec<[f32; 3]>,
    pub tangents: Vec<[f32; 4]>,
    pub uv_scale: Vec<[f32; 2]>,
}

#[derive(Clone, Copy)]
pub(super) struct BaseSample {
    pub p: DVec3,
    pub n: DVec3,
    pub t: DVec3,
    pub w: f64,
    pub scale: DVec2,
}

pub(super) fn v3(a: [f32; 3]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

pub(super) fn lerp_vertex(m: &Mesh, ws: [(usize, f64); 3]) -> BaseSample {
    let mut p = DVec3::ZERO;
    let mut n = DVec3::ZERO;
    let mut t = DVec3::ZERO;
    let mut s = DVec2::ZERO;
    for (i, w) in ws {
        p += v3(m.positions[i]) * w;
        n += v3(m.normals[i]) * w;
        let tg = m.tangents[i];
        t += DVec3::new(tg[0] as f64, tg[1] as f64, tg[2] as f64) * w;
        s += DVec2::new(m.uv_scale[i][0] as f64, m.uv_scale[i][1] as f64) * w;
    }
    BaseSample {
        p,
        n: n.normalize_or_zero(),
        t,
        w: m.tangents[ws[0].0][3] as f64,
        scale: s,
    }
}

//! What stays resident on the GPU between renders, keyed by content: height maps (with their
//! pyramids), albedos, meshes (the base mesh, or a method's own geometry) and methods' own
//! resources. Each cache is bounded (least recently used goes first) and can be re-keyed in
//! place (`update_height`).

use crate::contract::{BuildInputs, Geometry, GpuMesh, MethodResources, Resident};
use crate::error::Result;
use crate::gpu::Context;
use super::mip_builder::MipBuilder;
use crate::heightmap::{mip_count, pyramid, GpuHeight};
use crate::mesh::borders::{contacts, open_borders, Border, Contacts, Part};
use crate::mesh::topology::Topology;
use crate::scene::{Albedo, HeightMap, Keyed, Object};
use std::sync::Arc;

/// A bounded cache, most recently used last.
pub struct Cached<T> {
    entries: Vec<(u64, Arc<T>)>,
    cap: usize,
}

impl<T> Cached<T> {
    pub fn new(cap: usize) -> Self {
        Self {
            entries: Vec::new(),
            cap,
        }
    }
    pub fn get_or(&mut self, key: u64, make: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
        if let Some(pos) = self.entries.iter().position(|(k, _)| *k == key) {
            let e = self.entries.remove(pos);
            let v = e.1.clone();
            self.entries.push(e);
            return Ok(v);
        }
        let v = Arc::new(make()?);
        self.entries.push((key, v.clone()));
        while self.entries.len() > self.cap {
            self.entries.remove(0);
        }
        Ok(v)
    }
    pub fn get(&self, key: u64) -> Option<Arc<T>> {
        self.entries
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.clone())
    }
    /// The entry under `old` now answers to `new` (its contents were updated in place).
    pub fn rekey(&mut self, old: u64, new: u64) -> bool {
        match self.entries.iter_mut().find(|(k, _)| *k == old) {
            Some(e) => {
                e.0 = new;
                true
            }
            None => false,
        }
    }
    /// Drop an entry (it is rebuilt on its next use).
    pub fn remove(&mut self, key: u64) {
        self.entries.retain(|(k, _)| *k != key);
    }
}

pub struct Resources {
    pub heights: Cached<GpuHeight>,
    pub albedos: Cached<wgpu::TextureView>,
    pub meshes: Cached<GpuMesh>,
    /// methods' own resources, keyed as each method says
    pub method: Cached<Vec<Resident>>,
    /// meshes' open borders (by mesh key), for the objects' contacts
    pub borders: Cached<Vec<Border>>,
}

impl Resources {
    pub fn new() -> Self {
        Resources {
            heights: Cached::new(8),
            albedos: Cached::new(8),
            meshes: Cached::new(8),
            method: Cached::new(8),
            borders: Cached::new(64),
        }
    }

    /// Each object's contacts (`mesh::borders::contacts`), its mesh's borders found once.
    pub fn contacts(&mut self, objects: &[Object]) -> Result<Vec<Contacts>> {
        let mut parts = Vec::with_capacity(objects.len());
        for o in objects {
            let borders = self.borders.get_or(o.mesh.key, || {
                Ok(open_borders(&o.mesh, &Topology::quantised(&o.mesh)))
            })?;
            parts.push(Part {
                borders,
                bounds: o.mesh.bounds(),
                to_world: o.transform.m,
            });
        }
        Ok(contacts(&parts))
    }

    pub fn height(
        &mut self,
        ctx: &Context,
        mips: &MipBuilder,
        map: &Keyed<HeightMap>,
    ) -> Result<Arc<GpuHeight>> {
        self.heights.get_or(map.key, || mips.create(ctx, map))
    }

    /// The albedo with its box-filtered mips, as half floats (filterable on every adapter).
    pub fn albedo(
        &mut self,
        ctx: &Context,
        albedo: Option<&Keyed<Albedo>>,
    ) -> Result<Arc<wgpu::TextureView>> {
        let grey = Albedo {
            width: 1,
            height: 1,
            data: vec![[0.5, 0.5, 0.5, 1.0]],
        };
        let (a, key) = match albedo {
            Some(k) => (&**k, k.key),
            None => (&grey, 0),
        };
        self.albedos.get_or(key, || {
            let levels = pyramid(a.width, a.height, a.data.clone(), |q| {
                std::array::from_fn(|c| (q[0][c] + q[1][c] + q[2][c] + q[3][c]) * 0.25)
            });
            let bits: Vec<u16> = levels
                .iter()
                .flatten()
                .flat_map(|p| p.map(f16_bits))
                .collect();
            ctx.scoped(|| {
                use wgpu::util::DeviceExt;
                let tex = ctx.device.create_texture_with_data(
                    &ctx.queue,
                    &wgpu::TextureDescriptor {
                        label: Some("albedo"),
                        size: wgpu::Extent3d {
                            width: a.width,
                            height: a.height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: mip_count(a.width, a.height),
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::Rgba16Float,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    bytemuck::cast_slice(&bits),
                );
                Ok(tex.create_view(&Default::default()))
            })
        })
    }

    /// The mesh a method's geometry asks for: the base mesh, or the method's own (built by it).
    pub fn mesh(
        &mut self,
        ctx: &Context,
        object: &Object,
        geometry: &Geometry,
    ) -> Result<Arc<GpuMesh>> {
        match geometry {
            Geometry::Base => self.meshes.get_or(object.mesh.key, || {
                GpuMesh::upload_indexed(ctx, &object.mesh.vertices(), &object.mesh.indices, "mesh")
            }),
            Geometry::Own(g) => self.meshes.get_or(g.key(object), || g.build(ctx, object)),
        }
    }

    /// A method's own resources for one object, built by the method on first use.
    pub fn method(
        &mut self,
        resources: &dyn MethodResources,
        inputs: &BuildInputs<'_>,
    ) -> Result<Arc<Vec<Resident>>> {
        self.method
            .get_or(resources.key(inputs.object), || resources.build(inputs))
    }
}

/// f32 -> IEEE half (round to nearest even), for the albedo texture.
pub fn f16_bits(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = ((b >> 16) & 0x8000) as u16;
    let exp = ((b >> 23) & 0xff) as i32;
    let man = b & 0x7f_ffff;
    if exp == 255 {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 31 {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rem = m & ((1u32 << shift) - 1);
        let mut r = m >> shift;
        if rem > half || (rem == half && (r & 1) == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let mut h = ((e as u32) << 10) | (man >> 13);
    let rem = man & 0x1fff;
    if rem > 0x1000 || (rem == 0x1000 && (h & 1) == 1) {
        h += 1;
    }
    sign | h as u16
}

#[cfg(test)]
mod tests {
    use super::f16_bits;
    #[test]
    fn half_floats() {
        assert_eq!(f16_bits(1.0), 0x3c00);
        assert_eq!(f16_bits(0.5), 0x3800);
        assert_eq!(f16_bits(0.0), 0);
        assert_eq!(f16_bits(65504.0), 0x7bff);
        assert_eq!(f16_bits(1e-7), 0x0002);
    }
}

/// One object's draw in a frame: its mesh, its object bind group (group 1) and its method bind
/// group (group 2).
pub struct Draw {
    pub mesh: std::sync::Arc<crate::contract::GpuMesh>,
    pub object: wgpu::BindGroup,
    pub method: wgpu::BindGroup,
}

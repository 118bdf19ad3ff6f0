//! What stays resident on the GPU between renders, keyed by content: height maps (with their
//! pyramids), albedos, meshes (base, tessellated, prisms) and NCS frame maps. Each cache is
//! bounded (least recently used goes first) and can be re-keyed in place (`update_height`).

use crate::conemap::{ConeBuilder, ConeMap, Cones};
use crate::contract::Geometry;
use crate::error::{Error, Result};
use crate::geometry::{prisms, tessellate::tessellate};
use crate::gpu::Context;
use crate::heightmap::{mip_count, pyramid, GpuHeight, MipBuilder};
use crate::mesh::Vertex;
use crate::scene::{hash_bytes, Albedo, HeightMap, Keyed, Object};
use crate::texspace::{FrameMaps, TexSpace};
use std::sync::Arc;

/// The cone cache's key of a height map's cones.
pub fn cone_key(height_key: u64, cones: Cones) -> u64 {
    hash_bytes(&[&height_key.to_le_bytes(), &[cones as u8]])
}

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

pub struct GpuMesh {
    pub vbuf: wgpu::Buffer,
    /// None: a non-indexed draw (prisms)
    pub ibuf: Option<wgpu::Buffer>,
    pub count: u32,
    /// Prism: the per-prism data the fragment shader reads
    pub prisms: Option<wgpu::Buffer>,
}

impl GpuMesh {
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vbuf.slice(..));
        match &self.ibuf {
            Some(ib) => {
                pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.count, 0, 0..1);
            }
            None => pass.draw(0..self.count, 0..1),
        }
    }
}

pub struct Resources {
    pub heights: Cached<GpuHeight>,
    pub albedos: Cached<wgpu::TextureView>,
    pub meshes: Cached<GpuMesh>,
    pub frame_maps: Cached<FrameMaps>,
    /// cone maps, keyed by the height map's key and the kind of cones
    pub cones: Cached<ConeMap>,
}

impl Resources {
    pub fn new() -> Self {
        Resources {
            heights: Cached::new(8),
            albedos: Cached::new(8),
            meshes: Cached::new(8),
            frame_maps: Cached::new(4),
            cones: Cached::new(8),
        }
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

    /// The mesh a method's geometry asks for: the base mesh, the displaced mesh (with the base
    /// frame per vertex) or the prisms.
    pub fn mesh(
        &mut self,
        ctx: &Context,
        object: &Object,
        geometry: Geometry,
    ) -> Result<Arc<GpuMesh>> {
        let (mesh, m) = (&object.mesh, &object.material);
        let base_key = mesh.key;
        match geometry {
            Geometry::Base => self.meshes.get_or(base_key, || {
                upload_indexed(ctx, &mesh.vertices(), &mesh.indices)
            }),
            Geometry::Tessellated { texels_per_vertex } => {
                let key = hash_bytes(&[
                    &base_key.to_le_bytes(),
                    &m.height.key.to_le_bytes(),
                    &m.depth.to_le_bytes(),
                    &m.tiling.to_le_bytes(),
                    &texels_per_vertex.to_le_bytes(),
                ]);
                self.meshes.get_or(key, || {
                    let t = tessellate(mesh, m, texels_per_vertex)?;
                    // the base frame per vertex: Tessellated shades with the height field's normal
                    let v = Vertex::interleave(
                        &t.positions,
                        &t.base_normals,
                        &t.uvs,
                        &t.tangents,
                        &t.uv_scale,
                    );
                    upload_indexed(ctx, &v, &t.indices)
                })
            }
            Geometry::Prisms { outward } => {
                let key = hash_bytes(&[
                    &base_key.to_le_bytes(),
                    &m.height.key.to_le_bytes(),
                    &m.depth.to_le_bytes(),
                    &m.tiling.to_le_bytes(),
                    &[outward as u8],
                ]);
                self.meshes.get_or(key, || {
                    let prisms::Prisms { vertices: verts, data } = prisms::build(mesh, m.depth, outward, &m.height, m.tiling);
                    let vbytes = std::mem::size_of_val(verts.as_slice()) as u64;
                    if vbytes > ctx.limits.max_buffer_size || std::mem::size_of_val(data.as_slice()) as u64 > ctx.limits.max_storage_buffer_binding_size as u64 {
                        return Err(Error::limit("mesh", format!("the prisms need {vbytes} bytes of vertices; over the device's buffer limits")));
                    }
                    ctx.scoped(|| {
                        let vbuf = ctx.upload("prism vertices", bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX);
                        let pbuf = ctx.upload("prisms", bytemuck::cast_slice(&data), wgpu::BufferUsages::STORAGE);
                        Ok(GpuMesh { vbuf, ibuf: None, count: verts.len() as u32, prisms: Some(pbuf) })
                    })
                })
            }
        }
    }

    /// The cone map of a resident height map.
    pub fn cone_map(
        &mut self,
        ctx: &Context,
        builder: &ConeBuilder,
        height: &GpuHeight,
        height_key: u64,
        cones: Cones,
    ) -> Result<Arc<ConeMap>> {
        self.cones.get_or(cone_key(height_key, cones), || {
            builder.build(ctx, height, cones)
        })
    }

    /// NCS's frame maps of the base mesh (`mesh` must be the base mesh's upload).
    pub fn frame_maps(
        &mut self,
        ctx: &Context,
        texspace: &TexSpace,
        mesh: &GpuMesh,
        base_key: u64,
    ) -> Result<Arc<FrameMaps>> {
        self.frame_maps.get_or(base_key, || {
            texspace.maps(
                ctx,
                &mesh.vbuf,
                mesh.ibuf.as_ref().expect("indexed"),
                mesh.count,
            )
        })
    }
}

fn upload_indexed(ctx: &Context, verts: &[Vertex], indices: &[u32]) -> Result<GpuMesh> {
    let vbytes = std::mem::size_of_val(verts) as u64;
    if vbytes > ctx.limits.max_buffer_size {
        return Err(Error::limit(
            "texels_per_vertex",
            format!(
                "the mesh needs a {vbytes}-byte vertex buffer; the device's max_buffer_size is {}",
                ctx.limits.max_buffer_size
            ),
        ));
    }
    ctx.scoped(|| {
        let vbuf = ctx.upload(
            "vertices",
            bytemuck::cast_slice(verts),
            wgpu::BufferUsages::VERTEX,
        );
        let ibuf = ctx.upload(
            "indices",
            bytemuck::cast_slice(indices),
            wgpu::BufferUsages::INDEX,
        );
        Ok(GpuMesh {
            vbuf,
            ibuf: Some(ibuf),
            count: indices.len() as u32,
            prisms: None,
        })
    })
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

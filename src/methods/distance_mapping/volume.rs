//! The distance volume's builder: one compute pass over the max pyramid (distance_volume.wgsl).

use crate::contract::{BuildInputs, Composer};
use crate::error::Result;
use crate::gpu::{Context, TableOut, TablePass, TableTarget};
use crate::heightmap::{level_size, max_atlas, top_maxmip_level};

pub const VOLUME_SHADER: &str = include_str!("distance_volume.wgsl");

/// How a map's volume is laid out: the max-pyramid level its voxels span, its size in voxels
/// and slices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub level: u32,
    pub size: (u32, u32),
    pub slices: u32,
}

impl Layout {
    /// The coarsest level at or below `max_voxels` a side whose nodes tile the map.
    pub fn of(w: u32, h: u32, slices: u32, max_voxels: u32) -> Layout {
        let top = top_maxmip_level(w, h);
        let mut level = 0;
        while level < top
            && (level_size(w, h, level).0 > max_voxels || level_size(w, h, level).1 > max_voxels)
        {
            level += 1;
        }
        Layout {
            level,
            size: level_size(w, h, level),
            slices,
        }
    }
    /// Bytes of the volume (its header included).
    pub fn bytes(&self) -> u64 {
        4 * (4 + self.size.0 as u64 * self.size.1 as u64 * self.slices as u64)
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct VolumeParams {
    band_row: u32,
    slices: u32,
    size: [u32; 2],
    radius: i32,
    offset: u32,
    level: u32,
    pad: u32,
}

/// The distance volume's pass (distance_volume.wgsl), made once per renderer.
pub fn pass(ctx: &Context, lib: &dyn Composer) -> Result<TablePass> {
    let file = "src/methods/distance_mapping/distance_volume.wgsl";
    TablePass::new(
        ctx,
        "distance volume",
        lib.compose_pass(VOLUME_SHADER, file)?,
        "build",
        &[TableOut::Buffer],
    )
}

/// The volume of an object's resident height map in layout `l`, its distances within `radius`
/// voxels (its max pyramid must be current).
pub fn build(
    pass: &TablePass,
    inputs: &BuildInputs<'_>,
    l: Layout,
    radius: u32,
) -> Result<wgpu::Buffer> {
    let ctx = inputs.ctx;
    let header = [
        l.size.0 as f32,
        l.size.1 as f32,
        l.slices as f32,
        l.level as f32,
    ];
    let buf = ctx.scoped(|| {
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let desc = wgpu::BufferDescriptor {
            label: Some("distance volume"),
            size: l.bytes(),
            usage,
            mapped_at_creation: false,
        };
        let buf = ctx.device.create_buffer(&desc);
        ctx.queue
            .write_buffer(&buf, 0, bytemuck::cast_slice(&header));
        Ok(buf)
    })?;
    let (w, h) = inputs.height_size;
    let p = VolumeParams {
        band_row: 0,
        slices: l.slices,
        size: [l.size.0, l.size.1],
        radius: radius as i32,
        offset: max_atlas(w, h).0[l.level as usize],
        level: l.level,
        pad: 0,
    };
    pass.run(
        ctx,
        inputs.height_max,
        bytemuck::bytes_of(&p),
        &[TableTarget::Buffer(&buf)],
        (l.size.0, l.size.1 * l.slices),
        &mut |done, total| crate::progress::report("distance volume", done as u64, total as u64),
    )?;
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::Layout;

    #[test]
    fn layout_and_memory() {
        // a 256^2 map at 16 slices: level 1, 128^2 voxels, 1 MiB (4x the map's float32 level 0)
        let l = Layout::of(256, 256, 16, 128);
        assert_eq!((l.level, l.size), (1, (128, 128)));
        assert_eq!(l.bytes(), 4 * (4 + 128 * 128 * 16));
        assert_eq!(
            l.bytes() as f64 / (256.0 * 256.0 * 4.0),
            4.0 + 16.0 / (256.0 * 256.0 * 4.0)
        );
        // an odd size: no coarser level tiles it, the volume is at the map's resolution
        assert_eq!(Layout::of(63, 40, 8, 128).size, (63, 40));
        // a small map stays at level 0
        assert_eq!(Layout::of(64, 64, 16, 128).level, 0);
    }
}

//! Cone maps, built on the GPU from the max-mip pyramid by cone_map.wgsl: one (base, w) pair of
//! f32 per cell of the bilinear field, in a storage buffer (two channels of the map's size). See
//! the shader for the bound.

use super::Cones;
use crate::contract::{BuildInputs, Composer};
use crate::error::Result;
use crate::gpu::{Context, TablePass};
use crate::heightmap::{max_offset_table, top_maxmip_level};

pub const CONE_MAP_SHADER: &str = include_str!("cone_map.wgsl");

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ConeParams {
    size: [u32; 2],
    top: u32,
    relaxed: u32,
    offsets: [[u32; 4]; 4],
}

/// The cone map's pass (cone_map.wgsl), made once per renderer.
pub fn pass(ctx: &Context, lib: &dyn Composer) -> Result<TablePass> {
    let module = lib.compose_pass(CONE_MAP_SHADER, "src/methods/cone_step/cone_map.wgsl")?;
    TablePass::new(ctx, "cone map", module, "build")
}

/// The cone map of an object's resident height map (its max pyramid current): (base, w) per cell.
pub fn build(pass: &TablePass, inputs: &BuildInputs<'_>, cones: Cones) -> Result<wgpu::Buffer> {
    let (ctx, (w, h)) = (inputs.ctx, inputs.height_size);
    let buf = ctx.scoped(|| {
        Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cone map"),
            size: w as u64 * h as u64 * 8,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        }))
    })?;
    let p = ConeParams {
        size: [w, h],
        top: top_maxmip_level(w, h),
        relaxed: (cones == Cones::Relaxed) as u32,
        offsets: max_offset_table(w, h),
    };
    pass.run(ctx, inputs.height_max, bytemuck::bytes_of(&p), &buf, (w, h))?;
    Ok(buf)
}

/// Read a cone map back (tests): (base, w) per cell, row-major.
pub fn read_cone_map(ctx: &Context, cone_buf: &wgpu::Buffer) -> Result<Vec<[f32; 2]>> {
    let size = cone_buf.size();
    let buf = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("cone readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(cone_buf, 0, &buf, 0, size);
    ctx.queue.submit([enc.finish()]);
    ctx.map_read(&buf, |raw| {
        bytemuck::cast_slice::<u8, [f32; 2]>(raw).to_vec()
    })
}

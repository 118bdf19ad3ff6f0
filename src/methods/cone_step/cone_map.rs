//! Cone maps, built on the GPU from the max-mip pyramid by cone_map.wgsl: one (base, w) pair of
//! f32 per cell of the bilinear field, in a storage buffer (two channels of the map's size). See
//! the shader for the bound.

use super::Cones;
use crate::contract::Composer;
use crate::error::Result;
use crate::gpu::{layout, Context};
use crate::heightmap::{max_offset_table, top_maxmip_level};

pub const CONE_MAP_SHADER: &str = include_str!("cone_map.wgsl");

pub struct ConeBuilder {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ConeParams {
    size: [u32; 2],
    top: u32,
    relaxed: u32,
    offsets: [[u32; 4]; 4],
}

impl ConeBuilder {
    pub fn new(ctx: &Context, lib: &dyn Composer) -> Result<Self> {
        let module = lib.compose_pass(CONE_MAP_SHADER, "src/methods/cone_step/cone_map.wgsl")?;
        ctx.scoped(|| {
            let dev = &ctx.device;
            let cs = wgpu::ShaderStages::COMPUTE;
            let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("cone map"),
                entries: &[
                    layout::buffer(0, cs, wgpu::BufferBindingType::Storage { read_only: true }),
                    layout::buffer(1, cs, wgpu::BufferBindingType::Uniform),
                    layout::buffer(2, cs, wgpu::BufferBindingType::Storage { read_only: false }),
                ],
            });
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("pomkit cone map"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
            let pipeline = ctx.compute_pipeline("cone map", &module, "build", &layout);
            Ok(ConeBuilder { pipeline, layout })
        })
    }

    /// Build the cone map of a resident height map (its max pyramid must be current).
    pub fn build(
        &self,
        ctx: &Context,
        max_buf: &wgpu::Buffer,
        (w, h): (u32, u32),
        cones: Cones,
    ) -> Result<wgpu::Buffer> {
        ctx.scoped(|| {
            let buf = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("cone map"),
                size: w as u64 * h as u64 * 8,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let p = ConeParams {
                size: [w, h],
                top: top_maxmip_level(w, h),
                relaxed: (cones == Cones::Relaxed) as u32,
                offsets: max_offset_table(w, h),
            };
            let ubuf = ctx.upload(
                "cone params",
                bytemuck::bytes_of(&p),
                wgpu::BufferUsages::UNIFORM,
            );
            let bg = ctx.bind_group(
                "cone map",
                &self.layout,
                vec![
                    max_buf.as_entire_binding(),
                    ubuf.as_entire_binding(),
                    buf.as_entire_binding(),
                ],
            );
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            Context::dispatch_8x8(&mut enc, "cone map", &self.pipeline, 0, &bg, (w, h));
            ctx.queue.submit([enc.finish()]);
            Ok(buf)
        })
    }
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

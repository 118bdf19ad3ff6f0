//! Texel I/O for the textures the core builds: level-0 writes of packed texels and read-backs,
//! shared by the pyramids, the cone map, the prisms and the walk.

use crate::error::Result;
use crate::gpu::Context;

/// Write `w x h` float32 texels (as bytes, row-major) to level 0 of an R32Float texture.
pub fn write_r32(ctx: &Context, tex: &wgpu::Texture, bytes: &[u8], wh: (u32, u32)) {
    write_texels(ctx, tex, bytes, wh, 4);
}

/// Write `w x h` texels of `texel_bytes` each (as bytes, row-major) to level 0 of a texture.
pub fn write_texels(
    ctx: &Context,
    tex: &wgpu::Texture,
    bytes: &[u8],
    (w, h): (u32, u32),
    texel_bytes: u32,
) {
    ctx.queue.write_texture(
        tex.as_image_copy(),
        bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(texel_bytes * w),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

/// Read a `w x h` region at the origin of one mip level of an R32Float texture (tests, builds).
pub fn read_r32(
    ctx: &Context,
    tex: &wgpu::Texture,
    mip_level: u32,
    wh: (u32, u32),
) -> Result<Vec<f32>> {
    read_f32_texels(ctx, tex, mip_level, wh, 1)
}

/// Read a `w x h` region at the origin of one mip level of a texture of `channels` float32s a
/// texel (R32Float: 1, Rgba32Float: 4), row-major, the channels of a texel together.
pub fn read_f32_texels(
    ctx: &Context,
    tex: &wgpu::Texture,
    mip_level: u32,
    wh: (u32, u32),
    channels: u32,
) -> Result<Vec<f32>> {
    let raw = read_texel_bytes(ctx, tex, mip_level, wh, 4 * channels)?;
    Ok(raw
        .chunks_exact(4)
        .map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
        .collect())
}

/// Read a `w x h` region at the origin of one mip level of a texture of `texel` bytes a texel,
/// row-major, as its bytes.
pub fn read_texel_bytes(
    ctx: &Context,
    tex: &wgpu::Texture,
    mip_level: u32,
    (w, h): (u32, u32),
    texel: u32,
) -> Result<Vec<u8>> {
    let texel = texel as u64;
    let row = (w as u64 * texel).div_ceil(256) * 256;
    let buf = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texel readback"),
        size: row * h as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: tex,
            mip_level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buf,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row as u32),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    ctx.queue.submit([enc.finish()]);
    ctx.map_read(&buf, |raw| {
        let mut out = Vec::with_capacity((w as u64 * h as u64 * texel) as usize);
        for y in 0..h as usize {
            out.extend_from_slice(
                &raw[y * row as usize..y * row as usize + (texel * w as u64) as usize],
            );
        }
        out
    })
}

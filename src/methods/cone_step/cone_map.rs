//! Cone maps, built on the GPU from the max-mip pyramid by cone_map.wgsl: one (base, w) pair of
//! f32 per cell of the bilinear field, in two R32Float textures of the map's size (8 bytes a
//! cell: 2x the map's float32 level 0). See the shader for the bound.

use crate::contract::{BuildInputs, Composer};
use crate::error::Result;
use crate::gpu::texels::{read_r32, write_r32};
use crate::gpu::{Context, TableOut, TablePass, TableTarget};
use crate::heightmap::{max_offset_table, top_maxmip_level};
use crate::progress;

crate::option_enum!(
    /// Which cones: conservative against the bilinear field, or relaxed (wider, refined).
    Cones, "cones", {
        Conservative = "conservative",
        Relaxed = "relaxed",
    }
);

pub const CONE_MAP_SHADER: &str = include_str!("cone_map.wgsl");

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ConeParams {
    band_row: u32,
    top: u32,
    size: [u32; 2],
    relaxed: u32,
    global_max: f32,
    pad: [u32; 2],
    offsets: [[u32; 4]; 4],
}

/// The cone map's pass (cone_map.wgsl), made once per renderer.
pub fn pass(ctx: &Context, lib: &dyn Composer) -> Result<TablePass> {
    let module = lib.compose_pass(CONE_MAP_SHADER, "src/methods/cone_step/cone_map.wgsl")?;
    TablePass::new(
        ctx,
        "cone map",
        module,
        "build",
        &[TableOut::R32Float, TableOut::R32Float],
    )
}

/// The cone map of an object's resident height map (its max pyramid current): two R32Float
/// textures of the map's size, base and w per cell. A build that took longer than
/// `progress::keep_after()` is kept on disk, keyed by `key` (the map's content, the kind of cones
/// and this builder's source), and read from there next time; the build reports its rows to
/// `progress`.
pub fn build(
    pass: &TablePass,
    inputs: &BuildInputs<'_>,
    cones: Cones,
    key: u64,
) -> Result<[wgpu::TextureView; 2]> {
    let (ctx, (w, h)) = (inputs.ctx, inputs.height_size);
    let texels = w as usize * h as usize;
    let key = crate::scene::hash_bytes(&[&key.to_le_bytes(), CONE_MAP_SHADER.as_bytes()]);
    let textures = ctx.scoped(|| {
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST;
        Ok(["cone base", "cone w"]
            .map(|l| ctx.texture_2d(l, (w, h), wgpu::TextureFormat::R32Float, usage)))
    })?;
    let views = textures
        .each_ref()
        .map(|t| t.create_view(&Default::default()));
    if let Some(kept) = progress::load("cone-map", key, texels * 8) {
        ctx.scoped(|| {
            for (t, half) in textures.iter().zip(kept.chunks(texels * 4)) {
                write_r32(ctx, t, half, (w, h));
            }
            Ok(())
        })?;
        return Ok(views);
    }
    let p = ConeParams {
        band_row: 0,
        top: top_maxmip_level(w, h),
        size: [w, h],
        relaxed: (cones == Cones::Relaxed) as u32,
        global_max: inputs
            .object
            .material
            .height
            .data
            .iter()
            .fold(0.0f32, |a, &b| a.max(b)),
        pad: [0; 2],
        offsets: max_offset_table(w, h),
    };
    let t0 = std::time::Instant::now();
    pass.run(
        ctx,
        inputs.height_max,
        bytemuck::bytes_of(&p),
        &[
            TableTarget::Texture(&views[0]),
            TableTarget::Texture(&views[1]),
        ],
        (w, h),
        &mut |done, total| progress::report("cone map", done as u64, total as u64),
    )?;
    ctx.wait()?;
    if t0.elapsed() > progress::keep_after() {
        let base = read_r32(ctx, &textures[0], 0, (w, h))?;
        let slope = read_r32(ctx, &textures[1], 0, (w, h))?;
        progress::store(
            "cone-map",
            key,
            &[bytemuck::cast_slice(&base), bytemuck::cast_slice(&slope)],
        );
    }
    Ok(views)
}

/// Read a cone map back (tests): (base, w) per cell, row-major.
pub fn read_cone_map(ctx: &Context, maps: &[wgpu::TextureView]) -> Result<Vec<[f32; 2]>> {
    let [base, slope] = maps else {
        return Err(crate::error::Error::Gpu(
            "a cone map is two textures".into(),
        ));
    };
    let tex = |v: &wgpu::TextureView| v.texture().clone();
    let (b, s) = (tex(base), tex(slope));
    let size = (b.width(), b.height());
    let (bv, sv) = (read_r32(ctx, &b, 0, size)?, read_r32(ctx, &s, 0, size)?);
    Ok(bv.into_iter().zip(sv).map(|(x, y)| [x, y]).collect())
}

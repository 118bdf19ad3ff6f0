//! Compute passes that build a method's tables from the height map's max pyramid (the cone map,
//! the distance volume): bound, dispatched in bands and reported (`TablePass`).

use super::{layout, Context};
use crate::error::Result;

/// What a `TablePass` writes, at bindings 3, 4, ...
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableOut {
    /// a read-write storage buffer
    Buffer,
    /// a write-only R32Float storage texture (every backend has it, GL too)
    R32Float,
}

/// An output a `TablePass` fills.
pub enum TableTarget<'a> {
    Buffer(&'a wgpu::Buffer),
    Texture(&'a wgpu::TextureView),
}

/// A compute pass that makes a method's table from the height map's max pyramid: bindings 0 and
/// 1 its level 0 and atlas (shaders/max_tables.wgsl), 2 a uniform block of parameters, 3.. the
/// outputs; dispatched over a w x h grid in 8 x 8 workgroups, in bands of rows (`run`). Methods
/// build their own data this way (the cone map, the distance volume).
pub struct TablePass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    label: &'static str,
}

/// Cells a band of a `TablePass` covers at most: one submission each, so that a long build is
/// never one dispatch that a driver's watchdog could end, and its progress can be shown.
pub const TABLE_BAND_CELLS: u64 = 1 << 22;

impl TablePass {
    /// `module` (composed) with entry point `entry`.
    pub fn new(
        ctx: &Context,
        label: &'static str,
        module: naga::Module,
        entry: &str,
        outputs: &[TableOut],
    ) -> Result<Self> {
        ctx.scoped(|| {
            let dev = &ctx.device;
            let cs = wgpu::ShaderStages::COMPUTE;
            let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
            let mut entries = vec![
                layout::texture(0, cs, unfilterable),
                layout::texture(1, cs, unfilterable),
                layout::buffer(2, cs, wgpu::BufferBindingType::Uniform),
            ];
            for (i, o) in outputs.iter().enumerate() {
                let b = 3 + i as u32;
                entries.push(match o {
                    TableOut::Buffer => {
                        layout::buffer(b, cs, wgpu::BufferBindingType::Storage { read_only: false })
                    }
                    TableOut::R32Float => {
                        layout::storage_texture(b, cs, wgpu::TextureFormat::R32Float)
                    }
                });
            }
            let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            });
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
            let pipeline = ctx.compute_pipeline(label, &module, entry, &layout);
            Ok(TablePass {
                pipeline,
                layout,
                label,
            })
        })
    }

    /// Fill `outputs` from the max pyramid `max` (its level 0 and its atlas: the height map's
    /// `max0_view` and `max_atlas_view`) with `params` over `grid`, in bands of
    /// rows of at most `TABLE_BAND_CELLS` cells, each submitted and waited for; `progress` is
    /// told the rows done after each. The shader offsets its rows by `band_row`, the u32 at
    /// byte 0 of `params`, which this writes.
    pub fn run(
        &self,
        ctx: &Context,
        max: [&wgpu::TextureView; 2],
        params: &[u8],
        outputs: &[TableTarget<'_>],
        (w, h): (u32, u32),
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<()> {
        let band = ((TABLE_BAND_CELLS / w.max(1) as u64).max(8) as u32).min(h.max(1));
        let mut row = 0;
        progress(0, h);
        while row < h {
            let rows = band.min(h - row);
            ctx.scoped(|| {
                let mut p = params.to_vec();
                p[0..4].copy_from_slice(&row.to_le_bytes());
                let ubuf = ctx.upload(self.label, &p, wgpu::BufferUsages::UNIFORM);
                let mut res = vec![
                    wgpu::BindingResource::TextureView(max[0]),
                    wgpu::BindingResource::TextureView(max[1]),
                    ubuf.as_entire_binding(),
                ];
                for o in outputs {
                    res.push(match o {
                        TableTarget::Buffer(b) => b.as_entire_binding(),
                        TableTarget::Texture(v) => wgpu::BindingResource::TextureView(v),
                    });
                }
                let bg = ctx.bind_group(self.label, &self.layout, res);
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                Context::dispatch_8x8(&mut enc, self.label, &self.pipeline, 0, &bg, (w, rows));
                ctx.queue.submit([enc.finish()]);
                Ok(())
            })?;
            row += rows;
            if row < h {
                ctx.wait()?;
            }
            progress(row, h);
        }
        Ok(())
    }
}

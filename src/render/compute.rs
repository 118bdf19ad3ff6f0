//! The compute pipeline's passes over a frame: the visibility pass, then the surface per pixel.

use super::resources::Draw;
use super::targets::Targets;
use super::{FrameBinds, Renderer};
use crate::error::{Error, Result};

impl Renderer {
    /// The compute pipeline's passes: the visibility pass (triangle ids under the same depth
    /// test), then the surface per pixel into the targets. Timed from the first pass's start to
    /// the second's end.
    pub(super) fn encode_compute(
        &self,
        enc: &mut wgpu::CommandEncoder,
        tg: &Targets,
        (visibility, surface): (&wgpu::RenderPipeline, &wgpu::ComputePipeline),
        binds: &FrameBinds,
        draws: &[Draw],
    ) -> Result<()> {
        use wgpu::BindingResource as R;
        let ctx = &self.ctx;
        let vis_view = tg
            .visibility
            .as_ref()
            .ok_or_else(|| Error::Gpu("no visibility target on this adapter".into()))?;
        let mesh_groups: Vec<(wgpu::BindGroup, wgpu::BindGroup)> = draws
            .iter()
            .map(|d| {
                let idx = d.mesh.ibuf.as_ref().unwrap_or(&self.fixed.no_indices);
                let vis = ctx.bind_group(
                    "visibility mesh",
                    &self.pipelines.visibility_bgl,
                    vec![d.mesh.vbuf.as_entire_binding(), idx.as_entire_binding()],
                );
                let mut e = vec![
                    d.mesh.vbuf.as_entire_binding(),
                    idx.as_entire_binding(),
                    R::TextureView(vis_view),
                ];
                e.extend(tg.targets.iter().map(|t| R::TextureView(&t.v)));
                let cs = ctx.bind_group("compute surface", &self.pipelines.compute_bgl, e);
                (vis, cs)
            })
            .collect();
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("visibility"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: vis_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(tg.depth_attachment()),
                timestamp_writes: tg
                    .queries
                    .as_ref()
                    .map(|q| wgpu::RenderPassTimestampWrites {
                        query_set: q,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: None,
                    }),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(visibility);
            pass.set_bind_group(0, &binds.view, &[]);
            for (d, (vis, _)) in draws.iter().zip(&mesh_groups) {
                pass.set_bind_group(1, &d.object, &[]);
                pass.set_bind_group(2, &d.method, &[]);
                pass.set_bind_group(3, vis, &[]);
                pass.draw(0..d.mesh.count, 0..1);
            }
        }
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("compute surface"),
                timestamp_writes: tg
                    .queries
                    .as_ref()
                    .map(|q| wgpu::ComputePassTimestampWrites {
                        query_set: q,
                        beginning_of_pass_write_index: None,
                        end_of_pass_write_index: Some(1),
                    }),
            });
            pass.set_pipeline(surface);
            pass.set_bind_group(0, &binds.view, &[]);
            for (d, (_, cs)) in draws.iter().zip(&mesh_groups) {
                pass.set_bind_group(1, &d.object, &[]);
                pass.set_bind_group(2, &d.method, &[]);
                pass.set_bind_group(3, cs, &[]);
                pass.dispatch_workgroups(tg.w.div_ceil(8), tg.h.div_ceil(8), 1);
            }
        }
        Ok(())
    }
}

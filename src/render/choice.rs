//! Which pipeline draws a frame: what the compute pipeline cannot draw, and "auto"'s rule, with
//! the probe it times once per device (the probe's method is the registry's:
//! `Method::auto_probe`).

use super::pipelines::{self, Kind};
use super::{Aovs, Renderer, AUTO_MARGIN};
use crate::contract::Spec;
use crate::error::{Error, Result};
use crate::methods::Method;
use crate::scene::{HeightMap, Scene};

impl Renderer {
    /// Why the compute pipeline cannot draw `scene` with `spec` (None: it can).
    pub fn compute_refusal(&self, scene: &Scene, spec: &Spec, aovs: Aovs) -> Option<String> {
        if !self.ctx.caps.compute_pipeline() {
            return Some(format!(
                "this adapter ({}, {}) lacks what it needs: {} (python -m pomkit info lists its features)",
                self.ctx.info.name,
                self.ctx.info.backend,
                self.ctx.caps.compute_pipeline_missing.join(", ")
            ));
        }
        if !matches!(spec.pass, crate::contract::Pass::Surface { .. }) {
            return Some(
                "the method draws geometry of its own (prisms: a pixel may need several of them), which only the raster pipeline draws".into(),
            );
        }
        if scene.objects.len() > 1 {
            return Some(
                "a frame of several objects orders them by their displaced depth, which a visibility pass at the base mesh's depth cannot".into(),
            );
        }
        if aovs.counts_fragments() {
            return Some(
                "the `fragments` AOV counts the raster pipeline's fragment invocations (the compute pipeline runs one invocation a pixel)".into(),
            );
        }
        let extra = if spec.defs.contains(&"VERTEX_EXTRA") {
            16
        } else {
            0
        };
        let stride = pipelines::vertex_layout(&spec.geometry).array_stride;
        if stride != std::mem::size_of::<crate::mesh::Vertex>() as u64 + extra {
            return Some(format!(
                "the method's geometry has {stride}-byte vertices, a layout shaders/visibility.wgsl does not read"
            ));
        }
        None
    }

    /// The pipeline that draws `scene` with `spec`: the one asked for, or for "auto" the
    /// adapter's verdict (`auto_compute`) where the compute pipeline can draw the frame.
    pub fn kind(
        &self,
        choice: pipelines::Choice,
        auto_compute: bool,
        scene: &Scene,
        spec: &Spec,
        aovs: Aovs,
    ) -> Result<Kind> {
        match choice {
            pipelines::Choice::Raster => Ok(Kind::Raster),
            pipelines::Choice::Compute => match self.compute_refusal(scene, spec, aovs) {
                None => Ok(Kind::Compute),
                Some(why) => Err(Error::arg(
                    "pipeline",
                    format!("'compute' cannot draw this frame: {why}; use pipeline='raster', or 'auto' (which rasterises such frames)"),
                )),
            },
            pipelines::Choice::Auto => Ok(
                if auto_compute && self.compute_refusal(scene, spec, aovs).is_none() {
                    Kind::Compute
                } else {
                    Kind::Raster
                },
            ),
        }
    }

    /// "auto"'s rule: whether this device draws the per-pixel methods faster in compute. A CPU
    /// adapter rasterises (measured on llvmpipe: docs/cost.md, "Two pipelines"); any other
    /// adapter with the compute pipeline is measured once, on first use: POM on a plane at
    /// 512², both pipelines interleaved, and compute wins where its median GPU time is below
    /// `AUTO_MARGIN` of the raster pipeline's.
    pub fn auto_compute(&self) -> bool {
        if !self.ctx.caps.compute_pipeline() || self.ctx.info.device_type == "Cpu" {
            return false;
        }
        *self.ctx.auto_compute.get_or_init(|| match self.probe() {
            Ok((r, c)) => c < AUTO_MARGIN * r,
            Err(_) => false,
        })
    }

    /// "auto"'s probe on this device: the median ms of the raster and the compute pipeline.
    pub fn probe(&self) -> Result<(f64, f64)> {
        Ok((
            self.probe_ms(pipelines::Choice::Raster)?,
            self.probe_ms(pipelines::Choice::Compute)?,
        ))
    }

    /// The median time (GPU time, or wall time without timestamps) of "auto"'s probe frame with
    /// `choice`, after a warm-up.
    fn probe_ms(&self, choice: pipelines::Choice) -> Result<f64> {
        let n = 256u32;
        let field: Vec<f32> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
                0.5 + 0.25 * ((x * 50.0).sin() + (y * 40.0).cos())
            })
            .collect();
        let scene = Scene::single(
            crate::scene::shared(crate::mesh::Mesh::plane(2.0, 1)?)?,
            crate::scene::Material {
                height: crate::scene::shared(HeightMap::new(n, n, field)?)?,
                depth: 0.08,
                tiling: 1.0,
                albedo: None,
            },
            crate::scene::Camera {
                eye: [0.0, 1.2, 1.6],
                target: [0.0; 3],
                up: [0.0, 1.0, 0.0],
                fov_y: 40.0,
                width: 512,
                height: 512,
                window: None,
                samples: 1,
            },
            vec![],
            [0.5; 3],
        );
        let method = Method::auto_probe();
        let mut times = Vec::new();
        for i in 0..7 {
            let f = self.render_with(
                std::slice::from_ref(&scene),
                &method,
                Aovs::STANDARD,
                choice,
            )?;
            if i >= 2 {
                let f = &f[0];
                times.push(f.gpu_ms.unwrap_or(f.wall_ms));
            }
        }
        times.sort_by(f64::total_cmp);
        Ok(times[times.len() / 2])
    }
}

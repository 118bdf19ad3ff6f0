//! The renderer across the boundary: `pomkit._core.Renderer` (scenes and methods in, frames
//! out, the GIL released while the GPU works) and the adapters.

use super::frame::{aovs_from_py, frame_to_py, PyRenderedFrame};
use super::handles::PyHeightData;
use super::scene_args::scene_from_py;
use crate::methods::Method;
use crate::render::Renderer;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::sync::Arc;

/// The renderer: one per Python Renderer, sharing the process-wide device.
#[pyclass(name = "Renderer", module = "pomkit._core", frozen)]
pub struct PyRenderer {
    inner: Arc<Renderer>,
}

#[pymethods]
impl PyRenderer {
    #[new]
    #[pyo3(signature = (adapter=None, pipeline="auto"))]
    fn new(py: Python<'_>, adapter: Option<String>, pipeline: &str) -> PyResult<Self> {
        let choice = crate::render::pipelines::Choice::parse(pipeline)?;
        let r = py.detach(|| {
            let ctx = crate::gpu::shared(adapter.as_deref())?;
            Renderer::new(ctx, choice)
        })?;
        Ok(Self { inner: Arc::new(r) })
    }

    /// Render `scene` (a pomkit.Scene, read attribute by attribute) with `method` (a pomkit
    /// method dataclass, extracted field by field into the core's typed `Method`): the frame's
    /// arrays and timings (`frame_to_py`).
    #[pyo3(signature = (scene, method, aovs=None, spp=1))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, PyAny>,
        method: Method,
        aovs: Option<&Bound<'py, PyAny>>,
        spp: u32,
    ) -> PyResult<Bound<'py, PyRenderedFrame>> {
        let aovs = aovs_from_py(aovs)?;
        let scene = scene_from_py(scene)?;
        let r = self.inner.clone();
        let mut frames =
            py.detach(move || r.render_many_spp(std::slice::from_ref(&scene), &method, aovs, spp))?;
        frame_to_py(py, frames.pop().expect("one frame"))
    }

    /// Render many scenes with one method, pipelined (`Renderer::render_many`): a list of
    /// what `render` returns.
    #[pyo3(signature = (scenes, method, aovs=None, spp=1))]
    fn render_many<'py>(
        &self,
        py: Python<'py>,
        scenes: Vec<Bound<'py, PyAny>>,
        method: Method,
        aovs: Option<&Bound<'py, PyAny>>,
        spp: u32,
    ) -> PyResult<Vec<Bound<'py, PyRenderedFrame>>> {
        let aovs = aovs_from_py(aovs)?;
        let scenes = scenes
            .iter()
            .map(scene_from_py)
            .collect::<PyResult<Vec<_>>>()?;
        let r = self.inner.clone();
        let frames = py.detach(move || r.render_many_spp(&scenes, &method, aovs, spp))?;
        frames.into_iter().map(|f| frame_to_py(py, f)).collect()
    }

    /// Dynamic height fields: write `new` into the GPU texture holding `old` (same size) and
    /// rebuild the pyramids on the GPU. False when `old` is not resident.
    fn update_height(
        &self,
        py: Python<'_>,
        old: &Bound<'_, PyHeightData>,
        new: &Bound<'_, PyHeightData>,
    ) -> PyResult<bool> {
        let (o, n) = (old.get().0.clone(), new.get().0.clone());
        let r = self.inner.clone();
        py.detach(move || r.update_height(&o, &n))
            .map_err(PyErr::from)
    }

    /// Adapter name, backend, device type, driver and the features pomkit uses.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = &self.inner.ctx;
        let d = PyDict::new(py);
        d.set_item("name", &c.info.name)?;
        d.set_item("backend", &c.info.backend)?;
        d.set_item("device_type", &c.info.device_type)?;
        d.set_item("driver", &c.info.driver)?;
        d.set_item("timestamps", c.caps.timestamps)?;
        d.set_item("float32_filterable", c.caps.float32_filterable)?;
        d.set_item(
            "max_texture_dimension_2d",
            c.limits.max_texture_dimension_2d,
        )?;
        d.set_item("max_buffer_size", c.limits.max_buffer_size)?;
        d.set_item(
            "max_storage_buffer_binding_size",
            c.limits.max_storage_buffer_binding_size,
        )?;
        d.set_item(
            "max_storage_buffers_per_shader_stage",
            c.limits.max_storage_buffers_per_shader_stage,
        )?;
        // (feature, present, what pomkit does without it)
        let feats = PyList::empty(py);
        for (name, present, fallback) in c.caps.report() {
            feats.append((name, present, fallback))?;
        }
        d.set_item("features", feats)?;
        d.set_item("wgpu_version", crate::gpu::WGPU_VERSION)?;
        d.set_item("pipeline", self.inner.pipeline.name())?;
        // what "auto" draws the per-pixel methods with on this adapter
        d.set_item(
            "auto_pipeline",
            if self.inner.auto_compute() {
                "compute"
            } else {
                "raster"
            },
        )?;
        Ok(d)
    }

    /// "auto"'s probe on this device: (raster ms, compute ms), the median of five frames of POM
    /// on a plane at 512² each (`python -m pomkit info` prints it).
    fn pipeline_probe(&self, py: Python<'_>) -> PyResult<(f64, f64)> {
        let r = self.inner.clone();
        py.detach(move || r.probe()).map_err(PyErr::from)
    }

    /// Trigger a wgpu validation error (tests: it must raise GpuError and leave the renderer usable).
    #[cfg(feature = "test-hooks")]
    fn _provoke_validation_error(&self, py: Python<'_>) -> PyResult<()> {
        let r = self.inner.clone();
        py.detach(move || crate::render::test_hooks::provoke_validation_error(&r))
            .map_err(PyErr::from)
    }

    /// Destroy the device (to test device-loss handling).
    #[cfg(feature = "test-hooks")]
    fn _destroy_device(&self) {
        self.inner.ctx.destroy();
    }
}

#[pyfunction]
pub fn adapters<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let list = py.detach(crate::gpu::adapters)?;
    let out = PyList::empty(py);
    for a in list {
        let d = PyDict::new(py);
        d.set_item("name", a.name)?;
        d.set_item("backend", a.backend)?;
        d.set_item("device_type", a.device_type)?;
        d.set_item("driver", a.driver)?;
        out.append(d)?;
    }
    Ok(out)
}

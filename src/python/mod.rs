//! The pyo3 layer: numpy in, numpy out, core errors mapped to Python exceptions (`From<Error>
//! for PyErr`), method dataclasses extracted into the core's types (methods.rs). No logic.

mod frame;
mod io;
mod methods;
mod progress;
mod scene;

use crate::error::Error;
use crate::methods::Method;
use crate::oracle::exact_hits;
use crate::render::Renderer;
use frame::{aovs_from_py, frame_to_py};
use numpy::ndarray::Array;
use numpy::IntoPyArray;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use scene::{scene_from_py, PyAlbedoData, PyHeightData, PyMeshData};
use std::sync::Arc;

create_exception!(
    _core,
    GpuError,
    PyRuntimeError,
    "A wgpu validation or out-of-memory error."
);
create_exception!(
    _core,
    DeviceLostError,
    GpuError,
    "The GPU device was lost; create a new Renderer."
);
create_exception!(
    _core,
    NoAdapterError,
    PyRuntimeError,
    "No GPU adapter is available."
);

/// A numpy array of `shape` that takes ownership of `v` (no copy).
pub(crate) fn nd_array<'py, T: numpy::Element, D: numpy::ndarray::Dimension>(
    py: Python<'py>,
    shape: impl numpy::ndarray::IntoDimension<Dim = D>,
    v: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    let a = Array::from_shape_vec(shape, v).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py).into_any())
}

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        match e {
            Error::InvalidArgument { .. } | Error::Limit { .. } => {
                PyValueError::new_err(e.to_string())
            }
            Error::NoAdapter(_) => NoAdapterError::new_err(e.to_string()),
            Error::Gpu(_) => GpuError::new_err(e.to_string()),
            Error::DeviceLost(_) => DeviceLostError::new_err(e.to_string()),
        }
    }
}

/// The renderer: one per Python Renderer, sharing the process-wide device.
#[pyclass(name = "Renderer", module = "pomkit._core", frozen)]
struct PyRenderer {
    inner: Arc<Renderer>,
}

#[pymethods]
impl PyRenderer {
    #[new]
    #[pyo3(signature = (adapter=None))]
    fn new(py: Python<'_>, adapter: Option<String>) -> PyResult<Self> {
        let r = py.detach(|| {
            let ctx = crate::gpu::shared(adapter.as_deref())?;
            Renderer::new(ctx)
        })?;
        Ok(Self { inner: Arc::new(r) })
    }

    /// Render `scene` (a dict from pomkit.Scene._describe()) with `method` (a pomkit method
    /// dataclass, extracted field by field into the core's typed `Method`). Returns (a dict of
    /// numpy arrays by AOV name, None for those not in `aovs`; gpu_ms; wall_ms): `frame_to_py`.
    #[pyo3(signature = (scene, method, aovs=None, spp=1))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, PyDict>,
        method: Method,
        aovs: Option<&Bound<'py, PyAny>>,
        spp: u32,
    ) -> PyResult<Bound<'py, PyTuple>> {
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
        scenes: Vec<Bound<'py, PyDict>>,
        method: Method,
        aovs: Option<&Bound<'py, PyAny>>,
        spp: u32,
    ) -> PyResult<Vec<Bound<'py, PyTuple>>> {
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
        Ok(d)
    }

    /// Trigger a wgpu validation error (tests: it must raise GpuError and leave the renderer usable).
    fn _provoke_validation_error(&self, py: Python<'_>) -> PyResult<()> {
        let r = self.inner.clone();
        py.detach(move || r.provoke_validation_error())
            .map_err(PyErr::from)
    }

    /// Destroy the device (to test device-loss handling).
    fn _destroy_device(&self) {
        self.inner.ctx.destroy();
    }
}

#[pyfunction]
fn adapters<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
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

/// The CPU float64 oracle: dict with uv (H, W, 2) f64, depth (H, W) f64, mask, cells, and the
/// first directional light's visibility (H, W) f64.
#[pyfunction]
#[pyo3(signature = (scene, light_bias=0.0))]
fn exact_uv<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    light_bias: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let o = py.detach(move || exact_hits(&scene, light_bias))?;
    let (h, w) = (o.height as usize, o.width as usize);
    let d = PyDict::new(py);
    d.set_item("uv", nd_array(py, (h, w, 2), o.uv)?)?;
    d.set_item("depth", nd_array(py, (h, w), o.depth)?)?;
    d.set_item("mask", nd_array(py, (h, w), o.mask)?)?;
    d.set_item("cells", nd_array(py, (h, w), o.cells)?)?;
    d.set_item("visibility", nd_array(py, (h, w), o.visibility)?)?;
    Ok(d)
}

/// The exact image (`oracle/image.rs`): dict with color (H, W, 3) f32 and coverage (H, W) f32
/// from k x k exact samples per pixel shaded with the reference shading.
#[pyfunction]
#[pyo3(signature = (scene, spp, shadows=true))]
fn render_exact<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    spp: u32,
    shadows: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let o = py.detach(move || crate::oracle::image::render_exact(&scene, spp, shadows))?;
    let (h, w) = (o.height as usize, o.width as usize);
    let d = PyDict::new(py);
    d.set_item("color", nd_array(py, (h, w, 3), o.color)?)?;
    d.set_item("coverage", nd_array(py, (h, w), o.coverage)?)?;
    Ok(d)
}

/// The displaced surface of object `object` of `scene` as arrays (positions, shading normals,
/// uvs, faces) in object space, with `texels_per_vertex` lattice spacing.
#[pyfunction]
#[pyo3(signature = (scene, texels_per_vertex, object=0))]
fn tessellate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    texels_per_vertex: f64,
    object: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    scene.validate()?;
    let obj = scene.objects.get(object).ok_or_else(|| {
        Error::arg(
            "object",
            format!("the scene has {} objects", scene.objects.len()),
        )
    })?;
    let t = py.detach(move || {
        crate::methods::tessellated::tessellate::tessellate(
            &obj.mesh,
            &obj.material,
            texels_per_vertex,
        )
    })?;
    let n = t.positions.len();
    let d = PyDict::new(py);
    d.set_item("positions", nd_array(py, (n, 3), t.positions.concat())?)?;
    d.set_item("normals", nd_array(py, (n, 3), t.normals.concat())?)?;
    d.set_item("uvs", nd_array(py, (n, 2), t.uvs.concat())?)?;
    d.set_item("faces", nd_array(py, (t.indices.len() / 3, 3), t.indices)?)?;
    Ok(d)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("NCS_MAP_SIZE", crate::methods::NCS_MAP_SIZE)?;
    // the contracts Python derives its checks and Literals from (one source: the core)
    m.add("MAX_LIGHTS", crate::scene::MAX_LIGHTS)?;
    m.add("AOV_NAMES", crate::render::Aovs::NAMES.to_vec())?;
    let docs = PyDict::new(m.py());
    for a in crate::render::aovs::AOVS {
        docs.set_item(a.name, a.doc)?;
    }
    m.add("AOV_DOCS", docs)?;
    m.add("SHADOW_KINDS", crate::methods::Shadows::NAMES.to_vec())?;
    m.add("FILTERING_KINDS", crate::methods::Filtering::NAMES.to_vec())?;
    m.add("CONE_KINDS", crate::methods::Cones::NAMES.to_vec())?;
    m.add("REFINE_KINDS", crate::methods::Refine::NAMES.to_vec())?;
    m.add("MAX_STEPS_LIMIT", crate::methods::MAX_STEPS_LIMIT)?;
    m.add_class::<PyRenderer>()?;
    m.add_class::<PyMeshData>()?;
    m.add_class::<PyHeightData>()?;
    m.add_class::<PyAlbedoData>()?;
    m.add_function(wrap_pyfunction!(adapters, m)?)?;
    m.add_function(wrap_pyfunction!(exact_uv, m)?)?;
    m.add_function(wrap_pyfunction!(render_exact, m)?)?;
    m.add_function(wrap_pyfunction!(scene::mesh_from_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(scene::mesh_generate, m)?)?;
    m.add_function(wrap_pyfunction!(scene::bounding_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(tessellate, m)?)?;
    m.add_function(wrap_pyfunction!(io::load_image, m)?)?;
    m.add_function(wrap_pyfunction!(progress::set_progress_hook, m)?)?;
    m.add_function(wrap_pyfunction!(progress::set_cache_dir, m)?)?;
    m.add("GpuError", m.py().get_type::<GpuError>())?;
    m.add("DeviceLostError", m.py().get_type::<DeviceLostError>())?;
    m.add("NoAdapterError", m.py().get_type::<NoAdapterError>())?;
    Ok(())
}

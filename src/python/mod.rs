//! The pyo3 layer: numpy in, numpy out, core errors mapped to Python exceptions (`From<Error>
//! for PyErr`), method dataclasses extracted into the core's types (methods.rs). No logic.

mod methods;

use crate::error::Error;
use crate::exact::exact_hits;
use crate::mesh::Mesh;
use crate::methods::Method;
use crate::render::{Frame, Renderer};
use crate::scene::{Albedo, Camera, HeightMap, Light, Material, Scene};
use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
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

fn rows<const N: usize>(a: &PyReadonlyArray2<'_, f32>, name: &str) -> PyResult<Vec<[f32; N]>> {
    let v = a.as_array();
    if v.shape()[1] != N {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (n, {N}), got {:?}",
            v.shape()
        )));
    }
    Ok(v.outer_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

type MeshArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
);

fn mesh_out<'py>(py: Python<'py>, m: &Mesh) -> PyResult<MeshArrays<'py>> {
    let n = m.positions.len();
    let f = |v: Vec<f32>, k: usize| -> PyResult<Bound<'py, PyAny>> {
        Ok(Array::from_shape_vec((n, k), v)
            .map_err(|e| PyValueError::new_err(e.to_string()))?
            .into_pyarray(py)
            .into_any())
    };
    Ok((
        f(m.positions.concat(), 3)?,
        f(m.normals.concat(), 3)?,
        f(m.uvs.concat(), 2)?,
        m.indices.clone().into_pyarray(py).into_any(),
        f(m.tangents.concat(), 4)?,
        f(m.uv_scale.concat(), 2)?,
        Array::from_shape_vec((m.charts.len(), 3), m.charts.concat())
            .map_err(|e| PyValueError::new_err(e.to_string()))?
            .into_pyarray(py)
            .into_any(),
    ))
}

/// Validate mesh arrays and compute the tangent frames. Returns
/// (positions, normals, uvs, indices, tangents, uv_scale, degenerate_uv_triangles, fallback_vertices).
#[pyfunction]
#[pyo3(signature = (positions, normals, uvs, indices, tangents=None))]
fn mesh_from_arrays<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f32>,
    normals: PyReadonlyArray2<'py, f32>,
    uvs: PyReadonlyArray2<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    tangents: Option<PyReadonlyArray2<'py, f32>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let p = rows::<3>(&positions, "positions")?;
    let n = rows::<3>(&normals, "normals")?;
    let u = rows::<2>(&uvs, "uvs")?;
    let i: Vec<u32> = indices.as_array().iter().copied().collect();
    let t = tangents
        .as_ref()
        .map(|t| rows::<4>(t, "tangents"))
        .transpose()?;
    let (mesh, rep) = py.detach(|| Mesh::from_arrays(p, n, u, i, t))?;
    let a = mesh_out(py, &mesh)?;
    PyTuple::new(
        py,
        [
            a.0,
            a.1,
            a.2,
            a.3,
            a.4,
            a.5,
            a.6,
            rep.degenerate_uv_triangles.into_pyobject(py)?.into_any(),
            rep.fallback_vertices.into_pyobject(py)?.into_any(),
        ],
    )
}

/// A generated base mesh: kind in plane, sphere, torus, cylinder, cube.
#[pyfunction]
fn mesh_generate<'py>(
    py: Python<'py>,
    kind: &str,
    a: f64,
    b: f64,
    n1: u32,
    n2: u32,
) -> PyResult<MeshArrays<'py>> {
    let m = match kind {
        "plane" => Mesh::plane(a, n1),
        "sphere" => Mesh::sphere(a, n1, n2),
        "torus" => Mesh::torus(a, b, n1, n2),
        "cylinder" => Mesh::cylinder(a, b, n1, n2),
        "cube" => Mesh::cube(a, n1),
        o => Err(Error::arg("kind", format!("unknown mesh kind {o:?}"))),
    }?;
    mesh_out(py, &m)
}

fn item<'py>(d: &Bound<'py, PyDict>, k: &str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(k)?
        .ok_or_else(|| PyValueError::new_err(format!("scene description lacks {k:?}")))
}

fn v3(x: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    x.extract()
}

/// Build a core Scene from the dict that `pomkit.Scene._describe()` returns.
fn scene_from_py(d: &Bound<'_, PyDict>) -> PyResult<Scene> {
    let mesh = item(d, "mesh")?;
    let mesh = mesh.cast::<PyDict>()?;
    let positions: PyReadonlyArray2<f32> = item(mesh, "positions")?.extract()?;
    let normals: PyReadonlyArray2<f32> = item(mesh, "normals")?.extract()?;
    let uvs: PyReadonlyArray2<f32> = item(mesh, "uvs")?.extract()?;
    let tangents: PyReadonlyArray2<f32> = item(mesh, "tangents")?.extract()?;
    let uv_scale: PyReadonlyArray2<f32> = item(mesh, "uv_scale")?.extract()?;
    let indices: PyReadonlyArray1<u32> = item(mesh, "indices")?.extract()?;
    let mesh = Mesh {
        positions: rows::<3>(&positions, "positions")?,
        normals: rows::<3>(&normals, "normals")?,
        uvs: rows::<2>(&uvs, "uvs")?,
        tangents: rows::<4>(&tangents, "tangents")?,
        uv_scale: rows::<2>(&uv_scale, "uv_scale")?,
        indices: indices.as_array().iter().copied().collect(),
        charts: {
            let c: PyReadonlyArray2<u32> = item(mesh, "charts")?.extract()?;
            let c = c.as_array();
            if c.len() > 0 && c.shape()[1] != 3 {
                return Err(PyValueError::new_err("charts: expected shape (k, 3)"));
            }
            c.outer_iter().map(|r| [r[0], r[1], r[2]]).collect()
        },
    };
    let height: PyReadonlyArray2<f32> = item(d, "height")?.extract()?;
    let hv = height.as_array();
    let (hh, hw) = (hv.shape()[0] as u32, hv.shape()[1] as u32);
    let height = HeightMap::new(hw, hh, hv.iter().copied().collect())?;
    let albedo = item(d, "albedo")?;
    let albedo = if albedo.is_none() {
        None
    } else {
        let a: PyReadonlyArray3<f32> = albedo.extract()?;
        let av = a.as_array();
        if av.shape()[2] != 3 {
            return Err(PyValueError::new_err("albedo: expected shape (H, W, 3)"));
        }
        let data = av
            .outer_iter()
            .flat_map(|r| {
                r.outer_iter()
                    .map(|p| [p[0], p[1], p[2], 1.0])
                    .collect::<Vec<_>>()
            })
            .collect();
        Some(Albedo {
            width: av.shape()[1] as u32,
            height: av.shape()[0] as u32,
            data,
        })
    };
    let material = Material {
        height,
        depth: item(d, "depth")?.extract()?,
        tiling: item(d, "tiling")?.extract()?,
        albedo,
    };
    let cam = item(d, "camera")?;
    let cam = cam.cast::<PyDict>()?;
    let camera = Camera {
        eye: v3(&item(cam, "eye")?)?,
        target: v3(&item(cam, "target")?)?,
        up: v3(&item(cam, "up")?)?,
        fov_y: item(cam, "fov_y")?.extract()?,
        width: item(cam, "width")?.extract()?,
        height: item(cam, "height")?.extract()?,
    };
    let mut lights = Vec::new();
    let ls = item(d, "lights")?;
    for l in ls.cast::<PyList>()?.iter() {
        let l = l.cast::<PyDict>()?.clone();
        let kind: String = item(&l, "kind")?.extract()?;
        let rgb = |x: Bound<'_, PyAny>| -> PyResult<[f32; 3]> { x.extract() };
        lights.push(match kind.as_str() {
            "directional" => Light::Directional {
                direction: v3(&item(&l, "direction")?)?,
                irradiance: rgb(item(&l, "irradiance")?)?,
                angular_diameter: item(&l, "angular_diameter")?.extract()?,
            },
            "sphere" => Light::Sphere {
                position: v3(&item(&l, "position")?)?,
                radius: item(&l, "radius")?.extract()?,
                intensity: rgb(item(&l, "intensity")?)?,
            },
            o => {
                return Err(PyValueError::new_err(format!(
                    "lights: unknown light kind {o:?}"
                )))
            }
        });
    }
    let ambient: [f32; 3] = item(d, "ambient")?.extract()?;
    Ok(Scene {
        mesh,
        material,
        camera,
        lights,
        ambient,
    })
}

fn frame_to_py<'py>(py: Python<'py>, f: Frame) -> PyResult<Bound<'py, PyDict>> {
    let (h, w) = (f.height as usize, f.width as usize);
    let e = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
    let d = PyDict::new(py);
    d.set_item(
        "color",
        Array::from_shape_vec((h, w, 3), f.color)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "uv",
        Array::from_shape_vec((h, w, 2), f.uv)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "depth",
        Array::from_shape_vec((h, w), f.depth)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "mask",
        Array::from_shape_vec((h, w), f.mask)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "steps",
        Array::from_shape_vec((h, w), f.steps)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "lod",
        Array::from_shape_vec((h, w), f.lod)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "flags",
        Array::from_shape_vec((h, w), f.flags)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item("gpu_ms", f.gpu_ms)?;
    d.set_item("wall_ms", f.wall_ms)?;
    Ok(d)
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
    /// dataclass, extracted field by field into the core's typed `Method`). Returns a dict of
    /// numpy arrays.
    fn render<'py>(
        &self,
        py: Python<'py>,
        scene: &Bound<'py, PyDict>,
        method: Method,
    ) -> PyResult<Bound<'py, PyDict>> {
        let scene = scene_from_py(scene)?;
        let r = self.inner.clone();
        let frame = py.detach(move || r.render(&scene, &method))?;
        frame_to_py(py, frame)
    }

    /// Dynamic height fields: write `new` into the GPU texture holding `old` (same size) and
    /// rebuild the pyramids on the GPU. False when `old` is not resident.
    fn update_height(
        &self,
        py: Python<'_>,
        old: PyReadonlyArray2<'_, f32>,
        new: PyReadonlyArray2<'_, f32>,
    ) -> PyResult<bool> {
        let conv = |a: &PyReadonlyArray2<'_, f32>| {
            let v = a.as_array();
            HeightMap::new(
                v.shape()[1] as u32,
                v.shape()[0] as u32,
                v.iter().copied().collect(),
            )
        };
        let (o, n) = (conv(&old)?, conv(&new)?);
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
        d.set_item("timestamps", c.timestamps)?;
        d.set_item("float32_filterable", c.float32_filterable)?;
        d.set_item(
            "max_texture_dimension_2d",
            c.limits.max_texture_dimension_2d,
        )?;
        d.set_item("max_buffer_size", c.limits.max_buffer_size)?;
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

/// The CPU float64 oracle: dict with uv (H, W, 2) f64, depth (H, W) f64, mask, cells.
#[pyfunction]
fn exact_uv<'py>(py: Python<'py>, scene: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let o = py.detach(move || exact_hits(&scene))?;
    let (h, w) = (o.height as usize, o.width as usize);
    let e = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
    let d = PyDict::new(py);
    d.set_item(
        "uv",
        Array::from_shape_vec((h, w, 2), o.uv)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "depth",
        Array::from_shape_vec((h, w), o.depth)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "mask",
        Array::from_shape_vec((h, w), o.mask)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "cells",
        Array::from_shape_vec((h, w), o.cells)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    Ok(d)
}

/// The displaced surface of `scene` as arrays (positions, shading normals, uvs, faces), with
/// `texels_per_vertex` lattice spacing.
#[pyfunction]
fn tessellate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    texels_per_vertex: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    scene.validate()?;
    let t = py.detach(move || {
        crate::geometry::tessellate::tessellate(&scene.mesh, &scene.material, texels_per_vertex)
    })?;
    let e = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
    let n = t.positions.len();
    let d = PyDict::new(py);
    d.set_item(
        "positions",
        Array::from_shape_vec((n, 3), t.positions.concat())
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "normals",
        Array::from_shape_vec((n, 3), t.normals.concat())
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "uvs",
        Array::from_shape_vec((n, 2), t.uvs.concat())
            .map_err(e)?
            .into_pyarray(py),
    )?;
    d.set_item(
        "faces",
        Array::from_shape_vec((t.indices.len() / 3, 3), t.indices)
            .map_err(e)?
            .into_pyarray(py),
    )?;
    Ok(d)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("NCS_MAP_SIZE", crate::texspace::MAP_SIZE)?;
    m.add_class::<PyRenderer>()?;
    m.add_function(wrap_pyfunction!(adapters, m)?)?;
    m.add_function(wrap_pyfunction!(exact_uv, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_from_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_generate, m)?)?;
    m.add_function(wrap_pyfunction!(tessellate, m)?)?;
    m.add("GpuError", m.py().get_type::<GpuError>())?;
    m.add("DeviceLostError", m.py().get_type::<DeviceLostError>())?;
    m.add("NoAdapterError", m.py().get_type::<NoAdapterError>())?;
    Ok(())
}

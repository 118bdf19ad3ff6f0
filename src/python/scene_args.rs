//! Scene data across the boundary: meshes (generated or from arrays), and the keyed handles
//! (`MeshData`, `HeightData`, `AlbedoData`) that the Python scene classes make once, so that a
//! render neither copies nor hashes their arrays again.

use super::nd_array;
use crate::error::Error;
use crate::mesh::{Mesh, TangentFrames};
use crate::scene::{
    shared, Albedo, Camera, HeightMap, Light, Material, Object, Scene, Shared, Transform,
};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

fn rows<const N: usize>(a: &PyReadonlyArray2<'_, f32>, name: &str) -> PyResult<Vec<[f32; N]>> {
    let v = a.as_array();
    if v.shape()[1] != N {
        return Err(crate::python::errors::argument_error(format!(
            "{name}: expected shape (n, {N}), got {:?}",
            v.shape()
        )));
    }
    Ok(v.outer_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

/// A mesh's arrays by name (the stub's `MeshArrays`): positions (n, 3), normals (n, 3), uvs
/// (n, 2), indices (m,), tangents (n, 4), uv_scale (n, 2), charts (c, 3).
pub(crate) fn mesh_out<'py>(py: Python<'py>, m: &Mesh) -> PyResult<Bound<'py, PyDict>> {
    let n = m.positions.len();
    let f = |v: Vec<f32>, k: usize| nd_array(py, (n, k), v);
    let d = PyDict::new(py);
    d.set_item("positions", f(m.positions.concat(), 3)?)?;
    d.set_item("normals", f(m.normals.concat(), 3)?)?;
    d.set_item("uvs", f(m.uvs.concat(), 2)?)?;
    d.set_item("indices", m.indices.clone().into_pyarray(py))?;
    d.set_item("tangents", f(m.tangents.concat(), 4)?)?;
    d.set_item("uv_scale", f(m.uv_scale.concat(), 2)?)?;
    d.set_item(
        "charts",
        nd_array(py, (m.charts.len(), 3), m.charts.concat())?,
    )?;
    Ok(d)
}

/// Validate mesh arrays and compute the tangent frames: the given `tangents`, or else `frames`
/// ("pomkit" or "mikktspace"). Returns the mesh's arrays by name (`mesh_out`) and the repairs
/// made: degenerate_uv_triangles, fallback_vertices.
#[pyfunction]
#[pyo3(signature = (positions, normals, uvs, indices, tangents=None, frames="pomkit"))]
pub fn mesh_from_arrays<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f32>,
    normals: PyReadonlyArray2<'py, f32>,
    uvs: PyReadonlyArray2<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    tangents: Option<PyReadonlyArray2<'py, f32>>,
    frames: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let p = rows::<3>(&positions, "positions")?;
    let n = rows::<3>(&normals, "normals")?;
    let u = rows::<2>(&uvs, "uvs")?;
    let i: Vec<u32> = indices.as_array().iter().copied().collect();
    let t = tangents
        .as_ref()
        .map(|t| rows::<4>(t, "tangents"))
        .transpose()?;
    let frames = match (t, frames) {
        (Some(t), _) => TangentFrames::Given(t),
        (None, "pomkit") => TangentFrames::Pomkit,
        (None, "mikktspace") => TangentFrames::MikkTSpace,
        (None, o) => {
            return Err(Error::arg(
                "tangents",
                format!(
                "unknown tangent frames {o:?}: give \"mikktspace\", \"pomkit\" or an (n, 4) array"
            ),
            )
            .into())
        }
    };
    let (mesh, rep) = py.detach(|| Mesh::from_arrays_with(p, n, u, i, frames))?;
    let d = mesh_out(py, &mesh)?;
    d.set_item("degenerate_uv_triangles", rep.degenerate_uv_triangles)?;
    d.set_item("fallback_vertices", rep.fallback_vertices)?;
    Ok(d)
}

/// A generated base mesh: kind in plane, sphere, torus, cylinder, cube.
#[pyfunction]
pub fn mesh_generate<'py>(
    py: Python<'py>,
    kind: &str,
    a: f64,
    b: f64,
    n1: u32,
    n2: u32,
) -> PyResult<Bound<'py, PyDict>> {
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
        .ok_or_else(|| crate::python::errors::argument_error(format!("scene description lacks {k:?}")))
}

fn v3(x: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    x.extract()
}

/// A mesh converted once and keyed (content hash) for the GPU caches: `pomkit.Mesh` makes one
/// on its first render and keeps it.
#[pyclass(name = "MeshData", module = "pomkit._core", frozen)]
pub struct PyMeshData(pub Shared<Mesh>);

#[pymethods]
impl PyMeshData {
    #[new]
    fn new(
        positions: PyReadonlyArray2<'_, f32>,
        normals: PyReadonlyArray2<'_, f32>,
        uvs: PyReadonlyArray2<'_, f32>,
        tangents: PyReadonlyArray2<'_, f32>,
        uv_scale: PyReadonlyArray2<'_, f32>,
        indices: PyReadonlyArray1<'_, u32>,
        charts: PyReadonlyArray2<'_, u32>,
    ) -> PyResult<Self> {
        let c = charts.as_array();
        if !c.is_empty() && c.shape()[1] != 3 {
            return Err(crate::python::errors::argument_error("charts: expected shape (k, 3)"));
        }
        let mesh = Mesh {
            positions: rows::<3>(&positions, "positions")?,
            normals: rows::<3>(&normals, "normals")?,
            uvs: rows::<2>(&uvs, "uvs")?,
            tangents: rows::<4>(&tangents, "tangents")?,
            uv_scale: rows::<2>(&uv_scale, "uv_scale")?,
            indices: indices.as_array().iter().copied().collect(),
            charts: c.outer_iter().map(|r| [r[0], r[1], r[2]]).collect(),
        };
        Ok(PyMeshData(shared(mesh)?))
    }
    /// The content key the GPU caches use.
    #[getter]
    fn key(&self) -> u64 {
        self.0.key
    }
}

/// A height map converted once and keyed: `pomkit.Material` makes one on its first render.
#[pyclass(name = "HeightData", module = "pomkit._core", frozen)]
pub struct PyHeightData(pub Shared<HeightMap>);

#[pymethods]
impl PyHeightData {
    #[new]
    fn new(height: PyReadonlyArray2<'_, f32>) -> PyResult<Self> {
        let v = height.as_array();
        let (h, w) = (v.shape()[0] as u32, v.shape()[1] as u32);
        let data = match v.as_slice() {
            Some(s) => s.to_vec(),
            None => v.iter().copied().collect(),
        };
        Ok(PyHeightData(shared(HeightMap::new(w, h, data)?)?))
    }
    #[getter]
    fn key(&self) -> u64 {
        self.0.key
    }
}

/// A linear RGB albedo converted once and keyed.
#[pyclass(name = "AlbedoData", module = "pomkit._core", frozen)]
pub struct PyAlbedoData(pub Shared<Albedo>);

#[pymethods]
impl PyAlbedoData {
    #[new]
    fn new(albedo: PyReadonlyArray3<'_, f32>) -> PyResult<Self> {
        let av = albedo.as_array();
        if av.shape()[2] != 3 {
            return Err(crate::python::errors::argument_error("albedo: expected shape (H, W, 3)"));
        }
        let data = av
            .outer_iter()
            .flat_map(|r| {
                r.outer_iter()
                    .map(|p| [p[0], p[1], p[2], 1.0])
                    .collect::<Vec<_>>()
            })
            .collect();
        Ok(PyAlbedoData(shared(Albedo {
            width: av.shape()[1] as u32,
            height: av.shape()[0] as u32,
            data,
        })?))
    }
    #[getter]
    fn key(&self) -> u64 {
        self.0.key
    }
}

/// One object of a scene description: its keyed mesh, height map and albedo, its material's
/// numbers and its transform (16 numbers, row-major).
fn object_from_py(d: &Bound<'_, PyDict>) -> PyResult<Object> {
    let mesh = item(d, "mesh")?.cast::<PyMeshData>()?.get().0.clone();
    let height = item(d, "height")?.cast::<PyHeightData>()?.get().0.clone();
    let albedo = item(d, "albedo")?;
    let albedo = if albedo.is_none() {
        None
    } else {
        Some(albedo.cast::<PyAlbedoData>()?.get().0.clone())
    };
    let material = Material {
        height,
        depth: item(d, "depth")?.extract()?,
        tiling: item(d, "tiling")?.extract()?,
        albedo,
    };
    let t = item(d, "transform")?;
    let transform = if t.is_none() {
        Transform::default()
    } else {
        let m: [f64; 16] = t.extract()?;
        Transform::new(glam::DMat4::from_cols_array(&m).transpose(), "transform")?
    };
    Ok(Object {
        mesh,
        material,
        transform,
    })
}

/// Build a core Scene from the dict that `pomkit.Scene._describe()` returns: the mesh, height
/// map and albedo arrive as keyed handles (shared, not copied).
pub fn scene_from_py(d: &Bound<'_, PyDict>) -> PyResult<Scene> {
    let mut objects = Vec::new();
    for o in item(d, "objects")?.cast::<PyList>()?.iter() {
        objects.push(object_from_py(o.cast::<PyDict>()?)?);
    }
    let cam = item(d, "camera")?;
    let cam = cam.cast::<PyDict>()?;
    let camera = Camera {
        eye: v3(&item(cam, "eye")?)?,
        target: v3(&item(cam, "target")?)?,
        up: v3(&item(cam, "up")?)?,
        fov_y: item(cam, "fov_y")?.extract()?,
        width: item(cam, "width")?.extract()?,
        height: item(cam, "height")?.extract()?,
        window: None,
        samples: 1,
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
                cast_shadows: item(&l, "cast_shadows")?.extract()?,
                shadow_map_size: item(&l, "shadow_map_size")?.extract()?,
            },
            "sphere" => Light::Sphere {
                position: v3(&item(&l, "position")?)?,
                radius: item(&l, "radius")?.extract()?,
                intensity: rgb(item(&l, "intensity")?)?,
            },
            o => {
                return Err(crate::python::errors::argument_error(format!(
                    "lights: unknown light kind {o:?}"
                )))
            }
        });
    }
    let ambient: [f32; 3] = item(d, "ambient")?.extract()?;
    Ok(Scene {
        objects,
        camera,
        lights,
        ambient,
    })
}

/// The scene's bounding sphere (`Scene::bounding_sphere`): ((x, y, z), radius).
#[pyfunction]
pub fn bounding_sphere(scene: &Bound<'_, PyDict>) -> PyResult<([f64; 3], f64)> {
    let (c, r) = scene_from_py(scene)?.bounding_sphere();
    Ok((c.to_array(), r))
}

/// The displaced surface of object `object` of `scene` as arrays (positions, shading normals,
/// uvs, faces, and the base frame each vertex was displaced from: base_normals, tangents,
/// uv_scale) in object space, with `texels_per_vertex` lattice spacing, each lattice quad cut by
/// `pattern` ("fan" or "grid").
#[pyfunction]
#[pyo3(signature = (scene, texels_per_vertex, object=0, pattern="fan"))]
pub fn tessellate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    texels_per_vertex: f64,
    object: usize,
    pattern: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let pattern = crate::methods::tessellated::Pattern::parse(pattern)?;
    let scene = scene_from_py(scene)?;
    scene.validate()?;
    let obj = scene.object(object)?;
    let t = py.detach(move || {
        crate::methods::tessellated::tessellate::tessellate(
            &obj.mesh,
            &obj.material,
            texels_per_vertex,
            pattern,
        )
    })?;
    let n = t.positions.len();
    let d = PyDict::new(py);
    d.set_item("positions", nd_array(py, (n, 3), t.positions.concat())?)?;
    d.set_item("normals", nd_array(py, (n, 3), t.normals.concat())?)?;
    d.set_item("uvs", nd_array(py, (n, 2), t.uvs.concat())?)?;
    d.set_item("faces", nd_array(py, (t.indices.len() / 3, 3), t.indices)?)?;
    d.set_item(
        "base_normals",
        nd_array(py, (n, 3), t.base_normals.concat())?,
    )?;
    d.set_item("tangents", nd_array(py, (n, 4), t.tangents.concat())?)?;
    d.set_item("uv_scale", nd_array(py, (n, 2), t.uv_scale.concat())?)?;
    Ok(d)
}

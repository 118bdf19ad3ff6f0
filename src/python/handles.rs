//! The keyed handles (`MeshData`, `HeightData`, `AlbedoData`) that the Python scene classes make
//! once, so that a render neither copies nor hashes their arrays again.

use crate::mesh::Mesh;
use crate::scene::{shared, Albedo, HeightMap, Shared};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;

/// An (n, N) float32 array's rows.
pub(crate) fn rows<const N: usize>(
    a: &PyReadonlyArray2<'_, f32>,
    name: &str,
) -> PyResult<Vec<[f32; N]>> {
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
            return Err(crate::python::errors::argument_error(
                "charts: expected shape (k, 3)",
            ));
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
            return Err(crate::python::errors::argument_error(
                "albedo: expected shape (H, W, 3)",
            ));
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

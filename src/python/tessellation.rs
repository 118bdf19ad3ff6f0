//! Tessellated's CPU tessellation across the boundary: the displaced surface of one of a scene's
//! objects as arrays (the mesh `pk.reference` renders).

use super::arrays::nd_array;
use super::scene_args::scene_from_py;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The displaced surface of object `object` of `scene` as arrays (positions, shading normals,
/// uvs, faces, and the base mesh's basis each vertex was displaced from: base_normals, tangents,
/// uv_scale) in object space, with `texels_per_vertex` lattice spacing, each lattice quad cut by
/// `pattern` ("fan" or "grid").
#[pyfunction]
#[pyo3(signature = (scene, texels_per_vertex, object=0, pattern="fan"))]
pub fn tessellate<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
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

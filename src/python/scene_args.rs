//! Scenes across the boundary: a `pomkit.Scene` read by attribute (its camera, lights and
//! materials through the core's schema, fields.rs; meshes and maps as keyed handles,
//! handles.rs), and meshes generated or made from arrays.

use super::fields::{attr, read};
use super::handles::{rows, PyMeshData};
use super::arrays::nd_array;
use crate::error::Error;
use crate::mesh::{Mesh, TangentBases};
use crate::scene::{
    Camera, DirectionalLight, Light, Material, Object, Scene, Shared, SphereLight, Transform,
};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

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

/// Validate mesh arrays and compute the tangent bases: the given `tangents`, or else `frames`
/// ("pomkit" or "mikktspace"). Returns the mesh's arrays by name (`mesh_out`) and the repairs
/// made: degenerate_uv_triangles, fallback_vertices, replaced_normals (as `normals_mode` asked:
/// "file", "recompute" or "repair", `mesh::normals`).
#[pyfunction]
#[pyo3(signature = (positions, normals, uvs, indices, tangents=None, frames="pomkit", normals_mode="file"))]
pub fn mesh_from_arrays<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f32>,
    normals: PyReadonlyArray2<'py, f32>,
    uvs: PyReadonlyArray2<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    tangents: Option<PyReadonlyArray2<'py, f32>>,
    frames: &str,
    normals_mode: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = crate::mesh::normals::NormalsMode::parse(normals_mode)?;
    let p = rows::<3>(&positions, "positions")?;
    let mut n = rows::<3>(&normals, "normals")?;
    let u = rows::<2>(&uvs, "uvs")?;
    let i: Vec<u32> = indices.as_array().iter().copied().collect();
    let replaced = crate::mesh::normals::apply(mode, &p, &mut n, &i, "")?;
    let t = tangents
        .as_ref()
        .map(|t| rows::<4>(t, "tangents"))
        .transpose()?;
    let frames = match (t, frames) {
        (Some(t), _) => TangentBases::Given(t),
        (None, "pomkit") => TangentBases::Pomkit,
        (None, "mikktspace") => TangentBases::MikkTSpace,
        (None, o) => {
            return Err(Error::arg(
                "tangents",
                format!(
                "unknown tangent bases {o:?}: give \"mikktspace\", \"pomkit\" or an (n, 4) array"
            ),
            )
            .into())
        }
    };
    let (mesh, rep) = py.detach(|| Mesh::from_arrays_with(p, n, u, i, frames))?;
    let d = mesh_out(py, &mesh)?;
    d.set_item("degenerate_uv_triangles", rep.degenerate_uv_triangles)?;
    d.set_item("fallback_vertices", rep.fallback_vertices)?;
    d.set_item("replaced_normals", replaced)?;
    Ok(d)
}

/// The generated base meshes (`Mesh::plane`, ...), each by its parameters' names.
#[pyfunction]
pub fn mesh_plane(py: Python<'_>, size: f64, segments: u32) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::plane(size, segments)?)
}

#[pyfunction]
pub fn mesh_sphere(
    py: Python<'_>,
    radius: f64,
    segments: u32,
    rings: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::sphere(radius, segments, rings)?)
}

#[pyfunction]
pub fn mesh_torus(
    py: Python<'_>,
    major: f64,
    minor: f64,
    segments: u32,
    tube_segments: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::torus(major, minor, segments, tube_segments)?)
}

#[pyfunction]
pub fn mesh_cylinder(
    py: Python<'_>,
    radius: f64,
    height: f64,
    segments: u32,
    rings: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::cylinder(radius, height, segments, rings)?)
}

#[pyfunction]
pub fn mesh_cube(py: Python<'_>, size: f64, segments: u32) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::cube(size, segments)?)
}

/// The mesh's keyed handle, which `pomkit.Mesh` makes once (`Mesh._core_data()`).
fn mesh_handle(ob: &Bound<'_, PyAny>) -> PyResult<Shared<Mesh>> {
    let h = ob
        .call_method0("_core_data")
        .map_err(|_| Error::arg("mesh", "expected a pomkit.Mesh"))?;
    Ok(h.cast_into::<PyMeshData>()?.get().0.clone())
}

/// One `pomkit.Object`: its mesh's keyed handle and transform (a 4x4 array) as the object
/// orients them (`_oriented`: never mirroring), and its material (a schema class).
fn object_from_py(o: &Bound<'_, PyAny>) -> PyResult<Object> {
    let what = "a pomkit.Object";
    let (mesh, t): (Bound<'_, PyAny>, Bound<'_, PyAny>) = attr(o, "_oriented", what)?
        .extract()
        .map_err(|_| Error::arg("objects", "expected pomkit.Object instances"))?;
    let mesh = mesh_handle(&mesh)?;
    let material: Material = read(&attr(o, "material", what)?, "a pomkit.Material")?;
    let rows: [[f64; 4]; 4] = t
        .extract()
        .or_else(|_| t.call_method0("tolist")?.extract())
        .map_err(|_| Error::arg("transform", "expected a 4x4 matrix"))?;
    let m4 = glam::DMat4::from_cols_array_2d(&rows).transpose();
    let transform = if m4 == glam::DMat4::IDENTITY {
        Transform::default()
    } else {
        Transform::new(m4, "transform")?
    };
    Ok(Object {
        mesh,
        material,
        transform,
        contacts: Default::default(),
    })
}

/// One light: the schema class its `_schema` attribute names.
fn light_from_py(l: &Bound<'_, PyAny>) -> PyResult<Light> {
    let kind: String = l
        .getattr("_schema")
        .and_then(|k| k.extract())
        .map_err(|_| {
            Error::arg(
                "lights",
                format!("expected pomkit.DirectionalLight or pomkit.SphereLight, got {l}"),
            )
        })?;
    use crate::scene::schema::Schema;
    Ok(match kind.as_str() {
        DirectionalLight::CLASS => Light::Directional(read(l, "a pomkit.DirectionalLight")?),
        SphereLight::CLASS => Light::Sphere(read(l, "a pomkit.SphereLight")?),
        o => return Err(Error::arg("lights", format!("unknown light class {o:?}")).into()),
    })
}

/// What a light delivers, tint included (`Light::power`): linear RGB irradiance or intensity.
#[pyfunction]
pub fn light_power(light: &Bound<'_, PyAny>) -> PyResult<[f32; 3]> {
    Ok(light_from_py(light)?.power())
}

/// A `pomkit.Scene` as the core's Scene, read attribute by attribute: the mesh, height map and
/// albedo arrive as keyed handles (shared, not copied).
pub fn scene_from_py(s: &Bound<'_, PyAny>) -> PyResult<Scene> {
    let what = "a pomkit.Scene";
    let mut objects = Vec::new();
    for o in attr(s, "objects", what)?.try_iter()? {
        objects.push(object_from_py(&o?)?);
    }
    let camera: Camera = read(&attr(s, "camera", what)?, "a pomkit.Camera")?;
    let mut lights = Vec::new();
    for l in attr(s, "lights", what)?.try_iter()? {
        lights.push(light_from_py(&l?)?);
    }
    let ambient = attr(s, "ambient", what)?;
    let ambient: [f32; 3] = ambient.extract().map_err(|_| {
        Error::arg(
            "ambient",
            format!("expected three numbers (linear RGB), got {ambient}"),
        )
    })?;
    Ok(Scene {
        objects,
        camera,
        lights,
        ambient,
    })
}

/// The scene's bounding sphere (`Scene::bounding_sphere`): ((x, y, z), radius).
#[pyfunction]
pub fn bounding_sphere(scene: &Bound<'_, PyAny>) -> PyResult<([f64; 3], f64)> {
    let (c, r) = scene_from_py(scene)?.bounding_sphere();
    Ok((c.to_array(), r))
}

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

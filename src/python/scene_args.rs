//! Scenes across the boundary: a `pomkit.Scene` read by attribute (its camera, lights and
//! materials through the core's schema, fields.rs; meshes and maps as keyed handles,
//! handles.rs), and what the core answers of one without rendering it (a light's power, the
//! scene's bounding sphere).

use super::fields::{attr, read};
use super::handles::PyMeshData;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::scene::{
    Camera, DirectionalLight, Light, Material, Object, Scene, Shared, SphereLight, Transform,
};
use pyo3::prelude::*;

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

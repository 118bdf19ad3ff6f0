//! Hooks for the tests (Rust and Python), kept apart from the Renderer's API: a validation
//! error provoked inside the error scopes, the GPU's pyramids read back, a method's resources
//! built as a render builds them.

use super::{poisoned, Renderer};
use crate::contract::Resident;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::methods::Method;
use crate::scene::{shared, Camera, HeightMap, Keyed, Material, Scene};

/// Issue an invalid wgpu call (a buffer both MAP_READ and MAP_WRITE) inside the error
/// scopes: used by tests to check that validation errors surface as `Error::Gpu` and leave
/// the renderer usable.
pub fn provoke_validation_error(r: &Renderer) -> Result<()> {
    r.ctx.scoped(|| {
        let _b = r.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("invalid on purpose"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
            mapped_at_creation: false,
        });
        Ok(())
    })
}

/// The GPU's pyramids for a map (tests): (mean mips, max mips).
#[allow(clippy::type_complexity)]
pub fn read_pyramids(
    r: &Renderer,
    map: &Keyed<HeightMap>,
) -> Result<(Vec<Vec<f32>>, Vec<Vec<f32>>)> {
    let g = r
        .resources
        .lock()
        .map_err(poisoned)?
        .height(&r.ctx, &r.mips, map)?;
    Ok((
        r.mips.read_back(&r.ctx, &g, false)?,
        r.mips.read_back(&r.ctx, &g, true)?,
    ))
}

/// The GPU's children atlas for a map (tests): `MipBuilder::read_children`.
pub fn read_children(r: &Renderer, map: &Keyed<HeightMap>) -> Result<Vec<Vec<[u8; 4]>>> {
    let g = r
        .resources
        .lock()
        .map_err(poisoned)?
        .height(&r.ctx, &r.mips, map)?;
    r.mips.read_children(&r.ctx, &g)
}

/// A method's own resources for object 0 of `scene` (tests and inspection: e.g. to read a
/// built table back), built as a render would build them.
pub fn method_resources(r: &Renderer, scene: &Scene, method: &Method) -> Result<Vec<Resident>> {
    let spec = method.spec();
    let obj = scene
        .objects
        .first()
        .ok_or_else(|| Error::arg("scene", "has no object"))?;
    let mut res = r.resources.lock().map_err(poisoned)?;
    let (_, _, own) = r.object_resources(&mut res, obj, &spec)?;
    Ok(own.map(|o| o.to_vec()).unwrap_or_default())
}

/// A scene of one object (`mesh` with the height map `height`, depth 0.1, one tile), an 8 x 8
/// camera and no light: enough to build a method's own resources with `method_resources`.
pub fn resource_scene(mesh: Mesh, height: HeightMap) -> Result<Scene> {
    Ok(Scene::single(
        shared(mesh)?,
        Material {
            height: shared(height)?,
            depth: 0.1,
            tiling: 1.0,
            albedo: None,
        },
        Camera {
            eye: [0.0, 2.0, 1.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y: 30.0,
            width: 8,
            height: 8,
            window: None,
            samples: 1,
        },
        vec![],
        [0.0; 3],
    ))
}

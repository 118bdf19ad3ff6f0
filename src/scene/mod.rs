//! Plain validated scene data: mesh, material, camera, lights. Nothing here touches the GPU.

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use glam::{DMat4, DVec3, DVec4};
use std::hash::{Hash, Hasher};

mod camera;
pub mod schema;
pub use camera::{Camera, CameraBasis, Window};
pub use crate::heightmap::field::HeightMap;
pub(crate) use crate::heightmap::field::floor;
use std::sync::Arc;

/// A hash of byte slices (with their lengths): the content keys of the GPU caches.
pub fn hash_bytes(parts: &[&[u8]]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in parts {
        p.len().hash(&mut h);
        p.hash(&mut h);
    }
    h.finish()
}

/// Data whose content key the GPU caches look up, checked once when it is shared.
pub trait ContentKey {
    fn content_key(&self) -> u64;
    fn check(&self) -> Result<()>;
}

/// Immutable scene data with its content key, hashed once when it is made (not per render) and
/// shared between scenes and frames without copies.
#[derive(Debug)]
pub struct Keyed<T> {
    value: T,
    pub key: u64,
}

/// Shared keyed data: what a `Scene` holds for its mesh, height map and albedo.
pub type Shared<T> = Arc<Keyed<T>>;

/// Check and key `value` once, and share it.
pub fn shared<T: ContentKey>(value: T) -> Result<Shared<T>> {
    value.check()?;
    let key = value.content_key();
    Ok(Arc::new(Keyed { value, key }))
}

impl<T> std::ops::Deref for Keyed<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.value
    }
}

/// A 2-D image's key (size and texels) and size check, shared by height maps and albedos.
fn image_key<T: bytemuck::Pod>(w: u32, h: u32, data: &[T]) -> u64 {
    hash_bytes(&[
        &w.to_le_bytes(),
        &h.to_le_bytes(),
        bytemuck::cast_slice(data),
    ])
}

fn check_image_size(arg: &str, w: u32, h: u32, len: usize) -> Result<()> {
    if w == 0 || h == 0 || len != (w as usize) * (h as usize) {
        return Err(Error::arg(
            arg,
            format!("must be a non-empty image whose data matches its size {w}x{h}"),
        ));
    }
    Ok(())
}

impl ContentKey for HeightMap {
    /// `HeightMap::new` checks the values; this checks the size of maps built by hand.
    fn check(&self) -> Result<()> {
        check_image_size("height", self.width, self.height, self.data.len())
    }
    fn content_key(&self) -> u64 {
        image_key(self.width, self.height, &self.data)
    }
}

impl ContentKey for Albedo {
    fn check(&self) -> Result<()> {
        check_image_size("albedo", self.width, self.height, self.data.len())?;
        if self.data.iter().any(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(Error::arg("albedo", "contains NaN or Inf"));
        }
        Ok(())
    }
    fn content_key(&self) -> u64 {
        image_key(self.width, self.height, &self.data)
    }
}

/// A mesh's arrays hashed in place (no vertex array is built).
impl ContentKey for Mesh {
    fn check(&self) -> Result<()> {
        self.validate()
    }
    fn content_key(&self) -> u64 {
        hash_bytes(&[
            bytemuck::cast_slice(&self.positions),
            bytemuck::cast_slice(&self.normals),
            bytemuck::cast_slice(&self.uvs),
            bytemuck::cast_slice(&self.tangents),
            bytemuck::cast_slice(&self.uv_scale),
            bytemuck::cast_slice(&self.indices),
        ])
    }
}

/// Linear RGB albedo texture, row-major like the height map.
#[derive(Clone, Debug)]
pub struct Albedo {
    pub width: u32,
    pub height: u32,
    pub data: Vec<[f32; 4]>,
}

crate::schema! {
    /// Height map and albedo.
    ///
    /// height: (H, W) float32 in [0, 1] (uint8 and uint16 are normalised); h = 1 is the base
    /// surface, h = 0 lies `depth` world units below it. albedo: (H, W, 3) sRGB uint8 or linear
    /// float32; None is a constant linear 0.5 grey. tiling: repetitions of the maps over the
    /// mesh's uv square.
    pub struct Material {
        /// the height map, h = 1 at the base surface
        pub height: Shared<HeightMap> = Height;
        /// the distance between h = 1 (the base surface) and h = 0, in object units
        pub depth: f32 = Real(0.0, 1e30), "0.08";
        /// the albedo (None: a constant linear 0.5 grey)
        pub albedo: Option<Shared<Albedo>> = Albedo, "None";
        /// repetitions of the maps over the mesh's uv square
        pub tiling: f32 = Real(1e-12, 1e6), "1.0";
    }
}

impl Material {
    /// Its fields against the table (the height map and albedo were checked when shared).
    pub fn validate(&self) -> Result<()> {
        self.check_fields()
    }
}

crate::schema! {
    /// A distant light. `direction` is the way the light travels (as in Mitsuba); `irradiance`
    /// (linear RGB or a scalar) is measured on a surface facing the light; `angular_diameter`
    /// (degrees) is the apparent size of the source, which the soft shadows estimate.
    ///
    /// cast_shadows: the objects shadow each other from this light through a shadow map in which
    /// each object casts with its displaced surface (the method itself, run in a depth-only pass);
    /// a surface receives it at its displaced hit point. Only the first directional light with
    /// cast_shadows=True casts; `SphereLight`s never do. A method's own `shadows=` (self-shadowing
    /// of its height field) multiplies with it. shadow_map_size: the map's size in texels (square,
    /// orthographic, fitted to the scene's bounding sphere; clamped to the device's limit), also
    /// used by `Tessellated`'s own shadows; docs/objects.md measures what it does to shadow edges.
    pub struct DirectionalLight {
        /// the way the light travels (a non-zero vector)
        pub direction: [f64; 3] = Vec3;
        /// linear RGB irradiance on a surface facing the light (a scalar for grey)
        pub irradiance: [f32; 3] = Rgb, "1.0";
        /// the source's apparent size in degrees (0: a point-like source)
        pub angular_diameter: f64 = Real(0.0, 179.999), "0.0";
        /// objects shadow each other from this light through a shadow map
        pub cast_shadows: bool = Bool, "False" @ setting;
        /// the shadow map's size in texels (square; clamped to the device's limit)
        pub shadow_map_size: u32 = Integer(16, 16384), "1024" @ setting;
        /// a linear RGB tint that multiplies `irradiance` (glTF KHR_lights_punctual's `color`)
        pub color: [f32; 3] = Rgb, "1.0";
    }
}

crate::schema! {
    /// A spherical area light at `position` with `radius` and radiant intensity `intensity`
    /// (W/sr, linear RGB or scalar): irradiance I / r^2 on a surface facing it at distance r. Its
    /// radiance is I / (pi radius^2) (Mitsuba: a `sphere` shape with an `area` emitter).
    pub struct SphereLight {
        /// the sphere's centre
        pub position: [f64; 3] = Vec3;
        /// the sphere's radius (0: a point light)
        pub radius: f64 = Real(0.0, 1e30), "0.05";
        /// linear RGB radiant intensity in W/sr (a scalar for grey)
        pub intensity: [f32; 3] = Rgb, "1.0";
        /// a linear RGB tint that multiplies `intensity` (glTF KHR_lights_punctual's `color`)
        pub color: [f32; 3] = Rgb, "1.0";
    }
}

/// A scene's light: one of the schema's light classes.
#[derive(Clone, Debug)]
pub enum Light {
    Directional(DirectionalLight),
    Sphere(SphereLight),
}

impl Light {
    /// What the light delivers, tint included: a directional light's irradiance, a sphere
    /// light's intensity (W/sr), in linear RGB.
    pub fn power(&self) -> [f32; 3] {
        let (e, c) = match self {
            Light::Directional(l) => (l.irradiance, l.color),
            Light::Sphere(l) => (l.intensity, l.color),
        };
        [e[0] * c[0], e[1] * c[1], e[2] * c[2]]
    }

    pub fn validate(&self) -> Result<()> {
        match self {
            Light::Directional(l) => {
                l.check_fields()?;
                if DVec3::from(l.direction).length() < 1e-12 {
                    return Err(Error::arg("direction", "must be a non-zero vector"));
                }
            }
            Light::Sphere(l) => l.check_fields()?,
        }
        Ok(())
    }
}

/// The most lights a scene takes: the one source of the shaders' light array (the MAX_LIGHTS
/// shader def) and of Python's `pomkit._core.MAX_LIGHTS`.
pub const MAX_LIGHTS: usize = 4;

/// An object-to-world transform: an affine 4x4 matrix that keeps orientation (it may scale
/// non-uniformly; a mirror is refused, and `pomkit.Object` reflects the mesh instead). Positions
/// map by `m`, directions by its linear part, normals by the inverse transpose. The displacement
/// `depth` is in object units: the displaced surface is `m` applied to the object-space one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: DMat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self { m: DMat4::IDENTITY }
    }
}

impl Transform {
    /// An affine, finite, invertible matrix; `arg` names the argument in errors.
    pub fn new(m: DMat4, arg: &str) -> Result<Self> {
        if !m.is_finite() {
            return Err(Error::arg(arg, "must be finite (it holds NaN or Inf)"));
        }
        let r = m.row(3);
        if r != DVec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(Error::arg(
                arg,
                format!("must be affine: its last row must be [0, 0, 0, 1], got {r:?}"),
            ));
        }
        // singular (or nearly): the scale of the smallest axis against the largest
        let lin = glam::DMat3::from_mat4(m);
        let scale = lin
            .x_axis
            .length()
            .max(lin.y_axis.length())
            .max(lin.z_axis.length());
        // (m is finite, so the determinant is a number)
        if scale == 0.0 || lin.determinant().abs() <= 1e-12 * scale.powi(3) {
            return Err(Error::arg(
                arg,
                "is singular (it flattens the object); give an invertible matrix",
            ));
        }
        if lin.determinant() < 0.0 {
            // fronts would turn clockwise under it, and every pass culls and builds its bases
            // for counter-clockwise fronts
            return Err(Error::arg(
                arg,
                "mirrors (its determinant is negative); give the mesh reflected through x = 0 with its winding and tangent handedness reversed, under the transform times diag(-1, 1, 1) (pomkit.Object does this)",
            ));
        }
        Ok(Self { m })
    }
    pub fn is_identity(&self) -> bool {
        self.m == DMat4::IDENTITY
    }
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.m.transform_point3(p)
    }
    /// The largest factor by which the transform stretches a length (its largest singular
    /// value, by power iteration on the linear part's Gram matrix).
    pub fn max_scale(&self) -> f64 {
        if self.is_identity() {
            return 1.0;
        }
        let l = glam::DMat3::from_mat4(self.m);
        let g = l.transpose() * l;
        let mut v = DVec3::new(0.577, 0.577, 0.578);
        let mut s2 = 0.0;
        for _ in 0..64 {
            let w = g * v;
            s2 = w.length();
            if s2 == 0.0 {
                return 0.0;
            }
            v = w / s2;
        }
        s2.sqrt()
    }
}

/// One object of a scene: a base mesh, its material, and where it stands.
#[derive(Clone, Debug)]
pub struct Object {
    pub mesh: Shared<Mesh>,
    pub material: Material,
    pub transform: Transform,
    /// the other objects' open borders that meet this one's (`mesh::borders::contacts`):
    /// empty as a scene is read; the renderer finds them for a geometry that asks
    /// (`MethodGeometry::uses_contacts`)
    pub contacts: crate::mesh::borders::Contacts,
}

impl Object {
    /// The world box of the base mesh's vertices, and the world distance the displacement can
    /// move a point (`depth` times the transform's largest stretch).
    pub fn bounds(&self) -> (DVec3, DVec3, f64) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        if self.transform.is_identity() {
            (lo, hi) = self.mesh.bounds();
        } else {
            for p in &self.mesh.positions {
                let w = self
                    .transform
                    .point(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
                lo = lo.min(w);
                hi = hi.max(w);
            }
        }
        (
            lo,
            hi,
            self.material.depth as f64 * self.transform.max_scale(),
        )
    }
}

/// The most objects a scene may hold (object ids are stored in 32 bits; this bounds the draws).
pub const MAX_OBJECTS: usize = 4096;

#[derive(Clone, Debug)]
pub struct Scene {
    /// at least one; an object's index is its id in the `object` AOV
    pub objects: Vec<Object>,
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// constant environment radiance, linear RGB
    pub ambient: [f32; 3],
}

impl Scene {
    /// A sphere (centre, radius) holding every object's displaced surface: the clip range, the
    /// shadow map's fit and the reference's far lights all read it (one home).
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        if let [o] = self.objects.as_slice() {
            // one object: its box, grown by the displacement in every direction
            let (lo, hi, d) = o.bounds();
            return ((lo + hi) * 0.5, (hi - lo).length() * 0.5 + d + 1e-3);
        }
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for o in &self.objects {
            let (a, b, d) = o.bounds();
            lo = lo.min(a - DVec3::splat(d));
            hi = hi.max(b + DVec3::splat(d));
        }
        ((lo + hi) * 0.5, (hi - lo).length() * 0.5 + 1e-3)
    }

    /// A scene of one object at the origin (no transform).
    pub fn single(
        mesh: Shared<Mesh>,
        material: Material,
        camera: Camera,
        lights: Vec<Light>,
        ambient: [f32; 3],
    ) -> Self {
        Scene {
            objects: vec![Object {
                mesh,
                material,
                transform: Transform::default(),
                contacts: Default::default(),
            }],
            camera,
            lights,
            ambient,
        }
    }

    /// The only object, for what is defined on one object (the CPU oracle, the displaced mesh);
    /// `what` names the caller in the error.
    /// Object `i` of the scene, or an error on the argument `object` that says how many there are.
    pub fn object(&self, i: usize) -> Result<&Object> {
        self.objects.get(i).ok_or_else(|| {
            Error::arg(
                "object",
                format!("the scene has {} objects", self.objects.len()),
            )
        })
    }

    pub fn only_object(&self, what: &str) -> Result<&Object> {
        match self.objects.as_slice() {
            [o] => Ok(o),
            _ => Err(Error::arg(
                "scene",
                format!(
                    "{what} takes a scene of one object, got {}; render the objects one by one",
                    self.objects.len()
                ),
            )),
        }
    }

    /// The checks of the per-render parameters (the shared data was checked when it was made).
    pub fn validate(&self) -> Result<()> {
        if self.objects.is_empty() {
            return Err(Error::arg(
                "objects",
                "is empty; give at least one pomkit.Object",
            ));
        }
        if self.objects.len() > MAX_OBJECTS {
            return Err(Error::arg(
                "objects",
                format!(
                    "at most {MAX_OBJECTS} objects are supported, got {}",
                    self.objects.len()
                ),
            ));
        }
        for o in &self.objects {
            o.material.validate()?;
            Transform::new(o.transform.m, "transform")?;
        }
        self.camera.validate()?;
        if self.lights.len() > MAX_LIGHTS {
            return Err(Error::arg(
                "lights",
                format!(
                    "at most {MAX_LIGHTS} lights are supported, got {}",
                    self.lights.len()
                ),
            ));
        }
        for l in &self.lights {
            l.validate()?;
        }
        if self.ambient.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return Err(Error::arg("ambient", "must be finite and >= 0"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A transform that mirrors is refused with the remedy; one that keeps orientation (scaled,
    /// rotated, translated) is taken.
    #[test]
    fn a_mirroring_transform_is_refused_with_the_remedy() {
        let m = DMat4::from_scale(DVec3::new(-1.0, 2.0, 1.0));
        let e = Transform::new(m, "transform").unwrap_err().to_string();
        assert!(e.contains("transform") && e.contains("mirrors") && e.contains("diag(-1, 1, 1)"), "{e}");
        let ok = DMat4::from_scale_rotation_translation(
            DVec3::new(1.0, 2.0, 3.0),
            glam::DQuat::from_rotation_y(0.7),
            DVec3::new(1.0, 0.0, -2.0),
        );
        assert!(Transform::new(ok, "transform").is_ok());
    }
}

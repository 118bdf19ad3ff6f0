//! The renderer-method contract, at the bottom of the crate: what a method declares (its shader,
//! its shader defs, its geometry, its uniform block, the per-pixel options it takes) and what the
//! renderer runs from it. `shaders`, `render` and `methods` all depend on this module; it depends
//! on none of them (tests/test_layers.py holds the module graph acyclic).

use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::scene::Object;
use std::any::Any;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Loops a shader may run per pixel: more would risk the driver's watchdog.
pub const MAX_STEPS_LIMIT: u32 = 4096;

/// WINDOW's vertex attribute (src/methods/hybrid writes it, surface.wgsl reads it): the nearest
/// of its two floors holds for a ray that stays within 1 / WINDOW_NEAR_SHARE_DIV of its reach
/// (the shader def of that name).
pub const WINDOW_NEAR_SHARE_DIV: u32 = 16;

pub use crate::fields::{FieldValue, Fields, FromFields};

/// A parameter struct whose fields are read from `Fields` by their names (the dataclass's).
#[macro_export]
macro_rules! params {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty,)* }) => {
        $(#[$m])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $name {
            $($(#[$fm])* pub $f: $t,)*
        }

        impl $crate::fields::FromFields for $name {
            #[allow(unused_variables)]
            fn from_fields(src: &dyn $crate::fields::Fields) -> $crate::error::Result<Self> {
                Ok($name {
                    $($f: <$t as $crate::fields::FieldValue>::get(src, stringify!($f))?,)*
                })
            }
        }

        impl $name {
            /// The fields the core reads, by name, in order.
            pub const FIELDS: &'static [&'static str] = &[$(stringify!($f),)*];
        }
    };
}

/// An option of string values: the enum, its values as `NAMES` (exported to Python as the one
/// source of the `Literal`s), and `parse` with an error that names the argument and the values.
#[macro_export]
macro_rules! option_enum {
    ($(#[$m:meta])* $name:ident, $arg:literal, { $($variant:ident = $value:literal,)* }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $name {
            $($variant,)*
        }

        impl $crate::fields::FieldValue for $name {
            fn get(f: &dyn $crate::fields::Fields, name: &str) -> $crate::error::Result<Self> {
                Self::parse(&f.str(name)?)
            }
        }

        impl $name {
            /// The values a user passes, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($value,)*];
            pub fn parse(s: &str) -> $crate::error::Result<Self> {
                match s {
                    $($value => Ok($name::$variant),)*
                    o => Err($crate::error::Error::arg(
                        $arg,
                        format!("must be one of {}, got {o:?}", Self::NAMES.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(", ")),
                    )),
                }
            }
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $value,)*
                }
            }
            /// The value as a WGSL shader def: the argument and the value, upper case
            /// ("SHADOWS_HORIZON", "REFINE_EXACT"), defined (true) in the variant that takes it.
            pub fn shader_def(self) -> &'static str {
                static DEFS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
                DEFS.get_or_init(|| {
                    Self::NAMES.iter().map(|v| format!("{}_{}", $arg, v).to_uppercase()).collect()
                })[self as usize]
                    .as_str()
            }
        }
    };
}

option_enum!(
    /// Self-shadowing of the per-pixel methods.
    Shadows, "shadows", {
        None = "none",
        Hard = "hard",
        Soft = "soft",
        Horizon = "horizon",
        Exact = "exact",
    }
);

option_enum!(
    /// Height sampling: the sampler's bilinear filter, or four loads and a float32 lerp.
    Filtering, "filtering", {
        Hardware = "hardware",
        Exact = "exact",
    }
);

params! {
    /// The options every per-pixel method shares (shadows, filtering, AO).
    pub struct PerPixel {
        pub shadows: Shadows,
        pub shadow_steps: u32,
        pub filtering: Filtering,
        /// sample the footprint's mip level (Tatarchuk's tex2Dgrad); false: level 0
        pub mip_filtering: bool,
        /// horizon AO directions (0 = off)
        pub ao_directions: u32,
        /// horizon samples at 2^k texels, k < horizon_samples ("horizon" shadows and AO)
        pub horizon_samples: u32,
    }
}

impl PerPixel {
    /// No shadows, no AO, hardware filtering of the footprint's level. (The user-facing
    /// defaults live in the Python dataclasses.)
    pub fn off() -> Self {
        PerPixel {
            shadows: Shadows::None,
            shadow_steps: 8,
            filtering: Filtering::Hardware,
            mip_filtering: true,
            ao_directions: 0,
            horizon_samples: 8,
        }
    }
    pub fn with_shadows(self, shadows: Shadows) -> Self {
        PerPixel { shadows, ..self }
    }
    pub fn validate(&self) -> Result<()> {
        check_range("shadow_steps", self.shadow_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("ao_directions", self.ao_directions, 0, 64)?;
        check_range("horizon_samples", self.horizon_samples, 1, 16)
    }
}

pub fn check_range(name: &str, v: u32, lo: u32, hi: u32) -> Result<()> {
    if v < lo || v > hi {
        return Err(Error::arg(
            name,
            format!("must lie in [{lo}, {hi}], got {v}"),
        ));
    }
    Ok(())
}

/// A WGSL source the composer registers under an import path.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderUnit {
    /// naga_oil import path, e.g. `pomkit::methods::pom`
    pub path: String,
    /// the file name shown in compile errors
    pub file: String,
    pub source: std::borrow::Cow<'static, str>,
    /// modules of the method's own that this one imports (registered before it)
    pub deps: Vec<ShaderUnit>,
}

impl ShaderUnit {
    pub fn builtin(path: &str, file: &str, source: &'static str) -> Self {
        ShaderUnit {
            path: path.to_string(),
            file: file.to_string(),
            source: std::borrow::Cow::Borrowed(source),
            deps: Vec::new(),
        }
    }
    pub fn with_deps(mut self, deps: Vec<ShaderUnit>) -> Self {
        self.deps = deps;
        self
    }
}

/// The shader of a built-in method: `pomkit::methods::<name>`, from `<name>.wgsl` beside the Rust
/// file that names it (one name, not three).
#[macro_export]
macro_rules! method_shader {
    ($name:literal) => {
        $crate::contract::ShaderUnit::builtin(
            concat!("pomkit::methods::", $name),
            &$crate::contract::beside(file!(), concat!($name, ".wgsl")),
            include_str!(concat!($name, ".wgsl")),
        )
    };
}

/// The path of `name` in the folder of the source file `rs` (error messages name shaders so).
pub fn beside(rs: &str, name: &str) -> String {
    std::path::Path::new(rs)
        .with_file_name(name)
        .to_string_lossy()
        .into_owned()
}

/// What composes WGSL with pomkit's library (implemented by `shaders::ShaderLib`): a method's
/// builder composes its compute passes through it.
pub trait Composer: Send + Sync {
    /// Register a module (and its deps) so that others can import it; once per import path.
    fn register(&self, unit: &ShaderUnit) -> Result<()>;
    /// A top-level pass (compute or render) that imports the library and registered modules.
    fn compose_pass(&self, source: &str, file: &str) -> Result<naga::Module>;
}

/// Which pass draws the method.
#[derive(Clone, Debug, PartialEq)]
pub enum Pass {
    /// surface.wgsl, which imports `method` as `method`: a method that `marches` defines
    /// `fn march(r: Ray) -> Hit` (shader def MARCH); one that does not shades the rasterised
    /// surface itself, `fn shade_surface(f: Basis, s: vec2<f32>, p: vec3<f32>, lod: f32,
    /// px: vec2<f32>) -> Shaded` (shader def SHADE), and the shadow map takes its rasterised depth
    Surface { method: ShaderUnit, marches: bool },
    /// a top-level shader of the method's own
    Own {
        shader: ShaderUnit,
        vs: &'static str,
        fs: &'static str,
        /// the shadow-map pass's entry points (depth only: the fragment writes the hit's depth)
        shadow_vs: &'static str,
        shadow_fs: &'static str,
    },
}

/// A mesh on the GPU: vertices, indices (None: a non-indexed draw), and the buffers or textures
/// its builder made beside them for the method's resources to bind.
pub struct GpuMesh {
    pub vbuf: wgpu::Buffer,
    pub ibuf: Option<wgpu::Buffer>,
    pub count: u32,
    pub extra: Vec<Resident>,
}

impl GpuMesh {
    /// Upload an indexed mesh; `arg` names what a user changes when it exceeds the device's
    /// buffer limit.
    pub fn upload_indexed<V: bytemuck::Pod>(
        ctx: &Context,
        verts: &[V],
        indices: &[u32],
        arg: &str,
    ) -> Result<GpuMesh> {
        let vbytes = std::mem::size_of_val(verts) as u64;
        if vbytes > ctx.limits.max_buffer_size {
            return Err(Error::limit(
                arg,
                format!(
                    "the mesh needs a {vbytes}-byte vertex buffer; the device's max_buffer_size is {}",
                    ctx.limits.max_buffer_size
                ),
            ));
        }
        ctx.scoped(|| {
            let vbuf = ctx.upload(
                "vertices",
                bytemuck::cast_slice(verts),
                // STORAGE: the compute pipeline reads the mesh (shaders/visibility.wgsl)
                wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
            );
            let ibuf = ctx.upload(
                "indices",
                bytemuck::cast_slice(indices),
                wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
            );
            Ok(GpuMesh {
                vbuf,
                ibuf: Some(ibuf),
                count: indices.len() as u32,
                extra: Vec::new(),
            })
        })
    }
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vbuf.slice(..));
        match &self.ibuf {
            Some(ib) => {
                pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.count, 0, 0..1);
            }
            None => pass.draw(0..self.count, 0..1),
        }
    }
}

/// A mesh a method builds for itself from an object (instead of drawing the base mesh).
pub trait MethodGeometry: std::fmt::Debug + Send + Sync {
    /// What the mesh is built from, as a cache key (the renderer keeps the upload).
    fn key(&self, object: &Object) -> u64;
    fn build(&self, ctx: &Context, object: &Object) -> Result<GpuMesh>;
    fn vertex_layout(&self) -> wgpu::VertexBufferLayout<'static>;
    /// Cull back faces in the shadow-map pass (a closed shell casts from its entry faces);
    /// otherwise a mesh casts from both sides.
    fn shadow_cull_back(&self) -> bool {
        false
    }
    /// Build from the object with its contacts found (the other objects' open borders that
    /// meet its own: `Object::contacts`); they are part of the key.
    fn uses_contacts(&self) -> bool {
        false
    }
}

/// The mesh the pass rasterises.
#[derive(Clone, Debug)]
pub enum Geometry {
    /// the base mesh
    Base,
    /// a mesh of the method's own
    Own(Arc<dyn MethodGeometry>),
}

/// The kind of one binding of a method's own resources (bind group 2, from binding 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ResourceKind {
    /// `var<storage, read>`
    Storage,
    /// `texture_2d<u32>`
    TextureUint,
    /// `texture_2d<f32>`, unfilterable (read with textureLoad)
    TextureFloat,
}

/// One built resource, bound in the order its method declares.
#[derive(Clone, Debug)]
pub enum Resident {
    Buffer(wgpu::Buffer),
    Texture(wgpu::TextureView),
}

impl Resident {
    pub fn binding(&self) -> wgpu::BindingResource<'_> {
        match self {
            Resident::Buffer(b) => b.as_entire_binding(),
            Resident::Texture(v) => wgpu::BindingResource::TextureView(v),
        }
    }
}

/// What a method's resources for one object are built from.
pub struct BuildInputs<'a> {
    pub ctx: &'a Context,
    pub composer: &'a dyn Composer,
    /// compiled builder pipelines, made once per renderer
    pub builders: &'a Builders,
    pub object: &'a Object,
    /// the object's height map on the GPU: its size, and its max pyramid's level 0 and atlas
    /// (`heightmap::GpuHeight`'s `max0_view` and `max_atlas_view`)
    pub height_size: (u32, u32),
    pub height_max: [&'a wgpu::TextureView; 2],
    /// the mesh this method draws for the object (the base mesh, or its own geometry)
    pub mesh: &'a GpuMesh,
}

/// The GPU data a method brings (a cone map, the walk data, per-prism data): it
/// declares the bindings its WGSL reads at group 2 from binding 1, builds them for an object (on
/// the CPU or in compute passes of its own), and keys them by what they are built from; the
/// renderer caches and binds them and knows nothing else of them.
pub trait MethodResources: std::fmt::Debug + Send + Sync {
    /// The bindings, in order from binding 1.
    fn layout(&self) -> Vec<ResourceKind>;
    /// What one object's resources are built from, as a cache key.
    fn key(&self, object: &Object) -> u64;
    fn build(&self, inputs: &BuildInputs<'_>) -> Result<Vec<Resident>>;
}

/// A resource that a method's own geometry builds beside its vertices (`GpuMesh::extra[0]`: the
/// prisms' data, the walk data), bound as one binding of `kind` and keyed as the geometry is, so
/// that it is uploaded once, with the geometry.
#[derive(Debug)]
pub struct GeometryData<G: MethodGeometry> {
    pub geometry: G,
    pub kind: ResourceKind,
    /// what it is, in its cache key and its error
    pub what: &'static str,
}

impl<G: MethodGeometry> MethodResources for GeometryData<G> {
    fn layout(&self) -> Vec<ResourceKind> {
        vec![self.kind]
    }
    fn key(&self, object: &Object) -> u64 {
        crate::scene::hash_bytes(&[
            self.what.as_bytes(),
            &self.geometry.key(object).to_le_bytes(),
        ])
    }
    fn build(&self, inputs: &BuildInputs<'_>) -> Result<Vec<Resident>> {
        let data = inputs.mesh.extra.first().ok_or_else(|| {
            Error::Gpu(format!("the {} was not built with its geometry", self.what))
        })?;
        Ok(vec![data.clone()])
    }
}

/// Builder state a method makes once per renderer (compiled compute pipelines), by name.
#[derive(Default)]
pub struct Builders(Mutex<HashMap<&'static str, Arc<dyn Any + Send + Sync>>>);

impl Builders {
    /// The builder `name`, made by `make` on first use.
    pub fn get<T: Any + Send + Sync>(
        &self,
        name: &'static str,
        make: impl FnOnce() -> Result<T>,
    ) -> Result<Arc<T>> {
        let mut g = self
            .0
            .lock()
            .map_err(|_| Error::Gpu("builder cache lock poisoned".into()))?;
        if let Some(b) = g.get(name) {
            return b
                .clone()
                .downcast::<T>()
                .map_err(|_| Error::Gpu(format!("builder {name} has another type")));
        }
        let b = Arc::new(make()?);
        g.insert(name, b.clone());
        Ok(b)
    }
}

/// Everything the renderer needs to run a method.
#[derive(Clone, Debug)]
pub struct Spec {
    pub pass: Pass,
    /// boolean shader defs (MARCH or SHADE, LOD_BLEND, MESH_SURFACE, ... and the method's own).
    /// VERTEX_EXTRA: the method's geometry adds a vec4 attribute at location 5, which the
    /// surface pass interpolates and hands to its march as `Ray::extra`.
    pub defs: Vec<&'static str>,
    pub geometry: Geometry,
    /// the method's own GPU data (bind group 2, from binding 1)
    pub resources: Option<Arc<dyn MethodResources>>,
    /// the method's self-shadowing is the scene's shadow map of its own geometry (a method that
    /// rasterises the displaced surface itself)
    pub shadow_map_self: bool,
    /// the uniform block `params` (group 2, binding 0), field by field, all f32
    pub params: Vec<(String, f32)>,
    pub pixel: PerPixel,
    /// LOD_BLEND's threshold
    pub lod_threshold: f32,
    /// bound of every max-mip traversal (the method's and exact shadows)
    pub max_iterations: u32,
    /// the argument a shader compile error names: "method" for the built-ins, "wgsl" for a
    /// user's source (`Custom`)
    pub shader_arg: &'static str,
}

impl Spec {
    /// A per-pixel method of the surface pass, marching with `march`.
    pub fn surface(march: ShaderUnit, pixel: &PerPixel, params: &[(&str, f32)]) -> Self {
        Spec {
            pass: Pass::Surface {
                method: march,
                marches: true,
            },
            defs: vec!["MARCH"],
            geometry: Geometry::Base,
            resources: None,
            shadow_map_self: false,
            params: params.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
            pixel: pixel.clone(),
            lod_threshold: 0.0,
            max_iterations: 4096,
            shader_arg: "method",
        }
    }
    /// A surface-pass method without a march: `method` shades the rasterised surface.
    pub fn shade_only(method: ShaderUnit, pixel: PerPixel, geometry: Geometry) -> Self {
        Spec {
            pass: Pass::Surface {
                method,
                marches: false,
            },
            defs: vec!["SHADE"],
            geometry,
            resources: None,
            shadow_map_self: false,
            params: Vec::new(),
            pixel,
            lod_threshold: 0.0,
            max_iterations: 4096,
            shader_arg: "method",
        }
    }
}

pub fn flag(b: bool) -> f32 {
    if b {
        1.0
    } else {
        0.0
    }
}

pub fn check_finite(name: &str, v: f32) -> Result<()> {
    if !v.is_finite() {
        return Err(Error::arg(
            name,
            format!("must be a finite number, got {v}"),
        ));
    }
    Ok(())
}

/// One method's unit: its parameter struct says what the renderer runs (`spec`) and checks what
/// the core needs for safety (`validate`).
pub trait Unit {
    /// Whether the method takes the per-pixel options (shadows, filtering, AO): the Python
    /// dataclass then derives from `_PerPixel`. Otherwise the options are `PerPixel::off()`.
    const PER_PIXEL: bool = true;
    /// Parameter sets whose shader variants the tests compose, translate and check
    /// (`builtin_variants`): each once per shadow mode and filtering for a per-pixel method.
    fn examples() -> Vec<Self>
    where
        Self: Sized,
    {
        Vec::new()
    }
    fn spec(&self, o: &PerPixel) -> Spec;
    fn validate(&self) -> Result<()> {
        Ok(())
    }
}

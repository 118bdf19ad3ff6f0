//! Render passes and the Frame. One render pass draws the base mesh with the method's pipeline
//! into two float32 targets (colour + steps, uv + distance + lod); one readback returns all AOVs.

use crate::error::{Error, Result};
use crate::gpu::{layout, Context};
use crate::heightmap::{mip_count, GpuHeight, MipBuilder};
use crate::methods::{Filtering, Kind, Method};
use crate::mesh::tessellate::tessellate;
use crate::mesh::{Mesh, Vertex};
use crate::scene::{Albedo, HeightMap, Light, Scene, MAX_LIGHTS};
use crate::texspace::{FrameMaps, TexSpace};
use glam::DVec3;
use std::collections::hash_map::DefaultHasher;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};
use wgpu::util::DeviceExt;

/// All WGSL, concatenated in dependency order: one file per concern.
pub const SHADER_SOURCE: &str = concat!(
    include_str!("../shaders/common.wgsl"),
    "\n",
    include_str!("../shaders/lod.wgsl"),
    "\n",
    include_str!("../shaders/pom.wgsl"),
    "\n",
    include_str!("../shaders/shadows.wgsl"),
    "\n",
    include_str!("../shaders/relief.wgsl"),
    "\n",
    include_str!("../shaders/exact.wgsl"),
    "\n",
    include_str!("../shaders/horizon.wgsl"),
    "\n",
    include_str!("../shaders/ncs.wgsl"),
    "\n",
    include_str!("../shaders/prism.wgsl"),
    "\n",
    include_str!("../shaders/surface.wgsl"),
);

/// Per-pixel results of one render. Arrays are row-major (H, W, ...), row 0 at the top.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// linear RGB, H*W*3
    pub color: Vec<f32>,
    /// hit uv in mesh uv space (unwrapped), H*W*2, NaN where no hit
    pub uv: Vec<f32>,
    /// distance eye -> hit, NaN where no hit
    pub depth: Vec<f32>,
    pub mask: Vec<bool>,
    /// height-map samples taken (view + shadow rays)
    pub steps: Vec<u32>,
    /// mip level used, NaN where no hit
    pub lod: Vec<f32>,
    /// bit 0: the march hit its iteration bound (Exact)
    pub flags: Vec<u8>,
    /// GPU time of the render pass from timestamp queries, if the adapter has them
    pub gpu_ms: Option<f64>,
    /// wall time of submit-and-wait, always measured
    pub wall_ms: f64,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LightU {
    vec: [f32; 4],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    tex: [f32; 4],
    march: [f32; 4],
    extra: [f32; 4],
    params: [f32; 4],
    params2: [f32; 4],
    ambient: [f32; 4],
    lights: [LightU; MAX_LIGHTS],
    shadow_vp: [[f32; 4]; 4],
    shadow: [f32; 4],
    /// element offsets of the max pyramid's levels in its buffer
    max_offsets: [[u32; 4]; 4],
}

/// Shadow-map size for `Tessellated(shadows="hard")` (clamped to the device's limit).
pub const SHADOW_MAP_SIZE: u32 = 2048;

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
struct PipelineKey {
    method: u32,
    shadows: u32,
    filtering: u32,
}

struct Cached<T> {
    pub(crate) entries: Vec<(u64, Arc<T>)>,
    cap: usize,
}

impl<T> Cached<T> {
    fn new(cap: usize) -> Self {
        Self { entries: Vec::new(), cap }
    }
    /// Most-recently used last; evicts the oldest beyond `cap` (bounded GPU memory).
    fn get_or(&mut self, key: u64, make: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
        if let Some(pos) = self.entries.iter().position(|(k, _)| *k == key) {
            let e = self.entries.remove(pos);
            let v = e.1.clone();
            self.entries.push(e);
            return Ok(v);
        }
        let v = Arc::new(make()?);
        self.entries.push((key, v.clone()));
        while self.entries.len() > self.cap {
            self.entries.remove(0);
        }
        Ok(v)
    }
}

/// The frame's render targets and readback buffers, kept for the next frame of the same size.
struct Targets {
    w: u32,
    h: u32,
    color_t: wgpu::Texture,
    geo_t: wgpu::Texture,
    color_v: wgpu::TextureView,
    geo_v: wgpu::TextureView,
    depth_v: wgpu::TextureView,
    color_buf: wgpu::Buffer,
    geo_buf: wgpu::Buffer,
    queries: Option<wgpu::QuerySet>,
    ts_resolve: Option<wgpu::Buffer>,
    ts_read: Option<wgpu::Buffer>,
}

struct GpuMesh {
    vbuf: wgpu::Buffer,
    /// None: a non-indexed draw (prisms)
    ibuf: Option<wgpu::Buffer>,
    count: u32,
    /// Prism: the per-prism data the fragment shader reads
    prisms: Option<wgpu::Buffer>,
}

struct Inner {
    pipelines: HashMap<PipelineKey, Arc<wgpu::RenderPipeline>>,
    heights: Cached<GpuHeight>,
    albedos: Cached<wgpu::TextureView>,
    meshes: Cached<GpuMesh>,
    frame_maps: Cached<FrameMaps>,
}

impl GpuMesh {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
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

/// Content key of a mesh: its arrays hashed in place (no vertex array is built).
fn mesh_key(mesh: &Mesh) -> u64 {
    hash_bytes(&[
        bytemuck::cast_slice(&mesh.positions),
        bytemuck::cast_slice(&mesh.normals),
        bytemuck::cast_slice(&mesh.uvs),
        bytemuck::cast_slice(&mesh.tangents),
        bytemuck::cast_slice(&mesh.uv_scale),
        bytemuck::cast_slice(&mesh.indices),
    ])
}

pub struct Renderer {
    pub ctx: Arc<Context>,
    module: wgpu::ShaderModule,
    bgl: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    height_sampler: wgpu::Sampler,
    albedo_sampler: wgpu::Sampler,
    shadow_sampler: wgpu::Sampler,
    shadow_pipeline: wgpu::RenderPipeline,
    dummy_shadow: wgpu::TextureView,
    mips: MipBuilder,
    texspace: TexSpace,
    dummy_maps: FrameMaps,
    dummy_prisms: wgpu::Buffer,
    inner: Mutex<Inner>,
    /// serialises GPU submissions so that error scopes and timings belong to one render
    submit: Mutex<()>,
    /// the last frame size's targets (used under `submit`)
    targets: Mutex<Option<Arc<Targets>>>,
}

/// float32 bits in uint targets: exact on every backend (GL cannot render to Rgba32Float)
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Depth test and write, less-than: the surface pass and the shadow-map pass.
fn depth_state() -> Option<wgpu::DepthStencilState> {
    Some(wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    })
}

/// The highest max-mip level whose nodes tile the map exactly (its size divides both sides).
pub fn top_maxmip_level(w: u32, h: u32) -> u32 {
    let mut l = 0;
    while l + 1 < mip_count(w, h) && w % (1 << (l + 1)) == 0 && h % (1 << (l + 1)) == 0 {
        l += 1;
    }
    l
}

fn height_key(map: &HeightMap) -> u64 {
    hash_bytes(&[&map.width.to_le_bytes(), &map.height.to_le_bytes(), bytemuck::cast_slice(&map.data)])
}

fn hash_bytes(parts: &[&[u8]]) -> u64 {
    let mut h = DefaultHasher::new();
    for p in parts {
        p.len().hash(&mut h);
        p.hash(&mut h);
    }
    h.finish()
}

/// f32 -> IEEE half (round to nearest even), for the albedo texture.
pub fn f16_bits(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = ((b >> 16) & 0x8000) as u16;
    let exp = ((b >> 23) & 0xff) as i32;
    let man = b & 0x7f_ffff;
    if exp == 255 {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 31 {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rem = m & ((1u32 << shift) - 1);
        let mut r = m >> shift;
        if rem > half || (rem == half && (r & 1) == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let mut h = ((e as u32) << 10) | (man >> 13);
    let rem = man & 0x1fff;
    if rem > 0x1000 || (rem == 0x1000 && (h & 1) == 1) {
        h += 1;
    }
    sign | h as u16
}

impl Renderer {
    pub fn new(ctx: Arc<Context>) -> Result<Self> {
        let dev = &ctx.device;
        let filterable = ctx.float32_filterable;
        let (module, bgl, pipeline_layout, height_sampler, albedo_sampler, shadow_sampler, shadow_pipeline, dummy_shadow) = ctx.scoped(|| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("pomkit surface"),
                source: wgpu::ShaderSource::Wgsl(SHADER_SOURCE.into()),
            });
            let vf = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::VERTEX;
            let tex_entry = |binding: u32, filterable: bool| layout::texture(binding, vf, wgpu::TextureSampleType::Float { filterable });
            let samp_entry = |binding: u32, filtering: bool| {
                layout::sampler(binding, vf, if filtering { wgpu::SamplerBindingType::Filtering } else { wgpu::SamplerBindingType::NonFiltering })
            };
            let uint_entry = |binding: u32| layout::texture(binding, vf, wgpu::TextureSampleType::Uint);
            let storage = |binding: u32| layout::buffer(binding, vf, wgpu::BufferBindingType::Storage { read_only: true });
            let bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("pomkit surface"),
                entries: &[
                    layout::buffer(0, vf, wgpu::BufferBindingType::Uniform),
                    tex_entry(1, filterable),
                    samp_entry(2, filterable),
                    tex_entry(3, true),
                    samp_entry(4, true),
                    layout::texture(5, vf, wgpu::TextureSampleType::Depth),
                    layout::sampler(6, vf, wgpu::SamplerBindingType::Comparison),
                    storage(7),
                    uint_entry(8),
                    uint_entry(9),
                    storage(10),
                ],
            });
            let pipeline_layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("pomkit surface"),
                bind_group_layouts: &[Some(&bgl)],
                immediate_size: 0,
            });
            let filt = if filterable { wgpu::FilterMode::Linear } else { wgpu::FilterMode::Nearest };
            let mfilt = if filterable { wgpu::MipmapFilterMode::Linear } else { wgpu::MipmapFilterMode::Nearest };
            let height_sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("height"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                address_mode_w: wgpu::AddressMode::Repeat,
                mag_filter: filt,
                min_filter: filt,
                mipmap_filter: mfilt,
                ..Default::default()
            });
            let albedo_sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("albedo"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                address_mode_w: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            });
            let shadow_sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            });
            let shadow_pipeline = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("pomkit shadow map"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_shadow"),
                    compilation_options: Default::default(),
                    buffers: &[Some(Vertex::layout())],
                },
                primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::TriangleList, cull_mode: None, ..Default::default() },
                depth_stencil: depth_state(),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            });
            let dummy_shadow = dev
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("no shadow map"),
                    size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: DEPTH_FORMAT,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default());
            Ok((module, bgl, pipeline_layout, height_sampler, albedo_sampler, shadow_sampler, shadow_pipeline, dummy_shadow))
        })?;
        let mips = MipBuilder::new(&ctx)?;
        let texspace = TexSpace::new(&ctx)?;
        let dummy_maps = ctx.scoped(|| {
            let t = |label| {
                ctx.device
                    .create_texture(&wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::Rgba32Uint,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    })
                    .create_view(&Default::default())
            };
            Ok(FrameMaps { n: t("no frame map N"), t: t("no frame map T") })
        })?;
        let dummy_prisms = ctx.scoped(|| {
            Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("no prisms"),
                size: std::mem::size_of::<crate::prism::PrismData>() as u64,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }))
        })?;
        Ok(Self {
            ctx,
            module,
            bgl,
            pipeline_layout,
            height_sampler,
            albedo_sampler,
            shadow_sampler,
            shadow_pipeline,
            dummy_shadow,
            mips,
            texspace,
            dummy_maps,
            dummy_prisms,
            inner: Mutex::new(Inner {
                pipelines: HashMap::new(),
                heights: Cached::new(8),
                albedos: Cached::new(8),
                meshes: Cached::new(8),
                frame_maps: Cached::new(4),
            }),
            submit: Mutex::new(()),
            targets: Mutex::new(None),
        })
    }

    /// Issue an invalid wgpu call (a buffer both MAP_READ and MAP_WRITE) inside the error
    /// scopes: used by tests to check that validation errors surface as `Error::Gpu` and leave
    /// the renderer usable.
    pub fn provoke_validation_error(&self) -> Result<()> {
        self.ctx.scoped(|| {
            let _b = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("invalid on purpose"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
                mapped_at_creation: false,
            });
            Ok(())
        })
    }

    /// The GPU's pyramids for a map (tests): (mean mips, max mips).
    pub fn read_pyramids(&self, map: &HeightMap) -> Result<(Vec<Vec<f32>>, Vec<Vec<f32>>)> {
        let g = {
            let mut inner = self.inner.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
            self.height_texture(&mut inner, map)?
        };
        Ok((self.mips.read_back(&self.ctx, &g, false)?, self.mips.read_back(&self.ctx, &g, true)?))
    }

    /// The filtering a method actually gets: exact where the adapter cannot filter float32.
    pub fn effective_filtering(&self, f: Filtering) -> Filtering {
        if self.ctx.float32_filterable { f } else { Filtering::Exact }
    }

    fn pipeline(&self, inner: &mut Inner, key: PipelineKey) -> Result<Arc<wgpu::RenderPipeline>> {
        if let Some(p) = inner.pipelines.get(&key) {
            return Ok(p.clone());
        }
        let constants = [
            ("METHOD", key.method as f64),
            ("SHADOWS", key.shadows as f64),
            ("FILTERING", key.filtering as f64),
        ];
        let target = Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let prism = key.method == Kind::Prism.shader_id();
        let (vs, fs, layout) = if prism {
            ("vs_prism", "fs_prism", crate::prism::PrismVertex::layout())
        } else {
            ("vs_main", "fs_main", Vertex::layout())
        };
        let p = self.ctx.scoped(|| {
            Ok(self.ctx.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("pomkit surface"),
                layout: Some(&self.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &self.module,
                    entry_point: Some(vs),
                    compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                    buffers: &[Some(layout)],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: depth_state(),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &self.module,
                    entry_point: Some(fs),
                    compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                    targets: &[target.clone(), target],
                }),
                multiview_mask: None,
                cache: None,
            }))
        })?;
        let p = Arc::new(p);
        inner.pipelines.insert(key, p.clone());
        Ok(p)
    }

    fn height_texture(&self, inner: &mut Inner, map: &HeightMap) -> Result<Arc<GpuHeight>> {
        let key = height_key(map);
        inner.heights.get_or(key, || self.mips.create(&self.ctx, map))
    }

    /// Dynamic height fields: write `new` into the GPU texture that holds `old` (same size),
    /// rebuild both pyramids on the GPU, and re-key the cache entry. No pipeline is rebuilt and
    /// nothing is allocated. Returns false when `old` was not resident (it will upload on the
    /// next render instead).
    pub fn update_height(&self, old: &HeightMap, new: &HeightMap) -> Result<bool> {
        let mut inner = self.inner.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
        let old_key = height_key(old);
        let new_key = height_key(new);
        let Some(pos) = inner.heights.entries.iter().position(|(k, _)| *k == old_key) else {
            return Ok(false);
        };
        let g = inner.heights.entries[pos].1.clone();
        if g.width != new.width || g.height != new.height {
            return Ok(false);
        }
        let _guard = self.submit.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
        self.mips.update(&self.ctx, &g, new)?;
        self.ctx.wait()?;
        inner.heights.entries[pos].0 = new_key;
        Ok(true)
    }

    fn albedo_texture(&self, inner: &mut Inner, albedo: Option<&Albedo>) -> Result<Arc<wgpu::TextureView>> {
        let grey = Albedo { width: 1, height: 1, data: vec![[0.5, 0.5, 0.5, 1.0]] };
        let a = albedo.unwrap_or(&grey);
        let key = hash_bytes(&[&a.width.to_le_bytes(), &a.height.to_le_bytes(), bytemuck::cast_slice(&a.data)]);
        let ctx = &self.ctx;
        inner.albedos.get_or(key, || {
            // mips by box filter, stored as half floats (filterable on every adapter)
            let mut levels: Vec<Vec<[f32; 4]>> = vec![a.data.clone()];
            let n = mip_count(a.width, a.height);
            for k in 1..n {
                let (pw, ph) = crate::heightmap::level_size(a.width, a.height, k - 1);
                let (w, h) = crate::heightmap::level_size(a.width, a.height, k);
                let prev = &levels[(k - 1) as usize];
                let mut out = Vec::with_capacity((w * h) as usize);
                for y in 0..h {
                    for x in 0..w {
                        let mut acc = [0.0f32; 4];
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let p = prev[(((2 * y + dy).min(ph - 1)) * pw + (2 * x + dx).min(pw - 1)) as usize];
                            for c in 0..4 {
                                acc[c] += p[c] * 0.25;
                            }
                        }
                        out.push(acc);
                    }
                }
                levels.push(out);
            }
            let bits: Vec<u16> = levels.iter().flatten().flat_map(|p| p.map(f16_bits)).collect();
            ctx.scoped(|| {
                let tex = ctx.device.create_texture_with_data(
                    &ctx.queue,
                    &wgpu::TextureDescriptor {
                        label: Some("albedo"),
                        size: wgpu::Extent3d { width: a.width, height: a.height, depth_or_array_layers: 1 },
                        mip_level_count: n,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::Rgba16Float,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    bytemuck::cast_slice(&bits),
                );
                Ok(tex.create_view(&Default::default()))
            })
        })
    }

    /// The base mesh, or for `Tessellated` the displaced mesh (with the base frame per vertex).
    fn gpu_mesh(&self, inner: &mut Inner, scene: &Scene, method: &Method, base_key: u64) -> Result<Arc<GpuMesh>> {
        let mesh = &scene.mesh;
        let mut key = base_key;
        let tess = method.kind == Kind::Tessellated;
        if tess {
            let m = &scene.material;
            key = hash_bytes(&[
                &key.to_le_bytes(),
                bytemuck::cast_slice(&m.height.data),
                &m.height.width.to_le_bytes(),
                &m.depth.to_le_bytes(),
                &m.tiling.to_le_bytes(),
                &method.texels_per_vertex.to_le_bytes(),
            ]);
        }
        let ctx = &self.ctx;
        if method.kind == Kind::Prism {
            let m = &scene.material;
            let key = hash_bytes(&[&base_key.to_le_bytes(), &height_key(&m.height).to_le_bytes(), &m.depth.to_le_bytes(),
                &m.tiling.to_le_bytes(), &[method.outward as u8]]);
            return inner.meshes.get_or(key, || {
                let (verts, data) = crate::prism::build(mesh, m.depth, method.outward, &m.height, m.tiling);
                let vbytes = (verts.len() * std::mem::size_of::<crate::prism::PrismVertex>()) as u64;
                if vbytes > ctx.limits.max_buffer_size || (data.len() * std::mem::size_of::<crate::prism::PrismData>()) as u64 > ctx.limits.max_storage_buffer_binding_size as u64 {
                    return Err(Error::limit("mesh", format!("the prisms need {vbytes} bytes of vertices; over the device's buffer limits")));
                }
                ctx.scoped(|| {
                    let vbuf = ctx.upload("prism vertices", bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX);
                    let pbuf = ctx.upload("prisms", bytemuck::cast_slice(&data), wgpu::BufferUsages::STORAGE);
                    Ok(GpuMesh { vbuf, ibuf: None, count: verts.len() as u32, prisms: Some(pbuf) })
                })
            });
        }
        inner.meshes.get_or(key, || {
            let (verts, indices) = if tess {
                let t = tessellate(mesh, &scene.material, method.texels_per_vertex)?;
                let v: Vec<Vertex> = (0..t.positions.len())
                    .map(|i| Vertex {
                        position: t.positions[i],
                        normal: t.base_normals[i],
                        uv: t.uvs[i],
                        tangent: t.tangents[i],
                        uv_scale: t.uv_scale[i],
                    })
                    .collect();
                (v, t.indices)
            } else {
                (mesh.vertices(), mesh.indices.clone())
            };
            let vbytes = (verts.len() * std::mem::size_of::<Vertex>()) as u64;
            if vbytes > ctx.limits.max_buffer_size {
                return Err(Error::limit("texels_per_vertex", format!("the mesh needs a {vbytes}-byte vertex buffer; the device's max_buffer_size is {}", ctx.limits.max_buffer_size)));
            }
            ctx.scoped(|| {
                let vbuf = ctx.upload("vertices", bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX);
                let ibuf = ctx.upload("indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
                Ok(GpuMesh { vbuf, ibuf: Some(ibuf), count: indices.len() as u32, prisms: None })
            })
        })
    }

    /// Refuse sizes over the device's limits before anything reaches the GPU.
    pub fn check_limits(&self, scene: &Scene) -> Result<()> {
        let lim = &self.ctx.limits;
        let maxd = lim.max_texture_dimension_2d;
        let cam = &scene.camera;
        if cam.width > maxd || cam.height > maxd {
            return Err(Error::limit(
                "width",
                format!("frame {}x{} exceeds the device's max_texture_dimension_2d = {maxd}", cam.width, cam.height),
            ));
        }
        let row = (cam.width as u64 * 16).div_ceil(256) * 256;
        let bytes = row * cam.height as u64;
        if bytes > lim.max_buffer_size {
            return Err(Error::limit(
                "width",
                format!("frame {}x{} needs a {bytes}-byte readback buffer; the device's max_buffer_size is {}", cam.width, cam.height, lim.max_buffer_size),
            ));
        }
        let hm = &scene.material.height;
        if hm.width > maxd || hm.height > maxd {
            return Err(Error::limit(
                "height",
                format!("height map {}x{} exceeds the device's max_texture_dimension_2d = {maxd}", hm.width, hm.height),
            ));
        }
        if let Some(a) = &scene.material.albedo {
            if a.width > maxd || a.height > maxd {
                return Err(Error::limit(
                    "albedo",
                    format!("albedo {}x{} exceeds the device's max_texture_dimension_2d = {maxd}", a.width, a.height),
                ));
            }
        }
        let vbytes = scene.mesh.positions.len() as u64 * std::mem::size_of::<Vertex>() as u64;
        if vbytes > lim.max_buffer_size {
            return Err(Error::limit("mesh", format!("vertex buffer of {vbytes} bytes exceeds max_buffer_size = {}", lim.max_buffer_size)));
        }
        Ok(())
    }

    fn globals(&self, scene: &Scene, method: &Method) -> Globals {
        let (lo, hi) = scene.mesh.bounds();
        let c = (lo + hi) * 0.5;
        let r = (hi - lo).length() * 0.5 + scene.material.depth as f64 + 1e-3;
        let d = (DVec3::from(scene.camera.eye) - c).length();
        let far = (d + r) * 1.01 + 1e-3;
        let near = (d - r).max(far * 1e-5);
        let vp = scene.camera.view_proj(near, far);
        let mut lights = [LightU { vec: [0.0; 4], color: [0.0; 4] }; MAX_LIGHTS];
        for (i, l) in scene.lights.iter().enumerate() {
            lights[i] = match l {
                Light::Directional { direction, irradiance, angular_diameter } => {
                    let d = DVec3::from(*direction).normalize();
                    LightU {
                        vec: [d.x as f32, d.y as f32, d.z as f32, 0.0],
                        color: [irradiance[0], irradiance[1], irradiance[2], (angular_diameter.to_radians() * 0.5).tan() as f32],
                    }
                }
                Light::Sphere { position, radius, intensity } => LightU {
                    vec: [position[0] as f32, position[1] as f32, position[2] as f32, 1.0],
                    color: [intensity[0], intensity[1], intensity[2], *radius as f32],
                },
            };
        }
        let hm = &scene.material.height;
        let mut shadow_vp = [[0.0f32; 4]; 4];
        let mut shadow = [-1.0f32, 0.0, 1.0, 0.0];
        if method.kind == Kind::Tessellated && method.shadows != crate::methods::Shadows::None {
            if let Some((i, dir)) = scene.lights.iter().enumerate().find_map(|(i, l)| match l {
                Light::Directional { direction, .. } => Some((i, DVec3::from(*direction).normalize())),
                _ => None,
            }) {
                let size = SHADOW_MAP_SIZE.min(self.ctx.limits.max_texture_dimension_2d);
                let up = if dir.y.abs() < 0.99 { DVec3::Y } else { DVec3::X };
                let right = dir.cross(up).normalize();
                let up = right.cross(dir);
                let eye = c - dir * (2.0 * r);
                // orthographic: x, y in [-r, r], depth along dir from eye in [0, 4r]
                let m = glam::DMat4::from_cols(
                    glam::DVec4::new(right.x / r, up.x / r, dir.x / (4.0 * r), 0.0),
                    glam::DVec4::new(right.y / r, up.y / r, dir.y / (4.0 * r), 0.0),
                    glam::DVec4::new(right.z / r, up.z / r, dir.z / (4.0 * r), 0.0),
                    glam::DVec4::new(-right.dot(eye) / r, -up.dot(eye) / r, -dir.dot(eye) / (4.0 * r), 1.0),
                );
                shadow_vp = m.as_mat4().to_cols_array_2d();
                shadow = [i as f32, (2.0 * r / size as f64) as f32, size as f32, 0.0];
            }
        }
        Globals {
            view_proj: vp.to_cols_array_2d(),
            eye: [scene.camera.eye[0] as f32, scene.camera.eye[1] as f32, scene.camera.eye[2] as f32, scene.lights.len() as f32],
            tex: [hm.width as f32, hm.height as f32, scene.material.tiling, scene.material.depth],
            march: [method.min_steps as f32, method.max_steps as f32, method.shadow_steps as f32, method.lod_threshold],
            extra: [
                if method.adaptive { 1.0 } else { 0.0 },
                if method.mip_filtering { 1.0 } else { 0.0 },
                method.ao_directions as f32,
                method.horizon_samples as f32,
            ],
            params: [method.scale, method.bias, if method.offset_limiting { 1.0 } else { 0.0 }, method.max_iterations as f32],
            params2: [
                method.binary_steps as f32,
                if method.depth_bias { 1.0 } else { 0.0 },
                top_maxmip_level(hm.width, hm.height) as f32,
                if method.exact { 1.0 } else { 0.0 },
            ],
            ambient: [scene.ambient[0], scene.ambient[1], scene.ambient[2], mip_count(hm.width, hm.height) as f32],
            lights,
            shadow_vp,
            shadow,
            max_offsets: {
                let (o, _) = crate::heightmap::max_offsets(hm.width, hm.height);
                let mut a = [[0u32; 4]; 4];
                for (k, v) in o.iter().enumerate().take(16) {
                    a[k / 4][k % 4] = *v;
                }
                a
            },
        }
    }

    pub fn render(&self, scene: &Scene, method: &Method) -> Result<Frame> {
        scene.validate()?;
        self.check_limits(scene)?;
        self.ctx.check_alive()?;
        let filtering = self.effective_filtering(method.filtering);
        let key = PipelineKey {
            method: method.kind.shader_id(),
            shadows: method.shadow_id(),
            filtering: if filtering == Filtering::Exact { 1 } else { 0 },
        };
        let (pipeline, height, albedo, mesh, maps) = {
            let mut inner = self.inner.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
            let pipeline = self.pipeline(&mut inner, key)?;
            let height = self.height_texture(&mut inner, &scene.material.height)?;
            let albedo = self.albedo_texture(&mut inner, scene.material.albedo.as_ref())?;
            let base_key = mesh_key(&scene.mesh);
            let mesh = self.gpu_mesh(&mut inner, scene, method, base_key)?;
            let maps = if method.kind == Kind::Ncs {
                let key = base_key;
                let (tx, m) = (&self.texspace, &mesh);
                Some(inner.frame_maps.get_or(key, || tx.maps(&self.ctx, &m.vbuf, m.ibuf.as_ref().expect("indexed"), m.count))?)
            } else {
                None
            };
            (pipeline, height, albedo, mesh, maps)
        };
        let globals = self.globals(scene, method);
        let _guard = self.submit.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
        self.draw(scene, &pipeline, &height, &albedo, &mesh, maps.as_deref().unwrap_or(&self.dummy_maps), &globals)
    }

    /// Render targets and readback buffers for a w x h frame (reused while the size stays).
    fn targets(&self, w: u32, h: u32) -> Result<Arc<Targets>> {
        let mut slot = self.targets.lock().map_err(|_| Error::Gpu("renderer lock poisoned".into()))?;
        if let Some(t) = slot.as_ref() {
            if t.w == w && t.h == h {
                return Ok(t.clone());
            }
        }
        let dev = &self.ctx.device;
        let size = wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 };
        let tex = |label, format, usage| {
            dev.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let color_t = tex("color", COLOR_FORMAT, rt);
        let geo_t = tex("geo", COLOR_FORMAT, rt);
        let depth_t = tex("depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let row_bytes = (w as u64 * 16).div_ceil(256) * 256;
        let buf = |label, size, usage| dev.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false });
        let rb = wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST;
        let ts = self.ctx.timestamps;
        let t = Arc::new(Targets {
            w,
            h,
            color_v: color_t.create_view(&Default::default()),
            geo_v: geo_t.create_view(&Default::default()),
            depth_v: depth_t.create_view(&Default::default()),
            color_buf: buf("color readback", row_bytes * h as u64, rb),
            geo_buf: buf("geo readback", row_bytes * h as u64, rb),
            queries: ts.then(|| dev.create_query_set(&wgpu::QuerySetDescriptor { label: Some("pass time"), ty: wgpu::QueryType::Timestamp, count: 2 })),
            ts_resolve: ts.then(|| buf("ts resolve", 16, wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC)),
            ts_read: ts.then(|| buf("ts read", 16, rb)),
            color_t,
            geo_t,
        });
        *slot = Some(t.clone());
        Ok(t)
    }

    #[allow(clippy::too_many_arguments)]
    fn bind_group(&self, ubuf: &wgpu::Buffer, height: &GpuHeight, albedo: &wgpu::TextureView, shadow: &wgpu::TextureView, maps: &FrameMaps, prisms: &wgpu::Buffer) -> wgpu::BindGroup {
        self.ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("surface"),
            layout: &self.bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: ubuf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&height.view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&self.height_sampler) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(albedo) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&self.albedo_sampler) },
                wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(shadow) },
                wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::Sampler(&self.shadow_sampler) },
                wgpu::BindGroupEntry { binding: 7, resource: height.max_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(&maps.n) },
                wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::TextureView(&maps.t) },
                wgpu::BindGroupEntry { binding: 10, resource: prisms.as_entire_binding() },
            ],
        })
    }

    fn draw(
        &self,
        scene: &Scene,
        pipeline: &wgpu::RenderPipeline,
        height: &GpuHeight,
        albedo: &wgpu::TextureView,
        mesh: &GpuMesh,
        maps: &FrameMaps,
        globals: &Globals,
    ) -> Result<Frame> {
        let ctx = &self.ctx;
        let dev = &ctx.device;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let row_bytes = (w as u64 * 16).div_ceil(256) * 256;
        let mut wall_ms = 0.0;
        let targets = ctx.scoped(|| {
            let ubuf = ctx.upload("globals", bytemuck::bytes_of(globals), wgpu::BufferUsages::UNIFORM);
            let prisms = mesh.prisms.as_ref().unwrap_or(&self.dummy_prisms);
            let bind = self.bind_group(&ubuf, height, albedo, &self.dummy_shadow, maps, prisms);
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("render") });
            // Tessellated's shadow map: the displaced mesh's depth from the light
            let shadow_view = (globals.shadow[0] >= 0.0).then(|| {
                let size = globals.shadow[2] as u32;
                let t = dev.create_texture(&wgpu::TextureDescriptor {
                    label: Some("shadow map"),
                    size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: DEPTH_FORMAT,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                });
                let v = t.create_view(&Default::default());
                {
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("shadow map"),
                        color_attachments: &[],
                        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                            view: &v,
                            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                            stencil_ops: None,
                        }),
                        timestamp_writes: None,
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    pass.set_pipeline(&self.shadow_pipeline);
                    pass.set_bind_group(0, &bind, &[]);
                    mesh.draw(&mut pass);
                }
                v
            });
            let bind = match &shadow_view {
                None => bind,
                Some(v) => self.bind_group(&ubuf, height, albedo, v, maps, prisms),
            };
            let tg = self.targets(w, h)?;
            let (color_v, geo_v, depth_v) = (&tg.color_v, &tg.geo_v, &tg.depth_v);
            let queries = tg.queries.as_ref();
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("surface"),
                    color_attachments: &[
                        Some(wgpu::RenderPassColorAttachment {
                            view: color_v,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
                        }),
                        Some(wgpu::RenderPassColorAttachment {
                            view: geo_v,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                // distance -1.0 (as float32 bits) marks pixels without a hit
                                load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.0, g: 0.0, b: (-1.0f32).to_bits() as f64, a: 0.0 }),
                                store: wgpu::StoreOp::Store,
                            },
                        }),
                    ],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_v,
                        depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: queries.map(|q| wgpu::RenderPassTimestampWrites {
                        query_set: q,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    }),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bind, &[]);
                mesh.draw(&mut pass);
            }
            for (t, b) in [(&tg.color_t, &tg.color_buf), (&tg.geo_t, &tg.geo_buf)] {
                enc.copy_texture_to_buffer(
                    t.as_image_copy(),
                    wgpu::TexelCopyBufferInfo {
                        buffer: b,
                        layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row_bytes as u32), rows_per_image: Some(h) },
                    },
                    wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                );
            }
            if let (Some(q), Some(res), Some(read)) = (queries, &tg.ts_resolve, &tg.ts_read) {
                enc.resolve_query_set(q, 0..2, res, 0);
                enc.copy_buffer_to_buffer(res, 0, read, 0, 16);
            }
            let t0 = std::time::Instant::now();
            ctx.queue.submit([enc.finish()]);
            ctx.wait()?;
            wall_ms = t0.elapsed().as_secs_f64() * 1e3;
            Ok(tg)
        })?;
        let tg = targets;
        let mut frame = Frame::empty(w, h);
        let gpu_ms = match &tg.ts_read {
            Some(b) => {
                let raw = ctx.read_buffer(b)?;
                let t: &[u64] = bytemuck::cast_slice(&raw);
                let period = ctx.queue.get_timestamp_period() as f64;
                (t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period / 1e6)
            }
            None => None,
        };
        ctx.map_read(&tg.geo_buf, |g| frame.unpack_geo(row_bytes as usize, g))?;
        ctx.map_read(&tg.color_buf, |c| frame.unpack_color(row_bytes as usize, c))?;
        frame.gpu_ms = gpu_ms;
        frame.wall_ms = wall_ms;
        Ok(frame)
    }
}

impl Frame {
    fn empty(w: u32, h: u32) -> Self {
        let n = (w * h) as usize;
        Frame {
            width: w,
            height: h,
            color: vec![0.0; n * 3],
            uv: vec![f32::NAN; n * 2],
            depth: vec![f32::NAN; n],
            mask: vec![false; n],
            steps: vec![0; n],
            lod: vec![f32::NAN; n],
            flags: vec![0; n],
            gpu_ms: None,
            wall_ms: 0.0,
        }
    }

    /// uv, distance and lod from the geo target (distance < 0: no hit); sets the mask.
    fn unpack_geo(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        for y in 0..self.height as usize {
            let g: &[f32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 16]);
            for (x, px) in g.chunks_exact(4).enumerate() {
                if px[2] >= 0.0 {
                    let i = y * w + x;
                    self.mask[i] = true;
                    self.uv[2 * i] = px[0];
                    self.uv[2 * i + 1] = px[1];
                    self.depth[i] = px[2];
                    self.lod[i] = px[3];
                }
            }
        }
    }

    /// Colour, steps and flags from the colour target (steps and flags only where hit).
    fn unpack_color(&mut self, row_bytes: usize, raw: &[u8]) {
        let w = self.width as usize;
        for y in 0..self.height as usize {
            let c: &[u32] = bytemuck::cast_slice(&raw[y * row_bytes..y * row_bytes + w * 16]);
            for (x, px) in c.chunks_exact(4).enumerate() {
                let i = y * w + x;
                self.color[3 * i] = f32::from_bits(px[0]);
                self.color[3 * i + 1] = f32::from_bits(px[1]);
                self.color[3 * i + 2] = f32::from_bits(px[2]);
                if self.mask[i] {
                    self.steps[i] = px[3] & 0x0fff_ffff;
                    self.flags[i] = (px[3] >> 28) as u8;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::f16_bits;
    #[test]
    fn half_floats() {
        assert_eq!(f16_bits(1.0), 0x3c00);
        assert_eq!(f16_bits(0.5), 0x3800);
        assert_eq!(f16_bits(0.0), 0);
        assert_eq!(f16_bits(65504.0), 0x7bff);
        assert_eq!(f16_bits(1e-7), 0x0002);
    }
}

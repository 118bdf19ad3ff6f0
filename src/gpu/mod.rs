//! The GPU context: instance, adapter choice, one device per process, error capture,
//! uploads and readback.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// What `adapters()` reports about one adapter.
#[derive(Clone, Debug)]
pub struct AdapterDesc {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
}

mod caps;
pub mod texels;
pub use caps::{Capabilities, STORAGE_BUFFERS_PER_STAGE, WGPU_VERSION};
mod table;
pub use table::{TableOut, TablePass, TableTarget, TABLE_BAND_CELLS};

pub struct Context {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: AdapterDesc,
    pub caps: Capabilities,
    pub limits: wgpu::Limits,
    lost: Arc<AtomicBool>,
    lost_msg: Arc<Mutex<String>>,
    uncaptured: Arc<Mutex<Option<String>>>,
    /// "auto"'s verdict on this device, measured on first use (render::Renderer::auto_compute)
    pub auto_compute: OnceLock<bool>,
}

/// Which backends to try: POMKIT_BACKEND=vulkan|metal|dx12|gl|all forces them (default: every
/// native backend; the best adapter wins, GL last).
pub fn backends_from_env() -> Result<wgpu::Backends> {
    match std::env::var("POMKIT_BACKEND")
        .ok()
        .as_deref()
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        None | Some("") | Some("auto") | Some("all") => Ok(wgpu::Backends::VULKAN
            | wgpu::Backends::METAL
            | wgpu::Backends::DX12
            | wgpu::Backends::GL),
        Some("vulkan") | Some("vk") => Ok(wgpu::Backends::VULKAN),
        Some("metal") | Some("mtl") => Ok(wgpu::Backends::METAL),
        Some("dx12") | Some("d3d12") => Ok(wgpu::Backends::DX12),
        Some("gl") | Some("gles") | Some("opengl") => Ok(wgpu::Backends::GL),
        Some(other) => Err(Error::arg(
            "POMKIT_BACKEND",
            format!("unknown backend {other:?}; use vulkan, metal, dx12, gl or auto"),
        )),
    }
}

fn instance(backends: wgpu::Backends) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    desc.flags = wgpu::InstanceFlags::empty();
    wgpu::Instance::new(desc)
}

fn describe(a: &wgpu::Adapter) -> AdapterDesc {
    let i = a.get_info();
    AdapterDesc {
        name: i.name,
        backend: format!("{:?}", i.backend).to_lowercase(),
        device_type: format!("{:?}", i.device_type),
        driver: format!("{} {}", i.driver, i.driver_info).trim().to_string(),
    }
}

/// The OpenGL version a GL adapter's driver string opens with ("4.5 (Core Profile) Mesa 22.3.6",
/// "3.3.0 NVIDIA 580.159.04", "OpenGL ES 3.2 ..."): (major, minor, whether ES).
fn gl_version(driver: &str) -> Option<(u32, u32, bool)> {
    let es = driver.contains("OpenGL ES");
    let v = driver
        .split_whitespace()
        .find(|w| w.starts_with(|c: char| c.is_ascii_digit()))?;
    let mut it = v.split('.').map(|x| x.parse::<u32>().ok());
    Some((it.next()??, it.next()??, es))
}

const NO_ADAPTER_HELP: &str =
    "pomkit needs a Vulkan, Metal, DX12 or OpenGL adapter. Without a GPU on Linux, install Mesa's \
software drivers: `sudo apt-get install mesa-vulkan-drivers libegl1 libegl-mesa0 libgl1-mesa-dri` \
(Debian/Ubuntu), or set POMKIT_BACKEND=gl to try the GL backend";

/// Every adapter the allowed backends expose.
pub fn adapters() -> Result<Vec<AdapterDesc>> {
    let backends = backends_from_env()?;
    let inst = instance(backends);
    let list = pollster::block_on(inst.enumerate_adapters(backends));
    Ok(list.iter().map(describe).collect())
}

impl Context {
    /// Open a device on the adapter whose name, backend or index matches `choice`, or the
    /// best one (discrete > integrated > cpu; Vulkan before GL).
    pub fn new(choice: Option<&str>) -> Result<Self> {
        let backends = backends_from_env()?;
        let inst = instance(backends);
        let mut list = pollster::block_on(inst.enumerate_adapters(backends));
        if list.is_empty() {
            return Err(Error::NoAdapter(NO_ADAPTER_HELP.to_string()));
        }
        let rank = |a: &wgpu::Adapter| {
            let i = a.get_info();
            let t = match i.device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Cpu => 3,
                wgpu::DeviceType::Other => 4,
            };
            // native APIs before GL (GL is the fallback: fewer features, see Capabilities)
            let b = if i.backend == wgpu::Backend::Gl { 1 } else { 0 };
            (t, b)
        };
        list.sort_by_key(rank);
        let adapter = match choice {
            None => list.swap_remove(0),
            Some(c) => {
                let names: Vec<String> = list
                    .iter()
                    .map(|a| {
                        let d = describe(a);
                        format!("{} ({})", d.name, d.backend)
                    })
                    .collect();
                let idx = if let Ok(k) = c.parse::<usize>() {
                    (k < list.len()).then_some(k)
                } else {
                    let c = c.to_ascii_lowercase();
                    list.iter().position(|a| {
                        let d = describe(a);
                        d.name.to_ascii_lowercase().contains(&c) || d.backend == c
                    })
                };
                match idx {
                    Some(k) => list.swap_remove(k),
                    None => {
                        return Err(Error::arg(
                            "adapter",
                            format!("no adapter matches {c:?}; available: {}", names.join(", ")),
                        ))
                    }
                }
            }
        };
        let info = describe(&adapter);
        let caps = Capabilities::detect(&adapter);
        if !caps.fragment_storage || !caps.compute_shaders || !caps.gather {
            return Err(Error::NoAdapter(format!(
                "{} ({}) lacks storage buffers in fragment shaders, compute shaders or sampling of R32Float textures, which pomkit needs; {NO_ADAPTER_HELP}",
                info.name, info.backend
            )));
        }
        if info.backend == "gl" {
            if let Some((major, minor, es)) = gl_version(&info.driver) {
                if (major, minor) < if es { (3, 1) } else { (4, 3) } {
                    return Err(Error::NoAdapter(format!(
                        "{} (gl) gave pomkit an OpenGL{} {major}.{minor} context, whose shaders have no compute stage \
                         (pomkit needs OpenGL 4.3 or OpenGL ES 3.1): use its Vulkan driver (POMKIT_BACKEND=vulkan)",
                        info.name,
                        if es { " ES" } else { "" }
                    )));
                }
            }
        }
        let features = caps.required();
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("pomkit"),
            required_features: features,
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| Error::NoAdapter(format!("could not open a device on {}: {e}", info.name)))?;

        let lost = Arc::new(AtomicBool::new(false));
        let lost_msg = Arc::new(Mutex::new(String::new()));
        {
            let lost = lost.clone();
            let lost_msg = lost_msg.clone();
            device.set_device_lost_callback(move |reason, msg| {
                lost.store(true, Ordering::SeqCst);
                if let Ok(mut m) = lost_msg.lock() {
                    *m = format!("{reason:?}: {msg}");
                }
            });
        }
        // wgpu's default handler panics on errors outside an error scope: keep the message
        // instead, so that the next call can report it.
        let uncaptured = Arc::new(Mutex::new(None));
        {
            let u = uncaptured.clone();
            device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                if let Ok(mut g) = u.lock() {
                    *g = Some(e.to_string());
                }
            }));
        }
        Ok(Self {
            adapter,
            device,
            queue,
            info,
            caps,
            limits,
            lost,
            lost_msg,
            uncaptured,
            auto_compute: OnceLock::new(),
        })
    }

    pub fn check_alive(&self) -> Result<()> {
        if self.lost.load(Ordering::SeqCst) {
            let m = self.lost_msg.lock().map(|m| m.clone()).unwrap_or_default();
            return Err(Error::DeviceLost(format!(
                "{m}; create a new pomkit.Renderer() to open a fresh device"
            )));
        }
        Ok(())
    }

    /// Run `f` inside validation and out-of-memory error scopes; a wgpu error becomes `Error::Gpu`.
    pub fn scoped<T>(&self, f: impl FnOnce() -> Result<T>) -> Result<T> {
        self.check_alive()?;
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let val = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let r = f();
        let ve = pollster::block_on(val.pop());
        let oe = pollster::block_on(oom.pop());
        if let Some(e) = ve.or(oe) {
            return Err(Error::Gpu(e.to_string()));
        }
        if let Some(m) = self.uncaptured.lock().ok().and_then(|mut g| g.take()) {
            return Err(Error::Gpu(m));
        }
        self.check_alive()?;
        r
    }

    /// Destroy the device (simulates device loss for tests).
    pub fn destroy(&self) {
        self.device.destroy();
        self.lost.store(true, Ordering::SeqCst);
        if let Ok(mut m) = self.lost_msg.lock() {
            if m.is_empty() {
                *m = "the device was destroyed".into();
            }
        }
    }

    pub fn wait(&self) -> Result<()> {
        self.wait_for(None)
    }

    /// Block until `submission` (None: the latest) has finished and its callbacks have run.
    pub fn wait_for(&self, submission: Option<wgpu::SubmissionIndex>) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: submission,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))
    }

    /// Map a buffer (MAP_READ) after all submitted work, hand its bytes to `f`, unmap. No copy
    /// of the mapped memory.
    pub fn map_read<T>(&self, buf: &wgpu::Buffer, f: impl FnOnce(&[u8]) -> T) -> Result<T> {
        self.map_read_all(&[buf], None, |b| f(b[0]))
    }

    /// Map several buffers (MAP_READ) once `submission` (None: all submitted work) has
    /// finished, with one wait for all of them, hand their bytes to `f` (in order), unmap. Later
    /// submissions keep running: a frame's readback overlaps the next frame's GPU work
    /// (`Renderer::render_many`).
    pub fn map_read_all<T>(
        &self,
        bufs: &[&wgpu::Buffer],
        submission: Option<wgpu::SubmissionIndex>,
        f: impl FnOnce(&[&[u8]]) -> T,
    ) -> Result<T> {
        type Slot = Arc<Mutex<Option<std::result::Result<(), wgpu::BufferAsyncError>>>>;
        let slots: Vec<Slot> = bufs
            .iter()
            .map(|b| {
                let slot: Slot = Arc::new(Mutex::new(None));
                let s2 = slot.clone();
                b.map_async(wgpu::MapMode::Read, .., move |r| {
                    *s2.lock().unwrap() = Some(r);
                });
                slot
            })
            .collect();
        self.wait_for(submission)?;
        // Another thread's poll may have collected this mapping's callback and not yet run it
        // when our wait returns (the shared device: tests, Python threads): poll until every
        // callback has run, with a deadline.
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while slots
            .iter()
            .any(|s| s.lock().map(|g| g.is_none()).unwrap_or(false))
            && std::time::Instant::now() < deadline
        {
            self.device
                .poll(wgpu::PollType::Poll)
                .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))?;
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        for s in &slots {
            match s.lock().unwrap().take() {
                Some(Ok(())) => {}
                Some(Err(e)) => return Err(Error::Gpu(format!("buffer map failed: {e}"))),
                None => return Err(Error::Gpu("buffer map did not complete".into())),
            }
        }
        let out = {
            let views = bufs
                .iter()
                .map(|b| {
                    b.get_mapped_range(..)
                        .map_err(|e| Error::Gpu(format!("{e}")))
                })
                .collect::<Result<Vec<_>>>()?;
            let bytes: Vec<&[u8]> = views.iter().map(|v| &v[..]).collect();
            f(&bytes)
        };
        for b in bufs {
            b.unmap();
        }
        Ok(out)
    }

    /// Read a buffer (MAP_READ) back to host memory.
    pub fn read_buffer(&self, buf: &wgpu::Buffer) -> Result<Vec<u8>> {
        self.map_read(buf, |b| b.to_vec())
    }
}

/// Bind-group layout entries, shared by every pipeline's layout.
pub mod layout {
    pub fn texture(
        binding: u32,
        stages: wgpu::ShaderStages,
        sample_type: wgpu::TextureSampleType,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }
    }
    pub fn storage_texture(
        binding: u32,
        stages: wgpu::ShaderStages,
        format: wgpu::TextureFormat,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        }
    }
    pub fn buffer(
        binding: u32,
        stages: wgpu::ShaderStages,
        ty: wgpu::BufferBindingType,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }
    }
    pub fn sampler(
        binding: u32,
        stages: wgpu::ShaderStages,
        ty: wgpu::SamplerBindingType,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: wgpu::BindingType::Sampler(ty),
            count: None,
        }
    }
}

impl Context {
    /// A buffer initialised with `contents`.
    /// A w x h 2-D texture with one mip level and one sample.
    pub fn texture_2d(
        &self,
        label: &str,
        (w, h): (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    /// A compute pipeline whose layout is the one bind group `bgl` (group 0).
    pub fn compute_pipeline(
        &self,
        label: &str,
        module: &wgpu::ShaderModule,
        entry: &str,
        bgl: &wgpu::BindGroupLayout,
    ) -> wgpu::ComputePipeline {
        let pl = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(bgl)],
                immediate_size: 0,
            });
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pl),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
    }

    /// Record one compute pass of `pipeline` over a w x h grid in 8 x 8 workgroups (every
    /// compute shader of pomkit), with `bg` at bind group `group`.
    pub fn dispatch_8x8(
        enc: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: u32,
        bg: &wgpu::BindGroup,
        (w, h): (u32, u32),
    ) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(group, bg, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }

    /// A bind group of `layout` with `resources` at bindings 0, 1, 2, ...
    pub fn bind_group(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = resources
            .into_iter()
            .enumerate()
            .map(|(b, resource)| wgpu::BindGroupEntry {
                binding: b as u32,
                resource,
            })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &entries,
        })
    }

    pub fn upload(&self, label: &str, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
    }
}

static SHARED: OnceLock<Mutex<Option<(Option<String>, Arc<Context>)>>> = OnceLock::new();

/// The process-wide context: created lazily on first use and reused. A different adapter
/// choice, or a lost device, replaces it.
pub fn shared(choice: Option<&str>) -> Result<Arc<Context>> {
    let cell = SHARED.get_or_init(|| Mutex::new(None));
    let mut g = cell
        .lock()
        .map_err(|_| Error::Gpu("context lock poisoned".into()))?;
    if let Some((c, ctx)) = g.as_ref() {
        let same = choice.is_none() || c.as_deref() == choice;
        if same && ctx.check_alive().is_ok() {
            return Ok(ctx.clone());
        }
    }
    let ctx = Arc::new(Context::new(choice)?);
    *g = Some((choice.map(str::to_string), ctx.clone()));
    Ok(ctx)
}

/// The rows of a texture holding `n` records of `texels` texels each, a power-of-two number of
/// records a row (a shader finds a record with a shift and a mask) within `max_dim` texels a
/// side, no wider than `n` needs: (records a row, rows), or Err(the most records that fit).
pub fn record_rows(
    n: usize,
    texels: u32,
    max_dim: u32,
) -> std::result::Result<(u32, usize), usize> {
    let n = n.max(1);
    let fit = (max_dim / texels).max(1);
    let per_row = (1u32 << (31 - fit.leading_zeros())).min((n as u32).next_power_of_two());
    let rows = n.div_ceil(per_row as usize);
    if rows > max_dim as usize {
        return Err(per_row as usize * max_dim as usize);
    }
    Ok((per_row, rows))
}

#[cfg(test)]
mod gl_version_tests {
    use super::gl_version;

    #[test]
    fn reads_the_version_a_gl_driver_reports() {
        assert_eq!(
            gl_version("4.5 (Core Profile) Mesa 22.3.6"),
            Some((4, 5, false))
        );
        assert_eq!(gl_version("3.3.0 NVIDIA 580.159.04"), Some((3, 3, false)));
        assert_eq!(
            gl_version("OpenGL ES 3.2 NVIDIA 580.159.04"),
            Some((3, 2, true))
        );
        assert_eq!(gl_version("NVIDIA"), None);
    }
}

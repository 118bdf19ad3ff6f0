//! What the adapter can do that pomkit uses, detected once per device, with the fallback for
//! each missing feature: the one place these decisions live.

/// The wgpu release pomkit is built against (Cargo.lock's; a test holds the two equal), for
/// `python -m pomkit info` and the bench's records.
pub const WGPU_VERSION: &str = "30.0.1";

/// Read-only storage buffers the surface pass may bind per stage (render/pipelines.rs; today
/// DistanceMapping's volume: the max pyramid, the cone map and the prisms are textures).
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 3;

/// What the adapter can do that pomkit uses, detected once per device, and the fallback taken
/// for each missing feature. The one place these decisions live: the renderer reads them from
/// here, `python -m pomkit info` prints them (docs/platforms.md).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Capabilities {
    /// TIMESTAMP_QUERY: GPU time around the render pass. Fallback: `gpu_ms` is None and the
    /// bench times submit-and-wait (`wall_ms`).
    pub timestamps: bool,
    /// TIMESTAMP_QUERY_INSIDE_PASSES (reported; pomkit times whole passes only)
    pub timestamps_inside_passes: bool,
    /// FLOAT32_FILTERABLE: the R32Float height map through a linear sampler. Fallback: every
    /// height sample takes `filtering="exact"` (four loads and a float32 lerp), and the
    /// mip-filtered march lerps between levels in the shader.
    pub float32_filterable: bool,
    /// storage buffers in fragment shaders (the max pyramid, prisms, cone data): required;
    /// without them pomkit reports no usable adapter rather than rendering wrongly
    pub fragment_storage: bool,
    /// FRAGMENT_WRITABLE_STORAGE with a storage buffer to spare per stage: the `fragments`
    /// AOV's per-pixel counter (an atomic add in the surface pass). Fallback: asking for
    /// `fragments` raises an error that says the adapter lacks it; nothing else needs it.
    pub fragment_counters: bool,
    /// compute shaders (the mip and max pyramids, methods' tables): required
    pub compute_shaders: bool,
    /// What the adapter lacks of the compute pipeline (`compute_pipeline`; empty: it has it).
    pub compute_pipeline_missing: Vec<String>,
    /// The max-mip walk (Exact, ConeStep's exact refinement, exact shadows, the exact Prism)
    /// reads the node a candidate's miss walks on to in the same round as the candidate's patch
    /// (maxmip.wgsl, PREFETCH): a GPU waits one fetch latency less a miss. On a CPU adapter
    /// (llvmpipe) every lane runs both sides of the branch, so the read is extra work: off.
    /// POMKIT_PREFETCH=1 or 0 overrides (the tests compare both on any adapter).
    pub prefetch: bool,
    /// textureGather on the R32Float height map (the max-mip walk's cell corners): WGSL core
    /// wherever the format can be sampled, which is what is detected; required
    pub gather: bool,
    /// SHADER_F64 (reported: the float64 oracle runs on the CPU, no shader needs f64)
    pub shader_f64: bool,
    /// Compute writes to a mip level through a single-level storage view land in that level.
    /// Not on wgpu's GL backend (measured: Mesa GL 4.5 left levels >= 1 at zero, so every
    /// mip-filtered march read a flat field). Fallback: each level is reduced into a
    /// single-level texture and copied into its mip level (src/render/mip_builder.rs).
    pub storage_mip_views: bool,
    /// A render pass may leave gaps in its colour attachments (write the geo target without the
    /// colour target). Not on wgpu's GL backend (measured: with only the geo target attached,
    /// at location 1, its clear did not happen and a new target read as hits everywhere).
    /// Fallback: every target up to the last requested one is written and cleared (not read).
    pub sparse_attachments: bool,
}

/// What `adapter` lacks of the compute pipeline's needs (Capabilities::compute_pipeline).
fn compute_pipeline_missing(adapter: &wgpu::Adapter) -> Vec<String> {
    let d = adapter.get_downlevel_capabilities();
    let l = adapter.limits();
    let mut m = Vec::new();
    if !d.flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
        m.push("compute shaders".to_string());
    }
    if !d.flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE) {
        m.push("storage buffers in vertex shaders".to_string());
    }
    if l.max_storage_textures_per_shader_stage < 4 {
        m.push(format!(
            "4 storage textures a stage (it has {})",
            l.max_storage_textures_per_shader_stage
        ));
    }
    if l.max_bind_groups < 4 {
        m.push(format!("4 bind groups (it has {})", l.max_bind_groups));
    }
    for f in [
        wgpu::TextureFormat::Rgba32Uint,
        wgpu::TextureFormat::R32Uint,
    ] {
        if !adapter
            .get_texture_format_features(f)
            .allowed_usages
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
        {
            m.push(format!("{f:?} storage textures"));
        }
    }
    m
}

impl Capabilities {
    pub(super) fn detect(adapter: &wgpu::Adapter) -> Self {
        let f = adapter.features();
        let d = adapter.get_downlevel_capabilities();
        let gl = adapter.get_info().backend == wgpu::Backend::Gl;
        Capabilities {
            prefetch: match std::env::var("POMKIT_PREFETCH").ok().as_deref() {
                Some("1") => true,
                Some("0") => false,
                _ => adapter.get_info().device_type != wgpu::DeviceType::Cpu,
            },
            timestamps: f.contains(wgpu::Features::TIMESTAMP_QUERY),
            timestamps_inside_passes: f.contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES),
            float32_filterable: f.contains(wgpu::Features::FLOAT32_FILTERABLE),
            fragment_storage: d.flags.contains(wgpu::DownlevelFlags::FRAGMENT_STORAGE)
                && adapter.limits().max_storage_buffers_per_shader_stage
                    >= STORAGE_BUFFERS_PER_STAGE,
            fragment_counters: d
                .flags
                .contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE)
                && adapter.limits().max_storage_buffers_per_shader_stage
                    > STORAGE_BUFFERS_PER_STAGE,
            compute_shaders: d.flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS),
            compute_pipeline_missing: compute_pipeline_missing(adapter),
            gather: adapter
                .get_texture_format_features(wgpu::TextureFormat::R32Float)
                .allowed_usages
                .contains(wgpu::TextureUsages::TEXTURE_BINDING),
            shader_f64: f.contains(wgpu::Features::SHADER_F64),
            storage_mip_views: !gl,
            sparse_attachments: !gl,
        }
    }

    /// The compute pipeline (`pk.Renderer(pipeline="compute")`): a visibility pass whose vertex
    /// stage reads the mesh from storage, and a compute pass that stores the targets as storage
    /// textures (Rgba32Uint, R32Uint). Without it every frame is rasterised.
    pub fn compute_pipeline(&self) -> bool {
        self.compute_pipeline_missing.is_empty()
    }

    /// The features pomkit asks the device for (those it uses, where present).
    pub(super) fn required(&self) -> wgpu::Features {
        let mut f = wgpu::Features::empty();
        if self.timestamps {
            f |= wgpu::Features::TIMESTAMP_QUERY;
        }
        if self.float32_filterable {
            f |= wgpu::Features::FLOAT32_FILTERABLE;
        }
        f
    }

    /// (feature, present, what pomkit does without it), for `python -m pomkit info`.
    pub fn report(&self) -> Vec<(&'static str, bool, &'static str)> {
        vec![
            (
                "timestamp queries (around passes)",
                self.timestamps,
                "gpu_ms is None; the bench times submit-and-wait",
            ),
            (
                "timestamp queries (inside passes)",
                self.timestamps_inside_passes,
                "not used: pomkit times whole passes",
            ),
            (
                "float32 filtering",
                self.float32_filterable,
                "filtering=\"exact\" everywhere (four loads, float32 lerp)",
            ),
            (
                "storage buffers in fragment shaders",
                self.fragment_storage,
                "required: no usable adapter",
            ),
            (
                "writable storage in fragment shaders",
                self.fragment_counters,
                "the `fragments` AOV (overdraw) raises an error naming the adapter",
            ),
            (
                "compute pipeline (visibility pass, surface in compute)",
                self.compute_pipeline(),
                "pipeline=\"compute\" raises an error naming the adapter; \"auto\" rasterises",
            ),
            (
                "max-mip prefetch (the walk's next node read a round early; POMKIT_PREFETCH)",
                self.prefetch,
                "off on a CPU adapter: each miss waits a round more, one read less",
            ),
            (
                "compute shaders",
                self.compute_shaders,
                "required: no usable adapter",
            ),
            (
                "textureGather on R32Float",
                self.gather,
                "required: no usable adapter",
            ),
            (
                "shader f64",
                self.shader_f64,
                "not used: the float64 oracle runs on the CPU",
            ),
            (
                "compute writes to mip-level views",
                self.storage_mip_views,
                "each mip level reduced into its own texture and copied",
            ),
            (
                "colour attachments with gaps",
                self.sparse_attachments,
                "the targets before the last requested one are written too (not read)",
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn wgpu_version_is_the_locked_one() {
        let lock = include_str!("../../Cargo.lock");
        let i = lock
            .find("name = \"wgpu\"\nversion = \"")
            .expect("wgpu in Cargo.lock");
        let rest = &lock[i + "name = \"wgpu\"\nversion = \"".len()..];
        assert_eq!(&rest[..rest.find('"').unwrap()], super::WGPU_VERSION);
    }
}

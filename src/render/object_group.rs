//! The object bind group (group 1), declared once: `OBJECT_GROUP` lists its bindings in order,
//! each with the name shaders/object.wgsl gives it and what it holds. The layout
//! (pipelines.rs) and every object's group (mod.rs, from an `ObjectBindings`) are made from the
//! list, and a test holds object.wgsl's `@group(1)` declarations to it.

use crate::gpu::layout;

/// What a binding of the object group holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// the object's uniforms (`ObjectUniforms`)
    Globals,
    /// the height map, and its sampler (filtering where the adapter filters float32 textures)
    Height,
    HeightSampler,
    /// the albedo (rgba8, always filterable), and its sampler
    Albedo,
    AlbedoSampler,
    /// the max pyramid: its level 0, the atlas of levels 1.., and the children atlas
    Max0,
    MaxAtlas,
    MaxChildren,
}

/// The object group's bindings in binding order, with their names in shaders/object.wgsl.
pub const OBJECT_GROUP: [(Slot, &str); 8] = [
    (Slot::Globals, "G"),
    (Slot::Height, "height_tex"),
    (Slot::HeightSampler, "height_samp"),
    (Slot::Albedo, "albedo_tex"),
    (Slot::AlbedoSampler, "albedo_samp"),
    (Slot::Max0, "max0_tex"),
    (Slot::MaxAtlas, "max_atlas"),
    (Slot::MaxChildren, "max_children"),
];

/// The layout's entries, visible to every stage; `filterable`: whether the adapter filters
/// float32 textures (the height map's texture and sampler then filter).
pub fn layout_entries(filterable: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
    let stages =
        wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE;
    let tex = |b: u32, filterable: bool| {
        layout::texture(b, stages, wgpu::TextureSampleType::Float { filterable })
    };
    let samp = |b: u32, filtering: bool| {
        let ty = if filtering {
            wgpu::SamplerBindingType::Filtering
        } else {
            wgpu::SamplerBindingType::NonFiltering
        };
        layout::sampler(b, stages, ty)
    };
    OBJECT_GROUP
        .iter()
        .enumerate()
        .map(|(b, (slot, _))| {
            let b = b as u32;
            match slot {
                Slot::Globals => layout::buffer(b, stages, wgpu::BufferBindingType::Uniform),
                Slot::Height => tex(b, filterable),
                Slot::HeightSampler => samp(b, filterable),
                Slot::Albedo => tex(b, true),
                Slot::AlbedoSampler => samp(b, true),
                Slot::Max0 | Slot::MaxAtlas | Slot::MaxChildren => tex(b, false),
            }
        })
        .collect()
}

/// One object's resources for its group, by what they hold.
pub struct ObjectBindings<'a> {
    pub globals: wgpu::BindingResource<'a>,
    pub height: &'a wgpu::TextureView,
    pub height_sampler: &'a wgpu::Sampler,
    pub albedo: &'a wgpu::TextureView,
    pub albedo_sampler: &'a wgpu::Sampler,
    pub max0: &'a wgpu::TextureView,
    pub max_atlas: &'a wgpu::TextureView,
    pub max_children: &'a wgpu::TextureView,
}

impl<'a> ObjectBindings<'a> {
    /// The resources in `OBJECT_GROUP`'s order.
    pub fn resources(self) -> Vec<wgpu::BindingResource<'a>> {
        use wgpu::BindingResource as R;
        let mut globals = Some(self.globals);
        OBJECT_GROUP
            .iter()
            .map(|(slot, _)| match slot {
                Slot::Globals => globals.take().expect("one Globals slot"),
                Slot::Height => R::TextureView(self.height),
                Slot::HeightSampler => R::Sampler(self.height_sampler),
                Slot::Albedo => R::TextureView(self.albedo),
                Slot::AlbedoSampler => R::Sampler(self.albedo_sampler),
                Slot::Max0 => R::TextureView(self.max0),
                Slot::MaxAtlas => R::TextureView(self.max_atlas),
                Slot::MaxChildren => R::TextureView(self.max_children),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::OBJECT_GROUP;

    /// shaders/object.wgsl declares group 1's bindings with the names and numbers of
    /// `OBJECT_GROUP`, and no other.
    #[test]
    fn object_wgsl_declares_the_group_as_listed() {
        let src = include_str!("../../shaders/object.wgsl");
        let mut found: Vec<(u32, String)> = src
            .lines()
            .filter_map(|l| {
                let rest = l.trim().strip_prefix("@group(1) @binding(")?;
                let (n, decl) = rest.split_once(')')?;
                let decl = decl.trim().strip_prefix("var")?;
                // past an address space (var<uniform>)
                let decl = match decl.split_once('>') {
                    Some((q, after)) if q.trim_start().starts_with('<') => after,
                    _ => decl,
                };
                Some((n.parse().ok()?, decl.split(':').next()?.trim().to_string()))
            })
            .collect();
        found.sort();
        let want: Vec<(u32, String)> = OBJECT_GROUP
            .iter()
            .enumerate()
            .map(|(b, (_, name))| (b as u32, name.to_string()))
            .collect();
        assert_eq!(found, want);
    }
}

//! The shadow map: the scene's displaced surfaces' depth seen from the first directional light
//! (orthographic, fitted to the scene's bounding sphere), rendered before the surface pass.

use super::resources::Draw;
use super::targets::DEPTH_FORMAT;
use crate::contract::Spec;
use crate::scene::{Light, Scene};
use glam::DVec3;

#[derive(Clone, Copy, Debug)]
pub struct ShadowSetup {
    /// index of the shadowed light
    pub light: usize,
    pub view_proj: [[f32; 4]; 4],
    /// world size of a shadow-map texel
    pub texel: f32,
    pub size: u32,
    /// the cast-shadow lookup's depth bias: two texels of world length, in depth units
    pub bias: f32,
}

/// The shadow map a pass needs, if any: for the first directional light with `cast_shadows`
/// (every method: objects shadow each other), or else, for a method whose self-shadowing is
/// the shadow map of its own geometry (`Spec::shadow_map_self`), for the first directional light.
pub fn setup(scene: &Scene, spec: &Spec, max_dim: u32) -> Option<ShadowSetup> {
    let directional = |cast_only: bool| {
        scene.lights.iter().enumerate().find_map(|(i, l)| match l {
            Light::Directional(l) if l.cast_shadows || !cast_only => {
                Some((i, DVec3::from(l.direction).normalize(), l.shadow_map_size))
            }
            _ => None,
        })
    };
    let own_shadows = spec.shadow_map_self;
    let (i, dir, size) = directional(true).or_else(|| {
        if own_shadows {
            directional(false)
        } else {
            None
        }
    })?;
    let (c, r) = scene.bounding_sphere();
    let size = size.clamp(1, max_dim);
    let up = if dir.y.abs() < 0.99 {
        DVec3::Y
    } else {
        DVec3::X
    };
    let right = dir.cross(up).normalize();
    let up = right.cross(dir);
    let eye = c - dir * (2.0 * r);
    // orthographic: x, y in [-r, r], depth along dir from eye in [0, 4r]
    let m = glam::DMat4::from_cols(
        glam::DVec4::new(right.x / r, up.x / r, dir.x / (4.0 * r), 0.0),
        glam::DVec4::new(right.y / r, up.y / r, dir.y / (4.0 * r), 0.0),
        glam::DVec4::new(right.z / r, up.z / r, dir.z / (4.0 * r), 0.0),
        glam::DVec4::new(
            -right.dot(eye) / r,
            -up.dot(eye) / r,
            -dir.dot(eye) / (4.0 * r),
            1.0,
        ),
    );
    Some(ShadowSetup {
        light: i,
        view_proj: m.as_mat4().to_cols_array_2d(),
        texel: (2.0 * r / size as f64) as f32,
        size,
        // depth spans 4r; a texel spans 2r / size
        bias: (2.0 * (2.0 * r / size as f64) / (4.0 * r)) as f32,
    })
}

/// A depth texture of `size`² texels for shadow maps (the renderer keeps the last one).
pub fn target(ctx: &crate::gpu::Context, size: u32) -> crate::Result<wgpu::TextureView> {
    ctx.scoped(|| {
        Ok(ctx
            .texture_2d(
                "shadow map",
                (size, size),
                DEPTH_FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&Default::default()))
    })
}

/// Encode the shadow-map pass (depth only) of every object into `enc`, rendering into `target`
/// with `view_bind` (the frame's view bind group without the shadow map) at group 0.
pub fn encode(
    enc: &mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    view_bind: &wgpu::BindGroup,
    draws: &[Draw],
) {
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("shadow map"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: target,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, view_bind, &[]);
    for d in draws {
        pass.set_bind_group(1, &d.object, &[]);
        pass.set_bind_group(2, &d.method, &[]);
        d.mesh.draw(&mut pass);
    }
}

//! The uniform blocks' layouts: every field of `render::uniforms::{View, ObjectUniforms, LightU}` has
//! the same name and offset as in the composed WGSL (shaders/view.wgsl, shaders/object.wgsl).

use pomkit::methods::{Method, PerPixel};
use pomkit::render::uniforms::{LightU, ObjectUniforms, View};
use pomkit::shaders::ShaderLib;

/// The members (name, offset) of the composed module's struct `name`.
fn wgsl_members(module: &naga::Module, name: &str) -> Vec<(String, usize)> {
    for (_, ty) in module.types.iter() {
        let undecorated = ty
            .name
            .as_deref()
            .map(|n| n.split("X_naga_oil").next().unwrap_or(n).to_string());
        if undecorated.as_deref() == Some(name) {
            if let naga::TypeInner::Struct { members, .. } = &ty.inner {
                return members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
                    .collect();
            }
        }
    }
    panic!("no struct {name} in the composed module");
}

#[test]
fn uniform_layout() {
    let lib = ShaderLib::new().unwrap();
    let spec = Method::pom(PerPixel::off()).spec();
    let module = lib
        .compose(
            &spec,
            pomkit::contract::Filtering::Hardware,
            Default::default(),
            "method",
        )
        .unwrap();
    for (name, fields, size) in [
        ("View", View::FIELDS, std::mem::size_of::<View>()),
        (
            "ObjectUniforms",
            ObjectUniforms::FIELDS,
            std::mem::size_of::<ObjectUniforms>(),
        ),
        ("Light", LightU::FIELDS, std::mem::size_of::<LightU>()),
    ] {
        let wgsl = wgsl_members(&module, name);
        let rust: Vec<(String, usize)> = fields.iter().map(|(n, o)| (n.to_string(), *o)).collect();
        assert_eq!(wgsl, rust, "{name}: WGSL and Rust layouts differ");
        let last = module
            .types
            .iter()
            .find(|(_, t)| {
                t.name
                    .as_deref()
                    .map(|n| n.starts_with(name))
                    .unwrap_or(false)
            })
            .map(|(_, t)| t.inner.size(module.to_ctx()));
        assert_eq!(last, Some(size as u32), "{name}: size");
    }
}

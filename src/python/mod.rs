//! The pyo3 layer: conversion only, one file per concept (tokenizers' layout). The Renderer
//! (`renderer.rs`), scenes (`scene_args.rs`), meshes (`mesh_args.rs`), Tessellated's CPU mesh
//! (`tessellation.rs`), methods (`method_args.rs`), frames (`frame.rs`), the oracle
//! (`oracle_arrays.rs`), assets (`assets.rs`), image files (`io.rs`), long builds
//! (`build_hooks.rs`) and errors (`errors.rs`); this file holds the module's init and the
//! schema's tables.

mod arrays;
mod assets;
mod build_hooks;
mod errors;
mod fields;
mod frame;
mod handles;
mod io;
mod jod;
mod method_args;
mod oracle_arrays;
mod renderer;
mod mesh_args;
mod scene_args;
mod tessellation;

use handles::{PyAlbedoData, PyHeightData, PyMeshData};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The scene's schema classes (src/scene/schema.rs) as Python builds them: class name ->
/// (doc, [(field, kind, default literal or None, lo, hi, doc)]).
fn schema(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for (class, doc, fields) in crate::scene::schema::classes() {
        let fs: Vec<_> = fields
            .iter()
            .map(|f| {
                let (lo, hi) = f.kind.range().unzip();
                (f.name, f.kind.name(), f.default, lo, hi, f.doc.trim())
            })
            .collect();
        d.set_item(class, (doc.trim(), fs))?;
    }
    Ok(d)
}

/// Per schema class, its fields marked `@ setting` (pomkit's own renderer's settings, which no
/// reference render reads).
fn schema_settings(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for (class, _, fields) in crate::scene::schema::classes() {
        let names: Vec<_> = fields.iter().filter(|f| f.setting).map(|f| f.name).collect();
        d.set_item(class, names)?;
    }
    Ok(d)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "WALK_BYTES_PER_TRIANGLE",
        crate::methods::WALK_BYTES_PER_TRIANGLE,
    )?;
    m.add("PRISM_BYTES", crate::methods::PRISM_BYTES)?;
    m.add("PRISM_VERTEX_BYTES", crate::methods::PRISM_VERTEX_BYTES)?;
    // the contracts Python derives its checks and Literals from (one source: the core)
    m.add("MAX_LIGHTS", crate::scene::MAX_LIGHTS)?;
    m.add("SCHEMA", schema(m.py())?)?;
    m.add("SCHEMA_SETTINGS", schema_settings(m.py())?)?;
    m.add("ASSET_REPORT_FIELDS", assets::report_fields())?;
    m.add("METHOD_FIELDS", crate::methods::method_fields())?;
    m.add("HYBRID_FINE_KINDS", crate::methods::WINDOWED.to_vec())?;
    m.add("AOV_NAMES", crate::render::Aovs::NAMES.to_vec())?;
    // the AOVs counted only when named: those outside `aovs="all"`
    let standard = crate::render::Aovs::STANDARD;
    let cost: Vec<&str> = crate::render::Aovs::NAMES
        .iter()
        .copied()
        .filter(|n| !standard.has(n))
        .collect();
    m.add("COST_AOV_NAMES", cost)?;
    let docs = PyDict::new(m.py());
    for a in crate::render::aovs::AOVS {
        docs.set_item(a.name, a.doc)?;
    }
    m.add("AOV_DOCS", docs)?;
    m.add(
        "PIPELINES",
        crate::render::pipelines::Choice::NAMES.to_vec(),
    )?;
    m.add("SHADOW_KINDS", crate::methods::Shadows::NAMES.to_vec())?;
    m.add("FILTERING_KINDS", crate::methods::Filtering::NAMES.to_vec())?;
    m.add("CONE_KINDS", crate::methods::Cones::NAMES.to_vec())?;
    m.add(
        "NORMALS_MODES",
        crate::mesh::normals::NormalsMode::NAMES.to_vec(),
    )?;
    m.add("REFINE_KINDS", crate::methods::Refine::NAMES.to_vec())?;
    m.add(
        "PATTERN_KINDS",
        crate::methods::tessellated::Pattern::NAMES.to_vec(),
    )?;
    m.add("MAX_STEPS_LIMIT", crate::methods::MAX_STEPS_LIMIT)?;
    m.add_class::<renderer::PyRenderer>()?;
    m.add_class::<PyMeshData>()?;
    m.add_class::<frame::PyRenderedFrame>()?;
    m.add_class::<PyHeightData>()?;
    m.add_class::<PyAlbedoData>()?;
    m.add_class::<oracle_arrays::PyShells>()?;
    m.add_function(wrap_pyfunction!(renderer::adapters, m)?)?;
    m.add_function(wrap_pyfunction!(oracle_arrays::oracle_hits, m)?)?;
    m.add_function(wrap_pyfunction!(oracle_arrays::oracle_image, m)?)?;
    m.add_function(wrap_pyfunction!(oracle_arrays::reference_normals, m)?)?;
    m.add_function(wrap_pyfunction!(oracle_arrays::reference_directions, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_from_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(assets::load_gltf, m)?)?;
    m.add_function(wrap_pyfunction!(assets::shell_findings, m)?)?;
    m.add_function(wrap_pyfunction!(assets::check_asset, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_plane, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_torus, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_cylinder, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_args::mesh_cube, m)?)?;
    m.add_function(wrap_pyfunction!(scene_args::bounding_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(scene_args::light_power, m)?)?;
    m.add_function(wrap_pyfunction!(tessellation::tessellate, m)?)?;
    m.add_function(wrap_pyfunction!(io::load_image, m)?)?;
    m.add_function(wrap_pyfunction!(jod::jod, m)?)?;
    m.add_function(wrap_pyfunction!(jod::jod_displays, m)?)?;
    m.add_function(wrap_pyfunction!(build_hooks::set_progress_hook, m)?)?;
    m.add_function(wrap_pyfunction!(build_hooks::set_cache_dir, m)?)?;
    Ok(())
}

//! pomkit: inverse displacement mapping on wgpu.
//!
//! The core is usable without Python: build a [`scene::Scene`], pick a [`methods::Method`],
//! and call [`render::Renderer::render`]. The `python` feature adds the pyo3 layer
//! (`pomkit._core`), which only converts arrays and errors.

pub mod error;
pub mod exact;
pub mod gpu;
pub mod heightmap;
pub mod mesh;
pub mod methods;
pub mod prism;
pub mod render;
pub mod scene;
pub mod texspace;

#[cfg(feature = "python")]
mod python;

pub use error::{Error, Result};

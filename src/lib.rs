//! pomkit: inverse displacement mapping on wgpu.
//!
//! The core is usable without Python: build a [`scene::Scene`], pick a [`methods::Method`] (its `spec` says how it runs),
//! and call [`render::Renderer::render`]. The `python` feature adds the pyo3 layer
//! (`pomkit._core`, src/python/): it converts arguments, arrays and errors, and holds the hooks
//! that long builds report progress through.

pub mod assets;
pub mod contract;
pub mod error;
pub mod fields;
pub mod gpu;
pub mod heightmap;
pub mod imageio;
pub mod jod;
pub mod mesh;
pub mod methods;
pub mod oracle;
pub mod parallel;
pub mod progress;
pub mod render;
pub mod scene;
pub mod shaders;

#[cfg(feature = "python")]
mod python;

pub use error::{Error, Result};

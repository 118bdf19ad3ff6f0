//! Long builds across the boundary: the hook that reports their progress (to Python's
//! `pomkit._progress.report`, a tqdm bar) and the directory their results are cached in.

use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// Call `hook(label, done, total)` as a long build goes (None: nobody is told).
#[pyfunction]
#[pyo3(signature = (hook))]
pub fn set_progress_hook(hook: Option<Py<PyAny>>) {
    crate::progress::set_hook(hook.map(|h| {
        Arc::new(move |label: &str, done: u64, total: u64| {
            // a failing hook must not fail the build: its error is printed and dropped
            Python::attach(|py| {
                if let Err(e) = h.call1(py, (label, done, total)) {
                    e.print(py);
                }
            })
        }) as crate::progress::Hook
    }));
}

/// Keep builds that took longer than a second in `path` (None: keep nothing).
#[pyfunction]
#[pyo3(signature = (path))]
pub fn set_cache_dir(path: Option<PathBuf>) {
    crate::progress::set_cache_dir(path);
}

//! ColorVideoVDP across the boundary: `jod(test, reference, fps, display)` on (T, H, W, 3) or
//! (H, W, 3) float32 arrays of sRGB in [0, 1] (pomkit.metrics.jod encodes frames so).

use numpy::PyReadonlyArrayDyn;
use pyo3::prelude::*;

fn frames(
    a: &PyReadonlyArrayDyn<'_, f32>,
    name: &str,
) -> PyResult<((usize, usize, usize), Vec<f32>)> {
    let v = a.as_array();
    let s = v.shape();
    let (n, h, w) = match (s.len(), s.last()) {
        (3, Some(3)) => (1, s[0], s[1]),
        (4, Some(3)) => (s[0], s[1], s[2]),
        _ => {
            return Err(crate::python::errors::argument_error(format!(
                "{name}: expected shape (frames, H, W, 3) or (H, W, 3), got {s:?}"
            )))
        }
    };
    Ok(((n, h, w), v.iter().copied().collect()))
}

#[pyfunction]
#[pyo3(signature = (test, reference, fps=30.0, display="standard_4k"))]
pub fn jod(
    test: PyReadonlyArrayDyn<'_, f32>,
    reference: PyReadonlyArrayDyn<'_, f32>,
    fps: f64,
    display: &str,
) -> PyResult<f64> {
    let (st, t) = frames(&test, "test")?;
    let (sr, r) = frames(&reference, "reference")?;
    if st != sr {
        return Err(crate::python::errors::argument_error(format!(
            "reference: {sr:?} frames x H x W, the test has {st:?}; score videos of one size and length"
        )));
    }
    Ok(crate::jod::jod(&t, &r, st.2, st.1, st.0, fps, display)?)
}

#[pyfunction]
pub fn jod_displays() -> Vec<&'static str> {
    crate::jod::displays()
}

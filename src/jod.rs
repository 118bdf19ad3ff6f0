//! ColorVideoVDP's JOD (just-objectionable-differences; 10 = no visible difference) of a test
//! video against a reference video, by the pure-Rust `colorvideovdp` crate (Mantiuk et al. 2024,
//! base model 0.5.7). Frames are display-encoded sRGB in [0, 1], interleaved RGB, row-major, as
//! they would be shown; one frame is scored as an image, several as a video at `fps`.

use crate::error::{Error, Result};
use colorvideovdp::{Color, Cvvdp, DisplayModel, Image, Options};

/// The display the frames are judged on when none is named (also the default of the Python
/// binding, src/python/jod.rs): a 30-inch 4K monitor at 0.75 m,
/// 200 cd/m² (ColorVideoVDP's own default).
pub const DEFAULT_DISPLAY: &str = "standard_4k";

/// The displays ColorVideoVDP knows by name.
pub fn displays() -> Vec<&'static str> {
    let mut v = DisplayModel::names().unwrap_or_default();
    v.sort_unstable();
    v
}

fn frames(name: &str, data: &[f32], w: usize, h: usize, n: usize) -> Result<Vec<Image>> {
    if data.len() != w * h * 3 * n {
        return Err(Error::arg(
            name,
            format!(
                "expected {n} frames of {w}x{h}x3 values, got {} values",
                data.len()
            ),
        ));
    }
    if let Some(bad) = data.iter().position(|v| !v.is_finite()) {
        return Err(Error::arg(
            name,
            format!("value {bad} is not finite; encode the frames as sRGB in [0, 1]"),
        ));
    }
    data.chunks_exact(w * h * 3)
        .map(|c| Image::new(w, h, 3, c.to_vec()).map_err(|e| Error::arg(name, e.to_string())))
        .collect()
}

/// The JOD of `test` against `reference`, each `n` frames of `w` x `h` sRGB pixels in [0, 1]
/// (interleaved RGB), at `fps`, on the display named `display` (see `displays`).
pub fn jod(
    test: &[f32],
    reference: &[f32],
    w: usize,
    h: usize,
    n: usize,
    fps: f64,
    display: &str,
) -> Result<f64> {
    if w < 4 || h < 4 || n == 0 {
        return Err(Error::arg(
            "frames",
            format!("need at least one frame of at least 4x4 pixels, got {n} of {w}x{h}"),
        ));
    }
    if !(fps > 0.0 && fps <= 16384.0) {
        return Err(Error::arg(
            "fps",
            format!("must lie in (0, 16384], got {fps}"),
        ));
    }
    let model = DisplayModel::from_name(display).map_err(|_| {
        Error::arg(
            "display",
            format!(
                "unknown display {display:?}; one of {}",
                displays().join(", ")
            ),
        )
    })?;
    let metric =
        Cvvdp::new(model, Options::default()).map_err(|e| Error::arg("display", e.to_string()))?;
    let (t, r) = (
        frames("test", test, w, h, n)?,
        frames("reference", reference, w, h, n)?,
    );
    let p = if n == 1 {
        metric.predict_image(&t[0], &r[0], Color::Srgb)
    } else {
        metric.predict_video(&t, &r, fps as f32, Color::Srgb)
    }
    .map_err(|e| Error::arg("frames", e.to_string()))?;
    Ok(p.jod as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(w: usize, h: usize, n: usize, shift: impl Fn(usize) -> f32) -> Vec<f32> {
        let mut v = Vec::with_capacity(w * h * 3 * n);
        for k in 0..n {
            for y in 0..h {
                for x in 0..w {
                    let s =
                        0.5 + 0.4 * ((x as f32 + shift(k)) * 0.4).sin() * ((y as f32) * 0.3).cos();
                    v.extend([s, s * 0.9, s * 0.8]);
                }
            }
        }
        v
    }

    #[test]
    fn identical_videos_score_ten() {
        let a = ramp(32, 32, 6, |_| 0.0);
        assert!((jod(&a, &a, 32, 32, 6, 30.0, DEFAULT_DISPLAY).unwrap() - 10.0).abs() < 1e-3);
        assert!(
            (jod(
                &a[..32 * 32 * 3],
                &a[..32 * 32 * 3],
                32,
                32,
                1,
                30.0,
                DEFAULT_DISPLAY
            )
            .unwrap()
                - 10.0)
                .abs()
                < 1e-3
        );
    }

    /// A colour offset of 0.05 that alternates with none every frame (a 15 Hz flicker at 30 fps)
    /// scores below the same offset held still (measured: 8.11 against 9.60 JOD). A positional
    /// shift of fine texture is another matter: alternating a 1-pixel shift with none scored
    /// above the steady shift (5.14 against 4.04), the eye averaging the two positions.
    #[test]
    fn a_flickering_offset_scores_below_a_steady_one() {
        let n = 16;
        let r = ramp(32, 32, n, |_| 0.0);
        let offset = |on: &dyn Fn(usize) -> bool| -> Vec<f32> {
            let mut v = r.clone();
            for (i, x) in v.iter_mut().enumerate() {
                *x += if on(i / (32 * 32 * 3)) { 0.05 } else { 0.0 };
            }
            v
        };
        let j = |v: &Vec<f32>| jod(v, &r, 32, 32, n, 30.0, DEFAULT_DISPLAY).unwrap();
        let (steady, flicker) = (j(&offset(&|_| true)), j(&offset(&|k| k % 2 == 0)));
        assert!(
            steady < 10.0 && flicker < steady - 1.0,
            "steady {steady}, flickering {flicker}"
        );
    }

    #[test]
    fn bad_input_names_the_argument() {
        let a = ramp(8, 8, 1, |_| 0.0);
        assert!(jod(&a, &a, 8, 8, 2, 30.0, DEFAULT_DISPLAY)
            .unwrap_err()
            .to_string()
            .contains("test"));
        assert!(jod(&a, &a, 8, 8, 1, 30.0, "nope")
            .unwrap_err()
            .to_string()
            .contains("display"));
        assert!(jod(&a, &a, 8, 8, 1, -1.0, DEFAULT_DISPLAY)
            .unwrap_err()
            .to_string()
            .contains("fps"));
    }
}

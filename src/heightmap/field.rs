//! The height map and the bilinear, repeating field it defines: the project's central
//! definition (docs/conventions.md), which every method, the oracle and the references sample.

use crate::error::{Error, Result};

/// A height map: row-major, `data[r * width + c]` is the texel centred at
/// u = (c + 0.5) / width, v = (r + 0.5) / height. Values in [0, 1].
#[derive(Clone, Debug)]
pub struct HeightMap {
    pub width: u32,
    pub height: u32,
    pub data: Vec<f32>,
}

/// The integer at or below x, for finite x within i64's range (one conversion, not a call to
/// libm, as `f64::floor` is on a baseline x86-64 target).
#[inline]
pub(crate) fn floor(x: f64) -> i64 {
    let t = x as i64;
    t - ((t as f64) > x) as i64
}

impl HeightMap {
    pub fn new(width: u32, height: u32, data: Vec<f32>) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::arg(
                "height",
                "the height map is empty; pass a 2-D array with at least one texel",
            ));
        }
        if data.len() != (width as usize) * (height as usize) {
            return Err(Error::arg(
                "height",
                format!(
                    "expected {} values for a {width}x{height} map, got {}",
                    width as usize * height as usize,
                    data.len()
                ),
            ));
        }
        if let Some(i) = data.iter().position(|x| !x.is_finite()) {
            return Err(Error::arg(
                "height",
                format!("contains NaN or Inf (first at row {}, column {}); replace them, e.g. with np.nan_to_num", i / width as usize, i % width as usize),
            ));
        }
        if let Some(x) = data.iter().find(|x| **x < 0.0 || **x > 1.0) {
            return Err(Error::arg(
                "height",
                format!("values must lie in [0, 1], found {x}; normalise the map"),
            ));
        }
        Ok(Self {
            width,
            height,
            data,
        })
    }

    pub fn from_fn(width: u32, height: u32, f: impl Fn(f64, f64) -> f64) -> Self {
        let mut data = Vec::with_capacity((width * height) as usize);
        for r in 0..height {
            for c in 0..width {
                let u = (c as f64 + 0.5) / width as f64;
                let v = (r as f64 + 0.5) / height as f64;
                data.push(f(u, v).clamp(0.0, 1.0) as f32);
            }
        }
        Self {
            width,
            height,
            data,
        }
    }

    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> f64 {
        let w = self.width as i64;
        let h = self.height as i64;
        // (no division inside the period)
        let wrap = |i: i64, n: i64| {
            if (0..n).contains(&i) {
                i
            } else {
                i.rem_euclid(n)
            }
        };
        let xi = wrap(x, w) as usize;
        let yi = wrap(y, h) as usize;
        self.data[yi * self.width as usize + xi] as f64
    }

    /// The bilinear, repeating height field at texture coordinate (s, t) (tiled units).
    pub fn sample(&self, s: f64, t: f64) -> f64 {
        let x = s * self.width as f64 - 0.5;
        let y = t * self.height as f64 - 0.5;
        let (xi, yi) = (floor(x), floor(y));
        let fx = x - xi as f64;
        let fy = y - yi as f64;
        let h00 = self.texel(xi, yi);
        let h10 = self.texel(xi + 1, yi);
        let h01 = self.texel(xi, yi + 1);
        let h11 = self.texel(xi + 1, yi + 1);
        (h00 * (1.0 - fx) + h10 * fx) * (1.0 - fy) + (h01 * (1.0 - fx) + h11 * fx) * fy
    }

    /// The bilinear field at (s, t) and its derivatives along s and t (one-sided at a cell's
    /// edge: those of the cell the point lies in).
    pub fn sample_grad(&self, s: f64, t: f64) -> (f64, f64, f64) {
        let x = s * self.width as f64 - 0.5;
        let y = t * self.height as f64 - 0.5;
        let (xi, yi) = (floor(x), floor(y));
        let (fx, fy) = (x - xi as f64, y - yi as f64);
        let h00 = self.texel(xi, yi);
        let h10 = self.texel(xi + 1, yi);
        let h01 = self.texel(xi, yi + 1);
        let h11 = self.texel(xi + 1, yi + 1);
        let v = (h00 * (1.0 - fx) + h10 * fx) * (1.0 - fy) + (h01 * (1.0 - fx) + h11 * fx) * fy;
        let dx = (h10 - h00) * (1.0 - fy) + (h11 - h01) * fy;
        let dy = (h01 - h00) * (1.0 - fx) + (h11 - h10) * fx;
        (v, dx * self.width as f64, dy * self.height as f64)
    }
}

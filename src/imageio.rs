//! Height maps and albedos from image files, through the `image` crate (PNG, TIFF; OpenEXR in
//! pure Rust): values at the file's own precision.

use crate::error::{Error, Result};
use image::DynamicImage;
use std::path::Path;

/// An image's pixels as float32, row-major, `channels` per pixel, and the precision it had.
#[derive(Clone, Debug)]
pub struct Pixels {
    pub width: u32,
    pub height: u32,
    pub channels: usize,
    pub data: Vec<f32>,
    /// bits per channel in the file: 8, 16 or 32 (float)
    pub bits: u32,
}

fn bad(path: &Path, why: impl std::fmt::Display) -> Error {
    Error::arg("path", format!("{}: {why}", path.display()))
}

/// Decode `path`. Integer files become [0, 1] (value / max); float files keep their values.
pub fn load(path: &Path) -> Result<Pixels> {
    let reader = image::ImageReader::open(path)
        .map_err(|e| bad(path, format!("cannot open the file ({e})")))?
        .with_guessed_format()
        .map_err(|e| bad(path, format!("cannot read the file ({e})")))?;
    match reader.format() {
        None => return Err(bad(path, "not a PNG, TIFF or OpenEXR file")),
        Some(image::ImageFormat::Tiff) => {
            if let Some(p) = float_grey_tiff(path)? {
                return Ok(p);
            }
        }
        Some(_) => {}
    }
    let img = reader
        .decode()
        .map_err(|e| bad(path, format!("cannot decode the image ({e})")))?;
    let (width, height) = (img.width(), img.height());
    let scale8 = |v: &[u8]| v.iter().map(|&x| x as f32 / 255.0).collect::<Vec<_>>();
    let scale16 = |v: &[u16]| v.iter().map(|&x| x as f32 / 65535.0).collect::<Vec<_>>();
    let (channels, data, bits) = match &img {
        DynamicImage::ImageLuma8(b) => (1, scale8(b.as_raw()), 8),
        DynamicImage::ImageLumaA8(b) => (2, scale8(b.as_raw()), 8),
        DynamicImage::ImageRgb8(b) => (3, scale8(b.as_raw()), 8),
        DynamicImage::ImageRgba8(b) => (4, scale8(b.as_raw()), 8),
        DynamicImage::ImageLuma16(b) => (1, scale16(b.as_raw()), 16),
        DynamicImage::ImageLumaA16(b) => (2, scale16(b.as_raw()), 16),
        DynamicImage::ImageRgb16(b) => (3, scale16(b.as_raw()), 16),
        DynamicImage::ImageRgba16(b) => (4, scale16(b.as_raw()), 16),
        DynamicImage::ImageRgb32F(b) => (3, b.as_raw().clone(), 32),
        DynamicImage::ImageRgba32F(b) => (4, b.as_raw().clone(), 32),
        _ => return Err(bad(path, "unsupported pixel format")),
    };
    if width == 0 || height == 0 {
        return Err(bad(path, "the image is empty"));
    }
    Ok(Pixels {
        width,
        height,
        channels,
        data,
        bits,
    })
}

/// A 32-bit float greyscale TIFF (what scientific tools write for height maps), read with the
/// `tiff` crate; None for any other TIFF (left to `image`).
fn float_grey_tiff(path: &Path) -> Result<Option<Pixels>> {
    use tiff::decoder::{Decoder, DecodingResult};
    let file =
        std::fs::File::open(path).map_err(|e| bad(path, format!("cannot open the file ({e})")))?;
    let mut d = Decoder::new(std::io::BufReader::new(file))
        .map_err(|e| bad(path, format!("cannot decode the image ({e})")))?;
    if d.colortype().ok() != Some(tiff::ColorType::Gray(32)) {
        return Ok(None);
    }
    let (width, height) = d
        .dimensions()
        .map_err(|e| bad(path, format!("cannot decode the image ({e})")))?;
    match d.read_image() {
        Ok(DecodingResult::F32(data)) => Ok(Some(Pixels {
            width,
            height,
            channels: 1,
            data,
            bits: 32,
        })),
        // 32-bit integer grey: not a float map; let `image` report it
        Ok(_) => Ok(None),
        Err(e) => Err(bad(path, format!("cannot decode the image ({e})"))),
    }
}

/// A height map: one channel. A grey file's channel; a colour file only when its colour
/// channels are equal (grey stored as RGB), else an error naming the path.
pub fn load_height(path: &Path) -> Result<Pixels> {
    let p = load(path)?;
    let colour = match p.channels {
        1 | 2 => 1,
        _ => 3,
    };
    let n = (p.width * p.height) as usize;
    let mut out = Vec::with_capacity(n);
    for px in p.data.chunks_exact(p.channels) {
        if colour == 3 && (px[1] != px[0] || px[2] != px[0]) {
            return Err(bad(
                path,
                "a height map must be greyscale; this file has colour (convert it to one channel)",
            ));
        }
        out.push(px[0]);
    }
    if let Some(i) = out.iter().position(|x| !x.is_finite()) {
        return Err(bad(
            path,
            format!(
                "holds NaN or Inf at row {}, column {}",
                i / p.width as usize,
                i % p.width as usize
            ),
        ));
    }
    Ok(Pixels {
        channels: 1,
        data: out,
        ..p
    })
}

/// An albedo: three channels (alpha dropped; grey files repeated). Integer files hold sRGB
/// (decoded to linear by the caller, which knows the transfer function), float files linear.
pub fn load_albedo(path: &Path) -> Result<Pixels> {
    let p = load(path)?;
    let mut out = Vec::with_capacity((p.width * p.height) as usize * 3);
    for px in p.data.chunks_exact(p.channels) {
        match p.channels {
            1 | 2 => out.extend_from_slice(&[px[0]; 3]),
            _ => out.extend_from_slice(&px[..3]),
        }
    }
    if out.iter().any(|x| !x.is_finite() || *x < 0.0) {
        return Err(bad(path, "holds negative, NaN or Inf values"));
    }
    Ok(Pixels {
        channels: 3,
        data: out,
        ..p
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_bit_png_keeps_its_precision() {
        let dir = std::env::temp_dir().join(format!("pomkit-img-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("h16.png");
        let img = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(4, 3, |x, y| {
            image::Luma([(x * 1000 + y * 7 + 1) as u16])
        });
        img.save(&path).unwrap();
        let p = load_height(&path).unwrap();
        assert_eq!((p.width, p.height, p.bits), (4, 3, 16));
        assert_eq!(p.data[4 + 2], (2 * 1000 + 7 + 1) as f32 / 65535.0);
        let e = load_height(&dir.join("missing.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("path") && e.contains("missing.png"), "{e}");
    }
}

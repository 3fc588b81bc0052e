//! Reading and writing images: OpenEXR (float RGB), PFM, PNG (8-bit sRGB with an exposure).
//!
//! [`Image`] is linear RGB in row-major order, row 0 at the top.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Errors of image I/O; every variant names the file.
#[derive(Debug, Error)]
pub enum ImageError {
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: unsupported image format (expected .exr, .pfm or .png)")]
    UnknownExtension { path: PathBuf },
}

/// A linear-RGB float image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    /// Row-major pixels, row 0 at the top.
    pub data: Vec<[f32; 3]>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            data: vec![[0.0; 3]; width * height],
        }
    }
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        self.data[y * self.width + x]
    }
    #[inline]
    pub fn set(&mut self, x: usize, y: usize, v: [f32; 3]) {
        self.data[y * self.width + x] = v;
    }

    /// Reads `.exr`, `.pfm` or `.png` (PNG is decoded from sRGB to linear).
    pub fn read(path: &Path) -> Result<Image, ImageError> {
        match extension(path).as_deref() {
            Some("exr") => read_exr(path),
            Some("pfm") => {
                let bytes = std::fs::read(path).map_err(|e| io_err(path, e))?;
                parse_pfm(&bytes).map_err(|m| fmt_err(path, m))
            }
            Some("png") => read_png(path),
            _ => Err(ImageError::UnknownExtension {
                path: path.to_path_buf(),
            }),
        }
    }
    /// Writes by extension: `.exr`, `.pfm` (linear float) or `.png` (sRGB, exposure 0).
    pub fn write(&self, path: &Path) -> Result<(), ImageError> {
        match extension(path).as_deref() {
            Some("exr") => self.write_exr(path),
            Some("pfm") => self.write_pfm(path),
            Some("png") => self.write_png(path, 0.0),
            _ => Err(ImageError::UnknownExtension {
                path: path.to_path_buf(),
            }),
        }
    }
    /// Writes 32-bit float RGB OpenEXR.
    pub fn write_exr(&self, path: &Path) -> Result<(), ImageError> {
        self.check_size(path)?;
        use exr::prelude::{Image as ExrImage, SpecificChannels, WritableImage};
        let channels = SpecificChannels::rgb(|exr::math::Vec2(x, y)| {
            let p = self.get(x, y);
            (p[0], p[1], p[2])
        });
        // Compressed blocks are written in the order they finish when exr compresses in
        // parallel, so the file's bytes would vary from run to run; one thread keeps them a pure
        // function of the pixels (same seed, same bytes).
        ExrImage::from_channels((self.width, self.height), channels)
            .write()
            .non_parallel()
            .to_file(path)
            .map_err(|e| fmt_err(path, format!("cannot write OpenEXR: {e}")))
    }
    /// Writes little-endian PFM (bottom-to-top rows as the format requires).
    pub fn write_pfm(&self, path: &Path) -> Result<(), ImageError> {
        self.check_size(path)?;
        std::fs::write(path, self.encode_pfm()).map_err(|e| io_err(path, e))
    }
    /// Writes an 8-bit sRGB PNG after scaling by 2^`exposure` and clamping to [0, 1].
    pub fn write_png(&self, path: &Path, exposure: f32) -> Result<(), ImageError> {
        self.check_size(path)?;
        let (w, h) = png_size(path, self.width, self.height)?;
        let buf = self.to_srgb8(exposure);
        image::save_buffer_with_format(
            path,
            &buf,
            w,
            h,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| image_err(path, e))
    }

    /// The 8-bit sRGB pixels (RGB, row-major, row 0 at the top) PNG output holds: linear values
    /// times `2^exposure`, clamped to [0, 1] (NaN → 0) and encoded with the sRGB curve.
    pub fn to_srgb8(&self, exposure: f32) -> Vec<u8> {
        let scale = exposure.exp2();
        self.data
            .iter()
            .flat_map(|p| p.map(|v| encode_srgb8(v * scale)))
            .collect()
    }

    /// The PFM encoding ("PF", little-endian, rows bottom to top) of this image.
    pub fn encode_pfm(&self) -> Vec<u8> {
        let header = format!("PF\n{} {}\n-1.0\n", self.width, self.height);
        let mut out = Vec::with_capacity(header.len() + self.data.len() * 12);
        out.extend_from_slice(header.as_bytes());
        for y in (0..self.height).rev() {
            for x in 0..self.width {
                for c in self.get(x, y) {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
        out
    }

    fn check_size(&self, path: &Path) -> Result<(), ImageError> {
        if self.width == 0 || self.height == 0 || self.data.len() != self.width * self.height {
            return Err(fmt_err(
                path,
                format!(
                    "cannot write a {}x{} image with {} pixels",
                    self.width,
                    self.height,
                    self.data.len()
                ),
            ));
        }
        Ok(())
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

fn io_err(path: &Path, source: std::io::Error) -> ImageError {
    ImageError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn fmt_err(path: &Path, message: impl Into<String>) -> ImageError {
    ImageError::Format {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

fn image_err(path: &Path, e: image::ImageError) -> ImageError {
    match e {
        image::ImageError::IoError(source) => io_err(path, source),
        e => fmt_err(path, e.to_string()),
    }
}

fn png_size(path: &Path, w: usize, h: usize) -> Result<(u32, u32), ImageError> {
    match (u32::try_from(w), u32::try_from(h)) {
        (Ok(w), Ok(h)) => Ok((w, h)),
        _ => Err(fmt_err(path, format!("image {w}x{h} is too large for PNG"))),
    }
}

/// Linear value → 8-bit sRGB code (clamped to [0, 1]; NaN becomes 0).
fn encode_srgb8(v: f32) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (linear_to_srgb(v) * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8
}

fn read_exr(path: &Path) -> Result<Image, ImageError> {
    if let Err(e) = std::fs::metadata(path) {
        return Err(io_err(path, e));
    }
    let img = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |res, _| Image::new(res.width(), res.height()),
        |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            img.set(pos.x(), pos.y(), [r, g, b]);
        },
    )
    .map_err(|e| fmt_err(path, format!("cannot read OpenEXR: {e}")))?;
    Ok(img.layer_data.channel_data.pixels)
}

fn read_png(path: &Path) -> Result<Image, ImageError> {
    let reader = image::ImageReader::open(path).map_err(|e| io_err(path, e))?;
    let mut reader = reader.with_guessed_format().map_err(|e| io_err(path, e))?;
    reader.set_format(image::ImageFormat::Png);
    let dynimg = reader.decode().map_err(|e| image_err(path, e))?;
    let (w, h) = (dynimg.width() as usize, dynimg.height() as usize);
    let mut img = Image::new(w, h);
    let sixteen = matches!(
        dynimg.color(),
        image::ColorType::L16
            | image::ColorType::La16
            | image::ColorType::Rgb16
            | image::ColorType::Rgba16
    );
    if sixteen {
        let rgb = dynimg.into_rgb16();
        for (dst, px) in img.data.iter_mut().zip(rgb.pixels()) {
            *dst = px.0.map(|c| srgb_to_linear(c as f32 / 65535.0));
        }
    } else {
        // 8-bit: a lookup table makes the decode exact and fast.
        let lut: Vec<f32> = (0..256).map(|c| srgb_to_linear(c as f32 / 255.0)).collect();
        let rgb = dynimg.into_rgb8();
        for (dst, px) in img.data.iter_mut().zip(rgb.pixels()) {
            *dst = px.0.map(|c| lut[c as usize]);
        }
    }
    Ok(img)
}

/// Parses a PFM file ("PF" colour or "Pf" greyscale, either endianness; rows bottom to top).
fn parse_pfm(bytes: &[u8]) -> Result<Image, String> {
    let mut pos = 0usize;
    let mut token = |what: &str| -> Result<String, String> {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && pos - start < 64 {
            pos += 1;
        }
        if start == pos {
            return Err(format!("truncated PFM header: expected {what}"));
        }
        let t = std::str::from_utf8(&bytes[start..pos])
            .map_err(|_| format!("invalid PFM header: expected {what}"))?;
        Ok(t.to_string())
    };
    let magic = token("'PF' or 'Pf'")?;
    let channels = match magic.as_str() {
        "PF" => 3,
        "Pf" => 1,
        m => {
            return Err(format!(
                "not a PFM file (magic '{m}', expected 'PF' or 'Pf')"
            ));
        }
    };
    let width: usize = token("width")?
        .parse()
        .map_err(|_| "invalid PFM width".to_string())?;
    let height: usize = token("height")?
        .parse()
        .map_err(|_| "invalid PFM height".to_string())?;
    let scale: f32 = token("scale")?
        .parse()
        .map_err(|_| "invalid PFM scale".to_string())?;
    if scale == 0.0 || !scale.is_finite() {
        return Err(format!("invalid PFM scale {scale}"));
    }
    let little = scale < 0.0;
    // Exactly one whitespace character separates the header from the data.
    if pos >= bytes.len() || !bytes[pos].is_ascii_whitespace() {
        return Err("truncated PFM file: no pixel data".into());
    }
    pos += 1;
    if width == 0 || height == 0 {
        return Err(format!("invalid PFM size {width}x{height}"));
    }
    let needed = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(channels * 4))
        .ok_or_else(|| format!("PFM size {width}x{height} is too large"))?;
    let data = &bytes[pos..];
    if data.len() < needed {
        return Err(format!(
            "truncated PFM file: {width}x{height}x{channels} needs {needed} bytes of data, found {}",
            data.len()
        ));
    }
    let mut img = Image::new(width, height);
    let mut floats = data[..needed].chunks_exact(4).map(|c| {
        let b = [c[0], c[1], c[2], c[3]];
        if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    });
    for y in (0..height).rev() {
        for x in 0..width {
            let px = if channels == 3 {
                let r = floats.next().unwrap_or(0.0);
                let g = floats.next().unwrap_or(0.0);
                let b = floats.next().unwrap_or(0.0);
                [r, g, b]
            } else {
                let v = floats.next().unwrap_or(0.0);
                [v; 3]
            };
            img.set(x, y, px);
        }
    }
    Ok(img)
}

/// sRGB transfer function (linear → encoded), IEC 61966-2-1.
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse sRGB transfer function (encoded → linear).
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("caustica-image-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A test image with distinct, non-round values (including HDR and tiny values).
    fn pattern(w: usize, h: usize) -> Image {
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let t = (y * w + x) as f32;
                img.set(
                    x,
                    y,
                    [
                        t * 0.137 + 0.001,
                        1.0 / (t + 3.0),
                        (t * 0.71).sin() * 40.0 + 41.0,
                    ],
                );
            }
        }
        img
    }

    #[test]
    fn exr_bytes_are_a_function_of_the_pixels() {
        // 600 rows are ~38 compressed blocks: written in parallel, their order in the file
        // followed whichever thread finished first and two writes of one image differed.
        let img = pattern(300, 600);
        let bytes = |name: &str| {
            let p = tmp(name);
            img.write(&p).unwrap();
            std::fs::read(&p).unwrap()
        };
        let first = bytes("det-0.exr");
        for i in 1..6 {
            assert!(bytes(&format!("det-{i}.exr")) == first, "write {i} differs");
        }
    }

    #[test]
    fn exr_round_trip_is_bit_exact() {
        let img = pattern(7, 5);
        let p = tmp("rt.exr");
        img.write(&p).unwrap();
        let back = Image::read(&p).unwrap();
        assert_eq!(back, img);
    }

    #[test]
    fn pfm_round_trip_is_bit_exact() {
        let img = pattern(6, 4);
        let p = tmp("rt.pfm");
        img.write(&p).unwrap();
        let back = Image::read(&p).unwrap();
        assert_eq!(back, img);
    }

    #[test]
    fn pfm_header_and_row_order() {
        let mut img = Image::new(2, 3);
        img.set(0, 0, [1.0, 2.0, 3.0]); // top-left
        img.set(1, 2, [4.0, 5.0, 6.0]); // bottom-right
        let bytes = img.encode_pfm();
        let header = b"PF\n2 3\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let data = &bytes[header.len()..];
        assert_eq!(data.len(), 2 * 3 * 12);
        let f = |i: usize| {
            f32::from_le_bytes([
                data[4 * i],
                data[4 * i + 1],
                data[4 * i + 2],
                data[4 * i + 3],
            ])
        };
        // First stored row is the bottom row: its second pixel is (4, 5, 6).
        assert_eq!([f(3), f(4), f(5)], [4.0, 5.0, 6.0]);
        // Last stored row is the top row: its first pixel is (1, 2, 3).
        assert_eq!([f(12), f(13), f(14)], [1.0, 2.0, 3.0]);
    }

    #[test]
    fn pfm_reads_big_endian_greyscale() {
        let mut bytes = b"Pf\n2 2\n1.0\n".to_vec();
        for v in [1.0f32, 2.0, 3.0, 4.0] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        let p = tmp("grey_be.pfm");
        std::fs::write(&p, &bytes).unwrap();
        let img = Image::read(&p).unwrap();
        assert_eq!((img.width, img.height), (2, 2));
        // Bottom row stored first.
        assert_eq!(img.get(0, 1), [1.0; 3]);
        assert_eq!(img.get(1, 1), [2.0; 3]);
        assert_eq!(img.get(0, 0), [3.0; 3]);
        assert_eq!(img.get(1, 0), [4.0; 3]);
    }

    #[test]
    fn png_round_trip_within_quantisation() {
        let mut img = Image::new(16, 3);
        for x in 0..16 {
            let v = x as f32 / 15.0;
            img.set(x, 0, [v, v * v, 1.0 - v]);
            img.set(x, 1, [v * 0.01, 0.5, 0.25]);
            img.set(x, 2, [2.0, -1.0, f32::NAN]); // clamped to 1, 0, 0
        }
        let p = tmp("rt.png");
        img.write(&p).unwrap();
        let back = Image::read(&p).unwrap();
        for y in 0..2 {
            for x in 0..16 {
                for c in 0..3 {
                    let (a, b) = (img.get(x, y)[c], back.get(x, y)[c]);
                    // Half an 8-bit step in sRGB space, mapped back to linear.
                    let e = linear_to_srgb(a);
                    let tol = srgb_to_linear((e + 0.5 / 255.0).min(1.0))
                        - srgb_to_linear((e - 0.5 / 255.0).max(0.0));
                    assert!((a - b).abs() <= tol + 1e-6, "({x},{y},{c}): {a} vs {b}");
                }
            }
        }
        for x in 0..16 {
            assert_eq!(back.get(x, 2), [1.0, 0.0, 0.0]);
        }
    }

    #[test]
    fn png_exposure_scales_before_encoding() {
        let mut img = Image::new(1, 1);
        img.set(0, 0, [0.25, 0.125, 1.0]);
        let p = tmp("exposure.png");
        img.write_png(&p, 1.0).unwrap();
        let back = Image::read(&p).unwrap().get(0, 0);
        assert!((back[0] - 0.5).abs() < 3e-3, "{back:?}");
        assert!((back[1] - 0.25).abs() < 3e-3, "{back:?}");
        assert_eq!(back[2], 1.0);
    }

    #[test]
    fn png_reads_16_bit_grey() {
        let p = tmp("grey16.png");
        let raw: Vec<u8> = [0u16, 65535, 32768]
            .iter()
            .flat_map(|v| v.to_ne_bytes())
            .collect();
        image::save_buffer_with_format(
            &p,
            &raw,
            3,
            1,
            image::ExtendedColorType::L16,
            image::ImageFormat::Png,
        )
        .unwrap();
        let img = Image::read(&p).unwrap();
        assert_eq!(img.get(0, 0), [0.0; 3]);
        assert_eq!(img.get(1, 0), [1.0; 3]);
        let mid = srgb_to_linear(32768.0 / 65535.0);
        assert!((img.get(2, 0)[0] - mid).abs() < 1e-5);
        assert!((mid - 0.2140).abs() < 1e-3); // sRGB 0.5 ≈ 0.214 linear
    }

    #[test]
    fn garbage_and_truncated_files_are_errors_naming_the_path() {
        let garbage: Vec<u8> = (0..300u32)
            .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
            .collect();
        for name in ["garbage.exr", "garbage.pfm", "garbage.png"] {
            let p = tmp(name);
            std::fs::write(&p, &garbage).unwrap();
            let e = Image::read(&p).unwrap_err();
            assert!(e.to_string().contains(name), "{e}");
        }
        // Truncated versions of valid files.
        let img = pattern(9, 9);
        for ext in ["exr", "pfm", "png"] {
            let p = tmp(&format!("full.{ext}"));
            img.write(&p).unwrap();
            let bytes = std::fs::read(&p).unwrap();
            let q = tmp(&format!("truncated.{ext}"));
            std::fs::write(&q, &bytes[..bytes.len() / 2]).unwrap();
            let e = Image::read(&q).unwrap_err();
            assert!(e.to_string().contains("truncated."), "{e}");
        }
        // Absurd PFM sizes do not allocate or panic.
        let p = tmp("huge.pfm");
        std::fs::write(&p, b"PF\n4000000000 4000000000\n-1.0\n\0\0\0\0").unwrap();
        assert!(Image::read(&p).is_err());
        // Missing file and unknown extension.
        assert!(matches!(
            Image::read(&tmp("missing.pfm")),
            Err(ImageError::Io { .. })
        ));
        assert!(matches!(
            img.write(&tmp("x.bmp")),
            Err(ImageError::UnknownExtension { .. })
        ));
    }
}

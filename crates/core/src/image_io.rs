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
        let _ = path;
        todo!("image_io::read")
    }
    /// Writes by extension: `.exr`, `.pfm` (linear float) or `.png` (sRGB, exposure 0).
    pub fn write(&self, path: &Path) -> Result<(), ImageError> {
        let _ = path;
        todo!("image_io::write")
    }
    /// Writes 32-bit float RGB OpenEXR.
    pub fn write_exr(&self, path: &Path) -> Result<(), ImageError> {
        let _ = path;
        todo!("image_io::write_exr")
    }
    /// Writes little-endian PFM (bottom-to-top rows as the format requires).
    pub fn write_pfm(&self, path: &Path) -> Result<(), ImageError> {
        let _ = path;
        todo!("image_io::write_pfm")
    }
    /// Writes an 8-bit sRGB PNG after scaling by 2^`exposure` and clamping to [0, 1].
    pub fn write_png(&self, path: &Path, exposure: f32) -> Result<(), ImageError> {
        let _ = (path, exposure);
        todo!("image_io::write_png")
    }
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

//! Textures for albedo-like parameters: constants, images (bilinear, sRGB-decoded PNG or linear
//! EXR/PFM) and a procedural checkerboard.

use caustica_core::{Spectrum, Vec2};
use std::sync::Arc;

/// An image texture in linear RGB.
#[derive(Debug)]
pub struct ImageTexture {
    pub image: caustica_core::image_io::Image,
}

/// A spectrum-valued texture.
#[derive(Clone, Debug)]
pub enum Texture {
    Constant(Spectrum),
    Image(Arc<ImageTexture>),
    /// Alternates `a` and `b` on a grid of `scale × scale` squares per unit of uv.
    Checkerboard {
        a: Spectrum,
        b: Spectrum,
        scale: f32,
    },
}

impl Texture {
    /// Value at texture coordinates `uv` (wrapping; v = 0 is the bottom row of images).
    pub fn eval(&self, uv: Vec2) -> Spectrum {
        match self {
            Texture::Constant(c) => *c,
            Texture::Image(img) => img.eval(uv),
            Texture::Checkerboard { a, b, scale } => {
                let i = (uv.x * scale).floor() as i64 + (uv.y * scale).floor() as i64;
                if i.rem_euclid(2) == 0 { *a } else { *b }
            }
        }
    }
    /// Largest channel value anywhere (used to validate albedos ≤ 1).
    pub fn max_value(&self) -> f32 {
        match self {
            Texture::Constant(c) => c.max_component(),
            Texture::Image(img) => img
                .image
                .data
                .iter()
                .fold(0.0f32, |m, p| m.max(p[0]).max(p[1]).max(p[2])),
            Texture::Checkerboard { a, b, .. } => a.max_component().max(b.max_component()),
        }
    }
}

impl ImageTexture {
    /// Bilinear lookup with wrapping.
    pub fn eval(&self, uv: Vec2) -> Spectrum {
        let _ = uv;
        todo!("ImageTexture::eval")
    }
}

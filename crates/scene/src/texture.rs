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
    /// Wraps an image (already linear RGB).
    pub fn new(image: caustica_core::image_io::Image) -> Self {
        Self { image }
    }

    /// Loads an image file (`.png` is sRGB-decoded; `.exr`/`.pfm` are linear).
    pub fn load(path: &std::path::Path) -> Result<Self, caustica_core::image_io::ImageError> {
        caustica_core::image_io::Image::read(path).map(Self::new)
    }

    /// Bilinear lookup with wrapping. `uv` ∈ [0, 1)² covers the image once; v = 0 is the bottom
    /// row, texel centres sit at half-integer positions.
    pub fn eval(&self, uv: Vec2) -> Spectrum {
        let img = &self.image;
        let (w, h) = (img.width, img.height);
        if w == 0 || h == 0 || img.data.len() < w * h {
            return Spectrum::ZERO;
        }
        let u = if uv.x.is_finite() { uv.x } else { 0.0 };
        let v = if uv.y.is_finite() { uv.y } else { 0.0 };
        // Continuous texel coordinates with row 0 at the top.
        let x = u.rem_euclid(1.0) * w as f32 - 0.5;
        let y = (1.0 - v.rem_euclid(1.0)) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: f32, n: usize| (i as i64).rem_euclid(n as i64) as usize;
        let (xa, xb) = (wrap(x0, w), wrap(x0 + 1.0, w));
        let (ya, yb) = (wrap(y0, h), wrap(y0 + 1.0, h));
        let px = |x: usize, y: usize| {
            let p = img.data[y * w + x];
            Spectrum::new(p[0], p[1], p[2])
        };
        (px(xa, ya) * (1.0 - fx) + px(xb, ya) * fx) * (1.0 - fy)
            + (px(xa, yb) * (1.0 - fx) + px(xb, yb) * fx) * fy
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::image_io::Image;

    /// 2×2 image: top row (y = 0) red 1 / green 2, bottom row blue 3 / grey 4.
    fn tex() -> ImageTexture {
        let mut img = Image::new(2, 2);
        img.set(0, 0, [1.0, 0.0, 0.0]);
        img.set(1, 0, [0.0, 2.0, 0.0]);
        img.set(0, 1, [0.0, 0.0, 3.0]);
        img.set(1, 1, [4.0, 4.0, 4.0]);
        ImageTexture::new(img)
    }

    fn close(a: Spectrum, b: [f32; 3]) -> bool {
        (0..3).all(|i| (a.c[i] - b[i]).abs() < 1e-5)
    }

    #[test]
    fn texel_centres_return_texels_with_v0_at_the_bottom() {
        let t = tex();
        assert!(close(t.eval(Vec2::new(0.25, 0.25)), [0.0, 0.0, 3.0])); // bottom-left
        assert!(close(t.eval(Vec2::new(0.75, 0.25)), [4.0, 4.0, 4.0])); // bottom-right
        assert!(close(t.eval(Vec2::new(0.25, 0.75)), [1.0, 0.0, 0.0])); // top-left
        assert!(close(t.eval(Vec2::new(0.75, 0.75)), [0.0, 2.0, 0.0])); // top-right
    }

    #[test]
    fn bilinear_between_centres_and_wrapping() {
        let t = tex();
        // Midway between the two bottom texels.
        assert!(close(t.eval(Vec2::new(0.5, 0.25)), [2.0, 2.0, 3.5]));
        // The centre of the image averages all four.
        assert!(close(t.eval(Vec2::new(0.5, 0.5)), [1.25, 1.5, 1.75]));
        // u = 0 lies halfway between the right and left columns (wrapping).
        assert!(close(t.eval(Vec2::new(0.0, 0.25)), [2.0, 2.0, 3.5]));
        // Periodicity, including negative coordinates.
        for (u, v) in [(0.3, 0.6), (0.9, 0.1), (0.05, 0.95)] {
            let a = t.eval(Vec2::new(u, v));
            let b = t.eval(Vec2::new(u + 3.0, v - 2.0));
            assert!(close(a, b.c), "{u},{v}");
        }
        assert!(t.eval(Vec2::new(f32::NAN, 0.5)).is_finite());
    }
}

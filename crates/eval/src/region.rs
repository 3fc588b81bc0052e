//! The set of pixels a comparison looks at: a crop rectangle and an optional mask.

use crate::EvalError;
use caustica_core::image_io::Image;

/// Pixels of a `width`×`height` image selected by a crop rectangle and a mask.
#[derive(Clone, Debug)]
pub struct Region {
    /// Crop rectangle: left, top, width, height in pixels.
    pub x0: usize,
    pub y0: usize,
    pub w: usize,
    pub h: usize,
    /// Full-image selection (row-major, `width`×`height`), crop already applied.
    selected: Vec<bool>,
    width: usize,
}

impl Region {
    /// Every pixel of a `width`×`height` image.
    pub fn full(width: usize, height: usize) -> Self {
        Self {
            x0: 0,
            y0: 0,
            w: width,
            h: height,
            selected: vec![true; width * height],
            width,
        }
    }

    /// The crop rectangle (`x`, `y`, `w`, `h`) of a `width`×`height` image.
    pub fn crop(
        width: usize,
        height: usize,
        (x, y, w, h): (usize, usize, usize, usize),
    ) -> Result<Self, EvalError> {
        let fits = w > 0 && h > 0 && x.checked_add(w).is_some_and(|e| e <= width);
        let fits = fits && y.checked_add(h).is_some_and(|e| e <= height);
        if !fits {
            return Err(EvalError::BadCrop {
                x,
                y,
                w,
                h,
                width,
                height,
            });
        }
        let mut selected = vec![false; width * height];
        for row in y..y + h {
            selected[row * width + x..row * width + x + w].fill(true);
        }
        Ok(Self {
            x0: x,
            y0: y,
            w,
            h,
            selected,
            width,
        })
    }

    /// Keeps only pixels where `mask` is non-zero in any channel.
    pub fn with_mask(mut self, mask: &Image) -> Result<Self, EvalError> {
        let height = self.selected.len() / self.width.max(1);
        if mask.width != self.width || mask.height != height {
            return Err(EvalError::MaskSize {
                mw: mask.width,
                mh: mask.height,
                width: self.width,
                height,
            });
        }
        for (s, m) in self.selected.iter_mut().zip(&mask.data) {
            *s &= m.iter().any(|&c| c > 0.0);
        }
        Ok(self)
    }

    /// Drops pixels that are exactly black in both `image` and `reference` (Mitsuba's `ptracer`
    /// and caustica's light tracer leave pixels that see glass or mirrors directly black).
    /// Requiring black in *both* keeps the selection unbiased: a pixel that is black in one image
    /// only because no sample reached it stays in, and dropping pixels that are zero in both
    /// leaves both sums, and so the ratio of the means, unchanged.
    pub fn without_black(mut self, image: &Image, reference: &Image) -> Self {
        let black = |p: &[f32; 3]| p.iter().all(|&c| c == 0.0);
        for ((s, a), b) in self
            .selected
            .iter_mut()
            .zip(&image.data)
            .zip(&reference.data)
        {
            *s &= !(black(a) && black(b));
        }
        self
    }

    /// Whether the pixel (`x`, `y`) of the full image is selected.
    #[inline]
    pub fn contains(&self, x: usize, y: usize) -> bool {
        self.selected[y * self.width + x]
    }

    /// Row-major indices of the selected pixels.
    pub fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.selected
            .iter()
            .enumerate()
            .filter_map(|(i, &s)| s.then_some(i))
    }

    /// Number of selected pixels.
    pub fn count(&self) -> usize {
        self.selected.iter().filter(|&&s| s).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crop_mask_and_black() {
        assert!(Region::crop(4, 4, (3, 0, 2, 1)).is_err());
        assert!(Region::crop(4, 4, (0, 0, 0, 1)).is_err());
        assert!(Region::crop(4, 4, (usize::MAX, 0, 2, 1)).is_err());
        let r = Region::crop(4, 4, (1, 1, 2, 3)).unwrap();
        assert_eq!(r.count(), 6);
        assert!(r.contains(1, 1) && r.contains(2, 3) && !r.contains(0, 1) && !r.contains(3, 1));
        let mut mask = Image::new(4, 4);
        mask.set(1, 1, [0.0, 0.5, 0.0]);
        mask.set(2, 2, [1.0; 3]);
        mask.set(0, 0, [1.0; 3]); // outside the crop
        let m = r.clone().with_mask(&mask).unwrap();
        assert_eq!(m.indices().collect::<Vec<_>>(), vec![5, 10]);
        assert!(r.with_mask(&Image::new(3, 4)).is_err());
        let (mut image, mut reference) = (Image::new(4, 4), Image::new(4, 4));
        reference.set(3, 3, [0.0, 0.0, 1e-9]);
        image.set(0, 3, [0.5, 0.0, 0.0]);
        assert_eq!(
            Region::full(4, 4).without_black(&image, &reference).count(),
            2
        );
    }
}

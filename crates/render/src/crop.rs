//! The crop window: the rectangle of the camera's film a render computes (pbrt's
//! `--pixelbounds`, Mitsuba's film `crop_offset`/`crop_width`/`crop_height`).
//!
//! The camera keeps its full film: rays, the sampler's pixel streams and the light tracer's
//! raster positions are all in full-film pixel coordinates, and the [`crate::film::Film`] holds
//! only the window's pixels with the window's origin. So every pixel of a cropped render is the
//! pixel of the uncropped render with the same seed; light-side work (light paths, photon maps,
//! splatted photons) does not depend on the window, and splats outside it are dropped.

use crate::error::OptionError;
use std::fmt;

/// A `width` × `height` rectangle of pixels whose top-left pixel is (`x`, `y`) of the full film.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CropWindow {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl CropWindow {
    /// The whole `width` × `height` film.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x: 0,
            y: 0,
            width,
            height,
        }
    }

    /// Parses `X,Y,W,H` and checks the window against a `film_width` × `film_height` film.
    pub fn parse(s: &str, film_width: u32, film_height: u32) -> Result<Self, OptionError> {
        let refuse = |why: String| OptionError::Crop {
            got: format!("'{s}'"),
            film_width,
            film_height,
            why,
        };
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if parts.len() != 4 {
            return Err(refuse(format!("{} comma-separated values", parts.len())));
        }
        let mut v = [0u32; 4];
        for (out, p) in v.iter_mut().zip(&parts) {
            *out = p
                .parse()
                .map_err(|_| refuse(format!("'{p}' is not a non-negative integer")))?;
        }
        Self {
            x: v[0],
            y: v[1],
            width: v[2],
            height: v[3],
        }
        .check(film_width, film_height)
    }

    /// This window, if it is not empty and lies inside a `film_width` × `film_height` film.
    pub fn check(self, film_width: u32, film_height: u32) -> Result<Self, OptionError> {
        let why = if self.width == 0 || self.height == 0 {
            Some(format!("an empty {}x{} window", self.width, self.height))
        } else if u64::from(self.x) + u64::from(self.width) > u64::from(film_width)
            || u64::from(self.y) + u64::from(self.height) > u64::from(film_height)
        {
            Some(format!(
                "pixels {}..{} x {}..{} reach outside the film",
                self.x,
                u64::from(self.x) + u64::from(self.width),
                self.y,
                u64::from(self.y) + u64::from(self.height)
            ))
        } else {
            None
        };
        match why {
            None => Ok(self),
            Some(why) => Err(OptionError::Crop {
                got: format!("'{self}'"),
                film_width,
                film_height,
                why,
            }),
        }
    }

    /// Number of pixels.
    pub fn pixels(self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// True when full-film pixel (`x`, `y`) is inside.
    #[inline]
    pub fn contains(self, x: usize, y: usize) -> bool {
        x >= self.x as usize
            && y >= self.y as usize
            && x - (self.x as usize) < self.width as usize
            && y - (self.y as usize) < self.height as usize
    }
}

impl fmt::Display for CropWindow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x, self.y, self.width, self.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_windows_inside_the_film_and_refuses_the_rest() {
        assert_eq!(
            CropWindow::parse("2, 3,4,5", 6, 8),
            Ok(CropWindow {
                x: 2,
                y: 3,
                width: 4,
                height: 5
            })
        );
        assert_eq!(
            CropWindow::parse("0,0,6,8", 6, 8),
            Ok(CropWindow::full(6, 8))
        );
        for bad in [
            "",
            "1,2,3",
            "1,2,3,4,5",
            "-1,0,2,2",
            "0,0,0,2",
            "0,0,2,0",
            "a,0,1,1",
            "1.5,0,1,1",
            "3,0,4,1",
            "0,4,1,5",
            "6,0,1,1",
            "4294967295,0,2,1",
        ] {
            let e = CropWindow::parse(bad, 6, 8).expect_err(bad).to_string();
            assert!(e.contains("--crop") && e.contains("6x8"), "{bad}: {e}");
        }
    }

    #[test]
    fn contains_exactly_its_pixels() {
        let w = CropWindow {
            x: 2,
            y: 1,
            width: 3,
            height: 2,
        };
        let inside: Vec<(usize, usize)> = (0..8)
            .flat_map(|y| (0..8).map(move |x| (x, y)))
            .filter(|&(x, y)| w.contains(x, y))
            .collect();
        assert_eq!(inside.len() as u64, w.pixels());
        assert!(
            inside
                .iter()
                .all(|&(x, y)| (2..5).contains(&x) && (1..3).contains(&y))
        );
    }
}

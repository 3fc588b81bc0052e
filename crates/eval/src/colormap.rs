//! False-colour error images.

use caustica_core::image_io::{Image, srgb_to_linear};

/// Diverging map for signed values t in [−1, 1]: blue (image darker than the reference) through
/// white (equal) to red (brighter), returned as linear RGB so that the sRGB PNG shows the map.
pub fn diverging(t: f64) -> [f32; 3] {
    let t = if t.is_finite() {
        t.clamp(-1.0, 1.0)
    } else {
        0.0
    } as f32;
    let (cold, hot) = ([0.23, 0.30, 0.75], [0.71, 0.02, 0.15]);
    let end = if t < 0.0 { cold } else { hot };
    let a = t.abs();
    // Interpolate the display (sRGB-encoded) colours, then linearise for the film.
    [0, 1, 2].map(|c| srgb_to_linear((1.0 - a) + a * end[c]))
}

/// Image of the signed luminance difference `d` (row-major), `scale` mapping to full colour;
/// pixels outside `keep` are mid grey.
pub fn signed_error_image(
    d: &[f64],
    width: usize,
    height: usize,
    scale: f64,
    keep: impl Fn(usize) -> bool,
) -> Image {
    let mut img = Image::new(width, height);
    for (i, p) in img.data.iter_mut().enumerate() {
        *p = if keep(i) {
            diverging(d[i] / scale)
        } else {
            [srgb_to_linear(0.5); 3]
        };
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_and_centre() {
        assert_eq!(diverging(0.0), [1.0; 3]);
        assert_eq!(diverging(f64::NAN), [1.0; 3]);
        let red = diverging(5.0);
        assert!(red[0] > red[1] && red[0] > red[2]);
        let blue = diverging(-1.0);
        assert!(blue[2] > blue[0] && blue[2] > blue[1]);
    }
}

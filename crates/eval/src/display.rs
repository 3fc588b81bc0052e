//! The display transform under which MISE and SSIM are measured.
//!
//! A pixel's linear RGB radiance (W/m²/sr) becomes one display value in [0, 1]:
//! luminance Y (Rec. 709 weights), scaled by 2^`exposure`, clamped to [0, 1], then encoded by the
//! sRGB transfer function: exactly the grey value a PNG written with the same exposure would show.
//! The dynamic range L of SSIM (Wang et al. 2004, eq. 7) is therefore 1.

use caustica_core::Spectrum;
use caustica_core::image_io::linear_to_srgb;

/// Display value in [0, 1] of a linear RGB pixel (see the module documentation).
#[inline]
pub fn display_value(rgb: [f32; 3], exposure: f32) -> f64 {
    let y = Spectrum::new(rgb[0], rgb[1], rgb[2]).luminance() * exposure.exp2();
    f64::from(linear_to_srgb(y.clamp(0.0, 1.0)))
}

/// Linear luminance Y (W/m²/sr) of a pixel; non-finite values count as 0.
#[inline]
pub fn luminance(rgb: [f32; 3]) -> f64 {
    let y = f64::from(Spectrum::new(rgb[0], rgb[1], rgb[2]).luminance());
    if y.is_finite() { y } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_range_and_endpoints() {
        assert_eq!(display_value([0.0; 3], 0.0), 0.0);
        assert!((display_value([1.0; 3], 0.0) - 1.0).abs() < 1e-6);
        assert!((display_value([10.0; 3], 0.0) - 1.0).abs() < 1e-6);
        // 18 % grey encodes to ~0.4613 in sRGB.
        assert!((display_value([0.18; 3], 0.0) - 0.4613).abs() < 1e-3);
        // One stop of exposure doubles the linear value.
        assert!((display_value([0.09; 3], 1.0) - display_value([0.18; 3], 0.0)).abs() < 1e-6);
    }
}

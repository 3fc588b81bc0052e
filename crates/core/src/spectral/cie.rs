//! CIE colorimetry: the 1931 2° colour matching functions, illuminant D65 and the XYZ ↔ linear
//! sRGB matrices.
//!
//! The tables are the CIE's standard data (CIE 015:2018; ISO 11664-1 and -2): x̄, ȳ, z̄ at 1 nm
//! and the D65 relative spectral power distribution at 5 nm, both from 360 to 830 nm, written
//! into `cie_data.rs` by `tools/spectral/gen_cie_tables.py` (which says where it reads them).
//! Between table entries the functions are interpolated linearly; outside [360, 830] nm they
//! are zero.
//!
//! Normalisations (λ always in nm):
//! * [`CIE_Y_INTEGRAL`] = ∫ ȳ(λ) dλ ≈ 106.857 nm. Colours of spectra are
//!   `XYZ = ∫ S(λ) (x̄, ȳ, z̄)(λ) dλ / CIE_Y_INTEGRAL`, so the constant spectrum 1 has Y = 1
//!   (the convention of pbrt-v4 and Mitsuba 3).
//! * [`d65`] is the table (100 at 560 nm); [`d65_n`] is it scaled by [`D65_NORMALISATION`] so
//!   that its Y is 1. Its XYZ is [`D65_WHITE_XYZ`] ≈ (0.9505, 1, 1.0887).
//! * The matrices use the Rec. 709 primaries and D65_n's own XYZ as white (as pbrt-v4's
//!   `RGBColorSpace` derives its white from the illuminant spectrum), so D65_n is linear sRGB
//!   (1, 1, 1) up to f32 rounding; they differ from IEC 61966-2-1's printed matrix by up to 4e-4.

pub use super::cie_data::{
    CIE_Y_INTEGRAL, D65_NORMALISATION, D65_WHITE_XYZ, LAMBDA_MAX, LAMBDA_MIN, LINEAR_SRGB_TO_XYZ,
    XYZ_TO_LINEAR_SRGB,
};
use super::cie_data::{CMF_1NM, D65_5NM};

/// CIE 1931 2° colour matching functions [x̄, ȳ, z̄] at `lambda_nm` (dimensionless, ȳ(555) = 1),
/// linearly interpolated in the 1 nm table, zero outside [360, 830] nm (and for NaN).
#[inline]
pub fn cie_xyz(lambda_nm: f32) -> [f32; 3] {
    // `contains` is false for NaN too.
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda_nm) {
        return [0.0; 3];
    }
    let t = lambda_nm - LAMBDA_MIN;
    let i = (t as usize).min(CMF_1NM.len() - 2);
    let f = t - i as f32;
    let (a, b) = (CMF_1NM[i], CMF_1NM[i + 1]);
    [
        a[0] + f * (b[0] - a[0]),
        a[1] + f * (b[1] - a[1]),
        a[2] + f * (b[2] - a[2]),
    ]
}

/// CIE standard illuminant D65, relative spectral power (100 at 560 nm), linearly interpolated
/// in the 5 nm table, zero outside [360, 830] nm.
#[inline]
pub fn d65(lambda_nm: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda_nm) {
        return 0.0;
    }
    let t = (lambda_nm - LAMBDA_MIN) * 0.2;
    let i = (t as usize).min(D65_5NM.len() - 2);
    let f = t - i as f32;
    D65_5NM[i] + f * (D65_5NM[i + 1] - D65_5NM[i])
}

/// D65 normalised to luminance Y = 1 (`d65 · D65_NORMALISATION`): the spectrum of linear sRGB
/// white (1, 1, 1), and so the spectral form of an RGB emitter of radiance (1, 1, 1).
#[inline]
pub fn d65_n(lambda_nm: f32) -> f32 {
    d65(lambda_nm) * D65_NORMALISATION
}

#[inline]
fn mat_vec(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// CIE XYZ → linear sRGB (Rec. 709 primaries, D65 white; Y = 1 white ↦ (1, 1, 1)).
#[inline]
pub fn xyz_to_linear_srgb(xyz: [f32; 3]) -> [f32; 3] {
    mat_vec(&XYZ_TO_LINEAR_SRGB, xyz)
}

/// Linear sRGB → CIE XYZ; the inverse of [`xyz_to_linear_srgb`].
#[inline]
pub fn linear_srgb_to_xyz(rgb: [f32; 3]) -> [f32; 3] {
    mat_vec(&LINEAR_SRGB_TO_XYZ, rgb)
}

/// `XYZ = ∫ s(λ) (x̄, ȳ, z̄)(λ) dλ / CIE_Y_INTEGRAL` by the midpoint rule at 1 nm over [360, 830]:
/// a deterministic reference for tests and table building (not used while rendering).
pub fn spectrum_to_xyz(s: impl Fn(f32) -> f32) -> [f32; 3] {
    let mut acc = [0.0f64; 3];
    for i in 0..CMF_1NM.len() - 1 {
        let l = LAMBDA_MIN + i as f32 + 0.5;
        let v = s(l) as f64;
        let c = cie_xyz(l);
        for k in 0..3 {
            acc[k] += v * c[k] as f64;
        }
    }
    acc.map(|a| (a / CIE_Y_INTEGRAL as f64) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_integral_matches_the_table() {
        // Trapezoid rule over the table = the integral of the interpolant.
        let s: f64 = CMF_1NM
            .windows(2)
            .map(|w| 0.5 * (w[0][1] + w[1][1]) as f64)
            .sum();
        assert!((s / CIE_Y_INTEGRAL as f64 - 1.0).abs() < 1e-3, "{s}");
        // And the published value (pbrt-v4's CIE_Y_integral = 106.856895).
        assert!((CIE_Y_INTEGRAL / 106.856_895 - 1.0).abs() < 1e-3);
        // The midpoint rule over fine sub-steps agrees too (the interpolation is right).
        let mut m = 0.0f64;
        let n = 4 * 470;
        for i in 0..n {
            m += cie_xyz(360.0 + (i as f32 + 0.5) * 0.25)[1] as f64 * 0.25;
        }
        assert!((m / CIE_Y_INTEGRAL as f64 - 1.0).abs() < 1e-3, "{m}");
    }

    #[test]
    fn known_table_values() {
        assert_eq!(cie_xyz(555.0)[1], 1.0);
        assert!((cie_xyz(555.0)[0] - 0.51205).abs() < 1e-6);
        assert!(
            (cie_xyz(600.0)[0] - 1.0622).abs() < 1e-4,
            "{:?}",
            cie_xyz(600.0)
        );
        assert!(
            (cie_xyz(445.0)[2] - 1.7826).abs() < 1e-3,
            "{:?}",
            cie_xyz(445.0)
        );
        // Interpolation halfway between 555 (ȳ = 1) and 556 (ȳ = 0.999).
        assert!((cie_xyz(555.5)[1] - 0.9995).abs() < 1e-6);
        assert_eq!(cie_xyz(359.9), [0.0; 3]);
        assert_eq!(cie_xyz(830.1), [0.0; 3]);
        assert_eq!(cie_xyz(f32::NAN), [0.0; 3]);
        assert!(cie_xyz(830.0)[0] > 0.0);
        assert_eq!(d65(560.0), 100.0);
        assert!((d65(557.5) - 0.5 * (102.023 + 100.0)).abs() < 1e-3);
        assert_eq!(d65(300.0), 0.0);
        assert_eq!(d65(831.0), 0.0);
    }

    #[test]
    fn d65_n_is_linear_srgb_white() {
        let xyz = spectrum_to_xyz(d65_n);
        assert!((xyz[1] - 1.0).abs() < 1e-3, "{xyz:?}");
        for k in 0..3 {
            assert!((xyz[k] / D65_WHITE_XYZ[k] - 1.0).abs() < 1e-3, "{xyz:?}");
        }
        // Chromaticity of D65: x, y = 0.3127, 0.3290 (CIE 015).
        let s: f32 = xyz.iter().sum();
        assert!((xyz[0] / s - 0.3127).abs() < 2e-4 && (xyz[1] / s - 0.3290).abs() < 2e-4);
        let rgb = xyz_to_linear_srgb(xyz);
        for c in rgb {
            assert!((c - 1.0).abs() < 5e-3, "{rgb:?}");
        }
        for c in xyz_to_linear_srgb(D65_WHITE_XYZ) {
            assert!((c - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn matrices_are_inverses_and_match_the_standard() {
        for (i, v) in [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.2, 0.7, 0.4],
        ]
        .into_iter()
        .enumerate()
        {
            let back = linear_srgb_to_xyz(xyz_to_linear_srgb(v));
            let fwd = xyz_to_linear_srgb(linear_srgb_to_xyz(v));
            for k in 0..3 {
                assert!((back[k] - v[k]).abs() < 1e-5, "{i}: {back:?}");
                assert!((fwd[k] - v[k]).abs() < 1e-5, "{i}: {fwd:?}");
            }
        }
        // IEC 61966-2-1's matrix to four decimals (ours takes the white from the D65 table:
        // x, y = 0.31272, 0.32903 instead of 0.3127, 0.3290, which moves entries by up to 4e-4).
        let iec = [
            [0.4124, 0.3576, 0.1805],
            [0.2126, 0.7152, 0.0722],
            [0.0193, 0.1192, 0.9505],
        ];
        for r in 0..3 {
            for c in 0..3 {
                assert!(
                    (LINEAR_SRGB_TO_XYZ[r][c] - iec[r][c]).abs() < 5e-4,
                    "{r} {c}"
                );
            }
        }
        // The Y row is the luminance Spectrum uses.
        let l = crate::Spectrum::new(0.3, 0.5, 0.9).luminance();
        assert!((linear_srgb_to_xyz([0.3, 0.5, 0.9])[1] - l).abs() < 2e-4);
    }
}

//! Foundations of caustica's spectral mode (issue 22): colorimetry, wavelength sampling,
//! blackbodies and RGB → spectrum upsampling.
//!
//! * [`cie`] — CIE 1931 2° colour matching functions, illuminant D65, XYZ ↔ linear sRGB.
//! * [`wavelengths`] — [`SampledWavelengths`]: hero wavelength sampling (Wilkie et al. 2014)
//!   with three wavelengths, one per lane of [`crate::Spectrum`], and the film's conversion of
//!   a path's spectral value to XYZ and linear sRGB.
//! * [`blackbody`] — Planck's law and its peak-normalised form.
//! * [`upsample`] — Jakob and Hanika 2019 sigmoid spectra from RGB: [`RgbReflectance`],
//!   [`RgbUnbounded`], [`RgbIlluminant`].
//!
//! # Conventions
//!
//! * **Wavelengths** are in nm, in vacuum; every table covers [360, 830] nm and is zero outside.
//! * In spectral mode a path carries a [`SampledWavelengths`] and every [`crate::Spectrum`] on
//!   it holds, in lane j, the value of the quantity at `lambda[j]` (instead of the R, G, B of
//!   RGB mode). The arithmetic is unchanged.
//! * **Colour of a spectrum**: XYZ = ∫ S(λ) (x̄, ȳ, z̄)(λ) dλ / ∫ ȳ(λ) dλ, then linear sRGB by
//!   [`cie::xyz_to_linear_srgb`] (Rec. 709 primaries, D65 white). The film estimates this
//!   integral per sample with [`SampledWavelengths::to_linear_srgb`] and accumulates RGB.
//! * **Reflectances, transmittances, albedos** are dimensionless in both modes; an RGB
//!   reflectance becomes [`RgbReflectance`], whose colour under D65_n is that RGB.
//! * **Radiance**: RGB mode's radiance is linear sRGB in W·m⁻²·sr⁻¹. A spectral radiance
//!   L(λ) in spectral mode is scaled so that its RGB radiance is its colour by the formula
//!   above (Y = ∫ L ȳ dλ / ∫ ȳ dλ): if L_nm(λ) is a physical spectral radiance in
//!   W·m⁻²·sr⁻¹·nm⁻¹ whose ȳ-weighted integral ∫ L_nm ȳ dλ is meant to equal the RGB radiance's
//!   Y (in W·m⁻²·sr⁻¹), then L = [`cie::CIE_Y_INTEGRAL`] · L_nm, CIE_Y_INTEGRAL ≈ 106.857 nm.
//!   An RGB emitter of radiance (r, g, b) becomes [`RgbIlluminant`]`::new([r, g, b])`, whose
//!   colour is (r, g, b); in particular (1, 1, 1) ≡ D65_n ([`cie::d65_n`], D65 scaled to
//!   Y = 1), so a scene of RGB lights and RGB materials renders the same image in both modes up
//!   to noise and the upsampling's error (mean 0.3 %, worst within 1 % or 0.005 over the gamut's
//!   interior; and not exactly even then: a product of upsampled spectra is not the upsampling
//!   of the product of the RGBs).
//! * **Blackbody** lights use [`blackbody::blackbody_normalized`] (peak 1) times a scale in the
//!   units above; [`blackbody::blackbody`] is Planck's law in absolute W·m⁻²·sr⁻¹·nm⁻¹.
//! * **Dispersion**: an event whose direction depends on λ calls
//!   [`SampledWavelengths::terminate_secondary`]; the path then carries only the hero.

pub mod blackbody;
pub mod cie;
mod cie_data;
pub mod upsample;
pub mod wavelengths;

pub use blackbody::{BlackbodyNormalized, blackbody, blackbody_normalized};
pub use cie::{
    CIE_Y_INTEGRAL, LINEAR_SRGB_TO_XYZ, XYZ_TO_LINEAR_SRGB, cie_xyz, d65, d65_n,
    linear_srgb_to_xyz, xyz_to_linear_srgb,
};
pub use upsample::{
    RgbIlluminant, RgbReflectance, RgbToSpectrumTable, RgbUnbounded, fit_coefficients, sample3,
    srgb_table,
};
pub use wavelengths::{SampledWavelengths, visible_pdf};

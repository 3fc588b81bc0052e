//! `[[material]]`.

use super::texture::TexDesc;
use crate::toml::value::{NonNeg, Positive, Rgb};
use serde::Deserialize;

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
pub(crate) enum MaterialType {
    Diffuse,
    Mirror,
    Dielectric,
    Conductor,
    RoughConductor,
    RoughDielectric,
    Phong,
    /// Index-matched boundary of a medium.
    Null,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialDesc {
    pub(crate) name: String,
    #[serde(rename = "type")]
    pub(crate) ty: MaterialType,
    pub(crate) reflectance: Option<TexDesc>,
    pub(crate) ior: Option<Positive>,
    pub(crate) absorption: Option<Rgb>,
    pub(crate) eta: Option<Rgb>,
    pub(crate) k: Option<Rgb>,
    pub(crate) preset: Option<String>,
    pub(crate) specular: Option<Rgb>,
    pub(crate) alpha: Option<Positive>,
    pub(crate) diffuse: Option<TexDesc>,
    pub(crate) exponent: Option<NonNeg>,
    /// A dielectric's IOR as a function of wavelength (in place of `ior`).
    pub(crate) dispersion: Option<::toml::Spanned<DispersionDesc>>,
}

/// `dispersion = "BK7"` (a named glass or water), `dispersion = { sellmeier = [[B1, C1], …] }`
/// (C in µm², up to 4 terms) or `dispersion = { cauchy = [A, B] }` / `[A, B, C]` (B in µm², C
/// in µm⁴).
#[derive(Deserialize)]
#[serde(untagged)]
pub(crate) enum DispersionDesc {
    Named(String),
    Law(DispersionLaw),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct DispersionLaw {
    pub(crate) sellmeier: Option<Vec<[f64; 2]>>,
    pub(crate) cauchy: Option<Vec<f64>>,
}

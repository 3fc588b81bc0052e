//! `[[light]]`.

use crate::toml::value::{Positive, Rgb, V3};
use serde::Deserialize;

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
pub(crate) enum LightType {
    Point,
    Spot,
    Directional,
    Beam,
    Environment,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightDesc {
    #[serde(rename = "type")]
    pub(crate) ty: LightType,
    pub(crate) position: Option<V3>,
    pub(crate) center: Option<V3>,
    pub(crate) direction: Option<V3>,
    pub(crate) target: Option<V3>,
    pub(crate) intensity: Option<Rgb>,
    pub(crate) irradiance: Option<Rgb>,
    pub(crate) radiance: Option<Rgb>,
    pub(crate) radius: Option<Positive>,
    pub(crate) cutoff_angle: Option<Positive>,
    pub(crate) beam_width: Option<Positive>,
    /// A named emission spectrum (`D65`, `blackbody:<kelvin>`); the light's strength is then
    /// one number, its luminance.
    pub(crate) spectrum: Option<::toml::Spanned<String>>,
    /// The medium the light emits into, by name (found from its position when absent).
    pub(crate) medium: Option<::toml::Spanned<String>>,
}

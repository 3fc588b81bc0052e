//! `[camera]`.

use crate::toml::value::{Count, Matrix, NonNeg, Positive, V3};
use serde::Deserialize;

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
pub(crate) enum FovAxisDesc {
    X,
    Y,
    Smaller,
    Larger,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraDesc {
    pub(crate) eye: Option<V3>,
    pub(crate) target: Option<V3>,
    pub(crate) up: Option<V3>,
    pub(crate) to_world: Option<Matrix>,
    pub(crate) fov: Positive,
    pub(crate) fov_axis: Option<FovAxisDesc>,
    pub(crate) width: Count,
    pub(crate) height: Count,
    pub(crate) lens_radius: Option<NonNeg>,
    pub(crate) focus_distance: Option<Positive>,
    /// The medium the camera sits in, by name (found from its position when absent).
    pub(crate) medium: Option<::toml::Spanned<String>>,
}

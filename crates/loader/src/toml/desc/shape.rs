//! `[[shape]]`.

use super::animation::{FramesDesc, KeyframeDesc};
use super::transform::{RotateList, ScaleDesc};
use crate::toml::value::{Matrix, Positive, Rgb, V3};
use serde::Deserialize;

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
pub(crate) enum ShapeType {
    Obj,
    Ply,
    Sphere,
    Disk,
    Rectangle,
    Cube,
    Mesh,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ShapeDesc {
    #[serde(rename = "type")]
    pub(crate) ty: ShapeType,
    pub(crate) material: String,
    /// Medium on the shape's inside (−normal side) and outside, by name.
    pub(crate) interior: Option<::toml::Spanned<String>>,
    pub(crate) exterior: Option<::toml::Spanned<String>>,
    pub(crate) emission: Option<Rgb>,
    /// A named spectrum for `emission` (`D65`, `blackbody:<kelvin>`); `emission` is then one
    /// number, the radiance's luminance.
    pub(crate) emission_spectrum: Option<::toml::Spanned<String>>,
    pub(crate) flip_normals: Option<bool>,
    pub(crate) filename: Option<String>,
    pub(crate) center: Option<V3>,
    pub(crate) radius: Option<Positive>,
    pub(crate) normal: Option<V3>,
    pub(crate) positions: Option<Vec<V3>>,
    pub(crate) indices: Option<Vec<[u32; 3]>>,
    pub(crate) normals: Option<Vec<V3>>,
    pub(crate) uvs: Option<Vec<[f32; 2]>>,
    pub(crate) translate: Option<V3>,
    pub(crate) rotate: Option<RotateList>,
    pub(crate) scale: Option<ScaleDesc>,
    pub(crate) matrix: Option<Matrix>,
    /// A mesh sequence (obj, ply): one file per frame, identical topology.
    pub(crate) frames: Option<FramesDesc>,
    /// The first and last frame numbers of a `frames` pattern (inclusive).
    pub(crate) frame_range: Option<[i64; 2]>,
    /// The frame of the first file of a `frames` list (default 0).
    pub(crate) first_frame: Option<i64>,
    /// Animated transforms, at increasing integer frames.
    pub(crate) keyframe: Option<Vec<::toml::Spanned<KeyframeDesc>>>,
}

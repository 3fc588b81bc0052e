//! `[animation]` (frame rate and shutter) and a shape's motion: `frames` (a mesh sequence) or
//! `[[shape.keyframe]]` (animated transforms).

use super::transform::{RotateList, ScaleDesc};
use crate::toml::value::{Finite, NonNeg, Positive, V3};
use serde::Deserialize;

/// `[animation]`: time is counted in frames; `fps` converts them to seconds.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AnimationDesc {
    /// Frames per second (> 0): the rate of mesh sequences and keyframes, and of the preview of
    /// a rendered sequence; the shutter in seconds is `shutter / fps`.
    pub(crate) fps: Positive,
    /// The frame the shutter opens at (`--frame` overrides it). Default 0.
    pub(crate) frame: Option<Finite>,
    /// How long the shutter stays open, in frames (seed 003's exposure e; `--shutter`
    /// overrides it). Default 0: an instant.
    pub(crate) shutter: Option<NonNeg>,
}

/// `frames = "pattern-%04d.ply"` (with `frame_range`) or `frames = ["a.ply", "b.ply", …]`.
#[derive(Deserialize, Clone, Debug)]
#[serde(untagged)]
pub(crate) enum FramesDesc {
    Pattern(String),
    List(Vec<String>),
}

/// One `[[shape.keyframe]]`: the shape's transform at an integer frame, composed as the
/// shape's own (`translate · rotate · scale`) and applied after it.
#[derive(Deserialize, Clone, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct KeyframeDesc {
    pub(crate) frame: i64,
    pub(crate) translate: Option<V3>,
    pub(crate) rotate: Option<RotateList>,
    pub(crate) scale: Option<ScaleDesc>,
}

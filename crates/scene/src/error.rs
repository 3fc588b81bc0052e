//! Errors raised while building a scene (`SceneBuilder`); the loaders in `caustica-loader`
//! wrap them in their own error type, which adds file positions.

use thiserror::Error;

/// Every error names what the user must fix.
#[derive(Debug, Error)]
pub enum SceneError {
    /// A parameter is outside its valid range (e.g. IOR ≤ 0, negative radius).
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// The scene cannot be rendered as described (no camera, unknown material name, …).
    #[error("invalid scene: {0}")]
    Invalid(String),
}

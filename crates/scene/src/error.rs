//! Errors raised while building or loading a scene.

use std::path::PathBuf;
use thiserror::Error;

/// Every error names what the user must fix; loader errors name the file and, where the parser
/// knows it, the line and column.
#[derive(Debug, Error)]
pub enum SceneError {
    /// A scene file could not be parsed: `file:line:column: message`.
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// A file the scene refers to could not be read.
    #[error("{path}: {message}")]
    File { path: PathBuf, message: String },
    /// A parameter is outside its valid range (e.g. IOR ≤ 0, negative radius).
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// The scene cannot be rendered as described (no camera, unknown material name, …).
    #[error("invalid scene: {0}")]
    Invalid(String),
}

//! Errors raised while loading a scene.

use caustica_scene::SceneError;
use std::path::PathBuf;
use thiserror::Error;

/// Every error names what the user must fix; loader errors name the file and, where the parser
/// knows it, the line and column.
#[derive(Debug, Error)]
pub enum LoadError {
    /// A scene file could not be parsed: `file:line:column: message`.
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// `-D name=…` for a parameter the scene neither declares (`<default>`) nor uses (`$name`).
    #[error("{path}: -D {name}: the scene has no parameter '{name}' ({declared})")]
    UnknownParameter {
        path: PathBuf,
        name: String,
        /// "its parameters are: a, b" or "it has none".
        declared: String,
    },
    /// A file the scene refers to could not be read.
    #[error("{path}: {message}")]
    File { path: PathBuf, message: String },
    /// The scene builder rejected what the file describes (its message is shown unchanged).
    #[error(transparent)]
    Scene(#[from] SceneError),
}

//! Scene loaders: the caustica TOML format, OBJ and PLY meshes, and the built-in scenes.

pub mod builtin;
pub mod obj;
pub mod ply;
pub mod toml_scene;

pub use builtin::{DEFAULT_SCENE, builtin_names, builtin_scene};
pub use obj::load_obj;
pub use ply::load_ply;
pub use toml_scene::parse_toml_scene;

use crate::error::SceneError;
use crate::scene::Scene;
use std::path::Path;

/// Reads and builds the TOML scene at `path` (relative file names inside resolve against the
/// scene file's folder).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    parse_scene_file(path)?.build()
}

/// Reads the TOML scene at `path` into a [`crate::SceneBuilder`] without building it.
pub fn parse_scene_file(path: &Path) -> Result<crate::SceneBuilder, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::File {
        path: path.to_path_buf(),
        message: format!("cannot read scene file: {e}"),
    })?;
    parse_toml_scene(&text, path)
}

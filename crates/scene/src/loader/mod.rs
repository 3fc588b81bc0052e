//! Scene loaders: the caustica TOML format, OBJ and PLY meshes, and the built-in scenes.

pub mod builtin;
pub mod mitsuba;
pub mod obj;
pub mod ply;
pub mod toml_scene;

pub use builtin::{DEFAULT_SCENE, builtin_names, builtin_scene};
pub use mitsuba::{load_mitsuba, parse_mitsuba};
pub use obj::load_obj;
pub use ply::load_ply;
pub use toml_scene::parse_toml_scene;

use crate::error::SceneError;
use crate::scene::Scene;
use std::path::Path;

/// Reads and builds the scene at `path`: Mitsuba 3 XML for `.xml` files, caustica TOML
/// otherwise (relative file names inside resolve against the scene file's folder).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    parse_scene_file(path)?.build()
}

/// Reads the scene at `path` (Mitsuba XML for `.xml`, TOML otherwise) into a
/// [`crate::SceneBuilder`] without building it.
pub fn parse_scene_file(path: &Path) -> Result<crate::SceneBuilder, SceneError> {
    parse_scene_file_with_defines(path, &[])
}

/// As [`parse_scene_file`]; `defines` (`-D name=value`) override a Mitsuba scene's `<default>`
/// parameters and are ignored by TOML scenes.
pub fn parse_scene_file_with_defines(
    path: &Path,
    defines: &[(String, String)],
) -> Result<crate::SceneBuilder, SceneError> {
    let is_xml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"));
    if is_xml {
        return load_mitsuba(path, defines);
    }
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::File {
        path: path.to_path_buf(),
        message: format!("cannot read scene file: {e}"),
    })?;
    parse_toml_scene(&text, path)
}

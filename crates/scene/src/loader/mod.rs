//! Scene loaders: the caustica TOML format, OBJ and PLY meshes, and the built-in scenes.
//! (Being written; the CLI codes against these entry points.)

use crate::{Scene, SceneBuilder, SceneError};
use std::path::Path;

pub const DEFAULT_SCENE: &str = "glass-sphere";

pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let _ = path;
    todo!()
}

pub fn builtin_scene(name: &str) -> Option<SceneBuilder> {
    let _ = name;
    todo!()
}

pub fn builtin_names() -> &'static [&'static str] {
    &[]
}

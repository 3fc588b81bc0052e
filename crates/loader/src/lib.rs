//! Scene loaders of caustica: the caustica TOML format, Mitsuba 3 XML, OBJ and PLY meshes, and
//! the built-in scenes. Each returns a [`caustica_scene::SceneBuilder`] (or a mesh); errors are
//! [`LoadError`]s that name the file and, where known, the line and column.
#![forbid(unsafe_code)]

pub mod builtin;
pub mod error;
pub mod frame_pattern;
pub mod media;
pub mod mitsuba;
pub mod obj;
pub mod pbrt;
pub mod ply;
mod report;
mod similarity;
pub mod toml;
pub mod vol;

pub use self::toml::parse_toml_scene;
pub use builtin::{
    DEFAULT_SCENE, builtin_names, builtin_scene, plume_density, rising_smoke_density,
    room_smoke_density,
};
pub use error::LoadError;
pub use mitsuba::{load_mitsuba, parse_mitsuba};
pub use obj::{load_obj, parse_obj};
pub use pbrt::{load_pbrt, parse_pbrt};
pub use ply::{load_ply, parse_ply};

use caustica_scene::{Scene, SceneBuilder};
use std::path::Path;

/// Largest image (camera width × height) a scene file may ask for, in every format: the
/// renderer's film holds about 50 bytes per pixel, so larger sizes would fail to allocate rather
/// than give an error.
pub const MAX_FILM_PIXELS: u64 = 1 << 28;

/// Reads and builds the scene at `path`: Mitsuba 3 XML for `.xml` files, pbrt-v4 for `.pbrt`
/// files, caustica TOML otherwise (relative file names inside resolve against the scene file's folder).
pub fn load_scene(path: &Path) -> Result<Scene, LoadError> {
    Ok(parse_scene_file(path)?.build()?)
}

/// Reads the scene at `path` (Mitsuba XML for `.xml`, pbrt-v4 for `.pbrt`, TOML otherwise) into a
/// [`SceneBuilder`] without building it.
pub fn parse_scene_file(path: &Path) -> Result<SceneBuilder, LoadError> {
    parse_scene_file_with_defines(path, &[])
}

/// As [`parse_scene_file`]; `defines` (`-D name=value`) override a Mitsuba scene's `<default>`
/// parameters; a name the scene neither declares nor uses, or any `-D` on a TOML or pbrt scene,
/// is an error ([`LoadError::UnknownParameter`]).
pub fn parse_scene_file_with_defines(
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneBuilder, LoadError> {
    let is_xml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"));
    if is_xml {
        return load_mitsuba(path, defines);
    }
    let is_pbrt = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("pbrt"));
    if is_pbrt {
        if let Some((name, _)) = defines.first() {
            return Err(LoadError::UnknownParameter {
                path: path.to_path_buf(),
                name: name.clone(),
                declared: "-D sets a Mitsuba scene's <default> parameters; a pbrt scene has none"
                    .to_string(),
            });
        }
        return load_pbrt(path);
    }
    if let Some((name, _)) = defines.first() {
        return Err(LoadError::UnknownParameter {
            path: path.to_path_buf(),
            name: name.clone(),
            declared: "-D sets a Mitsuba scene's <default> parameters; a TOML scene has none"
                .to_string(),
        });
    }
    let text = std::fs::read_to_string(path).map_err(|e| LoadError::File {
        path: path.to_path_buf(),
        message: format!("cannot read scene file: {e}"),
    })?;
    parse_toml_scene(&text, path)
}

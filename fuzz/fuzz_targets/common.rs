//! Shared by the Mitsuba fuzz targets: turns fuzzer bytes into a loader input that cannot
//! touch the real file system.

use caustica_loader::LoadError;
use caustica_scene::SceneBuilder;
use std::path::Path;

/// The fuzzed document "lives" in a directory that does not exist, so every relative
/// `filename` (meshes, bitmaps, includes, `../..` included) fails to open.
pub const SCENE_PATH: &str = "/nonexistent-caustica-fuzz/scene.xml";

/// Parses `data` as a Mitsuba scene. Returns `None` for inputs the targets skip: non-UTF-8
/// bytes, and documents with an attribute value (after entity decoding) that starts with `/`,
/// which could name an absolute path (`/dev/zero`, a FIFO, a huge file). `$name` substitution
/// only concatenates attribute values, so a substituted value starting with `/` needs a raw
/// value starting with `/`, which is rejected here.
pub fn parse(data: &[u8]) -> Option<Result<SceneBuilder, LoadError>> {
    let text = std::str::from_utf8(data).ok()?;
    if let Ok(doc) = roxmltree::Document::parse(text) {
        let absolute = doc
            .descendants()
            .flat_map(|n| n.attributes())
            .any(|a| a.value().starts_with('/'));
        if absolute {
            return None;
        }
    }
    let defines = [("fuzz".to_string(), "1".to_string())];
    Some(caustica_loader::parse_mitsuba(
        text,
        Path::new(SCENE_PATH),
        &defines,
    ))
}

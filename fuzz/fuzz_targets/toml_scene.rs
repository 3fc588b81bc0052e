//! Fuzzes the caustica TOML scene loader and then `SceneBuilder::build` (BVH, light
//! preprocessing): any input must give a scene or an error, never a panic, a hang or an
//! unbounded allocation.
#![no_main]

use caustica_loader::parse_toml_scene;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

/// The fuzzed file "lives" in a directory that does not exist, so every relative `filename`
/// or `texture` (`../..` included) fails to open.
const SCENE_PATH: &str = "/nonexistent-caustica-fuzz/scene.toml";

/// Whether any string in `v` (at any depth) starts with `/` and so could name an absolute path
/// (`/dev/zero`, a FIFO, a huge file).
fn has_absolute_string(v: &toml::Value) -> bool {
    match v {
        toml::Value::String(s) => s.starts_with('/'),
        toml::Value::Array(a) => a.iter().any(has_absolute_string),
        toml::Value::Table(t) => t.values().any(has_absolute_string),
        _ => false,
    }
}

fuzz_target!(|data: &[u8]| {
    // Skipped: non-UTF-8 bytes, and documents with a string that could be an absolute path.
    // A document toml cannot parse as a table fails in the loader before any file is named.
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(table) = text.parse::<toml::Table>()
        && table.values().any(has_absolute_string)
    {
        return;
    }
    if let Ok(builder) = parse_toml_scene(text, Path::new(SCENE_PATH)) {
        let _ = builder.build();
    }
});

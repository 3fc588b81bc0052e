//! Fuzzes the pbrt-v4 loader and then `SceneBuilder::build` (BVH, light preprocessing), which
//! sees whatever numbers the loader let through.
//!
//! The scene "lives" in a directory that does not exist, so every relative file name it gives
//! (`Include`, `Import`, `plymesh`, `imagemap`, `../…` included) fails to open; inputs with a
//! quoted string starting with `/` (which could name an absolute path: `/dev/zero`, a FIFO, a
//! huge file) are skipped, as are non-UTF-8 inputs.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

const SCENE_PATH: &str = "/nonexistent-caustica-fuzz/scene.pbrt";

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if text.contains("\"/") {
        return;
    }
    if let Ok(builder) = caustica_loader::parse_pbrt(text, Path::new(SCENE_PATH)) {
        let _ = builder.build();
    }
});

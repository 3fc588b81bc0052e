//! Fuzzes the Mitsuba 3 XML loader and then `SceneBuilder::build` (BVH, light preprocessing),
//! which sees whatever numbers the loader let through.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(Ok(builder)) = common::parse(data) {
        let _ = builder.build();
    }
});

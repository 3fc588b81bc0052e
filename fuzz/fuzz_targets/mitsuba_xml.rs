//! Fuzzes the Mitsuba 3 XML loader: any input must give a scene or an error, never a panic,
//! a hang or an unbounded allocation.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = common::parse(data);
});

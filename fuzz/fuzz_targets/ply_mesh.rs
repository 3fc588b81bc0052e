//! Fuzzes the PLY mesh loader (ASCII and binary) and then the scene builder with the mesh it
//! returns: any input must give a mesh or an error, never a panic, a hang or an unbounded
//! allocation.
#![no_main]

mod mesh;

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let path = Path::new(mesh::MESH_DIR).join("mesh.ply");
    if let Ok(m) = caustica_loader::parse_ply(&mut &data[..], &path) {
        mesh::build(m);
    }
});

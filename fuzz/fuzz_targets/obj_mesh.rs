//! Fuzzes the Wavefront OBJ mesh loader and then the scene builder with the mesh it returns:
//! any input must give a mesh or an error, never a panic, a hang or an unbounded allocation.
//! The loader opens no material library (`mtllib`), so no input reads a file.
#![no_main]

mod mesh;

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let path = Path::new(mesh::MESH_DIR).join("mesh.obj");
    if let Ok(m) = caustica_loader::parse_obj(&mut &data[..], &path) {
        mesh::build(m);
    }
});

//! Stanford PLY meshes (ASCII and binary, via `ply-rs-bw`): vertex `x, y, z`, optional
//! `nx, ny, nz` and `u, v` (or `s, t`, `texture_u, texture_v`); faces as `vertex_indices` or
//! `vertex_index` lists, polygons triangulated as fans. [`to_ascii_ply`] writes a mesh back
//! (the procedural meshes of `scenes/meshes/`).

use crate::error::LoadError;
use caustica_core::{Vec2, Vec3};
use caustica_scene::shape::TriangleMesh;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::io::BufRead;
use std::path::Path;

fn file_err(path: &Path, message: impl Into<String>) -> LoadError {
    LoadError::File {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Loads `path` as a [`TriangleMesh`].
pub fn load_ply(path: &Path) -> Result<TriangleMesh, LoadError> {
    let file = std::fs::File::open(path)
        .map_err(|e| file_err(path, format!("cannot open PLY file: {e}")))?;
    parse_ply(&mut std::io::BufReader::new(file), path)
}

/// As [`load_ply`], reading the PLY data from `reader`; `path` only names errors.
pub fn parse_ply(reader: &mut impl BufRead, path: &Path) -> Result<TriangleMesh, LoadError> {
    let ply = Parser::<DefaultElement>::new()
        .read_ply(reader)
        .map_err(|e| file_err(path, format!("malformed PLY file: {e}")))?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| file_err(path, "PLY file has no 'vertex' element"))?;
    let faces = ply
        .payload
        .get("face")
        .ok_or_else(|| file_err(path, "PLY file has no 'face' element"))?;

    let scalar = |e: &DefaultElement, k: &str| e.get(k).and_then(Property::to_f32_lossy);
    let first_key = |keys: &[(&'static str, &'static str)]| {
        keys.iter().copied().find(|(a, b)| {
            vertices
                .first()
                .is_some_and(|v| v.contains_key(*a) && v.contains_key(*b))
        })
    };
    let mut mesh = TriangleMesh::default();
    let mut normals = Vec::with_capacity(vertices.len());
    let mut uvs = Vec::with_capacity(vertices.len());
    let has_normals = vertices
        .first()
        .is_some_and(|v| ["nx", "ny", "nz"].iter().all(|k| v.contains_key(*k)));
    let uv_keys = first_key(&[("u", "v"), ("s", "t"), ("texture_u", "texture_v")]);
    for (i, v) in vertices.iter().enumerate() {
        let p = match (scalar(v, "x"), scalar(v, "y"), scalar(v, "z")) {
            (Some(x), Some(y), Some(z)) => Vec3::new(x, y, z),
            _ => return Err(file_err(path, format!("vertex {i} lacks x, y or z"))),
        };
        mesh.positions.push(p);
        if has_normals {
            let n = [scalar(v, "nx"), scalar(v, "ny"), scalar(v, "nz")];
            normals.push(Vec3::from(n.map(|c| c.unwrap_or(f32::NAN))));
        }
        if let Some((ku, kv)) = uv_keys {
            let t = [scalar(v, ku), scalar(v, kv)];
            uvs.push(Vec2::from(t.map(|c| c.unwrap_or(f32::NAN))));
        }
    }
    for (i, f) in faces.iter().enumerate() {
        let list = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .ok_or_else(|| {
                file_err(path, "faces need a 'vertex_indices' or 'vertex_index' list")
            })?;
        let idx = list.to_u32_list().ok_or_else(|| {
            file_err(
                path,
                format!("face {i}: indices must be non-negative integers"),
            )
        })?;
        // Fan triangulation; out-of-range indices are removed (and counted) by `sanitize`.
        for k in 1..idx.len().saturating_sub(1) {
            mesh.indices.push([idx[0], idx[k], idx[k + 1]]);
        }
    }
    if mesh.indices.is_empty() {
        return Err(file_err(path, "PLY file contains no faces"));
    }
    if has_normals {
        mesh.normals = Some(normals);
    }
    if uv_keys.is_some() {
        mesh.uvs = Some(uvs);
    }
    Ok(mesh)
}

/// `mesh` as an ASCII PLY file (`x y z`, `nx ny nz` when the mesh has normals, triangles as
/// `vertex_indices`), each `comment` line in the header. Numbers are written in the shortest
/// form that reads back to the same `f32`, so [`load_ply`] returns the mesh bit for bit.
pub fn to_ascii_ply(mesh: &TriangleMesh, comments: &[&str]) -> String {
    use std::fmt::Write;
    let normals = mesh
        .normals
        .as_ref()
        .filter(|n| n.len() == mesh.positions.len());
    let mut s = String::from("ply\nformat ascii 1.0\n");
    for c in comments {
        let _ = writeln!(s, "comment {c}");
    }
    let _ = writeln!(s, "element vertex {}", mesh.positions.len());
    s.push_str("property float x\nproperty float y\nproperty float z\n");
    if normals.is_some() {
        s.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    let _ = writeln!(s, "element face {}", mesh.indices.len());
    s.push_str("property list uchar int vertex_indices\nend_header\n");
    for (i, p) in mesh.positions.iter().enumerate() {
        let _ = write!(s, "{} {} {}", p.x, p.y, p.z);
        if let Some(n) = normals {
            let _ = write!(s, " {} {} {}", n[i].x, n[i].y, n[i].z);
        }
        s.push('\n');
    }
    for t in &mesh.indices {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("caustica-ply-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn ascii_quad_with_normals_and_uvs() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                    property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
                    property float s\nproperty float t\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0 0 0 1 0 0\n2 0 0 0 0 1 1 0\n2 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";
        let m = load_ply(&write("quad.ply", text.as_bytes())).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert!((m.triangle_area(0) + m.triangle_area(1) - 2.0).abs() < 1e-6);
        assert_eq!(m.normals.as_ref().unwrap()[2], Vec3::Z);
        assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(1.0, 1.0));
    }

    #[test]
    fn binary_little_endian_triangle_with_vertex_index() {
        let mut bytes =
            b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                          property float y\nproperty float z\nelement face 1\n\
                          property list uchar uint vertex_index\nend_header\n"
                .to_vec();
        for v in [0.0f32, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0, 0.0] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.push(3);
        for i in [0u32, 1, 2] {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        let m = load_ply(&write("tri.ply", &bytes)).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2]]);
        assert_eq!(m.triangle_area(0), 6.0);
        assert!(m.normals.is_none() && m.uvs.is_none());
    }

    #[test]
    fn truncated_and_missing_files_are_errors() {
        let text = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                     property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                     end_header\n0 0 0\n1 0\n";
        let e = load_ply(&write("bad.ply", text)).unwrap_err();
        assert!(e.to_string().contains("bad.ply"), "{e}");
        let e = load_ply(Path::new("/nonexistent/mesh.ply")).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/mesh.ply"), "{e}");
    }

    #[test]
    fn ascii_writer_round_trips_bit_for_bit() {
        let mut m = caustica_scene::shape::TriangleMesh::cube(
            &caustica_core::Affine3A::from_scale(Vec3::new(0.1, 1.0 / 3.0, 7.25e-9)),
        );
        m.normals = Some(
            m.positions
                .iter()
                .map(|p| p.normalize() * if p.x > 0.0 { 1.0 } else { -1.0 })
                .collect(),
        );
        let text = to_ascii_ply(&m, &["a cube", "scaled"]);
        assert!(text.starts_with("ply\nformat ascii 1.0\ncomment a cube\ncomment scaled\n"));
        let r = load_ply(&write("roundtrip.ply", text.as_bytes())).unwrap();
        assert_eq!(r.indices, m.indices);
        let bits = |v: &[Vec3]| {
            v.iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&r.positions), bits(&m.positions));
        assert_eq!(
            bits(r.normals.as_ref().unwrap()),
            bits(m.normals.as_ref().unwrap())
        );
        m.normals = None;
        let r = load_ply(&write("roundtrip2.ply", to_ascii_ply(&m, &[]).as_bytes())).unwrap();
        assert!(r.normals.is_none());
        assert_eq!(bits(&r.positions), bits(&m.positions));
    }
}

//! Wavefront OBJ meshes (via `tobj`): triangulated, single-indexed, positions with optional
//! normals and texture coordinates. All objects/groups of a file are merged into one mesh.

use crate::error::LoadError;
use caustica_core::{Vec2, Vec3};
use caustica_scene::shape::TriangleMesh;
use std::io::BufRead;
use std::path::Path;

/// Loads `path` as one [`TriangleMesh`]. Vertex normals (uvs) are kept only if every object of
/// the file has them. Non-finite vertices are kept here; [`caustica_scene::SceneBuilder::add_shape`]
/// drops the affected triangles and counts them in the scene warnings.
pub fn load_obj(path: &Path) -> Result<TriangleMesh, LoadError> {
    let file = std::fs::File::open(path).map_err(|_| LoadError::File {
        path: path.to_path_buf(),
        message: "cannot open OBJ file".to_string(),
    })?;
    parse_obj(&mut std::io::BufReader::new(file), path)
}

/// As [`load_obj`], reading the OBJ text from `reader`; `path` only names errors. Material
/// libraries (`mtllib`) are never opened: caustica takes its materials from the scene file, and
/// a library could name a file that never ends (`/dev/zero`) or blocks (a FIFO).
pub fn parse_obj(reader: &mut impl BufRead, path: &Path) -> Result<TriangleMesh, LoadError> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    let mut guarded = FaceIndexGuard::new(reader);
    let (models, _materials) =
        tobj::load_obj_buf(&mut guarded, &opts, no_materials).map_err(|e| LoadError::File {
            path: path.to_path_buf(),
            message: match (guarded.bad_face.take(), e) {
                (Some(face), _) => format!("malformed OBJ file: {face}"),
                (None, tobj::LoadError::OpenFileFailed) => "cannot open OBJ file".to_string(),
                (None, e) => format!("malformed OBJ file: {e}"),
            },
        })?;
    let mut mesh = TriangleMesh::default();
    let all_normals = models
        .iter()
        .all(|m| !m.mesh.normals.is_empty() && m.mesh.normals.len() == m.mesh.positions.len());
    let all_uvs = models.iter().all(|m| {
        !m.mesh.texcoords.is_empty() && m.mesh.texcoords.len() / 2 == m.mesh.positions.len() / 3
    });
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        let count = m.positions.len() / 3;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if all_normals {
            normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        }
        if all_uvs {
            uvs.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])));
        }
        for t in m.indices.chunks_exact(3) {
            // Out-of-range indices are kept and removed (and counted) by `sanitize`.
            let idx = |i: u32| {
                if (i as usize) < count {
                    base + i
                } else {
                    u32::MAX
                }
            };
            mesh.indices.push([idx(t[0]), idx(t[1]), idx(t[2])]);
        }
    }
    if mesh.indices.is_empty() {
        return Err(LoadError::File {
            path: path.to_path_buf(),
            message: "OBJ file contains no faces".into(),
        });
    }
    if all_normals {
        mesh.normals = Some(normals);
    }
    if all_uvs {
        mesh.uvs = Some(uvs);
    }
    Ok(mesh)
}

/// Passes the OBJ text to tobj line by line (tobj reads it with `BufRead::lines`), counting the
/// `v`, `vt` and `vn` statements as tobj does, and stops with a read error at the first face
/// whose texture-coordinate or normal index tobj would overflow on when it builds the mesh
/// (`tobj` 4.0.5 computes `vt * 2` and `vn * 3` unchecked): a relative (negative) index reaching
/// before the first element, or a positive one beyond `usize::MAX / 3`. Debug builds panicked
/// there; release builds wrapped around and read the wrong texture coordinates or normals.
/// (Position indices are bounds-checked by tobj without overflow.) The face is described in
/// `bad_face`.
struct FaceIndexGuard<'r, R> {
    inner: &'r mut R,
    line: Vec<u8>,
    pos: usize,
    line_number: usize,
    /// Positions, texture coordinates and normals so far.
    counts: [usize; 3],
    bad_face: Option<String>,
}

impl<'r, R: BufRead> FaceIndexGuard<'r, R> {
    fn new(inner: &'r mut R) -> Self {
        Self {
            inner,
            line: Vec::new(),
            pos: 0,
            line_number: 0,
            counts: [0; 3],
            bad_face: None,
        }
    }

    /// Checks the line just read; `Err` names the first index that cannot be used.
    fn check_line(&mut self) -> Result<(), String> {
        // Lines that are not UTF-8 end tobj's reading with its own error.
        let Ok(text) = std::str::from_utf8(&self.line) else {
            return Ok(());
        };
        let mut words = text.split_whitespace();
        let counter = match words.next() {
            Some("v") => Some(0),
            Some("vt") => Some(1),
            Some("vn") => Some(2),
            _ => None,
        };
        if let Some(i) = counter {
            self.counts[i] += 1;
            return Ok(());
        }
        if !matches!(text.split_whitespace().next(), Some("f" | "l")) {
            return Ok(());
        }
        // Points and lines (fewer than three vertices) are ignored by the loader.
        if words.clone().count() < 3 {
            return Ok(());
        }
        const WHAT: [&str; 3] = ["position", "texture coordinate", "normal"];
        for word in words {
            for (i, part) in word.split('/').enumerate().take(3).skip(1) {
                let Ok(x) = part.parse::<isize>() else {
                    continue;
                };
                let before_first = x < 0 && x.unsigned_abs() > self.counts[i];
                let huge = x > 0 && x.unsigned_abs() - 1 > (usize::MAX - 2) / 3;
                if before_first || huge {
                    return Err(format!(
                        "line {}: face index '{word}' refers to {} {x} of {}",
                        self.line_number, WHAT[i], self.counts[i]
                    ));
                }
            }
        }
        Ok(())
    }
}

impl<R: BufRead> std::io::Read for FaceIndexGuard<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for FaceIndexGuard<'_, R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos == self.line.len() && self.bad_face.is_none() {
            self.line.clear();
            self.pos = 0;
            if self.inner.read_until(b'\n', &mut self.line)? > 0 {
                self.line_number += 1;
                if let Err(face) = self.check_line() {
                    self.bad_face = Some(face);
                }
            }
        }
        if let Some(face) = &self.bad_face {
            return Err(std::io::Error::other(face.clone()));
        }
        Ok(&self.line[self.pos..])
    }

    fn consume(&mut self, amt: usize) {
        self.pos = (self.pos + amt).min(self.line.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("caustica-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn quad_is_triangulated_and_objects_merged() {
        let p = write(
            "two.obj",
            "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
             f 1/1 2/2 3/3 4/4\no b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nvt 0 0\nvt 1 0\nvt 0 1\nf 5/5 6/6 7/7\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.indices.len(), 3);
        let area: f32 = (0..3).map(|i| m.triangle_area(i)).sum();
        assert!((area - 1.5).abs() < 1e-6);
        assert!(m.normals.is_none());
        let uvs = m.uvs.as_ref().unwrap();
        assert_eq!(uvs.len(), m.positions.len());
        // The second object's triangle refers to its own vertices at z = 1.
        let last = m.indices[2];
        assert!(last.iter().all(|&i| m.positions[i as usize].z == 1.0));
    }

    #[test]
    fn normals_are_loaded() {
        let p = write(
            "n.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.normals.as_ref().unwrap(), &vec![Vec3::Z; 3]);
    }

    #[test]
    fn nan_vertex_is_loaded_then_sanitized() {
        let p = write(
            "nan.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\nf 1 2 4\n",
        );
        let mut m = load_obj(&p).unwrap();
        assert_eq!(m.indices.len(), 2);
        let r = m.sanitize();
        assert_eq!(r.non_finite, 1);
        assert_eq!(m.indices.len(), 1);
    }

    #[test]
    fn material_libraries_are_not_read() {
        // With `a.mtl` read, tobj would split the faces by material into two models with their
        // own vertices (6); unread, the quad keeps its 4 shared vertices.
        write("a.mtl", "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n");
        let p = write(
            "mtl.obj",
            "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!((m.positions.len(), m.indices.len()), (4, 2));
        // Reading this library would never end.
        let p = write(
            "zero.obj",
            "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        );
        assert_eq!(load_obj(&p).unwrap().indices.len(), 1);
    }

    #[test]
    fn missing_file_names_the_path() {
        let e = load_obj(Path::new("/nonexistent/dir/bunny.obj")).unwrap_err();
        assert!(matches!(e, LoadError::File { .. }));
        assert!(e.to_string().contains("/nonexistent/dir/bunny.obj"), "{e}");
    }
}

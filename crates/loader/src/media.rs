//! What the loaders share about participating media: whether a medium boundary is closed.

use caustica_scene::shape::{ShapeGeometry, TriangleMesh};
use std::collections::HashMap;

/// Why `g` does not enclose a volume, or `None` if it does: spheres are closed, disks are not,
/// a mesh is closed when every edge (vertices welded by exact position) is shared by exactly two
/// triangles.
pub fn open_boundary_reason(g: &ShapeGeometry) -> Option<String> {
    match g {
        ShapeGeometry::Sphere(_) => None,
        ShapeGeometry::Disk(_) => Some("a disk has no inside".into()),
        ShapeGeometry::Mesh(m) => open_mesh_edge(m),
    }
}

fn open_mesh_edge(m: &TriangleMesh) -> Option<String> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let welded: Vec<u32> = m
        .positions
        .iter()
        .map(|p| {
            let key = p.to_array().map(|x| (x + 0.0).to_bits());
            let next = ids.len() as u32;
            *ids.entry(key).or_insert(next)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &m.indices {
        let v = t.map(|i| welded.get(i as usize).copied().unwrap_or(u32::MAX));
        for (a, b) in [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])] {
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    if m.indices.is_empty() {
        return Some("the mesh has no triangles".into());
    }
    let bad = edges.values().filter(|&&n| n != 2).count();
    (bad > 0).then(|| {
        format!(
            "{bad} of its {} edges are not shared by exactly two triangles",
            edges.len()
        )
    })
}

/// The warning for a shape that separates media without enclosing a volume.
pub fn open_boundary_warning(shape: &str, reason: &str) -> String {
    format!(
        "{shape} is a medium boundary but not closed ({reason}): rays passing around it see the \
         media on its sides swapped"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::{Affine3A, Vec3};
    use caustica_scene::shape::{Disk, Sphere};

    #[test]
    fn cubes_and_spheres_are_closed_rectangles_and_disks_are_not() {
        let t = Affine3A::from_scale_rotation_translation(
            Vec3::new(0.3, 0.7, 1.1),
            glam::Quat::from_rotation_y(0.4),
            Vec3::new(0.1, -0.2, 0.3),
        );
        let cube = TriangleMesh::cube(&t);
        assert_eq!(
            open_boundary_reason(&ShapeGeometry::Mesh(cube.clone())),
            None
        );
        let r = open_boundary_reason(&ShapeGeometry::Mesh(TriangleMesh::rectangle(&t))).unwrap();
        assert!(r.contains("4 of its 5 edges"), "{r}");
        assert!(
            open_boundary_reason(&ShapeGeometry::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: 1.0
            }))
            .is_none()
        );
        assert!(
            open_boundary_reason(&ShapeGeometry::Disk(Disk {
                center: Vec3::ZERO,
                normal: Vec3::Z,
                radius: 1.0
            }))
            .is_some()
        );
        // A cube missing one triangle is open; one with a triangle doubled too.
        let mut holed = cube.clone();
        holed.indices.pop();
        assert!(open_boundary_reason(&ShapeGeometry::Mesh(holed)).is_some());
        let mut doubled = cube;
        doubled.indices.push(doubled.indices[0]);
        assert!(open_boundary_reason(&ShapeGeometry::Mesh(doubled)).is_some());
    }
}

//! Built-in scenes, also shipped as TOML files in `scenes/` (a test checks they agree).

use super::toml_scene::look_at_transform;
use crate::camera::{FovAxis, PerspectiveCamera};
use crate::error::SceneError;
use crate::light::{Light, PointLight};
use crate::material::Material;
use crate::scene::{FilterKind, SceneBuilder};
use crate::shape::{ShapeGeometry, Sphere, TriangleMesh};
use crate::texture::Texture;
use caustica_core::{Affine3A, Spectrum, Vec3};

/// The scene `caustica render` uses without an argument.
/// The Cornell box until a caustic-capable default integrator (photon mapping) lands: the
/// glass-sphere caustic needs light paths, which the default path tracer cannot find from a
/// point light.
pub const DEFAULT_SCENE: &str = "cornell-box";

const NAMES: &[&str] = &["cornell-box", "glass-sphere"];

/// Names accepted by [`builtin_scene`].
pub fn builtin_names() -> &'static [&'static str] {
    NAMES
}

/// The built-in scene called `name`, or `None`.
pub fn builtin_scene(name: &str) -> Option<SceneBuilder> {
    match name {
        "cornell-box" => cornell_box().ok(),
        "glass-sphere" => glass_sphere().ok(),
        _ => None,
    }
}

fn camera(eye: Vec3, target: Vec3, fov: f32, width: u32, height: u32) -> PerspectiveCamera {
    PerspectiveCamera {
        width,
        height,
        to_world: look_at_transform(eye, target, Vec3::Y).unwrap_or(Affine3A::IDENTITY),
        fov_deg: fov,
        fov_axis: FovAxis::X,
        lens_radius: 0.0,
        focus_distance: (target - eye).length(),
        near_clip: 1e-4,
    }
}

fn diffuse(r: f32, g: f32, b: f32) -> Material {
    Material::Diffuse {
        reflectance: Texture::Constant(Spectrum::new(r, g, b)),
    }
}

/// `translate · rotate(axis, degrees) · scale`, the order Mitsuba's chained transforms use.
fn trs(t: Vec3, axis: Vec3, deg: f32, s: Vec3) -> Affine3A {
    Affine3A::from_translation(t)
        * Affine3A::from_axis_angle(axis, deg.to_radians())
        * Affine3A::from_scale(s)
}

/// Mitsuba's `mi.cornell_box()`: a 2×2×2 box around the origin, red left wall, green right
/// wall, a small rectangular area light under the ceiling and two boxes.
fn cornell_box() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("cornell-box");
    b.set_camera(camera(
        Vec3::new(0.0, 0.0, 3.9),
        Vec3::ZERO,
        39.3077,
        256,
        256,
    ));
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(8);
    b.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 2.0,
    };
    let white = b.add_material("white", diffuse(0.885809, 0.698859, 0.666422))?;
    let green = b.add_material("green", diffuse(0.105421, 0.37798, 0.076425))?;
    let red = b.add_material("red", diffuse(0.570068, 0.0430135, 0.0443706))?;
    let rect = |t: Affine3A| ShapeGeometry::Mesh(TriangleMesh::rectangle(&t));
    let one = Vec3::ONE;
    b.add_shape(
        rect(trs(
            Vec3::new(0.0, 0.99, 0.01),
            Vec3::X,
            90.0,
            Vec3::new(0.23, 0.19, 0.19),
        )),
        white,
        Some(Spectrum::new(18.387, 13.9873, 6.75357)),
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(0.0, -1.0, 0.0), Vec3::X, -90.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(0.0, 1.0, 0.0), Vec3::X, 90.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(0.0, 0.0, -1.0), Vec3::X, 0.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(1.0, 0.0, 0.0), Vec3::Y, -90.0, one)),
        green,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y, 90.0, one)),
        red,
        None,
        false,
    )?;
    let cube = |t: Affine3A| ShapeGeometry::Mesh(TriangleMesh::cube(&t));
    // Small box.
    b.add_shape(
        cube(trs(
            Vec3::new(0.335, -0.7, 0.38),
            Vec3::Y,
            -17.0,
            Vec3::splat(0.3),
        )),
        white,
        None,
        false,
    )?;
    // Large box.
    b.add_shape(
        cube(trs(
            Vec3::new(-0.33, -0.4, -0.28),
            Vec3::Y,
            18.25,
            Vec3::new(0.3, 0.61, 0.3),
        )),
        white,
        None,
        false,
    )?;
    Ok(b)
}

/// A glass ball (IOR 1.5, radius 0.5) resting on a grey diffuse floor, lit by a point light
/// above and to the side so that its caustic falls beside the contact point, seen from above.
fn glass_sphere() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("glass-sphere");
    b.set_camera(camera(
        Vec3::new(1.8, 2.6, 2.4),
        Vec3::new(0.15, 0.25, 0.0),
        40.0,
        256,
        256,
    ));
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(16);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let glass = b.add_material(
        "glass",
        Material::Dielectric {
            ior: 1.5,
            absorption: Spectrum::ZERO,
        },
    )?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::ZERO,
            Vec3::X,
            -90.0,
            Vec3::splat(2.0),
        ))),
        floor,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.0, 0.5, 0.0),
            radius: 0.5,
        }),
        glass,
        None,
        false,
    )?;
    b.add_light(Light::Point(PointLight::new(
        Vec3::new(-2.0, 3.5, 0.0),
        Spectrum::splat(40.0),
    )));
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loader::parse_scene_file;
    use std::path::Path;

    #[test]
    fn names_include_the_default() {
        assert!(builtin_names().contains(&DEFAULT_SCENE));
        assert!(builtin_names().contains(&"cornell-box"));
        assert!(builtin_scene("no-such-scene").is_none());
    }

    fn mesh_positions(b: &SceneBuilder) -> Vec<Vec<Vec3>> {
        b.shapes()
            .iter()
            .map(|s| match &s.geometry {
                ShapeGeometry::Mesh(m) => m.positions.clone(),
                ShapeGeometry::Sphere(s) => vec![s.center, Vec3::splat(s.radius)],
                ShapeGeometry::Disk(d) => vec![d.center, d.normal, Vec3::splat(d.radius)],
            })
            .collect()
    }

    #[test]
    fn builtin_scenes_match_their_toml_files() {
        for name in builtin_names() {
            let a = builtin_scene(name).unwrap();
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../scenes")
                .join(format!("{name}.toml"));
            let b = parse_scene_file(&path).unwrap();
            assert_eq!(a.name, b.name);
            assert_eq!(a.shape_count(), b.shape_count(), "{name}");
            assert_eq!(a.material_names(), b.material_names(), "{name}");
            assert_eq!(a.lights().len(), b.lights().len(), "{name}");
            for (la, lb) in a.lights().iter().zip(b.lights()) {
                let (pa, pb) = (la.power(), lb.power());
                for i in 0..3 {
                    assert!(
                        (pa.c[i] - pb.c[i]).abs() <= 1e-5 * pa.c[i].abs().max(1e-3),
                        "{name}: {pa:?} vs {pb:?}"
                    );
                }
                assert_eq!(std::mem::discriminant(la), std::mem::discriminant(lb));
            }
            let (ca, cb) = (a.camera().unwrap(), b.camera().unwrap());
            assert_eq!(
                (ca.width, ca.height, ca.fov_axis),
                (cb.width, cb.height, cb.fov_axis)
            );
            assert!((ca.fov_deg - cb.fov_deg).abs() < 1e-6);
            assert!(Mat4Cmp(ca.to_world).close(cb.to_world));
            assert!((ca.focus_distance - cb.focus_distance).abs() < 1e-5);
            assert_eq!(a.settings.spp, b.settings.spp);
            assert_eq!(a.settings.max_depth, b.settings.max_depth);
            assert_eq!(a.settings.filter, b.settings.filter);
            for (sa, sb) in a.shapes().iter().zip(b.shapes()) {
                assert_eq!(sa.material, sb.material, "{name}");
                assert_eq!(
                    sa.light == crate::intersection::NONE,
                    sb.light == crate::intersection::NONE
                );
            }
            for (pa, pb) in mesh_positions(&a).iter().zip(mesh_positions(&b).iter()) {
                assert_eq!(pa.len(), pb.len());
                for (x, y) in pa.iter().zip(pb) {
                    assert!(x.abs_diff_eq(*y, 1e-5), "{name}: {x} vs {y}");
                }
            }
        }
    }

    struct Mat4Cmp(Affine3A);
    impl Mat4Cmp {
        fn close(&self, o: Affine3A) -> bool {
            self.0.abs_diff_eq(o, 1e-5)
        }
    }

    #[test]
    fn cornell_box_geometry() {
        let b = builtin_scene("cornell-box").unwrap();
        assert_eq!(b.shape_count(), 8);
        assert_eq!(b.lights().len(), 1);
        // Light: 0.46 × 0.38 rectangle at y = 0.99 facing down.
        let ShapeGeometry::Mesh(l) = &b.shapes()[0].geometry else {
            panic!()
        };
        let area = l.triangle_area(0) + l.triangle_area(1);
        assert!((area - 0.46 * 0.38).abs() < 1e-5);
        let [p0, p1, p2] = l.indices[0].map(|i| l.positions[i as usize]);
        assert!(
            (p1 - p0)
                .cross(p2 - p0)
                .normalize()
                .abs_diff_eq(-Vec3::Y, 1e-6)
        );
        assert!(l.positions.iter().all(|p| (p.y - 0.99).abs() < 1e-6));
        // Every wall faces the inside of the box and the red wall is on the left (x = −1).
        for s in &b.shapes()[1..6] {
            let ShapeGeometry::Mesh(m) = &s.geometry else {
                panic!()
            };
            let [p0, p1, p2] = m.indices[0].map(|i| m.positions[i as usize]);
            let n = (p1 - p0).cross(p2 - p0).normalize();
            assert!(n.dot(-p0) > 0.9, "wall at {p0} faces {n}");
        }
        let red = b.material_index("red").unwrap();
        let ShapeGeometry::Mesh(m) = &b.shapes()[5].geometry else {
            panic!()
        };
        assert_eq!(b.shapes()[5].material, red);
        assert!(m.positions.iter().all(|p| (p.x + 1.0).abs() < 1e-6));
        // Boxes stand on the floor (Mitsuba's large box is 1.22 high and sinks 1 cm into it).
        for (s, floor) in b.shapes()[6..].iter().zip([-1.0f32, -1.01]) {
            let ShapeGeometry::Mesh(m) = &s.geometry else {
                panic!()
            };
            let min_y = m
                .positions
                .iter()
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            assert!(
                (min_y - floor).abs() < 1e-5,
                "box bottom at {min_y}, expected {floor}"
            );
        }
    }
}

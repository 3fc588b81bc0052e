//! Projection maps (`light::projection_map`): which emission cells are marked, the density the
//! guided emission samples with (χ² against `density`), that guided emission is unbiased
//! (the power reaching a mirror ball, analytic), that the densities' reciprocals average to one
//! (what keeps photon differentials' footprints tiling the emission, seed 002 eq. 5–6), and the
//! fallbacks (no specular surface, a light without power).

use caustica_core::chi2::{ChiSquareTest, SphericalDomain};
use caustica_core::sampling::Pcg32;
use caustica_core::{PI, Spectrum, Vec2, Vec3};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::projection_map::DEFENSIVE;
use caustica_scene::light::{BeamLight, DirectionalLight, Light, PointLight, SpotLight};
use caustica_scene::material::Material;
use caustica_scene::shape::{ShapeGeometry, Sphere, TriangleMesh};
use caustica_scene::texture::Texture;
use caustica_scene::{Scene, SceneBuilder};
use glam::Affine3A;

const LIGHT: Vec3 = Vec3::new(0.0, 3.0, 0.0);
const BALL: Vec3 = Vec3::new(1.0, 1.0, 0.5);
const BALL_R: f32 = 0.3;

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

/// A diffuse floor (y = 0, 8 × 8 m), a mirror ball of radius `BALL_R` at `BALL` (or a diffuse
/// one), and `lights`.
fn scene(mirror_ball: bool, lights: Vec<Light>, area_light: bool) -> Scene {
    let mut b = SceneBuilder::new("projection-test");
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 2.0, 6.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        32,
        32,
    ));
    let floor = b
        .add_material(
            "floor",
            Material::Diffuse {
                reflectance: Texture::Constant(Spectrum::splat(0.5)),
            },
        )
        .unwrap();
    let ball = b
        .add_material(
            "ball",
            if mirror_ball {
                Material::Mirror {
                    reflectance: Spectrum::ONE,
                }
            } else {
                Material::Diffuse {
                    reflectance: Texture::Constant(Spectrum::splat(0.5)),
                }
            },
        )
        .unwrap();
    let rect = Affine3A::from_rotation_x(-PI / 2.0) * Affine3A::from_scale(Vec3::splat(4.0));
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&rect)),
        floor,
        None,
        false,
    )
    .unwrap();
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: BALL,
            radius: BALL_R,
        }),
        ball,
        None,
        false,
    )
    .unwrap();
    if area_light {
        // A 0.4 m square facing down at y = 3.
        let light = b
            .add_material(
                "lamp",
                Material::Diffuse {
                    reflectance: Texture::Constant(Spectrum::ZERO),
                },
            )
            .unwrap();
        let to = Affine3A::from_translation(LIGHT)
            * Affine3A::from_rotation_x(PI / 2.0)
            * Affine3A::from_scale(Vec3::splat(0.2));
        b.add_shape(
            ShapeGeometry::Mesh(TriangleMesh::rectangle(&to)),
            light,
            Some(Spectrum::splat(10.0)),
            false,
        )
        .unwrap();
    }
    for l in lights {
        b.add_light(l);
    }
    b.build().unwrap()
}

fn point_scene() -> Scene {
    scene(
        true,
        vec![Light::Point(PointLight::new(LIGHT, Spectrum::splat(10.0)))],
        false,
    )
}

/// Primary sample of the uniform-sphere warp for direction `d` (its inverse).
fn sphere_u(d: Vec3) -> Vec2 {
    let phi = d.y.atan2(d.x);
    let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
    Vec2::new((1.0 - d.z) / 2.0, phi / (2.0 * PI))
}

/// Every direction from the point light toward the ball lies in a marked cell, and the marked
/// share is at least the ball's solid-angle share and not much more (the dilation's rim).
#[test]
fn point_light_marks_the_ball_and_little_else() {
    let s = point_scene();
    let map = s.projection_map();
    assert!(!map.is_empty(), "{:?}", map.warnings);
    let to_ball = BALL - LIGHT;
    let d = to_ball.length();
    let cos_a = (1.0 - (BALL_R / d).powi(2)).sqrt();
    let share = (1.0 - cos_a) as f64 / 2.0; // solid angle / 4π
    let m = map.marked_fraction();
    assert!(m >= share && m < 4.0 * share, "marked {m} vs ball {share}");
    // Directions uniform in the cone toward the ball: all in marked cells (density above ε).
    let mut rng = Pcg32::new(3, 1);
    let frame = caustica_core::Frame::from_normal(to_ball / d);
    for _ in 0..20_000 {
        let w = caustica_core::sampling::warp::square_to_uniform_cone(u2(&mut rng), cos_a);
        let dir = frame.to_world(w).normalize();
        let p = map.density(0, Vec2::splat(0.5), sphere_u(dir)).total();
        assert!(
            p > 1.5 * DEFENSIVE,
            "direction {dir} toward the ball not marked"
        );
    }
}

/// The guided emission's directions follow its density: χ² over the sphere with
/// `pdf(ω) = p_rel(u(ω)) / 4π`.
#[test]
fn guided_point_emission_chi_square() {
    let s = point_scene();
    let map = s.projection_map();
    let dist = s.light_distribution.as_ref().unwrap();
    let mut rng = Pcg32::new(11, 2);
    let domain = SphericalDomain {
        cos_bins: 64,
        phi_bins: 128,
        integration_res: 4,
    };
    let test = ChiSquareTest::new(domain, 2_000_000);
    let r = test.run(
        || {
            let g = map.sample(dist, rng.next_f32(), u2(&mut rng), u2(&mut rng))?;
            Some(s.lights[g.light].sample_emission(g.u_pos, g.u_dir).ray.d)
        },
        |w: Vec3| map.density(0, Vec2::splat(0.5), sphere_u(w)).total() / (4.0 * PI),
    );
    assert!(r.passed(), "{r}");
}

/// Guided emission is unbiased: the flux reaching the mirror ball, E[weight / (pmf p_rel) ·
/// hit], equals the analytic I · 2π (1 − cos α), and so does uniform emission's.
#[test]
fn guided_flux_onto_the_ball_is_analytic() {
    let s = point_scene();
    let map = s.projection_map();
    let dist = s.light_distribution.as_ref().unwrap();
    let to_ball = BALL - LIGHT;
    let cos_a = (1.0 - (BALL_R / to_ball.length()).powi(2)).sqrt();
    let expected = 10.0 * 2.0 * PI as f64 * (1.0 - cos_a as f64);
    let n = 400_000;
    let mut rng = Pcg32::new(5, 9);
    let (mut sum, mut sum2, mut hits) = (0.0f64, 0.0f64, 0u64);
    for _ in 0..n {
        let g = map
            .sample(dist, rng.next_f32(), u2(&mut rng), u2(&mut rng))
            .unwrap();
        let es = s.lights[g.light].sample_emission(g.u_pos, g.u_dir);
        let hit = s
            .intersect(&es.spawn_ray())
            .is_some_and(|si| si.material == 1);
        let v = if hit {
            hits += 1;
            (es.weight.average() / (g.pmf * g.density.total())) as f64
        } else {
            0.0
        };
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / n as f64;
    let sem = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    assert!(
        (mean - expected).abs() < 5.0 * sem + 1e-4 * expected,
        "guided flux {mean} ± {sem} vs analytic {expected}"
    );
    // Most guided paths reach the ball (uniform: the solid-angle share, 0.4 % here).
    let yield_ = hits as f64 / n as f64;
    assert!(yield_ > 0.5, "guided yield {yield_}");
}

/// E[1/p_rel] = E[1/p_pos] = E[1/p_dir] = 1 under the guided density, for point, area,
/// directional, spot and beam lights: N photons' initial footprints (areas ∝ 1/p_pos, solid angles
/// ∝ 1/p_dir) still sum to s² A_e and s² ω_e in expectation (seed 002 eq. 5–6).
#[test]
fn reciprocal_densities_average_to_one() {
    let scenes = [
        ("point", point_scene()),
        ("area", scene(true, vec![], true)),
        (
            "directional",
            scene(
                true,
                vec![Light::Directional(DirectionalLight::new(
                    Vec3::new(0.3, -1.0, 0.1).normalize(),
                    Spectrum::splat(2.0),
                ))],
                false,
            ),
        ),
        (
            "spot",
            scene(
                true,
                vec![Light::Spot(SpotLight::new(
                    LIGHT,
                    BALL - LIGHT,
                    Spectrum::splat(10.0),
                    30.0,
                    20.0,
                ))],
                false,
            ),
        ),
        (
            "beam",
            scene(
                true,
                vec![Light::Beam(BeamLight::new(
                    BALL + Vec3::new(0.0, 2.0, 0.0),
                    -Vec3::Y,
                    0.6,
                    Spectrum::splat(5.0),
                ))],
                false,
            ),
        ),
    ];
    for (name, s) in &scenes {
        let map = s.projection_map();
        assert!(!map.is_empty(), "{name}: {:?}", map.warnings);
        let dist = s.light_distribution.as_ref().unwrap();
        let mut rng = Pcg32::new(21, 4);
        let n = 400_000;
        let mut acc = [(0.0f64, 0.0f64); 3];
        for _ in 0..n {
            let g = map
                .sample(dist, rng.next_f32(), u2(&mut rng), u2(&mut rng))
                .unwrap();
            let d = g.density;
            for (k, x) in [1.0 / d.total(), 1.0 / d.pos, 1.0 / d.dir]
                .iter()
                .enumerate()
            {
                acc[k].0 += *x as f64;
                acc[k].1 += (*x as f64).powi(2);
            }
        }
        for (k, what) in ["1/p_rel", "1/p_pos", "1/p_dir"].iter().enumerate() {
            let mean = acc[k].0 / n as f64;
            let sem = ((acc[k].1 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
            assert!(
                (mean - 1.0).abs() < 5.0 * sem + 1e-4,
                "{name}: E[{what}] = {mean} ± {sem}"
            );
        }
    }
}

/// No specular surface: the map is empty, says so, and emission stays uniform.
#[test]
fn no_specular_surface_falls_back_to_uniform() {
    let s = scene(
        false,
        vec![Light::Point(PointLight::new(LIGHT, Spectrum::splat(10.0)))],
        false,
    );
    let map = s.projection_map();
    assert!(map.is_empty());
    assert!(
        map.warnings.iter().any(|w| w.contains("uniformly")),
        "{:?}",
        map.warnings
    );
    let dist = s.light_distribution.as_ref().unwrap();
    assert!(
        map.sample(dist, 0.5, Vec2::splat(0.3), Vec2::splat(0.7))
            .is_none()
    );
    assert_eq!(
        map.density(0, Vec2::splat(0.3), Vec2::splat(0.7)).total(),
        1.0
    );
}

/// A light without power is skipped with a warning; the other light's map still works and the
/// densities stay finite.
#[test]
fn zero_power_light_is_skipped() {
    let s = scene(
        true,
        vec![
            Light::Point(PointLight::new(LIGHT, Spectrum::ZERO)),
            Light::Point(PointLight::new(LIGHT, Spectrum::splat(10.0))),
        ],
        false,
    );
    let map = s.projection_map();
    assert!(map.lights[0].is_none() && map.lights[1].is_some());
    assert!(
        map.warnings
            .iter()
            .any(|w| w.contains("light 0 emits no power")),
        "{:?}",
        map.warnings
    );
    let dist = s.light_distribution.as_ref().unwrap();
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..10_000 {
        let g = map
            .sample(dist, rng.next_f32(), u2(&mut rng), u2(&mut rng))
            .unwrap();
        assert_eq!(g.light, 1);
        assert!(g.density.total().is_finite() && g.density.total() > 0.0);
    }
}

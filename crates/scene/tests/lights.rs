//! Tests of the lights (sampling densities, irradiance, power) and of the perspective camera.
//! Expected values are analytic or computed independently of the code under test.

use caustica_core::chi2::{ChiSquareTest, SphericalDomain};
use caustica_core::sampling::Pcg32;
use caustica_core::{Frame, PI, Spectrum, Vec2, Vec3};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::{
    AreaLight, AreaShape, BeamLight, DirectionalLight, EnvironmentLight, Light, PointLight,
    SpotLight,
};
use caustica_scene::shape::{Disk, Sphere};

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

/// Running mean and variance (f64).
#[derive(Clone, Default)]
struct Stats {
    n: f64,
    sum: f64,
    sum2: f64,
}
impl Stats {
    fn add(&mut self, x: f64) {
        self.n += 1.0;
        self.sum += x;
        self.sum2 += x * x;
    }
    fn mean(&self) -> f64 {
        self.sum / self.n
    }
    /// Standard error of the mean.
    fn sem(&self) -> f64 {
        let m = self.mean();
        ((self.sum2 / self.n - m * m).max(0.0) / self.n).sqrt()
    }
    /// Mean within 5 standard errors (plus a float-rounding slack) of `expected`.
    fn check(&self, expected: f64, what: &str) {
        let tol = 5.0 * self.sem() + 1e-4 * expected.abs();
        assert!(
            (self.mean() - expected).abs() <= tol,
            "{what}: mean {} expected {expected} (tol {tol})",
            self.mean()
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Ray intersection helpers (independent of the light code), to find the light point for pdf_li.

fn hit_triangle(o: Vec3, d: Vec3, t: &[Vec3; 3]) -> Option<f32> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let tt = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && tt > 0.0).then_some(tt)
}

fn hit_sphere(o: Vec3, d: Vec3, s: &Sphere) -> Option<f32> {
    let oc = o - s.center;
    let b = oc.dot(d);
    let c = oc.length_squared() - s.radius * s.radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    [-b - sq, -b + sq].into_iter().find(|&t| t > 0.0)
}

fn hit_disk(o: Vec3, d: Vec3, k: &Disk) -> Option<f32> {
    let dn = d.dot(k.normal);
    if dn.abs() < 1e-12 {
        return None;
    }
    let t = (k.center - o).dot(k.normal) / dn;
    (t > 0.0 && (o + d * t - k.center).length() <= k.radius).then_some(t)
}

/// Light point and geometric normal seen from `p` along `w` (nearest hit).
fn light_hit(shape: &AreaShape, p: Vec3, w: Vec3) -> Option<(Vec3, Vec3)> {
    match shape {
        AreaShape::Triangles(ts) => ts
            .iter()
            .filter_map(|t| hit_triangle(p, w, t).map(|h| (h, t)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(h, t)| (p + w * h, (t[1] - t[0]).cross(t[2] - t[0]).normalize())),
        AreaShape::Sphere(s) => {
            hit_sphere(p, w, s).map(|h| (p + w * h, (p + w * h - s.center).normalize()))
        }
        AreaShape::Disk(k) => hit_disk(p, w, k).map(|h| (p + w * h, k.normal)),
    }
}

/// Frame whose s axis is `toward` (so `toward` lies on the equator of the χ² grid), turned by an
/// arbitrary angle about it so that straight light edges do not align with grid lines.
fn binning_frame(toward: Vec3) -> Frame {
    let f = Frame::from_normal(toward);
    let n = f.s * 0.82f32.cos() + f.t * 0.82f32.sin();
    Frame::from_normal_tangent(n, toward)
}

fn shape_center(shape: &AreaShape) -> Vec3 {
    match shape {
        AreaShape::Triangles(ts) => {
            ts.iter().map(|t| t[0] + t[1] + t[2]).sum::<Vec3>() / (3.0 * ts.len() as f32)
        }
        AreaShape::Sphere(s) => s.center,
        AreaShape::Disk(k) => k.center,
    }
}

fn quad(c: Vec3, a: Vec3, b: Vec3) -> Vec<[Vec3; 3]> {
    // Square c ± a ± b, wound so the normal is a × b.
    let p = [c - a - b, c + a - b, c + a + b, c - a + b];
    vec![[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
}

fn area_shapes() -> Vec<(&'static str, AreaShape)> {
    vec![
        (
            "quad",
            // Normal b × a = (0, 0.24, −0.4) faces the shading points below it.
            AreaShape::Triangles(quad(
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(0.0, 0.5, 0.3),
                Vec3::new(0.8, 0.0, 0.0),
            )),
        ),
        (
            "sphere",
            AreaShape::Sphere(Sphere {
                center: Vec3::new(0.3, -0.2, 1.5),
                radius: 0.6,
            }),
        ),
        (
            "disk",
            AreaShape::Disk(Disk {
                center: Vec3::new(0.0, 0.5, 1.5),
                normal: Vec3::new(0.2, -0.3, -1.0).normalize(),
                radius: 0.7,
            }),
        ),
    ]
}

// ---------------------------------------------------------------------------------------------
// Chi-square tests.

#[test]
fn chi2_quad_sample_li_matches_pdf_li() {
    chi2_area_sample_li(0);
}
#[test]
fn chi2_sphere_sample_li_matches_pdf_li() {
    chi2_area_sample_li(1);
}
#[test]
fn chi2_disk_sample_li_matches_pdf_li() {
    chi2_area_sample_li(2);
}

fn chi2_area_sample_li(which: usize) {
    let points = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.5, -0.7, 0.4),
        Vec3::new(-0.4, 0.9, -0.5),
    ];
    for two_sided in [false, true] {
        {
            let (name, shape) = area_shapes().swap_remove(which);
            let light = Light::Area(AreaLight::new(
                shape.clone(),
                Spectrum::splat(2.0),
                two_sided,
            ));
            for (k, &p) in points.iter().enumerate() {
                let mut rng = Pcg32::new(100 + k as u64, 7);
                let mut mismatch = 0.0f32;
                // Bin in a frame that puts the light's centre on the equator, where the cells
                // of the (cos θ, φ) grid are closest to square (the density is discontinuous at
                // the light's outline, which the cell integration must resolve).
                let toward = (shape_center(&shape) - p).normalize();
                let bin = binning_frame(toward);
                let domain = SphericalDomain {
                    integration_res: 40,
                    ..SphericalDomain::default()
                };
                let test = ChiSquareTest::new(domain, 150_000);
                let res = test.run(
                    || {
                        let s = light.sample_li(p, u2(&mut rng))?;
                        // The returned pdf must be what pdf_li reports for that direction.
                        let (lp, ln) = light_hit(&shape, p, s.wi)?;
                        let q = light.pdf_li(p, s.wi, lp, ln);
                        mismatch = mismatch.max((q - s.pdf).abs() / s.pdf);
                        let le = light.le(ln, -s.wi);
                        let w = le.c[0] / s.pdf;
                        mismatch = mismatch.max((w - s.weight.c[0]).abs() / w);
                        Some(bin.to_local(s.wi))
                    },
                    |wl| {
                        let w = bin.to_world(wl);
                        match light_hit(&shape, p, w) {
                            Some((lp, ln)) => light.pdf_li(p, w, lp, ln),
                            None => 0.0,
                        }
                    },
                );
                assert!(
                    res.passed_at(0.01 / 6.0),
                    "{name} two_sided={two_sided} from {p}: {res}"
                );
                assert!(
                    mismatch < 1e-2,
                    "{name} from {p}: pdf/weight mismatch {mismatch}"
                );
            }
        }
    }
}

#[test]
fn chi2_environment_sample_li() {
    let mut light = Light::Environment(EnvironmentLight::constant(Spectrum::splat(1.0)));
    light.preprocess(Vec3::ZERO, 3.0);
    let mut rng = Pcg32::new(5, 1);
    let p = Vec3::new(0.3, 0.1, -0.2);
    let res = ChiSquareTest::new(SphericalDomain::default(), 200_000).run(
        || light.sample_li(p, u2(&mut rng)).map(|s| s.wi),
        |w| light.pdf_li(p, w, p + w * 10.0, -w),
    );
    assert!(res.passed(), "{res}");
}

#[test]
fn chi2_area_emission_directions_are_cosine() {
    for two_sided in [false, true] {
        for (name, shape) in area_shapes() {
            let light = AreaLight::new(shape.clone(), Spectrum::ONE, two_sided);
            let light = Light::Area(light);
            let mut rng = Pcg32::new(31, 3);
            let mut bad_normal = 0usize;
            let mut flipped = 0usize;
            let res = ChiSquareTest::new(SphericalDomain::default(), 150_000).run(
                || {
                    let e = light.sample_emission(u2(&mut rng), u2(&mut rng));
                    let n = e.normal?;
                    // The normal must be the geometric normal of the shape at the origin (up to
                    // the side for two-sided lights).
                    let ng = match &shape {
                        AreaShape::Sphere(s) => (e.ray.o - s.center).normalize(),
                        AreaShape::Disk(k) => k.normal,
                        AreaShape::Triangles(t) => {
                            (t[0][1] - t[0][0]).cross(t[0][2] - t[0][0]).normalize()
                        }
                    };
                    if n.dot(ng) < 0.0 {
                        flipped += 1;
                    }
                    if (n.dot(ng).abs() - 1.0).abs() > 1e-3 {
                        bad_normal += 1;
                    }
                    // Local direction relative to the emission normal.
                    Some(Frame::from_normal(n).to_local(e.ray.d))
                },
                |w| w.z.max(0.0) / PI,
            );
            assert!(res.passed_at(0.01 / 6.0), "{name}: {res}");
            assert_eq!(bad_normal, 0, "{name}: normal is not the surface normal");
            if two_sided {
                let f = flipped as f64 / 150_000.0;
                assert!((f - 0.5).abs() < 0.01, "{name}: back side fraction {f}");
            } else {
                assert_eq!(flipped, 0, "{name}: one-sided light emitted from its back");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Irradiance from sample_li against closed forms.

/// Estimates the irradiance at `p` with normal `n` from `n_samples` light samples.
fn irradiance(light: &Light, p: Vec3, n: Vec3, n_samples: usize, seed: u64) -> Stats {
    let mut rng = Pcg32::new(seed, 0);
    let mut st = Stats::default();
    for _ in 0..n_samples {
        let e = light
            .sample_li(p, u2(&mut rng))
            .map_or(0.0, |s| (s.weight.c[0] * s.wi.dot(n).max(0.0)) as f64);
        st.add(e);
    }
    st
}

#[test]
fn irradiance_point_light() {
    let light = Light::Point(PointLight::new(
        Vec3::new(1.0, 2.0, 3.0),
        Spectrum::splat(5.0),
    ));
    let p = Vec3::new(0.0, 0.0, 0.5);
    let n = Vec3::new(0.2, 0.5, 0.8).normalize();
    let v = Vec3::new(1.0, 2.0, 3.0) - p;
    let expected = 5.0 * n.dot(v.normalize()) / v.length_squared();
    let st = irradiance(&light, p, n, 10, 1);
    assert!((st.mean() - expected as f64).abs() < 1e-5 * expected as f64);
}

#[test]
fn irradiance_disk_on_axis() {
    let (r, d, l) = (0.8f32, 1.3f32, 3.0f32);
    let disk = Disk {
        center: Vec3::new(0.0, 0.0, d),
        normal: -Vec3::Z,
        radius: r,
    };
    let light = Light::Area(AreaLight::new(
        AreaShape::Disk(disk),
        Spectrum::splat(l),
        false,
    ));
    let expected = PI * l * r * r / (r * r + d * d);
    irradiance(&light, Vec3::ZERO, Vec3::Z, 200_000, 2).check(expected as f64, "disk");
    // The back of a one-sided disk is dark.
    let back = irradiance(&light, Vec3::new(0.0, 0.0, 2.0 * d), -Vec3::Z, 1000, 3);
    assert_eq!(back.mean(), 0.0);
}

#[test]
fn irradiance_sphere_normal_incidence() {
    let l = 2.0f32;
    for (radius, dist) in [(0.5f32, 2.0f32), (0.9, 1.0), (0.01, 3.0)] {
        let s = Sphere {
            center: Vec3::new(0.0, dist, 0.0),
            radius,
        };
        let light = Light::Area(AreaLight::new(
            AreaShape::Sphere(s),
            Spectrum::splat(l),
            false,
        ));
        let expected = PI * l * (radius / dist) * (radius / dist);
        irradiance(&light, Vec3::ZERO, Vec3::Y, 100_000, 4).check(expected as f64, "sphere");
    }
}

#[test]
fn irradiance_quad_matches_polygon_formula() {
    let l = 1.5f32;
    // Normal b × a = (0, 0.1, −0.2) faces p.
    let tris = quad(
        Vec3::new(0.2, 0.1, 1.0),
        Vec3::new(0.0, 0.4, 0.2),
        Vec3::new(0.5, 0.0, 0.0),
    );
    // Lambert's polygon formula: E = L/2 Σ_i angle(v_i, v_{i+1}) n · normalize(v_i × v_{i+1}).
    let p = Vec3::new(-0.1, 0.05, 0.0);
    let n = Vec3::new(0.1, -0.2, 1.0).normalize();
    let c = Vec3::new(0.2, 0.1, 1.0);
    let (a, b) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.0, 0.4, 0.2));
    let verts = [c - a - b, c + a - b, c + a + b, c - a + b];
    let mut sum = 0.0f64;
    for i in 0..4 {
        let v0 = (verts[i] - p).normalize().as_dvec3();
        let v1 = (verts[(i + 1) % 4] - p).normalize().as_dvec3();
        let cr = v0.cross(v1);
        sum += v0.dot(v1).clamp(-1.0, 1.0).acos() * n.as_dvec3().dot(cr.normalize());
    }
    let expected = 0.5 * l as f64 * sum.abs();
    assert!(b.cross(a).dot(p - c) > 0.0, "test setup: the quad faces p");
    let light = Light::Area(AreaLight::new(
        AreaShape::Triangles(tris.clone()),
        Spectrum::splat(l),
        false,
    ));
    irradiance(&light, p, n, 200_000, 6).check(expected, "quad");
    // Wound the other way, the one-sided quad is dark from p.
    let back: Vec<[Vec3; 3]> = tris.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let light = Light::Area(AreaLight::new(
        AreaShape::Triangles(back),
        Spectrum::splat(l),
        false,
    ));
    assert_eq!(irradiance(&light, p, n, 1000, 6).mean(), 0.0);
}

#[test]
fn irradiance_constant_environment() {
    let mut light = Light::Environment(EnvironmentLight::constant(Spectrum::splat(0.7)));
    light.preprocess(Vec3::ZERO, 1.0);
    let n = Vec3::new(0.3, -0.4, 0.5).normalize();
    irradiance(&light, Vec3::ONE, n, 200_000, 7).check((PI * 0.7) as f64, "environment");
}

#[test]
fn directional_and_beam_irradiance() {
    let dir = Vec3::new(0.0, -1.0, -1.0).normalize();
    let mut d = Light::Directional(DirectionalLight::new(dir, Spectrum::splat(4.0)));
    d.preprocess(Vec3::ZERO, 2.0);
    let s = d.sample_li(Vec3::new(0.3, 0.0, 0.1), Vec2::ZERO).unwrap();
    assert!((s.wi + dir).length() < 1e-6 && s.dist.is_infinite() && s.weight.c[0] == 4.0);

    let beam = Light::Beam(BeamLight::new(
        Vec3::new(0.0, 0.0, 5.0),
        -Vec3::Z,
        0.5,
        Spectrum::splat(3.0),
    ));
    let inside = beam
        .sample_li(Vec3::new(0.3, 0.3, 0.0), Vec2::ZERO)
        .unwrap();
    assert!((inside.wi - Vec3::Z).length() < 1e-6);
    assert!((inside.dist - 5.0).abs() < 1e-5 && inside.weight.c[0] == 3.0);
    assert!(
        beam.sample_li(Vec3::new(0.4, 0.4, 0.0), Vec2::ZERO)
            .is_none(),
        "outside radius"
    );
    assert!(
        beam.sample_li(Vec3::new(0.0, 0.0, 6.0), Vec2::ZERO)
            .is_none(),
        "behind aperture"
    );
    let e = beam.sample_emission(Vec2::new(0.9, 0.2), Vec2::ZERO);
    assert_eq!(e.normal, Some(-Vec3::Z));
    assert!((e.ray.o.z - 5.0).abs() < 1e-6 && e.ray.o.truncate().length() <= 0.5 + 1e-6);
    assert!(e.delta_dir && !e.delta_pos);
}

// ---------------------------------------------------------------------------------------------
// Power: the mean emission weight equals the power, which equals the analytic flux.

fn mean_emission_weight(light: &Light, n: usize, seed: u64) -> Stats {
    let mut rng = Pcg32::new(seed, 9);
    let mut st = Stats::default();
    for _ in 0..n {
        let e = light.sample_emission(u2(&mut rng), u2(&mut rng));
        assert!((e.ray.d.length() - 1.0).abs() < 1e-4, "unit direction");
        st.add(e.weight.c[0] as f64);
    }
    st
}

/// Power check: analytic `expected`, `power()` equal to it, mean emission weight equal to it.
fn check_power(light: &Light, expected: f64, what: &str) {
    let p = light.power().c[0] as f64;
    assert!(
        (p - expected).abs() <= 1e-4 * expected,
        "{what}: power {p} expected {expected}"
    );
    mean_emission_weight(light, 100_000, 77).check(expected, what);
}

#[test]
fn power_of_every_light() {
    let i = 2.0f64;
    let point = Light::Point(PointLight::new(Vec3::ONE, Spectrum::splat(i as f32)));
    check_power(&point, 4.0 * std::f64::consts::PI * i, "point");
    // Every point-light sample carries exactly the power.
    let st = mean_emission_weight(&point, 100, 1);
    assert!(st.sem() < 1e-9);

    let mut dl = Light::Directional(DirectionalLight::new(-Vec3::Y, Spectrum::splat(3.0)));
    dl.preprocess(Vec3::new(1.0, 2.0, 0.0), 1.5);
    check_power(&dl, std::f64::consts::PI * 1.5 * 1.5 * 3.0, "directional");
    let mut rng = Pcg32::new(2, 2);
    for _ in 0..1000 {
        let e = dl.sample_emission(u2(&mut rng), u2(&mut rng));
        let rel = e.ray.o - Vec3::new(1.0, 2.0, 0.0);
        // Starts on the disk one radius upstream: outside (or on) the bounding sphere, and the
        // ray's closest approach to the centre is within the radius.
        assert!(rel.length() >= 1.5 - 1e-4);
        assert!((rel - e.ray.d * rel.dot(e.ray.d)).length() <= 1.5 + 1e-4);
    }

    let beam = Light::Beam(BeamLight::new(
        Vec3::ZERO,
        Vec3::X,
        0.25,
        Spectrum::splat(8.0),
    ));
    check_power(&beam, std::f64::consts::PI * 0.0625 * 8.0, "beam");

    let mut env = Light::Environment(EnvironmentLight::constant(Spectrum::splat(0.5)));
    env.preprocess(Vec3::ZERO, 2.0);
    // Flux entering the bounding sphere: area 4π r² times irradiance π L.
    check_power(
        &env,
        4.0 * std::f64::consts::PI * 4.0 * std::f64::consts::PI * 0.5,
        "env",
    );

    for two_sided in [false, true] {
        let sides = if two_sided { 2.0 } else { 1.0 };
        let pi = std::f64::consts::PI;
        let le = 1.5;
        // Quad of half-sides |a| = 0.8 and |b| = sqrt(0.34): area 4 |a × b|.
        let a = Vec3::new(0.8, 0.0, 0.0);
        let b = Vec3::new(0.0, 0.5, 0.3);
        let area = 4.0 * a.cross(b).length() as f64;
        let cases = [
            (AreaShape::Triangles(quad(Vec3::ZERO, a, b)), area),
            (
                AreaShape::Sphere(Sphere {
                    center: Vec3::ONE,
                    radius: 0.5,
                }),
                4.0 * pi * 0.25,
            ),
            (
                AreaShape::Disk(Disk {
                    center: Vec3::ZERO,
                    normal: Vec3::Y,
                    radius: 0.3,
                }),
                pi * 0.09,
            ),
        ];
        for (shape, area) in cases {
            let l = Light::Area(AreaLight::new(shape, Spectrum::splat(le as f32), two_sided));
            check_power(&l, sides * pi * area * le, "area");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Spot light.

/// Mitsuba 3 falloff written independently: 1 inside `beam`, linear in angle to 0 at `cut`.
fn spot_profile(theta: f64, beam: f64, cut: f64) -> f64 {
    if theta >= cut {
        0.0
    } else if theta <= beam {
        1.0
    } else {
        (cut - theta) / (cut - beam)
    }
}

#[test]
fn spot_falloff_and_power() {
    let pos = Vec3::new(0.0, 3.0, 0.0);
    let axis = -Vec3::Y;
    let (cut, beam) = (30.0f32, 20.0f32);
    let spot = Light::Spot(SpotLight::new(pos, axis, Spectrum::splat(10.0), cut, beam));
    // Intensity toward a point at angle θ from the axis, distance 2: weight · d² = I(θ).
    let at = |deg: f32| {
        let t = deg.to_radians();
        let p = pos + 2.0 * Vec3::new(t.sin(), -t.cos(), 0.0);
        spot.sample_li(p, Vec2::ZERO)
            .map_or(0.0, |s| s.weight.c[0] * 4.0)
    };
    assert!((at(0.0) - 10.0).abs() < 1e-4);
    assert!((at(15.0) - 10.0).abs() < 1e-4);
    assert!((at(25.0) - 5.0).abs() < 1e-3, "midway: {}", at(25.0));
    assert!((at(27.5) - 2.5).abs() < 1e-3);
    assert_eq!(at(31.0), 0.0);
    assert_eq!(at(120.0), 0.0);
    // Power against a midpoint quadrature of 2π ∫ I(θ) sin θ dθ.
    let (b, c) = ((beam as f64).to_radians(), (cut as f64).to_radians());
    let m = 200_000;
    let mut sum = 0.0;
    for k in 0..m {
        let t = (k as f64 + 0.5) * c / m as f64;
        sum += spot_profile(t, b, c) * t.sin() * c / m as f64;
    }
    check_power(&spot, 2.0 * std::f64::consts::PI * 10.0 * sum, "spot");
    // Emitted directions stay in the cutoff cone.
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..1000 {
        let e = spot.sample_emission(u2(&mut rng), u2(&mut rng));
        assert!(e.ray.d.dot(axis) >= cut.to_radians().cos() - 1e-5);
        assert!(e.normal.is_none() && e.delta_pos);
    }
}

// ---------------------------------------------------------------------------------------------
// Camera.

fn camera(lens_radius: f32) -> PerspectiveCamera {
    let mut c = PerspectiveCamera::look_at(
        Vec3::new(1.0, 2.0, -3.0),
        Vec3::new(0.5, 1.5, 1.0),
        Vec3::Y,
        50.0,
        64,
        48,
    );
    c.lens_radius = lens_radius;
    c
}

#[test]
fn camera_centre_ray_and_orientation() {
    let cam = camera(0.0);
    let view = (Vec3::new(0.5, 1.5, 1.0) - Vec3::new(1.0, 2.0, -3.0)).normalize();
    let r = cam.generate_ray(Vec2::new(32.0, 24.0), Vec2::splat(0.5));
    assert!((r.ray.d - view).length() < 1e-5, "{:?}", r.ray.d);
    assert!((r.ray.d.length() - 1.0).abs() < 1e-5);
    // Not mirrored: right = view × up; a point to the right projects right of centre, a point
    // above projects above the centre (smaller raster y).
    let right = view.cross(Vec3::Y).normalize();
    let up = right.cross(view);
    let target = Vec3::new(0.5, 1.5, 1.0);
    let s = cam.sample_wi(target + right * 0.5, Vec2::ZERO).unwrap();
    assert!(
        s.raster.x > 32.0 && (s.raster.y - 24.0).abs() < 1e-3,
        "{:?}",
        s.raster
    );
    let s = cam.sample_wi(target + up * 0.5, Vec2::ZERO).unwrap();
    assert!(
        s.raster.y < 24.0 && (s.raster.x - 32.0).abs() < 1e-3,
        "{:?}",
        s.raster
    );
    // Behind the camera.
    assert!(
        cam.sample_wi(Vec3::new(1.0, 2.0, -3.0) - view, Vec2::ZERO)
            .is_none()
    );
    // Field of view: the left image edge is at 25° from the axis.
    let r = cam.generate_ray(Vec2::new(0.0, 24.0), Vec2::splat(0.5));
    assert!((r.ray.d.dot(view).acos().to_degrees() - 25.0).abs() < 1e-3);
    assert!(r.ray.d.dot(right) < 0.0);
}

#[test]
fn camera_round_trip() {
    for lens in [0.0, 0.2] {
        let cam = camera(lens);
        let mut rng = Pcg32::new(12, 0);
        for _ in 0..500 {
            let raster = Vec2::new(rng.next_f32() * 64.0, rng.next_f32() * 48.0);
            let ul = u2(&mut rng);
            let r = cam.generate_ray(raster, ul);
            let p = r.ray.at(0.5 + 8.0 * rng.next_f32());
            let s = cam.sample_wi(p, ul).expect("visible point");
            assert!(
                (s.raster - raster).length() < 2e-2,
                "lens {lens}: {:?} vs {raster:?}",
                s.raster
            );
            // The direction returned points from p back toward the lens point on the ray.
            assert!((s.wi + r.ray.d).length() < 1e-3);
            assert!((p + s.wi * s.dist - s.lens_p).length() < 1e-3);
            // Points on the focus plane project to the same pixel for any lens sample.
            if lens > 0.0 {
                let rc = cam.generate_ray(raster, Vec2::splat(0.5));
                let view = cam.to_world.transform_vector3(Vec3::Z);
                let pf = rc.ray.o + rc.ray.d * ((cam.focus_distance - 1e-4) / rc.ray.d.dot(view));
                let s2 = cam.sample_wi(pf, u2(&mut rng)).unwrap();
                assert!((s2.raster - raster).length() < 2e-2);
            }
        }
    }
}

#[test]
fn camera_ray_differentials_match_finite_differences() {
    for lens in [0.0, 0.2] {
        let cam = camera(lens);
        let mut rng = Pcg32::new(13, 0);
        for _ in 0..200 {
            let raster = Vec2::new(2.0 + rng.next_f32() * 60.0, 2.0 + rng.next_f32() * 44.0);
            let ul = u2(&mut rng);
            let r = cam.generate_ray(raster, ul);
            let h = 0.01;
            let fd = |dr: Vec2| {
                let a = cam.generate_ray(raster + dr * h, ul).ray;
                let b = cam.generate_ray(raster - dr * h, ul).ray;
                ((a.d - b.d) / (2.0 * h), (a.o - b.o) / (2.0 * h))
            };
            let (ddx, dox) = fd(Vec2::X);
            let (ddy, doy) = fd(Vec2::Y);
            let scale = r.dddx.length();
            assert!(
                (ddx - r.dddx).length() < 2e-2 * scale,
                "{ddx} vs {}",
                r.dddx
            );
            assert!(
                (ddy - r.dddy).length() < 2e-2 * scale,
                "{ddy} vs {}",
                r.dddy
            );
            // Origins start at the near clip plane: their derivatives are near_clip ∂v/∂x, tiny.
            assert!((dox - r.dodx).length() < 1e-4 && (doy - r.dody).length() < 1e-4);
            assert!(r.dodx.length() < 2.0 * cam.near_clip * scale + 1e-9);
            // One pixel ≈ 2 tan(25°)/64 rad near the centre.
            assert!(scale > 0.5 * 2.0 * 25f32.to_radians().tan() / 64.0);
        }
    }
}

/// Importance normalisation: for every pixel, ∫_lens ∫_pixel We cos θ dω dA = 1. With
/// weight = We cos θ_c / (dist² pdf_lens), this equals ∫_plane E_lens[weight] cos θ_s dA over a
/// plane covering the image, binned by pixel. A plane z = D in camera space is sampled uniformly.
#[test]
fn camera_importance_integrates_to_one_per_pixel() {
    for lens in [0.0, 0.3] {
        let mut cam = camera(lens);
        cam.width = 8;
        cam.height = 6;
        cam.focus_distance = 3.0;
        let depth = 4.0f32;
        // Half-extent large enough to cover the frustum from every lens point.
        let hx = depth * 25f32.to_radians().tan() + lens + 0.1;
        let hy = hx;
        let area = 4.0 * hx * hy;
        let n = 400_000;
        let mut rng = Pcg32::new(21, 0);
        let mut sums = vec![Stats::default(); 48];
        for _ in 0..n {
            let pc = Vec3::new(
                (2.0 * rng.next_f32() - 1.0) * hx,
                (2.0 * rng.next_f32() - 1.0) * hy,
                depth,
            );
            let p = cam.to_world.transform_point3(pc);
            let nrm = cam.to_world.transform_vector3(Vec3::Z);
            let mut contrib = vec![0.0f64; 48];
            if let Some(s) = cam.sample_wi(p, u2(&mut rng)) {
                let pix = s.raster.y as usize * 8 + s.raster.x as usize;
                contrib[pix] = (s.weight.c[0] * s.wi.dot(nrm).abs() * area) as f64;
            }
            for (st, c) in sums.iter_mut().zip(contrib) {
                st.add(c);
            }
        }
        for (i, st) in sums.iter().enumerate() {
            st.check(1.0, &format!("lens {lens} pixel {i}"));
            assert!(st.sem() < 0.05);
        }
    }
}

#[test]
fn collimated_lights_report_the_direction_they_emit() {
    // Photon differentials reuse one emission basis per light only when the emitted ray's
    // direction and normal equal `fixed_emission_direction` exactly.
    let mut d = Light::Directional(DirectionalLight::new(
        Vec3::new(0.3, -1.0, -0.2).normalize(),
        Spectrum::splat(1.0),
    ));
    d.preprocess(Vec3::new(1.0, 2.0, 3.0), 4.0);
    let beam = Light::Beam(BeamLight::new(
        Vec3::new(0.0, 1.0, 5.0),
        Vec3::new(0.1, 0.2, -1.0),
        0.5,
        Spectrum::splat(3.0),
    ));
    let mut rng = Pcg32::new(3, 3);
    for light in [&d, &beam] {
        let (dir, normal) = light.fixed_emission_direction().expect("collimated");
        for _ in 0..100 {
            let es = light.sample_emission(u2(&mut rng), u2(&mut rng));
            assert_eq!(es.ray.d, dir);
            assert_eq!(es.normal, normal);
        }
    }
    let point = Light::Point(PointLight::new(Vec3::ZERO, Spectrum::splat(1.0)));
    assert!(point.fixed_emission_direction().is_none());
}

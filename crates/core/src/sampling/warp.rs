//! Warping functions from the unit square to common domains, each with its density.
//!
//! Densities are with respect to the natural measure of the target domain: solid angle (sr⁻¹)
//! for directions, area (m⁻²) for surfaces.

use crate::{INV_2PI, INV_4PI, INV_PI, PI};
use glam::{Vec2, Vec3};

/// Concentric mapping of the square to the unit disk (Shirley & Chiu 1997).
#[inline]
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // θ = π/4 · (y / x) around x, π/2 − π/4 · (x / y) around y, from one quotient of the chosen
    // operands. The choice is a coin flip for the CPU: written as a choice between the two
    // quotients it compiled to a branch around each division, mispredicted about half the time
    // (callgrind's branch simulation, docs/performance.md, issue 26, sixteenth session), so it
    // is made by selects the compiler is told not to turn into branches. The same bits as the
    // two quotients (the path tracer's lanes compute it the same way).
    use std::hint::select_unpredictable as pick;
    let around_x = o.x.abs() > o.y.abs();
    let r = pick(around_x, o.x, o.y);
    let quarter = 0.25 * PI * (pick(around_x, o.y, o.x) / pick(around_x, o.x, o.y));
    let theta = pick(around_x, quarter, 0.5 * PI - quarter);
    Vec2::new(r * theta.cos(), r * theta.sin())
}

/// Density of [`square_to_disk_concentric`] on the unit disk (1/π).
#[inline]
pub fn disk_pdf(p: Vec2) -> f32 {
    if p.length_squared() <= 1.0 {
        INV_PI
    } else {
        0.0
    }
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method).
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`]: cos θ / π.
#[inline]
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z > 0.0 { w.z * INV_PI } else { 0.0 }
}

/// Uniform direction on the unit sphere.
#[inline]
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_sphere`]: 1/(4π).
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// Uniform direction on the +z hemisphere.
#[inline]
pub fn square_to_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_hemisphere`]: 1/(2π).
#[inline]
pub fn uniform_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z > 0.0 { INV_2PI } else { 0.0 }
}

/// Uniform direction inside the cone around +z with `cos θ ≥ cos_max`.
#[inline]
pub fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let z = 1.0 - u.x * (1.0 - cos_max);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_cone`]: 1 / (2π (1 − cos θ_max)).
#[inline]
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Uniform barycentrics `(b1, b2)` on a triangle (Heitz 2019, low-distortion map);
/// the point is `(1 − b1 − b2) p0 + b1 p1 + b2 p2`.
#[inline]
pub fn square_to_uniform_triangle(u: Vec2) -> Vec2 {
    // The smaller coordinate s maps to s/2 and the larger l to l − s/2, in whichever of b0, b1
    // the coordinate stands for. The choice is a select the compiler is told not to make a
    // branch: the comparison is a coin flip, and a mispredicted branch cost more than the whole
    // map (light sampling). (A bit mask was not enough: the compiler turned it back into a
    // branch, which callgrind's branch simulation caught in the sixteenth session.)
    let below = u.x < u.y;
    let pick = |a: f32, b: f32| std::hint::select_unpredictable(below, a, b);
    let (s, l) = (pick(u.x, u.y), pick(u.y, u.x));
    let h = s / 2.0;
    let m = l - h;
    let (b0, b1) = (pick(h, m), pick(m, h));
    Vec2::new(b1, 1.0 - b0 - b1)
}

/// Power heuristic with β = 2 (Veach 1997) for MIS weights.
#[inline]
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a == 0.0 && b == 0.0 {
        0.0
    } else if a.is_infinite() {
        1.0
    } else {
        a / (a + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chi2::{ChiSquareTest, SphericalDomain};
    use crate::sampling::Pcg32;

    fn run(sample: impl Fn(Vec2) -> Vec3, pdf: impl Fn(Vec3) -> f32, name: &str) {
        let mut rng = Pcg32::new(11, 0);
        let t = ChiSquareTest::new(SphericalDomain::default(), 200_000);
        let res = t.run(
            || {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                Some(sample(u))
            },
            pdf,
        );
        assert!(res.passed(), "{name}: {res}");
    }

    #[test]
    fn chi2_cosine_hemisphere() {
        run(
            square_to_cosine_hemisphere,
            cosine_hemisphere_pdf,
            "cosine hemisphere",
        );
    }
    #[test]
    fn chi2_uniform_sphere() {
        run(
            square_to_uniform_sphere,
            |_| uniform_sphere_pdf(),
            "uniform sphere",
        );
    }
    #[test]
    fn chi2_uniform_cone() {
        let c = 0.7f32;
        run(
            |u| square_to_uniform_cone(u, c),
            |w| if w.z >= c { uniform_cone_pdf(c) } else { 0.0 },
            "cone",
        );
    }
    #[test]
    fn triangle_barycentrics_are_inside() {
        let mut rng = Pcg32::new(3, 0);
        let mut mean = Vec2::ZERO;
        let n = 100_000;
        for _ in 0..n {
            let b = square_to_uniform_triangle(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            mean += b / n as f32;
        }
        // Centroid of a uniform triangle is (1/3, 1/3); std of b is sqrt(1/18), error < 5σ/√n.
        assert!(
            (mean - Vec2::splat(1.0 / 3.0)).abs().max_element()
                < 5.0 * (1.0f32 / 18.0).sqrt() / (n as f32).sqrt()
        );
    }
}

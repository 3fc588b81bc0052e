//! The 4-D position × direction kernel of photon cone focusing (seed 001 sec. 3.1) and its
//! progressive bandwidth (sec. 3.4).
//!
//! A box over a disc of radius σ times a box over a spherical cap of half-angle t (eq. 3.3–3.4):
//!
//! ```text
//! K_σ(x′ − x, ω′ − ω) = 1/C_σ  if ‖x′ − x‖ < σ and ∠(ω′, ω) < t(σ),   else 0,
//! C_σ = π σ² · 2π (1 − cos t(σ))                                     (eq. 3.5–3.6)
//! ```
//!
//! in m²·sr: the disc's area times the cap's solid angle (plain solid angle, not projected).
//! The spatial test is a 3-D distance (a ball around the query meets a surface in a disc) and
//! the normalisation is C_σ everywhere, even where the disc leaves the surface or the cap dips
//! below the horizon: seed 001's estimator, whose boundary bias sec. 5.3.3 shows (spec notes
//! Q11). The name is the spec notes' (Q18): seed 003's "cone" filter is another thing.
//!
//! The angular bandwidth follows the spatial one through t(σ) = θ₁ (σ/σ₁)^p, the simplest
//! polynomial of order p with t(σ₁) = θ₁ (eq. 3.7 and Lemma 3.3 ask for order p ≥ 1; the form
//! is the spec notes' reading of Table 4.1, Q1 [INF]), and the kernel volume C_σ shrinks by
//! eq. 3.27, C_{σ_{i+1}} = C_{σ_i} (i + α)/(i + 1), from the closed-form Γ product of
//! [`BandwidthSchedule`] (σ_i solved by bisection, t_i = t(σ_i)).

use caustica_core::{INV_PI, Vec3};
use caustica_density::{BandwidthSchedule, KernelVolume, ScheduleError};
use std::f64::consts::PI;
use std::sync::Arc;

/// The solid angle of a spherical cap of half-angle `t` (rad): 2π(1 − cos t), written
/// 4π sin²(t/2) so it stays accurate for small t.
pub fn cap_solid_angle(t: f64) -> f64 {
    let s = (0.5 * t).sin();
    4.0 * PI * s * s
}

/// t(σ) = θ₁ (σ/σ₁)^p: the angular bandwidth (rad) of spatial bandwidth σ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngularMap {
    /// σ₁ (m).
    pub sigma1: f64,
    /// θ₁ (rad), in (0, π].
    pub theta1: f64,
    /// The order p ≥ 1.
    pub order: f64,
}

impl AngularMap {
    /// t(σ) (rad).
    pub fn t(&self, sigma: f64) -> f64 {
        self.theta1 * (sigma / self.sigma1).powf(self.order)
    }

    /// The kernel volume C_σ = πσ² · 2π(1 − cos t(σ)) (m² sr), eq. 3.6.
    pub fn volume(&self, sigma: f64) -> f64 {
        PI * sigma * sigma * cap_solid_angle(self.t(sigma))
    }
}

/// One iteration's kernel: spatial radius σ (m) and cap half-angle t (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskCapKernel {
    /// σ (m).
    pub sigma: f32,
    /// t(σ) (rad).
    pub theta: f32,
    /// cos t: a direction ω′ is inside the cap around ω when ω′·ω > cos t.
    pub cos_theta: f32,
    /// 1/C_σ (m⁻² sr⁻¹).
    pub inv_volume: f32,
}

impl DiskCapKernel {
    pub fn new(sigma: f64, theta: f64) -> Self {
        let volume = PI * sigma * sigma * cap_solid_angle(theta);
        Self {
            sigma: sigma as f32,
            theta: theta as f32,
            cos_theta: theta.cos() as f32,
            inv_volume: (1.0 / volume) as f32,
        }
    }

    /// C_σ (m² sr).
    pub fn volume(&self) -> f64 {
        1.0 / self.inv_volume as f64
    }

    /// The factor that turns a sum of cone values times [`Aperture::weight`] into the kernel
    /// estimate (m⁻² sr⁻¹ for `Cap`: 1/C_σ; m⁻² for `Cosine`, whose weight is already per sr:
    /// 1/(πσ²)).
    #[inline]
    pub fn scale(&self, aperture: &Aperture) -> f32 {
        match aperture {
            Aperture::Cap(_) => self.inv_volume,
            Aperture::Cosine(_) => 1.0 / (std::f32::consts::PI * self.sigma * self.sigma),
        }
    }

    /// True if a cone at squared distance `d2` (m²) lies in the kernel's disc (eq. 3.3; a 3-D
    /// distance, so a ball around the query).
    #[inline]
    pub fn in_disc(&self, d2: f32) -> bool {
        d2 < self.sigma * self.sigma
    }

    /// The kernel's value for a cone at squared distance `d2` leaving in the unit direction
    /// `dir`, under `aperture` (m⁻² sr⁻¹): the disc test, the aperture's direction weight and
    /// the scale, the three parts [`super::PhotonConeMap::estimate`] applies (it sums the
    /// weighted values and scales once).
    #[inline]
    pub fn eval(&self, aperture: &Aperture, d2: f32, dir: Vec3) -> f32 {
        if self.in_disc(d2) {
            aperture.weight(self, dir) * self.scale(aperture)
        } else {
            0.0
        }
    }
}

/// The direction part of a lookup's kernel.
///
/// `Cap` is seed 001's box over a cap (eq. 3.4). `Cosine` is for a lookup on a Lambertian
/// surface, whose outgoing radiance does not depend on the direction (seed 001 sec. 4.4: "the
/// properties of surface material can be taken into account when deciding θ₁ … larger ones for
/// rough/diffusive BSDFs", taken to its end): the whole hemisphere the query looks at, weighted
/// by the projected solid angle, cos θ_j/π (sr⁻¹, integrating to 1 over the hemisphere). It adds
/// no angular bias where L_o is constant in ω, every cone within σ counts, and the weight
/// cancels the 1/cos θ_j of a cone drawn by cosine-weighted BSDF sampling (β·(ρ/π)/(cos θ_j/π)),
/// so such a cone adds exactly β ρ/π: photon mapping at r = σ (docs/pcf.md, "Lambertian lookups").
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aperture {
    /// The cap of half-angle t(σ) around the unit query direction ω (eq. 3.4).
    Cap(Vec3),
    /// The hemisphere around the unit normal `n` (oriented towards the query direction),
    /// weighted by cos θ/π.
    Cosine(Vec3),
}

impl Aperture {
    /// The direction weight of a cone leaving in the unit direction `dir` (sr⁻¹), times the
    /// cap's solid angle for `Cap` (1 inside, 0 outside; [`DiskCapKernel::scale`] divides by
    /// it).
    #[inline]
    pub fn weight(&self, k: &DiskCapKernel, dir: Vec3) -> f32 {
        match *self {
            Aperture::Cap(w) => {
                if dir.dot(w) > k.cos_theta {
                    1.0
                } else {
                    0.0
                }
            }
            Aperture::Cosine(n) => dir.dot(n).max(0.0) * INV_PI,
        }
    }
}

/// The kernels of a `pcf` render: iteration i's (σ_i, t(σ_i)) by eq. 3.27.
#[derive(Clone, Debug)]
pub struct ConeSchedule {
    map: AngularMap,
    schedule: BandwidthSchedule,
}

impl ConeSchedule {
    /// The schedule from σ₁ (m), θ₁ (rad), order p and α.
    pub fn new(sigma1: f64, theta1: f64, order: f64, alpha: f64) -> Result<Self, ScheduleError> {
        let map = AngularMap {
            sigma1,
            theta1,
            order,
        };
        let schedule = BandwidthSchedule::new(
            sigma1,
            alpha,
            KernelVolume::Custom(Arc::new(move |s| map.volume(s))),
        )?;
        Ok(Self { map, schedule })
    }

    /// Iteration `i`'s kernel (i ≥ 1).
    pub fn kernel(&self, i: u64) -> DiskCapKernel {
        let sigma = self.schedule.bandwidth(i);
        DiskCapKernel::new(sigma, self.map.t(sigma))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::rng::Pcg32;

    #[test]
    fn kernel_integrates_to_one_over_disc_times_cap() {
        // T-1: Monte Carlo over a square × the sphere: ∫∫ K dA dω = 1 (eq. 3.2, 3.5).
        for theta_deg in [1.0f64, 18.0, 60.0, 179.0] {
            let k = DiskCapKernel::new(0.1, theta_deg.to_radians());
            let mut rng = Pcg32::new(7, theta_deg as u64);
            let n = 2_000_000;
            let mut sum = 0.0f64;
            // Directions uniform on the sphere (pdf 1/4π), positions uniform on [−σ, σ]²
            // (pdf 1/(4σ²)); the cap is around +z. For small caps, sample directions uniformly
            // in a cap of twice the angle instead (pdf 1/Ω(2t)).
            let wide = (2.0 * theta_deg).min(180.0).to_radians();
            let cos_w = wide.cos();
            let omega_w = cap_solid_angle(wide);
            for _ in 0..n {
                let (x, y) = (
                    (2.0 * rng.next_f32() - 1.0) * 0.1,
                    (2.0 * rng.next_f32() - 1.0) * 0.1,
                );
                let z = 1.0 - rng.next_f32() as f64 * (1.0 - cos_w);
                let phi = 2.0 * PI * rng.next_f32() as f64;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let dir = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                sum += k.eval(&Aperture::Cap(Vec3::Z), x * x + y * y, dir) as f64
                    * (0.04 * omega_w as f32) as f64;
            }
            let est = sum / n as f64;
            assert!((est - 1.0).abs() < 3e-3, "theta {theta_deg}: {est}");
            // C_σ to floating-point precision, and the cap solid angle by quadrature.
            let c = PI * 0.01 * 2.0 * PI * (1.0 - theta_deg.to_radians().cos());
            assert!((k.volume() / c - 1.0).abs() < 1e-6);
            let m = 100_000;
            let t = theta_deg.to_radians();
            let quad: f64 = (0..m)
                .map(|j| {
                    let th = (j as f64 + 0.5) / m as f64 * t;
                    2.0 * PI * th.sin() * t / m as f64
                })
                .sum();
            assert!((quad / cap_solid_angle(t) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn cosine_aperture_integrates_to_one_over_the_disc_and_the_viewed_hemisphere() {
        // ∫∫ K dA dω = 1 for the cosine aperture too (Monte Carlo over the square [−σ, σ]² ×
        // the sphere, through `eval`, the estimator's parts), nothing below the horizon, and
        // the cap's direction weight is its indicator.
        let k = DiskCapKernel::new(0.1, 0.3);
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        let cosine = Aperture::Cosine(n);
        let mut rng = Pcg32::new(3, 1);
        let m = 2_000_000;
        let (mut sum, mut below, mut cap) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..m {
            let (x, y) = (
                (2.0 * rng.next_f32() - 1.0) * 0.1,
                (2.0 * rng.next_f32() - 1.0) * 0.1,
            );
            // Uniform on the sphere (pdf 1/4π).
            let z = 1.0 - 2.0 * rng.next_f32();
            let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            let v = k.eval(&cosine, x * x + y * y, d) as f64;
            sum += v;
            if d.dot(n) < 0.0 {
                below += v;
            }
            cap += Aperture::Cap(n).weight(&k, d) as f64;
        }
        let measure = 0.04 * 4.0 * PI / m as f64;
        assert!((sum * measure - 1.0).abs() < 5e-3, "{}", sum * measure);
        assert_eq!(below, 0.0);
        let omega = cap * 4.0 * PI / m as f64;
        assert!((omega / cap_solid_angle(0.3) - 1.0).abs() < 2e-2, "{omega}");
    }

    #[test]
    fn schedule_follows_eq_3_27_and_the_spec_table() {
        // T-2: g(σ_{i+1})/g(σ_i) = (i + α)/(i + 1) over 10⁴ iterations, σ decreasing, t → 0.
        let s = ConeSchedule::new(0.1, 18f64.to_radians(), 1.0, 0.2).unwrap();
        let mut prev = s.kernel(1);
        assert!((prev.sigma - 0.1).abs() < 1e-7);
        for i in 1..10_000u64 {
            let next = s.kernel(i + 1);
            let ratio = prev.volume() / next.volume();
            let want = (i as f64 + 1.0) / (i as f64 + 0.2);
            assert!(
                (ratio / want - 1.0).abs() < 1e-4,
                "i {i}: {ratio} vs {want}"
            );
            assert!(next.sigma < prev.sigma && next.theta < prev.theta);
            prev = next;
        }
        // The spec notes' table (sec. 2.5): σ_i / t(σ_i) with σ₁ = 0.1, θ₁ = 18°.
        for (alpha, p, rows) in [
            (
                0.2,
                1.0,
                [(2, 0.0880, 15.8), (10, 0.0643, 11.6), (1000, 0.0256, 4.61)],
            ),
            (
                0.2,
                2.0,
                [(2, 0.0918, 15.2), (100, 0.0548, 5.41), (4000, 0.0335, 2.02)],
            ),
            (
                0.5,
                1.0,
                [(2, 0.0930, 16.7), (100, 0.0579, 10.4), (4000, 0.0365, 6.57)],
            ),
        ] {
            let s = ConeSchedule::new(0.1, 18f64.to_radians(), p, alpha).unwrap();
            for (i, sigma, deg) in rows {
                let k = s.kernel(i);
                assert!(
                    (k.sigma as f64 - sigma).abs() < 6e-4,
                    "alpha {alpha} p {p} i {i}: sigma {}",
                    k.sigma
                );
                assert!(
                    ((k.theta as f64).to_degrees() - deg).abs() < 0.06,
                    "alpha {alpha} p {p} i {i}: t {}",
                    (k.theta as f64).to_degrees()
                );
            }
        }
        // The log-log slope of σ_i over the last decade: (α − 1)/(2p + 2) for small t.
        for (alpha, p) in [(0.2, 1.0), (0.5, 2.0)] {
            let s = ConeSchedule::new(0.1, 18f64.to_radians(), p, alpha).unwrap();
            let slope =
                (s.kernel(10_000).sigma as f64 / s.kernel(1000).sigma as f64).ln() / 10f64.ln();
            let want = (alpha - 1.0) / (2.0 * p + 2.0);
            assert!((slope - want).abs() < 1e-2, "{slope} vs {want}");
        }
    }

    #[test]
    fn bad_schedule_values_are_errors() {
        assert!(ConeSchedule::new(0.0, 0.3, 1.0, 0.5).is_err());
        assert!(ConeSchedule::new(0.1, 0.3, 1.0, 0.0).is_err());
    }
}

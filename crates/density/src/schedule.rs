//! The progressive bandwidth schedule shared by every progressive method (PPPM, progressive
//! photon differential splatting, and photon cone focusing next): seed 001 eq. 3.27,
//!
//! ```text
//! Var[ε_{i+1}] / Var[ε_i] = V(h_i) / V(h_{i+1}) = (i + 1) / (i + α),   0 < α ≤ 1, i = 1, 2, …
//! ```
//!
//! where `V(h)` is the volume of the kernel's support at bandwidth `h` (the per-iteration
//! variance of a density estimate is ∝ 1/V). With `V(r) = π r²` this is Knaus and Zwicker's
//! (2011) `r²_{i+1} = r²_i (i + α)/(i + 1)`; with `V(s) = s²` the rule for photon differential
//! footprints, whose area is ∝ s² (seed 002 eq. 4).
//!
//! The volume of iteration `i` is taken from the closed form of the product (spec notes
//! sec. 2.5, [CHK]),
//!
//! ```text
//! V(h_i) = V(h_1) Π_{k=1}^{i−1} (k + α)/(k + 1) = V(h_1) Γ(i + α) / (Γ(1 + α) Γ(i + 1)),
//! ```
//!
//! evaluated with `ln Γ`, rather than by chaining ratios, and `h_i` is the root of
//! `V(h) = V(h_i)` (in closed form for the power-law volumes, by bisection otherwise: `V` is
//! increasing). So iteration `i`'s bandwidth depends on `i` alone: a resumed or sharded
//! render computes it without replaying the schedule. `α = 1` keeps the bandwidth fixed (no
//! shrinking: the average of independent renders at `h_1`); as `α → 0` the volume falls like
//! `1/i` and the variance of the average never vanishes, so `α` must lie in `(0, 1]`.

use std::fmt;
use std::sync::Arc;

/// The support volume `V(h)` of a kernel as a function of its bandwidth `h` (any unit; only
/// ratios matter). Must be increasing in `h`.
#[derive(Clone)]
pub enum KernelVolume {
    /// `V = c h^d`: a disc (`d = 2`, PPPM's `π r²`), a ball (`d = 3`), a footprint area
    /// (`d = 2`). Solved in closed form.
    Power { d: f64 },
    /// Any increasing function (photon cone focusing's `2π² σ² (1 − cos t(σ))`, seed 001
    /// eq. 3.6); solved by bisection on `(0, h_1]`.
    Custom(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
}

impl fmt::Debug for KernelVolume {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KernelVolume::Power { d } => write!(f, "Power {{ d: {d} }}"),
            KernelVolume::Custom(_) => write!(f, "Custom(..)"),
        }
    }
}

impl KernelVolume {
    /// A 2-D kernel (disc or footprint area, `V ∝ h²`).
    pub const AREA: KernelVolume = KernelVolume::Power { d: 2.0 };
    /// A 3-D kernel (`V ∝ h³`).
    pub const BALL: KernelVolume = KernelVolume::Power { d: 3.0 };

    fn eval(&self, h: f64) -> f64 {
        match self {
            KernelVolume::Power { d } => h.powf(*d),
            KernelVolume::Custom(v) => v(h),
        }
    }
}

/// Errors of a schedule's parameters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScheduleError {
    #[error(
        "alpha must lie in (0, 1] (seed 001 sec. 3.5.3: at 0 the variance never vanishes, above 1 the bandwidth grows), got {0}"
    )]
    Alpha(f64),
    #[error("the initial bandwidth must be a finite number > 0, got {0}")]
    Bandwidth(f64),
}

/// Bandwidths `h_1, h_2, …` of a progressive render (seed 001 eq. 3.27; iterations count
/// from 1 as in the seed).
#[derive(Clone, Debug)]
pub struct BandwidthSchedule {
    alpha: f64,
    h1: f64,
    volume: KernelVolume,
}

impl BandwidthSchedule {
    /// A schedule starting at `h1` whose kernel volume `volume` shrinks by eq. 3.27 with `alpha`.
    pub fn new(h1: f64, alpha: f64, volume: KernelVolume) -> Result<Self, ScheduleError> {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(ScheduleError::Alpha(alpha));
        }
        if !(h1.is_finite() && h1 > 0.0) {
            return Err(ScheduleError::Bandwidth(h1));
        }
        Ok(Self { alpha, h1, volume })
    }

    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// `V(h_i)/V(h_1) = Γ(i + α) / (Γ(1 + α) Γ(i + 1))` for iteration `i ≥ 1` (1 at `i = 1`;
    /// `i = 0` is read as 1).
    pub fn volume_ratio(&self, i: u64) -> f64 {
        let i = i.max(1) as f64;
        let a = self.alpha;
        if a == 1.0 {
            return 1.0;
        }
        (libm::lgamma(i + a) - libm::lgamma(1.0 + a) - libm::lgamma(i + 1.0)).exp()
    }

    /// The bandwidth of iteration `i ≥ 1`.
    pub fn bandwidth(&self, i: u64) -> f64 {
        let ratio = self.volume_ratio(i);
        match &self.volume {
            KernelVolume::Power { d } => self.h1 * ratio.powf(1.0 / d),
            KernelVolume::Custom(_) => {
                let target = self.volume.eval(self.h1) * ratio;
                // V is increasing: bisection on (0, h1] to f64 resolution.
                let (mut lo, mut hi) = (0.0f64, self.h1);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if self.volume.eval(mid) < target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                0.5 * (lo + hi)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(h1: f64, alpha: f64) -> BandwidthSchedule {
        BandwidthSchedule::new(h1, alpha, KernelVolume::AREA).unwrap()
    }

    #[test]
    fn each_step_is_the_ratio_of_eq_3_27() {
        // V(h_{i+1}) / V(h_i) = (i + α)/(i + 1), i.e. PPPM's r²_{i+1} = r²_i (i + α)/(i + 1).
        for alpha in [0.2, 0.5, 2.0 / 3.0, 0.7, 0.95] {
            let s = area(0.05, alpha);
            for i in [1u64, 2, 3, 10, 99, 1000, 123_456] {
                let (a, b) = (s.bandwidth(i), s.bandwidth(i + 1));
                let ratio = (b * b) / (a * a);
                let want = (i as f64 + alpha) / (i as f64 + 1.0);
                assert!(
                    (ratio / want - 1.0).abs() < 1e-9,
                    "alpha {alpha}, i {i}: {ratio} vs {want}"
                );
            }
        }
    }

    #[test]
    fn closed_form_agrees_with_the_chained_product() {
        let s = area(1.0, 2.0 / 3.0);
        let mut chained = 1.0f64;
        for i in 1..=10_000u64 {
            let v = s.volume_ratio(i);
            assert!((v / chained - 1.0).abs() < 1e-9, "i {i}: {v} vs {chained}");
            chained *= (i as f64 + 2.0 / 3.0) / (i as f64 + 1.0);
        }
        // And the asymptote V_i/V_1 ~ i^{α−1}/Γ(1+α) of the spec notes (sec. 2.5).
        let i = 1.0e6f64;
        let asym = i.powf(2.0 / 3.0 - 1.0) / libm::tgamma(1.0 + 2.0 / 3.0);
        assert!((s.volume_ratio(1_000_000) / asym - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_spec_notes_table_values() {
        // Spec notes sec. 2.5: C_{σ_4000}/C_{σ_1} is 1.43e-3 at α = 0.2, 1.78e-2 at 0.5 and
        // 6.98e-2 at 2/3 (independent of the kernel volume's form).
        for (alpha, want) in [(0.2, 1.43e-3), (0.5, 1.78e-2), (2.0 / 3.0, 6.98e-2)] {
            let got = area(1.0, alpha).volume_ratio(4000);
            assert!((got / want - 1.0).abs() < 5e-3, "alpha {alpha}: {got}");
        }
    }

    #[test]
    fn alpha_one_keeps_the_bandwidth_and_iteration_one_is_h1() {
        let s = area(0.3, 1.0);
        for i in [1u64, 2, 1000, u64::MAX] {
            assert_eq!(s.bandwidth(i), 0.3);
        }
        assert_eq!(area(0.3, 0.5).bandwidth(1), 0.3);
        assert_eq!(area(0.3, 0.5).bandwidth(0), 0.3);
    }

    #[test]
    fn custom_volume_is_solved_by_bisection() {
        // A cone-like volume V = σ²(1 − cos(θ₁ σ/σ₁)) (seed 001 eq. 3.6 with p = 1).
        let (s1, t1) = (0.1f64, 18f64.to_radians());
        let v = move |s: f64| s * s * (1.0 - (t1 * s / s1).cos());
        let s = BandwidthSchedule::new(s1, 0.2, KernelVolume::Custom(Arc::new(v))).unwrap();
        // The spec notes' table (α = 0.2, p = 1): σ_10 = 0.0643, σ_1000 = 0.0256.
        assert!(
            (s.bandwidth(10) - 0.0643).abs() < 1e-4,
            "{}",
            s.bandwidth(10)
        );
        assert!((s.bandwidth(1000) - 0.0256).abs() < 1e-4);
        for i in [2u64, 50, 4000] {
            let got = v(s.bandwidth(i)) / v(s1);
            assert!((got / s.volume_ratio(i) - 1.0).abs() < 1e-9);
        }
        // A power-law volume through the generic path gives the closed form.
        let p = BandwidthSchedule::new(0.2, 0.6, KernelVolume::Custom(Arc::new(|h| h * h * h)))
            .unwrap();
        let q = BandwidthSchedule::new(0.2, 0.6, KernelVolume::BALL).unwrap();
        assert!((p.bandwidth(77) / q.bandwidth(77) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_refused() {
        for a in [0.0, -0.1, 1.01, f64::NAN] {
            assert!(matches!(
                BandwidthSchedule::new(1.0, a, KernelVolume::AREA),
                Err(ScheduleError::Alpha(_))
            ));
        }
        for h in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            assert!(matches!(
                BandwidthSchedule::new(h, 0.5, KernelVolume::AREA),
                Err(ScheduleError::Bandwidth(_))
            ));
        }
    }
}

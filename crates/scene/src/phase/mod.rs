//! Phase functions of participating media: the angular distribution of light scattered at a
//! point in a medium (seed 000 eq. 8.1, the `p` of the in-scattering integral).
//!
//! Conventions (the same as the BSDFs', [`crate::bsdf`]): directions are unit vectors in world
//! space, both pointing *away* from the scattering point — `wo` toward the viewer (or the
//! previous vertex), `wi` toward the light (or the next vertex). Light travelling along `−wi`
//! and leaving along `wo` is scattered by the angle θ with cos θ = −wo·wi; "forward
//! scattering" is `wi = −wo`. Phase functions are normalised over the sphere
//! (∫ p dω = 1, unit sr⁻¹) and reciprocal, so radiance and importance use the same `p`.
//!
//! * [`Isotropic`] — p = 1/(4π).
//! * [`HenyeyGreenstein`] — one-parameter lobe with mean cosine `g` ∈ (−1, 1).

pub mod henyey_greenstein;
pub mod isotropic;

pub use henyey_greenstein::HenyeyGreenstein;
pub use isotropic::Isotropic;

use caustica_core::{Vec2, Vec3};

/// A direction sampled from a phase function.
#[derive(Clone, Copy, Debug)]
pub struct PhaseSample {
    /// Unit direction toward the next vertex (world space).
    pub wi: Vec3,
    /// Solid-angle density of `wi` (sr⁻¹).
    pub pdf: f32,
    /// p(wo, wi)/pdf (dimensionless): 1 for the exactly sampled phase functions here.
    pub weight: f32,
}

/// What every phase function offers.
pub trait Phase {
    /// p(wo, wi) (sr⁻¹).
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Samples `wi` given `wo` from two uniform numbers.
    fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample>;
    /// Density of [`Phase::sample`] (sr⁻¹).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
}

/// The phase functions of caustica, dispatched statically.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseFunction {
    Isotropic(Isotropic),
    HenyeyGreenstein(HenyeyGreenstein),
}

impl Default for PhaseFunction {
    fn default() -> Self {
        PhaseFunction::Isotropic(Isotropic)
    }
}

impl PhaseFunction {
    /// Henyey–Greenstein with mean cosine `g`; `g` must lie in (−1, 1) (an error message naming
    /// the value otherwise). `g = 0` is isotropic.
    pub fn henyey_greenstein(g: f32) -> Result<Self, String> {
        HenyeyGreenstein::new(g).map(PhaseFunction::HenyeyGreenstein)
    }
    /// Mean cosine of the scattering angle (0 for isotropic).
    pub fn mean_cosine(&self) -> f32 {
        match self {
            PhaseFunction::Isotropic(_) => 0.0,
            PhaseFunction::HenyeyGreenstein(hg) => hg.g,
        }
    }
}

impl Phase for PhaseFunction {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            PhaseFunction::Isotropic(p) => p.eval(wo, wi),
            PhaseFunction::HenyeyGreenstein(p) => p.eval(wo, wi),
        }
    }
    #[inline]
    fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        match self {
            PhaseFunction::Isotropic(p) => p.sample(wo, u),
            PhaseFunction::HenyeyGreenstein(p) => p.sample(wo, u),
        }
    }
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            PhaseFunction::Isotropic(p) => p.pdf(wo, wi),
            PhaseFunction::HenyeyGreenstein(p) => p.pdf(wo, wi),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::chi2::{ChiSquareTest, SphericalDomain};
    use caustica_core::sampling::Pcg32;

    fn phases() -> Vec<PhaseFunction> {
        let mut v = vec![PhaseFunction::Isotropic(Isotropic)];
        for g in [-0.7, -0.3, 0.0, 0.3, 0.6, 0.9] {
            v.push(PhaseFunction::henyey_greenstein(g).unwrap());
        }
        v
    }

    fn wo_cases() -> [Vec3; 3] {
        [
            Vec3::Z,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(-0.9, 0.1, -0.2).normalize(),
        ]
    }

    #[test]
    fn sampling_matches_the_density_chi2() {
        let tests = (phases().len() * wo_cases().len()) as f64;
        for (i, phase) in phases().iter().enumerate() {
            for (j, wo) in wo_cases().into_iter().enumerate() {
                let mut rng = Pcg32::new(17 + i as u64, j as u64);
                // Fine in cos θ: at g = 0.9 the lobe varies on a scale of (1 − g)² = 0.01.
                let dom = SphericalDomain {
                    cos_bins: 200,
                    phi_bins: 40,
                    integration_res: 12,
                };
                let t = ChiSquareTest::new(dom, 400_000);
                let r = t.run(
                    || {
                        let u = Vec2::new(rng.next_f32(), rng.next_f32());
                        phase.sample(wo, u).map(|s| s.wi)
                    },
                    |wi| phase.pdf(wo, wi),
                );
                assert!(r.passed_at(0.01 / tests), "{phase:?} wo {wo}: {r}");
            }
        }
    }

    #[test]
    fn densities_integrate_to_one_and_eval_equals_pdf() {
        for phase in phases() {
            for wo in wo_cases() {
                let dom = SphericalDomain {
                    cos_bins: 200,
                    phi_bins: 100,
                    integration_res: 8,
                };
                let total = dom.integrate(&|wi| phase.eval(wo, wi));
                assert!((total - 1.0).abs() < 2e-3, "{phase:?}: ∫p = {total}");
                let mut rng = Pcg32::new(3, 4);
                for _ in 0..100 {
                    let u = Vec2::new(rng.next_f32(), rng.next_f32());
                    let s = phase.sample(wo, u).unwrap();
                    let p = phase.eval(wo, s.wi);
                    assert!(
                        (s.pdf - p).abs() <= 1e-4 * p,
                        "{phase:?}: pdf {} eval {p}",
                        s.pdf
                    );
                    assert!((s.weight - 1.0).abs() < 1e-5);
                    assert!((s.wi.length() - 1.0).abs() < 1e-4);
                    // Reciprocity.
                    let back = phase.eval(s.wi, wo);
                    assert!((back - p).abs() <= 1e-4 * p);
                }
            }
        }
    }

    #[test]
    fn henyey_greenstein_has_mean_cosine_g_and_scatters_forward() {
        for g in [-0.5f32, 0.3, 0.8] {
            let hg = PhaseFunction::henyey_greenstein(g).unwrap();
            let wo = Vec3::new(0.2, 0.4, -0.9).normalize();
            let mut rng = Pcg32::new(99, 1);
            let n = 200_000;
            let mut mean = 0.0f64;
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let s = hg.sample(wo, u).unwrap();
                // cos θ between the propagation direction −wi and the outgoing wo.
                mean += (-s.wi.dot(wo)) as f64;
            }
            mean /= n as f64;
            // Var(cos θ) ≤ 1, so 5 standard errors ≤ 5/√n ≈ 0.011.
            assert!((mean - g as f64).abs() < 0.012, "g {g}: mean cos {mean}");
        }
    }

    #[test]
    fn invalid_g_is_refused_with_its_value() {
        for g in [1.0f32, -1.0, 1.5, f32::NAN] {
            let e = PhaseFunction::henyey_greenstein(g).unwrap_err();
            assert!(e.contains("(-1, 1)"), "{e}");
        }
    }
}

//! Chi-square goodness-of-fit tests of a sampling routine against its density, in the spirit of
//! Mitsuba's `ChiSquareTest`: directions are binned on a (cos θ, φ) grid of equal-solid-angle
//! cells, the expected count of each cell is the density integrated numerically over the cell,
//! cells with an expected count below 5 are pooled, and the statistic is compared with the χ²
//! distribution. Samples the routine rejects (`None`) form one more cell whose expected count is
//! `n (1 − ∫ pdf)`, so densities that integrate to less than one (absorbing BSDFs, rays that
//! leave the hemisphere) are tested too.
//!
//! Used by the tests of every BSDF, light and warp. Tests use fixed seeds; the significance level
//! is 1 % per test divided by the number of tests in a group (Šidák-style correction left to the
//! caller through [`ChiSquareResult::passed_at`]).

use glam::Vec3;
use std::f64::consts::PI;
use std::fmt;

/// Binning of the unit sphere: `cos_bins` equal intervals of cos θ ∈ [−1, 1] times `phi_bins`
/// equal intervals of φ ∈ [0, 2π). Every cell has the same solid angle 4π/(cos_bins·phi_bins).
#[derive(Clone, Copy, Debug)]
pub struct SphericalDomain {
    pub cos_bins: usize,
    pub phi_bins: usize,
    /// Sub-cells per cell side used to integrate the density (midpoint rule).
    pub integration_res: usize,
}

impl Default for SphericalDomain {
    fn default() -> Self {
        Self {
            cos_bins: 40,
            phi_bins: 80,
            integration_res: 12,
        }
    }
}

impl SphericalDomain {
    fn cell_of(&self, w: Vec3) -> Option<usize> {
        let w = w.as_dvec3();
        let len = w.length();
        if !(len.is_finite()) || (len - 1.0).abs() > 1e-3 {
            return None;
        }
        let w = w / len;
        let c = ((w.z + 1.0) * 0.5 * self.cos_bins as f64).floor() as isize;
        let mut phi = w.y.atan2(w.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let p = (phi / (2.0 * PI) * self.phi_bins as f64).floor() as isize;
        let c = c.clamp(0, self.cos_bins as isize - 1) as usize;
        let p = p.clamp(0, self.phi_bins as isize - 1) as usize;
        Some(c * self.phi_bins + p)
    }

    /// ∫ pdf dω over each cell (midpoint rule on a sub-grid in (cos θ, φ), which is exact in
    /// measure because dω = d(cos θ) dφ).
    pub fn integrate_cells(&self, pdf: &impl Fn(Vec3) -> f32) -> Vec<f64> {
        let n = self.cos_bins * self.phi_bins;
        let r = self.integration_res;
        let dz = 2.0 / (self.cos_bins * r) as f64;
        let dphi = 2.0 * PI / (self.phi_bins * r) as f64;
        let mut out = vec![0.0; n];
        for ci in 0..self.cos_bins {
            for pi in 0..self.phi_bins {
                let mut acc = 0.0;
                for a in 0..r {
                    let z = -1.0 + ((ci * r + a) as f64 + 0.5) * dz;
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    for b in 0..r {
                        let phi = ((pi * r + b) as f64 + 0.5) * dphi;
                        let w = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
                        let v = pdf(w) as f64;
                        if v.is_finite() {
                            acc += v;
                        }
                    }
                }
                out[ci * self.phi_bins + pi] = acc * dz * dphi;
            }
        }
        out
    }

    /// ∫ pdf dω over the whole sphere.
    pub fn integrate(&self, pdf: &impl Fn(Vec3) -> f32) -> f64 {
        self.integrate_cells(pdf).iter().sum()
    }
}

/// A χ² test on the sphere with a fixed sample count.
pub struct ChiSquareTest {
    pub domain: SphericalDomain,
    pub samples: usize,
}

impl ChiSquareTest {
    pub fn new(domain: SphericalDomain, samples: usize) -> Self {
        Self { domain, samples }
    }

    /// Draws `samples` directions from `sample` (`None` = sample rejected) and tests them
    /// against `pdf` (solid-angle density, sr⁻¹).
    pub fn run(
        &self,
        mut sample: impl FnMut() -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) -> ChiSquareResult {
        let ncell = self.domain.cos_bins * self.domain.phi_bins;
        let mut observed = vec![0.0f64; ncell + 1];
        for _ in 0..self.samples {
            match sample().and_then(|w| self.domain.cell_of(w)) {
                Some(c) => observed[c] += 1.0,
                None => observed[ncell] += 1.0,
            }
        }
        let mut expected: Vec<f64> = self
            .domain
            .integrate_cells(&pdf)
            .iter()
            .map(|v| v * self.samples as f64)
            .collect();
        let total: f64 = expected.iter().sum();
        expected.push((self.samples as f64 - total).max(0.0));
        chi_square(&observed, &expected)
    }
}

/// Outcome of a χ² test.
#[derive(Clone, Debug)]
pub struct ChiSquareResult {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Total expected count, compared with the sample count: a density that does not integrate
    /// to the acceptance rate fails regardless of the χ² statistic.
    pub pooled_cells: usize,
    pub worst_cell: usize,
    pub worst_observed: f64,
    pub worst_expected: f64,
    pub sample_count_mismatch: Option<String>,
}

impl ChiSquareResult {
    /// Passes at significance 1 %.
    pub fn passed(&self) -> bool {
        self.passed_at(0.01)
    }
    pub fn passed_at(&self, alpha: f64) -> bool {
        self.sample_count_mismatch.is_none() && self.p_value > alpha
    }
}

impl fmt::Display for ChiSquareResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "chi2 = {:.1} with {} dof, p = {:.3e}; worst cell {} observed {} expected {:.1}; {} cells pooled",
            self.statistic,
            self.dof,
            self.p_value,
            self.worst_cell,
            self.worst_observed,
            self.worst_expected,
            self.pooled_cells
        )?;
        if let Some(m) = &self.sample_count_mismatch {
            write!(f, "; {m}")?;
        }
        Ok(())
    }
}

/// Pearson χ² test of observed against expected counts. Cells with expected count below 5 are
/// pooled into one cell; a cell observed non-empty with zero expectation fails outright.
pub fn chi_square(observed: &[f64], expected: &[f64]) -> ChiSquareResult {
    assert_eq!(observed.len(), expected.len());
    let n_obs: f64 = observed.iter().sum();
    let n_exp: f64 = expected.iter().sum();
    let mut mismatch = None;
    if (n_obs - n_exp).abs() > 1e-3 * n_obs.max(1.0) + 5.0 * n_obs.sqrt() {
        mismatch = Some(format!(
            "expected counts sum to {n_exp:.1} but {n_obs} samples were drawn"
        ));
    }
    let mut stat = 0.0;
    let mut dof = 0usize;
    let (mut pool_o, mut pool_e, mut pooled) = (0.0, 0.0, 0usize);
    let (mut worst, mut worst_v, mut wo, mut we) = (0usize, -1.0f64, 0.0, 0.0);
    for (i, (&o, &e)) in observed.iter().zip(expected).enumerate() {
        if e <= 0.0 && o > 0.0 {
            mismatch.get_or_insert_with(|| format!("cell {i} has {o} samples but zero density"));
        }
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
            pooled += 1;
            continue;
        }
        let v = (o - e) * (o - e) / e;
        if v > worst_v {
            (worst, worst_v, wo, we) = (i, v, o, e);
        }
        stat += v;
        dof += 1;
    }
    if pool_e >= 5.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        dof += 1;
    } else if pool_o > pool_e + 10.0 + 5.0 * pool_e.sqrt() {
        mismatch.get_or_insert_with(|| {
            format!("{pool_o} samples fell in cells expecting {pool_e:.2} in total")
        });
    }
    let dof = dof.saturating_sub(1).max(1);
    let p_value = chi_square_sf(stat, dof as f64);
    ChiSquareResult {
        statistic: stat,
        dof,
        p_value,
        pooled_cells: pooled,
        worst_cell: worst,
        worst_observed: wo,
        worst_expected: we,
        sample_count_mismatch: mismatch,
    }
}

/// Survival function of the χ² distribution with `dof` degrees of freedom: P(X > x).
pub fn chi_square_sf(x: f64, dof: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    regularized_gamma_q(0.5 * dof, 0.5 * x)
}

/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, n = 9; relative error below 1e-13).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised upper incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a): power series for
/// x < a + 1, Lentz continued fraction otherwise.
fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    let gln = ln_gamma(a);
    if x < a + 1.0 {
        let (mut ap, mut sum) = (a, 1.0 / a);
        let mut del = sum;
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - sum * (-x + a * x.ln() - gln).exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        ((-x + a * x.ln() - gln).exp() * h).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn chi_square_survival_matches_tables() {
        // Upper 5 % and 1 % points of χ² tables.
        for (x, k, p) in [
            (3.841_f64, 1.0, 0.05),
            (18.307, 10.0, 0.05),
            (124.342, 100.0, 0.05),
            (6.635, 1.0, 0.01),
            (1.0, 2.0, (-0.5f64).exp()),
        ] {
            let s = chi_square_sf(x, k);
            assert!((s - p).abs() < 2e-4, "sf({x}, {k}) = {s}, want {p}");
        }
    }

    use super::*;
    use crate::sampling::{Pcg32, warp};
    use glam::Vec2;

    #[test]
    fn detects_a_wrong_pdf() {
        // Uniform hemisphere samples tested against the cosine density must fail.
        let mut rng = Pcg32::new(5, 0);
        let t = ChiSquareTest::new(SphericalDomain::default(), 100_000);
        let r = t.run(
            || {
                Some(warp::square_to_uniform_hemisphere(Vec2::new(
                    rng.next_f32(),
                    rng.next_f32(),
                )))
            },
            warp::cosine_hemisphere_pdf,
        );
        assert!(!r.passed(), "{r}");
    }

    #[test]
    fn detects_missing_mass() {
        // Rejecting half the samples while claiming a normalised pdf must fail.
        let mut rng = Pcg32::new(6, 0);
        let t = ChiSquareTest::new(SphericalDomain::default(), 100_000);
        let r = t.run(
            || {
                let w =
                    warp::square_to_cosine_hemisphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                (rng.next_f32() < 0.5).then_some(w)
            },
            warp::cosine_hemisphere_pdf,
        );
        assert!(!r.passed(), "{r}");
    }

    #[test]
    fn integrates_uniform_density_to_one() {
        let i = SphericalDomain::default().integrate(&|_| warp::uniform_sphere_pdf());
        assert!((i - 1.0).abs() < 1e-4, "{i}");
    }
}

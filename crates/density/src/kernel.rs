//! Kernel functions for density estimation (Schjøth 2009, Table 2.1 and Table 5.1).
//!
//! Every kernel here is radially symmetric with support on the closed unit ball: photon gathers
//! stop at the bandwidth `h`, so a kernel with unbounded support would lose energy (thesis
//! §5.0.1). A kernel is a *profile* `p(u²)` of the squared normalised distance
//! `u² = |x − xᵢ|²/h²` times a per-dimension constant `c_d` chosen so that
//!
//! ```text
//! ∫_{|u|<1, u ∈ R^d} c_d p(|u|²) du = 1,   i.e.   c_d = 1 / (S_{d−1} ∫₀¹ p(r²) r^{d−1} dr)
//! ```
//!
//! with the unit-sphere "surface" `S₀ = 2` (the two points ±1), `S₁ = 2π`, `S₂ = 4π`. The density
//! estimate with bandwidth `h` is then `f̂(x) = Σᵢ K(|x − xᵢ|²/h²) / h^d` (eq. 2.2 generalised,
//! without the `1/n` when the samples carry their own weights), per m^d.
//!
//! | kernel | profile `p(u²)` | `c₁` | `c₂` | `c₃` |
//! |---|---|---|---|---|
//! | uniform | 1 | 1/2 | 1/π | 3/(4π) |
//! | Epanechnikov | 1 − u² | 3/4 | 2/π | 15/(8π) |
//! | biweight | (1 − u²)² | 15/16 | 3/π | 105/(32π) |
//! | Silverman (2nd order) | (1 − u²)² | 15/16 | 3/π | 105/(32π) |
//! | cubic (triweight) | (1 − u²)³ | 35/32 | 4/π | 315/(64π) |
//! | cone, `g ≥ 1` | 1 − |u|/g | 1/(2 − 1/g) | 1/(π(1 − 2/(3g))) | 3/(4π(1 − 3/(4g))) |
//! | Gaussian, σ = 1/3 | exp(−u²/(2σ²)) | 1/(σ√(2π) erf(3/√2)) | 1/(2πσ²(1 − e^{−9/2})) | see [`GAUSS_C3`] |
//!
//! # Relation to Table 5.1 and eq. 3.2
//!
//! Table 5.1 writes its kernels `K₅.₁(y)` in `y = u²` (the argument of `K` in eq. 3.2 is
//! `(x − xᵢ)ᵀ(x − xᵢ)/h²`) and normalised so that `∫ K₅.₁ du = π` over the unit disc, because
//! eq. 3.2 divides by the disc area `π h²` itself. Hence in two dimensions
//!
//! ```text
//! eval(u², Dim::Two) = K₅.₁(u²) / π,    L̂_r(x, ω) = 1/(π h²) Σᵢ K₅.₁(dᵢ²/h²) f_r Φᵢ
//!                                                 = 1/h²    Σᵢ eval(dᵢ²/h², Dim::Two) f_r Φᵢ.
//! ```
//!
//! Check of Table 5.1 (2-D, with `s = u²`, `du = π ds` in polar coordinates):
//! Epanechnikov `∫ 2(1 − s) π ds = π` ✓; Silverman `∫ 3(1 − s)² π ds = π` ✓;
//! cone `2π ∫₀¹ (1 − r/g) r dr / (1 − 2/(3g)) = π` ✓. The unnamed fourth row prints
//! `4(1 − |y|)³/3`, but `∫₀¹ (4/3)(1 − s)³ π ds = π/3`: the `/3` is a misprint and the kernel
//! normalised like the others is `4(1 − |y|)³`, which is what [`Kernel::Cubic`] implements
//! (`c₂ = 4/π`). Silverman's second-order kernel is the bivariate biweight; both names are
//! kept because both are in common use, and they give identical values.
//!
//! # The Gaussian
//!
//! Table 2.1's Gaussian `(2π)^{−1/2} exp(−x²/2)` has unbounded support. Here it is used with
//! standard deviation σ = h/3 (so the truncation at `|u| = 1` is at 3σ), truncated to the unit
//! ball and renormalised per dimension, so that it integrates to exactly 1 over the ball like
//! the other kernels. Truncation drops 0.27 % of the 1-D mass, 1.1 % of the 2-D mass and 2.9 %
//! of the 3-D mass before renormalisation. In 1-D:
//! `eval(u², One) = φ(u/σ) / (σ erf(3/√2))` with `φ` Table 2.1's Gaussian.

use std::f64::consts::PI;

use crate::DensityError;

/// A radially symmetric kernel with support on the unit ball (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kernel {
    /// Constant over the ball (Table 2.1, "Uniform").
    Uniform,
    /// `∝ 1 − u²` (Table 2.1, Table 5.1).
    Epanechnikov,
    /// `∝ (1 − u²)²` (Table 2.1).
    Biweight,
    /// Gaussian with σ = 1/3 (in units of h), truncated at `|u| = 1` and renormalised.
    Gaussian,
    /// Jensen's cone filter `∝ 1 − |u|/g`, `g ≥ 1` (Table 5.1).
    Cone {
        /// Slope parameter; `g = 1` reaches zero at the boundary, larger `g` flattens the cone.
        g: f32,
    },
    /// Silverman's second-order kernel `∝ (1 − u²)²` (Table 5.1; equal to the biweight).
    Silverman,
    /// `∝ (1 − u²)³` (Table 5.1's fourth row, with its normalisation corrected, see module docs).
    Cubic,
}

/// Dimension of the space a density estimate lives in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// Densities per m (e.g. along a beam).
    One = 1,
    /// Densities per m² (surface photon maps, eq. 3.2).
    Two = 2,
    /// Densities per m³ (volume photon maps).
    Three = 3,
}

impl Dim {
    /// The dimension as an integer.
    pub fn get(self) -> u32 {
        self as u32
    }

    fn idx(self) -> usize {
        self as usize - 1
    }

    /// `h^d` for a bandwidth `h` (m^d): the divisor of the density estimate.
    pub fn bandwidth_volume(self, h: f32) -> f32 {
        match self {
            Dim::One => h,
            Dim::Two => h * h,
            Dim::Three => h * h * h,
        }
    }

    /// `h^d` (m^d) from `h` and its square `h2` as the caller already has them, with `h2`
    /// itself for `d = 2` so that the 2-D estimate divides by exactly the `h²` it always did
    /// (the k-NN bandwidth is the k-th squared distance, not `√(d²)²`): `h`, `h2`, `h2 · h`.
    #[inline]
    pub fn bandwidth_volume_from(self, h: f32, h2: f32) -> f32 {
        match self {
            Dim::One => h,
            Dim::Two => h2,
            Dim::Three => h2 * h,
        }
    }

    /// Volume `V_d = π^{d/2} / Γ(d/2 + 1)` of the unit ball of `R^d`: 2, π, 4π/3 (length m,
    /// area m², volume m³ once multiplied by `r^d`).
    pub fn unit_ball_volume(self) -> f64 {
        match self {
            Dim::One => 2.0,
            Dim::Two => PI,
            Dim::Three => 4.0 / 3.0 * PI,
        }
    }

    /// Volume `V_d r^d` of the ball of radius `r` (m): `2r`, `πr²`, `4/3 π r³` (m^d). The k-NN
    /// density estimate with the uniform kernel is `k / V_d(h)` (eq. 2.12: `c_d = 1/V_d`), e.g.
    /// `k / (4/3 π r³)` photons per m³ in a volume (seed 000 eq. 8.3).
    pub fn ball_volume(self, r: f64) -> f64 {
        self.unit_ball_volume() * r.powi(self.get() as i32)
    }
}

/// Default slope parameter of the cone kernel when none is given (`"cone"`).
pub const DEFAULT_CONE_G: f32 = 1.1;

// ---- Normalisation constants c_d = 1 / (S_{d−1} ∫₀¹ p(r²) r^{d−1} dr) -------------------------
//
// Uniform, p = 1:            ∫₀¹ r^{d−1} dr = 1/d
//   c₁ = 1/(2·1) = 1/2,  c₂ = 1/(2π·1/2) = 1/π,  c₃ = 1/(4π·1/3) = 3/(4π).
// Epanechnikov, p = 1 − r²:  ∫₀¹ (1 − r²) dr = 2/3, ∫₀¹ (1 − r²) r dr = 1/4,
//                            ∫₀¹ (1 − r²) r² dr = 1/3 − 1/5 = 2/15
//   c₁ = 1/(4/3) = 3/4,  c₂ = 1/(2π/4) = 2/π,  c₃ = 1/(8π/15) = 15/(8π).
// Biweight, p = (1 − r²)²:   ∫₀¹ (1 − 2r² + r⁴) dr = 1 − 2/3 + 1/5 = 8/15,
//                            ∫₀¹ (1 − r²)² r dr = ½ ∫₀¹ (1 − s)² ds = 1/6,
//                            ∫₀¹ (1 − 2r² + r⁴) r² dr = 1/3 − 2/5 + 1/7 = 8/105
//   c₁ = 1/(16/15) = 15/16,  c₂ = 1/(2π/6) = 3/π,  c₃ = 1/(32π/105) = 105/(32π).
// Cubic, p = (1 − r²)³:      ∫₀¹ (1 − 3r² + 3r⁴ − r⁶) dr = 1 − 1 + 3/5 − 1/7 = 16/35,
//                            ∫₀¹ (1 − r²)³ r dr = ½ ∫₀¹ (1 − s)³ ds = 1/8,
//                            ∫₀¹ (1 − 3r² + 3r⁴ − r⁶) r² dr = 1/3 − 3/5 + 3/7 − 1/9 = 16/315
//   c₁ = 1/(32/35) = 35/32,  c₂ = 1/(2π/8) = 4/π,  c₃ = 1/(64π/315) = 315/(64π).
// Cone, p = 1 − r/g:         ∫₀¹ (1 − r/g) dr = 1 − 1/(2g), ∫₀¹ (1 − r/g) r dr = 1/2 − 1/(3g),
//                            ∫₀¹ (1 − r/g) r² dr = 1/3 − 1/(4g)
//   c₁ = 1/(2 − 1/g),  c₂ = 1/(π(1 − 2/(3g))),  c₃ = 1/(4π(1/3 − 1/(4g))) = 3/(4π(1 − 3/(4g))).
// Gaussian, p = exp(−r²/(2σ²)), σ = 1/3, so 1/(2σ²) = 9/2 and 1/σ = 3:
//   1-D: 2∫₀¹ e^{−r²/(2σ²)} dr = σ√(2π) erf(1/(σ√2)) = σ√(2π) erf(3/√2)
//   2-D: 2π∫₀¹ e^{−r²/(2σ²)} r dr = 2πσ² (1 − e^{−1/(2σ²)}) = 2πσ² (1 − e^{−9/2})
//   3-D: 4π∫₀¹ e^{−r²/(2σ²)} r² dr
//        = 4π σ³ [√(π/2) erf(1/(σ√2)) − (1/σ) e^{−1/(2σ²)}]     (integration by parts)
//        = 4π σ³ [√(π/2) erf(3/√2) − 3 e^{−9/2}].

const UNIFORM_C: [f64; 3] = [0.5, 1.0 / PI, 3.0 / (4.0 * PI)];
const EPANECHNIKOV_C: [f64; 3] = [0.75, 2.0 / PI, 15.0 / (8.0 * PI)];
const BIWEIGHT_C: [f64; 3] = [15.0 / 16.0, 3.0 / PI, 105.0 / (32.0 * PI)];
const CUBIC_C: [f64; 3] = [35.0 / 32.0, 4.0 / PI, 315.0 / (64.0 * PI)];

/// Gaussian standard deviation in units of the bandwidth.
pub const GAUSS_SIGMA: f64 = 1.0 / 3.0;
/// erf(3/√2) = P(|Z| < 3) for a standard normal Z.
const ERF_3_OVER_SQRT2: f64 = 0.997_300_203_936_739_8;
/// e^{−9/2}.
const EXP_M4_5: f64 = 0.011_108_996_538_242_306;
/// √(2π).
const SQRT_2PI: f64 = 2.506_628_274_631_000_2;
/// √(π/2).
const SQRT_PI_2: f64 = 1.253_314_137_315_500_3;
/// 1-D Gaussian normalisation `1/(σ√(2π) erf(3/√2))` ≈ 1.200067.
pub const GAUSS_C1: f64 = 1.0 / (GAUSS_SIGMA * SQRT_2PI * ERF_3_OVER_SQRT2);
/// 2-D Gaussian normalisation `1/(2πσ²(1 − e^{−9/2}))` ≈ 1.448486.
pub const GAUSS_C2: f64 = 1.0 / (2.0 * PI * GAUSS_SIGMA * GAUSS_SIGMA * (1.0 - EXP_M4_5));
/// 3-D Gaussian normalisation `1/(4πσ³[√(π/2) erf(3/√2) − 3e^{−9/2}])` ≈ 1.766058.
pub const GAUSS_C3: f64 = 1.0
    / (4.0
        * PI
        * GAUSS_SIGMA
        * GAUSS_SIGMA
        * GAUSS_SIGMA
        * (SQRT_PI_2 * ERF_3_OVER_SQRT2 - 3.0 * EXP_M4_5));
const GAUSS_C: [f64; 3] = [GAUSS_C1, GAUSS_C2, GAUSS_C3];
/// Exponent factor `1/(2σ²)` = 9/2.
const GAUSS_A: f32 = 4.5;

fn cone_c(g: f32, dim: Dim) -> f32 {
    let g = f64::from(g);
    let c = match dim {
        Dim::One => 1.0 / (2.0 - 1.0 / g),
        Dim::Two => 1.0 / (PI * (1.0 - 2.0 / (3.0 * g))),
        Dim::Three => 3.0 / (4.0 * PI * (1.0 - 3.0 / (4.0 * g))),
    };
    c as f32
}

impl Kernel {
    /// Parses "uniform", "epanechnikov", "biweight", "gaussian", "cone" (g = 1.1) or "cone:G"
    /// (G >= 1), "silverman", "cubic" (case-insensitive, surrounding whitespace ignored);
    /// a clear error listing the names otherwise.
    pub fn from_name(s: &str) -> Result<Kernel, DensityError> {
        let t = s.trim().to_ascii_lowercase();
        let k = match t.as_str() {
            "uniform" => Kernel::Uniform,
            "epanechnikov" => Kernel::Epanechnikov,
            "biweight" => Kernel::Biweight,
            "gaussian" => Kernel::Gaussian,
            "cone" => Kernel::Cone { g: DEFAULT_CONE_G },
            "silverman" => Kernel::Silverman,
            "cubic" => Kernel::Cubic,
            _ => {
                let Some(gs) = t.strip_prefix("cone:") else {
                    return Err(DensityError::UnknownKernel(s.to_string()));
                };
                let g: f32 = gs
                    .trim()
                    .parse()
                    .map_err(|_| DensityError::InvalidConeParameter(s.to_string()))?;
                if !(g.is_finite() && g >= 1.0) {
                    return Err(DensityError::InvalidConeParameter(s.to_string()));
                }
                Kernel::Cone { g }
            }
        };
        Ok(k)
    }

    /// The name accepted by [`Kernel::from_name`] (`"cone:G"` for the cone).
    pub fn name(&self) -> String {
        match self {
            Kernel::Uniform => "uniform".into(),
            Kernel::Epanechnikov => "epanechnikov".into(),
            Kernel::Biweight => "biweight".into(),
            Kernel::Gaussian => "gaussian".into(),
            Kernel::Cone { g } => format!("cone:{g}"),
            Kernel::Silverman => "silverman".into(),
            Kernel::Cubic => "cubic".into(),
        }
    }

    /// The normalisation constant `c_d` (see the module docs), so that
    /// `eval(u2, dim) = normalization(dim) · profile(u2)` inside the unit ball.
    pub fn normalization(&self, dim: Dim) -> f32 {
        let i = dim.idx();
        match self {
            Kernel::Uniform => UNIFORM_C[i] as f32,
            Kernel::Epanechnikov => EPANECHNIKOV_C[i] as f32,
            Kernel::Biweight | Kernel::Silverman => BIWEIGHT_C[i] as f32,
            Kernel::Cubic => CUBIC_C[i] as f32,
            Kernel::Gaussian => GAUSS_C[i] as f32,
            Kernel::Cone { g } => cone_c(*g, dim),
        }
    }

    /// The unnormalised profile `p(u²)` (1 at the centre); 0 for `u2 >= 1` or NaN.
    pub fn profile(&self, u2: f32) -> f32 {
        // NaN is rejected too.
        if u2.is_nan() || u2 >= 1.0 {
            return 0.0;
        }
        let u2 = u2.max(0.0);
        match self {
            Kernel::Uniform => 1.0,
            Kernel::Epanechnikov => 1.0 - u2,
            Kernel::Biweight | Kernel::Silverman => {
                let a = 1.0 - u2;
                a * a
            }
            Kernel::Cubic => {
                let a = 1.0 - u2;
                a * a * a
            }
            Kernel::Gaussian => (-GAUSS_A * u2).exp(),
            Kernel::Cone { g } => (1.0 - u2.sqrt() / g).max(0.0),
        }
    }

    /// Kernel value at squared normalised distance u2 = |x − x_i|²/h², normalised so that
    /// ∫_{R^d} K(|u|²) du = 1 over the d-dimensional unit ball; 0 for u2 >= 1. The density
    /// estimate with bandwidth h is then Σ K(d_i²/h²) / h^d.
    ///
    /// In 2-D this is Table 5.1's kernel divided by π, so eq. 3.2 reads
    /// `L̂ = 1/h² Σ eval(dᵢ²/h², Dim::Two) f_r Φᵢ` (see the [module docs](self)).
    #[inline]
    pub fn eval(&self, u2: f32, dim: Dim) -> f32 {
        if u2.is_nan() || u2 >= 1.0 {
            return 0.0;
        }
        self.normalization(dim) * self.profile(u2)
    }
}

impl std::fmt::Display for Kernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

impl std::str::FromStr for Kernel {
    type Err = DensityError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Kernel::from_name(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_kernels() -> Vec<Kernel> {
        vec![
            Kernel::Uniform,
            Kernel::Epanechnikov,
            Kernel::Biweight,
            Kernel::Gaussian,
            Kernel::Cone { g: 1.0 },
            Kernel::Cone { g: 1.1 },
            Kernel::Cone { g: 3.0 },
            Kernel::Silverman,
            Kernel::Cubic,
        ]
    }

    /// Midpoint rule on a Cartesian grid over the positive orthant of [0, 1]^d (the kernels are
    /// even in every coordinate), times 2^d. Independent of the radial derivation of c_d.
    fn integrate_cartesian(k: Kernel, dim: Dim, n: usize) -> f64 {
        let h = 1.0 / n as f64;
        let c = |i: usize| (i as f64 + 0.5) * h;
        let mut sum = 0.0f64;
        match dim {
            Dim::One => {
                for i in 0..n {
                    sum += f64::from(k.eval((c(i) * c(i)) as f32, dim));
                }
                2.0 * sum * h
            }
            Dim::Two => {
                for i in 0..n {
                    for j in 0..n {
                        let r2 = c(i) * c(i) + c(j) * c(j);
                        sum += f64::from(k.eval(r2 as f32, dim));
                    }
                }
                4.0 * sum * h * h
            }
            Dim::Three => {
                for i in 0..n {
                    for j in 0..n {
                        let rij = c(i) * c(i) + c(j) * c(j);
                        if rij >= 1.0 {
                            continue;
                        }
                        for l in 0..n {
                            let r2 = rij + c(l) * c(l);
                            sum += f64::from(k.eval(r2 as f32, dim));
                        }
                    }
                }
                8.0 * sum * h * h * h
            }
        }
    }

    #[test]
    fn integrates_to_one_in_every_dimension() {
        for k in all_kernels() {
            for (dim, n) in [(Dim::One, 200_000), (Dim::Two, 2_000), (Dim::Three, 300)] {
                let integral = integrate_cartesian(k, dim, n);
                assert!(
                    (integral - 1.0).abs() < 1e-3,
                    "{k:?} in {dim:?}: integral {integral}"
                );
            }
        }
    }

    /// The uniform kernel is one over the unit ball's volume, so the uniform k-NN estimate is
    /// `k / V_d(h)`: 2, π and 4π/3 written out here, not taken from [`Dim::unit_ball_volume`].
    #[test]
    fn uniform_is_one_over_the_ball_volume() {
        let pi = std::f64::consts::PI;
        for (dim, v) in [
            (Dim::One, 2.0),
            (Dim::Two, pi),
            (Dim::Three, 4.0 * pi / 3.0),
        ] {
            assert!((dim.unit_ball_volume() - v).abs() < 1e-15 * v);
            let c = f64::from(Kernel::Uniform.normalization(dim));
            assert!((c * v - 1.0).abs() < 1e-7, "{dim:?}: c = {c}");
            assert!((dim.ball_volume(0.5) - v * 0.5f64.powi(dim.get() as i32)).abs() < 1e-15);
        }
        // h^d from (h, h²): h² itself in 2-D (the k-NN bandwidth is a squared distance), told
        // apart from h·h by a deliberately inconsistent pair.
        let (h, h2) = (0.3f32, 0.1f32);
        assert_eq!(
            Dim::Two.bandwidth_volume_from(h, h2).to_bits(),
            h2.to_bits()
        );
        assert_eq!(Dim::Three.bandwidth_volume_from(h, h2), h2 * h);
        assert_eq!(Dim::One.bandwidth_volume_from(h, h2), h);
    }

    #[test]
    fn matches_table_2_1_in_one_dimension() {
        // Table 2.1, in its own variable x (univariate, |x| < 1).
        let xs = [0.0f32, 0.25, -0.5, 0.9];
        for x in xs {
            let x2 = x * x;
            let uni = 0.5;
            let epa = 0.75 * (1.0 - x2);
            let biw = 15.0 / 16.0 * (1.0 - x2) * (1.0 - x2);
            assert!((Kernel::Uniform.eval(x2, Dim::One) - uni).abs() < 1e-6);
            assert!((Kernel::Epanechnikov.eval(x2, Dim::One) - epa).abs() < 1e-6);
            assert!((Kernel::Biweight.eval(x2, Dim::One) - biw).abs() < 1e-6);
            // Gaussian: Table 2.1's φ(z) = exp(−z²/2)/√(2π) at z = x/σ = 3x, scaled to standard
            // deviation 1/3 (1/σ factor) and renormalised by the mass 0.9973002 inside |z| < 3.
            let z = 3.0 * f64::from(x);
            let phi = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
            let expect = 3.0 * phi / 0.997_300_2;
            let got = f64::from(Kernel::Gaussian.eval(x2, Dim::One));
            assert!(
                (got - expect).abs() < 1e-5 * expect.max(1.0),
                "{x}: {got} vs {expect}"
            );
        }
    }

    #[test]
    fn matches_table_5_1_in_two_dimensions() {
        // Table 5.1 in its own variable y = |x − xᵢ|²/h²; eval(y, Two) = K₅.₁(y)/π.
        let pi = std::f32::consts::PI;
        for y in [0.0f32, 0.1, 0.5, 0.81, 0.99] {
            let epa = 2.0 * (1.0 - y);
            let sil = 3.0 * (1.0 - y) * (1.0 - y);
            // Printed 4(1 − y)³/3; corrected normalisation 4(1 − y)³ (see module docs).
            let cub = 4.0 * (1.0 - y) * (1.0 - y) * (1.0 - y);
            let g = 1.1f32;
            let cone = (1.0 - y.sqrt() / g) / (1.0 - 2.0 / (3.0 * g));
            let close = |a: f32, b: f32| (a - b).abs() < 1e-5 * b.max(1.0);
            assert!(close(Kernel::Epanechnikov.eval(y, Dim::Two) * pi, epa));
            assert!(close(Kernel::Silverman.eval(y, Dim::Two) * pi, sil));
            assert!(close(Kernel::Cubic.eval(y, Dim::Two) * pi, cub));
            assert!(close(Kernel::Cone { g }.eval(y, Dim::Two) * pi, cone));
        }
        // Hand values: Silverman at the centre is 3/π, cubic 4/π.
        assert!((Kernel::Silverman.eval(0.0, Dim::Two) - 0.954_929_7).abs() < 1e-6);
        assert!((Kernel::Cubic.eval(0.0, Dim::Two) - 1.273_239_5).abs() < 1e-6);
    }

    #[test]
    fn zero_outside_unit_ball_and_non_negative() {
        for k in all_kernels() {
            for dim in [Dim::One, Dim::Two, Dim::Three] {
                for u2 in [1.0f32, 1.0001, 2.0, 1e30, f32::INFINITY, f32::NAN] {
                    assert_eq!(k.eval(u2, dim), 0.0, "{k:?} {dim:?} {u2}");
                }
                for i in 0..1000 {
                    let u2 = i as f32 / 1000.0;
                    let v = k.eval(u2, dim);
                    assert!(v >= 0.0 && v.is_finite(), "{k:?} {dim:?} {u2}: {v}");
                }
                assert!(k.eval(0.0, dim) > 0.0);
                // Negative input (rounding) is treated as the centre.
                assert_eq!(k.eval(-1e-7, dim), k.eval(0.0, dim));
            }
        }
    }

    #[test]
    fn parsing() {
        assert_eq!(Kernel::from_name("uniform"), Ok(Kernel::Uniform));
        assert_eq!(
            Kernel::from_name(" Epanechnikov "),
            Ok(Kernel::Epanechnikov)
        );
        assert_eq!(Kernel::from_name("cone"), Ok(Kernel::Cone { g: 1.1 }));
        assert_eq!(Kernel::from_name("cone:2.5"), Ok(Kernel::Cone { g: 2.5 }));
        assert_eq!(Kernel::from_name("cone:1"), Ok(Kernel::Cone { g: 1.0 }));
        for k in all_kernels() {
            assert_eq!(Kernel::from_name(&k.name()), Ok(k));
            assert_eq!(k.to_string().parse::<Kernel>(), Ok(k));
        }
        let e = Kernel::from_name("box").unwrap_err();
        assert!(matches!(e, DensityError::UnknownKernel(_)));
        let msg = e.to_string();
        for n in [
            "uniform",
            "epanechnikov",
            "biweight",
            "gaussian",
            "cone",
            "silverman",
            "cubic",
        ] {
            assert!(msg.contains(n), "{msg}");
        }
        for bad in [
            "cone:0.5", "cone:x", "cone:", "cone:inf", "cone:NaN", "cone:-2",
        ] {
            assert!(
                matches!(
                    Kernel::from_name(bad),
                    Err(DensityError::InvalidConeParameter(_))
                ),
                "{bad}"
            );
        }
    }
}

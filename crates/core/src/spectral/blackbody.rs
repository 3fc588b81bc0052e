//! Blackbody emission: Planck's law and its peak-normalised form for light colours.
//!
//! Planck's law (Planck 1901) for the spectral radiance of a blackbody at temperature T:
//! B(λ, T) = 2 h c² / λ⁵ / (exp(h c / (λ k_B T)) − 1). Its maximum over λ lies at Wien's
//! displacement λ_max = b / T, b = 2.897771955e-3 m·K (CODATA 2018). Lights in caustica give
//! their colour as [`blackbody_normalized`] (peak 1, as pbrt-v4's `BlackbodySpectrum`) times a
//! scale, so the temperature sets the colour and the scale the brightness.

/// Planck constant h (J·s, exact since the 2019 SI).
pub const PLANCK_H: f64 = 6.626_070_15e-34;
/// Speed of light in vacuum c (m/s, exact).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Boltzmann constant k_B (J/K, exact).
pub const BOLTZMANN_K: f64 = 1.380_649e-23;
/// Wien's displacement constant b in nm·K: the peak of B(λ, T) over λ is at b / T.
pub const WIEN_B_NM_K: f64 = 2.897_771_955e6;

/// Planck's law in f64: spectral radiance in W·m⁻²·sr⁻¹·nm⁻¹ at `lambda_nm` (nm) and `kelvin`
/// (K). Zero for non-positive λ or T.
pub fn blackbody_f64(lambda_nm: f64, kelvin: f64) -> f64 {
    if !(lambda_nm > 0.0 && kelvin > 0.0) {
        return 0.0;
    }
    let l = lambda_nm * 1e-9; // m
    let per_m = 2.0 * PLANCK_H * SPEED_OF_LIGHT * SPEED_OF_LIGHT
        / (l.powi(5) * (PLANCK_H * SPEED_OF_LIGHT / (l * BOLTZMANN_K * kelvin)).exp_m1());
    per_m * 1e-9 // W/m²/sr/m → W/m²/sr/nm
}

/// Planck's law: the spectral radiance of a blackbody at `kelvin` (K) and wavelength
/// `lambda_nm` (nm), in W·m⁻²·sr⁻¹·**nm**⁻¹ (multiply by 10⁹ for pbrt-v4's W·m⁻²·sr⁻¹·m⁻¹).
/// Zero for non-positive λ or T. Computed in f64 (λ⁵ in m underflows f32 below ~20 nm).
#[inline]
pub fn blackbody(lambda_nm: f32, kelvin: f32) -> f32 {
    blackbody_f64(lambda_nm as f64, kelvin as f64) as f32
}

/// A blackbody spectrum normalised to peak 1: B(λ, T) / B(b/T, T), the shape of pbrt-v4's
/// `BlackbodySpectrum`. Dimensionless; the peak may lie outside the visible range (below
/// ~3500 K or above ~8000 K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlackbodyNormalized {
    kelvin: f64,
    /// 1 / B(λ_max, T), in nm·m²·sr/W.
    inv_peak: f64,
}

impl BlackbodyNormalized {
    /// `kelvin` must be positive and finite; otherwise the spectrum is zero.
    pub fn new(kelvin: f32) -> Self {
        let kelvin = kelvin as f64;
        let peak = if kelvin > 0.0 && kelvin.is_finite() {
            blackbody_f64(WIEN_B_NM_K / kelvin, kelvin)
        } else {
            0.0
        };
        Self {
            kelvin,
            inv_peak: if peak > 0.0 { 1.0 / peak } else { 0.0 },
        }
    }

    /// Temperature (K).
    pub fn kelvin(&self) -> f32 {
        self.kelvin as f32
    }

    /// B(λ, T) / B(λ_max, T) ∈ [0, 1] at `lambda_nm` (nm).
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        (blackbody_f64(lambda_nm as f64, self.kelvin) * self.inv_peak) as f32
    }
}

/// B(λ, T) / B(b/T, T): Planck's law normalised to peak 1 (dimensionless). For many
/// evaluations at one temperature build a [`BlackbodyNormalized`] once.
#[inline]
pub fn blackbody_normalized(lambda_nm: f32, kelvin: f32) -> f32 {
    BlackbodyNormalized::new(kelvin).eval(lambda_nm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wien_displacement_law() {
        for t in [1000.0f32, 2700.0, 3000.0, 5000.0, 5778.0, 6500.0, 10000.0] {
            let peak = (WIEN_B_NM_K / t as f64) as f32;
            let b0 = blackbody(peak, t);
            // The peak is a maximum: 0.1 % to either side is lower...
            assert!(blackbody(peak * 0.999, t) < b0, "T = {t}");
            assert!(blackbody(peak * 1.001, t) < b0, "T = {t}");
            // ... and a 5 % wrong peak would be detected: the function still rises toward it.
            assert!(blackbody(peak * 0.95, t) < blackbody(peak * 0.97, t));
            // Normalised peak 1, and nowhere above 1.
            let n = BlackbodyNormalized::new(t);
            assert!((n.eval(peak) - 1.0).abs() < 1e-6, "{}", n.eval(peak));
            for l in (300..900).step_by(7) {
                assert!(n.eval(l as f32) <= 1.0 + 1e-6);
            }
        }
        // Golden-section search for the maximum at 6500 K lands on b / T within 0.05 %.
        let t = 6500.0f64;
        let (mut a, mut b) = (200.0f64, 900.0f64);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if blackbody_f64(c, t) > blackbody_f64(d, t) {
                b = d;
            } else {
                a = c;
            }
        }
        let want = WIEN_B_NM_K / t;
        assert!((0.5 * (a + b) / want - 1.0).abs() < 5e-4, "{a} {want}");
    }

    #[test]
    fn stefan_boltzmann_and_known_value() {
        // π ∫ B dλ = σ T⁴ (σ = 5.670374419e-8 W m⁻² K⁻⁴): midpoint rule in ln λ.
        let t = 5000.0;
        let (l0, l1, n) = (50.0f64, 1e6f64, 20_000);
        let h = (l1 / l0).ln() / n as f64;
        let mut s = 0.0;
        for i in 0..n {
            let l = l0 * ((i as f64 + 0.5) * h).exp();
            s += blackbody_f64(l, t) * l * h;
        }
        let sigma = 5.670_374_419e-8;
        assert!((std::f64::consts::PI * s / (sigma * t.powi(4)) - 1.0).abs() < 1e-4);
        // B(500 nm, 5778 K) = 2.63757e13 W/m²/sr/m (direct evaluation of Planck's law).
        assert!((blackbody(500.0, 5778.0) / 2.63757e4 - 1.0).abs() < 1e-3);
        assert_eq!(blackbody(-1.0, 5000.0), 0.0);
        assert_eq!(blackbody(500.0, 0.0), 0.0);
        assert_eq!(BlackbodyNormalized::new(f32::NAN).eval(500.0), 0.0);
    }
}

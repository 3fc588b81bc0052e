//! Dispersion: an index of refraction that varies with wavelength, for the smooth and rough
//! dielectrics in spectral mode.
//!
//! Two laws: Sellmeier's, n²(λ) = 1 + Σᵢ Bᵢ λ² / (λ² − Cᵢ), and Cauchy's, n(λ) = A + B/λ² (+ C/λ⁴),
//! both with λ in µm (the glass catalogues' unit; [`Dispersion::ior`] takes nm). Named media
//! carry their catalogue coefficients. In RGB mode a dispersive dielectric refracts with its IOR
//! at the helium d line, 587.56 nm ([`LAMBDA_D`]), the n_d glass catalogues quote.

/// The helium d line (nm), where catalogues quote n_d and where RGB mode evaluates a dispersive
/// IOR.
pub const LAMBDA_D: f32 = 587.56;

/// The wavelength range (nm) over which a dispersion law must give a valid IOR: the range the
/// spectral mode samples.
pub const VALID_RANGE: (f32, f32) = (360.0, 830.0);

/// A wavelength-dependent index of refraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dispersion {
    /// n² = 1 + Σ Bᵢ λ²/(λ² − Cᵢ), λ in µm, Cᵢ in µm²; unused terms have B = C = 0.
    Sellmeier { b: [f64; 4], c: [f64; 4] },
    /// n = A + B/λ² + C/λ⁴, λ in µm (B in µm², C in µm⁴).
    Cauchy { a: f64, b: f64, c: f64 },
}

/// The named media (case-insensitive names, see [`Dispersion::named`]).
pub const NAMED: &[&str] = &["bk7", "baf10", "f2", "fused-silica", "water"];

impl Dispersion {
    /// IOR at `lambda_nm` (nm).
    #[inline]
    pub fn ior(&self, lambda_nm: f32) -> f32 {
        self.ior_f64(lambda_nm as f64) as f32
    }

    /// IOR at `lambda_nm` (nm), in double precision.
    fn ior_f64(&self, lambda_nm: f64) -> f64 {
        let l = lambda_nm * 1e-3;
        let l2 = l * l;
        match self {
            Dispersion::Sellmeier { b, c } => {
                let mut n2 = 1.0;
                for i in 0..4 {
                    if b[i] != 0.0 {
                        n2 += b[i] * l2 / (l2 - c[i]);
                    }
                }
                n2.max(0.0).sqrt()
            }
            Dispersion::Cauchy { a, b, c } => a + b / l2 + c / (l2 * l2),
        }
    }

    /// dn/dλ at `lambda_nm` (nm⁻¹), in closed form: Sellmeier
    /// `dn/dλ = −(1/n) Σ Bᵢ Cᵢ λ / (λ² − Cᵢ)²` (λ in µm, then ×10⁻³ per nm), Cauchy
    /// `dn/dλ = −2B/λ³ − 4C/λ⁵`. Wavelength photon differentials refract with it.
    pub fn dior_dlambda(&self, lambda_nm: f32) -> f32 {
        let l = lambda_nm as f64 * 1e-3;
        let l2 = l * l;
        let per_um = match self {
            Dispersion::Sellmeier { b, c } => {
                let n = self.ior_f64(lambda_nm as f64);
                let mut dn2 = 0.0;
                for i in 0..4 {
                    if b[i] != 0.0 {
                        let d = l2 - c[i];
                        dn2 += -2.0 * b[i] * c[i] * l / (d * d);
                    }
                }
                dn2 / (2.0 * n)
            }
            Dispersion::Cauchy { b, c, .. } => -2.0 * b / (l2 * l) - 4.0 * c / (l2 * l2 * l),
        };
        (per_um * 1e-3) as f32
    }

    /// IOR at the d line: the value RGB mode uses.
    #[inline]
    pub fn ior_d(&self) -> f32 {
        self.ior(LAMBDA_D)
    }

    /// A named medium's catalogue law: `bk7` (Schott N-BK7), `baf10` (Schott N-BAF10), `f2`
    /// (Schott F2), `fused-silica` (Malitson 1965) and `water` (Daimon & Masumura 2007, 20 °C).
    /// Names are case-insensitive; `_`, ` ` and `-` are interchangeable, and `n-` prefixes
    /// (`N-BK7`) are accepted.
    pub fn named(name: &str) -> Option<Self> {
        let key: String = name
            .trim()
            .to_ascii_lowercase()
            .chars()
            .map(|c| if c == '_' || c == ' ' { '-' } else { c })
            .collect();
        let key = key.strip_prefix("n-").unwrap_or(&key);
        let s = |b: [f64; 4], c: [f64; 4]| Some(Dispersion::Sellmeier { b, c });
        match key {
            "bk7" => s(
                [1.039_612_12, 0.231_792_344, 1.010_469_45, 0.0],
                [0.006_000_698_67, 0.020_017_914_4, 103.560_653, 0.0],
            ),
            "baf10" => s(
                [1.585_149_5, 0.143_559_385, 1.085_212_69, 0.0],
                [0.009_266_812_82, 0.042_448_980_5, 105.613_573, 0.0],
            ),
            "f2" => s(
                [1.345_333_59, 0.209_073_176, 0.937_357_162, 0.0],
                [0.009_977_438_71, 0.047_045_076_7, 111.886_764, 0.0],
            ),
            "fused-silica" | "silica" | "fusedsilica" => s(
                [0.696_166_3, 0.407_942_6, 0.897_479_4, 0.0],
                [
                    0.068_404_3f64.powi(2),
                    0.116_241_4f64.powi(2),
                    9.896_161f64.powi(2),
                    0.0,
                ],
            ),
            "water" => s(
                [
                    5.684_027_565e-1,
                    1.726_177_391e-1,
                    2.086_189_578e-2,
                    1.130_748_688e-1,
                ],
                [
                    5.101_829_712e-3,
                    1.821_153_936e-2,
                    2.620_722_293e-2,
                    1.069_792_721e1,
                ],
            ),
            _ => None,
        }
    }

    /// Checks that the law gives a finite IOR above 1 everywhere in [`VALID_RANGE`] (sampled
    /// every nm): the message names the first wavelength where it does not.
    pub fn validate(&self) -> Result<(), String> {
        let (lo, hi) = VALID_RANGE;
        let mut l = lo;
        while l <= hi {
            let n = self.ior(l);
            if !(n.is_finite() && n > 1.0) {
                return Err(format!(
                    "dispersion gives IOR {n} at {l} nm; it must be finite and > 1 over \
                     {lo}–{hi} nm"
                ));
            }
            l += 1.0;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// n_d of each named medium against the catalogue value (Schott data sheets; Malitson;
    /// water 1.3330 at 20 °C), to the catalogues' 4 decimals.
    #[test]
    fn named_media_match_their_catalogue_nd() {
        for (name, nd) in [
            ("BK7", 1.5168),
            ("N-BAF10", 1.6700),
            ("F2", 1.6200),
            ("fused silica", 1.4585),
            ("water", 1.3330),
        ] {
            let d = Dispersion::named(name).unwrap();
            assert!(
                (d.ior_d() - nd).abs() < 6e-4,
                "{name}: {} vs {nd}",
                d.ior_d()
            );
            d.validate().unwrap();
            // Normal dispersion: the IOR falls with wavelength across the visible range.
            assert!(
                d.ior(420.0) > d.ior(550.0) && d.ior(550.0) > d.ior(680.0),
                "{name}"
            );
        }
        assert!(Dispersion::named("unobtainium").is_none());
    }

    /// Abbe number V_d = (n_d − 1)/(n_F − n_C) of BK7 (64.17) and F2 (36.37): checks the slope
    /// of the law, which the deviation of a prism's colours depends on.
    #[test]
    fn abbe_numbers() {
        let abbe = |d: Dispersion| (d.ior_d() - 1.0) / (d.ior(486.13) - d.ior(656.27));
        let bk7 = abbe(Dispersion::named("bk7").unwrap());
        let f2 = abbe(Dispersion::named("f2").unwrap());
        assert!((bk7 - 64.17).abs() < 0.3, "BK7 V_d {bk7}");
        assert!((f2 - 36.37).abs() < 0.3, "F2 V_d {f2}");
    }

    /// The closed-form dn/dλ against central differences of the law in double precision, for
    /// every named medium and a Cauchy law, across the visible range.
    #[test]
    fn dior_dlambda_matches_finite_differences() {
        let mut laws: Vec<Dispersion> = NAMED
            .iter()
            .map(|n| Dispersion::named(n).unwrap())
            .collect();
        laws.push(Dispersion::Cauchy {
            a: 1.5,
            b: 0.004,
            c: 0.0001,
        });
        for d in laws {
            for l in [380.0f64, 450.0, 550.0, 650.0, 800.0] {
                let h = 1e-3;
                let fd = (d.ior_f64(l + h) - d.ior_f64(l - h)) / (2.0 * h);
                let got = d.dior_dlambda(l as f32) as f64;
                assert!(
                    (got - fd).abs() <= 1e-4 * fd.abs() + 1e-9,
                    "{d:?} at {l} nm: {got} vs {fd}"
                );
                assert!(got < 0.0, "normal dispersion at {l} nm");
            }
        }
    }

    #[test]
    fn cauchy_law() {
        let c = Dispersion::Cauchy {
            a: 1.5,
            b: 0.004,
            c: 0.0001,
        };
        // n = A + B/λ² + C/λ⁴ with λ = 0.5 µm.
        let want = 1.5 + 0.004 / 0.25 + 0.0001 / 0.0625;
        assert!((c.ior(500.0) - want).abs() < 1e-6, "{}", c.ior(500.0));
    }

    #[test]
    fn invalid_laws_are_refused_with_the_wavelength() {
        let below_one = Dispersion::Cauchy {
            a: 0.9,
            b: 0.0,
            c: 0.0,
        };
        let e = below_one.validate().unwrap_err();
        assert!(e.contains("360 nm"), "{e}");
        // A resonance inside the visible range: n² changes sign around it.
        let resonance = Dispersion::Sellmeier {
            b: [1.0, 0.0, 0.0, 0.0],
            c: [0.25, 0.0, 0.0, 0.0],
        };
        assert!(resonance.validate().is_err());
        let nan = Dispersion::Cauchy {
            a: f64::NAN,
            b: 0.0,
            c: 0.0,
        };
        assert!(nan.validate().is_err());
    }
}

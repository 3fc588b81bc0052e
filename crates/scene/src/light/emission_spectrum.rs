//! The spectral distribution of a light's emission. A light is given in RGB (its intensity,
//! radiance or irradiance `Spectrum`), which spectral mode upsamples as an illuminant (the
//! colour times D65, `Channels::illuminant`); or by a named spectrum (D65, a blackbody), whose
//! shape spectral mode evaluates at the path's wavelengths and whose linear sRGB colour the
//! light's RGB values hold, so both modes render the same light.

use caustica_core::spectral::cie::spectrum_to_xyz;
use caustica_core::spectral::{RgbIlluminant, blackbody_normalized, d65, xyz_to_linear_srgb};
use caustica_core::{Channels, Spectrum};

/// A named emission spectrum, normalised to luminance Y = 1: a light of scale `s` with it has
/// the luminance `s` an RGB light of the same scale would have if it were white.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NamedSpectrum {
    /// CIE standard illuminant D65 (daylight, 6504 K).
    D65,
    /// Planck's blackbody at a temperature (K).
    Blackbody(f32),
}

impl NamedSpectrum {
    /// Parses `d65` or `blackbody:<kelvin>` (case-insensitive; the temperature in (0, 10⁶] K).
    pub fn parse(name: &str) -> Result<Self, String> {
        let key = name.trim().to_ascii_lowercase();
        if key == "d65" {
            return Ok(NamedSpectrum::D65);
        }
        if let Some(t) = key.strip_prefix("blackbody:") {
            let k: f32 = t
                .trim()
                .parse()
                .map_err(|_| format!("blackbody temperature `{t}` is not a number"))?;
            return Self::blackbody(k);
        }
        Err(format!(
            "unknown illuminant `{name}`: expected `D65` or `blackbody:<kelvin>`"
        ))
    }

    /// A blackbody at `kelvin`, checked to be finite and in (0, 10⁶] K.
    pub fn blackbody(kelvin: f32) -> Result<Self, String> {
        if kelvin.is_finite() && kelvin > 0.0 && kelvin <= 1e6 {
            Ok(NamedSpectrum::Blackbody(kelvin))
        } else {
            Err(format!(
                "blackbody temperature must be in (0, 1e6] K, got {kelvin}"
            ))
        }
    }

    /// The unnormalised shape at `lambda_nm`.
    fn shape(&self, lambda_nm: f32) -> f32 {
        match *self {
            NamedSpectrum::D65 => d65(lambda_nm),
            NamedSpectrum::Blackbody(k) => blackbody_normalized(lambda_nm, k),
        }
    }

    /// Luminance Y of the unnormalised shape.
    fn shape_luminance(&self) -> f32 {
        spectrum_to_xyz(|l| self.shape(l))[1]
    }

    /// Linear sRGB of the normalised spectrum: the colour of a light of scale 1 in RGB mode.
    pub fn rgb(&self) -> Spectrum {
        let y = self.shape_luminance();
        let xyz = spectrum_to_xyz(|l| self.shape(l) / y);
        Spectrum::from_rgb(xyz_to_linear_srgb(xyz))
    }
}

/// How a light's RGB values become spectra in spectral mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EmissionSpectrum {
    /// The light's RGB colour upsampled as an illuminant, at each conversion.
    Rgb,
    /// The same, upsampled once ([`EmissionSpectrum::prepared`]): every value the light returns
    /// is its colour (largest component 1, `illuminant`) times a scale.
    Upsampled { illuminant: RgbIlluminant },
    /// A flat spectrum (illuminant E) of the light's grey value: Mitsuba's `scalar_spectral`
    /// reading of `<spectrum value="x">` on an emitter (grey x in RGB mode).
    Flat,
    /// A named spectrum: the light's RGB values are `scale × unit_rgb`.
    Named {
        spectrum: NamedSpectrum,
        /// The spectrum's linear sRGB (`NamedSpectrum::rgb`) and its normalisation constant,
        /// precomputed.
        unit_rgb: Spectrum,
        inv_luminance: f32,
    },
}

impl EmissionSpectrum {
    /// The emission of a light with the named spectrum.
    pub fn named(spectrum: NamedSpectrum) -> Self {
        EmissionSpectrum::Named {
            spectrum,
            unit_rgb: spectrum.rgb(),
            inv_luminance: 1.0 / spectrum.shape_luminance(),
        }
    }

    /// This emission with an RGB light of colour `colour` (any positive multiple of the values
    /// it returns, e.g. its power) upsampled once, so that conversions cost three evaluations
    /// instead of a table lookup. Named spectra and black lights are unchanged.
    pub fn prepared(self, colour: Spectrum) -> Self {
        let m = colour.max_component();
        match self {
            EmissionSpectrum::Rgb if m > 0.0 && m.is_finite() => EmissionSpectrum::Upsampled {
                illuminant: RgbIlluminant::new((colour / m).to_rgb()),
            },
            e => e,
        }
    }

    /// A value `rgb` the light returned in RGB (a weight proportional to its colour: intensity
    /// over distance², radiance, flux over densities) in the lanes `ch` of a path: the identity
    /// in RGB mode.
    #[inline]
    pub fn convert(&self, rgb: Spectrum, ch: &Channels) -> Spectrum {
        match (self, ch) {
            (_, Channels::Rgb) => rgb,
            (EmissionSpectrum::Rgb, _) => ch.illuminant(rgb),
            (EmissionSpectrum::Flat, _) => {
                let v = rgb.average();
                ch.spectrum(rgb, |_| v)
            }
            (EmissionSpectrum::Upsampled { illuminant }, _) => {
                let s = rgb.max_component();
                ch.spectrum(rgb, |l| s * illuminant.eval(l))
            }
            (
                EmissionSpectrum::Named {
                    spectrum,
                    unit_rgb,
                    inv_luminance,
                },
                _,
            ) => {
                // rgb = s · unit_rgb for the light's scale s times geometric factors.
                let unit = unit_rgb.max_component();
                let s = if unit > 0.0 {
                    rgb.max_component() / unit
                } else {
                    0.0
                };
                ch.spectrum(rgb, |l| s * spectrum.shape(l) * inv_luminance)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::spectral::SampledWavelengths;

    /// The once-upsampled colour converts every multiple of it as the per-value upsampling
    /// does (the illuminant upsampling is homogeneous of degree 1).
    #[test]
    fn prepared_emission_matches_per_value_upsampling() {
        let colour = Spectrum::new(18.387, 13.9873, 6.75357);
        let prepared = EmissionSpectrum::Rgb.prepared(colour * 3.0);
        assert!(matches!(prepared, EmissionSpectrum::Upsampled { .. }));
        for (i, k) in [0.01f32, 1.0, 250.0].into_iter().enumerate() {
            let ch = Channels::Spectral(SampledWavelengths::sample_visible(0.1 + 0.3 * i as f32));
            let a = EmissionSpectrum::Rgb.convert(colour * k, &ch);
            let b = prepared.convert(colour * k, &ch);
            for j in 0..3 {
                assert!(
                    (a.c[j] - b.c[j]).abs() <= 1e-5 * a.c[j].abs().max(1e-6),
                    "{a:?} {b:?}"
                );
            }
        }
        assert_eq!(
            EmissionSpectrum::Rgb.prepared(Spectrum::ZERO),
            EmissionSpectrum::Rgb
        );
    }

    #[test]
    fn parse_names_and_refuse_bad_ones() {
        assert_eq!(NamedSpectrum::parse("D65"), Ok(NamedSpectrum::D65));
        assert_eq!(
            NamedSpectrum::parse("blackbody:3000"),
            Ok(NamedSpectrum::Blackbody(3000.0))
        );
        assert!(NamedSpectrum::parse("blackbody:-5").is_err());
        assert!(NamedSpectrum::parse("blackbody:hot").is_err());
        assert!(
            NamedSpectrum::parse("d50")
                .unwrap_err()
                .contains("unknown illuminant")
        );
    }

    /// D65 is the sRGB white: its normalised colour is grey (1, 1, 1); a 3000 K blackbody is
    /// orange (red > green > blue), a 10⁴ K one bluish; every one has luminance 1.
    #[test]
    fn colours_of_named_spectra() {
        let w = NamedSpectrum::D65.rgb();
        for c in w.c {
            assert!((c - 1.0).abs() < 5e-3, "{w:?}");
        }
        let warm = NamedSpectrum::Blackbody(3000.0).rgb();
        assert!(warm.c[0] > warm.c[1] && warm.c[1] > warm.c[2], "{warm:?}");
        let cold = NamedSpectrum::Blackbody(10000.0).rgb();
        assert!(cold.c[2] > cold.c[0], "{cold:?}");
        for s in [warm, cold] {
            assert!((s.luminance() - 1.0).abs() < 5e-3, "{s:?}");
        }
    }

    /// A named light's spectral values, averaged over many wavelength samples through the film
    /// conversion, give back the RGB values the light holds (within 1 %).
    #[test]
    fn spectral_mode_reproduces_the_rgb_colour() {
        for named in [NamedSpectrum::D65, NamedSpectrum::Blackbody(2700.0)] {
            let e = EmissionSpectrum::named(named);
            let rgb = named.rgb() * 7.0;
            let n = 20_000;
            let mut acc = [0.0f64; 3];
            for i in 0..n {
                let ch = Channels::Spectral(SampledWavelengths::sample_visible(
                    (i as f32 + 0.5) / n as f32,
                ));
                let v = ch.to_rgb(e.convert(rgb, &ch));
                for (a, x) in acc.iter_mut().zip(v.c) {
                    *a += x as f64 / n as f64;
                }
            }
            for (k, (a, want)) in acc.iter().zip(rgb.c).enumerate() {
                let want = want as f64;
                assert!(
                    (a - want).abs() < 0.01 * want.max(0.05 * 7.0),
                    "{named:?} channel {k}: {a} vs {want}"
                );
            }
        }
    }
}

//! Participating media: what fills the space between surfaces (seed 000 ch. 8, eq. 8.1).
//!
//! A [`Medium`] has absorption and scattering coefficients σ_a, σ_s (m⁻¹, per RGB channel)
//! scaled by a dimensionless density field, and a phase function:
//!
//! * [`homogeneous`] — density 1 everywhere: σ_t = σ_a + σ_s is constant, free flights and
//!   transmittance have closed forms.
//! * [`grid`] — density on a voxel grid ([`DensityGrid`], trilinear between voxel centres, the
//!   convention of Mitsuba 3's `gridvolume`), with a coarse grid of per-cell maxima (the
//!   majorants) walked by a 3-D DDA for delta and ratio tracking.
//!
//! [`tracking`] holds the estimators both share: free-flight sampling with spectral MIS over the
//! path's three lanes, and transmittance (closed form in homogeneous media, ratio tracking in
//! grids).
//!
//! # Spectral mode
//!
//! σ_a and σ_s are given in RGB. A path carries its lanes ([`Channels`]): in RGB mode they are
//! used as they are; in spectral mode each is upsampled as an unbounded spectrum
//! ([`Channels::unbounded`], Jakob–Hanika scaled sigmoid; grey values stay flat exactly) and
//! evaluated at the path's three wavelengths, once per medium span ([`Medium::coefficients`]),
//! never per tracking step. σ_t(λ) = σ_a(λ) + σ_s(λ). The phase function does not depend on λ.
//!
//! # Where media are
//!
//! Media live inside shapes (as in Mitsuba 3 and pbrt): a shape may name the medium on its
//! inside (the −ng side) and on its outside (+ng); a shape that names neither is not a medium
//! boundary and a ray crossing or leaving it stays in the medium it was in
//! ([`crate::SurfaceInteraction::medium_toward`]). A `null` material
//! ([`crate::material::Material::Null`]) makes a boundary index-matched: rays pass through it
//! unchanged and only the medium changes. The camera and each light know the medium they sit
//! in (given by the scene, or found by [`crate::Scene::medium_at`] when the scene is built).

pub mod grid;
pub mod homogeneous;
pub mod tracking;

pub use grid::DensityGrid;
pub use homogeneous::Homogeneous;
pub use tracking::{FreeFlight, TrackingSampler};

use crate::phase::PhaseFunction;
use caustica_core::spectral::{RgbReflectance, RgbUnbounded, SampledWavelengths};
use caustica_core::{Channels, Ray, Spectrum, Vec3};
use std::sync::OnceLock;

/// The density field of a medium.
#[derive(Clone, Debug)]
pub enum MediumKind {
    Homogeneous(Homogeneous),
    Grid(DensityGrid),
}

/// A participating medium: σ_a(x) = d(x) σ_a, σ_s(x) = d(x) σ_s with d the dimensionless density
/// of its kind (1 for homogeneous media).
#[derive(Clone, Debug)]
pub struct Medium {
    pub kind: MediumKind,
    /// Absorption coefficient at density 1 (m⁻¹, per channel), `scale` already applied.
    pub sigma_a: Spectrum,
    /// Scattering coefficient at density 1 (m⁻¹, per channel), `scale` already applied.
    pub sigma_s: Spectrum,
    pub phase: PhaseFunction,
    /// How the RGB coefficients become spectra in spectral mode (no effect in RGB mode).
    pub form: SpectralForm,
    /// The coefficients upsampled (spectral mode), made on first use with the RGB values they
    /// came from (a medium whose coefficients changed since is upsampled afresh).
    spectra: OnceLock<Upsampled>,
}

/// How a medium's coefficients, given in RGB, become spectra in spectral mode.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum SpectralForm {
    /// σ_a and σ_s, each upsampled as an unbounded spectrum (caustica's TOML, pbrt-v4's
    /// `sigma_a`/`sigma_s`, Mitsuba's `sigma_a`/`sigma_s`).
    #[default]
    AbsorptionScattering,
    /// Mitsuba 3's `sigma_t` and `albedo`, upsampled as its `scalar_spectral` does: σ_t =
    /// `scale` · c with the RGB c upsampled as a reflectance (Mitsuba refuses c above 1; caustica
    /// upsamples such a c as an unbounded spectrum), the albedo α as a reflectance, and per
    /// wavelength σ_s = α σ_t, σ_a = σ_t − σ_s. `sigma_a`/`sigma_s` hold the RGB values these
    /// gave at load (`rgb`); a medium whose RGB coefficients changed since falls back to
    /// [`Self::AbsorptionScattering`].
    ExtinctionAlbedo {
        /// c (per channel, m⁻¹ before `scale`).
        sigma_t: Spectrum,
        /// Mitsuba's `scale` (or a grid's density scale with c = 1).
        scale: f32,
        /// α ∈ [0, 1] per channel.
        albedo: Spectrum,
        /// The RGB (σ_a, σ_s) made from them at load.
        rgb: [Spectrum; 2],
    },
}

/// Either kind of upsampled RGB: a reflectance-like one (values in [0, 1]) or an unbounded one.
#[derive(Clone, Copy, Debug)]
enum Sigmoid {
    Grey(f32),
    Reflectance(RgbReflectance),
    Unbounded(RgbUnbounded),
}

impl Sigmoid {
    /// `c` upsampled: grey values as flat spectra (exactly), reflectances when `bounded` and
    /// every component is at most 1, else as an unbounded spectrum.
    fn new(c: Spectrum, bounded: bool) -> Self {
        if c.c[0] == c.c[1] && c.c[1] == c.c[2] {
            Sigmoid::Grey(c.c[0])
        } else if bounded && c.max_component() <= 1.0 {
            Sigmoid::Reflectance(RgbReflectance::new(c.to_rgb()))
        } else {
            Sigmoid::Unbounded(RgbUnbounded::new(c.to_rgb()))
        }
    }

    fn sample(&self, wl: &SampledWavelengths) -> Spectrum {
        match self {
            Sigmoid::Grey(v) => Spectrum::splat(*v),
            Sigmoid::Reflectance(r) => r.sample(wl),
            Sigmoid::Unbounded(u) => u.sample(wl),
        }
    }
}

/// A medium's upsampled coefficients and the RGB values they came from: σ_a and σ_s, or σ_t
/// (before its scale) and the albedo.
#[derive(Clone, Copy, Debug)]
struct Upsampled {
    form: SpectralForm,
    rgb: [Spectrum; 2],
    spectra: [Sigmoid; 2],
}

impl Upsampled {
    fn new(form: SpectralForm, sigma_a: Spectrum, sigma_s: Spectrum) -> Self {
        let spectra = match form {
            SpectralForm::ExtinctionAlbedo {
                sigma_t, albedo, ..
            } => [Sigmoid::new(sigma_t, true), Sigmoid::new(albedo, true)],
            SpectralForm::AbsorptionScattering => {
                [Sigmoid::new(sigma_a, false), Sigmoid::new(sigma_s, false)]
            }
        };
        Self {
            form,
            rgb: [sigma_a, sigma_s],
            spectra,
        }
    }
}

/// A medium's coefficients at density 1 in a path's lanes (m⁻¹ per lane): what the tracking
/// estimators use. From [`Medium::coefficients`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    /// Scattering coefficient σ_s (m⁻¹).
    pub sigma_s: Spectrum,
    /// Extinction coefficient σ_t = σ_a + σ_s (m⁻¹).
    pub sigma_t: Spectrum,
}

/// Optical depth (σ_t times distance, dimensionless) above which tracking through a grid would
/// take too many steps: ratio tracking takes about that many steps per shadow ray.
pub const MAX_OPTICAL_DEPTH: f32 = 1e5;

impl Medium {
    /// A homogeneous medium.
    pub fn homogeneous(sigma_a: Spectrum, sigma_s: Spectrum, phase: PhaseFunction) -> Self {
        Self {
            kind: MediumKind::Homogeneous(Homogeneous),
            sigma_a,
            sigma_s,
            phase,
            form: SpectralForm::AbsorptionScattering,
            spectra: OnceLock::new(),
        }
    }
    /// A medium whose density is `grid`.
    pub fn grid(
        grid: DensityGrid,
        sigma_a: Spectrum,
        sigma_s: Spectrum,
        phase: PhaseFunction,
    ) -> Self {
        Self {
            kind: MediumKind::Grid(grid),
            sigma_a,
            sigma_s,
            phase,
            form: SpectralForm::AbsorptionScattering,
            spectra: OnceLock::new(),
        }
    }

    /// A homogeneous medium from Mitsuba's extinction `scale` · `sigma_t` (m⁻¹) and albedo,
    /// upsampled in spectral mode as Mitsuba 3's `scalar_spectral` does
    /// ([`SpectralForm::ExtinctionAlbedo`]).
    pub fn homogeneous_albedo(
        sigma_t: Spectrum,
        scale: f32,
        albedo: Spectrum,
        phase: PhaseFunction,
    ) -> Self {
        let (sa, ss) = Self::coefficients_from_albedo(sigma_t * scale, albedo);
        Self::homogeneous(sa, ss, phase).with_albedo_form(sigma_t, scale, albedo)
    }

    /// A grid medium whose density scales extinction `scale` (m⁻¹) with albedo `albedo`, as
    /// Mitsuba's `heterogeneous` medium ([`SpectralForm::ExtinctionAlbedo`] with c = 1).
    pub fn grid_albedo(
        grid: DensityGrid,
        scale: f32,
        albedo: Spectrum,
        phase: PhaseFunction,
    ) -> Self {
        let (sa, ss) = Self::coefficients_from_albedo(Spectrum::splat(scale), albedo);
        Self::grid(grid, sa, ss, phase).with_albedo_form(Spectrum::ONE, scale, albedo)
    }

    fn with_albedo_form(mut self, sigma_t: Spectrum, scale: f32, albedo: Spectrum) -> Self {
        self.form = SpectralForm::ExtinctionAlbedo {
            sigma_t,
            scale,
            albedo,
            rgb: [self.sigma_a, self.sigma_s],
        };
        self
    }
    /// From Mitsuba's parameters: extinction σ_t (m⁻¹) and single-scattering albedo α ∈ [0, 1]
    /// per channel: σ_s = α σ_t, σ_a = (1 − α) σ_t.
    pub fn coefficients_from_albedo(sigma_t: Spectrum, albedo: Spectrum) -> (Spectrum, Spectrum) {
        let sigma_s = sigma_t * albedo;
        let sigma_a = (sigma_t - sigma_s).map(|v| v.max(0.0));
        (sigma_a, sigma_s)
    }

    /// Extinction coefficient at density 1 (m⁻¹, RGB).
    #[inline]
    pub fn sigma_t(&self) -> Spectrum {
        self.sigma_a + self.sigma_s
    }

    /// σ_s and σ_t at density 1 (m⁻¹) in the lanes `ch`: the RGB values themselves in RGB mode
    /// (the same bits as [`Self::sigma_t`]); in spectral mode σ_a and σ_s upsampled as unbounded
    /// spectra (the same values as [`Channels::unbounded`]: grey values unchanged) and evaluated
    /// at the path's wavelengths. The upsampling is done once per medium; call this once per
    /// medium span (it evaluates up to six sigmoids), not per tracking step.
    #[inline]
    pub fn coefficients(&self, ch: &Channels) -> Coefficients {
        let (sigma_a, sigma_s) = match ch {
            Channels::Rgb => (self.sigma_a, self.sigma_s),
            Channels::Spectral(wl) => {
                let rgb = [self.sigma_a, self.sigma_s];
                // The form, unless the RGB coefficients were changed after it was made.
                let form = match self.form {
                    SpectralForm::ExtinctionAlbedo { rgb: made, .. } if made != rgb => {
                        SpectralForm::AbsorptionScattering
                    }
                    f => f,
                };
                let fresh;
                let mut up = self
                    .spectra
                    .get_or_init(|| Upsampled::new(form, self.sigma_a, self.sigma_s));
                if up.rgb != rgb || up.form != form {
                    fresh = Upsampled::new(form, self.sigma_a, self.sigma_s);
                    up = &fresh;
                }
                let [a, b] = up.spectra.map(|s| s.sample(wl));
                match form {
                    SpectralForm::ExtinctionAlbedo { scale, .. } => {
                        // σ_t = scale · c(λ), σ_s = α(λ) σ_t, σ_a = σ_t − σ_s.
                        let sigma_t = a * scale;
                        let sigma_s = sigma_t * b;
                        ((sigma_t - sigma_s).map(|v| v.max(0.0)), sigma_s)
                    }
                    SpectralForm::AbsorptionScattering => (a, b),
                }
            }
        };
        Coefficients {
            sigma_s,
            sigma_t: sigma_a + sigma_s,
        }
    }

    /// Dimensionless density at `p` (world space, m).
    #[inline]
    pub fn density(&self, p: Vec3) -> f32 {
        match &self.kind {
            MediumKind::Homogeneous(_) => 1.0,
            MediumKind::Grid(g) => g.density(p),
        }
    }

    /// Samples where along `ray` (unit direction) before `t_max` the next real scattering
    /// happens, or that there is none, in the lanes `ch`; see [`tracking::sample_free_flight`].
    #[inline]
    pub fn sample_free_flight(
        &self,
        ray: &Ray,
        t_max: f32,
        ch: &Channels,
        ts: &mut TrackingSampler,
    ) -> FreeFlight {
        tracking::sample_free_flight(self, &self.coefficients(ch), ray, t_max, ts)
    }

    /// Transmittance exp(−∫₀^t_max σ_t) (dimensionless, per lane of `ch`) along `ray` (unit
    /// direction): exact in homogeneous media, an unbiased ratio-tracking estimate in grids
    /// ([`tracking::transmittance`]).
    #[inline]
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_max: f32,
        ch: &Channels,
        ts: &mut TrackingSampler,
    ) -> Spectrum {
        tracking::transmittance(self, &self.coefficients(ch), ray, t_max, ts)
    }

    /// Optical depth ∫_{t0}^{t1} σ_t (dimensionless, per RGB channel) along `ray` (unit
    /// direction), deterministic: exact in homogeneous media, the midpoint rule with steps of
    /// half a voxel in grids. For density estimators (the beam estimate's transmittance to each
    /// photon), which are biased anyway and, on the photon methods' camera side, RGB in both
    /// modes (docs/spectral.md).
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Spectrum {
        if t1 <= t0 {
            return Spectrum::ZERO;
        }
        let sigma_t = self.sigma_t();
        match &self.kind {
            MediumKind::Homogeneous(_) => sigma_t * (t1 - t0),
            MediumKind::Grid(g) => sigma_t * g.integrate_density(ray, t0, t1),
        }
    }

    /// Checks the coefficients (finite, non-negative) and, for grids, that tracking ends: the
    /// optical depth across the grid's box at its densest must stay below
    /// [`MAX_OPTICAL_DEPTH`]. The message names the offending value.
    pub fn validate(&self) -> Result<(), String> {
        for (name, c) in [("sigma_a", self.sigma_a), ("sigma_s", self.sigma_s)] {
            if !c.is_finite() || c.min_component() < 0.0 {
                return Err(format!(
                    "{name} must be finite and non-negative, got {:?}",
                    c.c
                ));
            }
        }
        if let PhaseFunction::HenyeyGreenstein(hg) = self.phase {
            PhaseFunction::henyey_greenstein(hg.g)?;
        }
        if let MediumKind::Grid(g) = &self.kind {
            let depth = self.sigma_t().max_component() * g.max_density() * g.world_diagonal();
            if !depth.is_finite() || depth > MAX_OPTICAL_DEPTH {
                return Err(format!(
                    "the densest optical depth across the grid is {depth:.3e} (sigma_t {:?} × \
                     density {} × box diagonal {} m); tracking would not end in reasonable \
                     time (at most {MAX_OPTICAL_DEPTH:e})",
                    self.sigma_t().c,
                    g.max_density(),
                    g.world_diagonal()
                ));
            }
        }
        Ok(())
    }
}

/// The media on the two sides of a shape ([`crate::intersection::NONE`] = vacuum). A shape
/// whose interface names neither side is not a medium boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumInterface {
    /// Medium on the −ng side.
    pub inside: u32,
    /// Medium on the +ng side.
    pub outside: u32,
}

impl Default for MediumInterface {
    fn default() -> Self {
        Self {
            inside: crate::intersection::NONE,
            outside: crate::intersection::NONE,
        }
    }
}

impl MediumInterface {
    /// True if the shape separates media (names at least one side).
    pub fn is_transition(&self) -> bool {
        self.inside != crate::intersection::NONE || self.outside != crate::intersection::NONE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The coefficients in a path's lanes: RGB unchanged in RGB mode; in spectral mode the
    /// upsampled spectra at the path's wavelengths (the same bits as `Channels::unbounded`,
    /// greys flat), still right after the RGB values change (the memo is keyed by them).
    #[test]
    fn coefficients_are_the_upsampled_spectra_at_the_paths_wavelengths() {
        let mut m = Medium::homogeneous(
            Spectrum::splat(0.05),
            Spectrum::new(0.4, 0.5, 0.6),
            PhaseFunction::default(),
        );
        let rgb = m.coefficients(&Channels::Rgb);
        assert_eq!(rgb.sigma_s, m.sigma_s);
        assert_eq!(rgb.sigma_t, m.sigma_t());
        for u in [0.1, 0.5, 0.93] {
            let ch = Channels::Spectral(SampledWavelengths::sample_visible(u));
            let c = m.coefficients(&ch);
            assert_eq!(c.sigma_s, ch.unbounded(m.sigma_s));
            assert_eq!(c.sigma_t, Spectrum::splat(0.05) + ch.unbounded(m.sigma_s));
            // A bluish σ_s is larger at short wavelengths.
            let Channels::Spectral(wl) = ch else {
                unreachable!()
            };
            let (lo, hi) = if wl.lambda[0] < wl.lambda[1] {
                (0, 1)
            } else {
                (1, 0)
            };
            assert!(c.sigma_s[lo] > c.sigma_s[hi], "{wl:?} {c:?}");
        }
        m.sigma_a = Spectrum::new(3.0, 1.0, 0.2);
        m.sigma_s = Spectrum::splat(0.7);
        let ch = Channels::Spectral(SampledWavelengths::sample_visible(0.3));
        let c = m.coefficients(&ch);
        assert_eq!(c.sigma_s, Spectrum::splat(0.7));
        assert_eq!(c.sigma_t, ch.unbounded(m.sigma_a) + Spectrum::splat(0.7));
    }

    /// Mitsuba's σ_t and albedo in spectral mode: σ_t = scale · c(λ) and α(λ) upsampled as
    /// reflectances (`Channels::reflectance`, computed here independently of the medium's memo),
    /// σ_s = α σ_t; RGB mode is the RGB product; a c above 1 is upsampled as unbounded; and
    /// after the RGB coefficients change the medium falls back to σ_a, σ_s.
    #[test]
    fn extinction_albedo_media_upsample_as_mitsuba() {
        let (c, albedo, scale) = (
            Spectrum::new(0.9, 0.5, 0.2),
            Spectrum::new(0.3, 0.6, 0.95),
            2.0,
        );
        let mut m = Medium::homogeneous_albedo(c, scale, albedo, PhaseFunction::default());
        let rgb = m.coefficients(&Channels::Rgb);
        assert_eq!(rgb.sigma_s, c * scale * albedo);
        for u in [0.1, 0.5, 0.93] {
            let ch = Channels::Spectral(SampledWavelengths::sample_visible(u));
            let got = m.coefficients(&ch);
            let st = ch.reflectance(c) * scale;
            let ss = st * ch.reflectance(albedo);
            for k in 0..3 {
                assert!(
                    (got.sigma_t[k] - st[k]).abs() <= 1e-6 * st[k],
                    "{got:?} vs {st:?}"
                );
                assert!(
                    (got.sigma_s[k] - ss[k]).abs() <= 1e-6 * ss[k],
                    "{got:?} vs {ss:?}"
                );
            }
            // Not the σ_a, σ_s form: the two upsamplings differ for coloured media.
            let other = ch.unbounded(m.sigma_a) + ch.unbounded(m.sigma_s);
            assert!(
                (0..3).any(|k| (other[k] - st[k]).abs() > 0.01 * st[k]),
                "{other:?}"
            );
        }
        let big = Medium::homogeneous_albedo(
            Spectrum::new(3.0, 1.0, 0.5),
            1.0,
            albedo,
            PhaseFunction::default(),
        );
        let ch = Channels::Spectral(SampledWavelengths::sample_visible(0.4));
        let st = big.coefficients(&ch).sigma_t;
        let want = ch.unbounded(Spectrum::new(3.0, 1.0, 0.5));
        assert!(
            (0..3).all(|k| (st[k] - want[k]).abs() <= 1e-6 * want[k]),
            "{st:?} {want:?}"
        );
        m.sigma_s = Spectrum::splat(0.7);
        let fallback = m.coefficients(&ch);
        assert_eq!(fallback.sigma_s, Spectrum::splat(0.7));
        assert_eq!(
            fallback.sigma_t,
            ch.unbounded(m.sigma_a) + Spectrum::splat(0.7)
        );
    }
}

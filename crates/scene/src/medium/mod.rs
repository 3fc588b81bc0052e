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
use caustica_core::spectral::RgbUnbounded;
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
    /// σ_a and σ_s upsampled (spectral mode), made on first use with the RGB values they came
    /// from (a medium whose coefficients changed since is upsampled afresh).
    spectra: OnceLock<Upsampled>,
}

/// A medium's upsampled coefficients and the RGB values they came from.
#[derive(Clone, Copy, Debug)]
struct Upsampled {
    rgb: [Spectrum; 2],
    spectra: [RgbUnbounded; 2],
}

impl Upsampled {
    fn new(sigma_a: Spectrum, sigma_s: Spectrum) -> Self {
        Self {
            rgb: [sigma_a, sigma_s],
            spectra: [sigma_a, sigma_s].map(|c| RgbUnbounded::new(c.to_rgb())),
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
            spectra: OnceLock::new(),
        }
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
                let fresh;
                let mut up = self
                    .spectra
                    .get_or_init(|| Upsampled::new(self.sigma_a, self.sigma_s));
                if up.rgb != rgb {
                    fresh = Upsampled::new(self.sigma_a, self.sigma_s);
                    up = &fresh;
                }
                let lanes = |k: usize| {
                    let c = rgb[k];
                    if c.c[0] == c.c[1] && c.c[1] == c.c[2] {
                        c
                    } else {
                        up.spectra[k].sample(wl)
                    }
                };
                (lanes(0), lanes(1))
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

    /// Optical depth ∫_{t0}^{t1} σ_t (dimensionless, per lane of `ch`) along `ray` (unit
    /// direction), deterministic: exact in homogeneous media, the midpoint rule with steps of
    /// half a voxel in grids. For density estimators (the beam estimate's transmittance to each
    /// photon), which are biased anyway.
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32, ch: &Channels) -> Spectrum {
        if t1 <= t0 {
            return Spectrum::ZERO;
        }
        let sigma_t = self.coefficients(ch).sigma_t;
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
    use caustica_core::spectral::SampledWavelengths;

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
}

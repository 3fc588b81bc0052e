//! What the three lanes of a path's [`Spectrum`] mean: linear RGB channels (the default), or
//! radiometric values at three wavelengths the path sampled (spectral mode, `--spectral`).
//!
//! A path carries one [`Channels`] from its start: the camera sample or the light path draws
//! its wavelengths once (hero wavelength sampling, Wilkie et al. 2014, with three wavelengths
//! because `Spectrum` has three lanes), every RGB value of the scene it meets is turned into
//! the spectrum's values at those wavelengths ([`Channels::reflectance`],
//! [`Channels::illuminant`], [`Channels::unbounded`]: Jakob & Hanika 2019 upsampling), and what
//! the path delivers to the film or stores as a photon is turned back into linear sRGB through
//! the CIE 1931 matching functions ([`Channels::to_rgb`]). In RGB mode every conversion is the
//! identity, so RGB renders are untouched.
//!
//! At a dispersive interface the wavelengths part ways: [`Channels::terminate_secondary`]
//! keeps the hero wavelength alone, and the estimate stays unbiased because the hero is
//! distributed as every wavelength is (see `SampledWavelengths::terminate_secondary`).

use crate::Spectrum;
use crate::spectral::{RgbIlluminant, RgbReflectance, RgbUnbounded, SampledWavelengths};

/// The meaning of a path's three `Spectrum` lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Channels {
    /// Linear Rec. 709 RGB: the scene's values are used as they are.
    Rgb,
    /// Values at three sampled wavelengths (nm), with their densities.
    Spectral(SampledWavelengths),
}

impl Channels {
    /// RGB channels, or (`spectral`) three wavelengths drawn from `u` ∈ [0, 1).
    #[inline]
    pub fn sample(spectral: bool, u: impl FnOnce() -> f32) -> Self {
        if spectral {
            Channels::Spectral(SampledWavelengths::sample_visible(u()))
        } else {
            Channels::Rgb
        }
    }

    /// The hero wavelength (nm) in spectral mode.
    #[inline]
    pub fn hero(&self) -> Option<f32> {
        match self {
            Channels::Rgb => None,
            Channels::Spectral(wl) => Some(wl.hero()),
        }
    }

    /// A reflectance-like quantity in [0, 1] (albedos, tints) given in RGB, in this path's
    /// lanes. Grey values are flat spectra (returned unchanged).
    #[inline(always)]
    pub fn reflectance(&self, rgb: Spectrum) -> Spectrum {
        // RGB paths (the default) take their values as they are, without a call.
        match self {
            Channels::Rgb => rgb,
            Channels::Spectral(wl) => spectral_reflectance(wl, rgb),
        }
    }

    /// An unbounded non-negative quantity given in RGB (absorption coefficients, complex IORs),
    /// in this path's lanes. Grey values are flat spectra.
    #[inline]
    pub fn unbounded(&self, rgb: Spectrum) -> Spectrum {
        match self {
            Channels::Spectral(wl) if !is_grey(rgb) => {
                let s = RgbUnbounded::new(rgb.to_rgb());
                lanes(wl, |l| s.eval(l))
            }
            _ => rgb,
        }
    }

    /// Emitted light given in RGB (radiance W/m²/sr, intensity W/sr, irradiance W/m², flux W),
    /// in this path's lanes: the upsampled colour times the D65 illuminant, so that RGB (1, 1, 1)
    /// light is D65 white and renders as (1, 1, 1) again. Linear in its argument's scale.
    #[inline]
    pub fn illuminant(&self, rgb: Spectrum) -> Spectrum {
        match self {
            Channels::Rgb => rgb,
            Channels::Spectral(wl) => {
                let s = RgbIlluminant::new(rgb.to_rgb());
                lanes(wl, |l| s.eval(l))
            }
        }
    }

    /// A spectrum given as a function of wavelength (nm), in this path's lanes; `rgb` is its
    /// value in RGB mode.
    #[inline]
    pub fn spectrum(&self, rgb: Spectrum, f: impl Fn(f32) -> f32) -> Spectrum {
        match self {
            Channels::Rgb => rgb,
            Channels::Spectral(wl) => lanes(wl, f),
        }
    }

    /// Linear sRGB of a value in this path's lanes: the identity in RGB mode; in spectral mode
    /// the Monte Carlo estimate of its CIE XYZ through the matching functions (one sample per
    /// lane, divided by the lane's density), converted to linear sRGB. Linear in `s`, so
    /// accumulating these is accumulating XYZ.
    #[inline]
    pub fn to_rgb(&self, s: Spectrum) -> Spectrum {
        match self {
            Channels::Rgb => s,
            Channels::Spectral(wl) => wl.to_linear_srgb(s),
        }
    }

    /// Keeps only the hero wavelength from here on (a dispersive interface); nothing in RGB
    /// mode or when already done.
    #[inline]
    pub fn terminate_secondary(&mut self) {
        if let Channels::Spectral(wl) = self {
            wl.terminate_secondary();
        }
    }
}

/// Entries of [`cached_reflectance`]'s per-thread memo.
const MEMO_SIZE: usize = 32;

/// One memo entry: the RGB's bits and its upsampled reflectance.
type MemoEntry = Option<([u32; 3], RgbReflectance)>;

thread_local! {
    /// The last reflectances upsampled on this thread, direct-mapped by their RGB bits: a
    /// scene's few constant albedos are looked up in the coefficient table once per thread
    /// instead of at every hit (a pure memo: the result is the same bits either way).
    static REFLECTANCE_MEMO: std::cell::RefCell<[MemoEntry; MEMO_SIZE]> =
        const { std::cell::RefCell::new([None; MEMO_SIZE]) };
}

/// `RgbReflectance::new(rgb)`, memoised per thread.
#[inline]
fn cached_reflectance(rgb: [f32; 3]) -> RgbReflectance {
    let key = rgb.map(f32::to_bits);
    let h = key[0]
        .wrapping_mul(0x9E37_79B1)
        .wrapping_add(key[1].wrapping_mul(0x85EB_CA77))
        .wrapping_add(key[2].wrapping_mul(0xC2B2_AE3D));
    let slot = (h >> 27) as usize % MEMO_SIZE;
    REFLECTANCE_MEMO.with(|m| {
        let mut m = m.borrow_mut();
        match m[slot] {
            Some((k, r)) if k == key => r,
            _ => {
                let r = RgbReflectance::new(rgb);
                m[slot] = Some((key, r));
                r
            }
        }
    })
}

/// [`Channels::reflectance`] in spectral mode: grey values are flat spectra.
#[inline(never)]
fn spectral_reflectance(wl: &SampledWavelengths, rgb: Spectrum) -> Spectrum {
    if is_grey(rgb) {
        return rgb;
    }
    let s = cached_reflectance(rgb.to_rgb());
    lanes(wl, |l| s.eval(l))
}

#[inline]
fn is_grey(c: Spectrum) -> bool {
    c.c[0] == c.c[1] && c.c[1] == c.c[2]
}

#[inline]
fn lanes(wl: &SampledWavelengths, f: impl Fn(f32) -> f32) -> Spectrum {
    Spectrum::new(f(wl.lambda[0]), f(wl.lambda[1]), f(wl.lambda[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RGB mode converts nothing; spectral reflectances through the memo are the same bits as
    /// upsampling afresh, whatever the order of colours (collisions in the memo included).
    #[test]
    fn memo_is_transparent_and_rgb_is_identity() {
        let c = Spectrum::new(0.7, 0.2, 0.05);
        assert_eq!(Channels::Rgb.reflectance(c), c);
        assert_eq!(Channels::Rgb.illuminant(c), c);
        assert_eq!(Channels::Rgb.to_rgb(c), c);
        let ch = Channels::Spectral(SampledWavelengths::sample_visible(0.37));
        let Channels::Spectral(wl) = ch else {
            unreachable!()
        };
        for round in 0..3 {
            for i in 0..200 {
                let f = |k: u32| ((i * 37 + k * 11 + round) % 97) as f32 / 96.0;
                let rgb = Spectrum::new(f(0), f(1), f(2));
                let want = if is_grey(rgb) {
                    rgb
                } else {
                    let s = RgbReflectance::new(rgb.to_rgb());
                    lanes(&wl, |l| s.eval(l))
                };
                assert_eq!(ch.reflectance(rgb), want, "{rgb:?}");
            }
        }
        // Grey albedos are flat spectra.
        assert_eq!(ch.reflectance(Spectrum::splat(0.3)), Spectrum::splat(0.3));
    }
}

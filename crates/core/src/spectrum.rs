//! The one colour type of caustica.
//!
//! Every radiometric quantity (flux in W, irradiance in W/m², radiance in W/m²/sr, BSDF values
//! in 1/sr, throughputs, albedos) is a [`Spectrum`]. It is linear RGB (Rec. 709 primaries) today;
//! a spectral mode for dispersion can replace the representation without changing callers, which
//! only use the arithmetic below, [`Spectrum::luminance`], [`Spectrum::max_component`] and
//! [`Spectrum::to_rgb`]/[`Spectrum::from_rgb`].

use std::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Sub};

/// Linear RGB triple used for every radiometric quantity.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spectrum {
    pub c: [f32; 3],
}

impl Spectrum {
    pub const ZERO: Spectrum = Spectrum { c: [0.0; 3] };
    pub const ONE: Spectrum = Spectrum { c: [1.0; 3] };

    #[inline]
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Self { c: [r, g, b] }
    }
    #[inline]
    pub const fn splat(v: f32) -> Self {
        Self { c: [v; 3] }
    }
    #[inline]
    pub const fn from_rgb(rgb: [f32; 3]) -> Self {
        Self { c: rgb }
    }
    #[inline]
    pub const fn to_rgb(self) -> [f32; 3] {
        self.c
    }
    #[inline]
    pub fn is_black(self) -> bool {
        self.c == [0.0; 3]
    }
    /// True when every component is finite (no NaN, no ±∞).
    #[inline]
    pub fn is_finite(self) -> bool {
        self.c.iter().all(|v| v.is_finite())
    }
    #[inline]
    pub fn max_component(self) -> f32 {
        self.c[0].max(self.c[1]).max(self.c[2])
    }
    #[inline]
    pub fn min_component(self) -> f32 {
        self.c[0].min(self.c[1]).min(self.c[2])
    }
    /// Mean of the channels.
    #[inline]
    pub fn average(self) -> f32 {
        (self.c[0] + self.c[1] + self.c[2]) / 3.0
    }
    /// Photometric luminance Y of linear Rec. 709 RGB.
    #[inline]
    pub fn luminance(self) -> f32 {
        0.2126 * self.c[0] + 0.7152 * self.c[1] + 0.0722 * self.c[2]
    }
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self {
            c: [f(self.c[0]), f(self.c[1]), f(self.c[2])],
        }
    }
    #[inline]
    pub fn exp(self) -> Self {
        self.map(f32::exp)
    }
    #[inline]
    pub fn sqrt(self) -> Self {
        self.map(|v| v.max(0.0).sqrt())
    }
    /// Component-wise division that yields 0 where the divisor is 0.
    #[inline]
    pub fn safe_div(self, o: Spectrum) -> Self {
        let d = |a: f32, b: f32| if b != 0.0 { a / b } else { 0.0 };
        Self {
            c: [
                d(self.c[0], o.c[0]),
                d(self.c[1], o.c[1]),
                d(self.c[2], o.c[2]),
            ],
        }
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $op:tt, $tra:ident, $fa:ident) => {
        impl $tr for Spectrum {
            type Output = Spectrum;
            #[inline]
            fn $f(self, o: Spectrum) -> Spectrum {
                Spectrum { c: [self.c[0] $op o.c[0], self.c[1] $op o.c[1], self.c[2] $op o.c[2]] }
            }
        }
        impl $tra for Spectrum {
            #[inline]
            fn $fa(&mut self, o: Spectrum) {
                *self = *self $op o;
            }
        }
    };
}
binop!(Add, add, +, AddAssign, add_assign);
binop!(Mul, mul, *, MulAssign, mul_assign);
binop!(Div, div, /, DivAssign, div_assign);

impl Sub for Spectrum {
    type Output = Spectrum;
    #[inline]
    fn sub(self, o: Spectrum) -> Spectrum {
        Spectrum {
            c: [self.c[0] - o.c[0], self.c[1] - o.c[1], self.c[2] - o.c[2]],
        }
    }
}

impl Mul<f32> for Spectrum {
    type Output = Spectrum;
    #[inline]
    fn mul(self, s: f32) -> Spectrum {
        Spectrum {
            c: [self.c[0] * s, self.c[1] * s, self.c[2] * s],
        }
    }
}
impl Mul<Spectrum> for f32 {
    type Output = Spectrum;
    #[inline]
    fn mul(self, s: Spectrum) -> Spectrum {
        s * self
    }
}
impl MulAssign<f32> for Spectrum {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}
impl Div<f32> for Spectrum {
    type Output = Spectrum;
    #[inline]
    fn div(self, s: f32) -> Spectrum {
        self * (1.0 / s)
    }
}
impl DivAssign<f32> for Spectrum {
    #[inline]
    fn div_assign(&mut self, s: f32) {
        *self = *self / s;
    }
}
impl Index<usize> for Spectrum {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.c[i]
    }
}
impl std::iter::Sum for Spectrum {
    fn sum<I: Iterator<Item = Spectrum>>(iter: I) -> Spectrum {
        iter.fold(Spectrum::ZERO, |a, b| a + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_is_componentwise() {
        let a = Spectrum::new(1.0, 2.0, 3.0);
        let b = Spectrum::new(2.0, 0.5, 0.0);
        assert_eq!(a * b, Spectrum::new(2.0, 1.0, 0.0));
        assert_eq!(a + b, Spectrum::new(3.0, 2.5, 3.0));
        assert_eq!(a.safe_div(b), Spectrum::new(0.5, 4.0, 0.0));
        assert!((Spectrum::ONE.luminance() - 1.0).abs() < 1e-6);
        assert!(!Spectrum::new(f32::NAN, 0.0, 0.0).is_finite());
    }
}

//! Option values that carry their own rule: a value of these types is valid by construction, and
//! an invalid one is refused once, here, with one message (the CLI parses them with [`FromStr`]
//! and states the same rule in `--help`).

use crate::error::OptionError;
use std::fmt;
use std::str::FromStr;

/// Declares a newtype over `f32` whose values satisfy `$valid`, with its name in messages and
/// the rule stated in words.
macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, $what:literal, $rule:literal, |$v:ident| $valid:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
        pub struct $name(f32);

        impl $name {
            /// How the value is named in messages.
            pub const WHAT: &'static str = $what;
            /// The rule a value must satisfy, in words (as `--help` states it).
            pub const RULE: &'static str = $rule;

            /// The value `v`, or why it is refused.
            pub fn new(v: f32) -> Result<Self, OptionError> {
                let $v = v;
                if $valid {
                    Ok(Self(v))
                } else {
                    Err(OptionError::Invalid {
                        what: $what,
                        rule: $rule,
                        got: v.to_string(),
                    })
                }
            }

            pub fn get(self) -> f32 {
                self.0
            }
        }

        impl FromStr for $name {
            type Err = OptionError;
            fn from_str(s: &str) -> Result<Self, OptionError> {
                let v: f32 = s.trim().parse().map_err(|_| OptionError::Unparsable {
                    what: $what,
                    rule: "a number",
                    got: s.to_string(),
                })?;
                Self::new(v)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

checked_f32!(
    /// The smoothing parameter s of photon differentials (seed 002 eq. 5–6): the emitted
    /// footprints tile the light's area and solid angle s² times. Unitless.
    Smoothing,
    "the smoothing parameter s (--smoothing)",
    "a positive finite number",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The fixed bandwidth h (m) of the `fixed` and diffusion estimators (eq. 2.15, 4.19).
    Bandwidth,
    "the bandwidth (--bandwidth)",
    "a positive finite length",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The first iteration's gather radius (m) of the progressive methods (`--radius`).
    Radius,
    "the first gather radius (--radius)",
    "a positive finite length",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The noise scale σ (m) of the diffusion estimator's gradient pre-pass (sec. 4.3.1).
    NoiseScale,
    "the noise scale (--noise-scale)",
    "a positive finite length",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The diffusivity coefficient q of eq. 4.15 (unitless; large = no adaptation).
    Diffusivity,
    "the diffusivity coefficient q (--q)",
    "a positive finite number",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The steepness α of eq. 4.15 (unitless).
    Steepness,
    "the steepness (--alpha)",
    "a positive finite number",
    |v| v.is_finite() && v > 0.0
);

checked_f32!(
    /// The normal-distance threshold against topological bias (seed 002 sec. 3.3), as a
    /// fraction of a footprint's gather radius; `inf` disables the test.
    NormalDistance,
    "the normal-distance threshold (--normal-distance)",
    "≥ 0 (a fraction of the footprint's gather radius; inf disables it)",
    |v| v >= 0.0
);

checked_f32!(
    /// The hybrid integrator's share of a time budget given to its light tracer
    /// (`--light-share`; the path tracer has the rest). Unitless.
    LightShare,
    "the light tracer's share of the time (--light-share)",
    "a number strictly between 0 and 1",
    |v| v > 0.0 && v < 1.0
);

impl LightShare {
    /// The default share: better than 0.25 on the glass sphere and the gold ring, within 13 %
    /// of 0.7 there without starving the path tracer elsewhere (docs/results/hybrid/share.md).
    pub const DEFAULT: Self = Self(0.5);
}

impl Smoothing {
    /// s = 1: the emitted footprints tile the light once.
    pub const ONE: Smoothing = Smoothing(1.0);
}

impl NormalDistance {
    /// A quarter of the gather radius (the default).
    pub const QUARTER: NormalDistance = NormalDistance(0.25);
    /// No normal-distance test.
    pub const OFF: NormalDistance = NormalDistance(f32::INFINITY);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rule_refuses_what_it_states() {
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(Smoothing::new(bad).is_err(), "{bad}");
            assert!(Bandwidth::new(bad).is_err(), "{bad}");
            assert!(NoiseScale::new(bad).is_err(), "{bad}");
            assert!(Diffusivity::new(bad).is_err(), "{bad}");
            assert!(Steepness::new(bad).is_err(), "{bad}");
        }
        assert_eq!(Smoothing::new(2.5).map(Smoothing::get), Ok(2.5));
        for bad in [-0.1, f32::NAN, f32::NEG_INFINITY] {
            assert!(NormalDistance::new(bad).is_err(), "{bad}");
        }
        assert_eq!(NormalDistance::new(0.0).map(NormalDistance::get), Ok(0.0));
        assert_eq!("inf".parse::<NormalDistance>(), Ok(NormalDistance::OFF));
    }

    #[test]
    fn messages_name_the_value_the_rule_and_what_was_given() {
        let e = "-1".parse::<Smoothing>().unwrap_err().to_string();
        assert_eq!(
            e,
            "the smoothing parameter s (--smoothing) must be a positive finite number, got -1"
        );
        let e = "x".parse::<Smoothing>().unwrap_err().to_string();
        assert_eq!(
            e,
            "the smoothing parameter s (--smoothing): 'x' is not a number"
        );
        let e = Bandwidth::new(-2.0).unwrap_err().to_string();
        assert_eq!(
            e,
            "the bandwidth (--bandwidth) must be a positive finite length, got -2"
        );
    }
}

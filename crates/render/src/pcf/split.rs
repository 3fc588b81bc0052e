//! Where a camera path stops path tracing and looks up the cone map: seed 001 eq. 3.14 and
//! Alg. 1 lines 12–15, read so that every full path is counted exactly once (spec notes
//! sec. 2.3, an erratum of eq. 3.14, which strips the emission at the lookup vertex x_k while
//! Alg. 1 counts "path lengths ≤ index"):
//!
//! * the unbiased part counts the paths whose last camera-side scattering is x_j, j < k:
//!   emission found at x_1 … x_k, and next-event estimation at x_1 … x_{k−1}, combined by MIS
//!   as in the path tracer;
//! * the cone estimate at x_k (cones of every light-path length ≥ 1) counts every path that
//!   scatters at x_k.
//!
//! Nested PCF (sec. 3.6; spec notes sec. 2.10 [INF]) replaces next-event estimation at
//! x_1 … x_{k−1} by the cone estimate restricted to light-path-length-1 cones (direct light),
//! and then the emission found by the bounce after x_j (j ≥ 1) is not counted: it is in x_j's
//! direct estimate. Emission seen at x_1 (an emitter seen directly) is always counted.
//!
//! Any rule for k that depends only on the camera prefix keeps this partition.

use crate::integrator::path::Direct;
use crate::options::{LookupRule, Nesting};
use crate::pcf::cone_map::ConeSet;
use caustica_core::Spectrum;
use caustica_scene::bsdf::BsdfFlags;

/// The split of a camera path between path tracing and the cone map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathSplit {
    pub rule: LookupRule,
    pub nested: Nesting,
    /// Next-event estimation for the direct light at non-delta lookup vertices.
    pub lookup_nee: bool,
}

impl PathSplit {
    /// True if the camera vertex at `depth` (1 = first hit) with BSDF `flags`, reached with no
    /// lookup before, is the lookup vertex x_k.
    pub fn is_lookup(&self, depth: u32, flags: BsdfFlags) -> bool {
        match self.rule {
            LookupRule::First => depth == 1,
            LookupRule::NonDelta => flags.is_smooth(),
            LookupRule::Diffuse => flags.contains(BsdfFlags::DIFFUSE),
            LookupRule::Bounce(n) => depth == n,
        }
    }

    /// Whether a lookup vertex with BSDF `flags` takes its direct light from NEE (then the cone
    /// estimate there sums lengths ≥ 2 only) or from length-1 cones (all lengths). NEE finds
    /// nothing at a delta vertex, which therefore always uses cones.
    pub fn nee_at_lookup(&self, flags: BsdfFlags) -> bool {
        self.lookup_nee && flags.is_smooth()
    }

    /// The cones the lookup at a vertex with BSDF `flags` sums.
    pub fn lookup_set(&self, flags: BsdfFlags) -> ConeSet {
        if self.nee_at_lookup(flags) {
            ConeSet::Indirect
        } else {
            ConeSet::All
        }
    }

    /// How a camera vertex before the lookup with BSDF `flags` gets its direct light (the
    /// spectrum is a placeholder the caller fills with the cone estimate): `Nesting::Off` NEE;
    /// `DeltaLights` adds delta lights' length-1 cones at delta vertices (where NEE finds
    /// nothing and no bounce can hit a delta light) and keeps NEE and emission hits for the
    /// rest; `All` replaces NEE and the next emission hit by all length-1 cones.
    pub fn direct_at(&self, flags: BsdfFlags) -> Direct {
        match self.nested {
            Nesting::Off => Direct::Nee,
            Nesting::DeltaLights if !flags.is_smooth() => Direct::Add(Spectrum::ZERO),
            Nesting::DeltaLights => Direct::Nee,
            Nesting::All => Direct::Replace(Spectrum::ZERO),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights with which the estimator counts a full camera-side path x_1 … x_m followed
    /// by an emitter (m = 0: the emitter seen directly), delta (point, spot, …) or not: the
    /// bookkeeping of `path::radiance_with` under the PCF rule, as weights that must sum to 1.
    fn count(split: PathSplit, prefix: &[BsdfFlags], m: usize, delta_light: bool) -> f64 {
        // k: the first vertex of the prefix the rule looks up at (none: path tracing only).
        let k = (0..prefix.len())
            .find(|&j| split.is_lookup(j as u32 + 1, prefix[j]))
            .map(|j| j + 1);
        if m == 0 {
            return 1.0; // emission at x_1 with weight 1 (a non-delta emitter seen directly)
        }
        if let Some(k) = k
            && m >= k
        {
            // At x_k: NEE without MIS counts the paths whose last scattering is x_k (m = k,
            // a length-1 cone), the cones the set admits the others.
            let nee = split.nee_at_lookup(prefix[k - 1]);
            let set = split.lookup_set(prefix[k - 1]);
            let length = (m - k + 1) as u32;
            let by_nee = if nee && m == k { 1.0 } else { 0.0 };
            let by_cones = if set.admits_length(length, delta_light) {
                1.0
            } else {
                0.0
            };
            return by_nee + by_cones;
        }
        // Last scattering at x_m, m < k: what x_m's direct term and the emission hit found by
        // its bounce count.
        let flags = prefix[m - 1];
        let (w_bsdf, w_nee) = (0.3, 0.7); // any MIS pair summing to 1
        let mut total = 0.0;
        let mut emission_counted = true;
        match split.direct_at(flags) {
            Direct::Nee => {
                if flags.is_smooth() {
                    // NEE reaches every light; MIS with the emission hit of non-delta ones.
                    total += if delta_light { 1.0 } else { w_nee };
                    if !delta_light {
                        total += w_bsdf;
                    }
                    emission_counted = false;
                }
            }
            Direct::Add(_) => {
                // Delta lights' length-1 cones at a delta vertex.
                if ConeSet::DirectFromDeltaLights.admits_length(1, delta_light) {
                    total += 1.0;
                }
            }
            Direct::Replace(_) => {
                // Every light's length-1 cones; the next emission hit weighs 0.
                if ConeSet::Direct.admits_length(1, delta_light) {
                    total += 1.0;
                }
                emission_counted = false;
            }
        }
        // At a delta vertex under NEE or Add, the bounce hits a non-delta emitter with
        // weight 1 (NEE finds nothing there); a delta light cannot be hit.
        if emission_counted && !delta_light {
            total += 1.0;
        }
        total
    }

    #[test]
    fn every_path_is_counted_once_for_every_rule_and_nesting() {
        // T-5: enumerate camera prefixes of up to 5 vertices over delta / glossy / diffuse
        // surfaces, every rule and nesting, every path length, delta and area lights. Without
        // nesting, paths from a delta light whose last camera-side scattering is delta are
        // not counted (0): the gap nesting fills.
        let kinds = [
            BsdfFlags::DELTA | BsdfFlags::REFLECTION,
            BsdfFlags::GLOSSY | BsdfFlags::REFLECTION,
            BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION,
        ];
        let rules = [
            LookupRule::First,
            LookupRule::NonDelta,
            LookupRule::Diffuse,
            LookupRule::Bounce(2),
            LookupRule::Bounce(3),
        ];
        let (mut checked, mut gaps) = (0, 0);
        for len in 1..=5usize {
            for code in 0..3usize.pow(len as u32) {
                let prefix: Vec<BsdfFlags> = (0..len)
                    .map(|j| kinds[(code / 3usize.pow(j as u32)) % 3])
                    .collect();
                for rule in rules {
                    for (nested, lookup_nee) in [
                        (Nesting::Off, false),
                        (Nesting::DeltaLights, true),
                        (Nesting::DeltaLights, false),
                        (Nesting::All, true),
                    ] {
                        let split = PathSplit {
                            rule,
                            nested,
                            lookup_nee,
                        };
                        for m in 0..=len {
                            for delta_light in [false, true] {
                                if m == 0 && delta_light {
                                    continue; // a delta light is never seen directly
                                }
                                let c = count(split, &prefix, m, delta_light);
                                let gap = nested == Nesting::Off
                                    && delta_light
                                    && m >= 1
                                    && !prefix[m - 1].is_smooth()
                                    && (0..m).all(|j| !split.is_lookup(j as u32 + 1, prefix[j]));
                                let want = if gap { 0.0 } else { 1.0 };
                                assert_eq!(
                                    c, want,
                                    "{rule:?} {nested:?} {prefix:?} m {m} delta light {delta_light}"
                                );
                                gaps += gap as usize;
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(checked > 1000 && gaps > 0);
    }

    #[test]
    fn rules_pick_the_vertex_they_name() {
        let delta = BsdfFlags::DELTA | BsdfFlags::TRANSMISSION;
        let glossy = BsdfFlags::GLOSSY | BsdfFlags::REFLECTION;
        let diffuse = BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION;
        let s = |rule| PathSplit {
            rule,
            nested: Nesting::Off,
            lookup_nee: true,
        };
        assert!(s(LookupRule::First).is_lookup(1, delta));
        assert!(!s(LookupRule::NonDelta).is_lookup(1, delta));
        assert!(s(LookupRule::NonDelta).is_lookup(2, glossy));
        assert!(!s(LookupRule::Diffuse).is_lookup(2, glossy));
        assert!(s(LookupRule::Diffuse).is_lookup(3, diffuse));
        assert!(s(LookupRule::Bounce(2)).is_lookup(2, delta));
        assert!(!s(LookupRule::Bounce(2)).is_lookup(1, diffuse));
    }
}

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

use crate::options::LookupRule;
use caustica_scene::bsdf::BsdfFlags;

/// The split of a camera path between path tracing and the cone map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathSplit {
    pub rule: LookupRule,
    pub nested: bool,
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The terms of the estimator that count a full camera-side path x_1 … x_m followed by an
    /// emitter (m = 0: the emitter is seen directly): the bookkeeping of
    /// `path::radiance_with` under the PCF rule, counted as weights that must sum to 1.
    fn count(split: PathSplit, prefix: &[BsdfFlags], m: usize) -> f64 {
        // k: the first vertex of the prefix the rule looks up at (none: path tracing only).
        let k = (0..prefix.len())
            .find(|&j| split.is_lookup(j as u32 + 1, prefix[j]))
            .map(|j| j + 1);
        if m == 0 {
            return 1.0; // emission at x_1, weight 1
        }
        let mut total = 0.0;
        match k {
            Some(k) if m >= k => total += 1.0, // the cone estimate at x_k
            _ => {
                // Last scattering at x_m, m < k: emission found at x_{m+1} and NEE at x_m.
                let smooth = prefix[m - 1].is_smooth();
                if split.nested {
                    total += 1.0; // length-1 cones at x_m; the emission hit weighs 0
                } else if smooth {
                    let (w_bsdf, w_nee) = (0.3, 0.7); // any MIS pair summing to 1
                    total += w_bsdf + w_nee;
                } else {
                    total += 1.0; // delta: emission weight 1, NEE finds nothing
                }
            }
        }
        total
    }

    #[test]
    fn every_path_is_counted_once_for_every_rule_with_and_without_nesting() {
        // T-5: enumerate camera prefixes of up to 5 vertices over delta / glossy / diffuse
        // surfaces, every rule and nesting, every path length.
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
        let mut checked = 0;
        for len in 1..=5usize {
            for code in 0..3usize.pow(len as u32) {
                let prefix: Vec<BsdfFlags> = (0..len)
                    .map(|j| kinds[(code / 3usize.pow(j as u32)) % 3])
                    .collect();
                for rule in rules {
                    for nested in [false, true] {
                        let split = PathSplit { rule, nested };
                        for m in 0..=len {
                            let c = count(split, &prefix, m);
                            assert_eq!(c, 1.0, "{rule:?} nested {nested} {prefix:?} m {m}");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 1000);
    }

    #[test]
    fn rules_pick_the_vertex_they_name() {
        let delta = BsdfFlags::DELTA | BsdfFlags::TRANSMISSION;
        let glossy = BsdfFlags::GLOSSY | BsdfFlags::REFLECTION;
        let diffuse = BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION;
        let s = |rule| PathSplit {
            rule,
            nested: false,
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

//! Path length limits: the maximum depth and Russian roulette, the same rule for camera and
//! light paths.

/// How long a path may grow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathLimits {
    /// Longest path in edges, Mitsuba's convention: 1 = emitters seen directly, 2 = direct
    /// lighting, … `u32::MAX` = unlimited (Russian roulette ends paths).
    pub max_depth: u32,
    /// Russian roulette starts after this many edges.
    pub rr_depth: u32,
}

impl Default for PathLimits {
    fn default() -> Self {
        Self {
            max_depth: u32::MAX,
            rr_depth: 5,
        }
    }
}

/// Russian roulette after `depth` edges: from `rr_depth` on, a path survives with probability
/// q = min(max channel of `beta`, 0.95) (Mitsuba's rule) and its throughput is divided by q.
/// Returns false when the path ends. `u` is the uniform number reserved for the decision.
#[inline]
pub fn russian_roulette(
    beta: &mut caustica_core::Spectrum,
    depth: u32,
    rr_depth: u32,
    u: f32,
) -> bool {
    if depth < rr_depth {
        return true;
    }
    let q = beta.max_component().min(0.95);
    if u >= q {
        return false;
    }
    *beta /= q;
    true
}

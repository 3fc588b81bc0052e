//! Why a differential could not be propagated.

use thiserror::Error;

/// The defined failure modes of the differential algebra. Every public operation either
/// returns finite values or one of these; none returns NaN.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum DiffError {
    /// The ray is (numerically) parallel to the plane: `|Vᵀ N| ≤ PARALLEL_COS·|V|·|N|`, so the
    /// transfer distance of eq. B.26 and its differential eq. B.27 are undefined. At emission
    /// ([`crate::emission`]) the same test on the emitter's normal: a photon leaving the emitter
    /// tangentially has a positional differential along its own direction (seed 002 eq. 3
    /// gives `D_v x ∥ ω`) and no cross-section.
    #[error("ray is parallel to the surface plane")]
    Parallel,
    /// The plane is hit at `s ≤ 0`; eq. B.15 asks for the smallest `s* > 0`.
    #[error("surface plane lies behind the ray origin")]
    BehindOrigin,
    /// The triangle's edges are (numerically) collinear or coincident, so its normal
    /// `n = (Q₂ − Q₀) × (Q₁ − Q₀)` (eq. B.30, B.35a) cannot be normalised.
    #[error("degenerate triangle")]
    DegenerateTriangle,
    /// The interpolated Phong normal `n = Σ λᵢ Nᵢ` (eq. B.42a) vanishes.
    #[error("interpolated shading normal vanishes")]
    DegenerateNormal,
    /// A zero direction vector was given where eq. B.1b must normalise it.
    #[error("zero direction vector")]
    ZeroDirection,
    /// `ξ ≤ 0` in eq. B.20b: no transmitted ray exists.
    #[error("total internal reflection")]
    TotalInternalReflection,
    /// The result overflowed (e.g. a grazing refraction whose `1/√ξ` in eq. B.22b explodes),
    /// or an input (origin, differential vector, flux) was not finite.
    #[error("differential is not finite")]
    NonFinite,
    /// The smoothing parameter `s` of seed 002 eq. 5–6 is not finite and positive.
    #[error("smoothing parameter s must be finite and > 0")]
    InvalidSmoothing,
    /// The photon count `N_e` of seed 002 eq. 5–6 is zero.
    #[error("number of emitted photons must be > 0")]
    NoPhotons,
    /// An emission extent is invalid: an area (m²) or solid angle (sr) that is negative or not
    /// finite, a solid angle above 4π, a spot cut-off cosine outside [−1, 1), a beam radius
    /// ≤ 0, or an emitter with neither area nor solid angle (both differentials zero, eq. 5–6).
    #[error("invalid emission area or solid angle")]
    InvalidExtent,
    /// The photon footprint has collapsed: `|D_u x × D_v x| ≤ COLLAPSED_SIN·|D_u x|·|D_v x|`
    /// after projection onto the receiving plane, or a differential vector is zero, so the
    /// area of seed 002 eq. 4 vanishes and the filter matrix of eq. 12 is singular (the seed
    /// discards such photons, sec. 3.3).
    #[error("photon footprint has collapsed")]
    CollapsedFootprint,
}

//! Why a differential could not be propagated.

use thiserror::Error;

/// The defined failure modes of the differential algebra. Every public operation either
/// returns finite values or one of these; none returns NaN.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum DiffError {
    /// The ray is (numerically) parallel to the plane: `|Vᵀ N| ≤ PARALLEL_COS·|V|·|N|`, so the
    /// transfer distance of eq. B.26 and its differential eq. B.27 are undefined.
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
    /// The result overflowed (e.g. a grazing refraction whose `1/√ξ` in eq. B.22b explodes).
    #[error("differential is not finite")]
    NonFinite,
}

//! Transfer: moving a ray differential along its ray onto a surface (seed 000 app. B.2.1,
//! eq. B.13–B.16, with the plane constraint of B.3.1, eq. B.24–B.29).

use caustica_core::{Mat3, Vec3};

use crate::ray_differential::all_finite;
use crate::{DiffError, RayDiff};

/// Rays with `|Vᵀ N| ≤ PARALLEL_COS · ‖V‖ ‖N‖` count as parallel to a plane
/// ([`DiffError::Parallel`]): the cosine below which eq. B.26 is not evaluated.
pub const PARALLEL_COS: f32 = 1e-6;

/// `|Vᵀ N| > PARALLEL_COS ‖V‖ ‖N‖` for `vn = Vᵀ N`, compared in squares (no square roots);
/// false for NaN.
#[inline]
fn is_transversal(vn: f32, v: Vec3, n: Vec3) -> bool {
    vn * vn > PARALLEL_COS * PARALLEL_COS * v.length_squared() * n.length_squared()
}

/// A ray differential transferred onto a plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transferred<const N: usize> {
    /// The transferred ray: `p = Q` (eq. B.13a, m), `v = W = V` (eq. B.13b), `dp[i] = ∂Q/∂θᵢ`
    /// (eq. B.16a), `dv[i] = ∂W/∂θᵢ = ∂V/∂θᵢ` (eq. B.16b).
    pub ray: RayDiff<N>,
    /// Transfer distance `s` (eq. B.26; m, since `V` is unit).
    pub s: f32,
    /// `∂s/∂θᵢ` (eq. B.27; m per unit of θᵢ).
    pub ds: [f32; N],
}

/// Transfers `ray` onto the plane through `q0` (m) with normal `normal` (any non-zero length;
/// the result does not depend on it), where the plane itself may depend on the parameters:
/// `dq0[i] = ∂Q₀/∂θᵢ` and `dnormal[i] = ∂N/∂θᵢ` (zero for a stationary plane).
///
/// Implements eq. B.24–B.26 for `s`, eq. B.27c for `ds`, eq. B.13 and eq. B.16 for `Q`, `W`
/// and their differentials (equivalently the matrix form eq. B.28a–b with `K`, `L` of
/// eq. B.29, see [`transfer_jacobians`]).
///
/// Errors: [`DiffError::Parallel`] if the ray is parallel to the plane,
/// [`DiffError::BehindOrigin`] if `s ≤ 0`, [`DiffError::NonFinite`] on overflow.
pub fn transfer_to_plane<const N: usize>(
    ray: &RayDiff<N>,
    q0: Vec3,
    dq0: &[Vec3; N],
    normal: Vec3,
    dnormal: &[Vec3; N],
) -> Result<Transferred<N>, DiffError> {
    let (p, v, n) = (ray.p, ray.v, normal);
    let vn = v.dot(n);
    if !is_transversal(vn, v, n) {
        return Err(DiffError::Parallel);
    }
    let q0p = q0 - p;
    let s = q0p.dot(n) / vn; // eq. B.26
    if !(s > 0.0) {
        return Err(DiffError::BehindOrigin);
    }
    let mut ds = [0.0; N];
    let mut dq = [Vec3::ZERO; N];
    for i in 0..N {
        // eq. B.27c: ds = (Nᵀ(dQ₀ − dP) + (Q₀ − P)ᵀ dN − s (Nᵀ dV + Vᵀ dN)) / (Vᵀ N)
        ds[i] = (n.dot(dq0[i] - ray.dp[i]) + q0p.dot(dnormal[i])
            - s * (n.dot(ray.dv[i]) + v.dot(dnormal[i])))
            / vn;
        // eq. B.16a: dQ = dP + V ds + s dV
        dq[i] = ray.dp[i] + v * ds[i] + s * ray.dv[i];
    }
    let q = p + s * v; // eq. B.13a
    // eq. B.13b and B.16b: W = V, dW = dV.
    let out = RayDiff::new(q, v, dq, ray.dv).finite_or_err()?;
    if !all_finite(std::iter::once(s).chain(ds)) {
        return Err(DiffError::NonFinite);
    }
    Ok(Transferred { ray: out, s, ds })
}

/// [`transfer_to_plane`] onto a plane that does not depend on the parameters (`dQ₀ = 0`,
/// `dN = 0`): eq. B.27c reduces to `ds = −Nᵀ(dP + s dV) / (Vᵀ N)`, the transfer of Igehy 1999.
/// Same results and errors, without the zero terms.
pub fn transfer_to_fixed_plane<const N: usize>(
    ray: &RayDiff<N>,
    q0: Vec3,
    normal: Vec3,
) -> Result<Transferred<N>, DiffError> {
    let (p, v, n) = (ray.p, ray.v, normal);
    let vn = v.dot(n);
    if !is_transversal(vn, v, n) {
        return Err(DiffError::Parallel);
    }
    let inv_vn = 1.0 / vn;
    let s = (q0 - p).dot(n) * inv_vn; // eq. B.26
    if !(s > 0.0) {
        return Err(DiffError::BehindOrigin);
    }
    let mut ds = [0.0; N];
    let mut dq = [Vec3::ZERO; N];
    for i in 0..N {
        let moved = ray.dp[i] + s * ray.dv[i];
        ds[i] = -n.dot(moved) * inv_vn; // eq. B.27c with dQ₀ = 0, dN = 0
        dq[i] = moved + v * ds[i]; // eq. B.16a: dQ = dP + V ds + s dV
    }
    let q = p + s * v; // eq. B.13a
    let out = RayDiff::new(q, v, dq, ray.dv).finite_or_err()?; // eq. B.13b, B.16b
    if !all_finite(std::iter::once(s).chain(ds)) {
        return Err(DiffError::NonFinite);
    }
    Ok(Transferred { ray: out, s, ds })
}

/// The matrices of the flat-surface transfer in matrix form (eq. B.28a–B.29):
/// `dQ = K dP + s K dV + (I₃ − K) dQ₀ + L dN`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransferJacobians {
    /// Transfer distance `s` (eq. B.26, m).
    pub s: f32,
    /// `K = I₃ − V Nᵀ / (Vᵀ N)` (eq. B.29a, unitless).
    pub k: Mat3,
    /// `L = (V (Q₀ − P)ᵀ − s V Vᵀ) / (Vᵀ N)` (eq. B.29b, m).
    pub l: Mat3,
}

/// `a bᵀ` as a glam matrix (glam is column-major: column `j` is `a b_j`).
#[inline]
pub(crate) fn outer(a: Vec3, b: Vec3) -> Mat3 {
    Mat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Computes `K`, `L` and `s` of eq. B.26 and B.29 for a ray from `p` in unit direction `v`
/// onto the plane through `q0` with unit normal `normal`. The per-parameter
/// [`transfer_to_plane`] is what the renderer should call; this matrix form is the
/// appendix's own statement and is kept to check one against the other.
pub fn transfer_jacobians(
    p: Vec3,
    v: Vec3,
    q0: Vec3,
    normal: Vec3,
) -> Result<TransferJacobians, DiffError> {
    let vn = v.dot(normal);
    if !is_transversal(vn, v, normal) {
        return Err(DiffError::Parallel);
    }
    let s = (q0 - p).dot(normal) / vn; // eq. B.26
    if !(s > 0.0) {
        return Err(DiffError::BehindOrigin);
    }
    let k = Mat3::IDENTITY - outer(v, normal) / vn; // eq. B.29a
    let l = (outer(v, q0 - p) - s * outer(v, v)) / vn; // eq. B.29b
    Ok(TransferJacobians { s, k, l })
}

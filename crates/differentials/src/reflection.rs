//! Mirror reflection of a ray differential (seed 000 app. B.2.2, eq. B.17–B.18).

use caustica_core::{Mat3, Vec3};

use crate::transfer::outer;
use crate::{DiffError, RayDiff};

/// Reflects a ray differential that has been transferred onto a surface (its `p` is the hit
/// point `Q`, its `v` the incoming unit direction `V`) about the unit normal `normal` with
/// derivatives `dnormal[i] = ∂N/∂θᵢ` (zero on a stationary flat surface).
///
/// * `Q_reflect = Q`, `dQ_reflect = dQ` (eq. B.17a);
/// * `W = V − 2 (Vᵀ N) N` (eq. B.17b), unit since `V` and `N` are;
/// * `dW = dV − 2((dVᵀ N + Vᵀ dN) N + (Vᵀ N) dN)` (eq. B.18a), which is
///   `(I₃ − 2 N Nᵀ) dV − 2 (Vᵀ N I₃ + N Vᵀ) dN` (eq. B.18b) and, for `dN = 0`, eq. B.28c.
///
/// The result does not depend on the sign of `normal`. Returns [`DiffError::NonFinite`] only
/// if the input was not finite.
pub fn reflect<const N: usize>(
    ray: &RayDiff<N>,
    normal: Vec3,
    dnormal: &[Vec3; N],
) -> Result<RayDiff<N>, DiffError> {
    let (v, n) = (ray.v, normal);
    let vn = v.dot(n);
    let w = v - 2.0 * vn * n; // eq. B.17b
    let dw = std::array::from_fn(|i| {
        let (dv, dn) = (ray.dv[i], dnormal[i]);
        dv - 2.0 * ((dv.dot(n) + v.dot(dn)) * n + vn * dn) // eq. B.18a
    });
    RayDiff::new(ray.p, w, ray.dp, dw).finite_or_err() // eq. B.17a: Q and dQ unchanged
}

/// The Jacobians of eq. B.18b, `dW = A dV + B dN` with `A = I₃ − 2 N Nᵀ` and
/// `B = −2 (Vᵀ N I₃ + N Vᵀ)`, returned as `(A, B)`. Multiplying `B` by the normal's Jacobians
/// gives the gathered forms eq. B.28c (flat, `dN = 0`) and eq. B.52 (Phong, `M = B J`).
pub fn reflection_jacobians(v: Vec3, normal: Vec3) -> (Mat3, Mat3) {
    let (n, vn) = (normal, v.dot(normal));
    let a = Mat3::IDENTITY - 2.0 * outer(n, n);
    let b = -2.0 * (Mat3::from_diagonal(Vec3::splat(vn)) + outer(n, v));
    (a, b)
}

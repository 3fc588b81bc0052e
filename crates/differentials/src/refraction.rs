//! Refraction of a ray differential (seed 000 app. B.2.3, eq. B.19–B.23).

use caustica_core::{Mat3, Vec3};

use crate::transfer::outer;
use crate::{DiffError, RayDiff};

/// The refracted direction and the coefficient `μ` (eq. B.19b–B.20) without differentials,
/// or `None` under total internal reflection. `v`, `normal` unit, `eta = n_incident /
/// n_transmitted`; `normal` is flipped if needed so that `Vᵀ N ≤ 0`.
pub fn refract_direction(v: Vec3, normal: Vec3, eta: f32) -> Option<Vec3> {
    let n = if v.dot(normal) > 0.0 { -normal } else { normal };
    let vn = v.dot(n);
    let xi = 1.0 - eta * eta * (1.0 - vn * vn); // eq. B.20b
    if !(xi > 0.0) {
        return None;
    }
    let mu = eta * vn + xi.sqrt(); // eq. B.20a
    Some(eta * v - mu * n) // eq. B.19b
}

/// Refracts a ray differential that has been transferred onto a surface (its `p` is the hit
/// point `Q`, its `v` the incoming unit direction `V`) through the interface with unit normal
/// `normal` and derivatives `dnormal[i] = ∂N/∂θᵢ`.
///
/// `eta` is the ratio of refractive indices `η = n_incident / n_transmitted` (unitless, taken
/// constant in θ as the appendix assumes before eq. B.21): 1/1.5 entering glass from air.
/// The appendix's formulas assume `Vᵀ N < 0` (the convention of eq. B.30); if `normal` points
/// along `V` it is negated together with `dnormal`, which changes nothing geometrically.
///
/// * `Q_refract = Q`, `dQ_refract = dQ` (eq. B.19a);
/// * `W = η V − μ N`, `μ = η Vᵀ N + √ξ`, `ξ = 1 − η² (1 − (Vᵀ N)²)` (eq. B.19b–B.20b), unit
///   since `V` and `N` are;
/// * `dμ = η (Nᵀ dV + Vᵀ dN) (1 + η Vᵀ N / √ξ)` (eq. B.22a–d, from
///   `dξ = 2 η² (Vᵀ N)(dVᵀ N + Vᵀ dN)`);
/// * `dW = η dV − N dμ − μ dN` (eq. B.21b), which gathers to eq. B.23 and, for `dN = 0`,
///   to eq. B.28d.
///
/// Errors: [`DiffError::TotalInternalReflection`] if `ξ ≤ 0`, [`DiffError::NonFinite`] if
/// `1/√ξ` overflows at grazing transmission.
pub fn refract<const N: usize>(
    ray: &RayDiff<N>,
    normal: Vec3,
    dnormal: &[Vec3; N],
    eta: f32,
) -> Result<RayDiff<N>, DiffError> {
    refract_dispersive(ray, normal, dnormal, eta, &[0.0; N])
}

/// [`refract`] through a dispersive interface: the relative IOR `η` depends on the parameters
/// too, `deta[i] = ∂η/∂θᵢ` (the appendix takes η constant before eq. B.21; with wavelength as a
/// parameter it is not, issue 22). Differentiating eq. B.19b–B.20b in η as well:
///
/// * `∂μ/∂η = Vᵀ N − η (1 − (Vᵀ N)²) / √ξ` (from `∂ξ/∂η = −2 η (1 − (Vᵀ N)²)`);
/// * `∂W/∂η = V − N ∂μ/∂η`;
///
/// so eq. B.21b becomes `dW = η dV − N dμ − μ dN + (∂W/∂η) dη` (and `dQ` is still unchanged,
/// eq. B.19a). Columns with `deta[i] = 0` are computed exactly as by [`refract`].
pub fn refract_dispersive<const N: usize>(
    ray: &RayDiff<N>,
    normal: Vec3,
    dnormal: &[Vec3; N],
    eta: f32,
    deta: &[f32; N],
) -> Result<RayDiff<N>, DiffError> {
    let v = ray.v;
    // Orientation convention of eq. B.30: Vᵀ N < 0.
    let sign = if v.dot(normal) > 0.0 { -1.0 } else { 1.0 };
    let n = sign * normal;
    let vn = v.dot(n);
    let xi = 1.0 - eta * eta * (1.0 - vn * vn); // eq. B.20b
    if !(xi > 0.0) {
        return Err(DiffError::TotalInternalReflection);
    }
    let sqrt_xi = xi.sqrt();
    let mu = eta * vn + sqrt_xi; // eq. B.20a
    let w = eta * v - mu * n; // eq. B.19b
    // The factor η (1 + η Vᵀ N / √ξ) shared by both terms of eq. B.22d and by eq. B.23.
    let g = eta * (1.0 + eta * vn / sqrt_xi);
    // ∂W/∂η for dispersive columns (see [`refract_dispersive`]).
    let dw_deta = v - n * (vn - eta * (1.0 - vn * vn) / sqrt_xi);
    let dw = std::array::from_fn(|i| {
        let (dv, dn) = (ray.dv[i], sign * dnormal[i]);
        let dmu = g * (n.dot(dv) + v.dot(dn)); // eq. B.22d
        let dw = eta * dv - n * dmu - mu * dn; // eq. B.21b
        if deta[i] != 0.0 {
            dw + dw_deta * deta[i]
        } else {
            dw
        }
    });
    RayDiff::new(ray.p, w, ray.dp, dw).finite_or_err() // eq. B.19a: Q and dQ unchanged
}

/// The Jacobians of eq. B.23, `dW = A dV + B dN` with
/// `A = η I₃ − η (1 + η Vᵀ N / √ξ) N Nᵀ` and `B = −(μ I₃ + η (1 + η Vᵀ N / √ξ) N Vᵀ)`,
/// returned as `(A, B)` for the orientation `Vᵀ N ≤ 0` (pass an oriented normal). `A` alone is
/// eq. B.28d; `B J` is the `H` of eq. B.54–B.55.
pub fn refraction_jacobians(v: Vec3, normal: Vec3, eta: f32) -> Result<(Mat3, Mat3), DiffError> {
    let n = normal;
    let vn = v.dot(n);
    let xi = 1.0 - eta * eta * (1.0 - vn * vn); // eq. B.20b
    if !(xi > 0.0) {
        return Err(DiffError::TotalInternalReflection);
    }
    let mu = eta * vn + xi.sqrt(); // eq. B.20a
    let g = eta * (1.0 + eta * vn / xi.sqrt());
    let a = eta * Mat3::IDENTITY - g * outer(n, n);
    let b = -(Mat3::from_diagonal(Vec3::splat(mu)) + g * outer(n, v));
    if a.is_finite() && b.is_finite() {
        Ok((a, b))
    } else {
        Err(DiffError::NonFinite)
    }
}

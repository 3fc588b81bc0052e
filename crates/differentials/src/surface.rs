//! Surface models: where a ray differential meets a triangle and which normal (with which
//! differential) reflection and refraction then use (seed 000 app. B.3, eq. B.24–B.55).
//!
//! * [`FlatTriangle`] — the plane of the triangle and its constant normal (B.3.1,
//!   eq. B.24–B.34).
//! * [`PhongTriangle`] — the same plane for the hit point (eq. B.35–B.40) but a normal
//!   interpolated from the vertex normals with the barycentrics of the hit point and
//!   normalised (eq. B.41–B.42); its differential follows the barycentrics through
//!   eq. B.43–B.49 into eq. B.45 (B.3.2).
//!
//! Both accept a [`TriangleMotion`]: derivatives of the vertices and vertex normals with
//! respect to the same parameters as the ray (e.g. time, seed 000 eq. B.12 and ch. 7). For a
//! stationary triangle pass [`TriangleMotion::stationary`] or call `hit`.
//!
//! The differentials are evaluated step by step — eq. B.27c for `ds`, eq. B.31c/B.31b for the
//! flat normal, eq. B.46 with B.49 for the barycentrics, eq. B.45 for the Phong normal, then
//! eq. B.18a / B.21–B.22 — which is algebraically the same as the appendix's gathered forms
//! eq. B.34, B.37–B.38, B.50–B.55 (eq. B.34 is also provided in matrix form,
//! [`FlatTriangle::transfer_jacobians`], and checked against the step-by-step path in the
//! tests). The hit is on the triangle's *plane*: barycentrics outside `[0, 1]` are not
//! rejected, since the neighbouring rays of a differential routinely leave the triangle.

use caustica_core::{Mat3, Vec3};

use crate::ray_differential::{all_finite, all_finite3};
use crate::transfer::{
    Transferred, outer, transfer_jacobians, transfer_to_fixed_plane, transfer_to_plane,
};
use crate::{DiffError, RayDiff, normalize_differential, reflection, refraction};

/// A triangle is degenerate when `‖E₀ × E₁‖ ≤ DEGENERATE_SIN · ‖E₀‖ ‖E₁‖` (the sine of its
/// angle at `Q₀`), or has a zero-length edge.
pub const DEGENERATE_SIN: f32 = 1e-6;

/// Derivatives of a triangle's vertices and vertex normals with respect to the `N`
/// parameters: `dq[k][i] = ∂Q_k/∂θᵢ` (m per unit of θᵢ), `dn[k][i] = ∂N_k/∂θᵢ` (per unit of
/// θᵢ; vertex normals need not be unit, eq. B.42 normalises after interpolating). `dn` is
/// ignored by [`FlatTriangle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleMotion<const N: usize> {
    pub dq: [[Vec3; N]; 3],
    pub dn: [[Vec3; N]; 3],
}

impl<const N: usize> TriangleMotion<N> {
    /// A triangle that does not depend on the parameters (`dQ_k = 0`, `dN_k = 0`).
    pub fn stationary() -> Self {
        Self {
            dq: [[Vec3::ZERO; N]; 3],
            dn: [[Vec3::ZERO; N]; 3],
        }
    }
}

impl<const N: usize> Default for TriangleMotion<N> {
    fn default() -> Self {
        Self::stationary()
    }
}

/// A ray differential transferred onto a triangle, with the normal that scatters it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit<const N: usize> {
    /// The transferred ray: `p = Q` (m), `v = W = V`, `dp = dQ`, `dv = dW = dV`
    /// (eq. B.13, B.16; B.28a–b / B.34 flat, B.37–B.39 Phong).
    pub ray: RayDiff<N>,
    /// Transfer distance `s` (m, eq. B.26 / B.36) and `∂s/∂θᵢ` (eq. B.27).
    pub s: f32,
    pub ds: [f32; N],
    /// Unit geometric normal `N_flat`, oriented so that `Vᵀ N_flat < 0` (eq. B.30–B.31a,
    /// B.35), and its derivatives (eq. B.31b–e; zero for a stationary triangle).
    pub geometric_normal: Vec3,
    pub dgeometric_normal: [Vec3; N],
    /// Unit normal used for reflection and refraction, oriented so that `Vᵀ N ≤ 0`, and its
    /// derivatives: the geometric normal for [`FlatTriangle`], the interpolated normal
    /// (eq. B.42, B.45) for [`PhongTriangle`].
    pub normal: Vec3,
    pub dnormal: [Vec3; N],
    /// Barycentrics `(λ₀, λ₁, λ₂)` of `Q` (eq. B.41, B.44) and `∂λ_k/∂θᵢ` as
    /// `dbarycentrics[i][k]` (eq. B.46).
    pub barycentrics: [f32; 3],
    pub dbarycentrics: [[f32; 3]; N],
}

impl<const N: usize> SurfaceHit<N> {
    /// Mirror reflection at the hit (eq. B.17–B.18; B.28c flat, B.52 Phong).
    pub fn reflect(&self) -> Result<RayDiff<N>, DiffError> {
        reflection::reflect(&self.ray, self.normal, &self.dnormal)
    }

    /// Refraction at the hit with `eta = n_incident / n_transmitted` (eq. B.19–B.23; B.28d
    /// flat, B.53–B.55 Phong). Total internal reflection is an error.
    pub fn refract(&self, eta: f32) -> Result<RayDiff<N>, DiffError> {
        refraction::refract(&self.ray, self.normal, &self.dnormal, eta)
    }

    /// [`Self::refract`] where `eta` also depends on the parameters, `deta[i] = ∂η/∂θᵢ`
    /// (a dispersive interface with wavelength as a parameter,
    /// [`refraction::refract_dispersive`]).
    pub fn refract_dispersive(&self, eta: f32, deta: &[f32; N]) -> Result<RayDiff<N>, DiffError> {
        refraction::refract_dispersive(&self.ray, self.normal, &self.dnormal, eta, deta)
    }
}

/// A flat triangle with vertices `q` (m): the surface of B.3.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatTriangle {
    pub q: [Vec3; 3],
}

/// A triangle with vertices `q` (m) and vertex normals `n` (any non-zero length), shaded with
/// Phong-interpolated normals: the "fish scale" surface of B.3.2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongTriangle {
    pub q: [Vec3; 3],
    pub n: [Vec3; 3],
}

/// The unit flat normal oriented against `v`, its derivatives, and `n = (Q₂ − Q₀) × (Q₁ − Q₀)`
/// before normalisation (after orientation).
fn flat_normal<const N: usize>(
    q: &[Vec3; 3],
    dq: &[[Vec3; N]; 3],
    v: Vec3,
) -> Result<(Vec3, [Vec3; N], Vec3), DiffError> {
    let e0 = q[1] - q[0]; // eq. B.43a
    let e1 = q[2] - q[0]; // eq. B.43b
    let mut n = e1.cross(e0); // eq. B.30, B.35a
    let scale = e0.length() * e1.length();
    if !(scale > 0.0 && n.length() > DEGENERATE_SIN * scale && n.is_finite()) {
        return Err(DiffError::DegenerateTriangle);
    }
    // eq. B.30: orient so that nᵀV < 0 ("otherwise interchange Q₁ and Q₂", which negates n
    // and dn).
    let sign = if n.dot(v) > 0.0 { -1.0 } else { 1.0 };
    n *= sign;
    let dn_unit = std::array::from_fn(|i| {
        let de0 = dq[1][i] - dq[0][i];
        let de1 = dq[2][i] - dq[0][i];
        let dn = sign * (de1.cross(e0) + e1.cross(de0)); // eq. B.31c (= B.31d–e)
        normalize_differential(n, dn) // eq. B.31b with J of eq. B.33
    });
    Ok((n.normalize(), dn_unit, n)) // eq. B.31a
}

/// Barycentrics of the hit of `ray` with the plane of `q` and their derivatives, by
/// Möller–Trumbore (eq. B.43–B.44) and eq. B.46 with B.49.
fn barycentrics<const N: usize>(
    ray: &RayDiff<N>,
    q: &[Vec3; 3],
    dq: &[[Vec3; N]; 3],
) -> ([f32; 3], [[f32; 3]; N]) {
    let v = ray.v;
    let e0 = q[1] - q[0]; // eq. B.43a
    let e1 = q[2] - q[0]; // eq. B.43b
    let t = ray.p - q[0]; // eq. B.43c
    let tau = v.cross(t);
    let gamma = v.cross(e0);
    let zeta = v.cross(e1);
    let (g1, z0) = (gamma.dot(e1), zeta.dot(e0)); // γᵀE₁ and ζᵀE₀
    let (t1, t0) = (tau.dot(e1), tau.dot(e0)); // τᵀE₁ and τᵀE₀
    let l1 = t1 / g1; // eq. B.44a–b
    let l2 = t0 / z0; // eq. B.44c–d
    let lambda = [1.0 - l1 - l2, l1, l2];
    let dlambda = std::array::from_fn(|i| {
        let dv = ray.dv[i];
        let de0 = dq[1][i] - dq[0][i];
        let de1 = dq[2][i] - dq[0][i];
        let dt = ray.dp[i] - dq[0][i];
        let dtau = dv.cross(t) + v.cross(dt); // eq. B.49a
        let dgamma = dv.cross(e0) + v.cross(de0); // eq. B.49b
        let dzeta = dv.cross(e1) + v.cross(de1); // eq. B.49c
        // eq. B.46b (first line), divided through by γᵀE₁ once.
        let dl1 = ((dtau.dot(e1) + tau.dot(de1)) - l1 * (dgamma.dot(e1) + gamma.dot(de1))) / g1;
        // eq. B.46c (first line), divided through by ζᵀE₀ once.
        let dl2 = ((dtau.dot(e0) + tau.dot(de0)) - l2 * (dzeta.dot(e0) + zeta.dot(de0))) / z0;
        [-dl1 - dl2, dl1, dl2] // eq. B.46a
    });
    (lambda, dlambda)
}

/// The shared part of both surface models: transfer onto the triangle's plane.
fn hit_plane<const N: usize>(
    q: &[Vec3; 3],
    ray: &RayDiff<N>,
    motion: &TriangleMotion<N>,
) -> Result<SurfaceHit<N>, DiffError> {
    let (ng, dng, _) = flat_normal(q, &motion.dq, ray.v)?;
    // eq. B.24–B.29 (B.36–B.40 for Phong): transfer onto the plane through Q₀ with the flat
    // normal; dN_flat enters eq. B.27c, giving eq. B.34 / B.37–B.38.
    let tr = transfer_to_plane(ray, q[0], &motion.dq[0], ng, &dng)?;
    let (lambda, dlambda) = barycentrics(ray, q, &motion.dq);
    plane_hit(tr, ng, dng, lambda, dlambda)
}

/// The hit on a triangle's plane with the flat normal as the scattering normal, or
/// [`DiffError::NonFinite`] if a barycentric or its derivative is not finite.
#[inline]
fn plane_hit<const N: usize>(
    tr: Transferred<N>,
    ng: Vec3,
    dng: [Vec3; N],
    lambda: [f32; 3],
    dlambda: [[f32; 3]; N],
) -> Result<SurfaceHit<N>, DiffError> {
    if !all_finite(lambda.iter().chain(dlambda.iter().flatten()).copied()) {
        return Err(DiffError::NonFinite);
    }
    Ok(SurfaceHit {
        ray: tr.ray,
        s: tr.s,
        ds: tr.ds,
        geometric_normal: ng,
        dgeometric_normal: dng,
        normal: ng,
        dnormal: dng,
        barycentrics: lambda,
        dbarycentrics: dlambda,
    })
}

/// [`hit_plane`] for a stationary triangle (`dQ_k = 0`, `dN_k = 0`): the same equations with
/// the motion terms dropped — eq. B.31 gives `dN_flat = 0`, eq. B.27c reduces to
/// `ds = −Nᵀ(dP + s dV) / (Vᵀ N)` ([`transfer_to_fixed_plane`]) and eq. B.49 to
/// `dτ = dV × T + V × dP`, `dγ = dV × E₀`, `dζ = dV × E₁`. This is what the renderer calls for
/// every delta vertex of a photon path, so it avoids the zero terms (floating point cannot
/// fold `0 · x` away).
fn hit_plane_stationary<const N: usize>(
    q: &[Vec3; 3],
    ray: &RayDiff<N>,
) -> Result<SurfaceHit<N>, DiffError> {
    let e0 = q[1] - q[0]; // eq. B.43a
    let e1 = q[2] - q[0]; // eq. B.43b
    let ng = oriented_flat_normal(e0, e1, ray.v)?;
    let tr = transfer_to_fixed_plane(ray, q[0], ng)?; // eq. B.24–B.29 with dQ₀ = 0, dN = 0
    // Barycentrics by Möller–Trumbore (eq. B.43–B.44) and eq. B.46 with B.49 for dQ_k = 0.
    let v = ray.v;
    let t = ray.p - q[0]; // eq. B.43c
    let tau = v.cross(t);
    let gamma = v.cross(e0);
    let zeta = v.cross(e1);
    let (g1, z0) = (1.0 / gamma.dot(e1), 1.0 / zeta.dot(e0)); // 1/γᵀE₁ and 1/ζᵀE₀
    let l1 = tau.dot(e1) * g1; // eq. B.44a–b
    let l2 = tau.dot(e0) * z0; // eq. B.44c–d
    let lambda = [1.0 - l1 - l2, l1, l2];
    let dlambda = std::array::from_fn(|i| {
        let dv = ray.dv[i];
        let dtau = dv.cross(t) + v.cross(ray.dp[i]); // eq. B.49a
        let dl1 = (dtau.dot(e1) - l1 * dv.cross(e0).dot(e1)) * g1; // eq. B.46b, B.49b
        let dl2 = (dtau.dot(e0) - l2 * dv.cross(e1).dot(e0)) * z0; // eq. B.46c, B.49c
        [-dl1 - dl2, dl1, dl2] // eq. B.46a
    });
    plane_hit(tr, ng, [Vec3::ZERO; N], lambda, dlambda)
}

/// The unit flat normal `N_flat` of the triangle with edges `e0`, `e1` oriented against `v`
/// (eq. B.30–B.31a), or [`DiffError::DegenerateTriangle`] (see [`DEGENERATE_SIN`]).
#[inline]
fn oriented_flat_normal(e0: Vec3, e1: Vec3, v: Vec3) -> Result<Vec3, DiffError> {
    // The degeneracy test compares squares.
    let n = e1.cross(e0); // eq. B.30, B.35a
    let scale2 = e0.length_squared() * e1.length_squared();
    let len2 = n.length_squared();
    if !(scale2 > 0.0 && len2 > DEGENERATE_SIN * DEGENERATE_SIN * scale2 && n.is_finite()) {
        return Err(DiffError::DegenerateTriangle);
    }
    let n = if n.dot(v) > 0.0 { -n } else { n };
    Ok(n / n.length())
}

/// `c×`, the cross-product matrix of eq. B.32 / B.48: `c× b = c × b`.
pub fn skew(c: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, c.z, -c.y),
        Vec3::new(-c.z, 0.0, c.x),
        Vec3::new(c.y, -c.x, 0.0),
    )
}

/// The flat-triangle transfer in the appendix's matrix form (eq. B.34):
/// `dQ = K dP + s K dV + Σ_k dq_dq[k] dQ_k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatTransferJacobians {
    /// Transfer distance (m).
    pub s: f32,
    /// `∂Q/∂P = K` (eq. B.29a).
    pub dq_dp: Mat3,
    /// `∂Q/∂V = s K` (m).
    pub dq_dv: Mat3,
    /// `∂Q/∂Q_k`: `I₃ − K + L J (Q₁× − Q₂×)`, `L J (Q₂× − Q₀×)`, `L J (Q₀× − Q₁×)`.
    pub dq_dq: [Mat3; 3],
}

impl FlatTriangle {
    /// Transfers `ray` onto this stationary triangle (eq. B.24–B.31 with `dQ_k = 0`; for a
    /// stationary flat surface `dQ = K dP + s K dV` as in Igehy 1999, app. B after eq. B.34).
    pub fn hit<const N: usize>(&self, ray: &RayDiff<N>) -> Result<SurfaceHit<N>, DiffError> {
        hit_plane_stationary(&self.q, ray)
    }

    /// Transfers `ray` onto this triangle whose vertices move with `motion.dq` (eq. B.28a with
    /// `dN` from eq. B.31, i.e. eq. B.34). The scattering normal is the flat normal.
    pub fn hit_moving<const N: usize>(
        &self,
        ray: &RayDiff<N>,
        motion: &TriangleMotion<N>,
    ) -> Result<SurfaceHit<N>, DiffError> {
        hit_plane(&self.q, ray, motion)
    }

    /// The matrices of eq. B.34 for a ray from `p` in unit direction `v`. The vertex labels
    /// are those of `self.q` even when eq. B.30 asks to interchange `Q₁` and `Q₂`.
    pub fn transfer_jacobians(&self, p: Vec3, v: Vec3) -> Result<FlatTransferJacobians, DiffError> {
        let (n_unit, _, n) = flat_normal::<0>(&self.q, &[[]; 3], v)?;
        // eq. B.30: if the orientation was flipped, the appendix interchanges Q₁ and Q₂.
        let swapped = (self.q[2] - self.q[0]).cross(self.q[1] - self.q[0]).dot(n) < 0.0;
        let q = if swapped {
            [self.q[0], self.q[2], self.q[1]]
        } else {
            self.q
        };
        let tj = transfer_jacobians(p, v, q[0], n_unit)?;
        let j = (Mat3::from_diagonal(Vec3::splat(n.length_squared())) - outer(n, n))
            / n.length_squared().powf(1.5); // eq. B.33
        let lj = tj.l * j;
        let mut dq_dq = [
            Mat3::IDENTITY - tj.k + lj * (skew(q[1]) - skew(q[2])), // eq. B.34, dQ₀
            lj * (skew(q[2]) - skew(q[0])),                         // eq. B.34, dQ₁
            lj * (skew(q[0]) - skew(q[1])),                         // eq. B.34, dQ₂
        ];
        if swapped {
            dq_dq.swap(1, 2);
        }
        Ok(FlatTransferJacobians {
            s: tj.s,
            dq_dp: tj.k,
            dq_dv: tj.s * tj.k,
            dq_dq,
        })
    }
}

impl PhongTriangle {
    /// Transfers `ray` onto this stationary triangle and interpolates its normal.
    pub fn hit<const N: usize>(&self, ray: &RayDiff<N>) -> Result<SurfaceHit<N>, DiffError> {
        let hit = hit_plane_stationary(&self.q, ray)?;
        self.shade(hit, ray.v, None)
    }

    /// Transfers `ray` onto the plane of this triangle with the flat normal (eq. B.35–B.40),
    /// computes the barycentrics of the hit and their differentials (eq. B.41, B.43–B.46,
    /// B.49), and interpolates and normalises the vertex normals (eq. B.42) with the
    /// differential `dN = J (Σ N_k dλ_k + λ_k dN_k)` (eq. B.45; gathered in eq. B.47, B.50,
    /// B.51). The interpolated normal is negated if needed so that `Vᵀ N ≤ 0`.
    ///
    /// Errors as for [`FlatTriangle::hit_moving`], plus [`DiffError::DegenerateNormal`] if the
    /// interpolated normal vanishes.
    pub fn hit_moving<const N: usize>(
        &self,
        ray: &RayDiff<N>,
        motion: &TriangleMotion<N>,
    ) -> Result<SurfaceHit<N>, DiffError> {
        let hit = hit_plane(&self.q, ray, motion)?;
        self.shade(hit, ray.v, Some(&motion.dn))
    }

    /// Interpolates the normal at `hit` (on this triangle's plane, ray direction `v`) and its
    /// differential (eq. B.42, B.45) with vertex-normal derivatives `dn_k` (`None`: zero).
    fn shade<const N: usize>(
        &self,
        mut hit: SurfaceHit<N>,
        v: Vec3,
        dn_k: Option<&[[Vec3; N]; 3]>,
    ) -> Result<SurfaceHit<N>, DiffError> {
        let l = hit.barycentrics;
        let n = l[0] * self.n[0] + l[1] * self.n[1] + l[2] * self.n[2]; // eq. B.42a
        let scale2 = self
            .n
            .iter()
            .map(|n| n.length_squared())
            .fold(0.0, f32::max);
        let len2 = n.length_squared();
        if !(len2 > 1e-12 * scale2 && n.is_finite()) {
            return Err(DiffError::DegenerateNormal);
        }
        // Orientation convention of eq. B.30 applied to the shading normal.
        let inv_len = 1.0 / len2.sqrt();
        let unit = n * inv_len; // eq. B.42b before orientation
        let sign = if n.dot(v) > 0.0 { -1.0 } else { 1.0 };
        hit.dnormal = std::array::from_fn(|i| {
            let dl = hit.dbarycentrics[i];
            let mut dn = self.n[0] * dl[0] + self.n[1] * dl[1] + self.n[2] * dl[2]; // eq. B.45b
            if let Some(dn_k) = dn_k {
                dn += l[0] * dn_k[0][i] + l[1] * dn_k[1][i] + l[2] * dn_k[2][i];
            }
            // eq. B.45a: J dn = (dn − N̂ (N̂ᵀ dn)) / ‖n‖ (normalize_differential, J computed once)
            sign * inv_len * (dn - unit * unit.dot(dn))
        });
        hit.normal = sign * unit; // eq. B.42b
        if !all_finite3(&hit.dnormal) {
            return Err(DiffError::NonFinite);
        }
        Ok(hit)
    }
}

/// The differential of the Phong normal in the appendix's gathered matrix form (eq. B.51):
/// `dN = Σ_k dn_dnk[k] dN_k + dn_dv dV + dn_dp dP + Σ_k dn_dq[k] dQ_k`, including the factor
/// `J` of eq. B.45a and the orientation `Vᵀ N ≤ 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongNormalJacobians {
    /// `∂N/∂N_k = λ_k J` (per unit of vertex normal).
    pub dn_dnk: [Mat3; 3],
    /// `∂N/∂V` (unitless).
    pub dn_dv: Mat3,
    /// `∂N/∂P` (per m).
    pub dn_dp: Mat3,
    /// `∂N/∂Q_k` (per m).
    pub dn_dq: [Mat3; 3],
}

impl PhongTriangle {
    /// The matrices of eq. B.51 for a ray from `p` in unit direction `v` hitting this
    /// triangle's plane. [`PhongTriangle::hit_moving`] evaluates the same differential step by
    /// step; this form is kept to check the appendix's algebra against it.
    pub fn normal_jacobians(&self, p: Vec3, v: Vec3) -> Result<PhongNormalJacobians, DiffError> {
        let ray = RayDiff::<0>::constant(p, v);
        let hit = hit_plane(&self.q, &ray, &TriangleMotion::stationary())?;
        let l = hit.barycentrics;
        let n = l[0] * self.n[0] + l[1] * self.n[1] + l[2] * self.n[2]; // eq. B.42a
        let scale = self.n.iter().map(|n| n.length()).fold(0.0, f32::max);
        if !(n.length() > 1e-6 * scale && n.is_finite()) {
            return Err(DiffError::DegenerateNormal);
        }
        let sign = if n.dot(v) > 0.0 { -1.0 } else { 1.0 };
        let j = sign * (Mat3::from_diagonal(Vec3::splat(n.length_squared())) - outer(n, n))
            / n.length_squared().powf(1.5); // eq. B.45a (J of eq. B.47), oriented
        let (e0, e1, t) = (self.q[1] - self.q[0], self.q[2] - self.q[0], p - self.q[0]);
        let (tau, gamma, zeta) = (v.cross(t), v.cross(e0), v.cross(e1)); // eq. B.44
        let (s0, s1) = (outer(e0, e0), outer(e1, e1)); // S₀, S₁ of eq. B.46
        let d1 = (self.n[1] - self.n[0]) / gamma.dot(s1 * gamma); // Δ₁
        let d2 = (self.n[2] - self.n[0]) / zeta.dot(s0 * zeta); // Δ₂
        // A row vector rᵀ M is stored as the column Mᵀ r.
        let row = |r: Vec3, m: Mat3| m.transpose() * r;
        let (vx, tx, e0x, e1x) = (skew(v), skew(t), skew(e0), skew(e1));
        let xi0 = e0.dot(tau) * zeta - e0.dot(zeta) * tau; // Ξ₀ = E₀ᵀ(τζᵀ − ζτᵀ)
        let xi1 = e1.dot(tau) * gamma - e1.dot(gamma) * tau; // Ξ₁ = E₁ᵀ(τγᵀ − γτᵀ)
        // eq. B.51, term by term.
        let a_v = outer(d1, row(s1 * tau, e0x) - row(s1 * gamma, tx))
            + outer(d2, row(s0 * tau, e1x) - row(s0 * zeta, tx));
        let a_p = outer(d1, row(s1 * gamma, vx)) + outer(d2, row(s0 * zeta, vx));
        let a_q0 = outer(d1, row(s1 * (tau - gamma), vx))
            + outer(d2, row(s0 * (tau - zeta), vx))
            + outer(d2, xi0)
            + outer(d1, xi1);
        let a_q1 = -(outer(d2, xi0) + outer(d1, row(s1 * tau, vx)));
        let a_q2 = -(outer(d1, xi1) + outer(d2, row(s0 * tau, vx)));
        let out = PhongNormalJacobians {
            dn_dnk: [l[0] * j, l[1] * j, l[2] * j],
            dn_dv: j * a_v,
            dn_dp: j * a_p,
            dn_dq: [j * a_q0, j * a_q1, j * a_q2],
        };
        let finite = [out.dn_dv, out.dn_dp]
            .iter()
            .chain(&out.dn_dq)
            .chain(&out.dn_dnk)
            .all(|m| m.is_finite());
        if finite {
            Ok(out)
        } else {
            Err(DiffError::NonFinite)
        }
    }
}

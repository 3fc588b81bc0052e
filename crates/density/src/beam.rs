//! The geometry of the beam radiance estimate (seed 000 ch. 8, sec. 8.3, eq. 8.4–8.16): how much
//! of a photon's kernel an eye-ray segment crosses.
//!
//! Eq. 8.4 sums, over the photons whose kernel the eye ray crosses,
//!
//! ```text
//! L(x, ω) ≈ T_r(x, x_s) L(x_s, ω) + Σᵢ T_r(x, xᵢ) p(xᵢ, ωᵢ, ω) (ΔΦᵢ / Vᵢ) wᵢ      (8.4)
//! ```
//!
//! with `Vᵢ` the kernel's volume (m³), `wᵢ` the kernel integrated along the ray (m), and `xᵢ`
//! the point of the ray closest to the photon, where transmittance and phase function are
//! evaluated. This module gives `wᵢ` ([`ball_weight`], [`ellipsoid_weight`]), the parameter
//! `t` of `xᵢ` ([`BeamHit::t`]) and `Vᵢ` ([`ball_volume`], [`ellipsoid_volume`]).
//!
//! # Kernel convention
//!
//! The thesis' kernels "do not integrate to unity because V is divided out in 8.4": a
//! [`BeamKernel`] has **mean 1** over its support, `∫ K dV = V`. Uniform `K = 1` inside (8.10),
//! 3-D Epanechnikov `K(y) = (5/2)(1 − (y/h)²)` (8.12; `(5/2)·(2/15)·4π = 4π/3` ✓). They are the
//! 3-D kernels of [`Kernel`] times the unit-ball volume: `BeamKernel::eval(u²) =
//! (4π/3) Kernel::eval(u², Dim::Three)`. With mean 1, `(ΔΦ/V) w` integrated over every eye
//! ray through the kernel (`Σ w dA⊥ = ∫ K dV = V`) gives back `ΔΦ`: energy is conserved.
//!
//! # Isotropic kernels (eq. 8.5–8.13)
//!
//! For a ball of radius `h` whose centre is at distance `y_s` from the line,
//! `y(t) = sqrt(t² + y_s²)` (8.6) and the weight is the kernel integrated over the chord:
//!
//! ```text
//! w = ∫ K(y(t)) dt  over the chord |t| < sqrt(h² − y_s²)                       (8.5, corrected)
//!   = 2 ∫_{y_s}^{h} K(y) y / sqrt(y² − y_s²) dy                                (8.9)
//! uniform:       w = 2 sqrt(h² − y_s²)                                         (8.11)
//! Epanechnikov:  w = 10/(3h²) (h² − y_s²)^{3/2}                                (8.13, corrected)
//! ```
//!
//! **Misprints corrected.** Eq. 8.5 prints `w = 2 ∫_{−Δt/2}^{Δt/2} K(y(t)) dt`: the factor 2 is
//! spurious, since the integral over the symmetric interval already covers the whole chord, and
//! 8.9 (whose 2 *is* the symmetric halves) and 8.11 (the chord length for `K = 1`) agree only
//! without it. Eq. 8.13 writes `y` for `y_s`. [`BeamKernel::chord_weight`] is 8.11 and
//! corrected 8.13; the tests check both against quadrature of the kernel along `t`.
//!
//! # Anisotropic kernels (eq. 8.14–8.16)
//!
//! A photon differential's kernel is the ellipsoid `{x : |M(x − c)| < 1}` with
//! `M = (½[D_u x D_v x D_w x])⁻¹` ([`filter_matrix`]; the differential vectors are the edges of
//! the parallelepiped around it, fig. 8.3–8.4) and `K` evaluated at `y = |M(x − c)|`, `h = 1`.
//! Along the ray `o + tω` (`ω` unit):
//!
//! ```text
//! a = |Mω|²,  b = Mω·M(o − c),  c₀ = |M(o − c)|²,  q(t) = |M(o + tω − c)|² = a t² + 2bt + c₀
//! t* = −b/a,  y_pd² = q(t*) = c₀ − b²/a                                        (8.14)
//! w  = 10/(3|Mω|) (1 − y_pd²)^{3/2}    (Epanechnikov)                           (8.15)
//! w  = 2 sqrt((1 − y_pd²)/a)           (uniform)
//! V  = (π/6) |(D_u x × D_v x)·D_w x| = (4π/3) |det(½[D_u D_v D_w])| = (4π/3)/|det M|   (8.16)
//! ```
//!
//! `t*` is the closest point in the *filter* metric, not the Euclidean one; 8.14 minimises the
//! filter-space distance, so that is the `xᵢ` this module reports for ellipsoids. A ball is the
//! case `M = I/h`, where both metrics agree. `y_pd²` is computed as the residual
//! `|M(o − c) + t* Mω|²`, which equals `c₀ − b²/a` without its cancellation far from the kernel.
//!
//! # Clipping ([`Clip`])
//!
//! 8.11–8.15 integrate over the whole chord. An eye segment `[t0, t1]` that starts or ends
//! inside a kernel (a camera in fog, a surface hit, the next segment of a path) should receive
//! only the part it crosses, or the energy near the ends is counted twice by consecutive
//! segments (or by a segment and the surface behind it). [`Clip::Exact`] (the default)
//! integrates `(5/2)(1 − q(t))` over `[max(t−, t0), min(t+, t1)]`, `t±` the roots of `q = 1`:
//! the thesis' antiderivative `F(t) = (5/2)[(1 − c₀)t − bt² − at³/3]` is evaluated in the
//! shifted variable `s = t − t*`, `q = a s² + y_pd²`, as
//! `(5/2)(s₁ − s₀)[(1 − y_pd²) − a(s₁² + s₁s₀ + s₀²)/3]` (the same integral, without the
//! cancellation of `F(t₁) − F(t₀)` at large `t`); for the uniform kernel it is the overlap's
//! length. [`Clip::WholeChord`] is 8.11–8.15 as printed. Both count a kernel only when the
//! chord overlaps the segment, so they select the same photons.
//!
//! In both modes `t*` is clamped to `[t0, t1]` (equivalently to the overlap, which contains the
//! clamped value), so transmittance is never evaluated beyond the segment.

use std::f64::consts::PI;

use caustica_core::{Mat3, Vec3};

use crate::DensityError;
use crate::kernel::Kernel;

/// The kernels of the beam estimate, with mean 1 over their support (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BeamKernel {
    /// `K = 1` inside the support (eq. 8.10).
    Uniform,
    /// `K = (5/2)(1 − u²)` (eq. 8.12), the thesis' choice.
    #[default]
    Epanechnikov,
}

/// How much of a kernel's chord a segment receives (see the [module docs](self#clipping-clip)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Clip {
    /// Integrate the kernel over the part of the chord inside `[t0, t1]` (exact; default).
    #[default]
    Exact,
    /// The whole chord's weight (eq. 8.11, 8.13, 8.15 as printed) whenever the chord overlaps
    /// `[t0, t1]`.
    WholeChord,
}

/// A segment `origin + t·dir`, `t ∈ [t0, t1]` (m), of an eye ray. `dir` must be unit length so
/// that `t` and the weights are in metres; `t1` may be `+∞` (a ray that escapes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaySegment {
    /// Ray origin (m).
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Start parameter (m).
    pub t0: f32,
    /// End parameter (m), `>= t0`.
    pub t1: f32,
}

impl RaySegment {
    /// The segment `origin + t·dir`, `t ∈ [t0, t1]`.
    pub fn new(origin: Vec3, dir: Vec3, t0: f32, t1: f32) -> Self {
        Self {
            origin,
            dir,
            t0,
            t1,
        }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// A kernel crossed by a segment: its weight and where eq. 8.4 evaluates `T_r` and `p`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamHit {
    /// The integrated kernel weight `wᵢ` of eq. 8.4 (m).
    pub weight: f32,
    /// Parameter of `xᵢ` (m): the closest point of the line to the kernel centre in the
    /// kernel's metric, clamped to `[t0, t1]`.
    pub t: f32,
}

/// The squared filter-space distance along a line, `q(t) = a (t − t*)² + y²` (eq. 8.14 with the
/// square completed): `a = |Mω|²` (m⁻²), `t*` (m), `y² = y_pd²` (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterChord {
    /// `|Mω|²` (m⁻²); `1/h²` for a ball.
    pub a: f32,
    /// The parameter of the filter-space closest point, `−b/a` (m).
    pub t_star: f32,
    /// `y_pd² = q(t*)`, the squared filter-space distance of the line (`y_s²/h²` for a ball).
    pub y2: f32,
}

impl BeamKernel {
    /// `K` at the squared normalised distance `u² = y²/h²` (or `|M(x − c)|²`): 1 or
    /// `(5/2)(1 − u²)` for `u² < 1`, 0 outside (and for NaN).
    #[inline]
    pub fn eval(self, u2: f32) -> f32 {
        match self {
            _ if u2 >= 1.0 || u2.is_nan() => 0.0,
            BeamKernel::Uniform => 1.0,
            BeamKernel::Epanechnikov => 2.5 * (1.0 - u2.max(0.0)),
        }
    }

    /// Whole-chord weight (m) of a ball of radius `h` (m) whose centre is `y_s` (m) from the
    /// line: `2 sqrt(h² − y_s²)` (8.11) or `10/(3h²) (h² − y_s²)^{3/2}` (8.13 with `y_s` for its
    /// misprinted `y`); 0 when `y_s >= h`.
    pub fn chord_weight(self, h: f32, y_s: f32) -> f32 {
        let l2 = h * h - y_s * y_s;
        match self {
            _ if l2 <= 0.0 || l2.is_nan() => 0.0,
            // (8.11)
            BeamKernel::Uniform => 2.0 * l2.sqrt(),
            // (8.13), corrected
            BeamKernel::Epanechnikov => 10.0 / (3.0 * h * h) * l2 * l2.sqrt(),
        }
    }

    /// The fraction of the kernel's mass within normalised radius `a` (clamped to `[0, 1]`):
    /// `∫₀^a K(u) u² du / ∫₀¹ K(u) u² du`, `a³` (uniform) or `(5a³ − 3a⁵)/2` (Epanechnikov). Rays
    /// from a kernel's centre keep this profile in filter space, so it is the mass a ray from
    /// the centre sees up to a surface (`caustica-render`'s kernel boundaries).
    #[inline]
    pub fn radial_mass(self, a: f32) -> f32 {
        let a = a.clamp(0.0, 1.0);
        let a3 = a * a * a;
        match self {
            BeamKernel::Uniform => a3,
            BeamKernel::Epanechnikov => 0.5 * a3 * (5.0 - 3.0 * a * a),
        }
    }
}

impl TryFrom<Kernel> for BeamKernel {
    type Error = DensityError;

    /// The beam estimate integrates its kernels in closed form, which this module does for the
    /// uniform and Epanechnikov kernels only.
    fn try_from(k: Kernel) -> Result<Self, DensityError> {
        match k {
            Kernel::Uniform => Ok(BeamKernel::Uniform),
            Kernel::Epanechnikov => Ok(BeamKernel::Epanechnikov),
            other => Err(DensityError::UnsupportedBeamKernel(other.name())),
        }
    }
}

impl FilterChord {
    /// The chord of the ball of radius `h` (m) around `centre` (`M = I/h`): `t*` is the
    /// Euclidean closest point. `None` if `h` is not positive and finite or an input is not
    /// finite.
    pub fn ball(seg: &RaySegment, centre: Vec3, h: f32) -> Option<Self> {
        if !(h > 0.0 && h.is_finite()) {
            return None;
        }
        let d = centre - seg.origin;
        let t_star = d.dot(seg.dir);
        let y2 = (d - seg.dir * t_star).length_squared() / (h * h);
        let a = 1.0 / (h * h);
        (t_star.is_finite() && y2.is_finite() && a.is_finite()).then_some(Self { a, t_star, y2 })
    }

    /// The chord of the ellipsoid `{x : |M(x − c)| < 1}` (eq. 8.14): `a = |Mω|²`,
    /// `t* = −Mω·M(o − c)/a`, `y² = |M(o − c) + t* Mω|²`. `None` if `Mω = 0` (a singular `M`)
    /// or an input is not finite.
    pub fn ellipsoid(seg: &RaySegment, centre: Vec3, m: Mat3) -> Option<Self> {
        let mw = m * seg.dir;
        let md = m * (seg.origin - centre);
        let a = mw.length_squared();
        if !(a > 0.0 && a.is_finite()) {
            return None;
        }
        let t_star = -mw.dot(md) / a;
        let y2 = (md + mw * t_star).length_squared();
        (t_star.is_finite() && y2.is_finite()).then_some(Self { a, t_star, y2 })
    }

    /// Half the chord's length (m), `sqrt((1 − y²)/a)`; 0 if the line misses the kernel.
    pub fn half_length(&self) -> f32 {
        if self.y2 < 1.0 {
            ((1.0 - self.y2) / self.a).sqrt()
        } else {
            0.0
        }
    }

    /// The weight of the kernel for the segment `[t0, t1]` of the line (see the
    /// [module docs](self)); `None` if the open chord `(t−, t+)` does not overlap `(t0, t1)`.
    pub fn weight(&self, kernel: BeamKernel, t0: f32, t1: f32, clip: Clip) -> Option<BeamHit> {
        let one_minus_y2 = 1.0 - self.y2;
        let half = (one_minus_y2 / self.a).sqrt();
        // Overlap of the chord [t* − L, t* + L] and [t0, t1], in s = t − t*.
        let s0 = (t0 - self.t_star).max(-half);
        let s1 = (t1 - self.t_star).min(half);
        // Every comparison is false for NaN (`max`/`min` would drop a NaN bound).
        let crosses = self.y2 < 1.0 && half > 0.0 && t0 <= t1 && s0 < s1;
        if !crosses {
            return None;
        }
        let weight = match (kernel, clip) {
            // Uniform, clipped: the overlap's length.
            (BeamKernel::Uniform, Clip::Exact) => s1 - s0,
            // (8.11) and its anisotropic form: the chord's length.
            (BeamKernel::Uniform, Clip::WholeChord) => 2.0 * half,
            // ∫_{s0}^{s1} (5/2)(1 − y² − a s²) ds, factored (see the module docs).
            (BeamKernel::Epanechnikov, Clip::Exact) => {
                let mean_s2 = (s1 * s1 + s1 * s0 + s0 * s0) / 3.0;
                (2.5 * (s1 - s0) * (one_minus_y2 - self.a * mean_s2)).max(0.0)
            }
            // (8.15): 10/(3|Mω|) (1 − y²)^{3/2} = (10/3)(1 − y²) L; for M = I/h this is (8.13).
            (BeamKernel::Epanechnikov, Clip::WholeChord) => 10.0 / 3.0 * one_minus_y2 * half,
        };
        Some(BeamHit {
            weight,
            t: self.t_star.clamp(t0, t1),
        })
    }
}

/// Weight and closest point of the ball of radius `h` (m) around `centre` for the segment
/// `seg` (eq. 8.5–8.13; [`FilterChord::ball`], [`FilterChord::weight`]). `None` when the
/// segment does not cross the ball or `h` is not positive and finite.
pub fn ball_weight(
    kernel: BeamKernel,
    seg: &RaySegment,
    centre: Vec3,
    h: f32,
    clip: Clip,
) -> Option<BeamHit> {
    FilterChord::ball(seg, centre, h)?.weight(kernel, seg.t0, seg.t1, clip)
}

/// Weight and filter-space closest point of the ellipsoid `{x : |M(x − c)| < 1}` for the
/// segment `seg` (eq. 8.14–8.15; [`FilterChord::ellipsoid`], [`FilterChord::weight`]). `None`
/// when the segment does not cross it or `Mω = 0`.
pub fn ellipsoid_weight(
    kernel: BeamKernel,
    seg: &RaySegment,
    centre: Vec3,
    m: Mat3,
    clip: Clip,
) -> Option<BeamHit> {
    FilterChord::ellipsoid(seg, centre, m)?.weight(kernel, seg.t0, seg.t1, clip)
}

/// Volume of the ball of radius `h`, `4πh³/3` (m³): `Vᵢ` of eq. 8.4 for an isotropic kernel.
pub fn ball_volume(h: f32) -> f32 {
    (4.0 / 3.0 * PI * f64::from(h).powi(3)) as f32
}

/// Volume of the ellipsoid inscribed in the parallelepiped with edges `du`, `dv`, `dw` (m),
/// `(π/6)|(D_u x × D_v x)·D_w x|` (eq. 8.16) (m³).
pub fn ellipsoid_volume(du: Vec3, dv: Vec3, dw: Vec3) -> f32 {
    let (du, dv, dw) = (du.as_dvec3(), dv.as_dvec3(), dw.as_dvec3());
    (PI / 6.0 * du.cross(dv).dot(dw).abs()) as f32
}

/// Volume of `{x : |M(x − c)| < 1}`, `(4π/3)/|det M|` (m³): eq. 8.16 for `M` from
/// [`filter_matrix`]. `+∞` for a singular `M`.
pub fn filter_volume(m: Mat3) -> f32 {
    (4.0 / 3.0 * PI / m.as_dmat3().determinant().abs()) as f32
}

/// Smallest `|det[D_u D_v D_w]| / (|D_u||D_v||D_w|)` (the volume of the parallelepiped relative
/// to that of the box of the same edge lengths) for which [`filter_matrix`] inverts.
pub const MIN_RELATIVE_VOLUME: f64 = 1e-6;

/// The filter matrix `M = (½[D_u x D_v x D_w x])⁻¹` (m⁻¹) of an anisotropic kernel (sec. 8.3,
/// fig. 8.3) from its differential vectors (m). `None` when the vectors are not finite or
/// (nearly) coplanar ([`MIN_RELATIVE_VOLUME`]), where the kernel would be flat.
pub fn filter_matrix(du: Vec3, dv: Vec3, dw: Vec3) -> Option<Mat3> {
    let half = Mat3::from_cols(du, dv, dw).as_dmat3() * 0.5;
    let det = half.determinant();
    let scale = half.x_axis.length() * half.y_axis.length() * half.z_axis.length();
    if !(det.is_finite() && det.abs() > MIN_RELATIVE_VOLUME * scale) {
        return None;
    }
    let m = half.inverse().as_mat3();
    m.is_finite().then_some(m)
}

/// Relative amount by which the bounding radii are rounded up, so that the f32 ellipsoid lies
/// inside its f32 bounding sphere.
const BOUND_ROUND_UP: f32 = 4.0 * f32::EPSILON;

/// The largest semi-axis (m) of the ellipsoid inscribed in the parallelepiped with edges `du`,
/// `dv`, `dw`: `½ sqrt(λ_max(G))` with `G` the Gram matrix of the three vectors (the semi-axes
/// are the singular values of `½[D_u D_v D_w]`). The radius of the smallest sphere about the
/// centre that contains the kernel, slightly rounded up. `None` if an input is not finite.
pub fn axes_bounding_radius(du: Vec3, dv: Vec3, dw: Vec3) -> Option<f32> {
    let c = [du.as_dvec3(), dv.as_dvec3(), dw.as_dvec3()];
    let mut g = [[0.0f64; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            g[i][j] = c[i].dot(c[j]);
        }
    }
    let r = (0.5 * sym3_max_eigenvalue(g).sqrt()) as f32 * (1.0 + BOUND_ROUND_UP);
    r.is_finite().then_some(r)
}

/// The largest semi-axis (m) of `{x : |M(x − c)| < 1}`, `1/σ_min(M) = σ_max(M⁻¹)`, slightly
/// rounded up (see [`axes_bounding_radius`]). `None` if `M` is singular or not finite.
pub fn filter_bounding_radius(m: Mat3) -> Option<f32> {
    let md = m.as_dmat3();
    let det = md.determinant();
    if !(det.is_finite() && det != 0.0) {
        return None;
    }
    let inv = md.inverse();
    let c = [inv.x_axis, inv.y_axis, inv.z_axis];
    let mut g = [[0.0f64; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            g[i][j] = c[i].dot(c[j]);
        }
    }
    let r = sym3_max_eigenvalue(g).sqrt() as f32 * (1.0 + BOUND_ROUND_UP);
    r.is_finite().then_some(r)
}

/// Largest eigenvalue of a symmetric 3×3 matrix (Smith 1961, the trigonometric solution of the
/// characteristic cubic).
fn sym3_max_eigenvalue(a: [[f64; 3]; 3]) -> f64 {
    let p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * p1;
    if p2 == 0.0 {
        return q;
    }
    let p = (p2 / 6.0).sqrt();
    let b = |i: usize, j: usize| (a[i][j] - if i == j { q } else { 0.0 }) / p;
    let det_b = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
        - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
        + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
    let phi = (det_b / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    q + 2.0 * p * phi.cos()
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    /// The kernels written out again in f64 for the reference integrals (8.10, 8.12).
    fn k_ref(kernel: BeamKernel, u2: f64) -> f64 {
        if u2 >= 1.0 {
            return 0.0;
        }
        match kernel {
            BeamKernel::Uniform => 1.0,
            BeamKernel::Epanechnikov => 2.5 * (1.0 - u2),
        }
    }

    /// Midpoint rule over `[a, b]` with `n` cells.
    fn midpoint(a: f64, b: f64, n: usize, f: impl Fn(f64) -> f64) -> f64 {
        let dt = (b - a) / n as f64;
        (0..n).map(|i| f(a + (i as f64 + 0.5) * dt)).sum::<f64>() * dt
    }

    fn unit(rng: &mut Pcg32) -> Vec3 {
        loop {
            let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// Random differential vectors of lengths 0.02–0.4 m (anisotropy up to 20:1), not too
    /// close to coplanar.
    fn differentials(rng: &mut Pcg32) -> (Vec3, Vec3, Vec3) {
        loop {
            let d: Vec<Vec3> = (0..3)
                .map(|_| unit(rng) * (0.02 + 0.38 * rng.next_f32()))
                .collect();
            let rel =
                d[0].cross(d[1]).dot(d[2]).abs() / (d[0].length() * d[1].length() * d[2].length());
            if rel > 0.2 {
                return (d[0], d[1], d[2]);
            }
        }
    }

    /// `|M(x − c)|²` in f64: the world-space definition of the anisotropic kernel's argument.
    /// at the point `o + t w`.
    fn q_world(m: Mat3, c: Vec3, o: Vec3, w: Vec3, t: f64) -> f64 {
        let x = o.as_dvec3() + w.as_dvec3() * t;
        (m.as_dmat3() * (x - c.as_dvec3())).length_squared()
    }

    /// Kernel integrated along `seg` restricted to `[ta, tb]`, by world-space quadrature.
    fn quad_ellipsoid(
        kernel: BeamKernel,
        seg: &RaySegment,
        c: Vec3,
        m: Mat3,
        ta: f64,
        tb: f64,
    ) -> f64 {
        midpoint(ta, tb, 200_000, |t| {
            k_ref(kernel, q_world(m, c, seg.origin, seg.dir, t))
        })
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-6)
    }

    const KERNELS: [BeamKernel; 2] = [BeamKernel::Uniform, BeamKernel::Epanechnikov];

    /// TM1: 8.11 and corrected 8.13 equal the kernel integrated along the chord by quadrature
    /// in `t` (8.5 without its factor 2), and `ball_weight` with the whole chord equals them.
    #[test]
    fn the_radial_mass_is_the_kernels_integral() {
        // C(a) against a midpoint rule of ∫₀^a K(u) u² du / ∫₀¹ K(u) u² du.
        for kernel in [BeamKernel::Uniform, BeamKernel::Epanechnikov] {
            let integral = |a: f64| {
                let n = 20_000;
                (0..n)
                    .map(|i| {
                        let u = a * (i as f64 + 0.5) / n as f64;
                        k_ref(kernel, u * u) * u * u * a / n as f64
                    })
                    .sum::<f64>()
            };
            for a in [0.0, 0.1, 0.35, 0.5, 0.8, 1.0] {
                let want = integral(a) / integral(1.0);
                let got = kernel.radial_mass(a as f32) as f64;
                assert!(
                    (got - want).abs() < 1e-5,
                    "{kernel:?} C({a}) = {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn closed_forms_811_813_match_quadrature_along_t() {
        let mut rng = Pcg32::new(81, 1);
        for _ in 0..40 {
            let h = 0.01 + rng.next_f32();
            let y_s = h * rng.next_f32() * 0.99;
            for k in KERNELS {
                let (hd, yd) = (f64::from(h), f64::from(y_s));
                let reference = midpoint(-hd, hd, 100_000, |t| {
                    k_ref(k, (t * t + yd * yd) / (hd * hd))
                });
                let closed = f64::from(k.chord_weight(h, y_s));
                assert!(
                    close(closed, reference, 1e-4),
                    "{k:?} h={h} y_s={y_s}: {closed} vs {reference}"
                );
                // The same through a ray at distance y_s from the centre.
                let dir = unit(&mut rng);
                let side = dir.any_orthonormal_vector();
                let c = Vec3::new(0.3, -0.2, 0.5);
                let seg = RaySegment::new(c + side * y_s - dir * 3.0, dir, 0.0, 10.0);
                let hit = ball_weight(k, &seg, c, h, Clip::WholeChord).expect("crosses");
                assert!(
                    close(f64::from(hit.weight), reference, 1e-3),
                    "{k:?}: {hit:?}"
                );
            }
        }
        for k in KERNELS {
            assert_eq!(k.chord_weight(1.0, 1.0), 0.0);
            assert_eq!(k.chord_weight(1.0, 2.0), 0.0);
        }
    }

    /// TM1: 8.15 (and the uniform chord `2 sqrt((1 − y²)/a)`) for random anisotropic `M` and
    /// directions equals the kernel `K(|M(x(t) − c)|²)` integrated along the ray in world space.
    #[test]
    fn anisotropic_815_matches_world_space_quadrature() {
        let mut rng = Pcg32::new(815, 3);
        let mut crossed = 0;
        for _ in 0..60 {
            let (du, dv, dw) = differentials(&mut rng);
            let m = filter_matrix(du, dv, dw).expect("not coplanar");
            let r = filter_bounding_radius(m).expect("regular");
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let dir = unit(&mut rng);
            // Lines passing within the bounding sphere, most of them through the ellipsoid.
            let side = unit(&mut rng).reject_from(dir).normalize_or_zero();
            let off = side * r * rng.next_f32() * 0.7;
            let seg = RaySegment::new(
                c + off - dir * 2.0 * r,
                dir,
                f32::NEG_INFINITY,
                f32::INFINITY,
            );
            let tc = f64::from((c - seg.origin).dot(dir));
            let rd = f64::from(r);
            for k in KERNELS {
                let reference = quad_ellipsoid(k, &seg, c, m, tc - rd, tc + rd);
                let hit = ellipsoid_weight(k, &seg, c, m, Clip::WholeChord);
                let w = hit.map_or(0.0, |h| f64::from(h.weight));
                assert!(
                    (w - reference).abs() <= 2e-3 * reference + 1e-6,
                    "{k:?}: {w} vs {reference}"
                );
                crossed += usize::from(hit.is_some());
            }
        }
        assert!(crossed > 60, "too few crossings to test: {crossed}");
    }

    /// TM1: with `M = I/h` the anisotropic weight is the isotropic one, i.e. 8.15 reduces to
    /// (corrected) 8.13 and the filter-space closest point to the Euclidean one.
    #[test]
    fn identity_over_h_reduces_to_813() {
        let mut rng = Pcg32::new(813, 5);
        for _ in 0..200 {
            let h = 0.05 + rng.next_f32();
            let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let dir = unit(&mut rng);
            let side = dir.any_orthonormal_vector();
            let y_s = h * rng.next_f32();
            let seg = RaySegment::new(c + side * y_s - dir * 5.0, dir, 0.0, 20.0);
            let m = Mat3::from_diagonal(Vec3::splat(1.0 / h));
            for clip in [Clip::WholeChord, Clip::Exact] {
                for k in KERNELS {
                    let e = ellipsoid_weight(k, &seg, c, m, clip);
                    let b = ball_weight(k, &seg, c, h, clip);
                    let (e, b) = match (e, b) {
                        (Some(e), Some(b)) => (e, b),
                        (None, None) => continue,
                        other => panic!("disagree: {other:?}"),
                    };
                    let closed = f64::from(k.chord_weight(h, y_s));
                    assert!(
                        close(f64::from(e.weight), closed, 1e-3),
                        "{e:?} vs {closed}"
                    );
                    assert!(
                        close(f64::from(b.weight), closed, 1e-3),
                        "{b:?} vs {closed}"
                    );
                    assert!((e.t - 5.0).abs() < 1e-4 && (b.t - 5.0).abs() < 1e-4);
                }
            }
        }
    }

    /// TM1: the clipped weight equals the whole chord's when `[t0, t1]` covers the chord, equals
    /// world-space quadrature over a partial chord (segments starting or ending inside the
    /// kernel), and is additive over consecutive segments.
    #[test]
    fn clipped_weight_is_the_integral_over_the_overlap() {
        let mut rng = Pcg32::new(916, 7);
        for i in 0..60 {
            let (du, dv, dw) = differentials(&mut rng);
            let (c, m) = if i % 3 == 0 {
                let h = 0.05 + 0.3 * rng.next_f32();
                (Vec3::ZERO, Mat3::from_diagonal(Vec3::splat(1.0 / h)))
            } else {
                (
                    Vec3::new(0.2, 0.1, -0.4),
                    filter_matrix(du, dv, dw).expect("regular"),
                )
            };
            let dir = unit(&mut rng);
            let o = c - dir * 1.5 + unit(&mut rng).reject_from(dir) * 0.02;
            let full = RaySegment::new(o, dir, 0.0, 3.0);
            let chord = FilterChord::ellipsoid(&full, c, m).expect("regular");
            if chord.y2 > 0.95 {
                continue;
            }
            let half = chord.half_length();
            let (lo, hi) = (chord.t_star - half, chord.t_star + half);
            for k in KERNELS {
                let whole = ellipsoid_weight(k, &full, c, m, Clip::WholeChord).expect("crosses");
                let exact = ellipsoid_weight(k, &full, c, m, Clip::Exact).expect("crosses");
                assert!(close(
                    f64::from(exact.weight),
                    f64::from(whole.weight),
                    1e-5
                ));
                // A segment from inside the kernel to inside it, and one from inside to beyond.
                let ta = lo + (hi - lo) * rng.next_f32();
                let tb = ta + (hi + 0.1 - ta) * rng.next_f32();
                let part = RaySegment {
                    t0: ta,
                    t1: tb,
                    ..full
                };
                let got = ellipsoid_weight(k, &part, c, m, Clip::Exact).map_or(0.0, |h| h.weight);
                let reference = quad_ellipsoid(k, &part, c, m, f64::from(ta), f64::from(tb));
                assert!(
                    (f64::from(got) - reference).abs()
                        <= 2e-3 * reference + 1e-6 * f64::from(whole.weight),
                    "{k:?} [{ta}, {tb}] in [{lo}, {hi}]: {got} vs {reference}"
                );
                // Additivity over [0, ta] + [ta, 3].
                let first = RaySegment { t1: ta, ..full };
                let second = RaySegment { t0: ta, ..full };
                let sum: f32 = [first, second]
                    .iter()
                    .filter_map(|s| ellipsoid_weight(k, s, c, m, Clip::Exact))
                    .map(|h| h.weight)
                    .sum();
                assert!(close(f64::from(sum), f64::from(exact.weight), 1e-4));
                // The whole chord is counted once per crossing segment: twice here.
                let whole_sum: f32 = [first, second]
                    .iter()
                    .filter_map(|s| ellipsoid_weight(k, s, c, m, Clip::WholeChord))
                    .map(|h| h.weight)
                    .sum();
                assert!(close(
                    f64::from(whole_sum),
                    2.0 * f64::from(whole.weight),
                    1e-5
                ));
            }
        }
    }

    /// `BeamHit::t` is the Euclidean closest point for a ball and the filter-space closest
    /// point for an ellipsoid (the minimum of `q` over the segment), clamped to `[t0, t1]`.
    #[test]
    fn closest_point_minimises_the_filter_distance_on_the_segment() {
        let mut rng = Pcg32::new(44, 9);
        for _ in 0..200 {
            let (du, dv, dw) = differentials(&mut rng);
            let m = filter_matrix(du, dv, dw).expect("regular");
            let c = Vec3::ZERO;
            let dir = unit(&mut rng);
            let o = c - dir * 1.0 + unit(&mut rng).reject_from(dir) * 0.05;
            let t0 = 0.6 + 0.8 * rng.next_f32();
            let seg = RaySegment::new(o, dir, t0, t0 + 0.8 * rng.next_f32());
            let Some(hit) = ellipsoid_weight(BeamKernel::Epanechnikov, &seg, c, m, Clip::Exact)
            else {
                continue;
            };
            assert!(hit.t >= seg.t0 && hit.t <= seg.t1);
            let q = |t: f32| q_world(m, c, seg.origin, seg.dir, f64::from(t));
            for j in 0..=50 {
                let t = seg.t0 + (seg.t1 - seg.t0) * j as f32 / 50.0;
                assert!(q(hit.t) <= q(t) + 1e-4, "t*={} t={t}", hit.t);
            }
            // A ball: the Euclidean closest point, clamped.
            let ball = ball_weight(BeamKernel::Uniform, &seg, c, 0.5, Clip::Exact);
            if let Some(b) = ball {
                let tc = (c - o).dot(dir).clamp(seg.t0, seg.t1);
                assert!((b.t - tc).abs() < 1e-5);
            }
        }
    }

    /// TM2: over a dense grid of parallel rays, `Σ w dA⊥ = V` (the kernel has mean 1 over its
    /// volume, eq. 8.4's normalisation) for balls and random anisotropic kernels, with `V` from
    /// `4πh³/3` and from eq. 8.16.
    #[test]
    fn parallel_rays_integrate_the_weight_to_the_volume() {
        let mut rng = Pcg32::new(2024, 11);
        for i in 0..6 {
            let (du, dv, dw) = differentials(&mut rng);
            let (m, volume) = if i < 2 {
                let h = 0.1 + rng.next_f32();
                (Mat3::from_diagonal(Vec3::splat(1.0 / h)), ball_volume(h))
            } else {
                let m = filter_matrix(du, dv, dw).expect("regular");
                (m, ellipsoid_volume(du, dv, dw))
            };
            let c = Vec3::new(0.5, -1.0, 2.0);
            let r = filter_bounding_radius(m).expect("regular");
            let dir = unit(&mut rng);
            let e1 = dir.any_orthonormal_vector();
            let e2 = dir.cross(e1);
            let n = 400;
            let cell = 2.0 * f64::from(r) / n as f64;
            for k in KERNELS {
                let mut sum = 0.0f64;
                for a in 0..n {
                    for b in 0..n {
                        let x = -f64::from(r) + (a as f64 + 0.5) * cell;
                        let y = -f64::from(r) + (b as f64 + 0.5) * cell;
                        let o = c + e1 * x as f32 + e2 * y as f32 - dir * 2.0 * r;
                        let seg = RaySegment::new(o, dir, 0.0, 4.0 * r);
                        if let Some(h) = ellipsoid_weight(k, &seg, c, m, Clip::Exact) {
                            sum += f64::from(h.weight);
                        }
                    }
                }
                let got = sum * cell * cell;
                assert!(
                    close(got, f64::from(volume), 3e-3),
                    "{k:?} #{i}: {got} vs {volume}"
                );
            }
        }
    }

    /// TM3: eq. 8.16 `(π/6)|(D_u × D_v)·D_w|` equals the Monte-Carlo volume of
    /// `{x : |M(x − c)| < 1}` (and `(4π/3)/|det M|`).
    #[test]
    fn volume_816_matches_monte_carlo() {
        let mut rng = Pcg32::new(816, 13);
        for _ in 0..5 {
            let (du, dv, dw) = differentials(&mut rng);
            let m = filter_matrix(du, dv, dw).expect("regular");
            let c = Vec3::new(-0.3, 0.7, 0.1);
            let r = filter_bounding_radius(m).expect("regular");
            let n = 400_000;
            let inside = (0..n)
                .filter(|_| {
                    let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
                    q_world(m, c, c + u * r, Vec3::ZERO, 0.0) < 1.0
                })
                .count();
            let p = inside as f64 / n as f64;
            let cube = (2.0 * f64::from(r)).powi(3);
            let mc = p * cube;
            let sigma = (p * (1.0 - p) / n as f64).sqrt() * cube;
            let v816 = f64::from(ellipsoid_volume(du, dv, dw));
            assert!(
                (v816 - mc).abs() < 4.0 * sigma,
                "8.16 {v816} vs MC {mc} ± {sigma}"
            );
            assert!(close(f64::from(filter_volume(m)), v816, 1e-5));
        }
        assert!(close(f64::from(ball_volume(2.0)), 32.0 / 3.0 * PI, 1e-6));
    }

    /// The bounding radius is the largest semi-axis: no point of the ellipsoid's surface
    /// `c + M⁻¹u` lies beyond it, and some come within 0.1 % of it; both forms agree.
    #[test]
    fn bounding_radius_is_the_largest_semi_axis() {
        let mut rng = Pcg32::new(5, 15);
        for _ in 0..50 {
            let (du, dv, dw) = differentials(&mut rng);
            let m = filter_matrix(du, dv, dw).expect("regular");
            let r = filter_bounding_radius(m).expect("regular");
            let r_axes = axes_bounding_radius(du, dv, dw).expect("finite");
            assert!(
                close(f64::from(r), f64::from(r_axes), 1e-5),
                "{r} vs {r_axes}"
            );
            let inv = m.inverse();
            let far = (0..20_000)
                .map(|_| (inv * unit(&mut rng)).length())
                .fold(0.0f32, f32::max);
            assert!(far <= r, "{far} > {r}");
            assert!(far > 0.999 * r, "{far} vs {r}");
            // Never smaller than the differentials' half-lengths (the ellipsoid touches the
            // parallelepiped's faces at ±½D).
            assert!(r >= 0.5 * du.length().max(dv.length()).max(dw.length()));
        }
    }

    /// The beam kernels are the crate's 3-D kernels times the unit-ball volume (mean 1).
    #[test]
    fn beam_kernels_are_the_3d_kernels_with_mean_one() {
        for (bk, k) in [
            (BeamKernel::Uniform, Kernel::Uniform),
            (BeamKernel::Epanechnikov, Kernel::Epanechnikov),
        ] {
            assert_eq!(BeamKernel::try_from(k), Ok(bk));
            for i in 0..=110 {
                let u2 = i as f32 / 100.0;
                let want = k.eval(u2, crate::Dim::Three) * (4.0 / 3.0 * std::f32::consts::PI);
                assert!((bk.eval(u2) - want).abs() < 1e-5, "{bk:?} {u2}");
            }
        }
        assert_eq!(BeamKernel::Epanechnikov.eval(0.0), 2.5);
        assert_eq!(BeamKernel::Uniform.eval(f32::NAN), 0.0);
        assert!(matches!(
            BeamKernel::try_from(Kernel::Biweight),
            Err(DensityError::UnsupportedBeamKernel(_))
        ));
    }

    /// Misses, empty or reversed segments, and degenerate kernels give `None`.
    #[test]
    fn degenerate_inputs_give_none() {
        let k = BeamKernel::Epanechnikov;
        let seg = RaySegment::new(Vec3::new(0.0, 0.0, -2.0), Vec3::Z, 0.0, 4.0);
        assert!(ball_weight(k, &seg, Vec3::ZERO, 1.0, Clip::Exact).is_some());
        // Passing at distance >= h, before t0 or after t1, reversed, empty.
        assert!(ball_weight(k, &seg, Vec3::new(1.0, 0.0, 0.0), 1.0, Clip::Exact).is_none());
        assert!(ball_weight(k, &seg, Vec3::new(0.0, 0.0, -3.5), 1.0, Clip::Exact).is_none());
        assert!(ball_weight(k, &seg, Vec3::new(0.0, 0.0, 3.0), 1.0, Clip::WholeChord).is_none());
        let rev = RaySegment {
            t0: 3.0,
            t1: 1.0,
            ..seg
        };
        assert!(ball_weight(k, &rev, Vec3::ZERO, 1.0, Clip::Exact).is_none());
        let empty = RaySegment {
            t0: 2.0,
            t1: 2.0,
            ..seg
        };
        assert!(ball_weight(k, &empty, Vec3::ZERO, 1.0, Clip::Exact).is_none());
        for h in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(
                ball_weight(k, &seg, Vec3::ZERO, h, Clip::Exact).is_none(),
                "{h}"
            );
        }
        let nan = RaySegment {
            origin: Vec3::NAN,
            ..seg
        };
        assert!(ball_weight(k, &nan, Vec3::ZERO, 1.0, Clip::Exact).is_none());
        assert!(ellipsoid_weight(k, &seg, Vec3::ZERO, Mat3::ZERO, Clip::Exact).is_none());
        assert!(filter_matrix(Vec3::X, Vec3::Y, Vec3::X + Vec3::Y).is_none());
        assert!(filter_matrix(Vec3::X, Vec3::Y, Vec3::NAN).is_none());
        assert!(filter_bounding_radius(Mat3::ZERO).is_none());
        // A ray escaping to infinity.
        let escape = RaySegment {
            t1: f32::INFINITY,
            ..seg
        };
        let hit = ball_weight(k, &escape, Vec3::ZERO, 1.0, Clip::Exact).expect("crosses");
        assert!((hit.weight - k.chord_weight(1.0, 0.0)).abs() < 1e-5 && hit.t == 2.0);
    }

    #[test]
    fn grazing_rays_through_thin_kernels_stay_finite_and_bounded() {
        // Bad input of the vpd issue: kernels 10⁶ times thinner than wide (nearly collapsed
        // footprints) crossed by rays almost in their plane. Each weight is finite, ≥ 0 and at
        // most the kernel's largest chord weight (10/3 × the longest semi-axis).
        let mut rng = Pcg32::new(12, 1);
        let mut crossed = 0;
        for _ in 0..20_000 {
            let (du, dv, _) = differentials(&mut rng);
            let n = du.cross(dv).normalize();
            let thin = n * (du.length() * 1e-6);
            let Some(m) = filter_matrix(du, dv, thin) else {
                continue;
            };
            let r = axes_bounding_radius(du, dv, thin).unwrap();
            // In the kernel's plane up to an angle of 1e-4…1e-7 rad.
            let tilt = 10f32.powf(-4.0 - 3.0 * rng.next_f32());
            let dir = (du.normalize() + n * tilt).normalize();
            let o = -dir * 3.0 * r + dv * (rng.next_f32() - 0.5);
            for kernel in [BeamKernel::Epanechnikov, BeamKernel::Uniform] {
                for clip in [Clip::Exact, Clip::WholeChord] {
                    let seg = RaySegment::new(o, dir, 0.0, 3.0 * r + r * rng.next_f32());
                    if let Some(hit) = ellipsoid_weight(kernel, &seg, Vec3::ZERO, m, clip) {
                        assert!(hit.weight.is_finite() && hit.weight >= 0.0, "{hit:?}");
                        assert!(hit.weight <= 10.0 / 3.0 * r * 1.001, "{hit:?} r {r}");
                        assert!(hit.t.is_finite());
                        crossed += 1;
                    }
                }
            }
        }
        assert!(crossed > 20_000, "{crossed} crossings");
    }
}

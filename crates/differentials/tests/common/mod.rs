//! Shared test scaffolding: parameterised ray families, moving triangles, an exact reference
//! tracer written independently of the crate's formulas, and the O(ε²) finite-difference
//! check.
//!
//! Precision choice: the crate works in `f32` like the renderer, so the tests use `f32` too
//! and pick ε well above `f32` noise. The parameters are scaled so that a step of ε = 1/32
//! turns the direction by ~1° and moves the origin by ~1 cm in a scene of size ~10 m: the
//! second-order remainder is then ~1e-4, three orders of magnitude above the ~1e-7 rounding
//! noise, and the third-order term shifts the error ratio from 4 by only a few per cent.
//! Errors below `FLOOR` count as "exactly linear in this parameter" (e.g. a parallel
//! translation of the origin onto a plane), where the ratio is rounding noise.
#![allow(dead_code)]

use caustica_core::Vec3;
use caustica_differentials::{RayDiff, TriangleMotion};

/// Number of parameters: θ₀, θ₁ move the origin, θ₂, θ₃ turn the direction (a photon
/// differential's 2 + 2, seed 002), θ₄ is time, which moves the triangles (seed 000 ch. 7).
pub const N: usize = 5;

/// Step of the finite differences (units of θ); the check also uses ε/2.
pub const EPS: f32 = 1.0 / 32.0;

/// Absolute error below which a parameter counts as acting linearly (rounding noise).
pub const FLOOR: f32 = 4e-6;

/// Accepted range of err(ε)/err(ε/2): "about 4", i.e. second order.
pub const RATIO: (f32, f32) = (3.2, 4.8);

/// `P(θ) = p0 + Σ θᵢ aᵢ`, `V(θ) = normalize(v0 + Σ θᵢ bᵢ)`.
#[derive(Clone, Copy)]
pub struct Family {
    pub p0: Vec3,
    pub a: [Vec3; N],
    pub v0: Vec3,
    pub b: [Vec3; N],
}

impl Family {
    pub fn at(&self, th: &[f32; N]) -> (Vec3, Vec3) {
        let mut p = self.p0;
        let mut v = self.v0;
        for ((t, a), b) in th.iter().zip(&self.a).zip(&self.b) {
            p += *t * *a;
            v += *t * *b;
        }
        (p, v.normalize())
    }
    /// The differential at θ = 0 (via eq. B.5b for the normalisation).
    pub fn diff(&self) -> RayDiff<N> {
        RayDiff::from_unnormalized(self.p0, self.v0, self.a, self.b).unwrap()
    }
}

/// The standard family: origin near the z = 0 plane, heading +z, every parameter mixed.
pub fn family() -> Family {
    Family {
        p0: Vec3::new(0.1, -0.2, 0.0),
        a: [
            Vec3::new(0.35, 0.05, 0.0),
            Vec3::new(-0.05, 0.3, 0.1),
            Vec3::new(0.05, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::ZERO,
        ],
        v0: Vec3::new(0.08, 0.05, 1.0),
        b: [
            Vec3::ZERO,
            Vec3::new(0.0, 0.25, 0.0),
            Vec3::new(0.6, 0.1, 0.0),
            Vec3::new(0.05, 0.5, 0.2),
            Vec3::ZERO,
        ],
    }
}

/// A triangle whose vertices and vertex normals move linearly with θ₄ (time).
#[derive(Clone, Copy)]
pub struct Tri {
    pub q: [Vec3; 3],
    pub n: [Vec3; 3],
    pub dq: [Vec3; 3],
    pub dn: [Vec3; 3],
}

impl Tri {
    pub fn at(&self, th: &[f32; N]) -> ([Vec3; 3], [Vec3; 3]) {
        let t = th[4];
        (
            std::array::from_fn(|k| self.q[k] + t * self.dq[k]),
            std::array::from_fn(|k| self.n[k] + t * self.dn[k]),
        )
    }
    pub fn motion(&self) -> TriangleMotion<N> {
        let mut m = TriangleMotion::stationary();
        for k in 0..3 {
            m.dq[k][4] = self.dq[k];
            m.dn[k][4] = self.dn[k];
        }
        m
    }
    pub fn stationary(mut self) -> Self {
        self.dq = [Vec3::ZERO; 3];
        self.dn = [Vec3::ZERO; 3];
        self
    }
}

/// Glass-like triangle facing the family (normals towards −z, clearly non-parallel), moving.
pub fn tri_a() -> Tri {
    Tri {
        q: [
            Vec3::new(-3.0, -3.0, 2.0),
            Vec3::new(3.0, -2.5, 2.4),
            Vec3::new(0.5, 3.0, 1.8),
        ],
        n: [
            Vec3::new(0.3, 0.1, -1.0),
            Vec3::new(-0.25, 0.3, -1.0),
            Vec3::new(0.1, -0.35, -1.0),
        ],
        dq: [
            Vec3::new(0.0, 0.0, 0.4),
            Vec3::new(0.2, -0.1, 0.0),
            Vec3::new(0.0, 0.3, -0.3),
        ],
        dn: [
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(0.0, -0.3, 0.1),
            Vec3::new(0.1, 0.1, 0.0),
        ],
    }
}

/// Mirror tilted by ~45° about x (plane z ≈ 6 + y), reflecting +z rays towards +y.
pub fn tri_b() -> Tri {
    Tri {
        q: [
            Vec3::new(-3.0, -3.0, 3.0),
            Vec3::new(3.0, -3.2, 3.1),
            Vec3::new(0.2, 3.0, 9.0),
        ],
        n: [
            Vec3::new(0.2, 1.0, -1.0),
            Vec3::new(-0.2, 1.1, -0.9),
            Vec3::new(0.0, 0.8, -1.2),
        ],
        dq: [
            Vec3::new(0.0, 0.3, 0.0),
            Vec3::new(0.0, 0.0, 0.3),
            Vec3::new(-0.2, 0.0, 0.0),
        ],
        dn: [
            Vec3::new(0.0, 0.1, 0.0),
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.15),
        ],
    }
}

/// Screen near the plane y = 4, facing −y.
pub fn tri_c() -> Tri {
    Tri {
        q: [
            Vec3::new(-5.0, 4.0, 0.0),
            Vec3::new(5.0, 4.3, 0.0),
            Vec3::new(0.0, 3.8, 12.0),
        ],
        n: [Vec3::NEG_Y; 3],
        dq: [
            Vec3::new(0.0, 0.2, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.1, -0.2, 0.0),
        ],
        dn: [Vec3::ZERO; 3],
    }
}

// ---- exact reference tracer (independent formulas) -------------------------------------

/// Exact hit of the ray with the plane of `q`, or None.
pub fn plane_hit(p: Vec3, v: Vec3, q: &[Vec3; 3]) -> Option<Vec3> {
    let n = (q[1] - q[0]).cross(q[2] - q[0]);
    let s = (q[0] - p).dot(n) / v.dot(n);
    (s > 0.0).then(|| p + s * v)
}

/// Barycentrics of a point in the plane of `q`, by area ratios.
pub fn bary(x: Vec3, q: &[Vec3; 3]) -> [f32; 3] {
    let (e0, e1) = (q[1] - q[0], q[2] - q[0]);
    let n = e0.cross(e1);
    let d = x - q[0];
    let l1 = d.cross(e1).dot(n) / n.length_squared();
    let l2 = e0.cross(d).dot(n) / n.length_squared();
    [1.0 - l1 - l2, l1, l2]
}

/// Which normal the scattering uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Model {
    Flat,
    Phong,
}

/// Exact normal at `x` (any orientation; callers orient it as they need).
pub fn normal_at(model: Model, x: Vec3, q: &[Vec3; 3], n: &[Vec3; 3]) -> Vec3 {
    match model {
        Model::Flat => (q[1] - q[0]).cross(q[2] - q[0]).normalize(),
        Model::Phong => {
            let l = bary(x, q);
            (l[0] * n[0] + l[1] * n[1] + l[2] * n[2]).normalize()
        }
    }
}

pub fn mirror(v: Vec3, n: Vec3) -> Vec3 {
    v - 2.0 * v.dot(n) * n
}

/// Snell refraction by tangential/normal decomposition, `eta = n_i / n_t`.
pub fn snell(v: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let nt = if v.dot(n) < 0.0 { -n } else { n }; // towards the transmission side
    let c = v.dot(nt);
    let tangential = eta * (v - c * nt);
    let sin2 = tangential.length_squared();
    (sin2 < 1.0).then(|| tangential + (1.0 - sin2).sqrt() * nt)
}

// ---- the finite-difference check --------------------------------------------------------

/// Outcome of checking one quantity (position or direction) for one parameter.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    pub err_eps: f32,
    pub err_half: f32,
    pub ok: bool,
}

fn judge(err_eps: f32, err_half: f32) -> Outcome {
    let ok = if err_eps <= FLOOR && err_half <= FLOOR {
        true // linear in this parameter: both errors are rounding noise
    } else {
        let r = err_eps / err_half;
        r >= RATIO.0 && r <= RATIO.1
    };
    Outcome {
        err_eps,
        err_half,
        ok,
    }
}

/// Compares `exact(θ)` for θ = ±h eᵢ (h = ε, ε/2) with the first-order prediction of `pred`;
/// returns `(param, position outcome, direction outcome)` for every parameter and prints them.
pub fn fd_check(
    name: &str,
    exact: impl Fn(&[f32; N]) -> (Vec3, Vec3),
    pred: &RayDiff<N>,
) -> Vec<(usize, Outcome, Outcome)> {
    let (p0, v0) = exact(&[0.0; N]);
    assert!(
        (p0 - pred.p).length() < 1e-4 && (v0 - pred.v).length() < 1e-5,
        "{name}: base ray differs: exact ({p0}, {v0}) vs differential ({}, {})",
        pred.p,
        pred.v
    );
    let mut out = Vec::new();
    for i in 0..N {
        let err = |h: f32| {
            let mut ep = 0.0f32;
            let mut ev = 0.0f32;
            for sign in [1.0f32, -1.0] {
                let mut th = [0.0; N];
                th[i] = sign * h;
                let (p, v) = exact(&th);
                ep = ep.max(((p - p0) - sign * h * pred.dp[i]).length());
                ev = ev.max(((v - v0) - sign * h * pred.dv[i]).length());
            }
            (ep, ev)
        };
        let (pe, ve) = err(EPS);
        let (ph, vh) = err(EPS / 2.0);
        let (po, vo) = (judge(pe, ph), judge(ve, vh));
        println!(
            "{name:<28} θ{i}: pos err {pe:.3e} → {ph:.3e} (×{:5.2}) {}   dir err {ve:.3e} → {vh:.3e} (×{:5.2}) {}",
            pe / ph,
            if po.ok { "ok" } else { "FAIL" },
            ve / vh,
            if vo.ok { "ok" } else { "FAIL" },
        );
        out.push((i, po, vo));
    }
    out
}

/// Asserts that every parameter passes, and that at least one check was non-trivial (above
/// the noise floor), so the test cannot pass vacuously.
pub fn assert_fd(name: &str, results: &[(usize, Outcome, Outcome)]) {
    for (i, po, vo) in results {
        assert!(po.ok, "{name}: position derivative θ{i} not O(ε²): {po:?}");
        assert!(vo.ok, "{name}: direction derivative θ{i} not O(ε²): {vo:?}");
    }
    assert!(
        results
            .iter()
            .any(|(_, po, vo)| po.err_eps > FLOOR || vo.err_eps > FLOOR),
        "{name}: every error under the noise floor; the check is vacuous"
    );
}

/// Asserts `v · dv[i] ≈ 0`: the derivatives are those of a unit direction.
pub fn assert_unit_derivatives(name: &str, r: &RayDiff<N>) {
    assert!(
        (r.v.length() - 1.0).abs() < 1e-5,
        "{name}: |v| = {}",
        r.v.length()
    );
    for (i, dv) in r.dv.iter().enumerate() {
        assert!(
            r.v.dot(*dv).abs() < 1e-4 * (1.0 + dv.length()),
            "{name}: v·dv[{i}] = {}",
            r.v.dot(*dv)
        );
    }
}

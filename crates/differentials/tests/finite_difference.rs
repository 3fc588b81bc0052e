//! Acceptance test of issue 5's differential algebra: every propagated differential agrees
//! with finite differences of exactly traced neighbouring rays to O(ε²) (the error at ε is
//! about 4× the error at ε/2), for transfer, reflection and refraction on flat and Phong
//! triangles, stationary and moving, and for a chain of them. See `common/mod.rs` for the
//! choice of ε in `f32`. Run with `--nocapture` to see the error table.

mod common;

use caustica_core::{Ray, RayDifferential, Vec3};
use caustica_differentials::{
    FlatTriangle, PhongTriangle, RayDiff, SurfaceHit, TriangleMotion, reflect,
    reflection_jacobians, refract, refraction_jacobians, transfer_to_fixed_plane,
};
use common::*;

#[derive(Clone, Copy, Debug)]
enum Op {
    Transfer,
    Reflect,
    Refract(f32),
    /// Refraction with `η(θ) = η + Σ θᵢ ∂η/∂θᵢ`: a dispersive interface with wavelength among
    /// the parameters (issue 22).
    Dispersive(f32, [f32; N]),
}

fn predicted_hit(
    model: Model,
    tri: &Tri,
    ray: &RayDiff<N>,
    motion: &TriangleMotion<N>,
) -> SurfaceHit<N> {
    // A stationary triangle goes through `hit`, the fast path the renderer uses.
    let stationary = *motion == TriangleMotion::stationary();
    match (model, stationary) {
        (Model::Flat, true) => FlatTriangle { q: tri.q }.hit(ray),
        (Model::Flat, false) => FlatTriangle { q: tri.q }.hit_moving(ray, motion),
        (Model::Phong, true) => PhongTriangle { q: tri.q, n: tri.n }.hit(ray),
        (Model::Phong, false) => PhongTriangle { q: tri.q, n: tri.n }.hit_moving(ray, motion),
    }
    .expect("hit")
}

/// The stationary fast path (`hit`, `FlatTriangle::transfer`) computes what the general
/// moving-triangle path computes with zero motion, to rounding.
#[test]
fn stationary_fast_path_matches_the_general_path() {
    let close = |a: Vec3, b: Vec3, what: &str| {
        let tol = 1e-5 * (1.0 + a.length().max(b.length()));
        assert!((a - b).length() <= tol, "{what}: {a} vs {b}");
    };
    let fam = family();
    let ray = fam.diff();
    for tri in [tri_a(), tri_b(), tri_c()] {
        let zero = TriangleMotion::stationary();
        let flat = FlatTriangle { q: tri.q };
        let phong = PhongTriangle { q: tri.q, n: tri.n };
        for (fast, general) in [
            (flat.hit(&ray), flat.hit_moving(&ray, &zero)),
            (phong.hit(&ray), phong.hit_moving(&ray, &zero)),
        ] {
            let (f, g) = (fast.expect("fast hit"), general.expect("general hit"));
            close(f.ray.p, g.ray.p, "Q");
            close(f.normal, g.normal, "N");
            assert!((f.s - g.s).abs() <= 1e-5 * g.s, "s");
            for i in 0..N {
                close(f.ray.dp[i], g.ray.dp[i], "dQ");
                close(f.ray.dv[i], g.ray.dv[i], "dV");
                close(f.dnormal[i], g.dnormal[i], "dN");
                assert!(
                    (f.ds[i] - g.ds[i]).abs() <= 1e-5 * (1.0 + g.ds[i].abs()),
                    "ds"
                );
                for k in 0..3 {
                    let (a, b) = (f.dbarycentrics[i][k], g.dbarycentrics[i][k]);
                    assert!((a - b).abs() <= 1e-5 * (1.0 + b.abs()), "dλ");
                }
            }
            // Where a photon lands the renderer transfers onto the plane through the hit with
            // the geometric normal: the same position differentials as the full hit.
            let t = transfer_to_fixed_plane(&ray, g.ray.p, g.geometric_normal).expect("transfer");
            close(t.ray.p, g.ray.p, "transfer Q");
            for i in 0..N {
                close(t.ray.dp[i], g.ray.dp[i], "transfer dQ");
            }
        }
    }
}

fn apply(op: Op, hit: &SurfaceHit<N>) -> RayDiff<N> {
    match op {
        Op::Transfer => hit.ray,
        Op::Reflect => hit.reflect().expect("reflect"),
        Op::Refract(eta) => hit.refract(eta).expect("refract"),
        Op::Dispersive(eta, deta) => hit.refract_dispersive(eta, &deta).expect("refract"),
    }
}

fn exact_step(model: Model, op: Op, tri: &Tri, th: &[f32; N], p: Vec3, v: Vec3) -> (Vec3, Vec3) {
    let (q, n) = tri.at(th);
    let x = plane_hit(p, v, &q).expect("exact hit");
    let normal = normal_at(model, x, &q, &n);
    let w = match op {
        Op::Transfer => v,
        Op::Reflect => mirror(v, normal),
        Op::Refract(eta) => snell(v, normal, eta).expect("exact refraction"),
        Op::Dispersive(eta, deta) => {
            let eta = eta + th.iter().zip(&deta).map(|(t, d)| t * d).sum::<f32>();
            snell(v, normal, eta).expect("exact refraction")
        }
    };
    (x, w)
}

fn single(model: Model, op: Op, moving: bool) {
    let fam = family();
    let tri = if moving {
        tri_a()
    } else {
        tri_a().stationary()
    };
    let name = format!("{model:?} {op:?}{}", if moving { " moving" } else { "" });
    let hit = predicted_hit(model, &tri, &fam.diff(), &tri.motion());
    let pred = apply(op, &hit);
    assert_unit_derivatives(&name, &pred);
    let res = fd_check(
        &name,
        |th| {
            let (p, v) = fam.at(th);
            exact_step(model, op, &tri, th, p, v)
        },
        &pred,
    );
    assert_fd(&name, &res);
}

const GLASS: f32 = 1.0 / 1.5;

#[test]
fn flat_transfer() {
    single(Model::Flat, Op::Transfer, false);
    single(Model::Flat, Op::Transfer, true);
}

#[test]
fn flat_reflection() {
    single(Model::Flat, Op::Reflect, false);
    single(Model::Flat, Op::Reflect, true);
}

#[test]
fn flat_refraction() {
    single(Model::Flat, Op::Refract(GLASS), false);
    single(Model::Flat, Op::Refract(GLASS), true);
    single(Model::Flat, Op::Refract(1.33), true); // water → air, no TIR at this incidence
}

/// ∂η/∂θ of a dispersive interface: θ₄ (time in the other tests, here standing for wavelength)
/// changes η alone on a stationary triangle, θ₁ changes both the ray and η. A step of ε
/// changes η by up to 0.01, about F2 glass between 450 and 650 nm.
const DETA: [f32; N] = [0.0, 0.12, 0.0, 0.0, 0.32];

#[test]
fn flat_dispersive_refraction() {
    single(Model::Flat, Op::Dispersive(GLASS, DETA), false);
    single(
        Model::Flat,
        Op::Dispersive(1.0 / GLASS, DETA.map(|d| -d)),
        false,
    );
}

#[test]
fn phong_dispersive_refraction() {
    single(Model::Phong, Op::Dispersive(GLASS, DETA), false);
    single(Model::Phong, Op::Dispersive(GLASS, DETA), true);
}

/// Dispersive refraction with `∂η/∂θ = 0` is plain refraction, bit for bit (the renderer's
/// images do not change where nothing disperses); with ∂η/∂θ ≠ 0 the η-only column is not
/// zero (the check above would pass vacuously otherwise).
#[test]
fn dispersive_refraction_reduces_to_refraction() {
    let fam = family();
    let tri = tri_a().stationary();
    let hit = predicted_hit(Model::Phong, &tri, &fam.diff(), &tri.motion());
    let plain = hit.refract(GLASS).unwrap();
    let same = hit.refract_dispersive(GLASS, &[0.0; N]).unwrap();
    assert_eq!(plain.dv, same.dv);
    assert_eq!(plain.dp, same.dp);
    let disp = hit.refract_dispersive(GLASS, &DETA).unwrap();
    assert!(
        (disp.dv[4] - plain.dv[4]).length() > 0.01,
        "{:?}",
        disp.dv[4]
    );
    assert_eq!(disp.dv[0], plain.dv[0]);
}

#[test]
fn phong_transfer() {
    single(Model::Phong, Op::Transfer, false);
    single(Model::Phong, Op::Transfer, true);
}

#[test]
fn phong_reflection() {
    single(Model::Phong, Op::Reflect, false);
    single(Model::Phong, Op::Reflect, true);
}

#[test]
fn phong_refraction() {
    single(Model::Phong, Op::Refract(GLASS), false);
    single(Model::Phong, Op::Refract(GLASS), true);
    single(Model::Phong, Op::Refract(1.33), true);
}

/// transfer → refraction → transfer → reflection → transfer.
fn chain(models: [Model; 3], moving: bool) {
    let fam = family();
    let pick = |t: Tri| if moving { t } else { t.stationary() };
    let (a, b, c) = (pick(tri_a()), pick(tri_b()), pick(tri_c()));
    let name = format!("chain {models:?}{}", if moving { " moving" } else { "" });

    let r0 = fam.diff();
    let r1 = apply(
        Op::Refract(GLASS),
        &predicted_hit(models[0], &a, &r0, &a.motion()),
    );
    let r2 = apply(Op::Reflect, &predicted_hit(models[1], &b, &r1, &b.motion()));
    let r3 = apply(
        Op::Transfer,
        &predicted_hit(models[2], &c, &r2, &c.motion()),
    );
    for r in [&r1, &r2, &r3] {
        assert_unit_derivatives(&name, r);
    }
    let res = fd_check(
        &name,
        |th| {
            let (p, v) = fam.at(th);
            let (p, v) = exact_step(models[0], Op::Refract(GLASS), &a, th, p, v);
            let (p, v) = exact_step(models[1], Op::Reflect, &b, th, p, v);
            exact_step(models[2], Op::Transfer, &c, th, p, v)
        },
        &r3,
    );
    assert_fd(&name, &res);
}

#[test]
fn chain_flat() {
    chain([Model::Flat; 3], false);
    chain([Model::Flat; 3], true);
}

#[test]
fn chain_phong() {
    chain([Model::Phong, Model::Phong, Model::Flat], false);
    chain([Model::Phong, Model::Phong, Model::Phong], true);
}

/// The check has teeth: dropping the normal's differential on a Phong surface (i.e. treating
/// it as flat, eq. B.28c instead of B.52) or perturbing one derivative by a few per cent is
/// caught.
#[test]
fn check_detects_wrong_derivatives() {
    let fam = family();
    let tri = tri_a().stationary();
    let hit = predicted_hit(Model::Phong, &tri, &fam.diff(), &tri.motion());
    let exact = |th: &[f32; N]| {
        let (p, v) = fam.at(th);
        exact_step(Model::Phong, Op::Reflect, &tri, th, p, v)
    };

    let no_dn = reflect(&hit.ray, hit.normal, &[Vec3::ZERO; N]).unwrap();
    let res = fd_check("Phong reflect, dN dropped", exact, &no_dn);
    assert!(res.iter().any(|(_, _, vo)| !vo.ok));

    let mut off = hit.reflect().unwrap();
    off.dv[2] *= 1.03;
    let res = fd_check("Phong reflect, dv[2] × 1.03", exact, &off);
    assert!(!res[2].2.ok);

    let mut off = hit.ray;
    off.dp[3] += 0.02 * off.dp[3].length() * Vec3::X;
    let res = fd_check(
        "Phong transfer, dp[3] + 2%",
        |th| {
            let (p, v) = fam.at(th);
            exact_step(Model::Phong, Op::Transfer, &tri, th, p, v)
        },
        &off,
    );
    assert!(!res[3].1.ok);

    let wrong_eta = refract(&hit.ray, hit.normal, &hit.dnormal, 1.0 / 1.45).unwrap();
    let res = fd_check(
        "Phong refract, wrong η",
        |th| {
            let (p, v) = fam.at(th);
            exact_step(Model::Phong, Op::Refract(GLASS), &tri, th, p, v)
        },
        &RayDiff {
            v: hit.refract(GLASS).unwrap().v,
            ..wrong_eta
        },
    );
    assert!(res.iter().any(|(_, _, vo)| !vo.ok));
}

/// The appendix's matrix form of the flat transfer (eq. B.34 with K, L of eq. B.29 and J of
/// eq. B.33) agrees with the step-by-step evaluation, for both vertex orientations
/// (eq. B.30's interchange of Q₁ and Q₂).
#[test]
fn matrix_form_b34_matches() {
    let fam = family();
    let ray = fam.diff();
    for swap in [false, true] {
        let mut t = tri_a();
        if swap {
            t.q.swap(1, 2);
            t.dq.swap(1, 2);
        }
        let tri = FlatTriangle { q: t.q };
        let hit = tri.hit_moving(&ray, &t.motion()).unwrap();
        let jac = tri.transfer_jacobians(ray.p, ray.v).unwrap();
        assert!((jac.s - hit.s).abs() < 1e-5);
        let m = t.motion();
        for i in 0..N {
            let dq = jac.dq_dp * ray.dp[i]
                + jac.dq_dv * ray.dv[i]
                + jac.dq_dq[0] * m.dq[0][i]
                + jac.dq_dq[1] * m.dq[1][i]
                + jac.dq_dq[2] * m.dq[2][i];
            assert!(
                (dq - hit.ray.dp[i]).length() < 1e-4 * (1.0 + dq.length()),
                "swap {swap} θ{i}: B.34 {dq} vs step-by-step {}",
                hit.ray.dp[i]
            );
        }
    }
}

/// caustica's camera `RayDifferential` round-trips through `RayDiff<2>`, and a 2-parameter
/// differential propagates (the renderer's use).
#[test]
fn core_ray_differential_round_trip() {
    let d = Vec3::new(0.1, 0.2, 1.0).normalize();
    let core = RayDifferential {
        ray: Ray::new(Vec3::new(0.0, 0.1, 0.0), d),
        dodx: Vec3::new(1e-3, 0.0, 0.0),
        dody: Vec3::new(0.0, 1e-3, 0.0),
        dddx: Vec3::X.reject_from(d) * 1e-3,
        dddy: Vec3::Y.reject_from(d) * 1e-3,
    };
    let r = RayDiff::<2>::from(&core);
    let back = r.to_core(7.0);
    assert_eq!(back.ray.o, core.ray.o);
    assert_eq!(back.ray.d, core.ray.d);
    assert_eq!(back.ray.t_max, 7.0);
    assert_eq!(
        [back.dodx, back.dody, back.dddx, back.dddy],
        [core.dodx, core.dody, core.dddx, core.dddy]
    );
    let t = tri_a();
    let hit = PhongTriangle { q: t.q, n: t.n }.hit(&r).unwrap();
    let out = hit.refract(GLASS).unwrap();
    assert!(out.is_finite());
    assert!(out.v.dot(out.dv[0]).abs() < 1e-6 && out.v.dot(out.dv[1]).abs() < 1e-6);
}

/// The appendix's gathered Phong forms — eq. B.51 for dN, and eq. B.52 / B.55 for the
/// reflected and refracted directions (the Jacobians of eq. B.18b / B.23 times those of
/// eq. B.51) — agree with the step-by-step evaluation, with moving vertices and normals.
#[test]
fn matrix_form_b51_b52_b55_matches() {
    let fam = family();
    let ray = fam.diff();
    for t in [tri_a(), tri_b()] {
        let tri = PhongTriangle { q: t.q, n: t.n };
        let m = t.motion();
        let hit = tri.hit_moving(&ray, &m).unwrap();
        let jac = tri.normal_jacobians(ray.p, ray.v).unwrap();
        let (ra, rb) = reflection_jacobians(ray.v, hit.normal);
        let (ta, tb) = refraction_jacobians(ray.v, hit.normal, GLASS).unwrap();
        let refl = hit.reflect().unwrap();
        let refr = hit.refract(GLASS).unwrap();
        let close = |a: Vec3, b: Vec3| (a - b).length() < 2e-5 * (1.0 + b.length());
        for i in 0..N {
            let mut dn = jac.dn_dv * ray.dv[i] + jac.dn_dp * ray.dp[i];
            for k in 0..3 {
                dn += jac.dn_dnk[k] * m.dn[k][i] + jac.dn_dq[k] * m.dq[k][i];
            }
            assert!(
                close(dn, hit.dnormal[i]),
                "θ{i}: B.51 {dn} vs step-by-step {}",
                hit.dnormal[i]
            );
            let dw = ra * ray.dv[i] + rb * dn; // eq. B.52
            assert!(close(dw, refl.dv[i]), "θ{i}: B.52 {dw} vs {}", refl.dv[i]);
            let dw = ta * ray.dv[i] + tb * dn; // eq. B.55
            assert!(close(dw, refr.dv[i]), "θ{i}: B.55 {dw} vs {}", refr.dv[i]);
        }
    }
}

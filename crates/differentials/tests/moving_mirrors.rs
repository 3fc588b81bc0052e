//! Closed-form time differentials of moving mirrors (seed 003; seed 000 Q-T TT3–TT4): a mirror
//! translating along its normal and a mirror rotating about an axis in its plane, reflecting a
//! ray onto a static parallel receiver, against the geometric answers.

use caustica_core::Vec3;
use caustica_differentials::{FlatTriangle, RayDiff, TriangleMotion, transfer_to_fixed_plane};

/// A large mirror triangle in the plane y = 0 around the origin.
const MIRROR: [Vec3; 3] = [
    Vec3::new(-10.0, 0.0, -10.0),
    Vec3::new(10.0, 0.0, -10.0),
    Vec3::new(0.0, 0.0, 10.0),
];

/// A ray (one parameter: time, zero at emission) aimed at the origin at `theta` from the
/// mirror's normal, travelling toward +x.
fn incoming(theta: f32) -> RayDiff<1> {
    let v = Vec3::new(theta.sin(), -theta.cos(), 0.0);
    RayDiff::new(-v * 3.0, v, [Vec3::ZERO], [Vec3::ZERO])
}

/// The differential after reflecting off the mirror moving with `motion` and landing on the
/// static plane y = `h_receiver`.
fn land(theta: f32, motion: &TriangleMotion<1>, h_receiver: f32) -> (Vec3, Vec3) {
    let hit = FlatTriangle { q: MIRROR }
        .hit_moving(&incoming(theta), motion)
        .unwrap();
    let out = hit.reflect().unwrap();
    let t = transfer_to_fixed_plane(&out, Vec3::new(0.0, h_receiver, 0.0), Vec3::Y).unwrap();
    (t.ray.dp[0], t.ray.dv[0])
}

#[test]
fn a_mirror_translating_along_its_normal_shifts_the_reflection_by_two_tan_theta() {
    // Raised by Δh per frame over an exposure of e frames: D_t q = e Δh ŷ for every vertex
    // (seed 003 eq. 5). The reflected ray shifts by −2 tan θ e Δh along x and keeps its direction.
    let (e, dh) = (0.75f32, 0.1f32);
    let mut m = TriangleMotion::<1>::stationary();
    for k in 0..3 {
        m.dq[k][0] = Vec3::Y * (e * dh);
    }
    for theta in [0.2f32, 0.5, 0.9] {
        let (dx, dw) = land(theta, &m, 2.0);
        let expect = Vec3::new(-2.0 * theta.tan() * e * dh, 0.0, 0.0);
        assert!(
            (dx - expect).length() < 1e-5,
            "θ = {theta}: {dx} vs {expect}"
        );
        assert!(dw.length() < 1e-6, "{dw}");
    }
}

#[test]
fn a_mirror_rotating_about_an_axis_in_its_plane_turns_the_reflection_by_twice_its_angle() {
    // Rotation by δα per frame about the z axis (in the mirror, ⊥ the plane of incidence):
    // D_t q = e δα ẑ × q. The reflected direction turns by 2 e δα (|D_t ω| = 2 e δα), and on a
    // receiver at height H above the pivot the spot moves by −2 e δα H / cos² θ along x.
    let (e, da) = (1.0f32, 0.01f32);
    let mut m = TriangleMotion::<1>::stationary();
    for (dq, q) in m.dq.iter_mut().zip(MIRROR) {
        dq[0] = Vec3::Z.cross(q) * (e * da);
    }
    for theta in [0.1f32, 0.4, 0.8] {
        let h = 2.0;
        let (dx, dw) = land(theta, &m, h);
        assert!(
            (dw.length() - 2.0 * e * da).abs() < 1e-5,
            "θ = {theta}: |D_t ω| = {}",
            dw.length()
        );
        // Counter-clockwise about z turns the normal, and the reflection with it (by twice the
        // angle), counter-clockwise: toward −x.
        assert!(dw.x < 0.0 && dw.z.abs() < 1e-7, "{dw}");
        let expect = -2.0 * e * da * h / (theta.cos() * theta.cos());
        assert!(
            (dx.x - expect).abs() < 1e-4 * (1.0 + expect),
            "θ = {theta}: {dx} vs {expect}"
        );
    }
}

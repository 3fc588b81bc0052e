//! Helpers for the radiance estimate (eq. 3.2) against topological and occlusion bias.
//!
//! * [`project_to_tangent_plane`] — appendix A, eq. A.1–A.2: move a photon along its incoming
//!   direction onto the tangent plane at the estimation point, so the 2-D density estimate is
//!   done on points that really lie in a plane (reduces topological bias near corners).
//! * [`disc_test`] — accept a photon only if it lies close to the tangent plane and its surface
//!   normal agrees with the one at the estimation point (the usual "disc instead of sphere"
//!   gather; rejects photons on nearby, differently oriented or occluded surfaces).

use caustica_core::Vec3;

/// Relative threshold under which `n·ωp` counts as zero (photon direction parallel to the
/// tangent plane): `|n·ωp| <= PARALLEL_EPS · |n| |ωp|`.
pub const PARALLEL_EPS: f32 = 1e-6;

/// Projects the photon at `xp` with incoming direction `wp` along its line onto the plane
/// through the estimation point `x` with normal `n` (Schjøth 2009, appendix A):
///
/// ```text
/// t      = n·(x − x_p) / (n·ω_p)      (A.1)
/// x_proj = x_p + ω_p t                (A.2)
/// ```
///
/// Neither `n` nor `wp` needs to be normalised, and the sign of `wp` does not matter (`t`
/// changes sign with it). Returns `None` when `n·ωp ≈ 0` (the photon travels parallel to the
/// plane; see [`PARALLEL_EPS`]) or when an input is not finite.
pub fn project_to_tangent_plane(x: Vec3, n: Vec3, xp: Vec3, wp: Vec3) -> Option<Vec3> {
    let n_dot_w = n.dot(wp);
    let scale = n.length() * wp.length();
    if n_dot_w.abs().partial_cmp(&(PARALLEL_EPS * scale)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // (A.1)
    let t = n.dot(x - xp) / n_dot_w;
    // (A.2)
    let x_proj = xp + wp * t;
    x_proj.is_finite().then_some(x_proj)
}

/// Disc test of a photon at `xp` with surface normal `np` for the estimate at `x` with unit
/// normal `n`: accepts it iff its distance from the tangent plane, `|n·(xp − x)|` (m), is at
/// most `max_plane_dist` and `n·np >= min_normal_cos` (both normals unit length). Rejects
/// photons whose inputs are not finite. Typical values: `max_plane_dist` a small fraction of the
/// gather radius (e.g. 0.1 h), `min_normal_cos` ≈ 0.9 (normals within ~25°); use
/// `min_normal_cos = -1` to accept any normal.
pub fn disc_test(
    x: Vec3,
    n: Vec3,
    xp: Vec3,
    np: Vec3,
    max_plane_dist: f32,
    min_normal_cos: f32,
) -> bool {
    let plane_dist = n.dot(xp - x).abs();
    let cos = n.dot(np);
    // Written so that NaN anywhere rejects.
    plane_dist <= max_plane_dist && cos >= min_normal_cos
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn rand_vec(rng: &mut Pcg32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE
    }

    #[test]
    fn hand_computed_example() {
        // Plane z = 1 (x = (0,0,1), n = +z). Photon at (1, 2, 3) coming in along (1, 0, -2):
        // t = n·(x − xp)/(n·ωp) = (1 − 3)/(−2) = 1; x_proj = (1, 2, 3) + (1, 0, −2) = (2, 2, 1).
        let p = project_to_tangent_plane(
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::Z,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 0.0, -2.0),
        )
        .unwrap();
        assert!((p - Vec3::new(2.0, 2.0, 1.0)).length() < 1e-6, "{p}");
        // Same with the direction reversed and an unnormalised normal.
        let p = project_to_tangent_plane(
            Vec3::new(5.0, -3.0, 1.0),
            Vec3::new(0.0, 0.0, -4.0),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-0.5, 0.0, 1.0),
        )
        .unwrap();
        assert!((p - Vec3::new(2.0, 2.0, 1.0)).length() < 1e-6, "{p}");
        // Tilted plane x + y + z = 3 through (1,1,1); photon at the origin along (1,1,1):
        // t = 3/3 = 1, projection (1, 1, 1).
        let p = project_to_tangent_plane(Vec3::ONE, Vec3::ONE, Vec3::ZERO, Vec3::ONE).unwrap();
        assert!((p - Vec3::ONE).length() < 1e-6, "{p}");
        // A photon already in the plane stays where it is.
        let xp = Vec3::new(0.3, -0.2, 1.0);
        let p = project_to_tangent_plane(Vec3::Z, Vec3::Z, xp, Vec3::new(0.2, 0.1, -1.0)).unwrap();
        assert!((p - xp).length() < 1e-7);
    }

    #[test]
    fn projection_lies_in_plane_and_on_photon_line() {
        let mut rng = Pcg32::new(7, 0);
        let mut done = 0;
        for _ in 0..10_000 {
            let x = rand_vec(&mut rng) * 3.0;
            let n = rand_vec(&mut rng).normalize();
            let xp = x + rand_vec(&mut rng) * 0.5;
            let wp = rand_vec(&mut rng).normalize();
            if n.dot(wp).abs() < 0.05 {
                continue; // keep the conditioning of the check reasonable
            }
            let p = project_to_tangent_plane(x, n, xp, wp).unwrap();
            let scale = 1.0 + (p - xp).length() + x.length();
            // In the plane: n·(p − x) = 0.
            assert!(n.dot(p - x).abs() < 1e-5 * scale, "off plane");
            // On the photon's line: (p − xp) parallel to ωp.
            assert!((p - xp).cross(wp).length() < 1e-5 * scale, "off line");
            done += 1;
        }
        assert!(done > 9000);
    }

    #[test]
    fn parallel_or_invalid_is_none() {
        assert_eq!(
            project_to_tangent_plane(Vec3::ZERO, Vec3::Z, Vec3::ONE, Vec3::X),
            None
        );
        assert_eq!(
            project_to_tangent_plane(Vec3::ZERO, Vec3::Z, Vec3::ONE, Vec3::new(1.0, 0.0, 1e-9)),
            None
        );
        assert_eq!(
            project_to_tangent_plane(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, Vec3::Z),
            None
        );
        assert_eq!(
            project_to_tangent_plane(Vec3::ZERO, Vec3::Z, Vec3::NAN, Vec3::Z),
            None
        );
        assert_eq!(
            project_to_tangent_plane(Vec3::ZERO, Vec3::Z, Vec3::ONE, Vec3::NAN),
            None
        );
    }

    #[test]
    fn disc_test_accepts_and_rejects() {
        let x = Vec3::new(1.0, 1.0, 0.0);
        let n = Vec3::Z;
        // Same plane, same normal, far in-plane: accepted (distance in the plane is the gather's
        // business, not the disc test's).
        assert!(disc_test(x, n, Vec3::new(3.0, -2.0, 0.0), n, 0.01, 0.9));
        // Slightly off the plane, within tolerance, both sides.
        assert!(disc_test(x, n, Vec3::new(1.2, 1.0, 0.009), n, 0.01, 0.9));
        assert!(disc_test(x, n, Vec3::new(1.2, 1.0, -0.009), n, 0.01, 0.9));
        // Too far from the plane (e.g. the floor of a thin step, or the back side of a wall).
        assert!(!disc_test(x, n, Vec3::new(1.2, 1.0, 0.011), n, 0.01, 0.9));
        assert!(!disc_test(x, n, Vec3::new(1.0, 1.0, -0.5), n, 0.01, 0.9));
        // Normal disagrees: 45° (cos 0.707 < 0.9) and opposite side of a thin sheet.
        let n45 = Vec3::new(1.0, 0.0, 1.0).normalize();
        assert!(!disc_test(x, n, x, n45, 0.01, 0.9));
        assert!(disc_test(x, n, x, n45, 0.01, 0.7));
        assert!(!disc_test(x, n, x, -n, 0.01, 0.0));
        assert!(disc_test(x, n, x, -n, 0.01, -1.0));
        // NaN anywhere rejects.
        assert!(!disc_test(x, n, Vec3::NAN, n, 0.01, -1.0));
        assert!(!disc_test(x, n, x, Vec3::NAN, 0.01, -1.0));
    }
}

//! Camera ray differentials (Igehy 1999; seed 000 app. B.1): the primary ray of a
//! [`PerspectiveCamera`] as a [`RayDiff<2>`] with θ = (x, y), the raster coordinates in pixels.
//!
//! Camera space (see [`PerspectiveCamera`]): the image plane z = 1 point seen at raster
//! `(x, y)` is
//!
//! `u(x, y) = (tₓ (1 − 2x/W), t_y (1 − 2y/H), 1)`, so `∂u/∂x = (−2tₓ/W, 0, 0)`,
//! `∂u/∂y = (0, −2t_y/H, 0)`,
//!
//! with `(tₓ, t_y)` = [`PerspectiveCamera::screen_half_extent`]. With `L` the lens point
//! (camera space, z = 0; `L = 0` and `f = 1` for a pinhole) and `f` the focus distance, the
//! unnormalised direction is `w = f u − L` (towards the focus-plane point `f u`, which moves
//! with the raster position while the lens sample stays fixed), and the ray starts on the
//! near-clip plane z = `n`: `P = L + (n/f) w`. Hence
//!
//! * `∂P/∂x = n ∂u/∂x` (both models; zero only for `near_clip = 0`),
//! * `∂w/∂x = f ∂u/∂x`, and `∂V/∂x = (I − V Vᵀ) ∂w/∂x / |w|` for `V = w/|w|` (eq. B.5b).
//!
//! Everything is mapped to world space by the camera-to-world transform before the
//! normalisation, so the result is the derivative of the normalised world direction.

use caustica_core::{Vec2, Vec3};
use caustica_scene::camera::PerspectiveCamera;

use crate::RayDiff;

/// The primary ray of `cam` through raster position `raster` (pixels, origin top-left) with
/// lens sample `u_lens` (ignored for a pinhole), with the derivatives of its origin and unit
/// direction with respect to the raster coordinates: `dp[0] = ∂P/∂x`, `dp[1] = ∂P/∂y`
/// (m per pixel), `dv[0] = ∂V/∂x`, `dv[1] = ∂V/∂y` (per pixel). See the module docs for the
/// derivation. The ray (origin on the near-clip plane, direction) is the one
/// [`PerspectiveCamera::generate_ray`] returns.
///
/// `None` if the result is not finite (e.g. a non-finite raster position or transform).
pub fn camera_ray_diff(cam: &PerspectiveCamera, raster: Vec2, u_lens: Vec2) -> Option<RayDiff<2>> {
    let ext = cam.screen_half_extent();
    // Image-plane (z = 1) point and its raster derivatives, camera space (the camera's own
    // helpers, so this ray is the one `generate_ray` returns).
    let u = cam.raster_to_plane(raster, ext);
    let (dux, duy) = cam.plane_steps(ext);
    let du = [dux, duy];
    // Lens point (0 for a pinhole) and focus distance (1 for a pinhole).
    let (lens, f) = if cam.lens_radius > 0.0 {
        (cam.lens_point(u_lens).0, cam.focus())
    } else {
        (Vec3::ZERO, 1.0)
    };
    // Unnormalised direction towards the focus-plane point and its derivatives.
    let w = u * f - lens;
    let dw = du.map(|d| d * f);
    // Origin on the near-clip plane z = n: P = L + (n/f) w, so dP = n du.
    let near = cam.near_clip;
    let p = lens + w * (near / f);
    let dp = du.map(|d| d * near);
    let m = &cam.to_world;
    RayDiff::from_unnormalized(
        m.transform_point3(p),
        m.transform_vector3(w),
        dp.map(|d| m.transform_vector3(d)),
        dw.map(|d| m.transform_vector3(d)),
    )
    .ok()
}

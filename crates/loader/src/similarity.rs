//! Similarity transforms: the shapes caustica keeps analytic (spheres, disks) survive a transform
//! only if it scales all directions alike.

use caustica_core::{Affine3A, Mat3};

/// The uniform scale factor of `m` (orthogonal columns of equal length), or `None`.
pub(crate) fn uniform_scale(m: &Affine3A) -> Option<f32> {
    let m3 = Mat3::from(m.matrix3);
    let s2 = m3.x_axis.length_squared();
    if !(s2 > 0.0 && s2.is_finite()) {
        return None;
    }
    let g = m3.transpose() * m3 * (1.0 / s2);
    g.abs_diff_eq(Mat3::IDENTITY, 1e-4).then(|| s2.sqrt())
}

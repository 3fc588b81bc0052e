//! A shape's transform from its `matrix`, `scale`, `rotate` and `translate` fields.

use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::shape::ShapeDesc;
use caustica_core::{Affine3A, Mat3};
use std::ops::Range;

/// The shape's transform: `translate · rotate · scale · matrix` (matrix applied first).
pub(crate) fn shape_transform(
    cx: &Ctx,
    span: &Range<usize>,
    s: &ShapeDesc,
) -> Result<Affine3A, LoadError> {
    let mut t = Affine3A::IDENTITY;
    if let Some(m) = s.matrix {
        if !m.0.row(3).abs_diff_eq(glam::Vec4::W, 1e-6) {
            return Err(cx.err(
                span.clone(),
                "field 'matrix': the last row must be [0, 0, 0, 1]",
            ));
        }
        t = Affine3A::from_mat4(m.0);
    }
    if let Some(sc) = s.scale {
        t = Affine3A::from_scale(sc.0) * t;
    }
    for r in s.rotate.iter().flat_map(|l| l.0.iter()) {
        let axis = r
            .axis
            .0
            .try_normalize()
            .ok_or_else(|| cx.err(span.clone(), "field 'rotate': the axis must be non-zero"))?;
        t = Affine3A::from_axis_angle(axis, r.angle.0.to_radians()) * t;
    }
    if let Some(tr) = s.translate {
        t = Affine3A::from_translation(tr.0) * t;
    }
    if t.matrix3.determinant().abs() < 1e-12 || !t.matrix3.determinant().is_finite() {
        return Err(cx.err(span.clone(), "the shape transform is singular"));
    }
    Ok(t)
}

/// Uniform scale factor of a similarity transform, or `None` if it is not one.
pub(crate) fn similarity_scale(t: &Affine3A) -> Option<f32> {
    let m = Mat3::from(t.matrix3);
    let s = m.determinant().abs().cbrt();
    let mtm = m.transpose() * m;
    (s > 0.0 && mtm.abs_diff_eq(Mat3::IDENTITY * (s * s), 1e-4 * s * s)).then_some(s)
}

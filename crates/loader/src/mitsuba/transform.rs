//! `<transform>` elements: `translate`, `rotate`, `scale`, `matrix`, `lookat`, composed in
//! Mitsuba's order (each new element pre-multiplies: M = T_new · M_old).

use super::{Doc, Loader};
use crate::error::LoadError;
use crate::toml::look_at_transform;
use caustica_core::{Affine3A, Mat3, Mat4, Vec3};
use glam::Vec4;
use roxmltree::Node;

/// Parses the children of a `<transform>` element into one matrix.
pub(super) fn parse_transform(lo: &mut Loader, d: &Doc, node: Node) -> Result<Mat4, LoadError> {
    let mut m = Mat4::IDENTITY;
    for c in node.children().filter(|c| c.is_element()) {
        let t = match c.tag_name().name() {
            "translate" => Mat4::from_translation(vector_attrs(lo, d, c, 0.0)?),
            "scale" => {
                let s = match lo.attr(d, c, "value")? {
                    Some((v, pos)) => {
                        let n = d.numbers(&v, pos)?;
                        match n.len() {
                            1 => Vec3::splat(n[0]),
                            3 => Vec3::new(n[0], n[1], n[2]),
                            k => {
                                return Err(d.err_at(
                                    pos,
                                    format!("scale: expected 1 or 3 numbers, got {k}"),
                                ));
                            }
                        }
                    }
                    None => vector_attrs(lo, d, c, 1.0)?,
                };
                Mat4::from_scale(s)
            }
            "rotate" => {
                let axis = match lo.attr(d, c, "axis")? {
                    Some((v, pos)) => d.vec3(&v, pos)?,
                    None => vector_attrs(lo, d, c, 0.0)?,
                };
                let (angle, apos) = lo.req_attr(d, c, "angle")?;
                let angle = d.number(&angle, apos)?;
                let Some(axis) = axis.try_normalize() else {
                    return Err(d.err_at(
                        d.pos(c),
                        "rotate: the axis must be a non-zero vector (x, y, z or axis)",
                    ));
                };
                Mat4::from_axis_angle(axis, angle.to_radians())
            }
            "matrix" => {
                let (v, pos) = lo.req_attr(d, c, "value")?;
                let n = d.numbers(&v, pos)?;
                match n.len() {
                    16 => Mat4::from_cols_slice(&n).transpose(),
                    9 => Mat4::from_mat3(Mat3::from_cols_slice(&n).transpose()),
                    k => {
                        return Err(d.err_at(
                            pos,
                            format!("matrix: expected 16 numbers (row-major), got {k}"),
                        ));
                    }
                }
            }
            "lookat" => {
                let (o, opos) = lo.req_attr(d, c, "origin")?;
                let (t, tpos) = lo.req_attr(d, c, "target")?;
                let origin = d.vec3(&o, opos)?;
                let target = d.vec3(&t, tpos)?;
                let up = match lo.attr(d, c, "up")? {
                    Some((u, upos)) => d.vec3(&u, upos)?,
                    None => Vec3::Y,
                };
                let a = look_at_transform(origin, target, up).ok_or_else(|| {
                    d.err_at(
                        d.pos(c),
                        "lookat: origin and target must differ and up must not be parallel to the view direction",
                    )
                })?;
                Mat4::from(a)
            }
            other => {
                return Err(d.err_at(
                    d.pos(c),
                    format!(
                        "unknown transform element <{other}> (expected translate, rotate, scale, matrix or lookat)"
                    ),
                ));
            }
        };
        m = t * m;
    }
    if !m.is_finite() {
        return Err(d.err_at(d.pos(node), "transform is not finite"));
    }
    Ok(m)
}

/// `x`, `y`, `z` attributes (each defaulting to `default`) or `value="x y z"`.
fn vector_attrs(lo: &mut Loader, d: &Doc, c: Node, default: f32) -> Result<Vec3, LoadError> {
    if let Some((v, pos)) = lo.attr(d, c, "value")? {
        return d.vec3(&v, pos);
    }
    let mut out = [default; 3];
    for (i, k) in ["x", "y", "z"].iter().enumerate() {
        if let Some((v, pos)) = lo.attr(d, c, k)? {
            out[i] = d.number(&v, pos)?;
        }
    }
    Ok(Vec3::from(out))
}

/// The affine part of `m`; fails if the bottom row is not (0, 0, 0, 1).
pub(super) fn affine(d: &Doc, pos: usize, m: Mat4) -> Result<Affine3A, LoadError> {
    if !m.row(3).abs_diff_eq(Vec4::W, 1e-6) {
        return Err(d.err_at(
            pos,
            "projective transforms (bottom row other than 0 0 0 1) are not supported",
        ));
    }
    Ok(Affine3A::from_mat4(m))
}

/// True if the 3×3 part is a rotation or a reflection (orthonormal columns).
pub(super) fn is_rigid(m: &Affine3A) -> bool {
    let m3 = Mat3::from(m.matrix3);
    (m3.transpose() * m3).abs_diff_eq(Mat3::IDENTITY, 1e-4)
}

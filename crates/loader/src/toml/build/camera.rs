//! The camera: a look-at (Mitsuba's convention) or a rigid `to_world`.

use crate::MAX_FILM_PIXELS;
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::camera::{CameraDesc, FovAxisDesc};
use ::toml::Spanned;
use caustica_core::{Affine3A, Mat3, Vec3};
use caustica_scene::camera::{FovAxis, PerspectiveCamera};

/// Mitsuba's look-at: columns (left, up', dir, eye) with left = normalize(up × dir).
pub fn look_at_transform(eye: Vec3, target: Vec3, up: Vec3) -> Option<Affine3A> {
    let dir = (target - eye).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(Affine3A::from_cols(
        left.into(),
        new_up.into(),
        dir.into(),
        eye.into(),
    ))
}

pub(crate) fn camera(cx: &Ctx, c: &Spanned<CameraDesc>) -> Result<PerspectiveCamera, LoadError> {
    let span = c.span();
    let c = c.get_ref();
    if c.fov.0 >= 180.0 {
        return Err(cx.err(
            span,
            format!("field 'fov': must be below 180 degrees, got {}", c.fov.0),
        ));
    }
    let (width, height) = (c.width.0, c.height.0);
    if u64::from(width) * u64::from(height) > MAX_FILM_PIXELS {
        return Err(cx.err(
            span,
            format!("camera: an image of {width}x{height} pixels is too large (at most {MAX_FILM_PIXELS} pixels, e.g. 16384x16384)"),
        ));
    }
    let (to_world, default_focus) = match (c.to_world, c.eye, c.target) {
        (Some(m), None, None) if c.up.is_none() => {
            let m = m.0;
            let rows_ok = m.row(3).abs_diff_eq(glam::Vec4::W, 1e-6);
            let m3 = Mat3::from_mat4(m);
            let ortho = (m3.transpose() * m3).abs_diff_eq(Mat3::IDENTITY, 1e-4);
            if !rows_ok || !ortho {
                return Err(cx.err(
                    span,
                    "field 'to_world': the camera transform must be rigid (rotation and translation only)",
                ));
            }
            (Affine3A::from_mat4(m), 1.0)
        }
        (None, Some(eye), Some(target)) => {
            let up = c.up.map_or(Vec3::Y, |u| u.0);
            let t = look_at_transform(eye.0, target.0, up).ok_or_else(|| {
                cx.err(
                    span.clone(),
                    "camera: eye and target must differ and up must not be parallel to the view direction",
                )
            })?;
            (t, (target.0 - eye.0).length())
        }
        _ => {
            return Err(cx.err(
                span,
                "camera: give either eye and target (and optionally up), or to_world",
            ));
        }
    };
    Ok(PerspectiveCamera {
        width: c.width.0,
        height: c.height.0,
        to_world,
        fov_deg: c.fov.0,
        fov_axis: match c.fov_axis {
            None | Some(FovAxisDesc::X) => FovAxis::X,
            Some(FovAxisDesc::Y) => FovAxis::Y,
            Some(FovAxisDesc::Smaller) => FovAxis::Smaller,
            Some(FovAxisDesc::Larger) => FovAxis::Larger,
        },
        lens_radius: c.lens_radius.map_or(0.0, |x| x.0),
        focus_distance: c.focus_distance.map_or(default_focus, |x| x.0),
        near_clip: 1e-4,
    })
}

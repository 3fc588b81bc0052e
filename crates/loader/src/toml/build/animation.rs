//! Motion in scene files: `[animation]` (frame rate, shutter), mesh sequences (`frames`: one
//! OBJ or PLY file per frame, identical topology) and animated transforms
//! (`[[shape.keyframe]]`), each turned into the one representation of motion, a
//! [`MeshMotion`] with a keyframe per integer frame.

use crate::error::LoadError;
use crate::frame_pattern::FramePattern;
use crate::toml::context::Ctx;
use crate::toml::desc::animation::{AnimationDesc, FramesDesc, KeyframeDesc};
use crate::toml::desc::shape::{ShapeDesc, ShapeType};
use ::toml::Spanned;
use caustica_core::{Affine3A, Vec3};
use caustica_scene::Shutter;
use caustica_scene::shape::{MeshMotion, TriangleMesh};
use glam::Quat;
use std::ops::Range;

/// Longest animation a scene file may describe (keyframes per shape): every keyframe holds a
/// copy of the mesh's vertices.
pub(crate) const MAX_KEYFRAMES: i64 = 100_000;

/// `[animation]` → the frame rate and the shutter.
pub(crate) fn animation(cx: &Ctx, a: &Spanned<AnimationDesc>) -> Result<(f32, Shutter), LoadError> {
    let d = a.get_ref();
    let shutter = Shutter::new(d.frame.map_or(0.0, |f| f.0), d.shutter.map_or(0.0, |s| s.0))
        .map_err(|e| cx.err(a.span(), format!("[animation]: {e}")))?;
    Ok((d.fps.0, shutter))
}

/// The mesh sequence of a shape with `frames`: every file loaded (by `load`), moved by the
/// shape's transform `t`, and checked to have frame 0's topology. Errors name the file and
/// its frame.
pub(crate) fn mesh_sequence(
    cx: &Ctx,
    span: &Range<usize>,
    s: &ShapeDesc,
    frames: &FramesDesc,
    t: &Affine3A,
) -> Result<(TriangleMesh, MeshMotion), LoadError> {
    let files: Vec<(i64, String)> = match frames {
        FramesDesc::Pattern(p) => {
            let pattern = FramePattern::parse(p)
                .map_err(|e| cx.err(span.clone(), format!("field 'frames': {e}")))?;
            let Some([a, b]) = s.frame_range else {
                return Err(cx.err(
                    span.clone(),
                    "field 'frames' is a pattern: give 'frame_range = [first, last]' too",
                ));
            };
            if s.first_frame.is_some() {
                return Err(cx.err(
                    span.clone(),
                    "field 'first_frame' is for a list of frames; a pattern's first frame is \
                     frame_range's first",
                ));
            }
            if b < a || b - a >= MAX_KEYFRAMES {
                return Err(cx.err(
                    span.clone(),
                    format!(
                        "field 'frame_range': [{a}, {b}] must have first ≤ last and at most \
                         {MAX_KEYFRAMES} frames"
                    ),
                ));
            }
            (a..=b).map(|f| (f, pattern.name(f))).collect()
        }
        FramesDesc::List(l) => {
            if s.frame_range.is_some() {
                return Err(cx.err(
                    span.clone(),
                    "field 'frame_range' is for a pattern; a list's frames start at \
                     'first_frame'",
                ));
            }
            if l.is_empty() || l.len() as i64 > MAX_KEYFRAMES {
                return Err(cx.err(
                    span.clone(),
                    format!("field 'frames': give 1 to {MAX_KEYFRAMES} file names"),
                ));
            }
            let first = s.first_frame.unwrap_or(0);
            l.iter()
                .enumerate()
                .map(|(k, f)| (first + k as i64, f.clone()))
                .collect()
        }
    };
    let mut meshes = Vec::with_capacity(files.len());
    for (frame, file) in &files {
        let path = cx.input_file(file, span)?;
        let in_frame = |e: LoadError| {
            let (line, _) = super::super::position::line_column(cx.text, span.start);
            let why = match e {
                LoadError::File { message, .. } => message,
                e => e.to_string(),
            };
            LoadError::File {
                path: path.clone(),
                message: format!(
                    "frame {frame} of the mesh sequence of the shape at {}:{line}: {why}",
                    cx.path.display()
                ),
            }
        };
        let mut m = match s.ty {
            ShapeType::Obj => crate::obj::load_obj(&path),
            _ => crate::ply::load_ply(&path),
        }
        .map_err(in_frame)?;
        m.transform(t);
        meshes.push((frame, path, m));
    }
    let (first_frame, first_path, first) = &meshes[0];
    for (frame, path, m) in &meshes[1..] {
        let differs = if m.positions.len() != first.positions.len() {
            Some(format!(
                "{} vertices where frame {first_frame} has {}",
                m.positions.len(),
                first.positions.len()
            ))
        } else if m.indices != first.indices {
            Some(format!(
                "other faces than frame {first_frame} ({} triangles, {})",
                m.indices.len(),
                first.indices.len()
            ))
        } else if m.normals.is_some() != first.normals.is_some() {
            Some(format!(
                "{} vertex normals where frame {first_frame} {}",
                if m.normals.is_some() { "has" } else { "lacks" },
                if first.normals.is_some() {
                    "has them"
                } else {
                    "has none"
                }
            ))
        } else {
            None
        };
        if let Some(d) = differs {
            return Err(cx.err(
                span.clone(),
                format!(
                    "mesh sequence: frame {frame} ({}) has {d} ({}); every frame must have the \
                     same topology",
                    path.display(),
                    first_path.display()
                ),
            ));
        }
    }
    let n = first.positions.len();
    let normals = first.normals.is_some().then(|| {
        meshes
            .iter()
            .map(|(_, _, m)| m.normals.clone().unwrap_or_default())
            .collect()
    });
    let positions = meshes.iter().map(|(_, _, m)| m.positions.clone()).collect();
    let motion = MeshMotion::new(**first_frame as f32, positions, normals, n)
        .map_err(|e| cx.err(span.clone(), format!("mesh sequence: {e}")))?;
    Ok((meshes[0].2.clone(), motion))
}

/// A keyframe's transform split into its parts, interpolated part by part.
#[derive(Clone, Copy)]
struct Pose {
    translation: Vec3,
    rotation: Quat,
    scale: Vec3,
}

impl Pose {
    fn affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }

    /// Translation and scale interpolated linearly, rotation by slerp along the shorter arc
    /// (as pbrt-v4's `AnimatedTransform` and Mitsuba's animated transforms decompose them).
    fn lerp(&self, other: &Pose, u: f32) -> Pose {
        Pose {
            translation: self.translation.lerp(other.translation, u),
            rotation: self.rotation.slerp(other.rotation, u).normalize(),
            scale: self.scale.lerp(other.scale, u),
        }
    }
}

/// The motion `[[shape.keyframe]]` describes for `mesh` (already moved by the shape's own
/// transform): a keyframe per integer frame from the first to the last given, each the
/// interpolated pose of the two given keyframes around it. Keyframes must be at strictly
/// increasing frames; a rotation of more than 180° between two of them is taken the short way
/// round (add keyframes in between).
pub(crate) fn keyframed_motion(
    cx: &Ctx,
    span: &Range<usize>,
    mesh: &TriangleMesh,
    keys: &[Spanned<KeyframeDesc>],
) -> Result<MeshMotion, LoadError> {
    let mut poses: Vec<(i64, Pose)> = Vec::with_capacity(keys.len());
    for k in keys {
        let d = k.get_ref();
        if let Some((prev, _)) = poses.last()
            && d.frame <= *prev
        {
            return Err(cx.err(
                k.span(),
                format!(
                    "keyframe at frame {}: keyframes must be at increasing frames (the one \
                     before is at {prev})",
                    d.frame
                ),
            ));
        }
        let mut rotation = Quat::IDENTITY;
        for r in d.rotate.iter().flat_map(|l| l.0.iter()) {
            let axis = r.axis.0.try_normalize().ok_or_else(|| {
                cx.err(
                    k.span(),
                    "keyframe field 'rotate': the axis must be non-zero",
                )
            })?;
            rotation = Quat::from_axis_angle(axis, r.angle.0.to_radians()) * rotation;
        }
        poses.push((
            d.frame,
            Pose {
                translation: d.translate.map_or(Vec3::ZERO, |v| v.0),
                rotation,
                scale: d.scale.map_or(Vec3::ONE, |s| s.0),
            },
        ));
    }
    let (Some(&(first, _)), Some(&(last, _))) = (poses.first(), poses.last()) else {
        return Err(cx.err(span.clone(), "'keyframe' needs at least one keyframe"));
    };
    if last - first >= MAX_KEYFRAMES {
        return Err(cx.err(
            span.clone(),
            format!("keyframes span more than {MAX_KEYFRAMES} frames"),
        ));
    }
    let mut transforms = Vec::with_capacity((last - first + 1) as usize);
    let mut seg = 0;
    for f in first..=last {
        while seg + 1 < poses.len() - 1 && poses[seg + 1].0 <= f {
            seg += 1;
        }
        let pose = if poses.len() == 1 {
            poses[0].1
        } else {
            let ((fa, a), (fb, b)) = (poses[seg], poses[seg + 1]);
            a.lerp(&b, (f - fa) as f32 / (fb - fa) as f32)
        };
        transforms.push(pose.affine());
    }
    MeshMotion::from_transforms(first as f32, mesh, &transforms)
        .map_err(|e| cx.err(span.clone(), format!("keyframes: {e}")))
}

//! Shapes: meshes from files or inline arrays, spheres, disks, rectangles and cubes, with their
//! material, emission and orientation.

use super::animation::{keyframed_motion, mesh_sequence};
use super::fields::check_fields;
use super::transform::{shape_transform, similarity_scale};
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::shape::{ShapeDesc, ShapeType};
use ::toml::Spanned;
use caustica_core::{Spectrum, Vec2, Vec3};
use caustica_scene::light::{EmissionSpectrum, NamedSpectrum};
use caustica_scene::medium::MediumInterface;
use caustica_scene::shape::{Disk, MeshMotion, ShapeGeometry, Sphere, TriangleMesh};

/// A shape ready for `SceneBuilder::add_shape_with_media` (or `add_moving_mesh_with_media`):
/// geometry, material index, emission, flip, the media on its sides, and its motion.
pub(crate) struct ShapeEntry {
    pub(crate) geometry: ShapeGeometry,
    pub(crate) material: u32,
    pub(crate) emission: Option<Spectrum>,
    /// The named spectrum of the emission, if any.
    pub(crate) emission_spectrum: Option<EmissionSpectrum>,
    pub(crate) flip: bool,
    pub(crate) media: MediumInterface,
    pub(crate) motion: Option<MeshMotion>,
}

/// The index of the medium a field names.
pub(crate) fn medium_ref(
    cx: &Ctx,
    field: &str,
    name: &Spanned<String>,
    medium_names: &[String],
) -> Result<u32, LoadError> {
    medium_names
        .iter()
        .rposition(|n| n == name.get_ref())
        .map(|i| i as u32)
        .ok_or_else(|| {
            cx.err(
                name.span(),
                format!(
                    "field '{field}': no medium named '{}' (declare it in a [[medium]] table)",
                    name.get_ref()
                ),
            )
        })
}

pub(crate) fn shape(
    cx: &Ctx,
    s: &Spanned<ShapeDesc>,
    material_names: &[String],
    medium_names: &[String],
) -> Result<ShapeEntry, LoadError> {
    let span = s.span();
    let s = s.get_ref();
    let mut media = MediumInterface::default();
    if let Some(n) = &s.interior {
        media.inside = medium_ref(cx, "interior", n, medium_names)?;
    }
    if let Some(n) = &s.exterior {
        media.outside = medium_ref(cx, "exterior", n, medium_names)?;
    }
    let what = format!("a {:?} shape", s.ty).to_lowercase();
    let present = [
        ("filename", s.filename.is_some()),
        ("center", s.center.is_some()),
        ("radius", s.radius.is_some()),
        ("normal", s.normal.is_some()),
        ("positions", s.positions.is_some()),
        ("indices", s.indices.is_some()),
        ("normals", s.normals.is_some()),
        ("uvs", s.uvs.is_some()),
        ("frames", s.frames.is_some()),
        ("frame_range", s.frame_range.is_some()),
        ("first_frame", s.first_frame.is_some()),
        ("keyframe", s.keyframe.is_some()),
    ];
    let allowed: &[&str] = match s.ty {
        ShapeType::Obj | ShapeType::Ply if s.frames.is_some() => {
            &["frames", "frame_range", "first_frame"]
        }
        ShapeType::Obj | ShapeType::Ply => &["filename", "keyframe"],
        ShapeType::Sphere => &["center", "radius"],
        ShapeType::Disk => &["center", "radius", "normal"],
        ShapeType::Rectangle | ShapeType::Cube => &["keyframe"],
        ShapeType::Mesh => &["positions", "indices", "normals", "uvs", "keyframe"],
    };
    if s.frames.is_some() && s.filename.is_some() {
        return Err(cx.err(
            span,
            "a shape takes 'filename' (one mesh) or 'frames' (a mesh sequence), not both",
        ));
    }
    check_fields(cx, &span, &what, &present, allowed)?;
    let material = material_names
        .iter()
        .rposition(|n| *n == s.material)
        .ok_or_else(|| {
            cx.err(
                span.clone(),
                format!("field 'material': no material named '{}'", s.material),
            )
        })? as u32;
    let t = shape_transform(cx, &span, s)?;
    let similarity = || {
        similarity_scale(&t).ok_or_else(|| {
            cx.err(
                span.clone(),
                format!("{what} only accepts rotations, translations and uniform scales"),
            )
        })
    };
    let need_file = || {
        s.filename
            .as_deref()
            .ok_or_else(|| cx.err(span.clone(), format!("{what} needs 'filename'")))
            .and_then(|f| cx.input_file(f, &span))
    };
    let mut motion = None;
    let geometry = match s.ty {
        ShapeType::Obj | ShapeType::Ply if s.frames.is_some() => {
            let frames = s
                .frames
                .as_ref()
                .ok_or_else(|| cx.err(span.clone(), "frames"))?;
            let (m, mo) = mesh_sequence(cx, &span, s, frames, &t)?;
            motion = Some(mo);
            ShapeGeometry::Mesh(m)
        }
        ShapeType::Obj => {
            let mut m = crate::obj::load_obj(&need_file()?)?;
            m.transform(&t);
            ShapeGeometry::Mesh(m)
        }
        ShapeType::Ply => {
            let mut m = crate::ply::load_ply(&need_file()?)?;
            m.transform(&t);
            ShapeGeometry::Mesh(m)
        }
        ShapeType::Rectangle => ShapeGeometry::Mesh(TriangleMesh::rectangle(&t)),
        ShapeType::Cube => ShapeGeometry::Mesh(TriangleMesh::cube(&t)),
        ShapeType::Sphere => {
            let k = similarity()?;
            ShapeGeometry::Sphere(Sphere {
                center: t.transform_point3(s.center.map_or(Vec3::ZERO, |c| c.0)),
                radius: s.radius.map_or(1.0, |r| r.0) * k,
            })
        }
        ShapeType::Disk => {
            let k = similarity()?;
            let n = s
                .normal
                .map_or(Vec3::Z, |n| n.0)
                .try_normalize()
                .ok_or_else(|| cx.err(span.clone(), "field 'normal': must be non-zero"))?;
            ShapeGeometry::Disk(Disk {
                center: t.transform_point3(s.center.map_or(Vec3::ZERO, |c| c.0)),
                normal: t.transform_vector3(n).normalize(),
                radius: s.radius.map_or(1.0, |r| r.0) * k,
            })
        }
        ShapeType::Mesh => {
            let (Some(p), Some(i)) = (&s.positions, &s.indices) else {
                return Err(cx.err(span, "a mesh shape needs 'positions' and 'indices'"));
            };
            let n = p.len();
            if s.normals.as_ref().is_some_and(|v| v.len() != n)
                || s.uvs.as_ref().is_some_and(|v| v.len() != n)
            {
                return Err(cx.err(
                    span,
                    "mesh: 'normals' and 'uvs' need one entry per position",
                ));
            }
            let mut m = TriangleMesh {
                positions: p.iter().map(|v| v.0).collect(),
                normals: s.normals.as_ref().map(|v| v.iter().map(|x| x.0).collect()),
                uvs: s
                    .uvs
                    .as_ref()
                    .map(|v| v.iter().map(|x| Vec2::from(*x)).collect()),
                indices: i.clone(),
            };
            m.transform(&t);
            ShapeGeometry::Mesh(m)
        }
    };
    if let (Some(keys), ShapeGeometry::Mesh(m)) = (&s.keyframe, &geometry) {
        motion = Some(keyframed_motion(cx, &span, m, keys)?);
    }
    let (emission, emission_spectrum) = match (&s.emission_spectrum, s.emission) {
        (None, e) => (e.map(|e| e.0), None),
        (Some(name), e) => {
            let named = NamedSpectrum::parse(name.get_ref()).map_err(|e| {
                cx.err(
                    name.span(),
                    format!("{what}: field 'emission_spectrum': {e}"),
                )
            })?;
            let v = e.map_or(Spectrum::ONE, |e| e.0);
            if !(v.c[0] == v.c[1] && v.c[1] == v.c[2]) {
                return Err(cx.err(
                    name.span(),
                    format!(
                        "{what}: with 'emission_spectrum', 'emission' must be one number (the \
                         radiance's luminance), got {:?}",
                        v.to_rgb()
                    ),
                ));
            }
            (
                Some(named.rgb() * v.c[0]),
                Some(EmissionSpectrum::named(named)),
            )
        }
    };
    if motion.is_some() && emission.is_some() {
        return Err(cx.err(
            span,
            "a moving shape cannot emit light (give 'emission' to a static shape)",
        ));
    }
    Ok(ShapeEntry {
        geometry,
        material,
        emission,
        emission_spectrum,
        flip: s.flip_normals.unwrap_or(false),
        media,
        motion,
    })
}

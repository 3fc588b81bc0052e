//! The caustica TOML scene format (documented in `docs/scene-format.md`).
//!
//! Parsing happens in two passes: the file is deserialised with serde (values are range-checked
//! while deserialising, so errors carry the line and column of the offending value), then every
//! camera, material, shape and light is converted and validated, and only then added to a
//! [`SceneBuilder`].

use caustica_scene::camera::{FovAxis, PerspectiveCamera};
use crate::error::LoadError;
use caustica_scene::light::{BeamLight, DirectionalLight, EnvironmentLight, Light, PointLight, SpotLight};
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::scene::{FilterKind, SceneBuilder, SceneSettings};
use caustica_scene::shape::{Disk, ShapeGeometry, Sphere, TriangleMesh};
use caustica_scene::texture::{ImageTexture, Texture};
use caustica_core::{Affine3A, Mat3, Mat4, Spectrum, Vec2, Vec3};
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

// ---------------------------------------------------------------------------------------------
// Checked value types: range errors are raised while deserialising so that they carry a span.
// ---------------------------------------------------------------------------------------------

/// One number or an array of numbers (integers are accepted as floats).
struct Nums(Vec<f64>);

impl<'de> Deserialize<'de> for Nums {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Nums;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Nums, E> {
                Ok(Nums(vec![v]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Nums, E> {
                Ok(Nums(vec![v as f64]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Nums, E> {
                Ok(Nums(vec![v as f64]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Nums, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(Nums(out))
            }
        }
        d.deserialize_any(V)
    }
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Converts `Nums` to three finite values; `splat` allows a single number.
fn three<E: de::Error>(n: Nums, splat: bool, what: &str) -> Result<[f32; 3], E> {
    let v = match n.0.len() {
        3 => [n.0[0], n.0[1], n.0[2]],
        1 if splat => [n.0[0]; 3],
        k => {
            return Err(E::custom(format!(
                "expected {what} ({}3 numbers), got {k} numbers",
                if splat { "a number or " } else { "" }
            )));
        }
    };
    if !all_finite(&v) {
        return Err(E::custom(format!("{what} must be finite, got {v:?}")));
    }
    Ok(v.map(|x| x as f32))
}

/// A finite 3-vector `[x, y, z]`.
#[derive(Clone, Copy, Debug)]
struct V3(Vec3);
impl<'de> Deserialize<'de> for V3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        three(Nums::deserialize(d)?, false, "a vector [x, y, z]").map(|v| V3(Vec3::from(v)))
    }
}

/// A non-negative finite colour `[r, g, b]` or a single grey value.
#[derive(Clone, Copy, Debug)]
struct Rgb(Spectrum);
impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = three(Nums::deserialize(d)?, true, "a colour [r, g, b]")?;
        if v.iter().any(|&c| c < 0.0) {
            return Err(de::Error::custom(format!(
                "colour must be non-negative, got {v:?}"
            )));
        }
        Ok(Rgb(Spectrum::from_rgb(v)))
    }
}

macro_rules! checked_float {
    ($name:ident, $ok:expr, $msg:literal) => {
        #[derive(Clone, Copy, Debug)]
        struct $name(f32);
        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = f64::deserialize(d)?;
                let ok: fn(f64) -> bool = $ok;
                if v.is_finite() && ok(v) {
                    Ok($name(v as f32))
                } else {
                    Err(de::Error::custom(format!(concat!($msg, ", got {}"), v)))
                }
            }
        }
    };
}
checked_float!(Finite, |_| true, "must be a finite number");
checked_float!(Positive, |v| v > 0.0, "must be positive and finite");
checked_float!(NonNeg, |v| v >= 0.0, "must be non-negative and finite");

/// An integer ≥ 1.
#[derive(Clone, Copy, Debug)]
struct Count(u32);
impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = i64::deserialize(d)?;
        match u32::try_from(v) {
            Ok(n) if n >= 1 => Ok(Count(n)),
            _ => Err(de::Error::custom(format!(
                "must be an integer from 1 to {}, got {v}",
                u32::MAX
            ))),
        }
    }
}

/// A finite 4×4 matrix given as four rows.
#[derive(Clone, Copy, Debug)]
struct Matrix(Mat4);
impl<'de> Deserialize<'de> for Matrix {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let rows = <[[f64; 4]; 4]>::deserialize(d)?;
        if !rows.iter().all(|r| all_finite(r)) {
            return Err(de::Error::custom("matrix entries must be finite"));
        }
        let r = rows.map(|r| r.map(|x| x as f32));
        Ok(Matrix(Mat4::from_cols_array_2d(&r).transpose()))
    }
}

/// A texture-valued parameter: a colour, `{ texture = "file" }` or `{ checker = {...} }`.
#[derive(Clone, Debug)]
enum TexDesc {
    Constant(Spectrum),
    File(String),
    Checker(Spectrum, Spectrum, f32),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TexTable {
    texture: Option<String>,
    checker: Option<CheckerDesc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CheckerDesc {
    a: Option<Rgb>,
    b: Option<Rgb>,
    scale: Option<Positive>,
}

impl<'de> Deserialize<'de> for TexDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        fn grey<E: de::Error>(v: f64) -> Result<TexDesc, E> {
            if v.is_finite() && v >= 0.0 {
                Ok(TexDesc::Constant(Spectrum::splat(v as f32)))
            } else {
                Err(E::custom(format!(
                    "colour must be non-negative and finite, got {v}"
                )))
            }
        }
        impl<'de> Visitor<'de> for V {
            type Value = TexDesc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a colour [r, g, b], { texture = \"file\" } or { checker = { a, b, scale } }",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<TexDesc, E> {
                grey(v)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<TexDesc, E> {
                grey(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<TexDesc, E> {
                grey(v as f64)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<TexDesc, A::Error> {
                let rgb = Rgb::deserialize(de::value::SeqAccessDeserializer::new(seq))?;
                Ok(TexDesc::Constant(rgb.0))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<TexDesc, A::Error> {
                let t = TexTable::deserialize(de::value::MapAccessDeserializer::new(map))?;
                match (t.texture, t.checker) {
                    (Some(f), None) => Ok(TexDesc::File(f)),
                    (None, Some(c)) => Ok(TexDesc::Checker(
                        c.a.map_or(Spectrum::splat(0.4), |x| x.0),
                        c.b.map_or(Spectrum::splat(0.2), |x| x.0),
                        c.scale.map_or(4.0, |x| x.0),
                    )),
                    _ => Err(de::Error::custom(
                        "a texture table needs exactly one of 'texture' or 'checker'",
                    )),
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// `scale = s` or `scale = [sx, sy, sz]`.
#[derive(Clone, Copy, Debug)]
struct ScaleDesc(Vec3);
impl<'de> Deserialize<'de> for ScaleDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = three(Nums::deserialize(d)?, true, "a scale")?;
        if v.contains(&0.0) {
            return Err(de::Error::custom(format!(
                "scale must be non-zero, got {v:?}"
            )));
        }
        Ok(ScaleDesc(Vec3::from(v)))
    }
}

#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(deny_unknown_fields)]
struct RotateDesc {
    axis: V3,
    /// Degrees, counter-clockwise about `axis` (right-handed).
    angle: Finite,
}

/// `rotate = { axis, angle }` or an array of such tables (applied in order).
#[derive(Clone, Debug)]
struct RotateList(Vec<RotateDesc>);

impl<'de> Deserialize<'de> for RotateList {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RotateList;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("{ axis = [x, y, z], angle = degrees } or an array of them")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RotateList, A::Error> {
                let r = RotateDesc::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(RotateList(vec![r]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<RotateList, A::Error> {
                Vec::<RotateDesc>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(RotateList)
            }
        }
        d.deserialize_any(V)
    }
}

// ---------------------------------------------------------------------------------------------
// File structure.
// ---------------------------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    name: Option<String>,
    camera: Spanned<CameraDesc>,
    film: Option<Spanned<FilmDesc>>,
    render: Option<RenderDesc>,
    #[serde(default)]
    material: Vec<Spanned<MaterialDesc>>,
    #[serde(default)]
    shape: Vec<Spanned<ShapeDesc>>,
    #[serde(default)]
    light: Vec<Spanned<LightDesc>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum FovAxisDesc {
    X,
    Y,
    Smaller,
    Larger,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraDesc {
    eye: Option<V3>,
    target: Option<V3>,
    up: Option<V3>,
    to_world: Option<Matrix>,
    fov: Positive,
    fov_axis: Option<FovAxisDesc>,
    width: Count,
    height: Count,
    lens_radius: Option<NonNeg>,
    focus_distance: Option<Positive>,
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum FilterType {
    Box,
    Gaussian,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FilmDesc {
    filter: FilterType,
    stddev: Option<Positive>,
    radius: Option<Positive>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderDesc {
    spp: Option<Count>,
    max_depth: Option<Count>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
enum MaterialType {
    Diffuse,
    Mirror,
    Dielectric,
    Conductor,
    RoughConductor,
    RoughDielectric,
    Phong,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialDesc {
    name: String,
    #[serde(rename = "type")]
    ty: MaterialType,
    reflectance: Option<TexDesc>,
    ior: Option<Positive>,
    absorption: Option<Rgb>,
    eta: Option<Rgb>,
    k: Option<Rgb>,
    preset: Option<String>,
    specular: Option<Rgb>,
    alpha: Option<Positive>,
    diffuse: Option<TexDesc>,
    exponent: Option<NonNeg>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
enum ShapeType {
    Obj,
    Ply,
    Sphere,
    Disk,
    Rectangle,
    Cube,
    Mesh,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ShapeDesc {
    #[serde(rename = "type")]
    ty: ShapeType,
    material: String,
    emission: Option<Rgb>,
    flip_normals: Option<bool>,
    filename: Option<String>,
    center: Option<V3>,
    radius: Option<Positive>,
    normal: Option<V3>,
    positions: Option<Vec<V3>>,
    indices: Option<Vec<[u32; 3]>>,
    normals: Option<Vec<V3>>,
    uvs: Option<Vec<[f32; 2]>>,
    translate: Option<V3>,
    rotate: Option<RotateList>,
    scale: Option<ScaleDesc>,
    matrix: Option<Matrix>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
enum LightType {
    Point,
    Spot,
    Directional,
    Beam,
    Environment,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDesc {
    #[serde(rename = "type")]
    ty: LightType,
    position: Option<V3>,
    center: Option<V3>,
    direction: Option<V3>,
    target: Option<V3>,
    intensity: Option<Rgb>,
    irradiance: Option<Rgb>,
    radiance: Option<Rgb>,
    radius: Option<Positive>,
    cutoff_angle: Option<Positive>,
    beam_width: Option<Positive>,
}

// ---------------------------------------------------------------------------------------------
// Conversion.
// ---------------------------------------------------------------------------------------------

struct Ctx<'a> {
    text: &'a str,
    path: &'a Path,
    dir: PathBuf,
    textures: std::cell::RefCell<HashMap<PathBuf, Arc<ImageTexture>>>,
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

/// The key of the `key = value` assignment that `offset` lies in (on the same line), if any.
fn key_before(text: &str, offset: usize) -> Option<&str> {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let eq = line.rfind('=')?;
    let lhs = line[..eq].trim_end();
    let start = lhs
        .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
        .map_or(0, |i| i + 1);
    let key = &lhs[start..];
    (!key.is_empty()).then_some(key)
}

impl Ctx<'_> {
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> LoadError {
        let (line, column) = line_column(self.text, span.start);
        LoadError::Parse {
            path: self.path.to_path_buf(),
            line,
            column,
            message: message.into(),
        }
    }

    fn toml_err(&self, e: toml::de::Error) -> LoadError {
        let span = e.span().unwrap_or(0..0);
        let mut message = e.message().trim().to_string();
        if !message.contains("field")
            && let Some(key) = key_before(self.text, span.start)
        {
            message = format!("field '{key}': {message}");
        }
        self.err(span, message)
    }

    fn resolve(&self, file: &str) -> PathBuf {
        let p = Path::new(file);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.dir.join(p)
        }
    }

    fn texture(&self, t: &TexDesc) -> Result<Texture, LoadError> {
        Ok(match t {
            TexDesc::Constant(c) => Texture::Constant(*c),
            TexDesc::Checker(a, b, scale) => Texture::Checkerboard {
                a: *a,
                b: *b,
                scale: *scale,
            },
            TexDesc::File(f) => {
                let p = self.resolve(f);
                if let Some(t) = self.textures.borrow().get(&p) {
                    return Ok(Texture::Image(t.clone()));
                }
                let t = Arc::new(ImageTexture::load(&p).map_err(|e| LoadError::File {
                    path: p.clone(),
                    message: format!("cannot load texture: {e}"),
                })?);
                self.textures.borrow_mut().insert(p, t.clone());
                Texture::Image(t)
            }
        })
    }
}

/// Fails with a Parse error at `span` if any field in `present` is set but not in `allowed`.
fn check_fields(
    cx: &Ctx,
    span: &Range<usize>,
    what: &str,
    present: &[(&str, bool)],
    allowed: &[&str],
) -> Result<(), LoadError> {
    for (name, set) in present {
        if *set && !allowed.contains(name) {
            return Err(cx.err(
                span.clone(),
                format!("field '{name}' does not apply to {what}"),
            ));
        }
    }
    Ok(())
}

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

fn camera(cx: &Ctx, c: &Spanned<CameraDesc>) -> Result<PerspectiveCamera, LoadError> {
    let span = c.span();
    let c = c.get_ref();
    if c.fov.0 >= 180.0 {
        return Err(cx.err(
            span,
            format!("field 'fov': must be below 180 degrees, got {}", c.fov.0),
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

fn material(cx: &Ctx, m: &Spanned<MaterialDesc>) -> Result<Material, LoadError> {
    let span = m.span();
    let m = m.get_ref();
    let what = format!("material '{}' of type {:?}", m.name, m.ty).to_lowercase();
    let present = [
        ("reflectance", m.reflectance.is_some()),
        ("ior", m.ior.is_some()),
        ("absorption", m.absorption.is_some()),
        ("eta", m.eta.is_some()),
        ("k", m.k.is_some()),
        ("preset", m.preset.is_some()),
        ("specular", m.specular.is_some()),
        ("alpha", m.alpha.is_some()),
        ("diffuse", m.diffuse.is_some()),
        ("exponent", m.exponent.is_some()),
    ];
    let allowed: &[&str] = match m.ty {
        MaterialType::Diffuse => &["reflectance"],
        MaterialType::Mirror => &["reflectance"],
        MaterialType::Dielectric => &["ior", "absorption"],
        MaterialType::Conductor => &["eta", "k", "preset", "specular"],
        MaterialType::RoughConductor => &["eta", "k", "preset", "specular", "alpha"],
        MaterialType::RoughDielectric => &["ior", "absorption", "alpha"],
        MaterialType::Phong => &["diffuse", "specular", "exponent"],
    };
    check_fields(cx, &span, &what, &present, allowed)?;
    let albedo_check = |t: &Texture, field: &str| -> Result<(), LoadError> {
        if !matches!(t, Texture::Image(_)) && t.max_value() > 1.0 {
            return Err(cx.err(
                span.clone(),
                format!("{what}: field '{field}' must be at most 1 (energy conservation)"),
            ));
        }
        Ok(())
    };
    let grey = |x: f32| Spectrum::splat(x);
    let ior = m.ior.map_or(1.5, |x| x.0);
    let absorption = m.absorption.map_or(Spectrum::ZERO, |x| x.0);
    let alpha = m.alpha.map_or(0.1, |x| x.0);
    let specular = m.specular.map(|x| x.0);
    let eta_k = || -> Result<(Spectrum, Spectrum), LoadError> {
        match (&m.preset, m.eta, m.k) {
            (Some(p), None, None) => conductor_preset(p).ok_or_else(|| {
                cx.err(
                    span.clone(),
                    format!("{what}: field 'preset': unknown conductor '{p}' (expected Au, Ag, Al or Cu)"),
                )
            }),
            (None, Some(eta), Some(k)) => Ok((eta.0, k.0)),
            _ => Err(cx.err(
                span.clone(),
                format!("{what}: give either 'preset' or both 'eta' and 'k'"),
            )),
        }
    };
    let out = match m.ty {
        MaterialType::Diffuse => {
            let r = cx.texture(
                m.reflectance
                    .as_ref()
                    .unwrap_or(&TexDesc::Constant(grey(0.5))),
            )?;
            albedo_check(&r, "reflectance")?;
            Material::Diffuse { reflectance: r }
        }
        MaterialType::Mirror => {
            let r = match &m.reflectance {
                None => Spectrum::ONE,
                Some(TexDesc::Constant(c)) => *c,
                Some(_) => {
                    return Err(cx.err(
                        span,
                        format!("{what}: field 'reflectance' must be a colour"),
                    ));
                }
            };
            albedo_check(&Texture::Constant(r), "reflectance")?;
            Material::Mirror { reflectance: r }
        }
        MaterialType::Dielectric => Material::Dielectric { ior, absorption },
        MaterialType::RoughDielectric => Material::RoughDielectric {
            ior,
            alpha,
            absorption,
        },
        MaterialType::Conductor => {
            let (eta, k) = eta_k()?;
            Material::Conductor {
                eta,
                k,
                specular: specular.unwrap_or(Spectrum::ONE),
            }
        }
        MaterialType::RoughConductor => {
            let (eta, k) = eta_k()?;
            Material::RoughConductor {
                eta,
                k,
                alpha,
                specular: specular.unwrap_or(Spectrum::ONE),
            }
        }
        MaterialType::Phong => {
            let d = cx.texture(m.diffuse.as_ref().unwrap_or(&TexDesc::Constant(grey(0.5))))?;
            albedo_check(&d, "diffuse")?;
            let s = specular.unwrap_or(grey(0.2));
            albedo_check(&Texture::Constant(s), "specular")?;
            Material::Phong {
                diffuse: d,
                specular: s,
                exponent: m.exponent.map_or(30.0, |x| x.0),
            }
        }
    };
    Ok(out)
}

/// The shape's transform: `translate · rotate · scale · matrix` (matrix applied first).
fn shape_transform(cx: &Ctx, span: &Range<usize>, s: &ShapeDesc) -> Result<Affine3A, LoadError> {
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
fn similarity_scale(t: &Affine3A) -> Option<f32> {
    let m = Mat3::from(t.matrix3);
    let s = m.determinant().abs().cbrt();
    let mtm = m.transpose() * m;
    (s > 0.0 && mtm.abs_diff_eq(Mat3::IDENTITY * (s * s), 1e-4 * s * s)).then_some(s)
}

type ShapeEntry = (ShapeGeometry, u32, Option<Spectrum>, bool);

fn shape(
    cx: &Ctx,
    s: &Spanned<ShapeDesc>,
    material_names: &[String],
) -> Result<ShapeEntry, LoadError> {
    let span = s.span();
    let s = s.get_ref();
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
    ];
    let allowed: &[&str] = match s.ty {
        ShapeType::Obj | ShapeType::Ply => &["filename"],
        ShapeType::Sphere => &["center", "radius"],
        ShapeType::Disk => &["center", "radius", "normal"],
        ShapeType::Rectangle | ShapeType::Cube => &[],
        ShapeType::Mesh => &["positions", "indices", "normals", "uvs"],
    };
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
            .map(|f| cx.resolve(f))
            .ok_or_else(|| cx.err(span.clone(), format!("{what} needs 'filename'")))
    };
    let geometry = match s.ty {
        ShapeType::Obj => {
            let mut m = super::obj::load_obj(&need_file()?)?;
            m.transform(&t);
            ShapeGeometry::Mesh(m)
        }
        ShapeType::Ply => {
            let mut m = super::ply::load_ply(&need_file()?)?;
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
    Ok((
        geometry,
        material,
        s.emission.map(|e| e.0),
        s.flip_normals.unwrap_or(false),
    ))
}

fn light(cx: &Ctx, l: &Spanned<LightDesc>) -> Result<Light, LoadError> {
    let span = l.span();
    let l = l.get_ref();
    let what = format!("a {:?} light", l.ty).to_lowercase();
    let present = [
        ("position", l.position.is_some()),
        ("center", l.center.is_some()),
        ("direction", l.direction.is_some()),
        ("target", l.target.is_some()),
        ("intensity", l.intensity.is_some()),
        ("irradiance", l.irradiance.is_some()),
        ("radiance", l.radiance.is_some()),
        ("radius", l.radius.is_some()),
        ("cutoff_angle", l.cutoff_angle.is_some()),
        ("beam_width", l.beam_width.is_some()),
    ];
    let allowed: &[&str] = match l.ty {
        LightType::Point => &["position", "intensity"],
        LightType::Spot => &[
            "position",
            "direction",
            "target",
            "intensity",
            "cutoff_angle",
            "beam_width",
        ],
        LightType::Directional => &["direction", "irradiance"],
        LightType::Beam => &["center", "direction", "radius", "irradiance"],
        LightType::Environment => &["radiance"],
    };
    check_fields(cx, &span, &what, &present, allowed)?;
    let need = |v: Option<Rgb>, field: &str| {
        v.map(|x| x.0)
            .ok_or_else(|| cx.err(span.clone(), format!("{what} needs '{field}'")))
    };
    let dir = |origin: Vec3| -> Result<Vec3, LoadError> {
        let d = match (l.direction, l.target) {
            (Some(d), None) => d.0,
            (None, Some(t)) if l.ty == LightType::Spot => t.0 - origin,
            _ => {
                return Err(cx.err(
                    span.clone(),
                    format!(
                        "{what} needs 'direction'{}",
                        if l.ty == LightType::Spot {
                            " or 'target'"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        };
        d.try_normalize().ok_or_else(|| {
            cx.err(
                span.clone(),
                format!("{what}: the direction must be non-zero"),
            )
        })
    };
    Ok(match l.ty {
        LightType::Point => Light::Point(PointLight::new(
            l.position.map_or(Vec3::ZERO, |p| p.0),
            need(l.intensity, "intensity")?,
        )),
        LightType::Spot => {
            let p = l.position.map_or(Vec3::ZERO, |p| p.0);
            let cutoff = l.cutoff_angle.map_or(20.0, |x| x.0);
            let beam = l.beam_width.map_or(cutoff * 0.75, |x| x.0);
            if cutoff > 90.0 || beam > cutoff {
                return Err(cx.err(
                    span,
                    format!("{what}: need 0 < beam_width ≤ cutoff_angle ≤ 90 degrees, got beam_width {beam}, cutoff_angle {cutoff}"),
                ));
            }
            Light::Spot(SpotLight::new(
                p,
                dir(p)?,
                need(l.intensity, "intensity")?,
                cutoff,
                beam,
            ))
        }
        LightType::Directional => Light::Directional(DirectionalLight::new(
            dir(Vec3::ZERO)?,
            need(l.irradiance, "irradiance")?,
        )),
        LightType::Beam => {
            let c = l.center.map_or(Vec3::ZERO, |p| p.0);
            let r = l
                .radius
                .ok_or_else(|| cx.err(span.clone(), format!("{what} needs 'radius'")))?;
            Light::Beam(BeamLight::new(
                c,
                dir(c)?,
                r.0,
                need(l.irradiance, "irradiance")?,
            ))
        }
        LightType::Environment => {
            Light::Environment(EnvironmentLight::constant(need(l.radiance, "radiance")?))
        }
    })
}

/// Parses the TOML scene `text` (read from `path`, which names errors and anchors relative
/// file names) into a [`SceneBuilder`].
pub fn parse_toml_scene(text: &str, path: &Path) -> Result<SceneBuilder, LoadError> {
    let cx = Ctx {
        text,
        path,
        dir: path
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
        textures: Default::default(),
    };
    let file: SceneFile = toml::from_str(text).map_err(|e| cx.toml_err(e))?;

    // Pass 1: convert and validate everything.
    let camera = camera(&cx, &file.camera)?;
    let mut settings = SceneSettings::default();
    if let Some(r) = &file.render {
        settings.spp = r.spp.map(|x| x.0);
        settings.max_depth = r.max_depth.map(|x| x.0);
    }
    if let Some(f) = &file.film {
        let span = f.span();
        let f = f.get_ref();
        settings.filter = match f.filter {
            FilterType::Box => {
                check_fields(
                    &cx,
                    &span,
                    "the box filter",
                    &[
                        ("stddev", f.stddev.is_some()),
                        ("radius", f.radius.is_some()),
                    ],
                    &[],
                )?;
                FilterKind::Box
            }
            FilterType::Gaussian => FilterKind::Gaussian {
                stddev: f.stddev.map_or(0.5, |x| x.0),
                radius: f.radius.map_or(2.0, |x| x.0),
            },
        };
    }
    let mut materials = Vec::with_capacity(file.material.len());
    let mut names: Vec<String> = Vec::new();
    for m in &file.material {
        let name = &m.get_ref().name;
        if names.contains(name) {
            return Err(cx.err(
                m.span(),
                format!("a material named '{name}' already exists"),
            ));
        }
        materials.push(material(&cx, m)?);
        names.push(name.clone());
    }
    let shapes = file
        .shape
        .iter()
        .map(|s| shape(&cx, s, &names))
        .collect::<Result<Vec<_>, _>>()?;
    let lights = file
        .light
        .iter()
        .map(|l| light(&cx, l))
        .collect::<Result<Vec<_>, _>>()?;

    // Pass 2: assemble.
    let name = file.name.unwrap_or_else(|| {
        path.file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
    });
    let mut b = SceneBuilder::new(name);
    b.settings = settings;
    b.set_camera(camera);
    for (n, m) in names.iter().zip(materials) {
        b.add_material(n, m)?;
    }
    for (g, m, e, flip) in shapes {
        b.add_shape(g, m, e, flip)?;
    }
    for l in lights {
        b.add_light(l);
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SceneBuilder, LoadError> {
        parse_toml_scene(text, Path::new("/virtual/dir/test.toml"))
    }

    const CAMERA: &str = "[camera]\neye = [0, 0, 4.1]\ntarget = [0, 0, 0]\nfov = 39.3077\nwidth = 256\nheight = 256\n";

    /// Asserts a Parse error at `line` whose message contains every word of `words`.
    #[track_caller]
    fn expect_parse_error(text: &str, line: usize, words: &[&str]) {
        match parse(text) {
            Err(LoadError::Parse {
                path,
                line: l,
                message,
                ..
            }) => {
                assert_eq!(path, Path::new("/virtual/dir/test.toml"));
                assert_eq!(l, line, "wrong line for error '{message}'");
                for w in words {
                    assert!(message.contains(w), "'{message}' lacks '{w}'");
                }
            }
            Err(e) => panic!("expected a parse error at line {line}, got {e}"),
            Ok(_) => panic!("expected a parse error at line {line}, got a scene"),
        }
    }

    #[test]
    fn line_column_is_one_based() {
        assert_eq!(line_column("ab\ncd\n", 0), (1, 1));
        assert_eq!(line_column("ab\ncd\n", 4), (2, 2));
        assert_eq!(line_column("é\nx", 3), (2, 1));
    }

    #[test]
    fn syntax_error_reports_the_right_line() {
        // Missing closing bracket of a table header on line 8.
        let text = format!("{CAMERA}\n[render\nspp = 4\n");
        expect_parse_error(&text, 8, &[]);
        // Missing closing bracket of an array on line 2: arrays may span lines, so the error is
        // found at the first token that cannot continue it, on line 3.
        expect_parse_error(
            "[camera]\neye = [0, 0, 4.1\ntarget = [0, 0, 0]\n",
            3,
            &["expected"],
        );
        // A string inside a number array, on line 3.
        expect_parse_error("[camera]\nfov = 30\neye = [0, \"x\", 4]\n", 3, &["eye"]);
    }

    #[test]
    fn type_errors_name_the_field_and_line() {
        let text = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = \"wide\"\nwidth = 4\nheight = 4\n";
        expect_parse_error(text, 4, &["fov"]);
        let text = format!("{CAMERA}\n[[material]]\nname = \"m\"\ntype = \"velvet\"\n");
        expect_parse_error(&text, 10, &["velvet"]);
        let text =
            format!("{CAMERA}\n[[material]]\nname = \"m\"\ntype = \"diffuse\"\ncolour = 0.5\n");
        expect_parse_error(&text, 11, &["colour"]);
        let text = format!("{CAMERA}\n[[light]]\ntype = \"laser\"\n");
        expect_parse_error(&text, 9, &["laser"]);
    }

    #[test]
    fn invalid_values_are_rejected_with_field_names() {
        expect_parse_error(&format!("{CAMERA}[render]\nspp = 0\n"), 8, &["spp"]);
        expect_parse_error(&format!("{CAMERA}[render]\nspp = -3\n"), 8, &["spp"]);
        let m = "[[material]]\nname = \"g\"\ntype = \"dielectric\"\n";
        expect_parse_error(&format!("{CAMERA}{m}ior = 0\n"), 10, &["ior", "positive"]);
        expect_parse_error(&format!("{CAMERA}{m}ior = -1.5\n"), 10, &["ior"]);
        expect_parse_error(&format!("{CAMERA}{m}ior = nan\n"), 10, &["ior"]);
        expect_parse_error(
            &format!("{CAMERA}{m}absorption = [0, -1, 0]\n"),
            10,
            &["absorption"],
        );
        let d = "[[material]]\nname = \"d\"\ntype = \"diffuse\"\n";
        let sphere = "[[shape]]\ntype = \"sphere\"\nmaterial = \"d\"\n";
        expect_parse_error(
            &format!("{CAMERA}{d}{sphere}radius = -0.5\n"),
            13,
            &["radius", "positive"],
        );
        expect_parse_error(
            &format!("{CAMERA}{d}{sphere}center = [0, nan, 0]\n"),
            13,
            &["center", "finite"],
        );
        expect_parse_error(
            &format!("{CAMERA}{d}{sphere}radius = 1\nmaterial2 = 1\n"),
            14,
            &["material2"],
        );
        expect_parse_error(
            &format!("{CAMERA}{d}{sphere}rotate = {{ axis = [0, 1], angle = 3 }}\n"),
            13,
            &["axis", "vector"],
        );
        // Cross-field problems are reported at their table.
        expect_parse_error(&format!("{CAMERA}{d}ior = 1.5\n"), 7, &["ior", "diffuse"]);
        expect_parse_error(
            &format!("{CAMERA}{d}reflectance = 1.5\n"),
            7,
            &["reflectance"],
        );
        expect_parse_error(
            &format!("{CAMERA}{d}{sphere}radius = 1\nscale = [1, 2, 1]\n"),
            10,
            &["uniform"],
        );
        expect_parse_error(
            &format!("{CAMERA}[[shape]]\ntype = \"cube\"\nmaterial = \"nope\"\n"),
            7,
            &["nope"],
        );
        let cam =
            "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 4]\nfov = 40\nwidth = 4\nheight = 4\n";
        expect_parse_error(cam, 1, &["eye"]);
        let cam =
            "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 200\nwidth = 4\nheight = 4\n";
        expect_parse_error(cam, 1, &["fov"]);
        let cam =
            "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 0\nheight = 4\n";
        expect_parse_error(cam, 5, &["width"]);
        let spot = "[[light]]\ntype = \"spot\"\nintensity = 1\ndirection = [0, -1, 0]\n";
        expect_parse_error(
            &format!("{CAMERA}{spot}cutoff_angle = 10\nbeam_width = 20\n"),
            7,
            &["beam_width"],
        );
    }

    #[test]
    fn missing_mesh_file_names_the_resolved_path() {
        let text = format!(
            "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
             [[shape]]\ntype = \"obj\"\nmaterial = \"d\"\nfilename = \"meshes/missing.obj\"\n"
        );
        match parse(&text) {
            Err(e @ LoadError::File { .. }) => {
                assert!(
                    e.to_string().contains("/virtual/dir/meshes/missing.obj"),
                    "{e}"
                )
            }
            Err(e) => panic!("expected a file error, got {e}"),
            Ok(_) => panic!("expected a file error"),
        }
    }

    #[test]
    fn camera_follows_the_mitsuba_look_at_convention() {
        let text = "[camera]\neye = [1, 2, 3]\ntarget = [1, 2, -1]\nup = [0, 1, 0]\nfov = 30\n\
                    fov_axis = \"smaller\"\nwidth = 64\nheight = 32\nlens_radius = 0.1\n\
                    [render]\nspp = 7\nmax_depth = 5\n[film]\nfilter = \"gaussian\"\nstddev = 0.4\n";
        let b = parse(text).unwrap();
        let c = b.camera().unwrap();
        // Looking down −z: camera +x (image left) is world −x, +y is world +y, +z is world −z.
        let m = c.to_world;
        assert!(Vec3::from(m.matrix3.x_axis).abs_diff_eq(-Vec3::X, 1e-6));
        assert!(Vec3::from(m.matrix3.y_axis).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(Vec3::from(m.matrix3.z_axis).abs_diff_eq(-Vec3::Z, 1e-6));
        assert_eq!(c.position(), Vec3::new(1.0, 2.0, 3.0));
        assert_eq!((c.width, c.height, c.fov_deg), (64, 32, 30.0));
        assert_eq!(c.fov_axis, FovAxis::Smaller);
        assert_eq!(c.lens_radius, 0.1);
        assert_eq!(c.focus_distance, 4.0);
        assert_eq!(b.settings.spp, Some(7));
        assert_eq!(b.settings.max_depth, Some(5));
        assert_eq!(
            b.settings.filter,
            FilterKind::Gaussian {
                stddev: 0.4,
                radius: 2.0
            }
        );
        assert_eq!(b.name, "test");
        // A rigid to_world is taken as is; a scaled one is rejected.
        let rows = "[[0, 0, 1, 5], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]]";
        let text = format!("[camera]\nto_world = {rows}\nfov = 30\nwidth = 8\nheight = 8\n");
        let b = parse(&text).unwrap();
        let m = b.camera().unwrap().to_world;
        assert_eq!(Vec3::from(m.matrix3.z_axis), Vec3::X);
        assert_eq!(Vec3::from(m.translation), Vec3::new(5.0, 0.0, 0.0));
        let text = "[camera]\nto_world = [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n\
                    fov = 30\nwidth = 8\nheight = 8\n";
        expect_parse_error(text, 1, &["rigid"]);
    }

    #[test]
    fn lights_parse_without_materials() {
        let text = format!(
            "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 2, 3]\n\
             [[light]]\ntype = \"spot\"\nposition = [0, 2, 0]\ntarget = [0, 0, 0]\nintensity = 5\n\
             [[light]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 2\n\
             [[light]]\ntype = \"beam\"\ncenter = [0, 1, 0]\ndirection = [1, 0, 0]\nradius = 0.1\nirradiance = 3\n\
             [[light]]\ntype = \"environment\"\nradiance = 0.5\n"
        );
        let b = parse(&text).unwrap();
        let kinds: Vec<_> = b.lights().iter().map(std::mem::discriminant).collect();
        assert_eq!(kinds.len(), 5);
        assert!(matches!(b.lights()[0], Light::Point(_)));
        assert!(matches!(b.lights()[1], Light::Spot(_)));
        assert!(matches!(b.lights()[2], Light::Directional(_)));
        assert!(matches!(b.lights()[3], Light::Beam(_)));
        assert!(matches!(b.lights()[4], Light::Environment(_)));
        // Missing required parameters.
        expect_parse_error(
            &format!("{CAMERA}[[light]]\ntype = \"point\"\n"),
            7,
            &["intensity"],
        );
        expect_parse_error(
            &format!("{CAMERA}[[light]]\ntype = \"beam\"\ndirection = [1, 0, 0]\nirradiance = 1\n"),
            7,
            &["radius"],
        );
    }

    // The tests below add materials and emitting shapes, so they need `Material::validate`,
    // `conductor_preset` and `AreaLight::new`, which other helpers implement in parallel.

    fn scenes_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
    }

    #[test]
    fn feature_tour_parses_every_key() {
        let b = super::super::parse_scene_file(&scenes_dir().join("feature-tour.toml")).unwrap();
        assert_eq!(b.name, "feature-tour");
        assert_eq!(b.materials().len(), 7);
        assert_eq!(b.shape_count(), 7);
        assert_eq!(b.lights().len(), 6); // five explicit plus the emitting disk
        assert_eq!(b.settings.filter, FilterKind::Box);
        assert_eq!((b.settings.spp, b.settings.max_depth), (Some(16), Some(6)));
        let c = b.camera().unwrap();
        assert_eq!((c.width, c.height, c.fov_axis), (320, 240, FovAxis::Y));
        assert_eq!((c.lens_radius, c.focus_distance), (0.01, 5.0));
        let idx = |n: &str| b.material_index(n).unwrap() as usize;
        assert!(matches!(
            &b.materials()[idx("checker")],
            Material::Diffuse { reflectance: Texture::Checkerboard { scale, .. } } if *scale == 8.0
        ));
        let (eta, k) = conductor_preset("Au").unwrap();
        assert!(matches!(
            &b.materials()[idx("gold")],
            Material::Conductor { eta: e, k: kk, .. } if *e == eta && *kk == k
        ));
        assert!(matches!(
            &b.materials()[idx("tinted-glass")],
            Material::Dielectric { ior, absorption } if *ior == 1.5 && absorption.c == [0.0, 0.2, 0.4]
        ));
        assert!(
            matches!(&b.materials()[idx("frosted")], Material::RoughDielectric { alpha, .. } if *alpha == 0.3)
        );
        assert!(
            matches!(&b.materials()[idx("custom-metal")], Material::RoughConductor { alpha, .. } if *alpha == 0.2)
        );
        assert!(
            matches!(&b.materials()[idx("plastic")], Material::Phong { exponent, .. } if *exponent == 50.0)
        );
        assert!(
            matches!(&b.materials()[idx("chrome")], Material::Mirror { reflectance } if reflectance.c == [0.9; 3])
        );
        let shapes = b.shapes();
        // OBJ tetrahedron translated by (−1, 0.5, 0): edge length 2√2, centroid at the offset.
        let ShapeGeometry::Mesh(tet) = &shapes[0].geometry else {
            panic!()
        };
        assert_eq!(tet.indices.len(), 4);
        let centroid = tet.positions.iter().sum::<Vec3>() / 4.0;
        assert!(centroid.abs_diff_eq(Vec3::new(-1.0, 0.5, 0.0), 1e-6));
        // PLY quad scaled by 4 and rotated into the y = 0 plane facing +y.
        let ShapeGeometry::Mesh(quad) = &shapes[1].geometry else {
            panic!()
        };
        let area = quad.triangle_area(0) + quad.triangle_area(1);
        assert!((area - 16.0).abs() < 1e-4);
        let [p0, p1, p2] = quad.indices[0].map(|i| quad.positions[i as usize]);
        assert!(
            (p1 - p0)
                .cross(p2 - p0)
                .normalize()
                .abs_diff_eq(Vec3::Y, 1e-6)
        );
        assert!(quad.uvs.is_some());
        let ShapeGeometry::Mesh(tri) = &shapes[2].geometry else {
            panic!()
        };
        assert_eq!(tri.positions[1], Vec3::new(2.0, 0.0, 1.0));
        assert!(tri.normals.is_some() && tri.uvs.is_some());
        let ShapeGeometry::Sphere(s) = &shapes[3].geometry else {
            panic!()
        };
        assert_eq!((s.center, s.radius), (Vec3::new(0.0, 0.5, 0.0), 0.5));
        let ShapeGeometry::Disk(d) = &shapes[4].geometry else {
            panic!()
        };
        assert_eq!(
            (d.center, d.normal, d.radius),
            (Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.3)
        );
        assert_ne!(shapes[4].light, caustica_scene::intersection::NONE);
        let ShapeGeometry::Mesh(cube) = &shapes[5].geometry else {
            panic!()
        };
        let area: f32 = (0..12).map(|i| cube.triangle_area(i)).sum();
        assert!((area - 6.0 * 0.25).abs() < 1e-4); // six faces of side 0.5
    }

    #[test]
    fn nan_vertex_in_obj_is_skipped_and_counted_in_warnings() {
        let dir = std::env::temp_dir().join(format!("caustica-toml-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("nan.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 NaN 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\n",
        )
        .unwrap();
        let text = format!(
            "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
             [[shape]]\ntype = \"obj\"\nmaterial = \"d\"\nfilename = \"nan.obj\"\n"
        );
        let b = parse_toml_scene(&text, &dir.join("scene.toml")).unwrap();
        assert_eq!(b.shape_count(), 1);
        assert_eq!(b.shapes()[0].primitive_count(), 1);
        assert_eq!(b.skipped_triangles(), 2);
        assert!(
            b.pending_warnings()
                .iter()
                .any(|w| w.contains("skipped 2 triangles"))
        );
    }

    #[test]
    fn shapes_transforms_and_flip() {
        let text = format!(
            "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\nreflectance = {{ texture = \"missing.png\" }}\n"
        );
        assert!(
            matches!(parse(&text), Err(LoadError::File { path, .. }) if path.ends_with("dir/missing.png"))
        );
        let text = format!(
            "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
             [[shape]]\ntype = \"sphere\"\nmaterial = \"d\"\nradius = 0.5\ncenter = [1, 0, 0]\n\
             scale = 2\nrotate = {{ axis = [0, 0, 1], angle = 90 }}\ntranslate = [0, 0, 3]\n\
             [[shape]]\ntype = \"rectangle\"\nmaterial = \"d\"\nflip_normals = true\n"
        );
        let b = parse(&text).unwrap();
        let ShapeGeometry::Sphere(s) = &b.shapes()[0].geometry else {
            panic!()
        };
        // Scale first (centre → (2,0,0), radius 1), then rotate 90° about z → (0,2,0), then move.
        assert!(s.center.abs_diff_eq(Vec3::new(0.0, 2.0, 3.0), 1e-6));
        assert!((s.radius - 1.0).abs() < 1e-6);
        let ShapeGeometry::Mesh(r) = &b.shapes()[1].geometry else {
            panic!()
        };
        let [p0, p1, p2] = r.indices[0].map(|i| r.positions[i as usize]);
        assert!(
            (p1 - p0)
                .cross(p2 - p0)
                .normalize()
                .abs_diff_eq(-Vec3::Z, 1e-6)
        );
    }
}

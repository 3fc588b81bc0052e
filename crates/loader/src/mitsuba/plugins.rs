//! Conversion of Mitsuba plugins (BSDFs, shapes, emitters, sensor, integrator) to caustica's.

use super::transform::{affine, is_rigid};
use super::{Doc, Loader, MAX_NESTING, Props};
use crate::MAX_FILM_PIXELS;
use crate::error::LoadError;
use crate::media::{open_boundary_reason, open_boundary_warning};
use crate::similarity::uniform_scale;
use crate::{load_obj, load_ply};
use caustica_core::{Affine3A, Spectrum, Vec2, Vec3, Vec3A};
use caustica_scene::camera::{FovAxis, PerspectiveCamera};
use caustica_scene::light::{
    BeamLight, DirectionalLight, EmissionSpectrum, EnvironmentLight, Light, PointLight, SpotLight,
};
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::medium::MediumInterface;
use caustica_scene::scene::FilterKind;
use caustica_scene::shape::{Disk, ShapeGeometry, Sphere, TriangleMesh};
use caustica_scene::texture::{ImageTexture, Texture};
use roxmltree::Node;
use std::sync::Arc;

/// Segments around the axis of a tessellated `cylinder`.
pub const CYLINDER_SEGMENTS: u32 = 64;

/// Mitsuba's named indices of refraction (`int_ior` / `ext_ior`).
pub fn named_ior(name: &str) -> Option<f32> {
    Some(match name {
        "vacuum" => 1.0,
        "helium" => 1.000_036,
        "hydrogen" => 1.000_132,
        "air" => 1.000_277,
        "carbon dioxide" => 1.000_45,
        "water" => 1.333,
        "acetone" => 1.36,
        "ethanol" => 1.361,
        "carbon tetrachloride" => 1.461,
        "glycerol" => 1.4729,
        "benzene" => 1.501,
        "silicone oil" => 1.520_45,
        "bromine" => 1.661,
        "water ice" => 1.31,
        "fused quartz" => 1.458,
        "pyrex" => 1.47,
        "acrylic glass" | "acrylic" => 1.49,
        "polypropylene" => 1.49,
        "bk7" => 1.5046,
        "glass" => 1.5,
        "sodium chloride" => 1.544,
        "amber" => 1.55,
        "pet" => 1.575,
        "polycarbonate" => 1.58,
        "diamond" => 2.419,
        _ => return None,
    })
}

fn ty(lo: &Loader, d: &Doc, n: Node) -> Result<(String, usize), LoadError> {
    lo.req_attr(d, n, "type")
}

/// An IOR parameter given as a number or a name.
fn ior_param(
    lo: &Loader,
    d: &Doc,
    p: &mut Props,
    name: &str,
    default: f32,
) -> Result<f32, LoadError> {
    let _ = lo;
    let Some(prop) = p.take(name) else {
        return Ok(default);
    };
    let v = match prop.val {
        super::Val::Float(x) => x,
        super::Val::Int(i) => i as f32,
        super::Val::Str(s) => named_ior(s.trim().to_ascii_lowercase().as_str()).ok_or_else(|| {
            d.err_at(
                prop.pos,
                format!("unknown {name} '{s}' (give a number or a name such as vacuum, air, water, bk7, glass, acrylic, polycarbonate, diamond)"),
            )
        })?,
        _ => return Err(d.err_at(prop.pos, format!("parameter '{name}' must be a float or a string"))),
    };
    if v <= 0.0 {
        return Err(d.err_at(prop.pos, format!("{name} must be positive, got {v}")));
    }
    Ok(v)
}

/// Roughness: `alpha`, or `alpha_u`/`alpha_v` (anisotropy approximated by √(αu·αv)); and
/// `distribution` (Beckmann, Mitsuba's default, is approximated by GGX with the same α).
fn roughness(lo: &mut Loader, d: &Doc, p: &mut Props) -> Result<f32, LoadError> {
    let n = p.node;
    match p.string(d, "distribution")? {
        Some((s, _)) if s == "ggx" => {}
        Some((s, pos)) if s != "beckmann" => {
            return Err(d.err_at(
                pos,
                format!("unknown distribution '{s}' (expected beckmann or ggx)"),
            ));
        }
        _ => lo.approximated(
            d,
            n,
            "Beckmann microfacet distribution rendered as GGX with the same alpha",
        ),
    }
    let alpha = match (
        p.float(d, "alpha")?,
        p.float(d, "alpha_u")?,
        p.float(d, "alpha_v")?,
    ) {
        (Some(a), None, None) => a,
        (None, Some(u), Some(v)) if u > 0.0 && v > 0.0 => {
            if u != v {
                lo.approximated(
                    d,
                    n,
                    "anisotropic roughness replaced by sqrt(alpha_u*alpha_v)",
                );
            }
            (u * v).sqrt()
        }
        (None, None, None) => 0.1,
        _ => {
            return Err(d.err_at(d.pos(n), "give either alpha or both alpha_u and alpha_v"));
        }
    };
    if alpha <= 0.0 {
        return Err(d.err_at(d.pos(n), format!("alpha must be positive, got {alpha}")));
    }
    Ok(alpha)
}

fn conductor_eta_k(
    lo: &mut Loader,
    d: &Doc,
    p: &mut Props,
) -> Result<Option<(Spectrum, Spectrum)>, LoadError> {
    let material = p.string(d, "material")?;
    let eta = p.spectrum(d, "eta")?;
    let k = p.spectrum(d, "k")?;
    let _ = lo;
    match (material, eta, k) {
        (Some((m, _)), None, None) if m == "none" => Ok(None),
        (Some((m, pos)), None, None) => conductor_preset(&m).map(Some).ok_or_else(|| {
            d.err_at(
                pos,
                format!("unknown conductor material '{m}' (supported: Au, Ag, Al, Cu, none; or give eta and k)"),
            )
        }),
        (None, Some(eta), Some(k)) => Ok(Some((eta, k))),
        // Mitsuba's default material is "none": a perfect mirror.
        (None, None, None) => Ok(None),
        _ => Err(d.err_at(
            d.pos(p.node),
            "conductor: give either 'material' or both 'eta' and 'k'",
        )),
    }
}

/// A `<texture type="bitmap">`: `filename` (PNG decoded from sRGB, EXR/PFM linear).
pub(super) fn bitmap(lo: &mut Loader, d: &Doc, n: Node) -> Result<Texture, LoadError> {
    let (t, tpos) = ty(lo, d, n)?;
    if t != "bitmap" {
        return Err(d.err_at(
            tpos,
            format!("unsupported texture type '{t}' (only bitmap)"),
        ));
    }
    let mut p = lo.props(d, n)?;
    let (file, fpos) = p
        .string(d, "filename")?
        .ok_or_else(|| d.err_at(d.pos(n), "bitmap needs a 'filename' string"))?;
    let path = d.input_file(&file, fpos)?;
    let img = ImageTexture::load(&path).map_err(|e| LoadError::File {
        path: path.clone(),
        message: format!("cannot load texture: {e}"),
    })?;
    if p.bool(d, "raw")? == Some(true) {
        lo.approximated(
            d,
            n,
            "bitmap raw=true ignored (8-bit images are decoded from sRGB)",
        );
    }
    let _ = p.string(d, "filter_type")?;
    if let Some((w, _)) = p.string(d, "wrap_mode")?
        && w != "repeat"
    {
        lo.approximated(d, n, format!("bitmap wrap_mode '{w}' replaced by repeat"));
    }
    for c in std::mem::take(&mut p.children) {
        lo.unsupported(d, c, format!("<{}> inside {}", c.tag_name().name(), p.desc));
    }
    lo.leftovers(d, p);
    Ok(Texture::Image(Arc::new(img)))
}

/// A texture-or-colour parameter: a nested `<texture name=…>`, a `<ref name=… id=…>` to a
/// declared texture, or a colour value.
fn texture_param(
    lo: &mut Loader,
    d: &Doc,
    p: &mut Props,
    name: &str,
) -> Result<Option<Texture>, LoadError> {
    let found = p.children.iter().position(|c| {
        matches!(c.tag_name().name(), "texture" | "ref") && c.attribute("name") == Some(name)
    });
    let Some(i) = found else {
        return Ok(p.spectrum(d, name)?.map(Texture::Constant));
    };
    let c = p.children.remove(i);
    if c.tag_name().name() == "texture" {
        return bitmap(lo, d, c).map(Some);
    }
    let (id, pos) = lo.req_attr(d, c, "id")?;
    lo.textures
        .get(&id)
        .cloned()
        .map(Some)
        .ok_or_else(|| d.err_at(pos, format!("'{id}' is not a declared bitmap texture")))
}

/// Converts a `<bsdf>` element (nesting depth `depth`).
pub(super) fn bsdf(lo: &mut Loader, d: &Doc, n: Node, depth: usize) -> Result<Material, LoadError> {
    if depth > MAX_NESTING {
        return Err(d.err_at(d.pos(n), format!("BSDFs nested deeper than {MAX_NESTING}")));
    }
    let (t, tpos) = ty(lo, d, n)?;
    let mut p = lo.props(d, n)?;
    let grey = Spectrum::splat;
    let m = match t.as_str() {
        "diffuse" => {
            let r = texture_param(lo, d, &mut p, "reflectance")?;
            Material::Diffuse {
                reflectance: r.unwrap_or(Texture::Constant(grey(0.5))),
            }
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let int = ior_param(lo, d, &mut p, "int_ior", 1.5046)?;
            let ext = ior_param(lo, d, &mut p, "ext_ior", 1.000_277)?;
            let ior = int / ext;
            for k in ["specular_reflectance", "specular_transmittance"] {
                if let Some(s) = p.spectrum(d, k)?
                    && s != Spectrum::ONE
                {
                    lo.approximated(d, n, format!("{t} {k} other than 1 ignored"));
                }
            }
            match t.as_str() {
                "dielectric" => Material::Dielectric {
                    ior,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                "roughdielectric" => Material::RoughDielectric {
                    ior,
                    alpha: roughness(lo, d, &mut p)?,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                _ => {
                    lo.approximated(
                        d,
                        n,
                        "thindielectric rendered as an index-matched (ior 1) dielectric: transmission is undeviated but its reflection is dropped",
                    );
                    Material::Dielectric {
                        ior: 1.0,
                        absorption: Spectrum::ZERO,
                        dispersion: None,
                    }
                }
            }
        }
        "conductor" | "roughconductor" => {
            let ek = conductor_eta_k(lo, d, &mut p)?;
            let specular = p
                .spectrum(d, "specular_reflectance")?
                .unwrap_or(Spectrum::ONE);
            let rough = t == "roughconductor";
            let alpha = if rough {
                Some(roughness(lo, d, &mut p)?)
            } else {
                None
            };
            match (ek, alpha) {
                (None, None) => Material::Mirror {
                    reflectance: specular,
                },
                (None, Some(alpha)) => {
                    // A rough perfect mirror: a conductor with a very high extinction.
                    lo.approximated(
                        d,
                        n,
                        "roughconductor material 'none' rendered with eta 0, k 1e4",
                    );
                    Material::RoughConductor {
                        eta: grey(0.0),
                        k: grey(1e4),
                        alpha,
                        specular,
                    }
                }
                (Some((eta, k)), None) => Material::Conductor { eta, k, specular },
                (Some((eta, k)), Some(alpha)) => Material::RoughConductor {
                    eta,
                    k,
                    alpha,
                    specular,
                },
            }
        }
        "plastic" | "roughplastic" => {
            let int = ior_param(lo, d, &mut p, "int_ior", 1.49)?;
            let ext = ior_param(lo, d, &mut p, "ext_ior", 1.000_277)?;
            let kd = p.spectrum(d, "diffuse_reflectance")?.unwrap_or(grey(0.5));
            let ks = p
                .spectrum(d, "specular_reflectance")?
                .unwrap_or(Spectrum::ONE);
            let _ = p.bool(d, "nonlinear")?;
            let exponent = if t == "roughplastic" {
                let a = roughness(lo, d, &mut p)?;
                (2.0 / (a * a) - 2.0).max(1.0)
            } else {
                1000.0
            };
            let eta = int / ext;
            let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let specular = ks * f0;
            let diffuse = kd * (1.0 - f0);
            lo.approximated(
                d,
                n,
                format!("{t} rendered as Phong: specular = F0 {f0:.4} x specular_reflectance, exponent {exponent:.0}, diffuse = diffuse_reflectance x (1 - F0)"),
            );
            Material::Phong {
                diffuse: Texture::Constant(diffuse),
                specular,
                exponent,
            }
        }
        "null" => Material::Null,
        "twosided" | "bumpmap" | "normalmap" | "mask" => {
            if t != "twosided" {
                lo.approximated(d, n, format!("{t} ignored (its nested BSDF is used)"));
            }
            let inner: Vec<Node> = p
                .children
                .iter()
                .copied()
                .filter(|c| matches!(c.tag_name().name(), "bsdf" | "ref"))
                .collect();
            let Some(&first) = inner.first() else {
                return Err(d.err_at(d.pos(n), format!("{t} needs a nested <bsdf> or <ref>")));
            };
            if inner.len() > 1 {
                lo.approximated(
                    d,
                    n,
                    "twosided with two different BSDFs: the front one is used on both sides",
                );
            }
            for c in p
                .children
                .iter()
                .filter(|c| !matches!(c.tag_name().name(), "bsdf" | "ref"))
            {
                lo.unsupported(
                    d,
                    *c,
                    format!("<{}> inside {}", c.tag_name().name(), p.desc),
                );
            }
            let m = if first.tag_name().name() == "ref" {
                bsdf_ref(lo, d, first)?.0
            } else {
                bsdf(lo, d, first, depth + 1)?
            };
            // Parameters such as bumpmap's textures and mask's opacity are dropped silently
            // (reported in the approximation above).
            p.map.clear();
            p.children.clear();
            m
        }
        other => {
            return Err(d.err_at(
                tpos,
                format!("unknown bsdf type '{other}' (supported: diffuse, dielectric, thindielectric, roughdielectric, conductor, roughconductor, plastic, roughplastic, twosided, null)"),
            ));
        }
    };
    for c in std::mem::take(&mut p.children) {
        lo.unsupported(d, c, format!("<{}> inside {}", c.tag_name().name(), p.desc));
    }
    lo.leftovers(d, p);
    m.validate().map_err(|e| d.err_at(d.pos(n), e))?;
    Ok(m)
}

/// Resolves `<ref id=…/>` to a declared BSDF.
fn bsdf_ref(lo: &Loader, d: &Doc, r: Node) -> Result<(Material, u32), LoadError> {
    let (id, pos) = lo.req_attr(d, r, "id")?;
    match lo.bsdfs.get(&id) {
        Some(x) => Ok(x.clone()),
        None if lo.ids.contains(&id) => Err(d.err_at(pos, format!("'{id}' is not a bsdf"))),
        None => Err(d.err_at(pos, format!("reference to undeclared id '{id}'"))),
    }
}

fn to_world(d: &Doc, p: &mut Props) -> Result<Affine3A, LoadError> {
    match p.transform(d, "to_world")? {
        Some((m, pos)) => affine(d, pos, m),
        None => Ok(Affine3A::IDENTITY),
    }
}

/// Mitsuba's `cylinder`: the open tube of radius 1 around the z axis from z = 0 to z = 1
/// (before `p0`, `p1`, `radius` and `to_world`), tessellated into [`CYLINDER_SEGMENTS`] quads
/// with smooth vertex normals.
pub fn cylinder_mesh(to_world: &Affine3A) -> TriangleMesh {
    let n = CYLINDER_SEGMENTS;
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..=n {
        let phi = std::f32::consts::TAU * (i % n) as f32 / n as f32;
        let (s, c) = phi.sin_cos();
        for z in [0.0, 1.0] {
            m.positions.push(Vec3::new(c, s, z));
            normals.push(Vec3::new(c, s, 0.0));
            uvs.push(Vec2::new(i as f32 / n as f32, z));
        }
    }
    for i in 0..n {
        let (a, b, c, e) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
        m.indices.push([a, c, e]);
        m.indices.push([a, e, b]);
    }
    m.normals = Some(normals);
    m.uvs = Some(uvs);
    m.transform(to_world);
    m
}

pub(super) fn shape(lo: &mut Loader, d: &Doc, n: Node) -> Result<(), LoadError> {
    let (t, tpos) = ty(lo, d, n)?;
    let mut p = lo.props(d, n)?;
    let m = to_world(d, &mut p)?;
    let flip = p.bool(d, "flip_normals")?.unwrap_or(false);
    let geometry = match t.as_str() {
        "obj" | "ply" => {
            let (file, fpos) = p.string(d, "filename")?.ok_or_else(|| {
                d.err_at(d.pos(n), format!("shape '{t}' needs a 'filename' string"))
            })?;
            let path = d.input_file(&file, fpos)?;
            let mut mesh = if t == "obj" {
                load_obj(&path)?
            } else {
                load_ply(&path)?
            };
            mesh.transform(&m);
            if p.bool(d, "face_normals")?.unwrap_or(false) {
                mesh.normals = None;
            }
            // Texture-coordinate conventions do not matter without textures.
            let _ = p.bool(d, "flip_tex_coords")?;
            ShapeGeometry::Mesh(mesh)
        }
        "rectangle" => ShapeGeometry::Mesh(TriangleMesh::rectangle(&m)),
        "cube" => ShapeGeometry::Mesh(TriangleMesh::cube(&m)),
        "sphere" => {
            let c = p.vector(d, "center")?.unwrap_or(Vec3::ZERO);
            let r = p.float(d, "radius")?.unwrap_or(1.0);
            let s = uniform_scale(&m).ok_or_else(|| {
                d.err_at(
                    d.pos(n),
                    "sphere: to_world must be a uniform scale with rotation and translation",
                )
            })?;
            ShapeGeometry::Sphere(Sphere {
                center: m.transform_point3(c),
                radius: r * s,
            })
        }
        "disk" => {
            let ex = Vec3::from(m.matrix3.x_axis);
            let ey = Vec3::from(m.matrix3.y_axis);
            let (lx, ly) = (ex.length(), ey.length());
            if !(lx > 0.0 && (lx - ly).abs() <= 1e-4 * lx && ex.dot(ey).abs() <= 1e-4 * lx * ly) {
                return Err(d.err_at(
                    d.pos(n),
                    "disk: to_world must scale the disk uniformly in its plane (ellipses are not supported)",
                ));
            }
            let nm = m.matrix3.inverse().transpose();
            let normal = Vec3::from(nm * Vec3A::Z).normalize_or_zero();
            ShapeGeometry::Disk(Disk {
                center: m.transform_point3(Vec3::ZERO),
                normal,
                radius: lx,
            })
        }
        "cylinder" => {
            let p0 = p.vector(d, "p0")?.unwrap_or(Vec3::ZERO);
            let p1 = p.vector(d, "p1")?.unwrap_or(Vec3::Z);
            let r = p.float(d, "radius")?.unwrap_or(1.0);
            let axis = p1 - p0;
            let len = axis.length();
            if !(len > 0.0 && r > 0.0) {
                return Err(d.err_at(
                    d.pos(n),
                    "cylinder: p0 and p1 must differ and radius must be positive",
                ));
            }
            let rot = glam::Quat::from_rotation_arc(Vec3::Z, axis / len);
            let local = Affine3A::from_scale_rotation_translation(Vec3::new(r, r, len), rot, p0);
            lo.approximated(
                d,
                n,
                format!("cylinder tessellated into {CYLINDER_SEGMENTS} segments"),
            );
            ShapeGeometry::Mesh(cylinder_mesh(&(m * local)))
        }
        other => {
            return Err(d.err_at(
                tpos,
                format!("unknown shape type '{other}' (supported: obj, ply, rectangle, disk, sphere, cube, cylinder)"),
            ));
        }
    };
    // Nested BSDF / emitter.
    let mut material = None;
    let mut emission = None;
    // `<spectrum value="x">` radiance: a flat spectrum in spectral mode (Mitsuba's
    // scalar_spectral convention), as for the point-like emitters.
    let mut flat_emission = false;
    let mut beam = None;
    let mut media = MediumInterface::default();
    for c in std::mem::take(&mut p.children) {
        let side = c.attribute("name");
        match c.tag_name().name() {
            "medium" | "ref" if matches!(side, Some("interior" | "exterior")) => {
                let m = super::media::medium_child(lo, d, c)?;
                if side == Some("interior") {
                    media.inside = m;
                } else {
                    media.outside = m;
                }
            }
            "medium" => {
                return Err(d.err_at(
                    d.pos(c),
                    format!(
                        "a <medium> inside a shape needs name=\"interior\" or name=\"exterior\", got {}",
                        side.map_or_else(|| "none".to_string(), |s| format!("'{s}'"))
                    ),
                ));
            }
            "bsdf" | "ref" if material.is_none() => {
                if c.tag_name().name() == "ref" {
                    material = Some(bsdf_ref(lo, d, c)?.1);
                } else {
                    let mat = bsdf(lo, d, c, 1)?;
                    let id = lo.declare_id(d, c)?;
                    let name = id.clone().unwrap_or_else(|| lo.anonymous_name("bsdf"));
                    let idx = lo.add_material(d, c, &name, mat.clone())?;
                    if let Some(id) = id {
                        lo.bsdfs.insert(id, (mat, idx));
                    }
                    material = Some(idx);
                }
            }
            "emitter" => {
                let (et, epos) = ty(lo, d, c)?;
                if et != "area" && et != "directionalarea" {
                    return Err(d.err_at(
                        epos,
                        format!(
                            "emitter '{et}' cannot be attached to a shape (only 'area' or 'directionalarea')"
                        ),
                    ));
                }
                let mut ep = lo.props(d, c)?;
                flat_emission = ep.is_flat_spectrum("radiance");
                let radiance = ep.spectrum(d, "radiance")?.unwrap_or(Spectrum::ONE);
                for cc in std::mem::take(&mut ep.children) {
                    lo.unsupported(
                        d,
                        cc,
                        format!("<{}> inside {}", cc.tag_name().name(), ep.desc),
                    );
                }
                lo.leftovers(d, ep);
                if et == "area" {
                    emission = Some(radiance);
                } else {
                    beam = Some(DirectionalArea {
                        radiance,
                        type_pos: epos,
                        node: c,
                    });
                }
            }
            other => lo.unsupported(d, c, format!("<{other}> inside {}", p.desc)),
        }
    }
    if let Some(e) = beam {
        let shape = ShapeParts {
            ty: &t,
            geometry,
            flip,
            media,
            has_bsdf: material.is_some(),
        };
        return directional_area(lo, d, p, shape, e);
    }
    // Mitsuba gives a shape without a BSDF a diffuse one of reflectance 0.5, except when the
    // shape is an area emitter: then the default BSDF is black (the light does not reflect).
    let material = match material {
        Some(m) => m,
        None => {
            let (slot, name, albedo) = if emission.is_some() {
                (
                    &mut lo.default_emitter_material,
                    "default-emitter-black",
                    0.0,
                )
            } else {
                (&mut lo.default_material, "default-diffuse", 0.5)
            };
            match *slot {
                Some(m) => m,
                None => {
                    let idx = lo.b.add_material(
                        name,
                        Material::Diffuse {
                            reflectance: Texture::Constant(Spectrum::splat(albedo)),
                        },
                    )?;
                    *slot = Some(idx);
                    idx
                }
            }
        }
    };
    let desc = p.desc.clone();
    lo.leftovers(d, p);
    if media.is_transition()
        && let Some(reason) = open_boundary_reason(&geometry)
    {
        let shape = match n.attribute("id") {
            Some(id) => format!("shape '{id}' {desc} ({})", d.loc(n)),
            None => format!("shape {desc} ({})", d.loc(n)),
        };
        lo.b.warnings.push(format!(
            "Mitsuba scene: {}",
            open_boundary_warning(&shape, &reason)
        ));
    }
    let lights_before = lo.b.lights().len();
    lo.b.add_shape_with_media(geometry, material, emission, flip, media)
        .map_err(|e| d.err_at(d.pos(n), e.to_string()))?;
    if flat_emission {
        for l in lights_before..lo.b.lights().len() {
            lo.b.set_light_spectrum(l, EmissionSpectrum::Flat);
        }
    }
    Ok(())
}

/// A `directionalarea` emitter nested in a shape: its `radiance`, the position of its `type`
/// attribute and its element.
struct DirectionalArea<'a, 'i> {
    radiance: Spectrum,
    type_pos: usize,
    node: Node<'a, 'i>,
}

/// What [`directional_area`] needs of the shape holding the emitter.
struct ShapeParts<'t> {
    ty: &'t str,
    geometry: ShapeGeometry,
    flip: bool,
    media: MediumInterface,
    /// A BSDF was nested or referenced.
    has_bsdf: bool,
}

/// A disk with a `directionalarea` emitter (light leaving every point of the shape along its
/// normal) becomes a collimated [`BeamLight`]: the disk's centre and radius, its normal
/// (reversed by `flip_normals`) as the direction, and the emitter's `radiance` as the
/// irradiance across the beam (W/m²: Mitsuba 3's `directionalarea` gives each emitted ray the
/// weight `radiance` × area, so the beam carries `radiance` × π r² watts). The disk itself is
/// not a surface in caustica (a BSDF given to it is unused, noted as an approximation); its
/// exterior medium, if any, is the light's. Any other shape is an error at the emitter's type.
fn directional_area(
    lo: &mut Loader,
    d: &Doc,
    p: Props,
    shape: ShapeParts,
    e: DirectionalArea,
) -> Result<(), LoadError> {
    let ShapeGeometry::Disk(disk) = shape.geometry else {
        return Err(d.err_at(
            e.type_pos,
            format!(
                "a 'directionalarea' emitter needs a disk, not a '{}' shape (caustica imports it \
                 as a collimated beam from the disk)",
                shape.ty
            ),
        ));
    };
    if e.radiance.min_component() < 0.0 {
        return Err(d.err_at(
            d.pos(e.node),
            "directionalarea: radiance must be non-negative",
        ));
    }
    if shape.has_bsdf {
        lo.approximated(
            d,
            p.node,
            "the BSDF of a directionalarea disk is unused (the beam's aperture is not a surface)",
        );
    }
    let direction = if shape.flip {
        -disk.normal
    } else {
        disk.normal
    };
    lo.leftovers(d, p);
    lo.b.add_light(Light::Beam(BeamLight::new(
        disk.center,
        direction,
        disk.radius,
        e.radiance,
    )));
    if shape.media.outside != caustica_scene::intersection::NONE {
        lo.b.set_light_medium(lo.b.lights().len() - 1, shape.media.outside);
    }
    Ok(())
}

pub(super) fn emitter(lo: &mut Loader, d: &Doc, n: Node) -> Result<(), LoadError> {
    let (t, tpos) = ty(lo, d, n)?;
    let mut p = lo.props(d, n)?;
    let check = |d: &Doc, s: Spectrum, what: &str| -> Result<Spectrum, LoadError> {
        if s.min_component() < 0.0 {
            return Err(d.err_at(d.pos(n), format!("{what} must be non-negative")));
        }
        Ok(s)
    };
    // Mitsuba's scalar_spectral reads `<spectrum value="x">` on an emitter as a flat spectrum.
    let flat = ["intensity", "irradiance", "radiance"]
        .iter()
        .any(|k| p.is_flat_spectrum(k));
    let light = match t.as_str() {
        "point" => {
            let i = check(
                d,
                p.spectrum(d, "intensity")?.unwrap_or(Spectrum::ONE),
                "intensity",
            )?;
            let m = to_world(d, &mut p)?;
            let pos = match p.vector(d, "position")? {
                Some(v) => v,
                None => m.transform_point3(Vec3::ZERO),
            };
            Light::Point(PointLight::new(pos, i))
        }
        "spot" => {
            let i = check(
                d,
                p.spectrum(d, "intensity")?.unwrap_or(Spectrum::ONE),
                "intensity",
            )?;
            let m = to_world(d, &mut p)?;
            let cutoff = p.float(d, "cutoff_angle")?.unwrap_or(20.0);
            let beam = p.float(d, "beam_width")?.unwrap_or(cutoff * 0.75);
            if !(cutoff > 0.0 && cutoff <= 180.0 && beam >= 0.0 && beam <= cutoff) {
                return Err(d.err_at(
                    d.pos(n),
                    format!("spot: need 0 < cutoff_angle <= 180 and 0 <= beam_width <= cutoff_angle, got {cutoff} and {beam}"),
                ));
            }
            let dir = m
                .transform_vector3(Vec3::Z)
                .try_normalize()
                .ok_or_else(|| d.err_at(d.pos(n), "spot: to_world maps the z axis to zero"))?;
            Light::Spot(SpotLight::new(
                m.transform_point3(Vec3::ZERO),
                dir,
                i,
                cutoff,
                beam,
            ))
        }
        "directional" => {
            let e = check(
                d,
                p.spectrum(d, "irradiance")?.unwrap_or(Spectrum::ONE),
                "irradiance",
            )?;
            let m = to_world(d, &mut p)?;
            let dir = match p.vector(d, "direction")? {
                Some(v) => v,
                None => m.transform_vector3(Vec3::Z),
            };
            let dir = dir
                .try_normalize()
                .ok_or_else(|| d.err_at(d.pos(n), "directional: the direction must be non-zero"))?;
            Light::Directional(DirectionalLight::new(dir, e))
        }
        "constant" => {
            let l = check(
                d,
                p.spectrum(d, "radiance")?.unwrap_or(Spectrum::ONE),
                "radiance",
            )?;
            Light::Environment(EnvironmentLight::constant(l))
        }
        "area" | "directionalarea" => {
            return Err(d.err_at(
                tpos,
                format!("an {t} emitter must be nested inside a <shape>"),
            ));
        }
        other => {
            return Err(d.err_at(
                tpos,
                format!("unknown emitter type '{other}' (supported: area, directionalarea, point, spot, directional, constant)"),
            ));
        }
    };
    let mut medium = None;
    for c in std::mem::take(&mut p.children) {
        match c.tag_name().name() {
            "medium" | "ref" if matches!(t.as_str(), "point" | "spot") => {
                medium = Some(super::media::medium_child(lo, d, c)?);
            }
            _ => lo.unsupported(d, c, format!("<{}> inside {}", c.tag_name().name(), p.desc)),
        }
    }
    lo.leftovers(d, p);
    lo.b.add_light(light);
    if flat {
        lo.b.set_light_spectrum(lo.b.lights().len() - 1, EmissionSpectrum::Flat);
    }
    if let Some(m) = medium {
        lo.b.set_light_medium(lo.b.lights().len() - 1, m);
    }
    Ok(())
}

pub(super) fn sensor(lo: &mut Loader, d: &Doc, n: Node) -> Result<(), LoadError> {
    let (t, tpos) = ty(lo, d, n)?;
    if t != "perspective" && t != "thinlens" {
        return Err(d.err_at(
            tpos,
            format!("unknown sensor type '{t}' (supported: perspective, thinlens)"),
        ));
    }
    let mut p = lo.props(d, n)?;
    let (mut width, mut height) = (768u32, 576u32);
    for c in std::mem::take(&mut p.children) {
        match c.tag_name().name() {
            "film" => {
                let (ft, fpos) = ty(lo, d, c)?;
                if ft != "hdrfilm" {
                    lo.unsupported(d, c, format!("film type '{ft}' (treated as hdrfilm)"));
                    let _ = fpos;
                }
                let mut fp = lo.props(d, c)?;
                for (k, v) in [("width", &mut width), ("height", &mut height)] {
                    if let Some(prop) = fp.map.get(k).cloned() {
                        let x = fp.int(d, k)?.unwrap_or(0);
                        *v = u32::try_from(x)
                            .ok()
                            .filter(|&x| (1..=1 << 16).contains(&x))
                            .ok_or_else(|| {
                                d.err_at(prop.pos, format!("{k} must be from 1 to 65536, got {x}"))
                            })?;
                    }
                }
                if u64::from(width) * u64::from(height) > MAX_FILM_PIXELS {
                    return Err(d.err_at(
                        d.pos(c),
                        format!("film of {width}x{height} pixels is too large (at most {MAX_FILM_PIXELS} pixels, e.g. 16384x16384)"),
                    ));
                }
                for k in ["pixel_format", "component_format", "file_format"] {
                    let _ = fp.string(d, k)?;
                }
                for rc in std::mem::take(&mut fp.children) {
                    if rc.tag_name().name() != "rfilter" {
                        lo.unsupported(
                            d,
                            rc,
                            format!("<{}> inside {}", rc.tag_name().name(), fp.desc),
                        );
                        continue;
                    }
                    let (rt, rpos) = ty(lo, d, rc)?;
                    let mut rp = lo.props(d, rc)?;
                    lo.b.settings.filter = match rt.as_str() {
                        "box" => FilterKind::Box,
                        "gaussian" => {
                            let stddev = rp.float(d, "stddev")?.unwrap_or(0.5);
                            if stddev <= 0.0 {
                                return Err(d.err_at(
                                    d.pos(rc),
                                    format!("stddev must be positive, got {stddev}"),
                                ));
                            }
                            FilterKind::Gaussian {
                                stddev,
                                radius: 4.0 * stddev,
                            }
                        }
                        other => {
                            let _ = rpos;
                            lo.unsupported(d, rc, format!("rfilter '{other}' (box used)"));
                            rp.map.clear();
                            FilterKind::Box
                        }
                    };
                    lo.leftovers(d, rp);
                }
                lo.leftovers(d, fp);
            }
            "sampler" => {
                let (st, _) = ty(lo, d, c)?;
                let mut sp = lo.props(d, c)?;
                if let Some(prop) = sp.map.get("sample_count").cloned() {
                    let x = sp.int(d, "sample_count")?.unwrap_or(0);
                    let spp = u32::try_from(x).ok().filter(|&x| x >= 1).ok_or_else(|| {
                        d.err_at(
                            prop.pos,
                            format!("sample_count must be a positive integer, got {x}"),
                        )
                    })?;
                    lo.b.settings.spp = Some(spp);
                }
                if st != "independent" {
                    lo.approximated(
                        d,
                        c,
                        format!("sampler '{st}' replaced by caustica's sampler"),
                    );
                    sp.map.clear();
                }
                let _ = sp.int(d, "seed")?;
                lo.leftovers(d, sp);
            }
            "medium" | "ref" => {
                let m = super::media::medium_child(lo, d, c)?;
                lo.b.set_camera_medium(m);
            }
            other => lo.unsupported(d, c, format!("<{other}> inside {}", p.desc)),
        }
    }
    let m = match p.transform(d, "to_world")? {
        Some((m, pos)) => {
            let a = affine(d, pos, m)?;
            if !is_rigid(&a) {
                return Err(d.err_at(
                    pos,
                    "sensor to_world must be rigid (rotation, translation, reflection)",
                ));
            }
            a
        }
        None => Affine3A::IDENTITY,
    };
    let fov = match (p.float(d, "fov")?, p.take("focal_length")) {
        (Some(f), None) => f,
        (None, None) => {
            return Err(d.err_at(d.pos(n), "sensor: give 'fov' (degrees)"));
        }
        (_, Some(prop)) => {
            return Err(d.err_at(
                prop.pos,
                "sensor: focal_length is not supported, give 'fov'",
            ));
        }
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(d.err_at(
            d.pos(n),
            format!("fov must be in (0, 180) degrees, got {fov}"),
        ));
    }
    let (mut fov_deg, mut fov_axis) = (fov, FovAxis::X);
    if let Some((a, apos)) = p.string(d, "fov_axis")? {
        fov_axis = match a.as_str() {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            "diagonal" => {
                // Exact: the screen is planar, so tan(half-angle) scales with the extent.
                let (w, h) = (width as f32, height as f32);
                let t = (0.5 * fov.to_radians()).tan() * w / (w * w + h * h).sqrt();
                fov_deg = 2.0 * t.atan().to_degrees();
                FovAxis::X
            }
            other => {
                return Err(d.err_at(
                    apos,
                    format!(
                        "unknown fov_axis '{other}' (expected x, y, smaller, larger or diagonal)"
                    ),
                ));
            }
        };
    }
    let near_clip = p.float(d, "near_clip")?.unwrap_or(0.01);
    if near_clip <= 0.0 {
        return Err(d.err_at(
            d.pos(n),
            format!("near_clip must be positive, got {near_clip}"),
        ));
    }
    if let Some(far) = p.float(d, "far_clip")?
        && far < 1e4
    {
        lo.approximated(d, n, format!("far_clip {far} ignored (no far clipping)"));
    }
    let (lens_radius, focus_distance) = if t == "thinlens" {
        let r = p.float(d, "aperture_radius")?.unwrap_or(0.0);
        let f = p.float(d, "focus_distance")?.unwrap_or(1.0);
        if !(r >= 0.0 && f > 0.0) {
            return Err(d.err_at(
                d.pos(n),
                "thinlens: need aperture_radius >= 0 and focus_distance > 0",
            ));
        }
        (r, f)
    } else {
        (0.0, 1.0)
    };
    lo.leftovers(d, p);
    lo.b.set_camera(PerspectiveCamera {
        width,
        height,
        to_world: m,
        fov_deg,
        fov_axis,
        lens_radius,
        focus_distance,
        near_clip,
    });
    Ok(())
}

pub(super) fn integrator(lo: &mut Loader, d: &Doc, n: Node) -> Result<(), LoadError> {
    let (t, _) = ty(lo, d, n)?;
    let mut p = lo.props(d, n)?;
    if let Some(prop) = p.map.get("max_depth").cloned() {
        let x = p.int(d, "max_depth")?.unwrap_or(0);
        lo.b.settings.max_depth = match x {
            -1 => None,
            x => Some(u32::try_from(x).map_err(|_| {
                d.err_at(
                    prop.pos,
                    format!("max_depth must be -1 (unlimited) or >= 0, got {x}"),
                )
            })?),
        };
    }
    if !matches!(t.as_str(), "path" | "ptracer" | "volpath") {
        lo.approximated(
            d,
            n,
            format!("integrator '{t}' has no direct caustica equivalent"),
        );
    }
    let _ = p.int(d, "rr_depth")?;
    if p.bool(d, "hide_emitters")? == Some(true) {
        lo.approximated(d, n, "hide_emitters ignored (emitters stay visible)");
    }
    lo.b.settings.integrator = Some(t);
    for c in std::mem::take(&mut p.children) {
        lo.unsupported(d, c, format!("<{}> inside {}", c.tag_name().name(), p.desc));
    }
    lo.leftovers(d, p);
    Ok(())
}

//! `Material`/`MakeNamedMaterial` types (`diffuse`, `dielectric`, `thindielectric`,
//! `conductor`, `coateddiffuse`, `interface`) and `Texture` (`imagemap`, `checkerboard`,
//! `constant`) → caustica's materials and textures. Named spectra: pbrt's glasses become
//! caustica's dispersive Sellmeier glasses, its metals caustica's conductor presets.

use super::params::{Params, SpecVal};
use super::tokenizer::clip;
use super::{FloatTex, Loader};
use crate::error::LoadError;
use caustica_core::Spectrum;
use caustica_core::spectral::cie::spectrum_to_xyz;
use caustica_core::spectral::{d65, xyz_to_linear_srgb};
use caustica_scene::dispersion::{Dispersion, LAMBDA_D};
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::texture::{ImageTexture, Texture};
use std::sync::Arc;

/// pbrt's glasses caustica does not name, as Schott's Sellmeier coefficients (checked
/// against pbrt-v4's tabulated indices, which come from the same catalogue).
fn extra_glass(name: &str) -> Option<Dispersion> {
    let s = |b: [f64; 3], c: [f64; 3]| {
        Some(Dispersion::Sellmeier {
            b: [b[0], b[1], b[2], 0.0],
            c: [c[0], c[1], c[2], 0.0],
        })
    };
    match name {
        "fk51a" => s(
            [0.971_247_817, 0.216_901_417, 0.904_651_666],
            [0.004_723_019_95, 0.015_357_561_2, 168.681_33],
        ),
        "lasf9" => s(
            [2.000_295_47, 0.298_926_886, 1.806_918_43],
            [0.012_142_601_7, 0.053_873_623_6, 156.530_829],
        ),
        "f5" | "sf5" => s(
            [1.524_818_89, 0.187_085_527, 1.427_290_15],
            [0.011_254_756, 0.058_899_539_2, 129.141_675],
        ),
        "f10" | "sf10" => s(
            [1.621_539_02, 0.256_287_842, 1.644_475_52],
            [0.012_224_145_7, 0.059_573_677_5, 147.468_793],
        ),
        "f11" | "sf11" => s(
            [1.737_596_95, 0.313_747_346, 1.898_781_01],
            [0.013_188_707, 0.062_306_814_2, 155.236_29],
        ),
        _ => None,
    }
}

/// A named glass: `glass-BK7`, `glass-BAF10`, `glass-FK51A`, `glass-LASF9`, `glass-F5`,
/// `glass-F10`, `glass-F11` (pbrt-v4's), and caustica's own (`glass-F2`, `fused silica`,
/// `water`).
pub(crate) fn named_glass(name: &str) -> Option<Dispersion> {
    let key = name.trim().to_ascii_lowercase();
    let key = key.strip_prefix("glass-").unwrap_or(&key);
    extra_glass(key).or_else(|| Dispersion::named(key))
}

/// The RGB of a reflectance spectrum under D65 (linear sRGB).
fn sampled_reflectance(pairs: &[(f32, f32)]) -> Spectrum {
    let yw = spectrum_to_xyz(d65)[1];
    let xyz = spectrum_to_xyz(|l| super::lights::sample_piecewise(pairs, l) * d65(l));
    let rgb = xyz_to_linear_srgb(xyz.map(|x| x / yw)).map(|x| x.max(0.0));
    Spectrum::from_rgb(rgb)
}

/// A reflectance-like parameter (albedo in [0, 1]) as a texture; values above 1 are clamped
/// as pbrt clamps them.
fn reflectance(
    lo: &mut Loader,
    ps: &mut Params,
    name: &str,
    default: f32,
    line: usize,
) -> Result<Texture, LoadError> {
    let Some((v, l, c)) = ps.spectrum(name).map_err(|e| lo.perr(e))? else {
        return Ok(Texture::Constant(Spectrum::splat(default)));
    };
    let clamp = |lo: &mut Loader, s: Spectrum| {
        if s.max_component() > 1.0 {
            lo.approximated(
                line,
                format!("'{name}' above 1 clamped to 1 (as pbrt clamps reflectances)"),
            );
        }
        Spectrum::from_rgb(s.to_rgb().map(|x| x.clamp(0.0, 1.0)))
    };
    Ok(match v {
        SpecVal::Rgb(s) => Texture::Constant(clamp(lo, s)),
        SpecVal::Constant(x) => Texture::Constant(clamp(lo, Spectrum::splat(x.max(0.0)))),
        SpecVal::Sampled(p) => {
            lo.approximated(
                line,
                format!("sampled spectrum '{name}' reduced to its linear sRGB colour under D65"),
            );
            let s = sampled_reflectance(&p);
            Texture::Constant(clamp(lo, s))
        }
        SpecVal::Texture(t) => match lo.spectrum_textures.get(&t) {
            Some(tex) => tex.clone(),
            None if lo.float_textures.contains_key(&t) => {
                return Err(lo.err(
                    l,
                    c,
                    format!(
                        "texture \"{}\" is a float texture; '{name}' needs a spectrum texture",
                        clip(&t)
                    ),
                ));
            }
            None => {
                return Err(lo.err(
                    l,
                    c,
                    format!(
                        "unknown texture \"{}\" (define it with Texture before use)",
                        clip(&t)
                    ),
                ));
            }
        },
        SpecVal::Named(n) => {
            return Err(lo.err(l, c, format!("'{name}': named spectrum \"{}\" is not a reflectance (expected rgb, a sampled spectrum or a texture)", clip(&n))));
        }
        SpecVal::Blackbody(_) => {
            return Err(lo.err(l, c, format!("'{name}': a blackbody is not a reflectance")));
        }
    })
}

/// A float parameter that may also be a constant float texture.
fn float_param(lo: &mut Loader, ps: &mut Params, name: &str) -> Result<Option<f32>, LoadError> {
    let Some(p) = ps.list.iter().find(|p| p.name == name) else {
        return Ok(None);
    };
    if p.ty != "texture" {
        return ps.float(name).map_err(|e| lo.perr(e));
    }
    let Some((SpecVal::Texture(t), l, c)) = ps.spectrum(name).map_err(|e| lo.perr(e))? else {
        return Ok(None);
    };
    match lo.float_textures.get(&t) {
        Some(FloatTex::Constant(x)) => Ok(Some(*x)),
        Some(FloatTex::Other(ty)) => Err(lo.err(
            l,
            c,
            format!(
                "'{name}': a \"{}\" float texture is not supported here (expected a constant)",
                clip(ty)
            ),
        )),
        None => Err(lo.err(l, c, format!("unknown float texture \"{}\"", clip(&t)))),
    }
}

/// GGX α from `roughness` or `uroughness`/`vroughness` (anisotropy as √(αu αv), noted) and
/// `remaproughness` (pbrt-v4: α = √roughness).
fn alpha(lo: &mut Loader, ps: &mut Params, line: usize) -> Result<f32, LoadError> {
    let r = float_param(lo, ps, "roughness")?.unwrap_or(0.0);
    let u = float_param(lo, ps, "uroughness")?.unwrap_or(r);
    let v = float_param(lo, ps, "vroughness")?.unwrap_or(r);
    let remap = ps
        .bool("remaproughness")
        .map_err(|e| lo.perr(e))?
        .unwrap_or(true);
    if !(u >= 0.0 && v >= 0.0) {
        return Err(lo.err(
            line,
            1,
            format!("roughness must be non-negative, got {u} and {v}"),
        ));
    }
    let (au, av) = if remap { (u.sqrt(), v.sqrt()) } else { (u, v) };
    if au != av {
        lo.approximated(
            line,
            "anisotropic roughness replaced by sqrt(alpha_u*alpha_v)",
        );
    }
    Ok((au * av).sqrt())
}

/// `eta` of a dielectric: a float, a named glass (dispersive) or a sampled spectrum.
fn eta(
    lo: &mut Loader,
    ps: &mut Params,
    line: usize,
) -> Result<(f32, Option<Dispersion>), LoadError> {
    if ps.list.iter().any(|p| p.name == "eta" && p.ty == "texture") {
        return Ok((float_param(lo, ps, "eta")?.unwrap_or(1.5), None));
    }
    let Some((v, l, c)) = ps.spectrum("eta").map_err(|e| lo.perr(e))? else {
        return Ok((1.5, None));
    };
    let (ior, disp) = match v {
        SpecVal::Constant(x) => (x, None),
        SpecVal::Named(n) => {
            let d = named_glass(&n).ok_or_else(|| {
                lo.err(l, c, format!(
                    "unknown glass \"{}\" (expected glass-BK7, glass-BAF10, glass-FK51A, glass-LASF9, glass-F5, glass-F10, glass-F11, glass-F2, fused silica, water, or a number)",
                    clip(&n)
                ))
            })?;
            (d.ior_d(), Some(d))
        }
        SpecVal::Sampled(p) => {
            let x = super::lights::sample_piecewise(&p, LAMBDA_D);
            lo.approximated(
                line,
                format!("sampled eta replaced by its value {x} at {LAMBDA_D} nm (no dispersion)"),
            );
            (x, None)
        }
        _ => {
            return Err(lo.err(
                l,
                c,
                "eta must be a float, a named glass spectrum or a sampled spectrum",
            ));
        }
    };
    if !(ior > 0.0 && ior.is_finite()) {
        return Err(lo.err(l, c, format!("eta must be positive, got {ior}")));
    }
    Ok((ior, disp))
}

/// A conductor's `eta` or `k`: a named metal spectrum (`metal-Au-eta` …), rgb, or a constant.
fn metal_spectrum(
    lo: &mut Loader,
    ps: &mut Params,
    name: &str,
    default: &str,
) -> Result<Spectrum, LoadError> {
    let (v, l, c) = match ps.spectrum(name).map_err(|e| lo.perr(e))? {
        Some(x) => x,
        None => (SpecVal::Named(default.to_string()), 0, 0),
    };
    match v {
        SpecVal::Rgb(s) => Ok(s),
        SpecVal::Constant(x) => Ok(Spectrum::splat(x)),
        SpecVal::Named(n) => {
            let metal = n
                .strip_prefix("metal-")
                .and_then(|m| m.strip_suffix(&format!("-{name}")))
                .unwrap_or("");
            match conductor_preset(metal) {
                Some((eta, k)) => Ok(if name == "eta" { eta } else { k }),
                None => Err(lo.err(l, c, format!(
                    "unsupported conductor spectrum \"{}\" for '{name}' (supported: metal-Au-{name}, metal-Ag-{name}, metal-Al-{name}, metal-Cu-{name}, rgb values)",
                    clip(&n)
                ))),
            }
        }
        SpecVal::Sampled(p) => {
            let x = super::lights::sample_piecewise(&p, LAMBDA_D);
            lo.approximated(
                l,
                format!("sampled conductor '{name}' replaced by its value {x} at {LAMBDA_D} nm"),
            );
            Ok(Spectrum::splat(x))
        }
        _ => Err(lo.err(
            l,
            c,
            format!("conductor '{name}' must be a named metal spectrum, rgb or a constant"),
        )),
    }
}

pub(super) fn material(
    lo: &mut Loader,
    ty: &str,
    tl: usize,
    tc: usize,
    ps: &mut Params,
    line: usize,
) -> Result<Material, LoadError> {
    for k in ["displacement", "normalmap"] {
        if ps.has(k) {
            ps.ignore(k);
            lo.approximated(
                line,
                format!("material '{k}' ignored (no bump or normal mapping)"),
            );
        }
    }
    let m = match ty {
        "diffuse" => Material::Diffuse {
            reflectance: reflectance(lo, ps, "reflectance", 0.5, line)?,
        },
        "dielectric" => {
            let (ior, dispersion) = eta(lo, ps, line)?;
            let a = alpha(lo, ps, line)?;
            if a > 0.0 {
                Material::RoughDielectric {
                    ior,
                    alpha: a,
                    absorption: Spectrum::ZERO,
                    dispersion,
                }
            } else {
                Material::Dielectric {
                    ior,
                    absorption: Spectrum::ZERO,
                    dispersion,
                }
            }
        }
        "thindielectric" => {
            let _ = eta(lo, ps, line)?;
            lo.approximated(line, "thindielectric rendered as an index-matched (ior 1) dielectric: transmission is undeviated but its reflection is dropped");
            Material::Dielectric {
                ior: 1.0,
                absorption: Spectrum::ZERO,
                dispersion: None,
            }
        }
        "conductor" => {
            let refl = ps.spectrum("reflectance").map_err(|e| lo.perr(e))?;
            let a = alpha(lo, ps, line)?;
            let (eta, k) = match refl {
                Some((v, l, c)) => {
                    if ps.has("eta") || ps.has("k") {
                        return Err(lo.err(
                            l,
                            c,
                            "conductor: give either \"reflectance\" or \"eta\" and \"k\"",
                        ));
                    }
                    let r = match v {
                        SpecVal::Rgb(s) => s,
                        SpecVal::Constant(x) => Spectrum::splat(x),
                        _ => return Err(lo.err(l, c, "conductor \"reflectance\" must be rgb or a constant (textures are not supported)")),
                    };
                    let r = r.to_rgb();
                    if r.iter().all(|&x| x >= 1.0) {
                        // k → ∞: a perfect mirror.
                        if a > 0.0 {
                            lo.approximated(
                                line,
                                "rough conductor of reflectance 1 rendered with eta 0, k 1e4",
                            );
                            (Spectrum::ZERO, Spectrum::splat(1e4))
                        } else {
                            return Ok(Material::Mirror {
                                reflectance: Spectrum::ONE,
                            });
                        }
                    } else {
                        // pbrt-v4: eta = 1, k = 2√r / √(1 − r) (normal-incidence reflectance r).
                        let k = r.map(|x| {
                            let x = x.clamp(0.0, 0.9999);
                            2.0 * x.sqrt() / (1.0 - x).sqrt()
                        });
                        (Spectrum::ONE, Spectrum::from_rgb(k))
                    }
                }
                None => (
                    metal_spectrum(lo, ps, "eta", "metal-Cu-eta")?,
                    metal_spectrum(lo, ps, "k", "metal-Cu-k")?,
                ),
            };
            if a > 0.0 {
                Material::RoughConductor {
                    eta,
                    k,
                    alpha: a,
                    specular: Spectrum::ONE,
                }
            } else {
                Material::Conductor {
                    eta,
                    k,
                    specular: Spectrum::ONE,
                }
            }
        }
        "coateddiffuse" => {
            let kd = reflectance(lo, ps, "reflectance", 0.5, line)?;
            let a = alpha(lo, ps, line)?;
            let eta = float_param(lo, ps, "eta")?.unwrap_or(1.5);
            if !(eta > 0.0 && eta.is_finite()) {
                return Err(lo.err(
                    line,
                    1,
                    format!("coateddiffuse eta must be positive, got {eta}"),
                ));
            }
            for k in ["thickness", "albedo", "g", "maxdepth", "nsamples"] {
                ps.ignore(k);
            }
            let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let exponent = if a > 0.0 {
                (2.0 / (a * a) - 2.0).max(1.0)
            } else {
                1000.0
            };
            let diffuse = match kd {
                Texture::Constant(s) => Texture::Constant(s * (1.0 - f0)),
                Texture::Checkerboard { a, b, scale } => Texture::Checkerboard {
                    a: a * (1.0 - f0),
                    b: b * (1.0 - f0),
                    scale,
                },
                Texture::Image(_) => {
                    return Err(lo.err(tl, tc, "coateddiffuse with an image texture is not supported (caustica's approximation scales the reflectance by 1 - F0)"));
                }
            };
            lo.approximated(line, format!("coateddiffuse rendered as Phong: specular F0 {f0:.4}, exponent {exponent:.0}, diffuse = reflectance x (1 - F0); the coating's thickness, albedo and interreflection are ignored"));
            Material::Phong {
                diffuse,
                specular: Spectrum::splat(f0),
                exponent,
            }
        }
        "interface" | "" | "none" => Material::Null,
        "coatedconductor" | "diffusetransmission" | "hair" | "measured" | "mix" | "subsurface" => {
            return Err(lo.err(tl, tc, format!(
                "material \"{ty}\" is not supported (supported: diffuse, dielectric, thindielectric, conductor, coateddiffuse, interface)"
            )));
        }
        other => {
            return Err(lo.err(tl, tc, format!(
                "unknown material type \"{}\" (supported: diffuse, dielectric, thindielectric, conductor, coateddiffuse, interface)",
                clip(other)
            )));
        }
    };
    m.validate()
        .map_err(|e| lo.err(tl, tc, format!("material \"{ty}\": {e}")))?;
    Ok(m)
}

/// A checkerboard's `tex1`/`tex2`: constants only.
fn constant_value(
    lo: &mut Loader,
    ps: &mut Params,
    name: &str,
    default: f32,
) -> Result<Spectrum, LoadError> {
    match ps.spectrum(name).map_err(|e| lo.perr(e))? {
        None => Ok(Spectrum::splat(default)),
        Some((SpecVal::Rgb(s), ..)) => Ok(s),
        Some((SpecVal::Constant(x), ..)) => Ok(Spectrum::splat(x)),
        Some((_, l, c)) => Err(lo.err(l, c, format!("checkerboard '{name}' must be an rgb or float constant (nested textures are not supported)"))),
    }
}

pub(super) fn texture(
    lo: &mut Loader,
    name: &str,
    class: (&str, usize, usize),
    ty: (&str, usize, usize),
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    let spectrum = match class.0 {
        "spectrum" | "color" | "rgb" => true,
        "float" => false,
        other => {
            return Err(lo.err(
                class.1,
                class.2,
                format!(
                    "unknown texture class \"{}\" (expected \"spectrum\" or \"float\")",
                    clip(other)
                ),
            ));
        }
    };
    if lo.spectrum_textures.contains_key(name) || lo.float_textures.contains_key(name) {
        return Err(lo.err(
            class.1,
            class.2,
            format!("texture \"{}\" defined twice", clip(name)),
        ));
    }
    let mapping_defaults = [
        ("uscale", 1.0),
        ("vscale", 1.0),
        ("udelta", 0.0),
        ("vdelta", 0.0),
    ];
    match ty.0 {
        "constant" => {
            if spectrum {
                let v = constant_value(lo, ps, "value", 1.0)?;
                lo.spectrum_textures
                    .insert(name.to_string(), Texture::Constant(v));
            } else {
                let v = ps.float("value").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
                lo.float_textures
                    .insert(name.to_string(), FloatTex::Constant(v));
            }
        }
        "imagemap" => {
            let (file, fl, fc) = ps
                .string("filename")
                .map_err(|e| lo.perr(e))?
                .ok_or_else(|| lo.err(ty.1, ty.2, "imagemap needs \"string filename\""))?;
            if !spectrum {
                lo.float_textures
                    .insert(name.to_string(), FloatTex::Other("imagemap".into()));
                for p in [
                    "scale",
                    "invert",
                    "encoding",
                    "filter",
                    "maxanisotropy",
                    "wrap",
                    "uscale",
                    "vscale",
                    "udelta",
                    "vdelta",
                    "mapping",
                ] {
                    ps.ignore(p);
                }
                return Ok(());
            }
            let path = lo.input_file(&file, fl, fc)?;
            let mut img =
                caustica_core::image_io::Image::read(&path).map_err(|e| LoadError::File {
                    path: path.clone(),
                    message: format!("cannot load texture: {e}"),
                })?;
            let scale = ps.float("scale").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
            let invert = ps.bool("invert").map_err(|e| lo.perr(e))?.unwrap_or(false);
            if scale != 1.0 || invert {
                for p in &mut img.data {
                    for x in p.iter_mut() {
                        *x *= scale;
                        if invert {
                            *x = (1.0 - *x).max(0.0);
                        }
                    }
                }
            }
            if let Some((e, ..)) = ps.string("encoding").map_err(|e| lo.perr(e))?
                && e != "sRGB"
            {
                lo.approximated(
                    line,
                    format!(
                        "imagemap encoding \"{}\" ignored (8-bit images are decoded from sRGB)",
                        clip(&e)
                    ),
                );
            }
            if let Some((w, ..)) = ps.string("wrap").map_err(|e| lo.perr(e))?
                && w != "repeat"
            {
                lo.approximated(
                    line,
                    format!("imagemap wrap \"{}\" replaced by repeat", clip(&w)),
                );
            }
            for p in ["filter", "maxanisotropy"] {
                ps.ignore(p);
            }
            for (k, d) in mapping_defaults {
                if let Some(x) = ps.float(k).map_err(|e| lo.perr(e))?
                    && x != d
                {
                    lo.approximated(line, format!("imagemap '{k}' {x} ignored"));
                }
            }
            lo.spectrum_textures.insert(
                name.to_string(),
                Texture::Image(Arc::new(ImageTexture::new(img))),
            );
        }
        "checkerboard" => {
            if let Some(d) = ps.int("dimension").map_err(|e| lo.perr(e))?
                && d != 2
            {
                let (l, c) = ps.pos("dimension").unwrap_or((line, 1));
                return Err(lo.err(
                    l,
                    c,
                    format!("checkerboard dimension {d} is not supported (expected 2)"),
                ));
            }
            if !spectrum {
                lo.float_textures
                    .insert(name.to_string(), FloatTex::Other("checkerboard".into()));
                for p in [
                    "tex1", "tex2", "uscale", "vscale", "udelta", "vdelta", "mapping",
                ] {
                    ps.ignore(p);
                }
                return Ok(());
            }
            let a = constant_value(lo, ps, "tex1", 1.0)?;
            let b = constant_value(lo, ps, "tex2", 0.0)?;
            let us = ps.float("uscale").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
            let vs = ps.float("vscale").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
            if us != vs {
                lo.approximated(
                    line,
                    format!(
                        "checkerboard vscale {vs} replaced by uscale {us} (one scale for both axes)"
                    ),
                );
            }
            for k in ["udelta", "vdelta"] {
                if let Some(x) = ps.float(k).map_err(|e| lo.perr(e))?
                    && x != 0.0
                {
                    lo.approximated(line, format!("checkerboard '{k}' {x} ignored"));
                }
            }
            lo.approximated(
                line,
                "checkerboard is point-sampled (pbrt filters it over the pixel footprint)",
            );
            lo.spectrum_textures
                .insert(name.to_string(), Texture::Checkerboard { a, b, scale: us });
        }
        other => {
            return Err(lo.err(
                ty.1,
                ty.2,
                format!(
                    "unsupported texture type \"{}\" (supported: imagemap, checkerboard, constant)",
                    clip(other)
                ),
            ));
        }
    }
    if let Some((m, l, c)) = ps.string("mapping").map_err(|e| lo.perr(e))?
        && m != "uv"
    {
        return Err(lo.err(
            l,
            c,
            format!(
                "texture mapping \"{}\" is not supported (expected \"uv\")",
                clip(&m)
            ),
        ));
    }
    Ok(())
}

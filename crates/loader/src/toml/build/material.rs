//! Materials: the fields each type takes, energy conservation, conductor presets.

use super::fields::check_fields;
use super::texture::texture;
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::material::{DispersionDesc, DispersionLaw, MaterialDesc, MaterialType};
use crate::toml::desc::texture::TexDesc;
use ::toml::Spanned;
use caustica_core::Spectrum;
use caustica_scene::dispersion::Dispersion;
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::texture::Texture;

/// The dispersion law a `dispersion` field describes, validated over the visible range.
fn dispersion(d: &DispersionDesc) -> Result<Dispersion, String> {
    let law = match d {
        DispersionDesc::Named(name) => Dispersion::named(name).ok_or_else(|| {
            format!(
                "field 'dispersion': unknown glass '{name}' (expected one of {})",
                caustica_scene::dispersion::NAMED.join(", ")
            )
        })?,
        DispersionDesc::Law(DispersionLaw {
            sellmeier: Some(terms),
            cauchy: None,
        }) => {
            if terms.is_empty() || terms.len() > 4 {
                return Err(format!(
                    "field 'dispersion': 'sellmeier' takes 1 to 4 [B, C] terms, got {}",
                    terms.len()
                ));
            }
            let (mut b, mut c) = ([0.0; 4], [0.0; 4]);
            for (i, t) in terms.iter().enumerate() {
                (b[i], c[i]) = (t[0], t[1]);
            }
            Dispersion::Sellmeier { b, c }
        }
        DispersionDesc::Law(DispersionLaw {
            sellmeier: None,
            cauchy: Some(k),
        }) => match k.as_slice() {
            [a, b] => Dispersion::Cauchy {
                a: *a,
                b: *b,
                c: 0.0,
            },
            [a, b, c] => Dispersion::Cauchy {
                a: *a,
                b: *b,
                c: *c,
            },
            _ => {
                return Err(format!(
                    "field 'dispersion': 'cauchy' takes [A, B] or [A, B, C], got {} numbers",
                    k.len()
                ));
            }
        },
        DispersionDesc::Law(_) => {
            return Err(
                "field 'dispersion': give a glass name, { sellmeier = [[B, C], …] } or \
                 { cauchy = [A, B] }"
                    .into(),
            );
        }
    };
    law.validate()
        .map_err(|e| format!("field 'dispersion': {e}"))?;
    Ok(law)
}

pub(crate) fn material(cx: &Ctx, m: &Spanned<MaterialDesc>) -> Result<Material, LoadError> {
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
        ("dispersion", m.dispersion.is_some()),
    ];
    let allowed: &[&str] = match m.ty {
        MaterialType::Diffuse => &["reflectance"],
        MaterialType::Mirror => &["reflectance"],
        MaterialType::Dielectric => &["ior", "absorption", "dispersion"],
        MaterialType::Conductor => &["eta", "k", "preset", "specular"],
        MaterialType::RoughConductor => &["eta", "k", "preset", "specular", "alpha"],
        MaterialType::RoughDielectric => &["ior", "absorption", "alpha", "dispersion"],
        MaterialType::Phong => &["diffuse", "specular", "exponent"],
        MaterialType::Null => &[],
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
    let dispersion = match &m.dispersion {
        None => None,
        Some(d) => {
            if m.ior.is_some() {
                return Err(cx.err(
                    d.span(),
                    format!("{what}: give either 'ior' or 'dispersion', not both"),
                ));
            }
            Some(dispersion(d.get_ref()).map_err(|e| cx.err(d.span(), format!("{what}: {e}")))?)
        }
    };
    let ior = match (&dispersion, m.ior) {
        (Some(d), _) => d.ior_d(),
        (None, ior) => ior.map_or(1.5, |x| x.0),
    };
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
            let r = texture(
                cx,
                &span,
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
        MaterialType::Null => Material::Null,
        MaterialType::Dielectric => Material::Dielectric {
            ior,
            absorption,
            dispersion,
        },
        MaterialType::RoughDielectric => Material::RoughDielectric {
            ior,
            alpha,
            absorption,
            dispersion,
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
            let d = texture(
                cx,
                &span,
                m.diffuse.as_ref().unwrap_or(&TexDesc::Constant(grey(0.5))),
            )?;
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

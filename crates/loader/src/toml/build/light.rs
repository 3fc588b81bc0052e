//! Lights: the fields each type takes, directions, spot-light angles.

use super::fields::check_fields;
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::light::{LightDesc, LightType};
use crate::toml::value::Rgb;
use ::toml::Spanned;
use caustica_core::{Spectrum, Vec3};
use caustica_scene::light::{
    BeamLight, DirectionalLight, EmissionSpectrum, EnvironmentLight, Light, NamedSpectrum,
    PointLight, SpotLight,
};

/// A light and, when it names one, its emission spectrum.
pub(crate) fn light(
    cx: &Ctx,
    l: &Spanned<LightDesc>,
) -> Result<(Light, Option<EmissionSpectrum>), LoadError> {
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
        ("medium", l.medium.is_some()),
        ("spectrum", l.spectrum.is_some()),
    ];
    let allowed: &[&str] = match l.ty {
        LightType::Point => &["position", "intensity", "medium"],
        LightType::Spot => &[
            "position",
            "direction",
            "target",
            "intensity",
            "cutoff_angle",
            "beam_width",
            "medium",
        ],
        LightType::Directional => &["direction", "irradiance"],
        LightType::Beam => &["center", "direction", "radius", "irradiance", "medium"],
        LightType::Environment => &["radiance"],
    };
    let allowed: Vec<&str> = allowed.iter().copied().chain(["spectrum"]).collect();
    check_fields(cx, &span, &what, &present, &allowed)?;
    let named = match &l.spectrum {
        Some(s) => Some(
            NamedSpectrum::parse(s.get_ref())
                .map_err(|e| cx.err(s.span(), format!("{what}: field 'spectrum': {e}")))?,
        ),
        None => None,
    };
    // With a named spectrum the strength is one number (a grey value): the light's RGB values
    // are the spectrum's colour times it.
    let need = |v: Option<Rgb>, field: &str| -> Result<Spectrum, LoadError> {
        let v = v
            .map(|x| x.0)
            .ok_or_else(|| cx.err(span.clone(), format!("{what} needs '{field}'")))?;
        match named {
            None => Ok(v),
            Some(n) if v.c[0] == v.c[1] && v.c[1] == v.c[2] => Ok(n.rgb() * v.c[0]),
            Some(_) => Err(cx.err(
                span.clone(),
                format!(
                    "{what}: with 'spectrum', '{field}' must be one number (the light's \
                     luminance), got {:?}",
                    v.to_rgb()
                ),
            )),
        }
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
    let light = match l.ty {
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
    };
    Ok((light, named.map(EmissionSpectrum::named)))
}

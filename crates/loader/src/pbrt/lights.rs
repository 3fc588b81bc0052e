//! `LightSource` (`point`, `spot`, `distant`, `infinite` with a constant `L`) and
//! `AreaLightSource "diffuse"`, in pbrt-v4's units (see `docs/pbrt.md`): a light's spectrum is
//! divided by its luminance, except for the RGB factor of an `rgb` value, and multiplied by
//! `scale`; `power` or `illuminance` rescale it to the given total. caustica's values are
//! radiometric: intensity W/sr, radiance W/m²/sr, irradiance W/m², with an `rgb` value of 1
//! meaning what Mitsuba's RGB value 1 means.

use super::Loader;
use super::graphics_state::AreaLightDesc;
use super::params::{Params, SpecVal};
use super::shapes::affine;
use super::tokenizer::clip;
use crate::error::LoadError;
use caustica_core::spectral::cie::spectrum_to_xyz;
use caustica_core::spectral::xyz_to_linear_srgb;
use caustica_core::{PI, Spectrum, Vec3};
use caustica_scene::light::{
    DirectionalLight, EmissionSpectrum, EnvironmentLight, Light, NamedSpectrum, PointLight,
    SpotLight,
};

/// A light's spectrum parameter `name` as caustica's RGB value (luminance 1 unless given as
/// `rgb`) and, for named spectra, the spectrum spectral mode evaluates.
fn light_spectrum(
    lo: &mut Loader,
    ps: &mut Params,
    name: &str,
    line: usize,
) -> Result<(Spectrum, Option<EmissionSpectrum>), LoadError> {
    let Some((v, l, c)) = ps.spectrum(name).map_err(|e| lo.perr(e))? else {
        // pbrt's default: the colour space's illuminant (D65) at luminance 1: RGB white.
        return Ok((Spectrum::ONE, None));
    };
    let named = |s: NamedSpectrum| (s.rgb(), Some(EmissionSpectrum::named(s)));
    Ok(match v {
        SpecVal::Rgb(rgb) => (rgb, None),
        SpecVal::Constant(_) => {
            // A constant spectrum divided by its luminance: illuminant E of luminance 1.
            (Spectrum::ONE, Some(EmissionSpectrum::Flat))
        }
        SpecVal::Blackbody(t) => named(NamedSpectrum::blackbody(t).map_err(|m| lo.err(l, c, m))?),
        SpecVal::Named(n) => match n.as_str() {
            "stdillum-D65" => named(NamedSpectrum::D65),
            "stdillum-A" => {
                lo.approximated(line, "stdillum-A rendered as a 2856 K blackbody");
                named(NamedSpectrum::Blackbody(2856.0))
            }
            other => {
                return Err(lo.err(l, c, format!(
                    "parameter '{name}': unsupported light spectrum \"{}\" (expected \"stdillum-D65\", \"stdillum-A\", rgb, blackbody or sampled values)",
                    clip(other)
                )));
            }
        },
        SpecVal::Sampled(pairs) => {
            let f = |lambda: f32| sample_piecewise(&pairs, lambda);
            let xyz = spectrum_to_xyz(f);
            if !(xyz[1] > 0.0 && xyz[1].is_finite()) {
                return Err(lo.err(
                    l,
                    c,
                    format!("parameter '{name}': the sampled spectrum has no luminance"),
                ));
            }
            let rgb = xyz_to_linear_srgb(xyz.map(|x| x / xyz[1])).map(|x| x.max(0.0));
            lo.approximated(
                line,
                format!("sampled spectrum '{name}' reduced to its linear sRGB colour"),
            );
            (Spectrum::from_rgb(rgb), None)
        }
        SpecVal::Texture(_) => {
            return Err(lo.err(
                l,
                c,
                format!("parameter '{name}': lights cannot be textured"),
            ));
        }
    })
}

/// A piecewise-linear spectrum given as (wavelength, value) pairs, held constant beyond its
/// ends (as pbrt extends sampled spectra).
pub(crate) fn sample_piecewise(pairs: &[(f32, f32)], lambda: f32) -> f32 {
    let Some(&(l0, v0)) = pairs.first() else {
        return 0.0;
    };
    if lambda <= l0 {
        return v0;
    }
    for w in pairs.windows(2) {
        let ((la, va), (lb, vb)) = (w[0], w[1]);
        if lambda <= lb {
            let t = if lb > la {
                (lambda - la) / (lb - la)
            } else {
                0.0
            };
            return va + t * (vb - va);
        }
    }
    pairs.last().map_or(0.0, |p| p.1)
}

/// `scale` (any finite value pbrt allows, but a light must stay non-negative).
fn scale(lo: &Loader, ps: &mut Params, line: usize, col: usize) -> Result<f32, LoadError> {
    let s = ps.float("scale").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
    if s < 0.0 {
        let (l, c) = ps.pos("scale").unwrap_or((line, col));
        return Err(lo.err(l, c, format!("scale must be non-negative, got {s}")));
    }
    Ok(s)
}

/// A positive `power`/`illuminance`, or `None` (pbrt ignores values ≤ 0).
fn positive(lo: &Loader, ps: &mut Params, name: &str) -> Result<Option<f32>, LoadError> {
    Ok(ps.float(name).map_err(|e| lo.perr(e))?.filter(|&x| x > 0.0))
}

/// Adds `light` whose emitted value is `value`, which must be finite (a huge `scale` or
/// `power` could overflow it).
fn push(
    lo: &mut Loader,
    light: Light,
    value: Spectrum,
    spectrum: Option<EmissionSpectrum>,
    (line, col): (usize, usize),
) -> Result<(), LoadError> {
    if !value.is_finite() {
        return Err(lo.err(
            line,
            col,
            "the light's value (times scale, power or illuminance) is not finite in single precision",
        ));
    }
    lo.b.add_light(light);
    if let Some(s) = spectrum {
        lo.b.set_light_spectrum(lo.b.lights().len() - 1, s);
    }
    Ok(())
}

pub(super) fn light_source(
    lo: &mut Loader,
    ty: &str,
    tl: usize,
    tc: usize,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    let a = affine(&lo.gs.ctm)
        .ok_or_else(|| lo.err(tl, tc, "LightSource: the CTM must be affine and finite"))?;
    match ty {
        "point" => {
            let (i, spec) = light_spectrum(lo, ps, "I", line)?;
            let mut s = scale(lo, ps, tl, tc)?;
            if let Some(p) = positive(lo, ps, "power")? {
                s *= p / (4.0 * PI);
            }
            let from = ps
                .point3("from")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(Vec3::ZERO);
            let pos = a.transform_point3(from);
            push(
                lo,
                Light::Point(PointLight::new(pos, i * s)),
                i * s,
                spec,
                (tl, tc),
            )?;
        }
        "spot" => {
            let (i, spec) = light_spectrum(lo, ps, "I", line)?;
            let mut s = scale(lo, ps, tl, tc)?;
            let cone = ps
                .float("coneangle")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(30.0);
            let delta = ps
                .float("conedeltaangle")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(5.0);
            if !(cone > 0.0 && cone <= 180.0 && delta >= 0.0 && delta <= cone) {
                return Err(lo.err(tl, tc, format!("spot: need 0 < coneangle <= 180 and 0 <= conedeltaangle <= coneangle, got {cone} and {delta}")));
            }
            if let Some(p) = positive(lo, ps, "power")? {
                let (ce, cs) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
                s *= p / (2.0 * PI * ((1.0 - cs) + (cs - ce) / 2.0));
            }
            let from = ps
                .point3("from")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(Vec3::ZERO);
            let to = ps.point3("to").map_err(|e| lo.perr(e))?.unwrap_or(Vec3::Z);
            let (p0, p1) = (a.transform_point3(from), a.transform_point3(to));
            let dir = (p1 - p0)
                .try_normalize()
                .ok_or_else(|| lo.err(tl, tc, "spot: 'from' and 'to' must differ"))?;
            if delta > 0.0 {
                lo.approximated(line, "spot falloff: pbrt's smoothstep in cos θ replaced by caustica's (Mitsuba's) linear ramp in angle over the same cone");
            }
            push(
                lo,
                Light::Spot(SpotLight::new(p0, dir, i * s, cone, cone - delta)),
                i * s,
                spec,
                (tl, tc),
            )?;
        }
        "distant" => {
            let (l, spec) = light_spectrum(lo, ps, "L", line)?;
            let mut s = scale(lo, ps, tl, tc)?;
            if let Some(e) = positive(lo, ps, "illuminance")? {
                s *= e;
            }
            let from = ps
                .point3("from")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(Vec3::ZERO);
            let to = ps.point3("to").map_err(|e| lo.perr(e))?.unwrap_or(Vec3::Z);
            let dir = a
                .transform_vector3(to - from)
                .try_normalize()
                .ok_or_else(|| lo.err(tl, tc, "distant: 'from' and 'to' must differ"))?;
            push(
                lo,
                Light::Directional(DirectionalLight::new(dir, l * s)),
                l * s,
                spec,
                (tl, tc),
            )?;
        }
        "infinite" => {
            if let Some((f, fl, fc)) = ps.string("filename").map_err(|e| lo.perr(e))? {
                return Err(lo.err(fl, fc, format!(
                    "infinite light \"filename\" \"{}\": environment maps are not supported (expected a constant \"L\")",
                    clip(&f)
                )));
            }
            if ps.has("portal") {
                ps.ignore("portal");
                lo.unsupported(line, "infinite light 'portal' (no portal sampling)");
            }
            let (l, spec) = light_spectrum(lo, ps, "L", line)?;
            let mut s = scale(lo, ps, tl, tc)?;
            if let Some(e) = positive(lo, ps, "illuminance")? {
                s *= e / PI;
            }
            push(
                lo,
                Light::Environment(EnvironmentLight::constant(l * s)),
                l * s,
                spec,
                (tl, tc),
            )?;
        }
        "goniometric" | "projection" => {
            return Err(lo.err(tl, tc, format!("LightSource \"{ty}\" is not supported (supported: point, spot, distant, infinite)")));
        }
        other => {
            return Err(lo.err(
                tl,
                tc,
                format!(
                    "unknown light type \"{}\" (supported: point, spot, distant, infinite)",
                    clip(other)
                ),
            ));
        }
    }
    Ok(())
}

/// `AreaLightSource "diffuse"`: `L`, `scale`, `power`; `twosided` and image `filename`s are
/// errors (caustica's area lights are one-sided and uniform).
pub(super) fn area_light(
    lo: &mut Loader,
    ps: &mut Params,
    line: usize,
    col: usize,
) -> Result<AreaLightDesc, LoadError> {
    if let Some(true) = ps.bool("twosided").map_err(|e| lo.perr(e))? {
        let (l, c) = ps.pos("twosided").unwrap_or((line, col));
        return Err(lo.err(l, c, "AreaLightSource \"twosided\" true is not supported (caustica's area lights emit on one side: use two shapes facing away from each other)"));
    }
    if let Some((f, fl, fc)) = ps.string("filename").map_err(|e| lo.perr(e))? {
        return Err(lo.err(fl, fc, format!("AreaLightSource \"filename\" \"{}\": image area lights are not supported (expected \"L\")", clip(&f))));
    }
    let (l, spectrum) = light_spectrum(lo, ps, "L", line)?;
    let s = scale(lo, ps, line, col)?;
    let power = positive(lo, ps, "power")?;
    Ok(AreaLightDesc {
        radiance: l * s,
        spectrum,
        power,
    })
}

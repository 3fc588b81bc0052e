//! Media: coefficients from σ_a and σ_s or σ_t and albedo, times `scale`; grids from a `.vol`
//! file or a built-in procedural density, placed axis-aligned on the box [`min`, `max`].

use super::fields::check_fields;
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::medium::{MediumDesc, MediumType};
use ::toml::Spanned;
use caustica_scene::medium::{DensityGrid, Medium};

/// The procedural densities `density = "…"` names.
pub(crate) const DENSITIES: &[&str] = &["plume", "rising-smoke", "room-smoke"];

pub(crate) fn medium(cx: &Ctx, m: &Spanned<MediumDesc>) -> Result<Medium, LoadError> {
    let span = m.span();
    let m = m.get_ref();
    let what = format!("medium '{}' of type {:?}", m.name, m.ty).to_lowercase();
    let err = |msg: String| cx.err(span.clone(), format!("{what}: {msg}"));
    let present = [
        ("file", m.file.is_some()),
        ("density", m.density.is_some()),
        ("res", m.res.is_some()),
        ("min", m.min.is_some()),
        ("max", m.max.is_some()),
    ];
    let allowed: &[&str] = match m.ty {
        MediumType::Homogeneous => &[],
        MediumType::Grid => &["file", "density", "res", "min", "max"],
    };
    check_fields(cx, &span, &what, &present, allowed)?;
    let scale = m.scale.map_or(1.0, |s| s.0);
    let (sigma_a, sigma_s) = match (m.sigma_a, m.sigma_s, m.sigma_t, m.albedo) {
        (Some(a), Some(s), None, None) => (a.0 * scale, s.0 * scale),
        (None, None, Some(t), Some(al)) => {
            if al.0.max_component() > 1.0 {
                return Err(err(format!(
                    "field 'albedo' must lie in [0, 1], got {:?}",
                    al.0.c
                )));
            }
            Medium::coefficients_from_albedo(t.0 * scale, al.0)
        }
        _ => {
            return Err(err(
                "give either 'sigma_a' and 'sigma_s', or 'sigma_t' and 'albedo' (m⁻¹, a number or [r, g, b])".into(),
            ));
        }
    };
    let phase = m.phase.map(|p| p.0).unwrap_or_default();
    let out = match m.ty {
        MediumType::Homogeneous => Medium::homogeneous(sigma_a, sigma_s, phase),
        MediumType::Grid => {
            let (Some(min), Some(max)) = (m.min, m.max) else {
                return Err(err(
                    "a grid needs 'min' and 'max', the corners of the box it fills".into(),
                ));
            };
            let (min, max) = (min.0, max.0);
            if !min.cmplt(max).all() {
                return Err(err(format!(
                    "'min' must be below 'max' along every axis, got {min} and {max}"
                )));
            }
            let to_world = crate::builtin::unit_cube_to_box(min, max);
            let grid = match (&m.file, &m.density, m.res) {
                (Some(f), None, None) => {
                    let path = cx.input_file(f, &span)?;
                    let g = crate::vol::read_vol(&path).map_err(&err)?;
                    if g.channels == 3 {
                        return Err(err(format!(
                            "'{f}' has 3 channels per voxel; a grid medium needs one (a density)"
                        )));
                    }
                    DensityGrid::new(g.res, g.data, to_world)
                }
                (None, Some(name), Some(res)) => {
                    let f: fn(caustica_core::Vec3) -> f32 = match name.as_str() {
                        "plume" => crate::builtin::plume_density,
                        "rising-smoke" => crate::builtin::rising_smoke_density,
                        "room-smoke" => crate::builtin::room_smoke_density,
                        other => {
                            return Err(err(format!(
                                "unknown density '{other}' (built in: {})",
                                DENSITIES.join(", ")
                            )));
                        }
                    };
                    DensityGrid::from_fn(res.map(|r| r.0), to_world, f)
                }
                (Some(_), None, Some(_)) => {
                    return Err(err(
                        "field 'res' does not apply to a grid read from a file (the file gives it)"
                            .into(),
                    ));
                }
                (None, Some(_), None) => {
                    return Err(err("a procedural density needs 'res = [nx, ny, nz]'".into()));
                }
                _ => {
                    return Err(err(
                        "give either 'file' (a Mitsuba .vol grid) or 'density' with 'res'".into(),
                    ));
                }
            }
            .map_err(&err)?;
            Medium::grid(grid, sigma_a, sigma_s, phase)
        }
    };
    out.validate().map_err(err)?;
    Ok(out)
}

//! `[render]` and `[film]`: the scene's settings (sample count, path depth, pixel filter).

use super::fields::check_fields;
use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::film::{FilmDesc, FilterType};
use crate::toml::desc::integrator::IntegratorDesc;
use crate::toml::desc::render::RenderDesc;
use ::toml::Spanned;
use caustica_scene::scene::{FilterKind, SceneSettings};

pub(crate) fn settings(
    cx: &Ctx,
    render: Option<&RenderDesc>,
    film: Option<&Spanned<FilmDesc>>,
) -> Result<SceneSettings, LoadError> {
    let mut settings = SceneSettings::default();
    if let Some(r) = render {
        settings.spp = r.spp.map(|x| x.0);
        settings.max_depth = r.max_depth.map(|x| x.0);
    }
    if let Some(f) = film {
        let span = f.span();
        let f = f.get_ref();
        settings.filter = match f.filter {
            FilterType::Box => {
                check_fields(
                    cx,
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
    Ok(settings)
}

/// `[integrator]`: the suggested method and its photon options.
pub(crate) fn integrator(
    cx: &Ctx,
    desc: &Spanned<IntegratorDesc>,
    settings: &mut SceneSettings,
) -> Result<(), LoadError> {
    let d = desc.get_ref();
    settings.integrator = Some(d.ty.name().to_string());
    settings.photons = d.photons.map(|c| c.0);
    settings.final_gather = d.final_gather;
    settings.volume_photons = d.volume_photons.map(|c| c.0);
    for (name, value, slot) in [
        ("smoothing", d.smoothing, &mut settings.smoothing),
        (
            "volume_smoothing",
            d.volume_smoothing,
            &mut settings.volume_smoothing,
        ),
    ] {
        if let Some(s) = value {
            if !(s.is_finite() && s > 0.0) {
                return Err(cx.err(
                    desc.span(),
                    format!("[integrator] {name} must be a positive finite number, got {s}"),
                ));
            }
            *slot = Some(s);
        }
    }
    Ok(())
}

//! The options block: `Camera "perspective"`, `Film "rgb"`, `Sampler`, `PixelFilter` and
//! `Integrator`, mapped to caustica's camera and suggested render settings.
//!
//! pbrt's camera space is left-handed: raster x grows along camera +x = up × dir, where
//! caustica's (Mitsuba's) raster x grows along camera −x. The camera's world transform is
//! therefore pbrt's `worldFromCamera · diag(−1, 1, 1)`: a pbrt file renders as pbrt shows it,
//! and the usual `Scale -1 1 1` before `LookAt` of exported scenes cancels that mirror exactly.

use super::Loader;
use super::graphics_state::Xf;
use super::params::Params;
use super::tokenizer::clip;
use crate::MAX_FILM_PIXELS;
use crate::error::LoadError;
use caustica_core::{Affine3A, Mat3, Mat4, Vec3};
use caustica_scene::camera::{FovAxis, PerspectiveCamera};
use caustica_scene::scene::FilterKind;
use glam::Vec4;

/// A `Camera "perspective"`, completed with the film's size at the end of the file.
#[derive(Clone, Debug)]
pub(crate) struct CameraDesc {
    to_world: Affine3A,
    fov: f32,
    lens_radius: f32,
    focus_distance: f32,
    screen_window: Option<([f32; 4], usize, usize)>,
    frame_aspect: Option<(f32, usize, usize)>,
    path: std::path::PathBuf,
}

/// `Film` resolution (pbrt's defaults 1280 × 720).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FilmDesc {
    pub width: u32,
    pub height: u32,
}

impl Default for FilmDesc {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
        }
    }
}

/// pbrt's defaults for what a scene without `PixelFilter` or `Integrator` renders with: a
/// Gaussian filter of σ 0.5 and radius 1.5 pixels, and `volpath` (caustica `path`) with
/// `maxdepth` 5 (caustica max depth 6: pbrt counts bounces, caustica edges).
pub(crate) fn defaults(lo: &mut Loader) {
    lo.b.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 1.5,
    };
    lo.b.settings.integrator = Some("path".to_string());
    lo.b.settings.max_depth = Some(6);
}

pub(super) fn camera(
    lo: &mut Loader,
    ty: &str,
    tl: usize,
    tc: usize,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    if ty != "perspective" {
        return Err(lo.err(
            tl,
            tc,
            format!(
                "unsupported camera type \"{}\" (supported: perspective)",
                clip(ty)
            ),
        ));
    }
    let ctm = lo.gs.ctm;
    let world_from_camera = ctm.inv;
    if !world_from_camera.is_finite() || !world_from_camera.row(3).abs_diff_eq(Vec4::W, 1e-6) {
        return Err(lo.err(
            tl,
            tc,
            "Camera: the CTM must be an invertible affine transform",
        ));
    }
    let m = world_from_camera * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let a = Affine3A::from_mat4(m);
    let m3 = Mat3::from(a.matrix3);
    if !(m3.transpose() * m3).abs_diff_eq(Mat3::IDENTITY, 1e-4) {
        return Err(lo.err(tl, tc, "Camera: the CTM must be rigid (rotation, translation, reflection; no scale other than Scale -1 1 1)"));
    }
    lo.named_coords.insert(
        "camera".to_string(),
        Xf {
            m: world_from_camera,
            inv: ctm.m,
        },
    );
    let fov = ps.float("fov").map_err(|e| lo.perr(e))?.unwrap_or(90.0);
    if !(fov > 0.0 && fov < 180.0) {
        let (l, c) = ps.pos("fov").unwrap_or((tl, tc));
        return Err(lo.err(l, c, format!("fov must be in (0, 180) degrees, got {fov}")));
    }
    let lens_radius = ps
        .float("lensradius")
        .map_err(|e| lo.perr(e))?
        .unwrap_or(0.0);
    let focus = ps
        .float("focaldistance")
        .map_err(|e| lo.perr(e))?
        .unwrap_or(1e6);
    if !(lens_radius >= 0.0 && focus > 0.0) {
        return Err(lo.err(
            tl,
            tc,
            format!("need lensradius >= 0 and focaldistance > 0, got {lens_radius} and {focus}"),
        ));
    }
    let screen_pos = ps.pos("screenwindow");
    let screen_window = match ps.floats("screenwindow").map_err(|e| lo.perr(e))? {
        None => None,
        Some(v) if v.len() == 4 => {
            let (l, c) = screen_pos.unwrap_or((tl, tc));
            Some(([v[0], v[1], v[2], v[3]], l, c))
        }
        Some(v) => {
            let (l, c) = screen_pos.unwrap_or((tl, tc));
            return Err(lo.err(
                l,
                c,
                format!("screenwindow needs 4 numbers, got {}", v.len()),
            ));
        }
    };
    let aspect_pos = ps.pos("frameaspectratio");
    let frame_aspect = ps
        .float("frameaspectratio")
        .map_err(|e| lo.perr(e))?
        .map(|x| {
            let (l, c) = aspect_pos.unwrap_or((tl, tc));
            (x, l, c)
        });
    for k in ["shutteropen", "shutterclose"] {
        if ps.has(k) {
            ps.ignore(k);
            lo.unsupported(
                line,
                format!("Camera '{k}' (no shutter interval from pbrt files)"),
            );
        }
    }
    lo.camera = Some(CameraDesc {
        to_world: a,
        fov,
        lens_radius,
        focus_distance: if lens_radius > 0.0 { focus } else { 1.0 },
        screen_window,
        frame_aspect,
        path: lo.path.clone(),
    });
    Ok(())
}

pub(super) fn film(
    lo: &mut Loader,
    ty: &str,
    tl: usize,
    tc: usize,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    if ty != "rgb" {
        lo.unsupported(line, format!("Film \"{}\" (read as \"rgb\")", clip(ty)));
    }
    let mut f = FilmDesc::default();
    for (k, v) in [
        ("xresolution", &mut f.width),
        ("yresolution", &mut f.height),
    ] {
        let pos = ps.pos(k).unwrap_or((tl, tc));
        if let Some(x) = ps.int(k).map_err(|e| lo.perr(e))? {
            *v = u32::try_from(x)
                .ok()
                .filter(|&x| (1..=1 << 16).contains(&x))
                .ok_or_else(|| {
                    lo.err(
                        pos.0,
                        pos.1,
                        format!("{k} must be from 1 to 65536, got {x}"),
                    )
                })?;
        }
    }
    if u64::from(f.width) * u64::from(f.height) > MAX_FILM_PIXELS {
        return Err(lo.err(tl, tc, format!(
            "film of {}x{} pixels is too large (at most {MAX_FILM_PIXELS} pixels, e.g. 16384x16384)",
            f.width, f.height
        )));
    }
    lo.film = f;
    if let Some((name, ..)) = ps.string("filename").map_err(|e| lo.perr(e))? {
        lo.unsupported(
            line,
            format!(
                "Film filename \"{}\" (caustica writes where --output says)",
                clip(&name)
            ),
        );
    }
    for k in [
        "cropwindow",
        "pixelbounds",
        "iso",
        "exposuretime",
        "whitebalance",
        "sensor",
        "maxcomponentvalue",
        "diagonal",
    ] {
        if ps.has(k) {
            ps.ignore(k);
            lo.unsupported(line, format!("Film '{k}'"));
        }
    }
    ps.ignore("savefp16");
    Ok(())
}

pub(super) fn sampler(
    lo: &mut Loader,
    ty: &str,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    let spp = if ty == "stratified" {
        let x = ps.int("xsamples").map_err(|e| lo.perr(e))?.unwrap_or(4);
        let y = ps.int("ysamples").map_err(|e| lo.perr(e))?.unwrap_or(4);
        ps.ignore("jitter");
        Some(x.saturating_mul(y))
    } else {
        ps.int("pixelsamples").map_err(|e| lo.perr(e))?
    };
    if let Some(n) = spp {
        let n = u32::try_from(n).ok().filter(|&n| n >= 1).ok_or_else(|| {
            lo.err(
                line,
                1,
                format!("the sample count must be a positive integer, got {n}"),
            )
        })?;
        lo.b.settings.spp = Some(n);
    }
    for k in ["seed", "randomization"] {
        ps.ignore(k);
    }
    if ty != "independent" {
        lo.approximated(
            line,
            format!(
                "sampler \"{}\" replaced by caustica's sampler (same sample count)",
                clip(ty)
            ),
        );
    }
    Ok(())
}

pub(super) fn pixel_filter(
    lo: &mut Loader,
    ty: &str,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    let default_r = if ty == "box" { 0.5 } else { 1.5 };
    let xr = ps
        .float("xradius")
        .map_err(|e| lo.perr(e))?
        .unwrap_or(default_r);
    let yr = ps
        .float("yradius")
        .map_err(|e| lo.perr(e))?
        .unwrap_or(default_r);
    if !(xr > 0.0 && yr > 0.0) {
        return Err(lo.err(
            line,
            1,
            format!("filter radii must be positive, got {xr} and {yr}"),
        ));
    }
    if xr != yr {
        lo.approximated(
            line,
            format!("filter radii {xr} and {yr} replaced by {}", xr.max(yr)),
        );
    }
    lo.b.settings.filter = match ty {
        "box" => {
            if xr.max(yr) != 0.5 {
                lo.approximated(
                    line,
                    "box filter of radius other than 0.5 replaced by caustica's one-pixel box",
                );
            }
            FilterKind::Box
        }
        "gaussian" => {
            let sigma = ps.float("sigma").map_err(|e| lo.perr(e))?.unwrap_or(0.5);
            if !(sigma > 0.0 && sigma.is_finite()) {
                return Err(lo.err(
                    line,
                    1,
                    format!("gaussian sigma must be positive, got {sigma}"),
                ));
            }
            lo.approximated(line, "gaussian filter truncated at its radius without pbrt's offset (pbrt subtracts the value at the radius)");
            FilterKind::Gaussian {
                stddev: sigma,
                radius: xr.max(yr),
            }
        }
        other => {
            for k in ["B", "C", "tau"] {
                ps.ignore(k);
            }
            lo.approximated(
                line,
                format!(
                    "PixelFilter \"{}\" replaced by a gaussian of sigma 0.5 and radius {}",
                    clip(other),
                    xr.max(yr)
                ),
            );
            FilterKind::Gaussian {
                stddev: 0.5,
                radius: xr.max(yr),
            }
        }
    };
    Ok(())
}

pub(super) fn integrator(
    lo: &mut Loader,
    ty: &str,
    ps: &mut Params,
    line: usize,
) -> Result<(), LoadError> {
    let name = match ty {
        "path" | "volpath" => Some("path"),
        "lighttracer" => Some("lighttrace"),
        "bdpt" => {
            lo.approximated(
                line,
                "integrator \"bdpt\" suggested as caustica's lighttrace (no BDPT)",
            );
            Some("lighttrace")
        }
        "sppm" => Some("sppm"),
        "simplepath" | "simplevolpath" | "randomwalk" | "mlt" => {
            lo.approximated(
                line,
                format!("integrator \"{ty}\" suggested as caustica's path"),
            );
            Some("path")
        }
        other => {
            lo.unsupported(line, format!("Integrator \"{}\" (no caustica equivalent; the command line's integrator is used)", clip(other)));
            None
        }
    };
    lo.b.settings.integrator = name.map(str::to_string);
    let pos = ps.pos("maxdepth");
    let d = ps.int("maxdepth").map_err(|e| lo.perr(e))?.unwrap_or(5);
    lo.b.settings.max_depth = Some(
        u32::try_from(d)
            .ok()
            .and_then(|d| d.checked_add(1))
            .ok_or_else(|| {
                let (l, c) = pos.unwrap_or((line, 1));
                lo.err(
                    l,
                    c,
                    format!("maxdepth must be a non-negative integer, got {d}"),
                )
            })?,
    );
    for k in [
        "regularize",
        "lightsampler",
        "photonsperiteration",
        "iterations",
        "radius",
        "seed",
    ] {
        if ps.has(k) {
            ps.ignore(k);
            lo.unsupported(line, format!("Integrator '{k}'"));
        }
    }
    Ok(())
}

/// The camera of the scene: the `Camera` given (pbrt's default perspective camera of fov 90
/// at the origin otherwise) with the film's size.
pub(super) fn finish_camera(lo: &mut Loader) -> Result<(), LoadError> {
    let FilmDesc { width, height } = lo.film;
    let desc = lo.camera.clone().unwrap_or_else(|| CameraDesc {
        to_world: Affine3A::from_mat4(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))),
        fov: 90.0,
        lens_radius: 0.0,
        focus_distance: 1.0,
        screen_window: None,
        frame_aspect: None,
        path: lo.path.clone(),
    });
    let aspect = width as f32 / height as f32;
    let err = |l: usize, c: usize, m: String| LoadError::Parse {
        path: desc.path.clone(),
        line: l,
        column: c,
        message: m,
    };
    if let Some((x, l, c)) = desc.frame_aspect
        && (x - aspect).abs() > 1e-4 * aspect
    {
        return Err(err(
            l,
            c,
            format!(
                "frameaspectratio {x} differs from the film's {width}x{height} (changing the frame's aspect is not supported)"
            ),
        ));
    }
    if let Some((w, l, c)) = desc.screen_window {
        let d = if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        };
        if w.iter()
            .zip(d)
            .any(|(a, b)| (a - b).abs() > 1e-4 * b.abs().max(1.0))
        {
            return Err(err(
                l,
                c,
                format!(
                    "screenwindow {w:?} is not the default {d:?} for a {width}x{height} film (off-centre or zoomed screen windows are not supported)"
                ),
            ));
        }
    }
    lo.b.set_camera(PerspectiveCamera {
        width,
        height,
        to_world: desc.to_world,
        fov_deg: desc.fov,
        fov_axis: FovAxis::Smaller,
        lens_radius: desc.lens_radius,
        focus_distance: desc.focus_distance,
        near_clip: 0.01,
    });
    Ok(())
}

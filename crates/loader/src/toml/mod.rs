//! The caustica TOML scene format (documented in `docs/scene-format.md`).
//!
//! Parsing happens in two passes: the file is deserialised with serde (values are range-checked
//! while deserialising, so errors carry the line and column of the offending value), then every
//! camera, material, shape and light is converted and validated, and only then added to a
//! [`SceneBuilder`].
//!
//! * value parsing: `position` (byte spans → line and column), `context` (the file being read:
//!   `file:line:column` errors, relative paths), `value` (typed field readers that check ranges
//!   while deserialising);
//! * `desc`: the description each section deserialises to, one file per section;
//! * `build`: descriptions checked and turned into camera, settings, textures, materials, shape
//!   transforms, shapes and lights, one file each.

mod build;
mod context;
mod desc;
mod position;
mod value;

pub use build::camera::look_at_transform;
pub use position::line_column;

use crate::error::LoadError;
use build::animation::animation;
use build::camera::camera;
use build::light::light;
use build::material::material;
use build::medium::medium;
use build::settings::{integrator, settings};
use build::shape::medium_ref;
use build::shape::shape;
use caustica_scene::scene::SceneBuilder;
use caustica_scene::shape::ShapeGeometry;
use context::Ctx;
use desc::SceneFile;
use std::path::{Path, PathBuf};

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
    let file: SceneFile = ::toml::from_str(text).map_err(|e| cx.toml_err(e))?;

    // Pass 1: convert and validate everything.
    let camera = camera(&cx, &file.camera)?;
    let mut settings = settings(&cx, file.render.as_ref(), file.film.as_ref())?;
    if let Some(i) = &file.integrator {
        integrator(&cx, i, &mut settings)?;
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
    let mut media = Vec::with_capacity(file.medium.len());
    let mut medium_names: Vec<String> = Vec::new();
    for m in &file.medium {
        let name = &m.get_ref().name;
        if medium_names.contains(name) {
            return Err(cx.err(m.span(), format!("a medium named '{name}' already exists")));
        }
        media.push(medium(&cx, m)?);
        medium_names.push(name.clone());
    }
    let shapes = file
        .shape
        .iter()
        .map(|s| shape(&cx, s, &names, &medium_names))
        .collect::<Result<Vec<_>, _>>()?;
    let camera_medium = match &file.camera.get_ref().medium {
        Some(n) => Some(medium_ref(&cx, "medium", n, &medium_names)?),
        None => None,
    };
    let mut light_media = Vec::new();
    for (i, l) in file.light.iter().enumerate() {
        if let Some(n) = &l.get_ref().medium {
            light_media.push((i, medium_ref(&cx, "medium", n, &medium_names)?));
        }
    }
    let mut warnings = Vec::new();
    for (s, e) in file.shape.iter().zip(&shapes) {
        if e.media.is_transition()
            && let Some(reason) = crate::media::open_boundary_reason(&e.geometry)
        {
            let (line, _) = line_column(text, s.span().start);
            let file_name = path
                .file_name()
                .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
            let shape =
                format!("the {:?} shape at {file_name}:{line}", s.get_ref().ty).to_lowercase();
            warnings.push(crate::media::open_boundary_warning(&shape, &reason));
        }
    }
    let animation = match &file.animation {
        Some(a) => Some(animation(&cx, a)?),
        None => None,
    };
    if animation.is_none()
        && let Some((s, _)) = file
            .shape
            .iter()
            .zip(&shapes)
            .find(|(_, e)| e.motion.is_some())
    {
        return Err(cx.err(
            s.span(),
            "a moving shape needs the scene's frame rate: add [animation] with 'fps' (and \
             'shutter' in frames)",
        ));
    }
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
    for (n, m) in medium_names.iter().zip(media) {
        b.add_medium(n, m)?;
    }
    if let Some((fps, shutter)) = animation {
        b.settings.fps = Some(fps);
        b.set_shutter(shutter);
    }
    for (s, e) in file.shape.iter().zip(shapes) {
        match (e.geometry, e.motion) {
            (ShapeGeometry::Mesh(mesh), Some(motion)) => b
                .add_moving_mesh_with_media(mesh, motion, e.material, e.flip, e.media)
                .map_err(|err| cx.err(s.span(), err.to_string()))?,
            (g, _) => {
                let before = b.lights().len();
                b.add_shape_with_media(g, e.material, e.emission, e.flip, e.media)?;
                if let Some(spectrum) = e.emission_spectrum {
                    for l in before..b.lights().len() {
                        b.set_light_spectrum(l, spectrum);
                    }
                }
            }
        }
    }
    // The shapes' area lights come first in the builder's list.
    let first_light = b.lights().len();
    for (i, (l, spectrum)) in lights.into_iter().enumerate() {
        b.add_light(l);
        if let Some(s) = spectrum {
            b.set_light_spectrum(first_light + i, s);
        }
    }
    if let Some(m) = camera_medium {
        b.set_camera_medium(m);
    }
    for (i, m) in light_media {
        b.set_light_medium(first_light + i, m);
    }
    b.warnings.extend(warnings);
    Ok(b)
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_animation;

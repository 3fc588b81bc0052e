//! Descriptions: what each section of a TOML scene file deserialises to, before it is checked
//! against the other fields and converted (`super::build`).

pub(crate) mod animation;
pub(crate) mod camera;
pub(crate) mod film;
pub(crate) mod integrator;
pub(crate) mod light;
pub(crate) mod material;
pub(crate) mod medium;
pub(crate) mod render;
pub(crate) mod shape;
pub(crate) mod texture;
pub(crate) mod transform;

use ::toml::Spanned;
use animation::AnimationDesc;
use camera::CameraDesc;
use film::FilmDesc;
use integrator::IntegratorDesc;
use light::LightDesc;
use material::MaterialDesc;
use medium::MediumDesc;
use render::RenderDesc;
use serde::Deserialize;
use shape::ShapeDesc;

/// The whole file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub(crate) name: Option<String>,
    pub(crate) camera: Spanned<CameraDesc>,
    pub(crate) film: Option<Spanned<FilmDesc>>,
    pub(crate) render: Option<RenderDesc>,
    pub(crate) animation: Option<Spanned<AnimationDesc>>,
    pub(crate) integrator: Option<::toml::Spanned<IntegratorDesc>>,
    #[serde(default)]
    pub(crate) material: Vec<Spanned<MaterialDesc>>,
    #[serde(default)]
    pub(crate) medium: Vec<Spanned<MediumDesc>>,
    #[serde(default)]
    pub(crate) shape: Vec<Spanned<ShapeDesc>>,
    #[serde(default)]
    pub(crate) light: Vec<Spanned<LightDesc>>,
}

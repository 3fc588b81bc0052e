//! Builders: descriptions checked against each other and turned into the scene's camera,
//! settings, materials, shapes and lights. Every error points at the offending table.

pub(crate) mod animation;
pub(crate) mod camera;
pub(crate) mod fields;
pub(crate) mod light;
pub(crate) mod material;
pub(crate) mod medium;
pub(crate) mod settings;
pub(crate) mod shape;
pub(crate) mod texture;
pub(crate) mod transform;

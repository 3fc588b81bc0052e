//! `caustica.load`: a scene loaded once and rendered many times.

use caustica_cli::render_cmd::{Resolution, ShutterOverride, load_at};
use caustica_scene::Scene;
use pyo3::prelude::*;
use std::sync::Arc;

/// A loaded scene: a scene file (TOML, Mitsuba XML, pbrt-v4) or a built-in scene, with the
/// `<default>` parameters it was loaded with. Renders that change its image size, shutter or
/// spectral mode load it again with those settings; the others share this one.
#[pyclass(frozen, name = "Scene", module = "caustica._caustica")]
pub struct PyScene {
    /// The file or built-in name given to `load` (`None`: the embedded default scene).
    pub source: Option<String>,
    /// `-D name=value` definitions.
    pub defines: Vec<(String, String)>,
    /// The scene as loaded, without overrides.
    pub scene: Arc<Scene>,
}

#[pymethods]
impl PyScene {
    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }
    /// The file or built-in name it was loaded from (`None`: the embedded default scene).
    #[getter]
    fn source(&self) -> Option<&str> {
        self.source.as_deref()
    }
    /// Image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.scene.camera.width
    }
    /// Image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.scene.camera.height
    }
    /// The integrator the scene suggests, if any.
    #[getter]
    fn integrator(&self) -> Option<&str> {
        self.scene.settings.integrator.as_deref()
    }
    /// The samples per pixel the scene suggests, if any.
    #[getter]
    fn spp(&self) -> Option<u32> {
        self.scene.settings.spp
    }
    /// The `<default>` parameters given to `load`, as (name, value) pairs of strings.
    #[getter]
    fn defaults(&self) -> Vec<(String, String)> {
        self.defines.clone()
    }
    /// What the loader warned about (ignored or approximated elements).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "<caustica.Scene '{}' {}x{}{}>",
            self.scene.name,
            self.scene.camera.width,
            self.scene.camera.height,
            self.source
                .as_deref()
                .map(|s| format!(" from {s}"))
                .unwrap_or_default()
        )
    }
}

/// Loads `source` (a scene file or a built-in name; `None`: the default scene) with the
/// `<default>` overrides `defines`, exactly as `caustica render SOURCE -D name=value` does.
#[pyfunction]
#[pyo3(signature = (source, defines))]
pub fn load(
    py: Python<'_>,
    source: Option<String>,
    defines: Vec<(String, String)>,
) -> PyResult<PyScene> {
    let scene = py
        .detach(|| {
            load_at(
                source.as_deref(),
                &defines,
                Resolution::default(),
                ShutterOverride::default(),
            )
        })
        .map_err(crate::errors::to_py)?;
    Ok(PyScene {
        source,
        defines,
        scene: Arc::new(scene),
    })
}

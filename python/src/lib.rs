//! The native part of the `caustica` Python package (`caustica._caustica`). The public API,
//! with its docstrings and NumPy conversions, is `python/caustica/__init__.py`; this module
//! does the work with the command line's own code (`caustica_cli`), so a render from Python is
//! the render of the same command line, bit for bit.

mod errors;
mod images;
mod options;
mod render;
mod scene;

use pyo3::prelude::*;

/// The names of `render`'s keyword options and their Python kinds (bool, int, float, str, list).
#[pyfunction]
fn render_options() -> Vec<(String, String)> {
    options::names()
}

#[pymodule]
fn _caustica(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_image, m)?)?;
    m.add_function(wrap_pyfunction!(render_options, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::compare_images, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

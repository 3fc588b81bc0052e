//! caustica's errors as Python exceptions, with the messages the command line prints.

use caustica_core::image_io::ImageError;
use caustica_loader::LoadError;
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

/// The exception for an error of the command line's code: `OSError` when a file could not be
/// read or written, `ValueError` for everything else (a malformed scene, an option out of
/// range, options that exclude each other). The message is the CLI's (`error: {e:#}` without
/// the `error: `).
pub fn to_py(e: anyhow::Error) -> PyErr {
    let message = format!("{e:#}");
    let io = e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>().is_some()
            || matches!(c.downcast_ref::<LoadError>(), Some(LoadError::File { .. }))
            || matches!(c.downcast_ref::<ImageError>(), Some(ImageError::Io { .. }))
    });
    if io {
        PyOSError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

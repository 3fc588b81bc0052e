//! The file being read: errors at a span (`file:line:column: message`), toml's own errors given
//! the key they concern, relative file names resolved against the file's folder (input files must be regular files), and the cache
//! of image textures it loads.

use super::position::{key_before, line_column};
use crate::error::LoadError;
use caustica_scene::texture::ImageTexture;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The file being read (see the module comment).
pub(crate) struct Ctx<'a> {
    pub(crate) text: &'a str,
    pub(crate) path: &'a Path,
    pub(crate) dir: PathBuf,
    pub(crate) textures: std::cell::RefCell<HashMap<PathBuf, Arc<ImageTexture>>>,
}

impl Ctx<'_> {
    pub(crate) fn err(&self, span: Range<usize>, message: impl Into<String>) -> LoadError {
        let (line, column) = line_column(self.text, span.start);
        LoadError::Parse {
            path: self.path.to_path_buf(),
            line,
            column,
            message: message.into(),
        }
    }

    pub(crate) fn toml_err(&self, e: ::toml::de::Error) -> LoadError {
        let span = e.span().unwrap_or(0..0);
        let mut message = e.message().trim().to_string();
        if !message.contains("field")
            && let Some(key) = key_before(self.text, span.start)
        {
            message = format!("field '{key}': {message}");
        }
        self.err(span, message)
    }

    pub(crate) fn resolve(&self, file: &str) -> PathBuf {
        let p = Path::new(file);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.dir.join(p)
        }
    }

    /// `file` resolved as by [`Ctx::resolve`]; it must be an existing regular file (an error at
    /// `span` otherwise), so a scene cannot make the loader read a device (`/dev/zero`), a FIFO
    /// or a directory. Missing files are left to the reader, which names them with the OS error.
    pub(crate) fn input_file(&self, file: &str, span: &Range<usize>) -> Result<PathBuf, LoadError> {
        let path = self.resolve(file);
        match std::fs::metadata(&path) {
            Ok(m) if !m.is_file() => Err(self.err(
                span.clone(),
                format!("'{}' is not a regular file", path.display()),
            )),
            _ => Ok(path),
        }
    }
}

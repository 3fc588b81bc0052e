//! Texture-valued parameters; an image file is loaded once per scene file.

use crate::error::LoadError;
use crate::toml::context::Ctx;
use crate::toml::desc::texture::TexDesc;
use caustica_scene::texture::{ImageTexture, Texture};
use std::ops::Range;
use std::sync::Arc;

/// The texture `t` describes; a file error or a non-regular file is reported at `span`.
pub(crate) fn texture(cx: &Ctx, span: &Range<usize>, t: &TexDesc) -> Result<Texture, LoadError> {
    Ok(match t {
        TexDesc::Constant(c) => Texture::Constant(*c),
        TexDesc::Checker(a, b, scale) => Texture::Checkerboard {
            a: *a,
            b: *b,
            scale: *scale,
        },
        TexDesc::File(f) => {
            let p = cx.resolve(f);
            if let Some(t) = cx.textures.borrow().get(&p) {
                return Ok(Texture::Image(t.clone()));
            }
            let p = cx.input_file(f, span)?;
            let t = Arc::new(ImageTexture::load(&p).map_err(|e| LoadError::File {
                path: p.clone(),
                message: format!("cannot load texture: {e}"),
            })?);
            cx.textures.borrow_mut().insert(p, t.clone());
            Texture::Image(t)
        }
    })
}

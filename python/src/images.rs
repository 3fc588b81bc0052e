//! `caustica.read`, `caustica.write` and `caustica.compare`: images in and out, and the metrics
//! of `caustica compare`.

use crate::errors::to_py;
use caustica_cli::compare_cmd::MetricArgs;
use caustica_core::image_io::Image;
use caustica_eval::metrics::CompareOptions;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::path::PathBuf;

/// An image from little-endian f32 RGB `data` (row-major, top row first), checked against its
/// size.
fn image(what: &str, data: &[u8], width: usize, height: usize) -> PyResult<Image> {
    let n = width
        .checked_mul(height)
        .and_then(|p| p.checked_mul(12))
        .ok_or_else(|| PyValueError::new_err(format!("{what}: {width}x{height} is too large")))?;
    if data.len() != n {
        return Err(PyValueError::new_err(format!(
            "{what}: {} bytes for a {width}x{height} RGB float32 image, expected {n}",
            data.len()
        )));
    }
    let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let mut img = Image::new(width, height);
    for (px, b) in img.data.iter_mut().zip(data.chunks_exact(12)) {
        *px = [f(&b[0..4]), f(&b[4..8]), f(&b[8..12])];
    }
    Ok(img)
}

/// Reads an EXR, PFM or PNG image (PNG decoded from sRGB to linear): f32 RGB bytes, width,
/// height.
#[pyfunction]
pub fn read_image<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Bound<'py, PyByteArray>, usize, usize)> {
    let img = py
        .detach(|| caustica_cli::compare_cmd::read(&path, "image"))
        .map_err(to_py)?;
    Ok((PyByteArray::new(py, &bytes(&img)), img.width, img.height))
}

/// An image as little-endian f32 RGB bytes, row-major from the top row (what `image` reads).
pub fn bytes(img: &Image) -> Vec<u8> {
    img.data
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect()
}

/// Writes f32 RGB bytes as EXR, PFM or PNG (by extension; PNG tone-mapped at `exposure` stops
/// as `render --png` does).
#[pyfunction]
#[pyo3(signature = (path, data, width, height, exposure=0.0))]
pub fn write_image(
    py: Python<'_>,
    path: PathBuf,
    data: Vec<u8>,
    width: usize,
    height: usize,
    exposure: f32,
) -> PyResult<()> {
    let img = image("image", &data, width, height)?;
    let png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    py.detach(|| {
        if png {
            img.write_png(&path, exposure)
        } else {
            img.write(&path)
        }
    })
    .map_err(|e| to_py(anyhow::Error::new(e).context(format!("cannot write {}", path.display()))))
}

/// An image argument of `compare_images`: f32 RGB bytes, width, height.
type ImageArg = (Vec<u8>, usize, usize);

/// The metrics of `caustica compare IMAGE REFERENCE` as a dict.
#[pyfunction]
#[pyo3(signature = (image_arg, reference_arg, mask=None, crop=None, exposure=0.0, block=16, block_tolerance=0.01, mask_black=false))]
#[allow(clippy::too_many_arguments)]
pub fn compare_images<'py>(
    py: Python<'py>,
    image_arg: ImageArg,
    reference_arg: ImageArg,
    mask: Option<ImageArg>,
    crop: Option<String>,
    exposure: f32,
    block: usize,
    block_tolerance: f64,
    mask_black: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let img = image("image", &image_arg.0, image_arg.1, image_arg.2)?;
    let reference = image(
        "reference",
        &reference_arg.0,
        reference_arg.1,
        reference_arg.2,
    )?;
    let mask = mask.map(|(d, w, h)| image("mask", &d, w, h)).transpose()?;
    if block == 0 {
        return Err(PyValueError::new_err("block must be at least 1"));
    }
    let metric = MetricArgs {
        crop,
        mask: None,
        mask_black,
        exposure,
    };
    let (w, h) = (reference.width, reference.height);
    let c = py
        .detach(|| {
            let region = metric.region_with(w, h, mask.as_ref().map(|m| (m, "array")))?;
            let region = metric.region_for(&region, &img, &reference);
            let options = CompareOptions {
                exposure,
                block_size: block,
                block_tolerance,
            };
            caustica_eval::compare(&img, &reference, &region, options).map_err(anyhow::Error::new)
        })
        .map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("pixels", c.pixels)?;
    d.set_item("mean_image", c.mean_image.to_vec())?;
    d.set_item("mean_reference", c.mean_reference.to_vec())?;
    d.set_item("relative_mean_difference", c.relative_mean_difference)?;
    d.set_item("rmse", c.rmse)?;
    d.set_item("relative_mse", c.relative_mse)?;
    d.set_item("mise", c.mise)?;
    d.set_item("ssim", c.ssim)?;
    let p = PyDict::new(py);
    p.set_item("pixels", c.pixel_z.pixels)?;
    p.set_item("mean", c.pixel_z.mean)?;
    p.set_item("rms", c.pixel_z.rms)?;
    p.set_item("frac_over_2", c.pixel_z.frac_over_2)?;
    p.set_item("frac_over_3", c.pixel_z.frac_over_3)?;
    d.set_item("pixel_z", p)?;
    let b = PyDict::new(py);
    let bz = &c.block_z;
    b.set_item("size", bz.size)?;
    b.set_item("blocks", bz.blocks)?;
    b.set_item("threshold", bz.threshold)?;
    b.set_item("max_abs_z", bz.max_abs_z)?;
    b.set_item("worst_block", bz.worst_block)?;
    b.set_item("worst_relative", bz.worst_relative)?;
    b.set_item("tolerance", bz.tolerance)?;
    b.set_item("flagged", bz.flagged)?;
    d.set_item("block_z", b)?;
    Ok(d)
}

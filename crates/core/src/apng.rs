//! Animated PNG (APNG) previews of rendered sequences: 8-bit sRGB frames played at a frame rate,
//! looping. Every browser and most image viewers play them; a viewer without APNG support shows
//! the first frame. Written with the `png` crate (the encoder the `image` crate uses).

use crate::image_io::{Image, ImageError};
use std::path::Path;

fn err(path: &Path, message: impl Into<String>) -> ImageError {
    ImageError::Format {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The delay between frames at `fps` frames per second as the fraction APNG stores
/// (numerator, denominator, both 16-bit): exact for integer rates up to 65535 and for rates
/// with two decimals such as 23.98 or 29.97 (within 16 bits), rounded otherwise.
pub fn frame_delay(fps: f32) -> (u16, u16) {
    if !(fps.is_finite() && fps > 0.0) {
        return (1, 25);
    }
    for scale in [1.0f64, 100.0] {
        let den = fps as f64 * scale;
        if (den - den.round()).abs() < 1e-3 && den.round() <= u16::MAX as f64 && den >= 1.0 {
            return (scale as u16, den.round() as u16);
        }
    }
    // A rate that is no simple fraction: milliseconds per frame.
    let ms = (1000.0 / fps as f64).round().clamp(1.0, u16::MAX as f64);
    (ms as u16, 1000)
}

/// Writes `frames` (all of one size) as an APNG at `path` that loops forever at `fps`, with
/// `exposure` stops applied as for PNG output ([`Image::to_srgb8`]).
pub fn write_apng(
    path: &Path,
    frames: &[Image],
    fps: f32,
    exposure: f32,
) -> Result<(), ImageError> {
    let Some(first) = frames.first() else {
        return Err(err(path, "an animated PNG needs at least one frame"));
    };
    if let Some((k, f)) = frames
        .iter()
        .enumerate()
        .find(|(_, f)| (f.width, f.height) != (first.width, first.height))
    {
        return Err(err(
            path,
            format!(
                "frame {k} is {}x{}, frame 0 {}x{}: every frame must have one size",
                f.width, f.height, first.width, first.height
            ),
        ));
    }
    let (w, h) = match (u32::try_from(first.width), u32::try_from(first.height)) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
        _ => return Err(err(path, "image size unsuitable for PNG")),
    };
    let n = u32::try_from(frames.len()).map_err(|_| err(path, "too many frames"))?;
    let file = std::fs::File::create(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let png_err = |e: png::EncodingError| err(path, e.to_string());
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_animated(n, 0).map_err(png_err)?;
    let (num, den) = frame_delay(fps);
    enc.set_frame_delay(num, den).map_err(png_err)?;
    let mut writer = enc.write_header().map_err(png_err)?;
    for f in frames {
        writer
            .write_image_data(&f.to_srgb8(exposure))
            .map_err(png_err)?;
    }
    writer.finish().map_err(png_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_delays_are_exact_for_common_rates() {
        assert_eq!(frame_delay(25.0), (1, 25));
        assert_eq!(frame_delay(24.0), (1, 24));
        assert_eq!(frame_delay(29.97), (100, 2997));
        assert_eq!(frame_delay(0.5), (100, 50));
        assert_eq!(frame_delay(0.0), (1, 25));
        assert_eq!(frame_delay(1.0 / 3.0), (3000, 1000));
    }

    #[test]
    fn an_apng_holds_every_frame_and_its_delay() {
        let dir = std::env::temp_dir().join(format!("caustica-apng-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("seq.png");
        let frames: Vec<Image> = (0..3)
            .map(|k| {
                let mut im = Image::new(4, 2);
                im.set(k, 0, [1.0, 0.0, 0.0]);
                im
            })
            .collect();
        write_apng(&path, &frames, 12.0, 0.0).unwrap();
        // Decode with the png crate: three frames, 1/12 s each, frame k lit at pixel (k, 0).
        let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = dec.read_info().unwrap();
        let info = reader.info();
        let actl = info.animation_control().unwrap();
        assert_eq!((actl.num_frames, actl.num_plays), (3, 0));
        let mut buf = vec![0u8; reader.output_buffer_size().unwrap()];
        for k in 0..3 {
            reader.next_frame(&mut buf).unwrap();
            let fc = reader.info().frame_control().unwrap();
            assert_eq!((fc.delay_num, fc.delay_den), (1, 12));
            let lit: Vec<usize> = (0..8).filter(|&i| buf[3 * i] == 255).collect();
            assert_eq!(lit, vec![k], "frame {k}");
        }
        // Frames of different sizes are refused.
        let bad = [Image::new(4, 2), Image::new(2, 2)];
        assert!(write_apng(&path, &bad, 12.0, 0.0).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}

//! Mitsuba's binary `.vol` voxel grids (the format of Mitsuba 0.6 and 3's `gridvolume`), read
//! for heterogeneous media.
//!
//! Little endian: bytes `'V' 'O' 'L'`, a `u8` version (3), an `i32` encoding (1 = float32, the
//! only one supported), `i32` x, y and z resolutions, an `i32` channel count (1; 3 channels are
//! averaged into one, see [`VolGrid::channels`]), the bounding box as six `f32` (x, y, z
//! minimum, then maximum), then `f32` data with x fastest:
//! `data[((z·ny + y)·nx + x)·channels + c]`.
//!
//! The box is returned but does not place the grid: Mitsuba 3 places a `gridvolume`'s unit cube
//! by its `to_world` and uses the file's box only with `use_grid_bbox = true`.

use caustica_core::Vec3;
use std::path::Path;

/// Bytes before the voxel data.
pub const VOL_HEADER_BYTES: usize = 48;

/// A grid read from a `.vol` file, reduced to one channel.
#[derive(Clone, Debug, PartialEq)]
pub struct VolGrid {
    /// Voxels along x, y, z (each ≥ 1).
    pub res: [u32; 3],
    /// Channels stored in the file (1 or 3); with 3, `data` holds their mean.
    pub channels: u32,
    /// The bounding box stored in the file (minimum, maximum).
    pub bbox: [Vec3; 2],
    /// One finite, non-negative value per voxel, x fastest.
    pub data: Vec<f32>,
}

/// Reads the `.vol` file at `path`; the message of an error names the file and what is wrong.
pub fn read_vol(path: &Path) -> Result<VolGrid, String> {
    let bytes = std::fs::read(path)
        .map_err(|e| format!("cannot read grid file '{}': {e}", path.display()))?;
    parse_vol(&bytes).map_err(|e| format!("grid file '{}': {e}", path.display()))
}

fn i32_at(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Parses the bytes of a `.vol` file (see the module comment).
pub fn parse_vol(b: &[u8]) -> Result<VolGrid, String> {
    if b.len() < 4 || &b[..3] != b"VOL" {
        return Err("not a Mitsuba volume: it does not start with the bytes 'VOL'".into());
    }
    if b[3] != 3 {
        return Err(format!("unsupported .vol version {} (expected 3)", b[3]));
    }
    if b.len() < VOL_HEADER_BYTES {
        return Err(format!(
            "truncated: the header needs {VOL_HEADER_BYTES} bytes, the file has {}",
            b.len()
        ));
    }
    let encoding = i32_at(b, 4);
    if encoding != 1 {
        return Err(format!(
            "unsupported encoding {encoding} (only 1, float32, is supported)"
        ));
    }
    let r = [i32_at(b, 8), i32_at(b, 12), i32_at(b, 16)];
    if r.iter().any(|&x| x <= 0) {
        return Err(format!(
            "zero-size grid: the resolution must be at least 1 along each axis, got {}×{}×{}",
            r[0], r[1], r[2]
        ));
    }
    let channels = i32_at(b, 20);
    if channels != 1 && channels != 3 {
        return Err(format!(
            "{channels} channels per voxel (supported: 1, or 3 averaged into one)"
        ));
    }
    let res = r.map(|x| x as u32);
    let voxels = res
        .iter()
        .try_fold(1u64, |acc, &x| acc.checked_mul(u64::from(x)));
    let need = voxels
        .and_then(|v| v.checked_mul(channels as u64 * 4))
        .and_then(|d| d.checked_add(VOL_HEADER_BYTES as u64));
    let Some(need) = need.filter(|&n| n <= usize::MAX as u64) else {
        return Err(format!(
            "a {}×{}×{} grid is too large",
            res[0], res[1], res[2]
        ));
    };
    if b.len() as u64 != need {
        return Err(format!(
            "{}: a {}×{}×{} grid of {channels} channel(s) needs {need} bytes, the file has {}",
            if (b.len() as u64) < need {
                "truncated"
            } else {
                "trailing data"
            },
            res[0],
            res[1],
            res[2],
            b.len()
        ));
    }
    let f = |i: usize| f32_at(b, 24 + 4 * i);
    let bbox = [Vec3::new(f(0), f(1), f(2)), Vec3::new(f(3), f(4), f(5))];
    let n = need.saturating_sub(VOL_HEADER_BYTES as u64) as usize / (4 * channels as usize);
    let c = channels as usize;
    let mut data = Vec::with_capacity(n);
    for v in 0..n {
        let mut sum = 0.0f32;
        for k in 0..c {
            let x = f32_at(b, VOL_HEADER_BYTES + 4 * (v * c + k));
            if !(x.is_finite() && x >= 0.0) {
                let (nx, ny) = (res[0] as usize, res[1] as usize);
                return Err(format!(
                    "densities must be finite and non-negative, voxel (x {}, y {}, z {}) \
                     channel {k} is {x}",
                    v % nx,
                    (v / nx) % ny,
                    v / (nx * ny)
                ));
            }
            sum += x;
        }
        data.push(sum / c as f32);
    }
    Ok(VolGrid {
        res,
        channels: channels as u32,
        bbox,
        data,
    })
}

/// The bytes of a version-3, float32 `.vol` file of `channels` channels per voxel (`data` x
/// fastest, channels interleaved).
pub fn encode_vol(res: [u32; 3], channels: u32, bbox: [Vec3; 2], data: &[f32]) -> Vec<u8> {
    let mut out = Vec::with_capacity(VOL_HEADER_BYTES + 4 * data.len());
    out.extend_from_slice(b"VOL");
    out.push(3);
    out.extend_from_slice(&1i32.to_le_bytes());
    for r in res {
        out.extend_from_slice(&(r as i32).to_le_bytes());
    }
    out.extend_from_slice(&(channels as i32).to_le_bytes());
    for v in bbox[0].to_array().into_iter().chain(bbox[1].to_array()) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::Affine3A;
    use caustica_scene::medium::DensityGrid;

    fn bbox() -> [Vec3; 2] {
        [Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 4.0)]
    }

    #[test]
    fn round_trip_and_voxel_centres() {
        let res = [3u32, 2, 4];
        let data: Vec<f32> = (0..24).map(|i| i as f32 * 0.25).collect();
        let dir = std::env::temp_dir().join(format!("caustica-vol-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("ramp.vol");
        std::fs::write(&file, encode_vol(res, 1, bbox(), &data)).unwrap();
        let g = read_vol(&file).unwrap();
        assert_eq!(g.res, res);
        assert_eq!(g.channels, 1);
        assert_eq!(g.bbox, bbox());
        assert_eq!(g.data, data);
        // The trilinear density at each voxel centre is that voxel (x fastest).
        let grid = DensityGrid::new(g.res, g.data, Affine3A::IDENTITY).unwrap();
        for k in 0..4 {
            for j in 0..2 {
                for i in 0..3 {
                    let p = Vec3::new(
                        (i as f32 + 0.5) / 3.0,
                        (j as f32 + 0.5) / 2.0,
                        (k as f32 + 0.5) / 4.0,
                    );
                    let want = data[(k * 2 + j) * 3 + i];
                    assert!((grid.density(p) - want).abs() < 1e-5, "{i} {j} {k}");
                }
            }
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn three_channels_are_averaged() {
        let g = parse_vol(&encode_vol(
            [2, 1, 1],
            3,
            bbox(),
            &[1.0, 2.0, 6.0, 0.0, 0.0, 3.0],
        ))
        .unwrap();
        assert_eq!(g.channels, 3);
        assert_eq!(g.data, vec![3.0, 1.0]);
    }

    #[test]
    fn bad_files_are_refused_with_what_was_expected() {
        let good = encode_vol([2, 2, 1], 1, bbox(), &[0.0, 1.0, 2.0, 3.0]);
        let err = |b: &[u8]| parse_vol(b).unwrap_err();
        assert!(err(b"VOX\x03").contains("'VOL'"));
        assert!(err(b"").contains("'VOL'"));
        let mut v2 = good.clone();
        v2[3] = 2;
        assert!(err(&v2).contains("version 2"));
        let e = err(&good[..good.len() - 3]);
        assert!(
            e.contains("truncated") && e.contains("64 bytes") && e.contains("has 61"),
            "{e}"
        );
        let e = err(&good[..20]);
        assert!(e.contains("truncated") && e.contains("48"), "{e}");
        let mut long = good.clone();
        long.push(0);
        assert!(err(&long).contains("trailing"));
        let mut enc = good.clone();
        enc[4] = 2;
        assert!(err(&enc).contains("encoding 2"));
        let e = err(&encode_vol([0, 2, 1], 1, bbox(), &[]));
        assert!(e.contains("zero-size"), "{e}");
        let mut neg = good.clone();
        neg[12..16].copy_from_slice(&(-2i32).to_le_bytes());
        assert!(err(&neg).contains("zero-size"));
        let e = err(&encode_vol([1, 1, 1], 6, bbox(), &[0.0; 6]));
        assert!(e.contains("6 channels"), "{e}");
        let e = err(&encode_vol(
            [2, 2, 1],
            1,
            bbox(),
            &[0.0, 1.0, f32::NAN, 3.0],
        ));
        assert!(
            e.contains("voxel (x 0, y 1, z 0)") && e.contains("NaN"),
            "{e}"
        );
        let e = err(&encode_vol([2, 2, 1], 1, bbox(), &[0.0, -1.0, 0.0, 3.0]));
        assert!(
            e.contains("voxel (x 1, y 0, z 0)") && e.contains("-1"),
            "{e}"
        );
        // Sizes whose byte count overflows do not panic.
        let mut huge = good.clone();
        for a in [8, 12, 16] {
            huge[a..a + 4].copy_from_slice(&i32::MAX.to_le_bytes());
        }
        assert!(err(&huge).contains("too large") || err(&huge).contains("truncated"));
        let e = read_vol(Path::new("/no/such/dir/x.vol")).unwrap_err();
        assert!(e.contains("/no/such/dir/x.vol"), "{e}");
    }
}

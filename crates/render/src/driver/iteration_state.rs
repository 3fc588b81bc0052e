//! The state of a progressive render between iterations, as bytes for a state file: what
//! `--resume` needs to continue it to exactly the bytes an uninterrupted render gives. Since
//! iteration `i` is a pure function of `i` (its light paths, camera samples and bandwidth depend
//! on nothing else), the state is just the number of iterations pooled and the pooled film's
//! accumulators (exact sums, stored as their fixed-point integers), with a fingerprint of what was rendered (scene,
//! integrator, every option that changes an iteration) and a checksum.
//!
//! Layout (little-endian): magic `CAUSTICA-STATE\n`, format version (u32), fingerprint (u64
//! length + UTF-8), iterations (u64), window x, y, width, height and full-film width, height
//! (u32 each), per pixel Σ L (3 × i128, units of 2⁻⁶³: [`crate::ExactSum`]), sample count (u32)
//! and splat sum (3 × i128), the splat
//! path count (u64), the method's own statistics (u64 count + f64 each: SPPM's and PPM's R², N
//! and τ per pixel; none for pppm, ppds, ppdm), then the FNV-1a 64 checksum of everything before
//! it.

use crate::crop::CropWindow;
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::integrator::IntegratorKind;
use crate::options::RenderOptions;
use caustica_scene::Scene;

const MAGIC: &[u8] = b"CAUSTICA-STATE\n";
/// Bumped whenever the layout or what an iteration computes changes.
pub const STATE_VERSION: u32 = 3;

/// Why a state file cannot be resumed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateError {
    #[error("not a caustica state file (it does not start with the state file's magic line)")]
    NotState,
    #[error(
        "the state file has format version {found}; this caustica writes and reads version {expected}"
    )]
    Version { found: u32, expected: u32 },
    #[error("the state file is truncated or corrupted (its checksum does not match)")]
    Corrupted,
    #[error("the state file's {what} differs: it has '{state}', this render '{now}'")]
    Differs {
        what: &'static str,
        state: String,
        now: String,
    },
}

/// A progressive render after some iterations.
#[derive(Clone)]
pub struct IterationState {
    /// What was rendered ([`fingerprint`]).
    pub fingerprint: String,
    /// Complete iterations pooled into `film`.
    pub iterations: u64,
    pub film: Film,
    /// The method's statistics between iterations (SPPM and PPM: R², N, τ₀, τ₁, τ₂ per pixel).
    pub extra: Vec<f64>,
}

impl std::fmt::Debug for IterationState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "IterationState {{ iterations: {} }}", self.iterations)
    }
}

/// What a state file must match to be resumed: the caustica version, the scene (name, film
/// size, contents counted), the integrator and every option that changes an iteration (the
/// iteration count, time budget, checkpoints and memory limit may differ).
pub fn fingerprint(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> String {
    let mut o = opts.clone();
    o.time_limit = None;
    o.checkpoint_interval = None;
    o.memory_limit = None;
    o.resume = None;
    o.shard = None;
    o.photons.progressive.iterations = None;
    format!(
        "caustica {}\nscene {} {}x{} ({} primitives, {} lights, {} materials, {} media)\nintegrator {}\noptions {:?}",
        env!("CARGO_PKG_VERSION"),
        scene.name,
        scene.camera.width,
        scene.camera.height,
        scene.geometry.primitive_count(),
        scene.lights.len(),
        scene.materials.len(),
        scene.media.len(),
        kind.name(),
        o
    )
}

/// Where a render whose state is its pooled film alone (pppm, ppds, ppdm, pdpm, pcf) starts:
/// after the iterations of `opts.resume`, their film restored into `film` and a note added, or
/// at iteration 1. Returns that iteration and the render's fingerprint (for
/// [`IterationState::pooled`]).
pub fn resume_pooled(
    scene: &Scene,
    kind: IntegratorKind,
    opts: &RenderOptions,
    film: &mut Film,
    notes: &mut Vec<String>,
) -> Result<(u64, String), crate::error::OptionError> {
    let fp = fingerprint(scene, kind, opts);
    let first = match &opts.resume {
        Some(state) => {
            let next = state.restore_into(film, &fp, 0)?;
            notes.push(format!("resumed after iteration {}", state.iterations));
            next
        }
        None => 1,
    };
    Ok((first, fp))
}

impl IterationState {
    /// The state of a render (fingerprint `fingerprint`) whose pooled film `film` holds
    /// iterations 1 … `iterations` and which keeps no other statistics.
    pub fn pooled(fingerprint: &str, iterations: u64, film: &Film) -> Self {
        Self {
            fingerprint: fingerprint.to_string(),
            iterations,
            film: film.clone(),
            extra: Vec::new(),
        }
    }

    /// Restores this state into `film` for a render whose fingerprint is `fingerprint` and
    /// whose method keeps `extra_len` statistics: checks that they match (the CLI checks the
    /// file first and names what differs; this guards library callers), copies the pooled film
    /// and returns the iteration to go on from.
    pub fn restore_into(
        &self,
        film: &mut Film,
        fingerprint: &str,
        extra_len: usize,
    ) -> Result<u64, crate::error::OptionError> {
        if self.fingerprint != fingerprint
            || self.film.window() != film.window()
            || self.film.full != film.full
            || self.extra.len() != extra_len
        {
            return Err(crate::error::OptionError::Conflict(
                "the state to resume was written for another scene, integrator, film or options"
                    .into(),
            ));
        }
        *film = self.film.clone();
        Ok(self.iterations + 1)
    }

    /// This state's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        Self::encode_with(&self.fingerprint, self.iterations, &self.film, &self.extra)
    }

    /// The state file's bytes for `iterations` complete iterations pooled into `film`, with the
    /// method's statistics `extra`.
    pub fn encode_with(fingerprint: &str, iterations: u64, film: &Film, extra: &[f64]) -> Vec<u8> {
        let n = film.sum.len();
        let mut b = Vec::with_capacity(64 + fingerprint.len() + n * 100 + extra.len() * 8);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&STATE_VERSION.to_le_bytes());
        b.extend_from_slice(&(fingerprint.len() as u64).to_le_bytes());
        b.extend_from_slice(fingerprint.as_bytes());
        b.extend_from_slice(&iterations.to_le_bytes());
        put_frame(&mut b, film);
        for i in 0..n {
            for v in film.sum[i] {
                b.extend_from_slice(&v.to_bits().to_le_bytes());
            }
            b.extend_from_slice(&film.count[i].to_le_bytes());
            for v in film.splat[i] {
                b.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        }
        b.extend_from_slice(&film.splat_paths.to_le_bytes());
        b.extend_from_slice(&(extra.len() as u64).to_le_bytes());
        for v in extra {
            b.extend_from_slice(&v.to_le_bytes());
        }
        let sum = crate::partial::fnv1a(crate::partial::FNV_OFFSET, &b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Reads a state file's bytes, checked whole (magic, version, checksum) and against the
    /// render it should continue (`fingerprint` of it); the error says what differs.
    pub fn decode(bytes: &[u8], expected: &str) -> Result<Self, StateError> {
        if !bytes.starts_with(MAGIC) {
            return Err(StateError::NotState);
        }
        let mut r = Reader {
            b: bytes,
            at: MAGIC.len(),
        };
        let version = r.u32()?;
        if version != STATE_VERSION {
            return Err(StateError::Version {
                found: version,
                expected: STATE_VERSION,
            });
        }
        if bytes.len() < MAGIC.len() + 12 {
            return Err(StateError::Corrupted);
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let want = u64::from_le_bytes(tail.try_into().map_err(|_| StateError::Corrupted)?);
        if crate::partial::fnv1a(crate::partial::FNV_OFFSET, body) != want {
            return Err(StateError::Corrupted);
        }
        let len = r.u64()? as usize;
        let fp = std::str::from_utf8(r.take(len)?)
            .map_err(|_| StateError::Corrupted)?
            .to_string();
        if fp != expected {
            return Err(first_difference(&fp, expected));
        }
        let iterations = r.u64()?;
        let mut film = read_frame(&mut r, body.len())?;
        for i in 0..film.sum.len() {
            for k in 0..3 {
                film.sum[i][k] = ExactSum::from_bits(r.i128()?);
            }
            film.count[i] = r.u32()?;
            for k in 0..3 {
                film.splat[i][k] = ExactSum::from_bits(r.i128()?);
            }
        }
        film.splat_paths = r.u64()?;
        let n = r.u64()? as usize;
        if n > body.len() / 8 {
            return Err(StateError::Corrupted);
        }
        let extra = (0..n).map(|_| r.f64()).collect::<Result<Vec<f64>, _>>()?;
        if r.at != body.len() {
            return Err(StateError::Corrupted);
        }
        Ok(Self {
            fingerprint: fp,
            iterations,
            film,
            extra,
        })
    }
}

/// The first line (scene, integrator, version) or option that differs between two fingerprints.
pub(crate) fn first_difference(state: &str, now: &str) -> StateError {
    for (a, b) in state.lines().zip(now.lines()) {
        if a == b {
            continue;
        }
        let (what, a, b) = match a.split_once(' ') {
            Some(("options", rest)) => {
                // The first differing "field: value" of the options' Debug text.
                let bs = b.strip_prefix("options ").unwrap_or(b);
                let diff = rest
                    .split(", ")
                    .zip(bs.split(", "))
                    .find(|(x, y)| x != y)
                    .map(|(x, y)| (x.to_string(), y.to_string()))
                    .unwrap_or((rest.into(), bs.into()));
                ("options", diff.0, diff.1)
            }
            Some(("scene", _)) => ("scene", a.into(), b.into()),
            Some(("integrator", _)) => ("integrator", a.into(), b.into()),
            _ => ("caustica version", a.into(), b.into()),
        };
        return StateError::Differs {
            what,
            state: a,
            now: b,
        };
    }
    StateError::Differs {
        what: "render",
        state: state.into(),
        now: now.into(),
    }
}

/// Writes a film's frame: its window x, y, width, height and the full film's width, height
/// (u32 each). Shared by the state file and the shard's part ([`crate::partial`]).
pub(crate) fn put_frame(b: &mut Vec<u8>, film: &Film) {
    let w = film.window();
    for v in [
        w.x,
        w.y,
        w.width,
        w.height,
        film.full.0 as u32,
        film.full.1 as u32,
    ] {
        b.extend_from_slice(&v.to_le_bytes());
    }
}

/// Reads a frame ([`put_frame`]) into an empty film: a window inside its film, of at most
/// `limit` or 2²⁶ pixels, whichever is more (the checksum has passed, so this guards only
/// against a file written wrong allocating without bound).
pub(crate) fn read_frame(r: &mut Reader, limit: usize) -> Result<Film, StateError> {
    let [x, y, width, height, fw, fh] =
        [r.u32()?, r.u32()?, r.u32()?, r.u32()?, r.u32()?, r.u32()?];
    let fits = width >= 1
        && height >= 1
        && x as u64 + width as u64 <= fw as u64
        && y as u64 + height as u64 <= fh as u64
        && (width as u64 * height as u64) <= (limit as u64).max(1 << 26);
    if !fits {
        return Err(StateError::Corrupted);
    }
    let window = CropWindow {
        x,
        y,
        width,
        height,
    };
    Ok(Film::cropped(window, fw as usize, fh as usize))
}

pub(crate) struct Reader<'a> {
    pub(crate) b: &'a [u8],
    pub(crate) at: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], StateError> {
        let end = self.at.checked_add(n).ok_or(StateError::Corrupted)?;
        let s = self.b.get(self.at..end).ok_or(StateError::Corrupted)?;
        self.at = end;
        Ok(s)
    }
    pub(crate) fn u32(&mut self) -> Result<u32, StateError> {
        Ok(u32::from_le_bytes(
            self.take(4)?
                .try_into()
                .map_err(|_| StateError::Corrupted)?,
        ))
    }
    pub(crate) fn u64(&mut self) -> Result<u64, StateError> {
        Ok(u64::from_le_bytes(
            self.take(8)?
                .try_into()
                .map_err(|_| StateError::Corrupted)?,
        ))
    }
    pub(crate) fn i128(&mut self) -> Result<i128, StateError> {
        Ok(i128::from_le_bytes(
            self.take(16)?
                .try_into()
                .map_err(|_| StateError::Corrupted)?,
        ))
    }
    pub(crate) fn f64(&mut self) -> Result<f64, StateError> {
        Ok(f64::from_le_bytes(
            self.take(8)?
                .try_into()
                .map_err(|_| StateError::Corrupted)?,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film() -> Film {
        let mut f = Film::cropped(
            CropWindow {
                x: 1,
                y: 2,
                width: 3,
                height: 2,
            },
            8,
            6,
        );
        for (i, s) in f.sum.iter_mut().enumerate() {
            *s = [i as f64 * 0.1, 1.0 / 3.0, -2.5e3].map(ExactSum::from_f64);
        }
        f.count.iter_mut().for_each(|c| *c = 7);
        f.splat[3] = [1.0, 2.0, -3.0].map(ExactSum::from_f64);
        f.splat_paths = 99;
        f
    }

    #[test]
    fn round_trip_is_exact() {
        let f = film();
        let b = IterationState::encode_with("fp", 12, &f, &[]);
        let s = IterationState::decode(&b, "fp").unwrap();
        assert_eq!(s.iterations, 12);
        assert_eq!(s.film.window(), f.window());
        assert_eq!(s.film.full, f.full);
        assert_eq!(s.film.sum, f.sum);
        assert_eq!(s.film.count, f.count);
        assert_eq!(s.film.splat, f.splat);
        assert_eq!(s.film.splat_paths, 99);
        assert!(s.extra.is_empty());
        // With a method's statistics.
        let extra = [0.25, 3.0, 1e-9, -0.0, f64::MAX];
        let b = IterationState::encode_with("fp", 5, &f, &extra);
        let s = IterationState::decode(&b, "fp").unwrap();
        assert_eq!(s.extra, extra);
        assert_eq!(s.to_bytes(), b);
    }

    #[test]
    fn damage_is_detected() {
        let b = IterationState::encode_with("fp", 3, &film(), &[]);
        // Truncated anywhere.
        for cut in [0, 5, MAGIC.len() + 2, b.len() / 2, b.len() - 1] {
            assert!(
                IterationState::decode(&b[..cut], "fp").is_err(),
                "cut {cut}"
            );
        }
        // Any flipped byte after the magic and version.
        for at in [MAGIC.len() + 5, b.len() / 2, b.len() - 9, b.len() - 1] {
            let mut c = b.clone();
            c[at] ^= 0x10;
            assert_eq!(
                IterationState::decode(&c, "fp").unwrap_err(),
                StateError::Corrupted
            );
        }
        let mut v = b.clone();
        v[MAGIC.len()] = 9;
        assert!(matches!(
            IterationState::decode(&v, "fp"),
            Err(StateError::Version { found: 9, .. })
        ));
        assert_eq!(
            IterationState::decode(b"hello", "fp").unwrap_err(),
            StateError::NotState
        );
    }

    #[test]
    fn a_different_render_is_named() {
        let a = "caustica 0.1.0\nscene box 64x64 (3 shapes)\nintegrator pppm\noptions O { spp: 1, seed: 3, x: 1 }";
        let b = IterationState::encode_with(a, 1, &film(), &[]);
        let other_seed = a.replace("seed: 3", "seed: 4");
        match IterationState::decode(&b, &other_seed).unwrap_err() {
            StateError::Differs { what, state, now } => {
                assert_eq!(what, "options");
                assert_eq!((state.as_str(), now.as_str()), ("seed: 3", "seed: 4"));
            }
            e => panic!("{e}"),
        }
        let other_scene = a.replace("scene box", "scene ring");
        let e = IterationState::decode(&b, &other_scene).unwrap_err();
        assert!(e.to_string().contains("scene"), "{e}");
        let other_kind = a.replace("pppm", "ppds");
        let e = IterationState::decode(&b, &other_kind).unwrap_err();
        assert!(e.to_string().contains("integrator ppds"), "{e}");
    }
}

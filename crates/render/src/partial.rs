//! A shard's partial result (`--shard I/N`): its film's exact sums with a manifest saying what
//! was rendered, and the merge of parts into the film one render would give.
//!
//! Layout (little-endian), the `.cpart` file:
//!
//! ```text
//! magic "CAUSTICA-PART\n", format version (u32)
//! manifest: u64 length + UTF-8 text, lines
//!     shards <the shard indices it holds, e.g. "3" or "0..7, 9"> of N
//!     work <what this shard did, in words>
//!     scene-hash <16 hex digits: the scene's source and the options that change it>
//!     <the render's fingerprint: "caustica VERSION", "scene …", "integrator …", "options …">
//! film: window x, y, width, height, full-film width, height (u32 each), light paths (u64), then
//!     three planes (Σ L: 3 × i128 per pixel; sample counts: u32; splat sums: 3 × i128), each as
//!     its runs of rows holding a non-zero pixel: the number of runs (u32), each run's first and
//!     end row (u32, u32), then the pixels of those rows, run after run (rows outside the runs
//!     are zero: a row-split shard stores only its rows)
//! checksum: FNV-1a over the 64-bit words of everything before it (u64)
//! ```
//!
//! The sums are [`ExactSum`] integers (units of 2⁻⁶³), so merging parts in any order is exact.

use crate::driver::iteration_state::{Reader, StateError, first_difference, put_frame, read_frame};
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::shard::Shard;

const MAGIC: &[u8] = b"CAUSTICA-PART\n";
/// Bumped whenever the layout changes.
pub const PART_VERSION: u32 = 1;

/// What a part holds: which shards of which render.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Manifest {
    /// The shards the part holds, ascending: one for a shard's own part, several for a part
    /// merged from parts (`caustica merge … -o merged.cpart`, a level of a tree of merges).
    pub shards: Vec<u32>,
    /// The render's shard count N.
    pub count: u32,
    /// The shard's work in words ("light-path chunks 3..6 of 12 …").
    pub work: String,
    /// A hash of the scene's source (file bytes or built-in name) and of the options that
    /// change the scene (16 hex digits), computed by the caller.
    pub scene_hash: String,
    /// [`crate::driver::iteration_state::fingerprint`] of the render: caustica version,
    /// scene, integrator, options (without the shard).
    pub fingerprint: String,
}

impl Manifest {
    /// The manifest of `shard`'s own part.
    pub fn of_shard(shard: Shard, work: String, scene_hash: String, fingerprint: String) -> Self {
        Self {
            shards: vec![shard.index()],
            count: shard.count(),
            work,
            scene_hash,
            fingerprint,
        }
    }

    /// "3 of 8", "0..3, 5 of 8".
    pub fn shards_text(&self) -> String {
        format!("{} of {}", ranges(&self.shards), self.count)
    }

    fn to_text(&self) -> String {
        format!(
            "shards {}\nwork {}\nscene-hash {}\n{}",
            self.shards_text(),
            self.work,
            self.scene_hash,
            self.fingerprint
        )
    }

    fn parse(text: &str) -> Option<Self> {
        let mut lines = text.splitn(4, '\n');
        let (list, n) = lines.next()?.strip_prefix("shards ")?.rsplit_once(" of ")?;
        let count: u32 = n.parse().ok()?;
        let mut shards = Vec::new();
        for item in list.split(", ") {
            let (a, b) = match item.split_once("..") {
                Some((a, b)) => (a.parse::<u32>().ok()?, b.parse::<u32>().ok()?),
                None => (item.parse().ok()?, item.parse().ok()?),
            };
            if a > b || b >= count || shards.last().is_some_and(|&l| l >= a) {
                return None;
            }
            shards.extend(a..=b);
        }
        let work = lines.next()?.strip_prefix("work ")?.to_string();
        let scene_hash = lines.next()?.strip_prefix("scene-hash ")?.to_string();
        let fingerprint = lines.next()?.to_string();
        Some(Self {
            shards,
            count,
            work,
            scene_hash,
            fingerprint,
        })
    }
}

/// A shard's partial result.
#[derive(Clone, Debug)]
pub struct Part {
    pub manifest: Manifest,
    pub film: Film,
}

/// Why a part cannot be read or merged. `file` names the part (as the caller gave it).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PartError {
    #[error("{file}: not a caustica partial result (it does not start with the .cpart magic line)")]
    NotPart { file: String },
    #[error(
        "{file}: partial-result format version {found}; this caustica reads version {expected}"
    )]
    Version {
        file: String,
        found: u32,
        expected: u32,
    },
    #[error(
        "{file}: truncated or corrupted (its checksum does not match); render that shard again"
    )]
    Corrupted { file: String },
    #[error("{file} does not belong with {first}: its {what} differs ('{here}' against '{there}')")]
    Mismatch {
        file: String,
        first: String,
        what: String,
        here: String,
        there: String,
    },
    #[error("{file} and {other} both hold shard {shard}: give each shard once")]
    Duplicate {
        file: String,
        other: String,
        shard: String,
    },
    #[error(
        "shards missing: {missing} of {count} ({have} given); render them (--shard I/{count}) or merge with --partial for a preview"
    )]
    Missing {
        missing: String,
        count: u32,
        have: usize,
    },
    #[error("no partial results to merge")]
    Empty,
}

/// The FNV-1a 64 offset basis: the start of [`fnv1a`].
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// FNV-1a (64-bit) of `bytes`, continuing from `h` ([`FNV_OFFSET`] to start): the state file's
/// checksum and the scene hash of a part's manifest.
pub fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(FNV_PRIME);
    }
    h
}

/// FNV-1a over 64-bit little-endian words (the tail zero-padded), then the length: the checksum
/// of a part (a word at a time, eight times the speed of the byte-wise [`fnv1a`]).
fn checksum(bytes: &[u8]) -> u64 {
    let mut h = FNV_OFFSET;
    let mut words = bytes.chunks_exact(8);
    for w in &mut words {
        h ^= u64::from_le_bytes(w.try_into().unwrap_or_default());
        h = h.wrapping_mul(FNV_PRIME);
    }
    let mut tail = [0u8; 8];
    tail[..words.remainder().len()].copy_from_slice(words.remainder());
    h ^= u64::from_le_bytes(tail);
    h = h.wrapping_mul(FNV_PRIME);
    h ^= bytes.len() as u64;
    h.wrapping_mul(FNV_PRIME)
}

/// The runs `first..end` of rows of a plane (of `width` pixels per row) that hold a non-zero
/// pixel, in order.
fn nonzero_runs<T: PartialEq + Default>(plane: &[T], width: usize) -> Vec<(usize, usize)> {
    let rows = plane.len() / width.max(1);
    let zero = T::default();
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for y in 0..rows {
        if plane[y * width..(y + 1) * width].iter().all(|v| *v == zero) {
            continue;
        }
        match runs.last_mut() {
            Some(r) if r.1 == y => r.1 = y + 1,
            _ => runs.push((y, y + 1)),
        }
    }
    runs
}

/// Appends a plane's runs of non-zero rows: their count, each run's first and end row, then the
/// runs' pixels.
fn put_plane<T>(b: &mut Vec<u8>, plane: &[T], width: usize, put: impl Fn(&mut Vec<u8>, &T))
where
    T: PartialEq + Default,
{
    let runs = nonzero_runs(plane, width);
    b.extend_from_slice(&(runs.len() as u32).to_le_bytes());
    for &(lo, hi) in &runs {
        b.extend_from_slice(&(lo as u32).to_le_bytes());
        b.extend_from_slice(&(hi as u32).to_le_bytes());
    }
    for (lo, hi) in runs {
        for v in &plane[lo * width..hi * width] {
            put(b, v);
        }
    }
}

impl Part {
    /// The file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        Self::encode(&self.manifest, &self.film)
    }

    /// The bytes of the part `manifest` describes, holding `film` (without copying the film).
    pub fn encode(manifest: &Manifest, film: &Film) -> Vec<u8> {
        let manifest = manifest.to_text();
        let w = film.width;
        let mut b = Vec::with_capacity(128 + manifest.len() + film.sum.len() * 100);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&PART_VERSION.to_le_bytes());
        b.extend_from_slice(&(manifest.len() as u64).to_le_bytes());
        b.extend_from_slice(manifest.as_bytes());
        put_frame(&mut b, film);
        b.extend_from_slice(&film.splat_paths.to_le_bytes());
        let sums = |b: &mut Vec<u8>, px: &[ExactSum; 3]| {
            for v in px {
                b.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        };
        put_plane(&mut b, &film.sum, w, sums);
        put_plane(&mut b, &film.count, w, |b, c| {
            b.extend_from_slice(&c.to_le_bytes())
        });
        put_plane(&mut b, &film.splat, w, sums);
        let sum = checksum(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Reads a part's bytes (`file` names it in errors), checked whole: magic, version,
    /// checksum, and a layout that fits its film.
    pub fn decode(bytes: &[u8], file: &str) -> Result<Self, PartError> {
        let corrupted = || PartError::Corrupted { file: file.into() };
        if !bytes.starts_with(MAGIC) {
            return Err(PartError::NotPart { file: file.into() });
        }
        let mut r = Reader {
            b: bytes,
            at: MAGIC.len(),
        };
        let version = r.u32().map_err(|_| corrupted())?;
        if version != PART_VERSION {
            return Err(PartError::Version {
                file: file.into(),
                found: version,
                expected: PART_VERSION,
            });
        }
        if bytes.len() < MAGIC.len() + 12 {
            return Err(corrupted());
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let want = u64::from_le_bytes(tail.try_into().map_err(|_| corrupted())?);
        if checksum(body) != want {
            return Err(corrupted());
        }
        let read = |r: &mut Reader| -> Result<Self, StateError> {
            let len = r.u64()? as usize;
            let text = std::str::from_utf8(r.take(len)?).map_err(|_| StateError::Corrupted)?;
            let manifest = Manifest::parse(text).ok_or(StateError::Corrupted)?;
            let mut film = read_frame(r, body.len())?;
            film.splat_paths = r.u64()?;
            let w = film.width;
            let h = film.height;
            // A plane's runs: ascending, disjoint, inside the film.
            let runs = |r: &mut Reader| -> Result<Vec<std::ops::Range<usize>>, StateError> {
                let n = r.u32()? as usize;
                if n > h {
                    return Err(StateError::Corrupted);
                }
                let mut out = Vec::with_capacity(n);
                let mut end = 0;
                for _ in 0..n {
                    let (lo, hi) = (r.u32()? as usize, r.u32()? as usize);
                    if lo < end || lo >= hi || hi > h {
                        return Err(StateError::Corrupted);
                    }
                    end = hi;
                    out.push(lo * w..hi * w);
                }
                Ok(out)
            };
            for run in runs(r)? {
                for i in run {
                    for k in 0..3 {
                        film.sum[i][k] = ExactSum::from_bits(r.i128()?);
                    }
                }
            }
            for run in runs(r)? {
                for i in run {
                    film.count[i] = r.u32()?;
                }
            }
            for run in runs(r)? {
                for i in run {
                    for k in 0..3 {
                        film.splat[i][k] = ExactSum::from_bits(r.i128()?);
                    }
                }
            }
            Ok(Self { manifest, film })
        };
        let part = read(&mut r).map_err(|_| corrupted())?;
        if r.at != body.len() {
            return Err(corrupted());
        }
        Ok(part)
    }
}

/// Parts merged so far ([`Merge::add`]), checked to belong together.
pub struct Merge {
    /// The first part's manifest and name: what every other part must match.
    first: Option<(Manifest, String)>,
    /// For each shard index, the part that gave it.
    seen: Vec<Option<String>>,
    film: Option<Film>,
}

impl Default for Merge {
    fn default() -> Self {
        Self::new()
    }
}

impl Merge {
    pub fn new() -> Self {
        Self {
            first: None,
            seen: Vec::new(),
            film: None,
        }
    }

    /// Adds part `part` (named `file`): refused, with what differs, unless it is another shard
    /// of the same render (caustica version, scene, integrator, options and seed, shard count,
    /// film) that was not given before.
    pub fn add(&mut self, part: Part, file: &str) -> Result<(), PartError> {
        let m = &part.manifest;
        if let Some((first, name)) = &self.first {
            let differs = |what: &str, here: String, there: String| PartError::Mismatch {
                file: file.into(),
                first: name.clone(),
                what: what.into(),
                here,
                there,
            };
            let film = self.film.as_ref().ok_or(PartError::Empty)?;
            if (film.window(), film.full) != (part.film.window(), part.film.full) {
                return Err(differs(
                    "image size",
                    format!(
                        "{} of {}x{}",
                        part.film.window(),
                        part.film.full.0,
                        part.film.full.1
                    ),
                    format!("{} of {}x{}", film.window(), film.full.0, film.full.1),
                ));
            }
            if m.fingerprint != first.fingerprint {
                return Err(match first_difference(&m.fingerprint, &first.fingerprint) {
                    StateError::Differs { what, state, now } => {
                        let what = if what == "options" && state.starts_with("seed:") {
                            "seed"
                        } else {
                            what
                        };
                        differs(what, state, now)
                    }
                    _ => differs("render", m.fingerprint.clone(), first.fingerprint.clone()),
                });
            }
            if m.scene_hash != first.scene_hash {
                return Err(differs(
                    "scene (its source or the options that change it)",
                    format!("scene-hash {}", m.scene_hash),
                    format!("scene-hash {}", first.scene_hash),
                ));
            }
            if m.count != first.count {
                return Err(differs("shard count", m.shards_text(), first.shards_text()));
            }
        } else {
            self.first = Some((m.clone(), file.to_string()));
            self.seen = vec![None; m.count as usize];
        }
        for &i in &m.shards {
            if let Some(other) = &self.seen[i as usize] {
                return Err(PartError::Duplicate {
                    file: file.into(),
                    other: other.clone(),
                    shard: format!("{i}/{}", m.count),
                });
            }
        }
        for &i in &m.shards {
            self.seen[i as usize] = Some(file.to_string());
        }
        match &mut self.film {
            None => self.film = Some(part.film),
            Some(f) => f.merge(&part.film),
        }
        Ok(())
    }

    /// The shards not given yet.
    pub fn missing(&self) -> Vec<u32> {
        (0..self.seen.len() as u32)
            .filter(|&i| self.seen[i as usize].is_none())
            .collect()
    }

    /// The manifest of the first part.
    pub fn manifest(&self) -> Option<&Manifest> {
        self.first.as_ref().map(|(m, _)| m)
    }

    /// The parts merged so far as one part holding all their shards (a level of a tree of
    /// merges: merging it with the parts of the other shards gives the same film).
    pub fn finish_part(self) -> Result<Part, PartError> {
        let shards: Vec<u32> = (0..self.seen.len() as u32)
            .filter(|&i| self.seen[i as usize].is_some())
            .collect();
        let (first, _) = self.first.ok_or(PartError::Empty)?;
        let film = self.film.ok_or(PartError::Empty)?;
        Ok(Part {
            manifest: Manifest {
                work: format!("merged: shards {} of {}", ranges(&shards), first.count),
                shards,
                ..first
            },
            film,
        })
    }

    /// The merged film: refused while a shard is missing, unless `partial` (a preview of the
    /// shards given).
    pub fn finish(self, partial: bool) -> Result<Film, PartError> {
        let missing = self.missing();
        if !missing.is_empty() && !partial {
            return Err(PartError::Missing {
                missing: ranges(&missing),
                count: self.seen.len() as u32,
                have: self.seen.len() - missing.len(),
            });
        }
        self.film.ok_or(PartError::Empty)
    }
}

/// "0, 3..5, 9" for [0, 3, 4, 5, 9].
fn ranges(xs: &[u32]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < xs.len() {
        let mut j = i;
        while j + 1 < xs.len() && xs[j + 1] == xs[j] + 1 {
            j += 1;
        }
        out.push(if j > i {
            format!("{}..{}", xs[i], xs[j])
        } else {
            xs[i].to_string()
        });
        i = j + 1;
    }
    out.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    const FP: &str = "caustica 0.1.0\nscene box 8x6 (3 primitives)\nintegrator path\noptions RenderOptions { spp: 4, seed: 3, crop: None }";

    /// Shard `i` of `n` of an 8x6 film: rows of the band hold samples, every pixel a splat.
    fn part(i: u32, n: u32, fp: &str) -> Part {
        let shard = Shard::new(i, n).unwrap();
        let mut film = Film::new(8, 6);
        let band = shard.range(6);
        for y in band.start as usize..band.end as usize {
            for x in 0..8 {
                let p = y * 8 + x;
                film.sum[p] = [p as f64 * 0.1, 1.0 / 3.0, -2.0].map(ExactSum::from_f64);
                film.count[p] = 4;
            }
        }
        for (p, s) in film.splat.iter_mut().enumerate() {
            *s = [0.01 * (p as f64 + i as f64), 0.0, 1e-9].map(ExactSum::from_f64);
        }
        film.splat_paths = 1000;
        Part {
            manifest: Manifest::of_shard(
                shard,
                format!("pixel rows {}..{} of 6", band.start, band.end),
                "00000000deadbeef".into(),
                fp.into(),
            ),
            film,
        }
    }

    #[test]
    fn a_part_round_trips_and_stores_only_its_band() {
        let p = part(1, 3, FP);
        let b = p.to_bytes();
        let q = Part::decode(&b, "p1").unwrap();
        assert_eq!(q.manifest, p.manifest);
        assert_eq!(q.film.sum, p.film.sum);
        assert_eq!(q.film.count, p.film.count);
        assert_eq!(q.film.splat, p.film.splat);
        assert_eq!(q.film.splat_paths, 1000);
        assert_eq!(q.to_bytes(), b);
        // Two of six rows of samples (8 pixels × 52 bytes each) and all splats (48 × 48 bytes).
        let whole = Part {
            film: {
                let mut f = p.film.clone();
                f.sum
                    .iter_mut()
                    .for_each(|s| *s = [ExactSum::from_f64(1.0); 3]);
                f
            },
            ..p.clone()
        };
        assert_eq!(whole.to_bytes().len() - b.len(), 4 * 8 * 48);
        // Interleaved rows 1, 3, 5: three runs, each stored with its rows alone.
        let mut rows = p.clone();
        rows.film
            .sum
            .iter_mut()
            .for_each(|s| *s = [ExactSum::ZERO; 3]);
        for y in [1, 3, 5] {
            for x in 0..8 {
                rows.film.sum[y * 8 + x] = [ExactSum::from_f64(0.5); 3];
            }
        }
        let rb = rows.to_bytes();
        let back = Part::decode(&rb, "rows").unwrap();
        assert_eq!(back.film.sum, rows.film.sum);
        assert_eq!(rb.len() - b.len(), 8 * 48 + 2 * 8);
    }

    #[test]
    fn damage_is_detected_and_named() {
        let b = part(0, 2, FP).to_bytes();
        for cut in [0, 5, MAGIC.len() + 2, b.len() / 2, b.len() - 1] {
            let e = Part::decode(&b[..cut], "p0.cpart").unwrap_err();
            assert!(e.to_string().starts_with("p0.cpart"), "{e}");
        }
        for at in [
            MAGIC.len() + 6,
            b.len() / 3,
            b.len() / 2,
            b.len() - 9,
            b.len() - 1,
        ] {
            let mut c = b.clone();
            c[at] ^= 0x04;
            assert_eq!(
                Part::decode(&c, "p0.cpart").unwrap_err(),
                PartError::Corrupted {
                    file: "p0.cpart".into()
                },
                "byte {at}"
            );
        }
        let mut v = b.clone();
        v[MAGIC.len()] = 7;
        assert!(matches!(
            Part::decode(&v, "x"),
            Err(PartError::Version { found: 7, .. })
        ));
        assert!(matches!(
            Part::decode(b"CAUSTICA-STATE\nxxxx", "x"),
            Err(PartError::NotPart { .. })
        ));
    }

    #[test]
    fn merging_is_exact_in_any_order() {
        let n = 3;
        let mut forward = Merge::new();
        for i in 0..n {
            forward.add(part(i, n, FP), &format!("p{i}")).unwrap();
        }
        let mut backward = Merge::new();
        for i in (0..n).rev() {
            backward.add(part(i, n, FP), &format!("p{i}")).unwrap();
        }
        let (a, b) = (
            forward.finish(false).unwrap(),
            backward.finish(false).unwrap(),
        );
        assert_eq!(a.sum, b.sum);
        assert_eq!(a.splat, b.splat);
        assert_eq!(a.splat_paths, 3000);
        assert!(a.count.iter().all(|&c| c == 4));
        assert_eq!(a.to_image().data, b.to_image().data);
    }

    #[test]
    fn merged_parts_merge_again_to_the_same_film() {
        let n = 7;
        let one = |shards: &[u32]| {
            let mut m = Merge::new();
            for &i in shards {
                m.add(part(i, n, FP), &format!("p{i}")).unwrap();
            }
            m
        };
        let flat = one(&(0..n).collect::<Vec<_>>()).finish(false).unwrap();
        // Two levels: {0, 1, 2} and {4, 6} merged into parts (through their bytes), then with
        // 3 and 5.
        let a = one(&[2, 0, 1]).finish_part().unwrap();
        let b = one(&[6, 4]).finish_part().unwrap();
        assert_eq!(a.manifest.shards, vec![0, 1, 2]);
        assert_eq!(b.manifest.shards_text(), "4, 6 of 7");
        let a = Part::decode(&a.to_bytes(), "a").unwrap();
        let b = Part::decode(&b.to_bytes(), "b").unwrap();
        assert_eq!(a.manifest.shards_text(), "0..2 of 7");
        let mut top = Merge::new();
        top.add(part(5, n, FP), "p5").unwrap();
        top.add(b, "b").unwrap();
        top.add(part(3, n, FP), "p3").unwrap();
        top.add(a.clone(), "a").unwrap();
        let tree = top.finish(false).unwrap();
        assert_eq!(tree.sum, flat.sum);
        assert_eq!(tree.splat, flat.splat);
        assert_eq!(tree.count, flat.count);
        assert_eq!(tree.splat_paths, flat.splat_paths);
        // A merged part overlapping a shard given again is refused.
        let mut m = Merge::new();
        m.add(a, "a").unwrap();
        let e = m.add(part(1, n, FP), "p1").unwrap_err().to_string();
        assert!(e.contains("p1 and a both hold shard 1/7"), "{e}");
    }

    #[test]
    fn parts_that_do_not_belong_together_are_refused_with_the_reason() {
        let add_after_first = |other: Part| {
            let mut m = Merge::new();
            m.add(part(0, 2, FP), "a.cpart").unwrap();
            m.add(other, "b.cpart").unwrap_err().to_string()
        };
        let e = add_after_first(part(1, 2, &FP.replace("seed: 3", "seed: 4")));
        assert!(
            e.contains("b.cpart") && e.contains("a.cpart") && e.contains("its seed differs"),
            "{e}"
        );
        let e = add_after_first(part(1, 2, &FP.replace("spp: 4", "spp: 8")));
        assert!(e.contains("options differs") && e.contains("spp: 8"), "{e}");
        let e = add_after_first(part(1, 2, &FP.replace("0.1.0", "0.2.0")));
        assert!(e.contains("caustica version"), "{e}");
        let e = add_after_first(part(1, 2, &FP.replace("scene box", "scene ring")));
        assert!(e.contains("its scene differs"), "{e}");
        let mut other_source = part(1, 2, FP);
        other_source.manifest.scene_hash = "0123456789abcdef".into();
        assert!(add_after_first(other_source).contains("scene-hash"));
        assert!(add_after_first(part(1, 3, FP)).contains("shard count"));
        let mut bigger = part(1, 2, FP);
        bigger.film = Film::new(8, 7);
        assert!(add_after_first(bigger).contains("image size"));
        let e = add_after_first(part(0, 2, FP));
        assert!(e.contains("both hold shard 0/2"), "{e}");
        // Missing shards: named, unless a partial merge is asked for.
        let mut m = Merge::new();
        for i in [0, 2, 5] {
            m.add(part(i, 7, FP), &format!("p{i}")).unwrap();
        }
        assert_eq!(m.missing(), vec![1, 3, 4, 6]);
        let mut p = Merge::new();
        p.add(part(0, 7, FP), "p0").unwrap();
        assert!(p.finish(true).is_ok());
        let e = m.finish(false).unwrap_err().to_string();
        assert!(e.contains("1, 3..4, 6 of 7 (3 given)"), "{e}");
        assert_eq!(Merge::new().finish(true).unwrap_err(), PartError::Empty);
    }
}

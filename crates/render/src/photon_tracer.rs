//! The photon tracer shared by every photon method.
//!
//! Photons are energy packets (seed 001 ch. 2): a light path emitted with throughput β (W, see
//! [`crate::light_path`]) deposits at each non-delta surface it reaches a photon of flux
//! Φ = β / N, where N is the number of paths emitted for that map. The sum of the fluxes of the
//! photons in a surface region estimates the flux incident on it, so a density estimate of Φ
//! per area gives irradiance (W/m²), and Σ f_r Φ / area reflected radiance (W/m²/sr), eq. 3.1–3.2
//! of seed 000.
//!
//! Paths are numbered; fixed chunks of consecutive paths are traced in parallel and their photons
//! concatenated in chunk order, so the maps depend on the seed only, not on the thread count.

use crate::light_path::{LightEvent, LightScatter, LightVisitor, walk_light_path_with};
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec3};
use caustica_scene::Scene;
use rayon::prelude::*;

/// A stored photon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    /// Hit point (m).
    pub p: Vec3,
    /// Unit direction toward where the photon came from (away from the surface, pbrt's ωi).
    pub wi: Vec3,
    /// Geometric normal at the hit, on the side the photon arrived from (unit).
    pub n: Vec3,
    /// Flux (W): path throughput divided by the number of emitted paths.
    pub flux: Spectrum,
    /// Edges from the light (1 = direct illumination).
    pub depth: u16,
    /// True for caustic photons: every earlier scattering vertex was delta, L S+ D.
    pub caustic: bool,
}

/// Which photons a tracing pass keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// Paths L S+ D only.
    Caustic,
    /// Every non-delta hit, L (S|D)* D.
    Global,
}

/// Paths per parallel chunk.
const CHUNK: u64 = 1 << 12;
/// Give up (with a warning) after this many paths per requested photon.
const MAX_PATHS_PER_PHOTON: u64 = 1 << 12;
/// Give up (with a warning) when this many paths have stored no photon at all: the scene has no
/// lit diffuse surface (or, for the caustic map, no specular path to one). A caustic yield below
/// 1 in 2²⁰ paths would need ~10¹¹ paths for a usable map anyway.
const MAX_PATHS_WITHOUT_PHOTON: u64 = 1 << 20;

/// Photons of one map and how they were made.
pub struct TracedPhotons {
    /// Photons in path order, fluxes already divided by `paths`.
    pub photons: Vec<Photon>,
    /// Light paths emitted (the N of Φ = β/N).
    pub paths: u64,
    pub stats: RenderStats,
    /// Set when fewer photons than requested were found (no caustic paths, no diffuse surfaces).
    pub warning: Option<String>,
}

/// Emits light paths until `target` photons of `kind` are stored and returns them, cut at the
/// path where the count reaches `target` (so every emitted path contributes all of its photons
/// and N counts exactly those paths). `stream` separates the random numbers of different maps
/// with the same seed. Deterministic for a given seed whatever the thread count: paths are traced
/// in fixed chunks, in waves whose sizes depend only on photon counts.
pub fn trace_photons(
    scene: &Scene,
    target: usize,
    kind: MapKind,
    stream: u64,
    opts: &RenderOptions,
) -> TracedPhotons {
    let (mut photons, paths, stats) =
        trace_paths(target, stream, opts, &mut |_| {}, |_, sampler, out, st| {
            trace_one(scene, sampler, opts, kind, out, st)
        });
    let inv_n = 1.0 / paths.max(1) as f32;
    for p in &mut photons {
        p.flux *= inv_n;
    }
    let warning = (photons.len() < target).then(|| {
        format!(
            "only {} {} photons stored after {} light paths (requested {target}){}",
            photons.len(),
            match kind {
                MapKind::Caustic => "caustic",
                MapKind::Global => "global",
            },
            paths,
            if photons.is_empty() {
                match kind {
                    MapKind::Caustic => {
                        ": no light reaches a diffuse surface through glass or mirrors"
                    }
                    MapKind::Global => ": the scene has no non-specular surface lit by its lights",
                }
            } else {
                ""
            }
        )
    });
    TracedPhotons {
        photons,
        paths,
        stats,
        warning,
    }
}

/// The chunked, deterministic path loop behind [`trace_photons`] (and the photon-differential
/// tracer): emits numbered light paths (path `i` seeds the sampler with `(stream, i)`) in fixed
/// chunks of [`CHUNK`], `trace_one(path, sampler, records, stats)` storing each path's records,
/// until `target` records exist (`on_wave(found)` after each wave of chunks);
/// cut at the path where the count reaches `target`. Returns the records in path order (not
/// divided by the path count), the number of paths and the statistics.
pub(crate) fn trace_paths<P: Clone + Send>(
    target: usize,
    stream: u64,
    opts: &RenderOptions,
    on_wave: &mut dyn FnMut(usize),
    trace_one: impl Fn(u64, &mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync,
) -> (Vec<P>, u64, RenderStats) {
    // Reserved up front: growing by doubling touches twice the memory (page faults were ~5 %
    // of a photon-differential pass).
    let mut photons: Vec<P> = Vec::with_capacity(target);
    let mut stats = RenderStats::default();
    let mut emitted = 0u64;
    // Where to cut: (paths, photons) at the first path whose photons reach the target. Only the
    // wave that crosses the target needs per-path counts, so earlier waves' counts are dropped
    // (10⁶ caustic photons can take 2·10⁸ paths).
    let mut cut: Option<(u64, usize)> = None;
    let limit = (target as u64)
        .saturating_mul(MAX_PATHS_PER_PHOTON)
        .max(CHUNK);
    while cut.is_none()
        && emitted < limit
        && !(photons.is_empty() && emitted >= MAX_PATHS_WITHOUT_PHOTON)
    {
        // Size the next wave from the yield so far (deterministic: counts only).
        let wave = if photons.is_empty() {
            16 * CHUNK
        } else {
            let per_path = photons.len() as f64 / emitted as f64;
            (((target - photons.len()) as f64 / per_path * 1.05) as u64).clamp(CHUNK, 256 * CHUNK)
        };
        let chunks = wave.div_ceil(CHUNK);
        let first_chunk = emitted / CHUNK;
        // Per chunk: its photons, the photon count after each of its paths, its statistics.
        let parts: Vec<(Vec<P>, Vec<u32>, RenderStats)> = (first_chunk..first_chunk + chunks)
            .into_par_iter()
            .map(|c| {
                let mut out = Vec::new();
                let mut counts = Vec::with_capacity(CHUNK as usize);
                let mut st = RenderStats::default();
                let mut sampler = Sampler::new(opts.sampler, opts.seed);
                for path in c * CHUNK..(c + 1) * CHUNK {
                    sampler.start_path(stream, path);
                    trace_one(path, &mut sampler, &mut out, &mut st);
                    counts.push(out.len() as u32);
                }
                st.samples += CHUNK;
                (out, counts, st)
            })
            .collect();
        for (c, (p, counts, st)) in parts.into_iter().enumerate() {
            stats += st;
            if cut.is_some() {
                continue; // paths beyond the cut are not part of the map
            }
            let base = photons.len();
            if base + p.len() >= target {
                let i = counts
                    .iter()
                    .position(|&n| base + n as usize >= target)
                    .expect("the chunk reaches the target");
                let chunk_start = emitted + c as u64 * CHUNK;
                cut = Some((chunk_start + i as u64 + 1, base + counts[i] as usize));
            }
            photons.extend_from_slice(&p);
        }
        emitted += chunks * CHUNK;
        on_wave(photons.len().min(target));
    }
    let (paths, keep) = cut.unwrap_or((emitted, photons.len()));
    photons.truncate(keep);
    (photons, paths, stats)
}

/// Stores the photons of one light path: at every non-delta vertex (global map) or at those
/// reached through delta vertices only (caustic map). A caustic map's path ends at its first
/// non-delta bounce, after which no vertex can receive caustic light (L S+ D): the same photons,
/// fewer rays.
fn trace_one(
    scene: &Scene,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    kind: MapKind,
    out: &mut Vec<Photon>,
    stats: &mut RenderStats,
) {
    struct Store<'a> {
        kind: MapKind,
        out: &'a mut Vec<Photon>,
    }
    impl LightVisitor for Store<'_> {
        fn event(&mut self, event: LightEvent, _: &mut Sampler, stats: &mut RenderStats) {
            let LightEvent::Vertex(lv) = event else {
                return;
            };
            if !lv.v.bsdf.flags().is_smooth() {
                return;
            }
            if self.kind == MapKind::Caustic && !lv.after_specular_chain {
                return;
            }
            let flux = lv.beta;
            if !flux.is_finite() {
                stats.nonfinite += 1;
                return;
            }
            let ng = lv.v.si.ng;
            self.out.push(Photon {
                p: lv.v.si.p,
                wi: lv.wo,
                n: if ng.dot(lv.wo) >= 0.0 { ng } else { -ng },
                flux,
                depth: lv.depth.min(u16::MAX as u32) as u16,
                caustic: lv.after_specular_chain,
            });
        }
        fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
            self.kind == MapKind::Global || sc.sample.flags.is_delta()
        }
    }
    walk_light_path_with(scene, sampler, opts, stats, &mut Store { kind, out });
}

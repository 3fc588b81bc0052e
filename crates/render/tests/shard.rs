//! Exact shards (`--shard I/N`, issue 24): for the path tracer, the light tracer, pm, pds, pppm
//! and ppds (and dpm, pdm, pcf), the films of shards 0..N, written as partial results, read
//! back and merged in a shuffled order, are the unsharded render's film bit for bit, for
//! N = 1, 2, 3 and 7; one shard of each run renders on a single thread.

mod common;

use caustica_render::partial::{Manifest, Merge, Part};
use caustica_render::{Film, IntegratorKind, RenderControl, RenderOptions, Shard, render};
use caustica_scene::Scene;

fn film(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> Film {
    render(scene, kind, opts, &RenderControl::silent())
        .expect("valid options")
        .film
}

/// A partial result of `film` as shard `shard` (the same manifest for every part).
fn part(film: Film, shard: Shard) -> Part {
    Part {
        manifest: Manifest::of_shard(
            shard,
            String::new(),
            "0".repeat(16),
            "caustica test\nscene s\nintegrator k\noptions o".into(),
        ),
        film,
    }
}

/// A fixed shuffle of 0..n (a stride coprime with n, from the middle).
fn shuffled(n: u32) -> Vec<u32> {
    let stride = (1..=n)
        .rev()
        .find(|s| gcd(*s, n) == 1 && *s < n)
        .unwrap_or(1);
    (0..n).map(|k| (n / 2 + k * stride) % n).collect()
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// Asserts that the shards of `opts` merge into the unsharded film, for 1, 2, 3 and 7 shards.
fn shards_merge_exactly(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) {
    let whole = film(scene, kind, opts);
    // Exact sums, written as a part: the strongest comparison (every accumulator's bits).
    let whole_bytes = part(whole.clone(), Shard::new(0, 1).unwrap()).to_bytes();
    let whole_image = whole.to_image();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for n in [1u32, 2, 3, 7] {
        let mut merge = Merge::new();
        for (k, i) in shuffled(n).into_iter().enumerate() {
            let shard = Shard::new(i, n).unwrap();
            let o = RenderOptions {
                shard: Some(shard),
                ..opts.clone()
            };
            let f = if k == 0 {
                one_thread.install(|| film(scene, kind, &o))
            } else {
                film(scene, kind, &o)
            };
            let bytes = part(f, shard).to_bytes();
            let read = Part::decode(&bytes, "part").unwrap();
            merge.add(read, &format!("shard {i}")).unwrap();
        }
        let merged = merge.finish(false).unwrap();
        let image = merged.to_image();
        let same_pixels = image
            .data
            .iter()
            .zip(&whole_image.data)
            .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits));
        assert!(
            same_pixels,
            "{}: {n} shards merge into another image",
            kind.name()
        );
        assert_eq!(
            part(merged, Shard::new(0, 1).unwrap()).to_bytes(),
            whole_bytes,
            "{}: {n} shards merge into other sums",
            kind.name()
        );
    }
}

fn scene() -> Scene {
    common::small_builtin("caustic-box", 32, 24)
}

fn photons(caustic: usize, global: usize) -> RenderOptions {
    let mut o = RenderOptions {
        spp: 2,
        ..Default::default()
    };
    o.photons.caustic_photons = caustic;
    o.photons.global_photons = global;
    o.photons.final_gather = 4;
    o
}

#[test]
fn path_tracer_shards_by_rows() {
    let opts = RenderOptions {
        spp: 3,
        ..Default::default()
    };
    shards_merge_exactly(&scene(), IntegratorKind::Path, &opts);
}

#[test]
fn light_tracer_shards_by_light_path_chunks() {
    // 32 × 24 × 180 = 138 240 light paths: 9 chunks of 16 384, so 7 shards all splat.
    let opts = RenderOptions {
        spp: 180,
        ..Default::default()
    };
    shards_merge_exactly(&scene(), IntegratorKind::LightTrace, &opts);
}

#[test]
fn photon_mapping_shards_by_rows() {
    shards_merge_exactly(
        &scene(),
        IntegratorKind::PhotonMapping,
        &photons(3000, 2000),
    );
}

#[test]
fn diffusion_and_differential_mapping_shard_by_rows() {
    let opts = photons(2000, 1000);
    shards_merge_exactly(&scene(), IntegratorKind::DiffusionPhotonMapping, &opts);
    shards_merge_exactly(&scene(), IntegratorKind::PhotonDifferentialMapping, &opts);
}

#[test]
fn splatting_shards_by_splat_chunks() {
    // A light-path budget: 40 000 paths, 10 chunks of 4 096 for the splatting pass.
    let mut opts = photons(1000, 1000);
    opts.photons.light_paths = Some(40_000);
    shards_merge_exactly(&scene(), IntegratorKind::PhotonDifferentialSplatting, &opts);
    // A photon count: the counted paths (those that landed, listed) in chunks.
    shards_merge_exactly(
        &scene(),
        IntegratorKind::PhotonDifferentialSplatting,
        &photons(12_000, 1000),
    );
}

#[test]
fn progressive_methods_shard_by_iterations() {
    let mut opts = RenderOptions {
        spp: 1,
        ..Default::default()
    };
    opts.photons.progressive.iterations = Some(7);
    opts.photons.progressive.paths_per_iteration = 3000;
    shards_merge_exactly(&scene(), IntegratorKind::ProgressivePhotonMapping, &opts);
    shards_merge_exactly(&scene(), IntegratorKind::ProgressiveSplatting, &opts);
}

#[test]
fn photon_cone_focusing_shards_by_iterations() {
    let mut opts = RenderOptions {
        spp: 1,
        ..Default::default()
    };
    opts.photons.progressive.iterations = Some(3);
    opts.photons.progressive.paths_per_iteration = 2000;
    shards_merge_exactly(&scene(), IntegratorKind::PhotonConeFocusing, &opts);
}

#[test]
fn shuffles_are_permutations() {
    for n in [1, 2, 3, 7, 12] {
        let mut s = shuffled(n);
        s.sort_unstable();
        assert_eq!(s, (0..n).collect::<Vec<_>>());
    }
    assert_ne!(shuffled(7), (0..7).collect::<Vec<_>>());
}

#[test]
fn sppm_and_ppm_refuse_shards_and_time_budgets_too() {
    let mut opts = RenderOptions {
        shard: Some(Shard::new(0, 2).unwrap()),
        ..Default::default()
    };
    for kind in [
        IntegratorKind::StochasticProgressivePhotonMapping,
        IntegratorKind::ProgressivePhotonMappingHitPoints,
    ] {
        let e = render(&scene(), kind, &opts, &RenderControl::silent())
            .err()
            .expect("refused")
            .to_string();
        assert!(e.contains("cannot be sharded") && e.contains("pppm"), "{e}");
    }
    opts.time_limit = Some(std::time::Duration::from_secs(1));
    let e = render(
        &scene(),
        IntegratorKind::Path,
        &opts,
        &RenderControl::silent(),
    )
    .err()
    .expect("refused")
    .to_string();
    assert!(e.contains("time budget"), "{e}");
}

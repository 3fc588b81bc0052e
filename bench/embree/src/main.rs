//! caustica's BVH against Embree 3 (issue 26): build times and single-thread traversal
//! throughput on the workload of `crates/scene/benches/bvh.rs` — the same generators, through
//! the shared `workload` module — plus a diffuse-bounce ray set, and a check that both find the
//! same hits.
//!
//! `cargo run --release -- [--reps N] [--build-reps N] [--out FILE | --no-write] [--robust]`
//! (or `bench/embree_vs_caustica.sh`). Prints one Markdown report and writes it to
//! `docs/results/embree/latest.md` unless told otherwise.

mod embree;
mod ffi;
#[path = "../../../crates/scene/benches/workload/mod.rs"]
mod workload;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

use caustica_core::Ray;
use caustica_scene::bvh::BvhWidth;
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Shape, ShapeGeometry, TriangleMesh};

use embree::{Coherence, Device, Quality, Scene};
use workload::{
    BOUNCE_SEED, INCOHERENT_SEED, SHADOW_SEED, camera_rays, diffuse_bounce_rays, displaced_sphere,
    incoherent_rays, shadow_rays,
};

/// Camera resolution (coherent set) and sizes of the random sets: those of `benches/bvh.rs`.
const CAMERA: (u32, u32) = (512, 512);
const N_RANDOM: usize = 200_000;
const N_SHADOW: usize = 200_000;
/// Pixel tile of one coherent 8-ray packet.
const TILE: (u32, u32) = (4, 2);
/// Rays per `rtcIntersect1M` / `rtcOccluded1M` call.
const STREAM: usize = 256;
/// Agreement: hit distances within this relative difference, on at least this share of rays.
const REL_TOL: f32 = 1e-4;
const AGREE_MIN: f64 = 0.999;
/// Lane marker of an empty packet slot.
const EMPTY: u32 = u32::MAX;

struct Args {
    reps: usize,
    build_reps: usize,
    out: Option<PathBuf>,
    robust: bool,
    /// `displaced_sphere`'s tessellation (`--mesh NPHI,NTHETA`; 1024,512 by default).
    mesh: (u32, u32),
}

const USAGE: &str = "usage: caustica-embree-bench [REPS] [--reps N] [--build-reps N] \
                     [--out FILE | --no-write] [--robust] [--mesh NPHI,NTHETA]";

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        reps: 9,
        build_reps: 3,
        out: Some(
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/results/embree/latest.md"),
        ),
        robust: false,
        mesh: (1024, 512),
    };
    let mut it = std::env::args().skip(1);
    let num = |v: Option<String>, what: &str| -> Result<usize, String> {
        v.and_then(|s| s.parse().ok())
            .filter(|&n: &usize| n > 0)
            .ok_or(format!("{what} needs a positive integer"))
    };
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--reps" => a.reps = num(it.next(), "--reps")?,
            "--build-reps" => a.build_reps = num(it.next(), "--build-reps")?,
            "--out" => a.out = Some(it.next().ok_or("--out needs a file")?.into()),
            "--no-write" => a.out = None,
            "--robust" => a.robust = true,
            "--mesh" => {
                let v = it.next().unwrap_or_default();
                a.mesh = v
                    .split_once(',')
                    .and_then(|(p, t)| Some((p.trim().parse().ok()?, t.trim().parse().ok()?)))
                    .filter(|&(p, t): &(u32, u32)| p >= 3 && t >= 2)
                    .ok_or(format!(
                        "--mesh needs NPHI,NTHETA (integers, NPHI ≥ 3, NTHETA ≥ 2), got {v:?}"
                    ))?;
            }
            "-h" | "--help" => return Err(USAGE.into()),
            s if s.parse::<usize>().is_ok() => a.reps = num(Some(arg), "REPS")?,
            s => return Err(format!("unknown argument {s}\n{USAGE}")),
        }
    }
    Ok(a)
}

/// One ray set, with its packet grouping.
struct RaySet {
    name: &'static str,
    rays: Vec<Ray>,
    shadow: bool,
    coherence: Coherence,
    /// 8-ray packets as ray indices ([`EMPTY`] lanes unused): 4×2 pixel tiles for the camera
    /// rays, consecutive rays otherwise.
    packets: Vec<[u32; 8]>,
    /// The packets' rays in packet order: the order of the streams.
    order: Vec<u32>,
}

impl RaySet {
    fn new(name: &'static str, rays: Vec<Ray>, shadow: bool, camera: Option<(u32, u32)>) -> Self {
        let packets: Vec<[u32; 8]> = match camera {
            Some((w, h)) => {
                assert!(w % TILE.0 == 0 && h % TILE.1 == 0);
                let mut p = Vec::new();
                for ty in 0..h / TILE.1 {
                    for tx in 0..w / TILE.0 {
                        p.push(std::array::from_fn(|l| {
                            let (x, y) = (l as u32 % TILE.0, l as u32 / TILE.0);
                            (ty * TILE.1 + y) * w + tx * TILE.0 + x
                        }));
                    }
                }
                p
            }
            None => (0..rays.len().div_ceil(8))
                .map(|k| {
                    std::array::from_fn(|l| {
                        let i = 8 * k + l;
                        if i < rays.len() { i as u32 } else { EMPTY }
                    })
                })
                .collect(),
        };
        let order: Vec<u32> = packets
            .iter()
            .flatten()
            .copied()
            .filter(|&i| i != EMPTY)
            .collect();
        assert_eq!(order.len(), rays.len());
        Self {
            name,
            rays,
            shadow,
            coherence: if camera.is_some() {
                Coherence::Coherent
            } else {
                Coherence::Incoherent
            },
            packets,
            order,
        }
    }

    fn lanes(&self, p: &[u32; 8]) -> [Option<&Ray>; 8] {
        p.map(|i| (i != EMPTY).then(|| &self.rays[i as usize]))
    }
}

/// Rows of the traversal table.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Row {
    /// `Geometry::intersect` (full `SurfaceInteraction`); shadow rays: `Geometry::occluded`.
    Caustica,
    /// `Geometry::hit_distance` (t only; no shadow variant).
    CausticaT,
    /// `Geometry::intersect_stream` / `occluded_stream`: eight rays at a time through the
    /// 8-wide BVH, fed in packet order. Where a set has no such query its cells print n/a.
    CausticaPackets,
    /// `Geometry::hit_distance_stream`: as `CausticaPackets`, t only (no shadow variant).
    CausticaPacketsT,
    Embree1,
    Embree8,
    Embree1M,
}

const ROWS: [Row; 7] = [
    Row::Caustica,
    Row::CausticaT,
    Row::CausticaPackets,
    Row::CausticaPacketsT,
    Row::Embree1,
    Row::Embree8,
    Row::Embree1M,
];

impl Row {
    fn label(self) -> &'static str {
        match self {
            Row::Caustica => {
                "caustica `Geometry::intersect` → SurfaceInteraction (shadow: `occluded`), single rays"
            }
            Row::CausticaT => "caustica `Geometry::hit_distance` (t only), single rays",
            Row::CausticaPackets => {
                "caustica `Geometry::intersect_stream` / `occluded_stream`, 8 rays at a time"
            }
            Row::CausticaPacketsT => {
                "caustica `Geometry::hit_distance_stream` (t only), 8 rays at a time"
            }
            Row::Embree1 => "Embree `rtcIntersect1` / `rtcOccluded1`, single rays",
            Row::Embree8 => "Embree `rtcIntersect8` / `rtcOccluded8`, 8-ray packets",
            Row::Embree1M => "Embree `rtcIntersect1M` / `rtcOccluded1M`, streams of 256",
        }
    }
}

/// A query over a whole ray set: writes one result per ray (closest: `Some(t)` or `None`;
/// shadow: `Some(0.0)` if occluded, `None` if not), indexed like the set's rays.
type Query<'a> = Box<dyn FnMut(&mut [Option<f32>]) + 'a>;

/// A caustica stream query over `set`'s rays in packet order: `run(rays, results)` traces them,
/// `result` reads each ray's entry of the query's output ([`Query`]'s), written back in ray order.
fn in_packet_order<'a, T: 'a>(
    set: &'a RaySet,
    run: impl Fn(&[Ray], &mut Vec<T>) + 'a,
    result: impl Fn(&T) -> Option<f32> + 'a,
) -> Query<'a> {
    let rays: Vec<Ray> = set.order.iter().map(|&i| set.rays[i as usize]).collect();
    let mut res = Vec::new();
    Box::new(move |out| {
        run(&rays, &mut res);
        for (&i, r) in set.order.iter().zip(&res) {
            out[i as usize] = result(r);
        }
    })
}

/// The query of `row` on `set`, or `None` where the row has no such query.
fn query<'a>(row: Row, set: &'a RaySet, geo: &'a Geometry, scene: &'a Scene) -> Option<Query<'a>> {
    let coh = set.coherence;
    Some(match (row, set.shadow) {
        // black_box: the whole record must be computed, not only the t the check reads.
        (Row::Caustica, false) => Box::new(move |out| {
            for (o, r) in out.iter_mut().zip(&set.rays) {
                *o = black_box(geo.intersect(r)).map(|s| s.t);
            }
        }),
        (Row::Caustica, true) => Box::new(move |out| {
            for (o, r) in out.iter_mut().zip(&set.rays) {
                *o = geo.occluded(r).then_some(0.0);
            }
        }),
        (Row::CausticaT, false) => Box::new(move |out| {
            for (o, r) in out.iter_mut().zip(&set.rays) {
                *o = geo.hit_distance(r);
            }
        }),
        (Row::CausticaT, true) => return None,
        // caustica's packet queries, beside Embree's packets: the rays in packet order
        // (`set.order`: 4×2 pixel tiles for the camera rays, consecutive rays otherwise), so
        // each chunk of eight the stream takes is one of Embree's packets. Reordering is set-up
        // (a renderer generates its rays in tile order); results go back to ray order. A new
        // caustica packet or stream query gets a `Row` and an arm here, and its cells, ratios
        // and agreement check fill in by themselves.
        (Row::CausticaPackets, false) => in_packet_order(
            set,
            move |rays, res| geo.intersect_stream(rays, res),
            |h| h.as_ref().map(|s| s.t),
        ),
        (Row::CausticaPacketsT, false) => in_packet_order(
            set,
            move |rays, res| geo.hit_distance_stream(rays, res),
            |&t| t,
        ),
        (Row::CausticaPacketsT, true) => return None,
        (Row::CausticaPackets, true) => in_packet_order(
            set,
            move |rays, res| geo.occluded_stream(rays, res),
            |&occ| occ.then_some(0.0),
        ),
        (Row::Embree1, false) => Box::new(move |out| {
            for (o, r) in out.iter_mut().zip(&set.rays) {
                *o = scene.intersect1(coh, r);
            }
        }),
        (Row::Embree1, true) => Box::new(move |out| {
            for (o, r) in out.iter_mut().zip(&set.rays) {
                *o = scene.occluded1(coh, r).then_some(0.0);
            }
        }),
        (Row::Embree8, false) => Box::new(move |out| {
            for p in &set.packets {
                let t = scene.intersect8(coh, set.lanes(p));
                for (l, &i) in p.iter().enumerate() {
                    if i != EMPTY {
                        out[i as usize] = t[l];
                    }
                }
            }
        }),
        (Row::Embree8, true) => Box::new(move |out| {
            for p in &set.packets {
                let occ = scene.occluded8(coh, set.lanes(p));
                for (l, &i) in p.iter().enumerate() {
                    if i != EMPTY {
                        out[i as usize] = occ[l].then_some(0.0);
                    }
                }
            }
        }),
        (Row::Embree1M, false) => {
            let (mut refs, mut buf, mut res) = (Vec::new(), Vec::new(), vec![None; STREAM]);
            Box::new(move |out| {
                for chunk in set.order.chunks(STREAM) {
                    refs.clear();
                    refs.extend(chunk.iter().map(|&i| &set.rays[i as usize]));
                    let res = &mut res[..chunk.len()];
                    scene.intersect1m(coh, &refs, &mut buf, res);
                    for (&i, &t) in chunk.iter().zip(res.iter()) {
                        out[i as usize] = t;
                    }
                }
            })
        }
        (Row::Embree1M, true) => {
            let (mut refs, mut buf, mut res) = (Vec::new(), Vec::new(), vec![false; STREAM]);
            Box::new(move |out| {
                for chunk in set.order.chunks(STREAM) {
                    refs.clear();
                    refs.extend(chunk.iter().map(|&i| &set.rays[i as usize]));
                    let res = &mut res[..chunk.len()];
                    scene.occluded1m(coh, &refs, &mut buf, res);
                    for (&i, &occ) in chunk.iter().zip(res.iter()) {
                        out[i as usize] = occ.then_some(0.0);
                    }
                }
            })
        }
    })
}

/// A timed query: its repetitions' seconds and its last output.
struct Job<'a> {
    row: Row,
    set: usize,
    f: Query<'a>,
    out: Vec<Option<f32>>,
    secs: Vec<f64>,
}

/// Runs every job once untimed (warm-up), then `reps` times, interleaved (rep by rep) so that
/// a slow spell of the shared machine spreads over all of them.
fn run_jobs(jobs: &mut [Job], reps: usize) {
    for rep in 0..=reps {
        for j in jobs.iter_mut() {
            let t0 = Instant::now();
            (j.f)(&mut j.out);
            let dt = t0.elapsed().as_secs_f64();
            if rep > 0 {
                j.secs.push(dt);
            }
        }
        eprint!("\r  repetition {rep}/{reps}");
    }
    eprintln!();
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// CPU time (ns) of every thread of this process, by thread id, from
/// `/proc/self/task/*/schedstat` (its first field: time spent on a CPU).
fn thread_cpu_ns() -> HashMap<u64, u64> {
    let mut m = HashMap::new();
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return m;
    };
    for e in dir.flatten() {
        let Some(tid) = e.file_name().to_str().and_then(|s| s.parse().ok()) else {
            continue;
        };
        let ns = std::fs::read_to_string(e.path().join("schedstat"))
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse().ok());
        if let Some(ns) = ns {
            m.insert(tid, ns);
        }
    }
    m
}

/// Threads of this process.
fn process_threads() -> usize {
    std::fs::read_dir("/proc/self/task").map_or(0, |d| d.count())
}

/// A thread counts as having worked on a build if it ran for at least this share of the
/// build's CPU time.
const BUSY_SHARE: f64 = 0.05;

/// Wall and CPU seconds of repeated builds.
struct BuildStat {
    label: String,
    wall: Vec<f64>,
    cpu: Vec<f64>,
    /// Threads that ran for at least [`BUSY_SHARE`] of each build's CPU time.
    busy: Vec<usize>,
    /// Process threads after the builds.
    threads_after: usize,
}

impl BuildStat {
    /// Times `build(setup())` `reps` times (`setup` untimed), dropping each result before the
    /// next build; returns the last result.
    fn measure<S, T>(
        label: String,
        reps: usize,
        mut setup: impl FnMut() -> S,
        mut build: impl FnMut(S) -> T,
    ) -> (Self, T) {
        let (mut wall, mut cpu, mut busy, mut last) = (Vec::new(), Vec::new(), Vec::new(), None);
        for _ in 0..reps {
            drop(last.take());
            let input = setup();
            let (c0, t0) = (thread_cpu_ns(), Instant::now());
            let b = build(input);
            wall.push(t0.elapsed().as_secs_f64());
            let c1 = thread_cpu_ns();
            let deltas: Vec<f64> = c1
                .iter()
                .map(|(tid, &ns)| {
                    ns.saturating_sub(c0.get(tid).copied().unwrap_or(0)) as f64 * 1e-9
                })
                .collect();
            let total: f64 = deltas.iter().sum();
            cpu.push(total);
            busy.push(deltas.iter().filter(|&&d| d >= BUSY_SHARE * total).count());
            last = Some(b);
        }
        let s = Self {
            label,
            wall,
            cpu,
            busy,
            threads_after: process_threads(),
        };
        eprintln!(
            "  {}: {:.3} s (CPU/wall {:.2}, threads busy {:?})",
            s.label,
            median(&s.wall),
            s.cpu_per_wall(),
            s.busy
        );
        (s, last.expect("reps > 0"))
    }

    fn cpu_per_wall(&self) -> f64 {
        let r: Vec<f64> = self
            .cpu
            .iter()
            .zip(&self.wall)
            .map(|(c, w)| c / w)
            .collect();
        median(&r)
    }

    /// The most threads seen busy in one repetition.
    fn max_busy(&self) -> usize {
        self.busy.iter().copied().max().unwrap_or(0)
    }
}

fn agree(a: Option<f32>, b: Option<f32>, shadow: bool) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => shadow || (a - b).abs() <= REL_TOL * a.abs().max(b.abs()),
        (None, None) => true,
        _ => false,
    }
}

/// UTC date `YYYY-MM-DD` of the system clock (Hinnant's civil-from-days).
fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("model name"))
                .map(|v| v.trim_start_matches([' ', '\t', ':']).to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let scene_flags = if args.robust {
        ffi::RTC_SCENE_FLAG_ROBUST
    } else {
        ffi::RTC_SCENE_FLAG_NONE
    };
    let nproc = std::thread::available_parallelism().map_or(1, |n| n.get());

    let (nphi, ntheta) = args.mesh;
    eprintln!("workload: displaced_sphere({nphi}, {ntheta})");
    let mesh = displaced_sphere(nphi, ntheta);
    let n_tris = mesh.indices.len();
    let shapes = vec![Shape::new(ShapeGeometry::Mesh(mesh.clone()), 0)];

    eprintln!("builds ({} repetitions each):", args.build_reps);
    let mut builds = Vec::new();
    let threads0 = process_threads();
    let (b, geo) = BuildStat::measure(
        "caustica `Geometry::build` (obvhs PLOC single-threaded; rayon for the per-primitive passes)"
            .into(),
        args.build_reps,
        || shapes.clone(),
        Geometry::build,
    );
    builds.push(b);
    let threads_after_caustica = process_threads();

    // Embree's thread count is process-wide under TBB: Embree takes the largest request of
    // all live devices (0 = all cores). So the single-threaded device builds first, and is
    // released before the default device exists.
    fn embree_build<'d>(device: &'d Device, m: &TriangleMesh, q: Quality, f: u32) -> Scene<'d> {
        Scene::build(device, &m.positions, &m.indices, q, f)
            .unwrap_or_else(|e| panic!("Embree build failed: {e}"))
    }
    {
        let dev1 = Device::new(Some("threads=1")).expect("Embree device");
        for q in [Quality::High, Quality::Medium] {
            let (b, scene) = BuildStat::measure(
                format!("Embree {} (device config \"threads=1\")", q.name()),
                args.build_reps,
                || (),
                |()| embree_build(&dev1, &mesh, q, scene_flags),
            );
            drop(scene);
            builds.push(b);
        }
    }
    let device = Device::new(None).expect("Embree device");
    let props = [
        ("version", ffi::RTC_DEVICE_PROPERTY_VERSION),
        (
            "tasking system (0 internal, 1 TBB, 2 PPL)",
            ffi::RTC_DEVICE_PROPERTY_TASKING_SYSTEM,
        ),
        (
            "native 4-ray packets",
            ffi::RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED,
        ),
        (
            "native 8-ray packets",
            ffi::RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED,
        ),
        (
            "native 16-ray packets",
            ffi::RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED,
        ),
        ("ray streams", ffi::RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED),
        (
            "backface culling",
            ffi::RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED,
        ),
    ]
    .map(|(name, p)| (name, device.property(p)));
    let mut scenes = Vec::new();
    for q in [Quality::High, Quality::Medium] {
        let (b, scene) = BuildStat::measure(
            format!("Embree {} (default device config)", q.name()),
            args.build_reps,
            || (),
            |()| embree_build(&device, &mesh, q, scene_flags),
        );
        builds.push(b);
        scenes.push((q, scene));
    }

    eprintln!("ray sets");
    let bounds = geo.bounds();
    let primary = camera_rays(CAMERA.0, CAMERA.1);
    let bounce = diffuse_bounce_rays(&geo, &primary, BOUNCE_SEED);
    let sets = [
        RaySet::new("coherent primary", primary, false, Some(CAMERA)),
        RaySet::new("diffuse bounce", bounce, false, None),
        RaySet::new(
            "random incoherent",
            incoherent_rays(N_RANDOM, &bounds, INCOHERENT_SEED),
            false,
            None,
        ),
        RaySet::new(
            "shadow",
            shadow_rays(N_SHADOW, &bounds, SHADOW_SEED),
            true,
            None,
        ),
    ];

    // Which Embree build traces faster: rtcIntersect1 / rtcOccluded1 on every set.
    eprintln!("Embree build quality for tracing (rtcIntersect1 / rtcOccluded1):");
    let sel_reps = args.reps.div_ceil(3).max(1);
    let mut sel_jobs: Vec<Job> = Vec::new();
    for (qi, (_, scene)) in scenes.iter().enumerate() {
        for (si, set) in sets.iter().enumerate() {
            sel_jobs.push(Job {
                row: Row::Embree1,
                set: qi * sets.len() + si,
                f: query(Row::Embree1, set, &geo, scene).expect("rtcIntersect1 query"),
                out: vec![None; set.rays.len()],
                secs: Vec::new(),
            });
        }
    }
    run_jobs(&mut sel_jobs, sel_reps);
    let sel_time = |qi: usize| -> f64 {
        sel_jobs
            .iter()
            .filter(|j| j.set / sets.len() == qi)
            .map(|j| median(&j.secs))
            .sum()
    };
    let chosen = if sel_time(0) <= sel_time(1) { 0 } else { 1 };
    let (quality, scene) = (scenes[chosen].0, &scenes[chosen].1);
    eprintln!("  tracing with {}", quality.name());

    eprintln!("traversal ({} repetitions, single thread):", args.reps);
    let mut jobs: Vec<Job> = Vec::new();
    for row in ROWS {
        for (si, set) in sets.iter().enumerate() {
            if let Some(f) = query(row, set, &geo, scene) {
                jobs.push(Job {
                    row,
                    set: si,
                    f,
                    out: vec![None; set.rays.len()],
                    secs: Vec::new(),
                });
            }
        }
    }
    run_jobs(&mut jobs, args.reps);
    let find = |row: Row, si: usize| jobs.iter().find(|j| j.row == row && j.set == si);
    let mrays = |row: Row, si: usize| {
        find(row, si).map(|j| sets[si].rays.len() as f64 / median(&j.secs) / 1e6)
    };

    // ---- the report ----
    let mut md = String::new();
    let w = &mut md;
    let cmd: Vec<String> = std::env::args().collect();
    let _ = writeln!(
        w,
        "# caustica BVH vs Embree 3: displaced sphere ({nphi}, {ntheta}), {n_tris} triangles\n"
    );
    let _ = writeln!(
        w,
        "{} · `{}` · {} · nproc {nproc} · Embree {} ({}) · scene flags {} · \
         traversal: one thread, median of {} repetitions (interleaved) · builds: median of {}\n",
        today(),
        cmd.join(" "),
        cpu_model(),
        {
            let v = props[0].1;
            format!("{}.{}.{}", v / 10_000, v / 100 % 100, v % 100)
        },
        match props[1].1 {
            0 => "internal tasking",
            1 => "TBB",
            2 => "PPL",
            _ => "unknown tasking",
        },
        if args.robust { "ROBUST" } else { "NONE" },
        args.reps,
        args.build_reps,
    );
    let _ = writeln!(
        w,
        "caustica BVH: {}-wide nodes (`BvhWidth::detect`; `CAUSTICA_BVH_WIDTH=4` forces four), \
         {} nodes, {} leaf packets, {:.1} MB.\n",
        match geo.bvh.width() {
            BvhWidth::Four => 4,
            BvhWidth::Eight => 8,
        },
        geo.bvh.node_count(),
        geo.bvh.packet_count(),
        geo.bvh.memory_bytes() as f64 / 1e6,
    );
    let _ = writeln!(
        w,
        "## Traversal, Mrays/s (Embree scene: {} quality, the faster to trace)\n",
        quality.name()
    );
    let head: Vec<String> = sets
        .iter()
        .map(|s| format!("{} ({} rays)", s.name, s.rays.len()))
        .collect();
    let _ = writeln!(w, "| query | {} |", head.join(" | "));
    let _ = writeln!(w, "|---|{}", "---:|".repeat(sets.len()));
    for row in ROWS {
        let cells: Vec<String> = (0..sets.len())
            .map(|si| match (mrays(row, si), row) {
                (Some(m), _) => format!("{m:.2}"),
                (None, Row::CausticaPackets | Row::CausticaPacketsT) => "n/a".into(),
                (None, _) => "—".into(),
            })
            .collect();
        let _ = writeln!(w, "| {} | {} |", row.label(), cells.join(" | "));
    }
    let spread = jobs
        .iter()
        .map(|j| {
            let m = median(&j.secs);
            let (lo, hi) = j
                .secs
                .iter()
                .fold((f64::MAX, 0.0f64), |(lo, hi), &s| (lo.min(s), hi.max(s)));
            (hi - lo) / m
        })
        .fold(0.0f64, f64::max);
    let _ = writeln!(
        w,
        "\nLargest spread (max − min) / median of any cell: {:.0} %. Camera rays: caustica and \
         single Embree rays in row-major order, packets from 4×2 pixel tiles and streams in \
         tile order, context flag COHERENT; other sets: consecutive rays, flag INCOHERENT.\n",
        100.0 * spread
    );

    let _ = writeln!(w, "## Ratios caustica / Embree (> 1: caustica faster)\n");
    let _ = writeln!(w, "| ratio | {} |", head.join(" | "));
    let _ = writeln!(w, "|---|{}", "---:|".repeat(sets.len()));
    for (c, cname) in [
        (Row::Caustica, "`intersect` (shadow: `occluded`)"),
        (Row::CausticaT, "`hit_distance`"),
        (
            Row::CausticaPackets,
            "`intersect_stream` (`occluded_stream`)",
        ),
        (Row::CausticaPacketsT, "`hit_distance_stream`"),
    ] {
        for (e, ename) in [
            (Row::Embree1, "Embree single"),
            (Row::Embree8, "Embree packets of 8"),
            (Row::Embree1M, "Embree streams"),
        ] {
            let cells: Vec<String> = (0..sets.len())
                .map(|si| match (mrays(c, si), mrays(e, si)) {
                    (Some(a), Some(b)) => format!("{:.2}", a / b),
                    _ => "—".into(),
                })
                .collect();
            let _ = writeln!(w, "| caustica {cname} / {ename} | {} |", cells.join(" | "));
        }
    }

    let _ = writeln!(w, "\n## Builds (same mesh)\n");
    let _ = writeln!(
        w,
        "| builder | wall s (median) | CPU s (median) | CPU s / wall s | threads busy | \
         process threads after |"
    );
    let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|");
    for b in &builds {
        let _ = writeln!(
            w,
            "| {} | {:.3} | {:.3} | {:.2} | {} | {} |",
            b.label,
            median(&b.wall),
            median(&b.cpu),
            b.cpu_per_wall(),
            b.max_busy(),
            b.threads_after
        );
    }
    let _ = writeln!(
        w,
        "\nCPU time: the sum over the process's threads of their on-CPU time \
         (/proc/self/task/*/schedstat) during the build; *threads busy*: threads that ran for \
         ≥ {:.0} % of that time in some repetition. CPU s / wall s below the busy thread count \
         means the shared machine did not give the build all its cores (at ≈ 1 with two busy \
         threads, the build ran on the equivalent of one core, and only the CPU seconds \
         compare). Process threads: \
         {threads0} before any build, {threads_after_caustica} after caustica's (rayon's pool); \
         Embree's TBB workers appear with the default device. Embree's times include filling \
         its vertex and index buffers. Embree's default device config uses TBB with every core \
         ({nproc} here); \"threads=1\" builds on the calling thread alone.\n",
        100.0 * BUSY_SHARE
    );

    let _ = writeln!(
        w,
        "### Embree build quality: rtcIntersect1 / rtcOccluded1 Mrays/s (median of {sel_reps})\n"
    );
    let _ = writeln!(w, "| quality | {} | total s |", head.join(" | "));
    let _ = writeln!(w, "|---|{}---:|", "---:|".repeat(sets.len()));
    for (qi, (q, _)) in scenes.iter().enumerate() {
        let cells: Vec<String> = (0..sets.len())
            .map(|si| {
                let j = &sel_jobs[qi * sets.len() + si];
                format!("{:.2}", sets[si].rays.len() as f64 / median(&j.secs) / 1e6)
            })
            .collect();
        let mark = if qi == chosen { " (used)" } else { "" };
        let _ = writeln!(
            w,
            "| {}{mark} | {} | {:.3} |",
            q.name(),
            cells.join(" | "),
            sel_time(qi)
        );
    }

    let _ = writeln!(
        w,
        "\n## Agreement with caustica's `Geometry::intersect` / `occluded`\n\n\
         Same hit/miss (shadow: same occlusion) and, for hits, |t − t'| ≤ {REL_TOL:e}·max(t, t'). \
         Required: ≥ {:.1} % of every set.\n",
        100.0 * AGREE_MIN
    );
    let _ = writeln!(
        w,
        "| ray set | rays | caustica hits | `hit_distance` = `intersect`.t | \
         `intersect_stream` = `intersect` | `hit_distance_stream` = `intersect`.t | Embree hits | \
         agree rtcIntersect1 | agree rtcIntersect8 | agree rtcIntersect1M | hit/miss differ¹ | t differs¹ | max rel. t diff.¹ | ≥ {:.1} % |",
        100.0 * AGREE_MIN
    );
    let _ = writeln!(
        w,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let mut all_ok = true;
    let mut disagreements = Vec::new();
    for (si, set) in sets.iter().enumerate() {
        let n = set.rays.len();
        let c = &find(Row::Caustica, si).expect("caustica job").out;
        let hits = |o: &[Option<f32>]| o.iter().filter(|x| x.is_some()).count();
        let count = |row: Row| {
            find(row, si).map(|j| {
                c.iter()
                    .zip(&j.out)
                    .filter(|(a, b)| agree(**a, **b, set.shadow))
                    .count()
            })
        };
        let same = |row: Row| {
            find(row, si).map_or("—".into(), |j| {
                let k = c.iter().zip(&j.out).filter(|(a, b)| a == b).count();
                format!("{k}")
            })
        };
        let (same_t, same_stream, same_stream_t) = (
            same(Row::CausticaT),
            same(Row::CausticaPackets),
            same(Row::CausticaPacketsT),
        );
        let e1 = &find(Row::Embree1, si).expect("Embree job").out;
        let hm = c
            .iter()
            .zip(e1)
            .filter(|(a, b)| a.is_some() != b.is_some())
            .count();
        let td = c
            .iter()
            .zip(e1)
            .filter(|(a, b)| a.is_some() && b.is_some() && !agree(**a, **b, set.shadow))
            .count();
        let max_rel = c
            .iter()
            .zip(e1)
            .filter_map(|(a, b)| match (a, b) {
                (Some(a), Some(b)) if !set.shadow => Some((a - b).abs() / a.abs().max(b.abs())),
                _ => None,
            })
            .fold(0.0f32, f32::max);
        for (i, (a, b)) in c.iter().zip(e1).enumerate() {
            if !agree(*a, *b, set.shadow) && disagreements.len() < 8 {
                let r = &set.rays[i];
                disagreements.push(format!(
                    "- {} ray {i}: o = {:?}, d = {:?}; caustica {a:?}, Embree {b:?}",
                    set.name,
                    r.o.to_array(),
                    r.d.to_array()
                ));
            }
        }
        let counts: Vec<usize> = [Row::Embree1, Row::Embree8, Row::Embree1M]
            .iter()
            .map(|&r| count(r).expect("Embree job"))
            .collect();
        let ok = counts.iter().all(|&k| k as f64 >= AGREE_MIN * n as f64);
        all_ok &= ok;
        let pct = |k: usize| format!("{k} ({:.3} %)", 100.0 * k as f64 / n as f64);
        let _ = writeln!(
            w,
            "| {} | {n} | {} | {same_t} | {same_stream} | {same_stream_t} | {} | {} | {} | {} | {hm} | {td} | {} | {} |",
            set.name,
            hits(c),
            hits(e1),
            pct(counts[0]),
            pct(counts[1]),
            pct(counts[2]),
            if set.shadow {
                "—".to_string()
            } else {
                format!("{max_rel:.1e}")
            },
            if ok { "yes" } else { "**no**" },
        );
    }
    let _ = writeln!(
        w,
        "\n¹ against rtcIntersect1 / rtcOccluded1. Embree hits: rtcIntersect1's.\n"
    );
    if !disagreements.is_empty() {
        let _ = writeln!(
            w,
            "Disagreements with rtcIntersect1 (first {}):\n\n{}\n",
            disagreements.len(),
            disagreements.join("\n")
        );
    }
    let _ = writeln!(w, "Embree device properties:");
    for (name, v) in &props {
        let _ = writeln!(w, "- {name}: {v}");
    }

    print!("{md}");
    if let Some(path) = &args.out {
        if let Some(dir) = path.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        match std::fs::write(path, &md) {
            Ok(()) => eprintln!("wrote {}", path.display()),
            Err(e) => eprintln!("could not write {}: {e}", path.display()),
        }
    }
    if !all_ok {
        eprintln!("agreement below {:.1} % on some ray set", 100.0 * AGREE_MIN);
        std::process::exit(1);
    }
}

//! The live preview of a render: `--preview [PORT]` (a page on 127.0.0.1 showing the image
//! converging, [`server`]) and `--tev HOST:PORT` (the image streamed to a running tev,
//! [`tev`]).
//!
//! Both read one [`Hub`]: the render thread *publishes* into it (progress at every report, the
//! image at each preview snapshot: the film handed to `RenderControl::on_checkpoint`, whose
//! interval the CLI lowers to `--preview-interval`), and the server's and tev's threads *read*
//! it. Publishing only swaps an `Arc` under a mutex held for a few field copies, and wakes the
//! readers; the render thread never waits for a client, and nothing a client does reaches the
//! film, so the rendered image is byte-identical with and without a preview (docs/preview.md).

pub mod server;
pub mod tev;

use caustica_core::image_io::Image;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// The state a render publishes and the preview's readers see.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// Increases with each published image (0: none yet).
    pub version: u64,
    /// The latest image (linear radiance, as the film's `to_image`).
    pub image: Option<Arc<Image>>,
    /// The name of the image being rendered (its output file; tev's image name).
    pub name: String,
    /// The name of the render `image` is of (`name` when it was published).
    pub image_name: String,
    /// What is being rendered in a sequence ("frame 3 (2/5)"), else empty.
    pub label: String,
    /// The current pass ("camera pass", "tracing photons", …).
    pub pass: String,
    /// Fraction of the current pass done, and of the whole render (the progress bar's).
    pub pass_fraction: f64,
    pub fraction: f64,
    /// The time left as the progress bar says it (`eta.rs`), empty while unknown.
    pub eta: String,
    /// Samples (or light paths) per second in the current pass, with their unit.
    pub rate: Option<(f64, &'static str)>,
    /// Seconds since the preview started.
    pub elapsed: f64,
    /// The one-line summaries of the renders done (one per frame of a sequence).
    pub summaries: Vec<String>,
    /// The render has ended (successfully, interrupted or failed).
    pub done: bool,
    /// Why the render failed, if it did.
    pub error: Option<String>,
}

/// Where a pass's rate is measured since: the pass and its first report.
#[derive(Debug)]
struct PassClock {
    pass: &'static str,
    start: Instant,
    samples: u64,
}

#[derive(Debug)]
struct State {
    snap: Snapshot,
    pass_clock: Option<PassClock>,
}

/// The snapshots of one render (or one `--frames` sequence), shared by the render thread and
/// the preview's threads.
#[derive(Debug)]
pub struct Hub {
    state: Mutex<State>,
    changed: Condvar,
    started: Instant,
}

impl Default for Hub {
    fn default() -> Self {
        Self::new()
    }
}

impl Hub {
    pub fn new() -> Self {
        Self {
            state: Mutex::new(State {
                snap: Snapshot::default(),
                pass_clock: None,
            }),
            changed: Condvar::new(),
            started: Instant::now(),
        }
    }

    /// The state, even if a thread panicked while holding it (the data is plain values).
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A copy of the current state.
    pub fn snapshot(&self) -> Snapshot {
        let mut s = self.lock().snap.clone();
        s.elapsed = self.started.elapsed().as_secs_f64();
        s
    }

    /// Waits until the image version exceeds `after` or the render has ended, at most
    /// `timeout`; returns the state then (also on timeout).
    pub fn wait(&self, after: u64, timeout: Duration) -> Snapshot {
        let guard = self.lock();
        let (guard, _) = self
            .changed
            .wait_timeout_while(guard, timeout, |s| s.snap.version <= after && !s.snap.done)
            .unwrap_or_else(|e| e.into_inner());
        let mut s = guard.snap.clone();
        drop(guard);
        s.elapsed = self.started.elapsed().as_secs_f64();
        s
    }

    /// A new render starts (the next frame of a sequence): its output's name and label.
    pub fn start_render(&self, name: &str, label: &str) {
        let mut st = self.lock();
        st.snap.name = name.to_string();
        st.snap.label = label.trim().to_string();
        st.snap.pass.clear();
        st.snap.eta.clear();
        st.snap.rate = None;
        st.pass_clock = None;
    }

    /// A progress report, called from the render's worker threads (a few field copies): the
    /// pass, its fraction done and the render's, the time left as the bar shows it, and the
    /// samples (or light paths) the pass has done so far, for its rate.
    pub fn progress(
        &self,
        pass: &'static str,
        pass_fraction: f64,
        fraction: f64,
        eta: &str,
        samples: u64,
    ) {
        let now = Instant::now();
        let mut st = self.lock();
        // A pass starts at its first report (or when its count starts again: the passes of the
        // progressive methods' iterations repeat).
        let restart = match &st.pass_clock {
            Some(c) => c.pass != pass || samples < c.samples,
            None => true,
        };
        if restart {
            st.pass_clock = Some(PassClock {
                pass,
                start: now,
                samples,
            });
        }
        let rate = match (&st.pass_clock, rate_unit(pass)) {
            (Some(c), Some(unit)) if samples > c.samples => {
                let t = now.duration_since(c.start).as_secs_f64();
                (t >= 0.2).then(|| ((samples - c.samples) as f64 / t, unit))
            }
            _ => None,
        };
        let snap = &mut st.snap;
        if snap.pass != pass {
            snap.pass = pass.to_string();
        }
        snap.pass_fraction = pass_fraction;
        snap.fraction = fraction;
        if snap.eta != eta {
            snap.eta = eta.to_string();
        }
        if rate.is_some() || restart {
            snap.rate = rate;
        }
    }

    /// A new image (the film so far): readers waiting for a newer version wake up.
    pub fn publish(&self, image: Image) {
        let image = Arc::new(image);
        let mut st = self.lock();
        st.snap.version += 1;
        st.snap.image_name = st.snap.name.clone();
        // The old image is dropped after the lock is released (readers may still hold it).
        let old = st.snap.image.replace(image);
        drop(st);
        drop(old);
        self.changed.notify_all();
    }

    /// A render of the sequence has ended with this summary line; `complete` unless it was
    /// interrupted (a time budget ends a little early: the last report may say 99 %).
    pub fn summary(&self, line: &str, complete: bool) {
        let mut st = self.lock();
        st.snap.summaries.push(line.to_string());
        if complete {
            st.snap.fraction = 1.0;
            st.snap.pass_fraction = 1.0;
        }
        st.snap.eta.clear();
        drop(st);
        self.changed.notify_all();
    }

    /// The whole render (or sequence) has ended, with `error` if it failed.
    pub fn finish(&self, error: Option<String>) {
        let mut st = self.lock();
        st.snap.done = true;
        st.snap.error = error;
        drop(st);
        self.changed.notify_all();
    }
}

/// The live preview of one `caustica render`: the hub, the server (`--preview`) and the tev
/// stream (`--tev`), started before the render and ended after it.
pub struct Live {
    pub hub: Arc<Hub>,
    /// How often the render hands the preview its film (`--preview-interval`).
    pub interval: Duration,
    served: Option<Arc<server::Served>>,
    tev: Option<std::thread::JoinHandle<()>>,
    /// No snapshot before this instant (see [`Live::snapshot_due`]).
    next_snapshot: Mutex<Instant>,
}

/// The share of the render's time that snapshots may take, at most: after a snapshot that took
/// `d` (converting the film to an image, between passes, while the workers wait), the next one
/// comes no sooner than `d / SNAPSHOT_SHARE` later. At 256² a conversion takes ~3.5 ms, so the
/// interval decides; at 1 megapixel ~55 ms, so snapshots come every ~5.5 s at most.
pub const SNAPSHOT_SHARE: f64 = 0.01;

/// How long, at most, the process waits after the render for a watching page to fetch the
/// final image.
const LINGER: Duration = Duration::from_secs(3);

impl Live {
    /// Binds the preview's port and connects to tev, before any work: a port in use or a tev
    /// that does not answer is an error. `None` when neither is asked for.
    pub fn start(
        port: Option<u16>,
        tev: Option<&str>,
        interval: Duration,
    ) -> anyhow::Result<Option<Live>> {
        if port.is_none() && tev.is_none() {
            return Ok(None);
        }
        let server = port.map(server::Server::bind).transpose()?;
        let tev = tev.map(tev::Tev::connect).transpose()?;
        let hub = Arc::new(Hub::new());
        let served = match server {
            Some(s) => {
                let port = s.port();
                let served = s.spawn(hub.clone())?;
                eprintln!("preview: http://127.0.0.1:{port}/");
                Some(served)
            }
            None => None,
        };
        let tev = tev.map(|t| t.spawn(hub.clone())).transpose()?;
        Ok(Some(Live {
            hub,
            interval,
            served,
            tev,
            next_snapshot: Mutex::new(Instant::now()),
        }))
    }

    /// Whether a snapshot may be taken now: the last one's cost is at most [`SNAPSHOT_SHARE`]
    /// of the time since it.
    pub fn snapshot_due(&self) -> bool {
        self.next_snapshot
            .lock()
            .map_or(true, |t| Instant::now() >= *t)
    }

    /// A snapshot was taken; it cost `cost`.
    pub fn snapshot_taken(&self, cost: Duration) {
        if let Ok(mut t) = self.next_snapshot.lock() {
            *t = Instant::now() + cost.div_f64(SNAPSHOT_SHARE);
        }
    }

    /// The render (or sequence) has ended, with `error` if it failed: the page says so and may
    /// fetch the final image (for up to [`LINGER`] if a page is watching), tev gets the final
    /// image.
    pub fn end(self, error: Option<String>) {
        let last = self.hub.snapshot().version;
        self.hub.finish(error);
        if let Some(served) = &self.served {
            server::linger(served, last, LINGER);
        }
        if let Some(t) = self.tev {
            // The thread ends once the final image is sent (or tev is gone).
            let _ = t.join();
        }
    }
}

/// What a pass's sample count counts, when it is samples or light paths.
fn rate_unit(pass: &str) -> Option<&'static str> {
    match pass {
        "camera pass" | "path tracing" => Some("samples/s"),
        "tracing photons" | "tracing global photons" | "tracing light paths" | "photons" => {
            Some("light paths/s")
        }
        _ => None,
    }
}

/// `s` as a JSON string literal.
pub(crate) fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A finite number as JSON (non-finite numbers, which JSON lacks, as null).
fn json_number(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "null".to_string()
    }
}

impl Snapshot {
    /// The status the page polls (`/status`, `/wait`): everything but the image.
    pub fn to_json(&self) -> String {
        let (w, h) = self.image.as_ref().map_or((0, 0), |i| (i.width, i.height));
        let rate = match self.rate {
            Some((r, unit)) => format!(
                "{{\"per_second\":{},\"unit\":{}}}",
                json_number(r),
                json_string(unit)
            ),
            None => "null".to_string(),
        };
        let summaries: Vec<String> = self.summaries.iter().map(|s| json_string(s)).collect();
        format!(
            "{{\"version\":{},\"width\":{w},\"height\":{h},\"name\":{},\"label\":{},\"pass\":{},\"pass_percent\":{},\"percent\":{},\"eta\":{},\"rate\":{rate},\"elapsed\":{},\"summaries\":[{}],\"done\":{},\"error\":{}}}",
            self.version,
            json_string(&self.name),
            json_string(&self.label),
            json_string(&self.pass),
            json_number((100.0 * self.pass_fraction * 10.0).round() / 10.0),
            json_number((100.0 * self.fraction * 10.0).round() / 10.0),
            json_string(&self.eta),
            json_number((self.elapsed * 1000.0).round() / 1000.0),
            summaries.join(","),
            self.done,
            self.error
                .as_deref()
                .map_or("null".to_string(), json_string),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_escapes_quotes_and_controls() {
        assert_eq!(json_string("a\"b\\c\nd\u{1}"), "\"a\\\"b\\\\c\\nd\\u0001\"");
    }

    #[test]
    fn wait_returns_at_a_new_version_or_the_end_and_times_out_otherwise() {
        let hub = Arc::new(Hub::new());
        let t = Instant::now();
        let s = hub.wait(0, Duration::from_millis(50));
        assert_eq!(s.version, 0);
        assert!(t.elapsed() >= Duration::from_millis(50));
        let h = hub.clone();
        let waiter = std::thread::spawn(move || h.wait(0, Duration::from_secs(10)).version);
        std::thread::sleep(Duration::from_millis(20));
        hub.publish(Image::new(2, 1));
        assert_eq!(waiter.join().ok(), Some(1));
        hub.finish(None);
        let t = Instant::now();
        assert!(hub.wait(1, Duration::from_secs(10)).done);
        assert!(t.elapsed() < Duration::from_secs(5));
    }

    #[test]
    fn status_json_has_the_progress_and_the_summaries() {
        let hub = Hub::new();
        hub.start_render("out.exr", "frame 1 (1/2) ");
        hub.progress("camera pass", 0.5, 0.25, "ETA 3s", 10);
        hub.publish(Image::new(4, 3));
        assert!(hub.snapshot().to_json().contains("\"eta\":\"ETA 3s\""));
        hub.summary("scene: path 4x3 -> \"out.exr\"", false);
        let j = hub.snapshot().to_json();
        for part in [
            "\"version\":1",
            "\"width\":4,\"height\":3",
            "\"label\":\"frame 1 (1/2)\"",
            "\"pass\":\"camera pass\"",
            "\"pass_percent\":50",
            "\"percent\":25",
            "\"eta\":\"\"",
            "\"summaries\":[\"scene: path 4x3 -> \\\"out.exr\\\"\"]",
            "\"done\":false",
        ] {
            assert!(j.contains(part), "{part} not in {j}");
        }
    }
}

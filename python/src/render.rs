//! `caustica.render`: the command line's render, with the GIL released and Ctrl-C honoured.

use crate::errors::to_py;
use crate::options;
use crate::scene::PyScene;
use caustica_cli::render_cmd::{Resolution, ShutterOverride, load_at};
use caustica_render::{IntegratorKind, RenderControl, RenderOutput, render};
use caustica_scene::Scene;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread takes the GIL to look for a pending KeyboardInterrupt.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// Renders `scene` with the options `kwargs` (see [`options`]) on `threads` worker threads
/// (`None`: the global pool, one per core) and, with `crop` (`"X,Y,W,H"`), only that window.
/// Returns the image as little-endian f32 RGB radiance (W/m²/sr), row-major from the top row,
/// its width and height, and the render's notes.
#[pyfunction]
#[pyo3(signature = (scene, kwargs, threads=None, crop=None))]
pub fn render_image<'py>(
    py: Python<'py>,
    scene: &PyScene,
    kwargs: Vec<(String, Bound<'py, PyAny>)>,
    threads: Option<usize>,
    crop: Option<String>,
) -> PyResult<(Bound<'py, PyByteArray>, usize, usize, Bound<'py, PyDict>)> {
    let args = options::arguments(&kwargs)?;
    let settings = options::settings(scene.source.as_deref(), &args)?;
    let pool = match threads {
        Some(0) => return Err(PyValueError::new_err("--threads must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyValueError::new_err(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    // Settings that change the scene itself load it again, as the command line would.
    let overrides = settings.width.is_some()
        || settings.height.is_some()
        || settings.frame.is_some()
        || settings.shutter.is_some()
        || settings.spectral;
    let loaded: Arc<Scene> = if overrides {
        // (`-D` is not a keyword of render(): the scene keeps the definitions it was loaded with.)
        let defines = &scene.defines;
        let mut s = py
            .detach(|| {
                load_at(
                    scene.source.as_deref(),
                    defines,
                    Resolution {
                        width: settings.width,
                        height: settings.height,
                    },
                    ShutterOverride {
                        frame: settings.frame,
                        length: settings.shutter,
                    },
                )
            })
            .map_err(to_py)?;
        s.set_spectral(settings.spectral)
            .map_err(|e| PyValueError::new_err(format!("--spectral: {e}")))?;
        Arc::new(s)
    } else {
        scene.scene.clone()
    };
    let resolved = settings.resolve(&loaded).map_err(to_py)?;
    let kind = resolved.kind;
    let mut opts = resolved.opts;
    let cam = &loaded.camera;
    opts.crop = crop
        .as_deref()
        .map(|c| caustica_render::CropWindow::parse(c, cam.width, cam.height))
        .transpose()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;

    // The render runs on its own thread without the GIL; this thread waits for it, taking the
    // GIL briefly every SIGNAL_POLL to let Python run its signal handlers. A KeyboardInterrupt
    // sets the stop flag: the render ends after its current pass, and the exception is raised.
    let stop = AtomicBool::new(false);
    let mut interrupt: Option<PyErr> = None;
    let output = std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        let (loaded, opts, stop) = (&loaded, &opts, &stop);
        let pool = pool.as_ref();
        s.spawn(move || {
            let ctl = RenderControl {
                stop,
                ..RenderControl::silent()
            };
            let run = || render(loaded, kind, opts, &ctl);
            let out = match pool {
                Some(p) => p.install(run),
                None => run(),
            };
            // The receiver waits until this message (it never hangs up first).
            let _ = tx.send(out);
        });
        let mut rx = rx;
        loop {
            // The receiver is moved in and back: it may be sent between threads, not shared.
            let (back, got) = py.detach(move || {
                let got = rx.recv_timeout(SIGNAL_POLL);
                (rx, got)
            });
            rx = back;
            match got {
                Ok(out) => return Some(out),
                Err(mpsc::RecvTimeoutError::Disconnected) => return None,
                Err(mpsc::RecvTimeoutError::Timeout) => {}
            }
            if interrupt.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::SeqCst);
                interrupt = Some(e);
            }
        }
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    // (A panicking render thread would re-panic at the scope's end, before this.)
    let output = output
        .ok_or_else(|| PyRuntimeError::new_err("the render thread ended without a result"))?
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let notes = notes(py, &loaded, kind, &opts, &resolved.warnings, &output)?;
    let img = output.film.to_image();
    let bytes = crate::images::bytes(&img);
    Ok((PyByteArray::new(py, &bytes), img.width, img.height, notes))
}

/// The render's notes: what the command line prints before and in its summary line.
fn notes<'py>(
    py: Python<'py>,
    scene: &Scene,
    kind: IntegratorKind,
    opts: &caustica_render::RenderOptions,
    warnings: &[String],
    out: &RenderOutput,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let secs = out.elapsed.as_secs_f64();
    d.set_item("scene", &scene.name)?;
    d.set_item("integrator", kind.name())?;
    d.set_item("spectral", scene.spectral)?;
    d.set_item("width", out.film.width)?;
    d.set_item("height", out.film.height)?;
    d.set_item("seed", opts.seed)?;
    d.set_item("seconds", secs)?;
    match kind {
        IntegratorKind::LightTrace => d.set_item("light_paths", out.film.light_paths())?,
        IntegratorKind::Hybrid => {
            d.set_item("light_paths", out.film.light_paths())?;
            d.set_item("spp", out.film.mean_samples())?;
        }
        _ => d.set_item("spp", out.film.mean_samples())?,
    }
    d.set_item("iterations", out.iterations)?;
    d.set_item("samples", out.stats.samples)?;
    d.set_item("rays", out.stats.rays)?;
    d.set_item(
        "samples_per_second",
        out.stats.samples as f64 / secs.max(1e-9),
    )?;
    d.set_item("rays_per_second", out.stats.rays as f64 / secs.max(1e-9))?;
    d.set_item("nonfinite", out.stats.nonfinite)?;
    d.set_item("notes", out.notes.clone())?;
    let mut all: Vec<String> = scene.warnings.clone();
    all.extend(warnings.iter().cloned());
    d.set_item("warnings", all)?;
    Ok(d)
}

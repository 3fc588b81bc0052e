//! The live preview end to end: `render --preview` seen by headless Chromium (the page shows
//! the image converging and the progress), the image unchanged by a preview, a port in use
//! refused before any work, and `--tev` against a fake tev that parses tev's packets.
//!
//! The Chromium test runs Debian's `chromium` (or `$CHROMIUM`, `chromium-browser`,
//! `google-chrome`); without one it prints "skipped: no chromium" and passes, unless
//! `CAUSTICA_REQUIRE_BROWSER=1` (CI), when it fails.

mod common;

use caustica_core::image_io::Image;
use common::{assert_clean_failure, caustica, stderr, stdout};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("preview-test", name)
}

/// Starts `caustica args` (with `--preview 0`) and returns it with the port it printed.
fn start_with_preview(args: &[&str]) -> (Child, u16, mpsc::Receiver<String>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_caustica"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run caustica");
    let err = child.stderr.take().expect("stderr");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let deadline = Instant::now() + Duration::from_secs(30);
    let mut seen = Vec::new();
    while Instant::now() < deadline {
        let Ok(line) = rx.recv_timeout(Duration::from_millis(100)) else {
            if let Ok(Some(status)) = child.try_wait() {
                let _ = child.wait();
                panic!("caustica exited ({status}) before serving: {seen:?}");
            }
            continue;
        };
        if let Some(rest) = line.strip_prefix("preview: http://127.0.0.1:") {
            let port = rest.trim_end_matches('/').parse().expect("port");
            return (child, port, rx);
        }
        seen.push(line);
    }
    let _ = child.kill();
    let _ = child.wait();
    panic!("no preview URL printed: {seen:?}");
}

/// Waits for `child` at most `limit`; kills it (and fails) if it takes longer.
fn wait_for(mut child: Child, limit: Duration, what: &str) -> (std::process::ExitStatus, String) {
    let t = Instant::now();
    loop {
        if let Ok(Some(status)) = child.try_wait() {
            let mut out = String::new();
            if let Some(mut o) = child.stdout.take() {
                let _ = o.read_to_string(&mut out);
            }
            return (status, out);
        }
        if t.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what} did not end within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// One HTTP GET to the preview: (head, body).
fn get(port: u16, target: &str) -> std::io::Result<(String, Vec<u8>)> {
    let mut s = TcpStream::connect(("127.0.0.1", port))?;
    s.set_read_timeout(Some(Duration::from_secs(10)))?;
    write!(s, "GET {target} HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")?;
    let mut all = Vec::new();
    s.read_to_end(&mut all)?;
    let at = all
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .ok_or_else(|| std::io::Error::other("no head"))?;
    Ok((
        String::from_utf8_lossy(&all[..at]).into_owned(),
        all[at + 4..].to_vec(),
    ))
}

fn find_chromium() -> Option<PathBuf> {
    if let Some(c) = std::env::var_os("CHROMIUM").filter(|c| !c.is_empty()) {
        return Some(PathBuf::from(c));
    }
    let path = std::env::var_os("PATH")?;
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        for dir in std::env::split_paths(&path) {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// The text of the element with id `id` in Chromium's dumped DOM (up to its closing tag).
fn element_text<'a>(dom: &'a str, id: &str) -> Option<&'a str> {
    let at = dom.find(&format!("id=\"{id}\""))?;
    let rest = &dom[at..];
    let start = rest.find('>')? + 1;
    let end = rest.find("</")?;
    rest.get(start..end)
}

#[test]
fn headless_chromium_sees_the_image_converge_and_the_progress() {
    let Some(chromium) = find_chromium() else {
        if std::env::var("CAUSTICA_REQUIRE_BROWSER").as_deref() == Ok("1") {
            panic!("CAUSTICA_REQUIRE_BROWSER=1 but no chromium (set CHROMIUM or install chromium)");
        }
        println!("skipped: no chromium");
        return;
    };
    let out = tmp("chromium.exr");
    // A 4-second budget: long enough for the browser to start and see several images at the
    // quarter-second interval on any machine, whatever its speed.
    let (render, port, _stderr) = start_with_preview(&[
        "render",
        "cornell-box",
        "--integrator",
        "path",
        "--width",
        "96",
        "--height",
        "96",
        "--time",
        "4",
        "-q",
        "-o",
        out.to_str().unwrap(),
        "--preview",
        "0",
        "--preview-interval",
        "0.25",
    ]);
    let profile = tmp("chromium-profile");
    // The page long-polls /wait until the render is done; while a fetch is pending Chromium's
    // virtual time stands still, so the budget only runs out once the page has stopped polling.
    let browser = Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--dump-dom",
            "--virtual-time-budget=20000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("http://127.0.0.1:{port}/"))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("run chromium");
    let (status, dom) = wait_for(browser, Duration::from_secs(60), "chromium");
    assert!(status.success(), "chromium failed: {status}");
    let (status, summary) = wait_for(render, Duration::from_secs(60), "the render");
    assert!(status.success(), "render failed: {status}");
    // The page saw images while the render ran, each logged with the progress it came with.
    let log = dom
        .split_once("id=\"log\">")
        .and_then(|(_, rest)| rest.split_once("</ol>"))
        .map_or("", |(log, _)| log);
    let during: Vec<&str> = log
        .split("<li>")
        .filter(|l| l.contains("render ") && !l.contains("render 100.0%"))
        .collect();
    assert!(
        during.len() >= 2,
        "fewer than two updates while rendering: {log}\n{dom}"
    );
    assert!(
        during.iter().all(|l| l.contains("path tracing")),
        "progress without the pass: {log}"
    );
    let updates: usize = element_text(&dom, "updates")
        .and_then(|t| t.trim().parse().ok())
        .unwrap_or(0);
    assert!(updates >= 3, "updates {updates}: {dom}");
    // The end: done, 100 %, the summary the command printed, and an image on screen.
    assert_eq!(element_text(&dom, "state"), Some("done"), "{dom}");
    let progress = element_text(&dom, "progress").unwrap_or_default();
    assert!(progress.contains("render 100.0%"), "{progress}");
    let shown = element_text(&dom, "summary").unwrap_or_default();
    assert!(shown.contains("samples/s"), "{shown}");
    assert_eq!(
        shown.replace("&gt;", ">"),
        summary.trim(),
        "the page's summary is not the command's"
    );
    assert!(dom.contains("src=\"blob:"), "no image on the page: {dom}");
    assert!(out.exists());
}

/// Polls the preview like a page (`/wait`, then `/image.png` at exposure 1) until the render
/// ends; returns the last PNG and status received.
fn poll_like_a_page(
    port: u16,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<(Vec<u8>, String)> {
    std::thread::spawn(move || {
        let mut after = 0u64;
        let mut last = Vec::new();
        let mut status = String::new();
        while !stop.load(Ordering::SeqCst) {
            let Ok((_, body)) = get(port, &format!("/wait?after={after}")) else {
                break;
            };
            let json = String::from_utf8_lossy(&body).into_owned();
            let version = json
                .split("\"version\":")
                .nth(1)
                .and_then(|r| r.split(',').next())
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or(0);
            if version > after {
                if let Ok((head, png)) = get(port, "/image.png?exposure=1")
                    && head.starts_with("HTTP/1.1 200")
                {
                    last = png;
                }
                after = version;
            }
            let done = json.contains("\"done\":true");
            status = json;
            if done {
                break;
            }
        }
        (last, status)
    })
}

#[test]
fn the_image_is_the_same_bytes_with_and_without_a_preview() {
    // Every driver that hands over the film: pixel passes (path), light-path waves
    // (lighttrace), pds's splat batches, the progressive methods' iterations; a snapshot at
    // every pass, and a client polling the whole time.
    for (name, args) in [
        (
            "path",
            &["cornell-box", "--integrator", "path", "--spp", "24"][..],
        ),
        (
            "lighttrace",
            &["caustic-box", "--integrator", "lighttrace", "--spp", "2"][..],
        ),
        (
            "pds",
            &[
                "glass-sphere",
                "--integrator",
                "pds",
                "--spp",
                "2",
                "--light-paths",
                "300000",
            ][..],
        ),
        (
            "pppm",
            &[
                "caustic-box",
                "--integrator",
                "pppm",
                "--iterations",
                "6",
                "--photons-per-iteration",
                "20000",
            ][..],
        ),
    ] {
        let (plain, plain_png) = (tmp(&format!("{name}.exr")), tmp(&format!("{name}.png")));
        let (live, live_png) = (
            tmp(&format!("{name}-live.exr")),
            tmp(&format!("{name}-live.png")),
        );
        let size = ["--width", "64", "--height", "64", "-q", "--exposure", "1"];
        let mut a: Vec<&str> = vec!["render"];
        a.extend(args);
        a.extend(size);
        let mut without = a.clone();
        without.extend(["-o", plain.to_str().unwrap()]);
        without.extend(["--png", plain_png.to_str().unwrap()]);
        let o = caustica(&without);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let mut with = a.clone();
        with.extend(["-o", live.to_str().unwrap()]);
        with.extend(["--png", live_png.to_str().unwrap()]);
        with.extend(["--preview", "0", "--preview-interval", "0.001"]);
        let (child, port, _err) = start_with_preview(&with);
        let stop = Arc::new(AtomicBool::new(false));
        let page = poll_like_a_page(port, stop.clone());
        let (status, _) = wait_for(child, Duration::from_secs(120), name);
        stop.store(true, Ordering::SeqCst);
        assert!(status.success(), "{name}: {status}");
        assert!(
            std::fs::read(&plain).unwrap() == std::fs::read(&live).unwrap(),
            "{name}: the EXR differs with --preview"
        );
        assert!(
            std::fs::read(&plain_png).unwrap() == std::fs::read(&live_png).unwrap(),
            "{name}: the PNG differs with --preview"
        );
        // The last image served at exposure 1 has the pixels of --png at --exposure 1.
        let (png, _) = page.join().unwrap();
        assert!(!png.is_empty(), "{name}: no image served");
        let served = tmp(&format!("{name}-served.png"));
        std::fs::write(&served, &png).unwrap();
        assert_eq!(
            Image::read(&served).unwrap(),
            Image::read(&plain_png).unwrap(),
            "{name}: the served PNG is not --png's"
        );
    }
}

#[test]
fn a_port_in_use_is_refused_before_any_work() {
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let out = tmp("in-use.exr");
    let t = Instant::now();
    let o = caustica(&[
        "render",
        "glass-sphere",
        "--integrator",
        "pm",
        "-o",
        out.to_str().unwrap(),
        "--preview",
        &port,
    ]);
    assert_clean_failure(
        &o,
        &[&format!("port {port}"), "already in use", "--preview"],
    );
    assert!(!out.exists(), "an image was written");
    // No work: neither the memory estimate of the photon pass nor a summary.
    assert!(!stderr(&o).contains("memory:"), "{}", stderr(&o));
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert!(t.elapsed() < Duration::from_secs(10));
    drop(taken);
}

#[test]
fn bad_preview_options_fail_cleanly() {
    let out = tmp("bad.exr");
    let o = out.to_str().unwrap();
    for (extra, words) in [
        (vec!["--preview", "70000"], &["--preview"][..]),
        (vec!["--preview", "x"], &["--preview"][..]),
        (vec!["--preview-interval", "1"], &["--preview or --tev"][..]),
        (
            vec!["--preview", "0", "--preview-interval", "0"],
            &["--preview-interval", "positive"][..],
        ),
        (vec!["--tev", "nowhere"], &["--tev", "HOST:PORT"][..]),
        (vec!["--apng", "p.png"], &["--frames"][..]),
    ] {
        let mut args = vec!["render", "cornell-box", "--spp", "1", "-q", "-o", o];
        args.extend(extra);
        assert_clean_failure(&caustica(&args), words);
        assert!(!out.exists());
    }
}

/// A packet of tev's IPC protocol, as tev reads it.
#[derive(Debug)]
enum TevPacket {
    Create {
        name: String,
        width: i32,
        height: i32,
        channels: Vec<String>,
    },
    Update {
        name: String,
        channels: Vec<String>,
        x: i32,
        y: i32,
        width: i32,
        height: i32,
        /// Planar: each channel's width × height values in turn.
        values: Vec<f32>,
    },
}

/// Parses a stream of tev packets (u32 length, type, fields: tev's `Ipc.cpp`).
fn parse_tev(mut bytes: &[u8]) -> Vec<TevPacket> {
    struct Cursor<'a>(&'a [u8]);
    impl Cursor<'_> {
        fn u8(&mut self) -> u8 {
            let b = self.0[0];
            self.0 = &self.0[1..];
            b
        }
        fn i32(&mut self) -> i32 {
            let v = i32::from_le_bytes(self.0[..4].try_into().unwrap());
            self.0 = &self.0[4..];
            v
        }
        fn f32(&mut self) -> f32 {
            f32::from_bits(self.i32() as u32)
        }
        fn str(&mut self) -> String {
            let end = self.0.iter().position(|&b| b == 0).expect("NUL");
            let s = String::from_utf8(self.0[..end].to_vec()).unwrap();
            self.0 = &self.0[end + 1..];
            s
        }
    }
    let mut out = Vec::new();
    while !bytes.is_empty() {
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        let mut c = Cursor(&bytes[4..len]);
        bytes = &bytes[len..];
        let kind = c.u8();
        assert_eq!(c.u8(), 0, "grabFocus");
        let name = c.str();
        match kind {
            4 => {
                let (width, height, n) = (c.i32(), c.i32(), c.i32());
                let channels = (0..n).map(|_| c.str()).collect();
                out.push(TevPacket::Create {
                    name,
                    width,
                    height,
                    channels,
                });
            }
            5 => {
                let n = c.i32();
                let channels = (0..n).map(|_| c.str()).collect();
                let (x, y, width, height) = (c.i32(), c.i32(), c.i32(), c.i32());
                let values = (0..n * width * height).map(|_| c.f32()).collect();
                out.push(TevPacket::Update {
                    name,
                    channels,
                    x,
                    y,
                    width,
                    height,
                    values,
                });
            }
            k => panic!("unexpected packet type {k}"),
        }
        assert!(c.0.is_empty(), "packet longer than its fields");
    }
    out
}

#[test]
fn tev_gets_the_image_named_sized_and_final() {
    let fake_tev = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = fake_tev.local_addr().unwrap().to_string();
    let received = std::thread::spawn(move || {
        let (mut s, _) = fake_tev.accept().unwrap();
        let mut all = Vec::new();
        s.read_to_end(&mut all).unwrap();
        all
    });
    let out = tmp("tev.exr");
    // 150 × 140: tiles of 128 and the remainders 22 and 12.
    let o = caustica(&[
        "render",
        "cornell-box",
        "--integrator",
        "path",
        "--spp",
        "16",
        "--width",
        "150",
        "--height",
        "140",
        "-q",
        "-o",
        out.to_str().unwrap(),
        "--tev",
        &address,
        "--preview-interval",
        "0.001",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let packets = parse_tev(&received.join().unwrap());
    let name = out.display().to_string();
    match packets.first() {
        Some(TevPacket::Create {
            name: n,
            width,
            height,
            channels,
        }) => {
            assert_eq!(n, &name);
            assert_eq!((*width, *height), (150, 140));
            assert_eq!(channels, &["R", "G", "B"]);
        }
        p => panic!("the first packet is not CreateImage: {p:?}"),
    }
    let mut img = Image::new(150, 140);
    let mut updates = 0;
    for p in &packets[1..] {
        let TevPacket::Update {
            name: n,
            channels,
            x,
            y,
            width,
            height,
            values,
        } = p
        else {
            panic!("a second CreateImage");
        };
        assert_eq!(n, &name);
        assert_eq!(channels, &["R", "G", "B"]);
        assert!(*width <= 128 && *height <= 128);
        let (w, h) = (*width as usize, *height as usize);
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                let (px, py) = (*x as usize + i, *y as usize + j);
                img.set(
                    px,
                    py,
                    [values[k], values[w * h + k], values[2 * w * h + k]],
                );
            }
        }
        updates += 1;
    }
    // Four tiles per image; more than the final image was sent.
    assert_eq!(updates % 4, 0, "{updates} tiles");
    assert!(
        updates >= 8,
        "only {updates} tiles: no image before the final one"
    );
    assert_eq!(
        img,
        Image::read(&out).unwrap(),
        "tev's image is not the EXR"
    );
}

#[test]
fn tev_not_listening_is_refused_before_any_work() {
    let gone = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = gone.local_addr().unwrap().to_string();
    drop(gone);
    let out = tmp("no-tev.exr");
    let o = caustica(&[
        "render",
        "cornell-box",
        "--spp",
        "1",
        "-o",
        out.to_str().unwrap(),
        "--tev",
        &address,
    ]);
    assert_clean_failure(&o, &["cannot connect to tev", &address]);
    assert!(!out.exists());
    assert!(stdout(&o).is_empty());
}

#[test]
fn a_sequence_shows_each_frame_and_its_summary() {
    let pattern = tmp("seq_%02d.exr");
    let (child, port, _err) = start_with_preview(&[
        "render",
        "moving-wave",
        "--integrator",
        "path",
        "--frames",
        "0..1",
        "--spp",
        "1",
        "--width",
        "32",
        "--height",
        "24",
        "-q",
        "-o",
        pattern.to_str().unwrap(),
        "--preview",
        "0",
    ]);
    let stop = Arc::new(AtomicBool::new(false));
    let page = poll_like_a_page(port, stop.clone());
    // The status after the end (the process waits for the page to fetch the final image).
    let (status, _) = wait_for(child, Duration::from_secs(120), "the sequence");
    stop.store(true, Ordering::SeqCst);
    assert!(status.success());
    let (png, json) = page.join().unwrap();
    assert!(!png.is_empty());
    // Both frames' summaries, the second frame's label, and the end.
    for part in [
        "seq_00.exr\"",
        "seq_01.exr\"",
        "\"label\":\"frame 1 (2/2,",
        "\"done\":true",
    ] {
        assert!(json.contains(part), "{part} not in {json}");
    }
    for f in ["seq_00.exr", "seq_01.exr"] {
        assert!(Path::new(&tmp(f)).exists());
    }
}

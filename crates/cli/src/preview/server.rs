//! The preview's HTTP server: the page, its status and the tone-mapped image, on 127.0.0.1.
//!
//! A minimal HTTP/1.1 server on `std::net` rather than a crate (`tiny_http` would be the
//! alternative): it answers four `GET` routes to a browser on the same machine, one request per
//! connection (`Connection: close`: no keep-alive, no chunked bodies, no request bodies), so
//! all it needs is to read a request line and headers (bounded in size and time) and write a
//! response with a `Content-Length`. That is ~150 lines that can be read in full, where a
//! general server would bring its own dependencies for features unused here.
//!
//! Routes (docs/preview.md):
//! * `GET /`: the page (`page.html`, included in the binary);
//! * `GET /status`: the status as JSON (version, pass, percent, ETA, rate, summaries, done);
//! * `GET /wait?after=V`: the same JSON once the image version exceeds `V` or the render has
//!   ended, or after [`WAIT`] (long polling: the page neither spins nor misses an update);
//! * `GET /image.png?exposure=E`: the latest image as an 8-bit sRGB PNG at exposure `E`
//!   stops: the pixels `--png` would write at `--exposure E` (`Image::to_srgb8`).
//!
//! Each connection has its own thread (at most [`MAX_CLIENTS`] at once); they read the [`Hub`]
//! and never hold it while writing to a socket.

use super::Hub;
use anyhow::{Result, anyhow};
use caustica_core::image_io::Image;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The page, served at `/`.
const PAGE: &str = include_str!("page.html");
/// How long `/wait` holds a request when nothing changes.
pub const WAIT: Duration = Duration::from_secs(1);
/// Connections served at once (more are answered 503 at once).
const MAX_CLIENTS: usize = 32;
/// A request's line and headers, at most.
const MAX_HEAD: usize = 16 * 1024;

/// The port the preview listens on when `--preview` is given without one.
pub const DEFAULT_PORT: u16 = 8080;

/// A listening preview server (bound before the render starts, so a port in use is an error
/// before any work).
pub struct Server {
    listener: TcpListener,
    port: u16,
}

/// What the main thread learns from the running server.
#[derive(Debug, Default)]
pub struct Served {
    /// A request has been answered (a page or a script is watching).
    pub any_request: AtomicBool,
    /// The newest image version sent in full.
    pub image_version: AtomicU64,
    /// A status saying the render has ended was sent in full.
    pub done_sent: AtomicBool,
}

/// The PNG last encoded: (version, exposure's bits, bytes), shared by the clients.
type PngCache = Mutex<Option<(u64, u32, Arc<Vec<u8>>)>>;

impl Server {
    /// Listens on 127.0.0.1:`port` (0: any free port); a port in use is a clear error naming
    /// it.
    pub fn bind(port: u16) -> Result<Server> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port)).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AddrInUse {
                anyhow!(
                    "--preview: port {port} on 127.0.0.1 is already in use (another preview or server?); choose another port, e.g. --preview {}, or --preview 0 for any free port",
                    port.wrapping_add(1).max(1024)
                )
            } else {
                anyhow!("--preview: cannot listen on 127.0.0.1:{port}: {e}")
            }
        })?;
        let port = listener.local_addr().map(|a| a.port()).unwrap_or(port);
        Ok(Server { listener, port })
    }

    /// The port listened on (the one chosen for port 0).
    pub fn port(&self) -> u16 {
        self.port
    }

    /// Serves `hub` on a thread of its own, for the rest of the process.
    pub fn spawn(self, hub: Arc<Hub>) -> Result<Arc<Served>> {
        let served = Arc::new(Served::default());
        let shared = served.clone();
        let cache: Arc<PngCache> = Arc::new(Mutex::new(None));
        let active = Arc::new(AtomicUsize::new(0));
        std::thread::Builder::new()
            .name("preview-server".into())
            .spawn(move || {
                for conn in self.listener.incoming() {
                    let Ok(stream) = conn else { continue };
                    if active.fetch_add(1, Ordering::SeqCst) >= MAX_CLIENTS {
                        active.fetch_sub(1, Ordering::SeqCst);
                        let mut s = stream;
                        let _ = respond(&mut s, 503, "text/plain", b"busy\n", false, &[]);
                        continue;
                    }
                    let (hub, served, cache, mine) =
                        (hub.clone(), shared.clone(), cache.clone(), active.clone());
                    let spawned = std::thread::Builder::new()
                        .name("preview-client".into())
                        .spawn(move || {
                            // Errors are the client's (gone, too slow): nothing to report.
                            let _ = handle(stream, &hub, &served, &cache);
                            mine.fetch_sub(1, Ordering::SeqCst);
                        });
                    if spawned.is_err() {
                        active.fetch_sub(1, Ordering::SeqCst);
                    }
                }
            })
            .map_err(|e| anyhow!("cannot start the preview server's thread: {e}"))?;
        Ok(served)
    }
}

/// A parsed request: method, path and query.
struct Request {
    method: String,
    path: String,
    query: String,
}

impl Request {
    /// The value of `key` in the query string (`a=1&b=2`; values are numbers, not decoded).
    fn param(&self, key: &str) -> Option<&str> {
        self.query
            .split('&')
            .filter_map(|kv| kv.split_once('='))
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v)
    }
}

/// Reads the request line and headers (the body, which GET has none of, is not read).
fn read_request(stream: &TcpStream) -> std::io::Result<Option<Request>> {
    let mut reader = BufReader::new(stream.take(MAX_HEAD as u64));
    let mut line = String::new();
    if reader.read_line(&mut line)? == 0 {
        return Ok(None);
    }
    let mut parts = line.split_whitespace();
    let (Some(method), Some(target), Some(version)) = (parts.next(), parts.next(), parts.next())
    else {
        return Ok(None);
    };
    if !version.starts_with("HTTP/1.") {
        return Ok(None);
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let request = Request {
        method: method.to_string(),
        path: path.to_string(),
        query: query.to_string(),
    };
    // The headers, up to the empty line (their content is not needed).
    loop {
        let mut h = String::new();
        if reader.read_line(&mut h)? == 0 || h == "\r\n" || h == "\n" {
            break;
        }
    }
    Ok(Some(request))
}

fn handle(mut stream: TcpStream, hub: &Hub, served: &Served, cache: &PngCache) -> Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(5)))?;
    stream.set_write_timeout(Some(Duration::from_secs(10)))?;
    let Some(req) = read_request(&stream)? else {
        respond(&mut stream, 400, "text/plain", b"bad request\n", false, &[])?;
        return Ok(());
    };
    let head = match req.method.as_str() {
        "GET" => false,
        "HEAD" => true,
        _ => {
            respond(&mut stream, 405, "text/plain", b"GET only\n", false, &[])?;
            return Ok(());
        }
    };
    served.any_request.store(true, Ordering::SeqCst);
    let json = "application/json";
    match req.path.as_str() {
        "/" | "/index.html" => respond(
            &mut stream,
            200,
            "text/html; charset=utf-8",
            PAGE.as_bytes(),
            head,
            &[],
        ),
        "/status" | "/wait" => {
            let s = if req.path == "/wait" {
                let after = req.param("after").and_then(|v| v.parse().ok()).unwrap_or(0);
                hub.wait(after, WAIT)
            } else {
                hub.snapshot()
            };
            respond(&mut stream, 200, json, s.to_json().as_bytes(), head, &[])?;
            if s.done && !head {
                served.done_sent.store(true, Ordering::SeqCst);
            }
            Ok(())
        }
        "/image.png" => {
            let exposure = req
                .param("exposure")
                .and_then(|v| v.parse::<f32>().ok())
                .filter(|e| e.is_finite())
                .unwrap_or(0.0)
                .clamp(-30.0, 30.0);
            let s = hub.snapshot();
            let Some(img) = s.image else {
                return respond(&mut stream, 404, "text/plain", b"no image yet\n", head, &[]);
            };
            let png = png_of(cache, s.version, &img, exposure)?;
            let version = s.version.to_string();
            respond(
                &mut stream,
                200,
                "image/png",
                &png,
                head,
                &[("X-Image-Version", &version)],
            )?;
            served.image_version.fetch_max(s.version, Ordering::SeqCst);
            Ok(())
        }
        _ => respond(&mut stream, 404, "text/plain", b"not found\n", head, &[]),
    }
}

/// The PNG of image `version` at `exposure`, encoded once for every client asking for it.
fn png_of(cache: &PngCache, version: u64, img: &Image, exposure: f32) -> Result<Arc<Vec<u8>>> {
    let key = (version, exposure.to_bits());
    if let Ok(c) = cache.lock()
        && let Some((v, e, bytes)) = c.as_ref()
        && (*v, *e) == key
    {
        return Ok(bytes.clone());
    }
    let bytes = Arc::new(encode_png(img, exposure)?);
    if let Ok(mut c) = cache.lock() {
        *c = Some((key.0, key.1, bytes.clone()));
    }
    Ok(bytes)
}

/// An 8-bit sRGB PNG of `img` at `exposure`: the pixels of `Image::write_png` (`--png`), which
/// both take from `Image::to_srgb8`; fast compression (the page is local).
pub fn encode_png(img: &Image, exposure: f32) -> Result<Vec<u8>> {
    let (w, h) = (
        u32::try_from(img.width).map_err(|_| anyhow!("image too wide for PNG"))?,
        u32::try_from(img.height).map_err(|_| anyhow!("image too tall for PNG"))?,
    );
    let pixels = img.to_srgb8(exposure);
    let mut out = Vec::with_capacity(pixels.len() / 2 + 1024);
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header()?;
    writer.write_image_data(&pixels)?;
    writer.finish()?;
    Ok(out)
}

fn respond(
    stream: &mut TcpStream,
    code: u16,
    content_type: &str,
    body: &[u8],
    head_only: bool,
    extra: &[(&str, &str)],
) -> Result<()> {
    let reason = match code {
        200 => "OK",
        400 => "Bad Request",
        404 => "Not Found",
        405 => "Method Not Allowed",
        _ => "Service Unavailable",
    };
    let mut head = format!(
        "HTTP/1.1 {code} {reason}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n",
        body.len()
    );
    if code == 405 {
        head.push_str("Allow: GET, HEAD\r\n");
    }
    for (k, v) in extra {
        head.push_str(&format!("{k}: {v}\r\n"));
    }
    head.push_str("\r\n");
    stream.write_all(head.as_bytes())?;
    if !head_only {
        stream.write_all(body)?;
    }
    stream.flush()?;
    Ok(())
}

/// After the render: lets a watching page fetch the final status and image before the process
/// exits. Returns at once if no request was ever answered, else once the final image (version
/// `last`) and a status saying "done" have been sent, or after `limit`.
pub fn linger(served: &Served, last: u64, limit: Duration) {
    if !served.any_request.load(Ordering::SeqCst) {
        return;
    }
    let t = Instant::now();
    while (served.image_version.load(Ordering::SeqCst) < last
        || !served.done_sent.load(Ordering::SeqCst))
        && t.elapsed() < limit
    {
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn get(port: u16, target: &str) -> (String, Vec<u8>) {
        let mut s = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
        write!(s, "GET {target} HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
        let mut all = Vec::new();
        s.read_to_end(&mut all).unwrap();
        let at = all.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
        (
            String::from_utf8_lossy(&all[..at]).into_owned(),
            all[at + 4..].to_vec(),
        )
    }

    #[test]
    fn routes_answer_and_a_taken_port_is_refused() {
        let server = Server::bind(0).unwrap();
        let port = server.port();
        let err = Server::bind(port).err().unwrap().to_string();
        assert!(err.contains(&format!("port {port}")), "{err}");
        assert!(err.contains("already in use"), "{err}");
        let hub = Arc::new(Hub::new());
        let served = server.spawn(hub.clone()).unwrap();
        let (head, body) = get(port, "/");
        assert!(head.starts_with("HTTP/1.1 200"), "{head}");
        assert_eq!(body, PAGE.as_bytes());
        assert!(get(port, "/image.png").0.starts_with("HTTP/1.1 404"));
        assert!(get(port, "/nothing").0.starts_with("HTTP/1.1 404"));
        let mut img = Image::new(3, 2);
        img.set(1, 1, [0.25, 0.5, 1.0]);
        hub.publish(img.clone());
        let (head, body) = get(port, "/wait?after=0");
        assert!(head.contains("application/json"), "{head}");
        assert!(String::from_utf8_lossy(&body).contains("\"version\":1"));
        let (head, png) = get(port, "/image.png?exposure=1.5");
        assert!(head.contains("X-Image-Version: 1"), "{head}");
        // The pixels of --png at --exposure 1.5.
        let dec = png::Decoder::new(std::io::Cursor::new(png));
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&buf[..info.buffer_size()], &img.to_srgb8(1.5)[..]);
        assert_eq!(served.image_version.load(Ordering::SeqCst), 1);
        // Not GET.
        let mut s = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
        write!(s, "POST / HTTP/1.1\r\n\r\n").unwrap();
        let mut all = String::new();
        s.read_to_string(&mut all).unwrap();
        assert!(all.starts_with("HTTP/1.1 405"), "{all}");
    }
}

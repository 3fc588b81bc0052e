//! `--tev HOST:PORT`: the image streamed to a running tev (<https://github.com/Tom94/tev>) with
//! its TCP IPC protocol, as pbrt-v4's `--display-server` does.
//!
//! A tev packet is its total length (u32, little-endian, the 4 bytes included), a type byte and
//! the fields: booleans as one byte, strings NUL-terminated, integers and floats little-endian
//! (tev's `Ipc.cpp`). Two packets are sent:
//! * CreateImage (type 4): grab focus, name, width, height (i32), channel count (i32), channel
//!   names — an image of channels R, G, B, once per render (again if its name or size
//!   changes, i.e. at each frame of a sequence);
//! * UpdateImageV2 (type 5): grab focus, name, channel count, channel names, x, y, width,
//!   height (i32), then the channels' values one plane after the other (f32), for one tile of
//!   [`TILE`]² pixels; every tile of the image at each snapshot and at the end.
//!
//! (Version 2 of UpdateImage sends all channels in one packet and is read by tev since v1.17;
//! version 3 only adds strides, which planar tiles do not need.)
//!
//! A thread of its own sends the newest snapshot of the [`Hub`] (skipping those it was too slow
//! for); the render never waits for tev. If tev goes away, a warning says so once and the
//! render goes on.

use super::Hub;
use anyhow::{Context, Result, anyhow};
use caustica_core::image_io::Image;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// Tiles are at most this many pixels on a side (as pbrt-v4's).
pub const TILE: usize = 128;
/// The packet types sent.
pub const CREATE_IMAGE: u8 = 4;
pub const UPDATE_IMAGE_V2: u8 = 5;
/// The channels sent.
pub const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// A packet being written: its length is filled in by [`Packet::finish`].
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8) -> Self {
        let mut v = Vec::with_capacity(64);
        v.extend_from_slice(&0u32.to_le_bytes());
        v.push(kind);
        Packet(v)
    }
    fn bool(&mut self, b: bool) {
        self.0.push(u8::from(b));
    }
    fn str(&mut self, s: &str) {
        // tev reads up to the first NUL.
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
    }
    fn i32(&mut self, x: i32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f32(&mut self, x: f32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn finish(mut self) -> Result<Vec<u8>> {
        let n = u32::try_from(self.0.len()).map_err(|_| anyhow!("tev packet too large"))?;
        self.0[..4].copy_from_slice(&n.to_le_bytes());
        Ok(self.0)
    }
}

fn i32_of(x: usize) -> Result<i32> {
    i32::try_from(x).map_err(|_| anyhow!("image too large for tev"))
}

/// The CreateImage packet of an image `name` of `width` × `height` pixels with channels R, G, B.
pub fn create_image(name: &str, width: usize, height: usize) -> Result<Vec<u8>> {
    let mut p = Packet::new(CREATE_IMAGE);
    p.bool(false);
    p.str(name);
    p.i32(i32_of(width)?);
    p.i32(i32_of(height)?);
    p.i32(CHANNELS.len() as i32);
    for c in CHANNELS {
        p.str(c);
    }
    p.finish()
}

/// The UpdateImageV2 packets of every tile of `img`, named `name`.
pub fn update_image(name: &str, img: &Image) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for y0 in (0..img.height).step_by(TILE) {
        for x0 in (0..img.width).step_by(TILE) {
            let (w, h) = (TILE.min(img.width - x0), TILE.min(img.height - y0));
            let mut p = Packet::new(UPDATE_IMAGE_V2);
            p.0.reserve(64 + 12 * w * h);
            p.bool(false);
            p.str(name);
            p.i32(CHANNELS.len() as i32);
            for c in CHANNELS {
                p.str(c);
            }
            for v in [x0, y0, w, h] {
                p.i32(i32_of(v)?);
            }
            for c in 0..CHANNELS.len() {
                for y in y0..y0 + h {
                    for x in x0..x0 + w {
                        p.f32(img.get(x, y)[c]);
                    }
                }
            }
            out.push(p.finish()?);
        }
    }
    Ok(out)
}

/// A connection to tev, made before the render starts.
pub struct Tev {
    stream: TcpStream,
    address: String,
}

impl Tev {
    /// Connects to tev at `address` (HOST:PORT); refused or unreachable is an error.
    pub fn connect(address: &str) -> Result<Tev> {
        let addrs: Vec<_> = address
            .to_socket_addrs()
            .with_context(|| {
                format!(
                    "--tev {address}: expected HOST:PORT of a running tev (e.g. 127.0.0.1:14158)"
                )
            })?
            .collect();
        let mut last = None;
        for a in &addrs {
            match TcpStream::connect_timeout(a, Duration::from_secs(3)) {
                Ok(stream) => {
                    stream.set_write_timeout(Some(Duration::from_secs(5))).ok();
                    stream.set_nodelay(true).ok();
                    return Ok(Tev {
                        stream,
                        address: address.to_string(),
                    });
                }
                Err(e) => last = Some(e),
            }
        }
        Err(anyhow!(
            "--tev: cannot connect to tev at {address}: {} (start tev first; it listens on 127.0.0.1:14158 unless given --hostname)",
            last.map_or("no address".to_string(), |e| e.to_string())
        ))
    }

    /// Streams `hub`'s images on a thread of its own until the render has ended (its final
    /// image sent); join the handle before the process exits.
    pub fn spawn(self, hub: Arc<Hub>) -> Result<JoinHandle<()>> {
        std::thread::Builder::new()
            .name("tev".into())
            .spawn(move || {
                if let Err(e) = self.stream_images(&hub) {
                    eprintln!(
                        "warning: --tev {}: {e:#}; the render goes on without tev",
                        self.address
                    );
                }
            })
            .map_err(|e| anyhow!("cannot start the tev thread: {e}"))
    }

    fn stream_images(&self, hub: &Hub) -> Result<()> {
        let mut stream = &self.stream;
        let mut sent = 0u64;
        // The image tev holds: name and size.
        let mut created: Option<(String, usize, usize)> = None;
        loop {
            let s = hub.wait(sent, Duration::from_secs(1));
            if s.version > sent
                && let Some(img) = &s.image
            {
                let name = &s.image_name;
                let shape = (name.clone(), img.width, img.height);
                if created.as_ref() != Some(&shape) {
                    stream
                        .write_all(&create_image(name, img.width, img.height)?)
                        .context("tev closed the connection")?;
                    created = Some(shape);
                }
                for packet in update_image(name, img)? {
                    stream
                        .write_all(&packet)
                        .context("tev closed the connection")?;
                }
                sent = s.version;
            }
            if s.done && s.version <= sent {
                stream.flush()?;
                return Ok(());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_carry_their_length_type_and_fields() {
        let p = create_image("a.exr", 300, 2).unwrap();
        assert_eq!(
            u32::from_le_bytes(p[..4].try_into().unwrap()) as usize,
            p.len()
        );
        assert_eq!(p[4], CREATE_IMAGE);
        assert_eq!(&p[5..12], b"\0a.exr\0");
        assert_eq!(i32::from_le_bytes(p[12..16].try_into().unwrap()), 300);
        assert_eq!(&p[p.len() - 6..], b"R\0G\0B\0");
        let mut img = Image::new(300, 2);
        img.set(299, 1, [1.0, 2.0, 3.0]);
        let tiles = update_image("a.exr", &img).unwrap();
        // 300 = 128 + 128 + 44 wide.
        assert_eq!(tiles.len(), 3);
        let last = &tiles[2];
        assert_eq!(last[4], UPDATE_IMAGE_V2);
        // The last pixel's B is the tile's last float.
        assert_eq!(&last[last.len() - 4..], &3.0f32.to_le_bytes());
        assert_eq!(last.len(), 4 + 1 + 1 + 6 + 4 + 6 + 16 + 3 * 4 * 44 * 2);
    }
}

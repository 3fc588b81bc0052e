//! When a path happens: the time rule of camera rays and light paths in animated scenes.
//!
//! Time is measured in frames (seed 003: the exposure `e` is in frames). A camera ray or light
//! path gets one time for all its segments (rays spawned at a hit inherit the hit's time), drawn
//! by the path's rule. Every rule is the shutter's opening when nothing in the scene moves, and
//! then draws no random number, so static renders are unchanged by the existence of time.

use caustica_core::sampling::Sampler;
use caustica_scene::Scene;

/// How a light path chooses its time within the camera's shutter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PathTime {
    /// Uniform over the shutter: true motion blur (the path and light tracers' references,
    /// and Cammarano and Jensen's continuous-time photon map).
    #[default]
    Shutter,
    /// The shutter's opening: the frame instant of temporal photon differentials (seed 003
    /// sec. 4: one photon map per frame, traced at the frame).
    Instant,
    /// The middle of the shutter: temporal photon differentials with the centred shutter
    /// alignment.
    Middle,
    /// One of `n ≥ 1` evenly spaced times `open + k/n · length`, `k = 0 … n−1`, chosen
    /// uniformly: time-dependent photon mapping with `n − 1` in-between frames (seed 000
    /// sec. 7.2; `n = 1` is plain photon mapping at the frame instant).
    Slices(u32),
}

impl PathTime {
    /// The time (frames) of a path of `scene` under this rule, drawing one number from
    /// `sampler` only if the scene moves during a shutter of positive length.
    #[inline]
    pub fn sample(self, scene: &Scene, sampler: &mut Sampler) -> f32 {
        let shutter = scene.shutter;
        match self {
            PathTime::Instant | PathTime::Slices(0 | 1) => shutter.open,
            PathTime::Middle => {
                if scene.has_motion() {
                    shutter.open + 0.5 * shutter.length
                } else {
                    shutter.open
                }
            }
            PathTime::Shutter => scene.sample_time(|| sampler.next_1d()),
            PathTime::Slices(n) => scene.sample_time(|| {
                let k = ((sampler.next_1d() * n as f32) as u32).min(n - 1);
                k as f32 / n as f32
            }),
        }
    }
}

//! Keyframed motion of a triangle mesh: the vertex positions (and normals) of every frame of an
//! animation with one topology, linearly interpolated in between (seed 003 sec. 2–3: meshes
//! given per frame, time derivatives from the difference of two frames).
//!
//! Time is measured in **frames**: keyframe `k` is the mesh at time `first_frame + k`. Inside a
//! frame interval `[f, f + 1]` a vertex moves on the straight segment between its two keyframes,
//! so the geometry at any time is exact for the linear interpolation, the swept bounds of a
//! triangle over an interval are the union of its two keyframe boxes, and the derivative of a
//! vertex with respect to time is `q_{f+1} − q_f` per frame — the forward difference of seed 003
//! eq. 5 (the backward one at and after the last keyframe).

use caustica_core::Vec3;

use crate::error::SceneError;

/// Vertex positions and normals of a mesh at consecutive frames (one topology).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshMotion {
    /// Time (frames) of keyframe 0.
    pub first_frame: f32,
    /// `positions[k][i]`: vertex `i` at keyframe `k` (m).
    pub positions: Vec<Vec<Vec3>>,
    /// `normals[k][i]`: vertex normal `i` at keyframe `k` (any non-zero length), when the mesh
    /// has vertex normals.
    pub normals: Option<Vec<Vec<Vec3>>>,
}

/// Where a time falls in the keyframes: the interval `[k, k + 1]` and the fraction `alpha`
/// of it, plus the interval whose difference is the time derivative there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeyTime {
    pub k: usize,
    pub alpha: f32,
}

impl MeshMotion {
    /// Checks that every keyframe has `vertex_count` finite positions (and normals, if given)
    /// and that there is at least one keyframe. Errors name the first bad keyframe.
    pub fn new(
        first_frame: f32,
        positions: Vec<Vec<Vec3>>,
        normals: Option<Vec<Vec<Vec3>>>,
        vertex_count: usize,
    ) -> Result<Self, SceneError> {
        if !first_frame.is_finite() {
            return Err(SceneError::InvalidParameter(format!(
                "the first frame of a mesh animation must be finite, got {first_frame}"
            )));
        }
        if positions.is_empty() {
            return Err(SceneError::InvalidParameter(
                "a mesh animation needs at least one frame".into(),
            ));
        }
        for (k, frame) in positions.iter().enumerate() {
            if frame.len() != vertex_count {
                return Err(SceneError::InvalidParameter(format!(
                    "frame {k} of a mesh animation has {} vertices, the mesh has {vertex_count} \
                     (every frame must have the same topology)",
                    frame.len()
                )));
            }
            if let Some(i) = frame.iter().position(|v| !v.is_finite()) {
                return Err(SceneError::InvalidParameter(format!(
                    "frame {k} of a mesh animation: vertex {i} is not finite"
                )));
            }
        }
        if let Some(ns) = &normals {
            if ns.len() != positions.len() {
                return Err(SceneError::InvalidParameter(format!(
                    "a mesh animation has {} frames of positions but {} of normals",
                    positions.len(),
                    ns.len()
                )));
            }
            if let Some(k) = ns.iter().position(|f| f.len() != vertex_count) {
                return Err(SceneError::InvalidParameter(format!(
                    "frame {k} of a mesh animation has {} normals, the mesh has {vertex_count} \
                     vertices",
                    ns[k].len()
                )));
            }
        }
        Ok(Self {
            first_frame,
            positions,
            normals,
        })
    }

    /// The keyframes of `mesh` moved rigidly (or by any affine map) by `transforms[k]` at
    /// keyframe `k`: positions by the transform, normals by its inverse transpose. The
    /// animated transforms of scene files and built-in scenes become keyframes this way, so
    /// every motion is one representation (interpolated linearly between frames; a rotation's
    /// in-between vertices are then on chords, not arcs).
    pub fn from_transforms(
        first_frame: f32,
        mesh: &super::TriangleMesh,
        transforms: &[caustica_core::Affine3A],
    ) -> Result<Self, SceneError> {
        let positions = transforms
            .iter()
            .map(|t| {
                mesh.positions
                    .iter()
                    .map(|&p| t.transform_point3(p))
                    .collect()
            })
            .collect();
        let normals = mesh.normals.as_ref().map(|ns| {
            transforms
                .iter()
                .map(|t| {
                    let m = caustica_core::Mat3::from(t.matrix3).inverse().transpose();
                    ns.iter().map(|&n| (m * n).normalize_or_zero()).collect()
                })
                .collect()
        });
        Self::new(first_frame, positions, normals, mesh.positions.len())
    }

    /// Number of keyframes.
    pub fn frame_count(&self) -> usize {
        self.positions.len()
    }

    /// True if at least two keyframes differ (the mesh moves).
    pub fn moves(&self) -> bool {
        self.positions.windows(2).any(|w| w[0] != w[1])
            || self
                .normals
                .as_ref()
                .is_some_and(|n| n.windows(2).any(|w| w[0] != w[1]))
    }

    /// The keyframe interval of `time` (frames), clamped to the animation: before the first
    /// keyframe the mesh stays at it, after the last at the last.
    #[inline]
    pub fn key_time(&self, time: f32) -> KeyTime {
        let last = self.positions.len().saturating_sub(1);
        if last == 0 {
            return KeyTime { k: 0, alpha: 0.0 };
        }
        let x = time - self.first_frame;
        if x.is_nan() || x <= 0.0 {
            return KeyTime { k: 0, alpha: 0.0 };
        }
        let k = (x.floor() as usize).min(last - 1);
        KeyTime {
            k,
            alpha: (x - k as f32).min(1.0),
        }
    }

    /// The interval `[k, k + 1]` whose difference is the time derivative at `time`: the
    /// forward difference of the frame `time` lies in, the backward one at and after the last
    /// keyframe (seed 003 eq. 5). `None` for a single keyframe.
    #[inline]
    pub fn derivative_interval(&self, time: f32) -> Option<usize> {
        let last = self.positions.len().checked_sub(1)?;
        if last == 0 {
            return None;
        }
        let x = time - self.first_frame;
        if x.is_nan() || x <= 0.0 {
            return Some(0);
        }
        Some((x.floor() as usize).min(last - 1))
    }

    /// Position of vertex `i` at `time` (m).
    #[inline]
    pub fn position(&self, i: usize, time: f32) -> Vec3 {
        let kt = self.key_time(time);
        lerp_key(&self.positions, kt, i)
    }

    /// Vertex normal `i` at `time` (not normalised), if the mesh has normals.
    #[inline]
    pub fn normal(&self, i: usize, time: f32) -> Option<Vec3> {
        let kt = self.key_time(time);
        self.normals.as_ref().map(|n| lerp_key(n, kt, i))
    }

    /// `∂q_i/∂t` at `time` (m per frame): `q_{f+1} − q_f` of [`Self::derivative_interval`].
    #[inline]
    pub fn velocity(&self, i: usize, time: f32) -> Vec3 {
        match self.derivative_interval(time) {
            Some(k) => self.positions[k + 1][i] - self.positions[k][i],
            None => Vec3::ZERO,
        }
    }

    /// `∂N_i/∂t` at `time` (per frame) of the interpolated vertex normal, if the mesh has
    /// normals: `N_{f+1} − N_f`, exact for the interpolation [`Self::normal`] uses.
    #[inline]
    pub fn normal_velocity(&self, i: usize, time: f32) -> Option<Vec3> {
        let n = self.normals.as_ref()?;
        Some(match self.derivative_interval(time) {
            Some(k) => n[k + 1][i] - n[k][i],
            None => Vec3::ZERO,
        })
    }

    /// The keyframes needed for times in `[t0, t1]` (frames) and for the derivatives there:
    /// those of the intervals the window touches. Memory and BVH bounds then do not grow with
    /// the length of the whole animation.
    pub fn window(&self, t0: f32, t1: f32) -> Self {
        let (Some(a), Some(b)) = (self.derivative_interval(t0), self.derivative_interval(t1))
        else {
            return self.clone();
        };
        let (a, b) = (a.min(b), a.max(b) + 1);
        Self {
            first_frame: self.first_frame + a as f32,
            positions: self.positions[a..=b].to_vec(),
            normals: self.normals.as_ref().map(|n| n[a..=b].to_vec()),
        }
    }

    /// Reverses every keyframe normal (for shapes whose normals are flipped).
    pub fn flip_normals(&mut self) {
        if let Some(ns) = &mut self.normals {
            ns.iter_mut().flatten().for_each(|n| *n = -*n);
        }
    }
}

#[inline]
fn lerp_key(frames: &[Vec<Vec3>], kt: KeyTime, i: usize) -> Vec3 {
    let a = frames[kt.k][i];
    match frames.get(kt.k + 1) {
        Some(b) if kt.alpha > 0.0 => a + (b[i] - a) * kt.alpha,
        _ => a,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn three_frames() -> MeshMotion {
        let f = |x: f32| vec![Vec3::new(x, 0.0, 0.0), Vec3::new(0.0, x * x, 1.0)];
        MeshMotion::new(2.0, vec![f(0.0), f(1.0), f(3.0)], None, 2).unwrap()
    }

    #[test]
    fn positions_interpolate_linearly_inside_a_frame_and_clamp_outside() {
        let m = three_frames();
        assert_eq!(m.position(0, 2.0), Vec3::ZERO);
        assert_eq!(m.position(0, 2.25), Vec3::new(0.25, 0.0, 0.0));
        assert_eq!(m.position(0, 3.5), Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(m.position(1, 3.5), Vec3::new(0.0, 5.0, 1.0));
        assert_eq!(m.position(0, 4.0), Vec3::new(3.0, 0.0, 0.0));
        assert_eq!(m.position(0, 9.0), Vec3::new(3.0, 0.0, 0.0));
        assert_eq!(m.position(0, -1.0), Vec3::ZERO);
    }

    #[test]
    fn velocities_are_forward_differences_and_backward_on_the_last_frame() {
        let m = three_frames();
        assert_eq!(m.velocity(0, 2.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(m.velocity(0, 2.9), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(m.velocity(0, 3.0), Vec3::new(2.0, 0.0, 0.0));
        // The last keyframe (time 4): backward difference, equal to the previous forward one
        // (seed 003 eq. 5; TT10).
        assert_eq!(m.velocity(0, 4.0), Vec3::new(2.0, 0.0, 0.0));
        // A finite difference of the interpolated position equals the velocity.
        let h = 1e-3;
        let fd = (m.position(1, 3.2 + h) - m.position(1, 3.2)) / h;
        assert!((fd - m.velocity(1, 3.2)).length() < 1e-2, "{fd}");
    }

    #[test]
    fn a_window_keeps_the_bracketing_keyframes_and_the_same_motion() {
        let m = three_frames();
        let w = m.window(3.1, 3.6);
        assert_eq!(w.frame_count(), 2);
        assert_eq!(w.first_frame, 3.0);
        for t in [3.1, 3.3, 3.6] {
            assert_eq!(w.position(0, t), m.position(0, t));
            assert_eq!(w.velocity(1, t), m.velocity(1, t));
        }
    }

    #[test]
    fn bad_frames_are_refused_with_the_frame_named() {
        let ok = vec![Vec3::ZERO; 2];
        let e = MeshMotion::new(0.0, vec![ok.clone(), vec![Vec3::ZERO; 3]], None, 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("frame 1") && e.contains("3 vertices"), "{e}");
        let e = MeshMotion::new(0.0, vec![ok.clone(), vec![Vec3::NAN, Vec3::ZERO]], None, 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("frame 1") && e.contains("not finite"), "{e}");
        assert!(MeshMotion::new(0.0, vec![], None, 2).is_err());
        assert!(MeshMotion::new(f32::NAN, vec![ok], None, 2).is_err());
    }
}

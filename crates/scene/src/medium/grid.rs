//! Heterogeneous media on a voxel grid: a dimensionless density per voxel, interpolated
//! trilinearly between voxel centres, and a coarse grid of majorants for tracking.
//!
//! The grid fills the unit cube of its own space, which `to_world` (an affine map) places in
//! the scene, as Mitsuba 3's `gridvolume` does: voxel (i, j, k) of an `nx × ny × nz` grid holds
//! the density at the grid-space point ((i + ½)/nx, (j + ½)/ny, (k + ½)/nz); between voxel
//! centres the density is trilinear, beyond the outermost centres it is clamped to the edge
//! voxels, and outside the unit cube it is 0.
//!
//! Tracking needs an upper bound of the density along a ray (the majorant). A single bound for
//! the whole grid makes thin smoke around a dense core cost as much as the core; instead the
//! grid is divided into cells of [`MAJORANT_CELL`]³ voxels, each storing the largest density
//! its trilinear interpolation can take (the maximum over the voxels whose centres influence
//! the cell), and [`MajorantSegments`] walks the cells a ray crosses with a 3-D DDA (Amanatides
//! and Woo 1987), the scheme of pbrt-v4's `MajorantGrid`.

use caustica_core::{Affine3A, Ray, Vec3};

/// Voxels per majorant cell along each axis.
pub const MAJORANT_CELL: u32 = 4;

/// A density grid placed in the scene.
#[derive(Clone, Debug)]
pub struct DensityGrid {
    res: [u32; 3],
    data: Vec<f32>,
    to_grid: Affine3A,
    world_diagonal: f32,
    max_density: f32,
    majorant_res: [u32; 3],
    majorants: Vec<f32>,
}

impl DensityGrid {
    /// A grid of `res` voxels with densities `data` (x fastest: index (k·ny + j)·nx + i), filling
    /// the image of the unit cube under `to_world`. Densities must be finite and non-negative,
    /// `res` non-zero and `to_world` invertible; the message names what is wrong.
    pub fn new(res: [u32; 3], data: Vec<f32>, to_world: Affine3A) -> Result<Self, String> {
        if res.contains(&0) {
            return Err(format!(
                "a density grid needs at least one voxel per axis, got {res:?}"
            ));
        }
        let n = res.iter().map(|&r| r as usize).product::<usize>();
        if data.len() != n {
            return Err(format!(
                "a {}×{}×{} grid needs {n} densities, got {}",
                res[0],
                res[1],
                res[2],
                data.len()
            ));
        }
        if let Some((i, v)) = data
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || **v < 0.0)
        {
            return Err(format!(
                "grid densities must be finite and non-negative, voxel {i} is {v}"
            ));
        }
        let det = to_world.matrix3.determinant();
        if !(det.is_finite() && det.abs() > 1e-20 && to_world.translation.is_finite()) {
            return Err("the grid's to_world transform is not invertible".into());
        }
        let to_grid = to_world.inverse();
        let world_diagonal = (to_world.matrix3.x_axis.abs()
            + to_world.matrix3.y_axis.abs()
            + to_world.matrix3.z_axis.abs())
        .length();
        let max_density = data.iter().copied().fold(0.0f32, f32::max);
        let mut g = Self {
            res,
            data,
            to_grid,
            world_diagonal,
            max_density,
            majorant_res: res.map(|r| r.div_ceil(MAJORANT_CELL)),
            majorants: Vec::new(),
        };
        g.majorants = g.build_majorants();
        Ok(g)
    }

    /// A grid of `res` voxels whose density at each voxel centre is `f` of the grid-space point
    /// in [0, 1]³ (procedural media of the built-in scenes).
    pub fn from_fn(
        res: [u32; 3],
        to_world: Affine3A,
        f: impl Fn(Vec3) -> f32,
    ) -> Result<Self, String> {
        Self::new(res, Self::sample_fn(res, f), to_world)
    }

    /// The densities [`DensityGrid::from_fn`] stores: `f` at the voxel centres of the unit cube,
    /// x fastest, clamped at 0 (also the data of the built-in scenes' `.vol` files).
    pub fn sample_fn(res: [u32; 3], f: impl Fn(Vec3) -> f32) -> Vec<f32> {
        let mut data = Vec::with_capacity(res.iter().map(|&r| r as usize).product());
        for k in 0..res[2] {
            for j in 0..res[1] {
                for i in 0..res[0] {
                    let u = Vec3::new(
                        (i as f32 + 0.5) / res[0] as f32,
                        (j as f32 + 0.5) / res[1] as f32,
                        (k as f32 + 0.5) / res[2] as f32,
                    );
                    data.push(f(u).max(0.0));
                }
            }
        }
        data
    }

    pub fn resolution(&self) -> [u32; 3] {
        self.res
    }
    /// Largest voxel density.
    pub fn max_density(&self) -> f32 {
        self.max_density
    }
    /// Length (m) of the diagonal of the grid's bounding box in the scene.
    pub fn world_diagonal(&self) -> f32 {
        self.world_diagonal
    }
    /// Bytes held by the voxels and majorants.
    pub fn memory_bytes(&self) -> usize {
        (self.data.len() + self.majorants.len()) * 4
    }

    #[inline]
    fn voxel(&self, i: u32, j: u32, k: u32) -> f32 {
        self.data[((k * self.res[1] + j) * self.res[0] + i) as usize]
    }

    /// Density at the grid-space point `q` (trilinear, 0 outside [0, 1]³).
    #[inline]
    pub fn density_grid_space(&self, q: Vec3) -> f32 {
        if !(q.cmpge(Vec3::ZERO).all() && q.cmple(Vec3::ONE).all()) {
            return 0.0;
        }
        let mut i0 = [0u32; 3];
        let mut i1 = [0u32; 3];
        let mut f = [0.0f32; 3];
        for a in 0..3 {
            let x = q[a] * self.res[a] as f32 - 0.5;
            let fl = x.floor();
            f[a] = x - fl;
            let max = self.res[a] as i64 - 1;
            i0[a] = (fl as i64).clamp(0, max) as u32;
            i1[a] = (fl as i64 + 1).clamp(0, max) as u32;
        }
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let c00 = lerp(
            self.voxel(i0[0], i0[1], i0[2]),
            self.voxel(i1[0], i0[1], i0[2]),
            f[0],
        );
        let c10 = lerp(
            self.voxel(i0[0], i1[1], i0[2]),
            self.voxel(i1[0], i1[1], i0[2]),
            f[0],
        );
        let c01 = lerp(
            self.voxel(i0[0], i0[1], i1[2]),
            self.voxel(i1[0], i0[1], i1[2]),
            f[0],
        );
        let c11 = lerp(
            self.voxel(i0[0], i1[1], i1[2]),
            self.voxel(i1[0], i1[1], i1[2]),
            f[0],
        );
        lerp(lerp(c00, c10, f[1]), lerp(c01, c11, f[1]), f[2])
    }

    /// Density at the world-space point `p`.
    #[inline]
    pub fn density(&self, p: Vec3) -> f32 {
        self.density_grid_space(self.to_grid.transform_point3(p))
    }

    fn build_majorants(&self) -> Vec<f32> {
        let [mx, my, mz] = self.majorant_res;
        let mut out = Vec::with_capacity((mx * my * mz) as usize);
        // The voxels whose centres influence grid-space interval [lo, hi] along an axis of `r`
        // voxels: those from floor(lo·r − ½) to floor(hi·r − ½) + 1, clamped.
        let range = |c: u32, m: u32, r: u32| {
            let lo = c as f32 / m as f32 * r as f32 - 0.5;
            let hi = (c + 1) as f32 / m as f32 * r as f32 - 0.5;
            let a = (lo.floor() as i64).clamp(0, r as i64 - 1) as u32;
            let b = (hi.floor() as i64 + 1).clamp(0, r as i64 - 1) as u32;
            a..=b
        };
        for c in 0..mz {
            for b in 0..my {
                for a in 0..mx {
                    let mut m = 0.0f32;
                    for k in range(c, mz, self.res[2]) {
                        for j in range(b, my, self.res[1]) {
                            for i in range(a, mx, self.res[0]) {
                                m = m.max(self.voxel(i, j, k));
                            }
                        }
                    }
                    out.push(m);
                }
            }
        }
        out
    }

    /// The majorant cells `ray` crosses between `t0` and `t1`, in order.
    pub fn majorant_segments(&self, ray: &Ray, t0: f32, t1: f32) -> MajorantSegments<'_> {
        MajorantSegments::new(self, ray, t0, t1)
    }

    /// ∫_{t0}^{t1} d(ray(t)) dt (m) by the midpoint rule with steps of at most half the
    /// smallest voxel's extent along the ray.
    pub fn integrate_density(&self, ray: &Ray, t0: f32, t1: f32) -> f32 {
        let mut total = 0.0f64;
        for (a, b, maj) in self.majorant_segments(ray, t0, t1) {
            if maj <= 0.0 {
                continue;
            }
            let d = self.to_grid.transform_vector3(ray.d);
            let per_t = (d * Vec3::new(self.res[0] as f32, self.res[1] as f32, self.res[2] as f32))
                .abs()
                .max_element();
            let n = (((b - a) * per_t * 2.0).ceil() as usize).clamp(1, 1 << 16);
            let h = (b - a) / n as f32;
            let mut s = 0.0f64;
            for i in 0..n {
                s += self.density(ray.at(a + (i as f32 + 0.5) * h)) as f64;
            }
            total += s * h as f64;
        }
        total as f32
    }
}

/// The majorant cells along a ray: `(t_start, t_end, majorant density)` in ray order, covering
/// the part of `[t0, t1]` inside the grid's box (outside it the density is 0).
pub struct MajorantSegments<'a> {
    grid: &'a DensityGrid,
    cell: [i32; 3],
    step: [i32; 3],
    next_t: [f32; 3],
    delta_t: [f32; 3],
    t: f32,
    t_end: f32,
}

impl<'a> MajorantSegments<'a> {
    fn new(grid: &'a DensityGrid, ray: &Ray, t0: f32, t1: f32) -> Self {
        let o = grid.to_grid.transform_point3(ray.o);
        let d = grid.to_grid.transform_vector3(ray.d);
        // Clip [t0, t1] to the unit cube (slab test).
        let mut lo = t0;
        let mut hi = t1;
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < 0.0 || o[a] > 1.0 {
                    hi = f32::NEG_INFINITY;
                }
                continue;
            }
            let inv = 1.0 / d[a];
            let (ta, tb) = ((0.0 - o[a]) * inv, (1.0 - o[a]) * inv);
            lo = lo.max(ta.min(tb));
            hi = hi.min(ta.max(tb));
        }
        let m = grid.majorant_res;
        let mut s = Self {
            grid,
            cell: [0; 3],
            step: [0; 3],
            next_t: [f32::INFINITY; 3],
            delta_t: [f32::INFINITY; 3],
            t: lo,
            t_end: hi,
        };
        if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
            s.t_end = f32::NEG_INFINITY;
            return s;
        }
        let p = o + d * lo;
        for a in 0..3 {
            let mr = m[a] as f32;
            let c = ((p[a] * mr).floor() as i32).clamp(0, m[a] as i32 - 1);
            s.cell[a] = c;
            if d[a] > 0.0 {
                s.step[a] = 1;
                s.delta_t[a] = 1.0 / (d[a] * mr);
                s.next_t[a] = lo + ((c + 1) as f32 / mr - p[a]) / d[a];
            } else if d[a] < 0.0 {
                s.step[a] = -1;
                s.delta_t[a] = -1.0 / (d[a] * mr);
                s.next_t[a] = lo + (c as f32 / mr - p[a]) / d[a];
            }
        }
        s
    }
}

impl Iterator for MajorantSegments<'_> {
    type Item = (f32, f32, f32);
    fn next(&mut self) -> Option<(f32, f32, f32)> {
        if self.t.partial_cmp(&self.t_end) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        let m = self.grid.majorant_res;
        let idx = ((self.cell[2] as u32 * m[1] + self.cell[1] as u32) * m[0] + self.cell[0] as u32)
            as usize;
        let maj = self.grid.majorants[idx];
        // Axis whose cell boundary comes first.
        let a = if self.next_t[0] <= self.next_t[1] && self.next_t[0] <= self.next_t[2] {
            0
        } else if self.next_t[1] <= self.next_t[2] {
            1
        } else {
            2
        };
        let t_exit = self.next_t[a].min(self.t_end);
        let seg = (self.t, t_exit.max(self.t), maj);
        self.t = t_exit;
        self.cell[a] += self.step[a];
        self.next_t[a] += self.delta_t[a];
        if self.cell[a] < 0 || self.cell[a] >= m[a] as i32 {
            self.t_end = f32::NEG_INFINITY;
        }
        Some(seg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn ramp_grid(res: u32) -> DensityGrid {
        // Density x along x (grid space = world space): trilinear reproduces it exactly
        // between the first and last voxel centres.
        DensityGrid::from_fn([res, 3, 2], Affine3A::IDENTITY, |u| u.x).unwrap()
    }

    #[test]
    fn trilinear_interpolates_between_voxel_centres_and_is_zero_outside() {
        let g = ramp_grid(8);
        for x in [0.07f32, 0.2, 0.5, 0.93] {
            let d = g.density(Vec3::new(x, 0.4, 0.6));
            assert!((d - x).abs() < 1e-5, "x {x}: {d}");
        }
        // Clamped beyond the outermost centres, 0 outside the box.
        assert!((g.density(Vec3::new(0.01, 0.5, 0.5)) - 1.0 / 16.0).abs() < 1e-6);
        assert_eq!(g.density(Vec3::new(1.01, 0.5, 0.5)), 0.0);
        assert_eq!(g.density(Vec3::new(0.5, -0.01, 0.5)), 0.0);
    }

    #[test]
    fn majorants_bound_the_density_everywhere_along_rays() {
        let mut rng = Pcg32::new(5, 6);
        let data: Vec<f32> = (0..17 * 9 * 13).map(|_| rng.next_f32().powi(4)).collect();
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::new(2.0, 1.0, 0.5),
            glam::Quat::from_rotation_y(0.4),
            Vec3::new(-1.0, 0.2, 0.1),
        );
        let g = DensityGrid::new([17, 9, 13], data, to_world).unwrap();
        for _ in 0..300 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 6.0 - 3.0;
            let d = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5).normalize();
            let ray = Ray::new(o, d);
            let mut last = f32::NEG_INFINITY;
            let mut covered = 0.0;
            for (a, b, maj) in g.majorant_segments(&ray, 0.0, 10.0) {
                assert!(a >= last - 1e-5 && b >= a, "segments out of order");
                last = b;
                covered += b - a;
                for i in 0..20 {
                    let t = a + (b - a) * (i as f32 + 0.5) / 20.0;
                    let dens = g.density(ray.at(t));
                    assert!(dens <= maj + 1e-6, "density {dens} above majorant {maj}");
                }
            }
            // Every point of the ray with a positive density lies in some segment.
            let mut inside = 0.0;
            for i in 0..2000 {
                let q = g.to_grid.transform_point3(ray.at((i as f32 + 0.5) * 0.005));
                if q.cmpge(Vec3::ZERO).all() && q.cmple(Vec3::ONE).all() {
                    inside += 0.005;
                }
            }
            assert!(
                (covered - inside).abs() < 0.02,
                "covered {covered} vs inside {inside}"
            );
        }
    }

    #[test]
    fn density_integral_is_exact_on_a_ramp() {
        let g = ramp_grid(16);
        // Along x from the first to the last voxel centre the density is x itself.
        let ray = Ray::new(Vec3::new(0.0, 0.5, 0.5), Vec3::X);
        let (a, b) = (1.0 / 32.0, 31.0 / 32.0);
        let got = g.integrate_density(&ray, a, b);
        let want = (b * b - a * a) / 2.0;
        assert!((got - want).abs() < 1e-4, "{got} vs {want}");
    }

    #[test]
    fn bad_grids_are_refused() {
        assert!(DensityGrid::new([0, 1, 1], vec![], Affine3A::IDENTITY).is_err());
        assert!(DensityGrid::new([2, 1, 1], vec![1.0], Affine3A::IDENTITY).is_err());
        let e = DensityGrid::new([2, 1, 1], vec![1.0, f32::NAN], Affine3A::IDENTITY).unwrap_err();
        assert!(e.contains("voxel 1"), "{e}");
        assert!(DensityGrid::new([1, 1, 1], vec![-1.0], Affine3A::IDENTITY).is_err());
        assert!(DensityGrid::new([1, 1, 1], vec![1.0], Affine3A::from_scale(Vec3::ZERO)).is_err());
    }
}

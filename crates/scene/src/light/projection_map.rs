//! Projection maps (Jensen 1996; Jensen, *Realistic Image Synthesis Using Photon Mapping*,
//! sec. 5.2): where in each light's emission the caustic photons come from.
//!
//! A caustic light path L S+ D starts with an emitted ray whose first surface is specular
//! (delta: mirror, smooth glass or metal). On the glass sphere only 0.4 % of a point light's
//! directions reach the ball, so uniform emission wastes 99.6 % of its caustic light paths.
//!
//! # The map
//!
//! A light turns primary samples `(u_pos, u_dir) ∈ [0, 1)⁴` into an emitted ray
//! ([`super::LightSource::sample_emission`]). The map is a grid over that primary sample space,
//! per light: `R_p × R_p` cells over `u_pos` and `R_d × R_d` over `u_dir`, with `R = 1` for the
//! numbers a light ignores (a point or spot light has no position to sample, a directional or
//! beam light no direction). A cell is *marked* when one of a few test rays through it (fixed,
//! stratified and jittered by a hash of the cell: deterministic) meets a surface that
//! [`Material::can_be_delta`] first, passing index-matched boundaries; marked cells are then
//! dilated by one cell along every grid axis, so the thin rims a few test rays miss are covered.
//! Occlusion is taken into account (a ray stopped by a wall marks nothing), which Jensen's
//! bounding-sphere projection does not.
//!
//! # Sampling, without bias
//!
//! Test rays can still miss a specular object smaller than a cell. So that no caustic path is
//! ever impossible, guided emission is a one-sample mixture of two techniques (Veach's
//! defensive importance sampling): with probability `1 − ε` a marked cell is chosen (light `l`'s
//! cells in proportion to `P_l / C_l`: the light's power over its number of cells) and a point
//! uniformly inside it; with probability `ε` ([`DEFENSIVE`]) the light is chosen in proportion
//! to power and `(u_pos, u_dir)` uniformly, as uniform emission does. The joint density of
//! light `l` and primary sample `u` is
//!
//! `p(l, u) = (1 − ε) P_l [u ∈ M_l] / S_m + ε P_l / S`, with `S = Σ P_l` and
//! `S_m = Σ P_l m_l` (`m_l` = the fraction of light `l`'s cells that are marked),
//!
//! and relative to uniform emission (`P_l / S`) the density is
//! `p_rel(l, u) = (1 − ε) (S / S_m) [u ∈ M_l] + ε` ([`EmissionDensity::total`]). An emitted
//! path's flux is the uniform one divided by `p_rel`; a path emitted into a marked cell of the
//! glass sphere carries ≈ 1/150 of a uniform path's flux, and ≈ 99 % of them reach the ball
//! instead of 0.4 %. Global photons are unaffected (they are emitted uniformly).
//!
//! # Photon differentials (seed 002 eq. 5–6)
//!
//! Eq. 5–6 size a photon's initial differential vectors so that `N_e` photons tile the light's
//! area `A_e` and solid angle `ω_e`: `|D_u x| = 2 s √(A_e / (π N_e))`. Where guided emission
//! emits with relative density `p_rel`, photons are `p_rel` times as dense, so each stands for
//! a `p_rel` times smaller share and the vectors shrink by `1 / √p_rel` — split between the
//! two halves of the emission: the positional vectors by the density of the *origins*,
//! `p_pos(u_pos) = ∫ p_rel du_dir` (the marginal over the directions), and the directional
//! ones by the density of directions *given* the origin, `p_dir = p_rel / p_pos`
//! ([`EmissionDensity`]). For a point light `p_pos = 1`; for a collimated light `p_dir = 1`.
//! The photons' areas then still sum to `s² A_e` in expectation: `E[1/p_rel] = 1` over the
//! guided density.

use super::Light;
use crate::Scene;
use caustica_core::sampling::Distribution1D;
use caustica_core::sampling::rng::hash_u64;
use caustica_core::sampling::sampler::ONE_MINUS_EPSILON;
use caustica_core::{Ray, Vec2};
use rayon::prelude::*;

/// Probability `ε` of the uniform technique in the defensive mixture (see the module docs):
/// the share of light paths emitted uniformly, so that a caustic a test ray missed still gets
/// photons (weighted `1/ε` relative to uniform, never infinitely). It costs `ε` of the yield.
pub const DEFENSIVE: f32 = 0.1;

/// Test rays per cell of a map over two numbers (point, spot, directional, beam lights), in a
/// 2 × 2 stratified pattern.
const TESTS_2D: u32 = 4;
/// Test rays per cell of a map over four numbers (area and environment lights).
const TESTS_4D: u32 = 2;
/// Surfaces a test ray passes (index-matched boundaries) before giving up.
const MAX_PASSES: u32 = 64;

/// Cells per axis of one light's map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Cells per axis of `u_pos` (1: the light samples no position).
    pub pos: u32,
    /// Cells per axis of `u_dir` (1: the light samples no direction).
    pub dir: u32,
}

impl Grid {
    /// The grid for a light type: 256² cells over the one pair of numbers a point-like or
    /// collimated light uses; 4² × 128² over both pairs (the direction matters more than the point of a light far from what it lights) for area and environment lights.
    pub fn for_light(light: &Light) -> Self {
        match light {
            Light::Point(_) | Light::Spot(_) => Self { pos: 1, dir: 256 },
            Light::Directional(_) | Light::Beam(_) => Self { pos: 256, dir: 1 },
            Light::Area(_) | Light::Environment(_) => Self { pos: 4, dir: 128 },
        }
    }
    /// Cells over the directions (`R_d²`).
    fn dir_cells(&self) -> usize {
        (self.dir * self.dir) as usize
    }
    /// Cells in all (`R_p² R_d²`).
    pub fn cells(&self) -> usize {
        (self.pos * self.pos) as usize * self.dir_cells()
    }
    /// The cell holding `(u_pos, u_dir)`: `pos_index · R_d² + dir_index`, row-major.
    fn cell_of(&self, u_pos: Vec2, u_dir: Vec2) -> usize {
        let ax = |u: f32, r: u32| ((u * r as f32) as u32).min(r - 1) as usize;
        let pi = ax(u_pos.y, self.pos) * self.pos as usize + ax(u_pos.x, self.pos);
        let di = ax(u_dir.y, self.dir) * self.dir as usize + ax(u_dir.x, self.dir);
        pi * self.dir_cells() + di
    }
    /// The point of cell `cell` at offsets `(o_pos, o_dir) ∈ [0, 1)⁴` inside it.
    fn point_in(&self, cell: usize, o_pos: Vec2, o_dir: Vec2) -> (Vec2, Vec2) {
        let (pi, di) = (cell / self.dir_cells(), cell % self.dir_cells());
        let at = |i: usize, r: u32, o: Vec2| {
            let r_us = r as usize;
            let (x, y) = ((i % r_us) as f32, (i / r_us) as f32);
            (Vec2::new(x + o.x, y + o.y) / r as f32).min(Vec2::splat(ONE_MINUS_EPSILON))
        };
        (at(pi, self.pos, o_pos), at(di, self.dir, o_dir))
    }
    /// The cell's integer coordinates (pos x, pos y, dir x, dir y).
    fn coords(&self, cell: usize) -> [i64; 4] {
        let (pi, di) = (cell / self.dir_cells(), cell % self.dir_cells());
        let (p, d) = (self.pos as usize, self.dir as usize);
        [
            (pi % p) as i64,
            (pi / p) as i64,
            (di % d) as i64,
            (di / d) as i64,
        ]
    }
    fn index(&self, c: [i64; 4]) -> Option<usize> {
        let (p, d) = (self.pos as i64, self.dir as i64);
        let inside = |v: i64, r: i64| (0..r).contains(&v);
        (inside(c[0], p) && inside(c[1], p) && inside(c[2], d) && inside(c[3], d))
            .then(|| ((c[1] * p + c[0]) as usize) * self.dir_cells() + (c[3] * d + c[2]) as usize)
    }
}

/// One light's marked cells.
#[derive(Clone, Debug)]
pub struct LightCells {
    pub grid: Grid,
    /// Per cell: true if marked.
    marked: Vec<bool>,
    /// Per position cell: how many of its direction cells are marked.
    row_marked: Vec<u32>,
    /// Marked cells.
    pub count: usize,
}

impl LightCells {
    /// The fraction `m_l` of the light's primary sample space that is marked.
    pub fn fraction(&self) -> f64 {
        self.count as f64 / self.grid.cells() as f64
    }
}

/// Relative densities of a guided emission against uniform emission (1 = uniform): `pos` for
/// the origin (`p_pos`, the marginal over directions), `dir` for the direction given the
/// origin (`p_dir`); see the module docs. Photon differentials divide their initial positional
/// vectors by `√pos` and directional ones by `√dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionDensity {
    pub pos: f32,
    pub dir: f32,
}

impl EmissionDensity {
    /// Uniform emission.
    pub const UNIFORM: Self = Self { pos: 1.0, dir: 1.0 };
    /// `p_rel = p_pos p_dir`: the path's flux is divided by it.
    #[inline]
    pub fn total(&self) -> f32 {
        self.pos * self.dir
    }
}

/// A guided emission: the light and the primary samples to give its `sample_emission`.
#[derive(Clone, Copy, Debug)]
pub struct GuidedStart {
    pub light: usize,
    /// The light's probability under uniform emission (power-proportional): the caller divides
    /// by it as for uniform emission, and by [`EmissionDensity::total`].
    pub pmf: f32,
    pub u_pos: Vec2,
    pub u_dir: Vec2,
    pub density: EmissionDensity,
}

/// The projection maps of a scene's lights (see the module docs).
#[derive(Clone, Debug)]
pub struct ProjectionMap {
    /// Per light (parallel to `Scene::lights`): its cells, `None` for a light without power.
    pub lights: Vec<Option<LightCells>>,
    /// Every marked cell as `(light, cell)`, in light and cell order.
    cells: Vec<(u32, u32)>,
    /// Over `cells`, in proportion to `pmf_l / C_l`; `None` when no cell is marked.
    cell_distribution: Option<Distribution1D>,
    /// `S / S_m`: the marked cells' density boost (see the module docs).
    boost: f32,
    /// Problems found while building (no marked cell, lights skipped).
    pub warnings: Vec<String>,
    /// Test rays traced to build the map.
    pub test_rays: u64,
    /// Wall-clock time the build took (s).
    pub build_secs: f64,
}

impl ProjectionMap {
    /// Builds the maps of every light of `scene` from its BVH: deterministic (test rays are a
    /// hash of the cell), parallel over cells.
    pub fn build(scene: &Scene) -> Self {
        let start = std::time::Instant::now();
        let mut warnings = Vec::new();
        let mut test_rays = 0u64;
        let pmf = |l: usize| scene.light_pmf(l as u32);
        let lights: Vec<Option<LightCells>> = scene
            .lights
            .iter()
            .enumerate()
            .map(|(li, light)| {
                if pmf(li) <= 0.0 || pmf(li).is_nan() {
                    warnings.push(format!(
                        "light {li} emits no power: skipped by the projection map"
                    ));
                    return None;
                }
                let grid = Grid::for_light(light);
                let tests = if grid.pos > 1 && grid.dir > 1 {
                    TESTS_4D
                } else {
                    TESTS_2D
                };
                test_rays += grid.cells() as u64 * tests as u64;
                let hits: Vec<bool> = (0..grid.cells())
                    .into_par_iter()
                    .map(|cell| {
                        (0..tests).any(|k| {
                            let (o_pos, o_dir) = test_offsets(li, cell, k, tests);
                            let (u_pos, u_dir) = grid.point_in(cell, o_pos, o_dir);
                            let es = light.sample_emission(u_pos, u_dir);
                            es.pdf_pos > 0.0
                                && es.pdf_dir > 0.0
                                && !es.weight.is_black()
                                && first_surface_is_delta(scene, es.spawn_ray())
                        })
                    })
                    .collect();
                let marked = dilate(&grid, &hits);
                let mut row_marked = vec![0u32; (grid.pos * grid.pos) as usize];
                for (cell, &m) in marked.iter().enumerate() {
                    row_marked[cell / grid.dir_cells()] += m as u32;
                }
                let count = marked.iter().filter(|&&m| m).count();
                Some(LightCells {
                    grid,
                    marked,
                    row_marked,
                    count,
                })
            })
            .collect();
        let mut cells = Vec::new();
        let mut weights = Vec::new();
        let mut s_m = 0.0f64;
        for (li, lc) in lights.iter().enumerate() {
            let Some(lc) = lc else { continue };
            let w = pmf(li) as f64 / lc.grid.cells() as f64;
            s_m += pmf(li) as f64 * lc.fraction();
            for (cell, _) in lc.marked.iter().enumerate().filter(|(_, m)| **m) {
                cells.push((li as u32, cell as u32));
                weights.push(w as f32);
            }
        }
        let cell_distribution = Distribution1D::new(&weights);
        if cell_distribution.is_none() && !scene.lights.is_empty() {
            warnings.push(
                "projection map: no light reaches a mirror, glass or smooth metal surface; caustic \
                 photons are emitted uniformly"
                    .into(),
            );
        }
        // Σ pmf_l = 1 = S (normalised), so S / S_m = 1 / Σ pmf_l m_l.
        let boost = if s_m > 0.0 { (1.0 / s_m) as f32 } else { 1.0 };
        Self {
            lights,
            cells,
            cell_distribution,
            boost,
            warnings,
            test_rays,
            build_secs: start.elapsed().as_secs_f64(),
        }
    }

    /// True when no cell is marked: emission is uniform.
    pub fn is_empty(&self) -> bool {
        self.cell_distribution.is_none()
    }

    /// The marked share of the scene's emission, `S_m / S` (power-weighted): the caustic yield
    /// of uniform emission is at most this.
    pub fn marked_fraction(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            1.0 / self.boost as f64
        }
    }

    /// Marked cells over all lights.
    pub fn marked_cells(&self) -> usize {
        self.cells.len()
    }

    /// Cells over all lights with a map.
    pub fn total_cells(&self) -> usize {
        self.lights.iter().flatten().map(|l| l.grid.cells()).sum()
    }

    /// The guided emission for primary samples `u_light`, `u_pos`, `u_dir` (uniform in
    /// [0, 1)): the defensive mixture of the module docs, `u_light` choosing the technique and
    /// then the light or the cell, `u_pos` and `u_dir` the point (within the cell). `lights`
    /// is the scene's power distribution. `None` if the map is empty (emit uniformly instead).
    pub fn sample(
        &self,
        lights: &Distribution1D,
        u_light: f32,
        u_pos: Vec2,
        u_dir: Vec2,
    ) -> Option<GuidedStart> {
        let cells = self.cell_distribution.as_ref()?;
        let (light, u_pos, u_dir) = if u_light < DEFENSIVE {
            let u = (u_light / DEFENSIVE).min(ONE_MINUS_EPSILON);
            let (li, _, _) = lights.sample(u);
            (li, u_pos, u_dir)
        } else {
            let u = ((u_light - DEFENSIVE) / (1.0 - DEFENSIVE)).min(ONE_MINUS_EPSILON);
            let (k, _, _) = cells.sample(u);
            let (li, cell) = self.cells[k];
            let grid = self.lights[li as usize].as_ref()?.grid;
            let (p, d) = grid.point_in(cell as usize, u_pos, u_dir);
            (li as usize, p, d)
        };
        Some(GuidedStart {
            light,
            pmf: lights.pmf(light),
            u_pos,
            u_dir,
            density: self.density(light, u_pos, u_dir),
        })
    }

    /// The relative density with which [`Self::sample`] emits light `light` at primary samples
    /// `(u_pos, u_dir)` (uniform emission when the map is empty).
    pub fn density(&self, light: usize, u_pos: Vec2, u_dir: Vec2) -> EmissionDensity {
        let eps = DEFENSIVE;
        let Some(Some(lc)) = self.lights.get(light) else {
            return if self.is_empty() {
                EmissionDensity::UNIFORM
            } else {
                EmissionDensity { pos: eps, dir: 1.0 }
            };
        };
        if self.is_empty() {
            return EmissionDensity::UNIFORM;
        }
        let cell = lc.grid.cell_of(u_pos, u_dir);
        let total = if lc.marked[cell] {
            (1.0 - eps) * self.boost + eps
        } else {
            eps
        };
        // p_pos = ∫ p_rel du_dir = (1 − ε) boost (marked in the row / R_d²) + ε.
        let row = lc.row_marked[cell / lc.grid.dir_cells()] as f32 / lc.grid.dir_cells() as f32;
        let pos = (1.0 - eps) * self.boost * row + eps;
        EmissionDensity {
            pos,
            dir: total / pos,
        }
    }
}

/// Offsets of test ray `k` of `tests` inside cell `cell` of light `light`: stratified over the
/// numbers the cell spans and jittered by a hash (deterministic).
fn test_offsets(light: usize, cell: usize, k: u32, tests: u32) -> (Vec2, Vec2) {
    let h = hash_u64(((light as u64) << 40) ^ ((cell as u64) << 8) ^ k as u64);
    let unit = |bits: u64| (bits & 0xFFFF) as f32 / 65536.0;
    let j = [unit(h), unit(h >> 16), unit(h >> 32), unit(h >> 48)];
    if tests == TESTS_2D {
        // 2 × 2 strata, the same in both pairs (a light uses one of them).
        let (sx, sy) = ((k % 2) as f32, (k / 2) as f32);
        let o = Vec2::new((sx + j[0]) / 2.0, (sy + j[1]) / 2.0);
        (o, o)
    } else {
        (Vec2::new(j[0], j[1]), Vec2::new(j[2], j[3]))
    }
}

/// True if the first surface `ray` meets, passing index-matched boundaries, can scatter deltas.
fn first_surface_is_delta(scene: &Scene, mut ray: Ray) -> bool {
    for _ in 0..MAX_PASSES {
        let Some(si) = scene.intersect(&ray) else {
            return false;
        };
        match scene.materials.get(si.material as usize) {
            Some(m) if m.is_null() => ray = si.spawn_ray(ray.d),
            Some(m) => return m.can_be_delta(),
            None => return false,
        }
    }
    false
}

/// `hits` dilated by one cell along every axis of the grid (the 3⁴ neighbourhood in cell
/// coordinates; axes of one cell do not spread).
fn dilate(grid: &Grid, hits: &[bool]) -> Vec<bool> {
    let mut out = hits.to_vec();
    for (cell, _) in hits.iter().enumerate().filter(|(_, h)| **h) {
        let c = grid.coords(cell);
        for d0 in -1..=1 {
            for d1 in -1..=1 {
                for d2 in -1..=1 {
                    for d3 in -1..=1 {
                        if let Some(i) = grid.index([c[0] + d0, c[1] + d1, c[2] + d2, c[3] + d3]) {
                            out[i] = true;
                        }
                    }
                }
            }
        }
    }
    out
}

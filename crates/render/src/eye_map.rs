//! The eye-path map of photon differential splatting (seed 002 sec. 3.3): the first non-delta
//! vertex of every camera sample — seen directly or through mirrors and glass (paths D S* E) —
//! with what is needed to add a photon's reflected radiance (one term of eq. 10) to its pixel:
//! position, the direction toward the camera, the BSDF, the path throughput ("importance") and
//! the pixel index; and a k-d tree over the positions.
//!
//! A photon splats by a range query within its footprint's gather radius around its centre;
//! each vertex the footprint reaches ([`FootprintFilter::weight`], the rule `pdm` gathers with)
//! receives `f_r(x, ω_p, ω) π K(|M_p (x − x_p)|) Φ_p / A_p` (W/m²/sr) in its own accumulator.
//! The pixel receives `β · Σ` at the end, exactly the term `pdm` adds to that camera sample
//! (the eye vertices are those of `pdm`'s camera pass: same sampler, same paths).
//!
//! **Tiles.** The vertices are sorted into a locality-preserving order (k-d tree order) and cut
//! into tiles of [`TILE`] vertices, each with its own bounding box and k-d tree. Splatting runs
//! in parallel over tiles: a tile takes the photons of a batch in order, skips those whose
//! gather sphere misses its box and adds the others to its own accumulators. No splat lists,
//! no shared writes, and every vertex sums its photons in photon order, so the image does not
//! depend on the thread count and memory does not depend on how many vertices a photon covers.

use crate::photon_differential::{DiffPhoton, FootprintFilter};
use crate::surface::Vertex;
use caustica_core::{Frame, Spectrum, Vec3};
use caustica_density::kdtree::KdTree;
use caustica_scene::bsdf::{Bsdf, TransportMode};

/// One eye-path vertex: the first non-delta surface of a camera sample.
#[derive(Clone, Copy, Debug)]
pub struct EyeVertex {
    /// Position (m).
    pub p: Vec3,
    /// Geometric normal on the camera's side (unit).
    pub n: Vec3,
    /// Direction toward the camera, in the shading frame.
    pub wo: Vec3,
    pub frame: Frame,
    pub bsdf: Bsdf,
    /// Throughput of the camera path up to this vertex (the product of the delta vertices'
    /// weights and interior transmittances; 1 when seen directly).
    pub beta: Spectrum,
    /// Index `y · width + x` of the pixel whose sample this is.
    pub pixel: u32,
}

impl EyeVertex {
    /// The record of vertex `v` of a camera sample of pixel `pixel` with throughput `beta`.
    pub fn new(v: &Vertex, beta: Spectrum, pixel: u32) -> Self {
        let wo_world = v.frame.to_world(v.wo);
        let ng = v.si.ng;
        Self {
            p: v.si.p,
            n: if ng.dot(wo_world) >= 0.0 { ng } else { -ng },
            wo: v.wo,
            frame: v.frame,
            bsdf: v.bsdf,
            beta,
            pixel,
        }
    }
}

/// Eye vertices per tile.
pub const TILE: usize = 1 << 13;

/// A spatially compact group of eye vertices with its bounding box and k-d tree.
pub struct EyeTile {
    pub vertices: Vec<EyeVertex>,
    tree: KdTree,
    lo: Vec3,
    hi: Vec3,
}

impl EyeTile {
    fn new(vertices: Vec<EyeVertex>) -> Self {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.p).collect();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in positions.iter().filter(|p| p.is_finite()) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        Self {
            tree: KdTree::build(&positions),
            vertices,
            lo,
            hi,
        }
    }

    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Splats photon `p` onto this tile: calls `add(i, L)` with the reflected radiance
    /// `L = f_r π K(|M_p (x − x_p)|) Φ_p / A_p` (W/m²/sr, before the throughput β; seed 002
    /// eq. 10–12 with `filter`) for every vertex `i` of the tile its footprint reaches, found by a
    /// query over the footprint's bounding box. Returns the number of vertices reached.
    pub fn splat(
        &self,
        p: &BoxedPhoton,
        filter: &FootprintFilter,
        mut add: impl FnMut(usize, Spectrum),
    ) -> usize {
        if p.lo.cmpgt(self.hi).any() || p.hi.cmplt(self.lo).any() {
            return 0;
        }
        let ph = p.photon;
        let mut n = 0;
        self.tree.range_box(p.lo, p.hi, |i| {
            let v = &self.vertices[i as usize];
            let Some(w) = filter.weight(ph, v.p, v.n) else {
                return;
            };
            let f = v
                .bsdf
                .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
            let l = f * ph.flux * w;
            if l.is_finite() && !l.is_black() {
                add(i as usize, l);
                n += 1;
            }
        });
        n
    }
}

/// A photon with the bounding box of the points its footprint can reach, computed once per
/// photon (every tile tests it).
#[derive(Clone, Copy, Debug)]
pub struct BoxedPhoton<'a> {
    pub photon: &'a DiffPhoton,
    lo: Vec3,
    hi: Vec3,
}

impl<'a> BoxedPhoton<'a> {
    /// The box of `photon` under `filter`: the ellipse's bounding box, `x_p ± √(u² + v²)` per
    /// axis for the conjugate semi-diameters `u = ½ D_u x`, `v = ½ D_v x` (tighter than the
    /// sphere of the gather radius for elongated footprints), widened along `n_p` by the
    /// normal-distance threshold (at most the gather radius). `None` if it is not finite.
    pub fn new(photon: &'a DiffPhoton, filter: &FootprintFilter) -> Option<Self> {
        let fp = &photon.footprint;
        let [u, v] = fp.conjugate_semi_diameters();
        let slab = fp.normal().abs() * (filter.normal_distance.min(1.0) * fp.gather_radius());
        let half = (u * u + v * v).sqrt() + slab;
        let c = fp.center();
        (half.is_finite() && c.is_finite()).then_some(Self {
            photon,
            lo: c - half,
            hi: c + half,
        })
    }
}

/// The eye vertices of an image in tiles (see the module docs).
pub struct EyeMap {
    pub tiles: Vec<EyeTile>,
}

impl EyeMap {
    /// The map of `vertices` (any order; the map reorders them).
    pub fn new(vertices: Vec<EyeVertex>) -> Self {
        Self::with_tile_size(vertices, TILE)
    }

    /// [`EyeMap::new`] with `tile` vertices per tile (≥ 1).
    pub fn with_tile_size(vertices: Vec<EyeVertex>, tile: usize) -> Self {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.p).collect();
        let order: Vec<u32> = KdTree::build(&positions).indices_in_tree_order().collect();
        drop(positions);
        // Vertices with a non-finite position are not in the tree and can receive nothing.
        let sorted: Vec<EyeVertex> = order.iter().map(|&i| vertices[i as usize]).collect();
        drop(vertices);
        let tiles = sorted
            .chunks(tile.max(1))
            .map(|c| EyeTile::new(c.to_vec()))
            .collect();
        Self { tiles }
    }

    /// Number of eye vertices.
    pub fn len(&self) -> usize {
        self.tiles.iter().map(EyeTile::len).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes held by the vertices and the trees.
    pub fn memory_bytes(&self) -> usize {
        self.tiles
            .iter()
            .map(|t| {
                std::mem::size_of::<EyeTile>()
                    + t.vertices.capacity() * std::mem::size_of::<EyeVertex>()
                    + t.tree.memory_bytes()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_density::kernel::Kernel;
    use caustica_differentials::Footprint;
    use caustica_scene::bsdf::Lambertian;
    use std::f32::consts::PI;

    const ALBEDO: f32 = 0.5;

    /// A vertex on the floor y = 0 (normal +y) seen from straight above.
    fn vertex(p: Vec3, n: Vec3, pixel: u32) -> EyeVertex {
        let frame = Frame::from_normal(n);
        EyeVertex {
            p,
            n,
            wo: frame.to_local(n),
            frame,
            bsdf: Bsdf::Lambertian(Lambertian::new(Spectrum::splat(ALBEDO))),
            beta: Spectrum::ONE,
            pixel,
        }
    }

    /// A photon of flux 2 W landing at the origin from straight above, footprint semi-axes
    /// 0.2 m along x and 0.05 m along z (D x = twice the semi-axes).
    fn photon() -> DiffPhoton {
        DiffPhoton {
            footprint: Footprint::new(
                Vec3::ZERO,
                Vec3::new(0.4, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 0.1),
                Vec3::Y,
            )
            .unwrap(),
            wi: Vec3::Y,
            n: Vec3::Y,
            flux: Spectrum::splat(2.0),
            depth: 2,
        }
    }

    /// (pixel, radiance) of every vertex `photon()` reaches, by pixel; tiles of two vertices so
    /// that the tile culling is exercised too.
    fn splats(map: &EyeMap, filter: &FootprintFilter) -> Vec<(u32, Spectrum)> {
        let mut out = Vec::new();
        let ph = photon();
        let boxed = BoxedPhoton::new(&ph, filter).expect("a finite footprint");
        for t in &map.tiles {
            let n = t.splat(&boxed, filter, |i, l| out.push((t.vertices[i].pixel, l)));
            assert!(n <= t.len());
        }
        out.sort_by_key(|s| s.0);
        out
    }

    fn tiled(vertices: Vec<EyeVertex>) -> EyeMap {
        EyeMap::with_tile_size(vertices, 2)
    }

    #[test]
    fn a_splat_reaches_exactly_the_vertices_inside_the_ellipse() {
        let map = tiled(vec![
            vertex(Vec3::ZERO, Vec3::Y, 0),                   // centre
            vertex(Vec3::new(0.15, 0.0, 0.0), Vec3::Y, 1),    // inside, along the long axis
            vertex(Vec3::new(0.0, 0.0, 0.06), Vec3::Y, 2),    // outside, across
            vertex(Vec3::new(0.21, 0.0, 0.0), Vec3::Y, 3),    // outside, along
            vertex(Vec3::new(0.0, 0.0, 0.0), Vec3::NEG_Y, 4), // the underside
        ]);
        let f = FootprintFilter::default();
        let s = splats(&map, &f);
        let ids: Vec<u32> = s.iter().map(|s| s.0).collect();
        assert_eq!(ids, vec![0, 1]);
        // Eq. 10–12 at the centre: f_r Φ π K(0) / A, K(0) = 3/π (eq. 11), A = π · 0.2 · 0.05.
        let area = PI * 0.2 * 0.05;
        let expected = ALBEDO / PI * 2.0 * 3.0 / area;
        let got = s[0].1.c[0];
        assert!((got / expected - 1.0).abs() < 1e-5, "{got} vs {expected}");
        // At 3/4 of the long semi-axis: K ∝ (1 − 0.75²)².
        let ratio = s[1].1.c[0] / got;
        let k = (1.0f32 - 0.75 * 0.75).powi(2);
        assert!((ratio / k - 1.0).abs() < 1e-4, "{ratio} vs {k}");
        // The Epanechnikov kernel: 2/π at the centre.
        let e = splats(
            &map,
            &FootprintFilter {
                kernel: Kernel::Epanechnikov,
                ..f
            },
        );
        let r = e[0].1.c[0] / got;
        assert!((r - 2.0 / 3.0).abs() < 1e-5, "{r}");
    }

    #[test]
    fn the_normal_distance_threshold_keeps_splats_off_nearby_surfaces() {
        // A vertex 0.04 m above the floor (a step), inside the footprint's projection: the gather
        // radius is 0.2 m, so it is reached with the threshold off, not with 0.1 · 0.2 = 0.02 m.
        let map = tiled(vec![vertex(Vec3::new(0.05, 0.04, 0.0), Vec3::Y, 0)]);
        let off = FootprintFilter {
            normal_distance: f32::INFINITY,
            ..Default::default()
        };
        let on = FootprintFilter {
            normal_distance: 0.1,
            ..Default::default()
        };
        assert_eq!(splats(&map, &off).len(), 1);
        assert_eq!(splats(&map, &on).len(), 0);
        // A wall (normal +x) at the centre: rejected by the normal test whatever the threshold.
        let wall = tiled(vec![vertex(Vec3::ZERO, Vec3::X, 0)]);
        assert_eq!(splats(&wall, &off).len(), 0);
    }

    #[test]
    fn an_empty_map_splats_nothing() {
        let empty = tiled(Vec::new());
        assert_eq!(splats(&empty, &FootprintFilter::default()).len(), 0);
        assert!(empty.is_empty());
    }
}

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

/// One splat: reflected radiance (W/m²/sr, before the throughput β) for eye vertex `vertex`.
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    pub vertex: u32,
    pub radiance: Spectrum,
}

/// The eye vertices of an image and a k-d tree over their positions.
pub struct EyeMap {
    pub vertices: Vec<EyeVertex>,
    tree: KdTree,
}

impl EyeMap {
    pub fn new(vertices: Vec<EyeVertex>) -> Self {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.p).collect();
        let tree = KdTree::build(&positions);
        Self { vertices, tree }
    }

    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Bytes held by the vertices and the tree.
    pub fn memory_bytes(&self) -> usize {
        self.vertices.capacity() * std::mem::size_of::<EyeVertex>() + self.tree.memory_bytes()
    }

    /// Splats photon `ph`: pushes one [`Splat`] per eye vertex its footprint reaches (seed 002
    /// eq. 10–12 with `filter`; the range query uses the footprint's gather radius, its true
    /// semi-major axis). Returns the number of splats pushed.
    pub fn splat(&self, ph: &DiffPhoton, filter: &FootprintFilter, out: &mut Vec<Splat>) -> usize {
        let before = out.len();
        let r = ph.footprint.gather_radius();
        if !(r.is_finite() && r > 0.0) || self.vertices.is_empty() {
            return 0;
        }
        self.tree.range(ph.footprint.center(), r * r, |i, _| {
            let v = &self.vertices[i as usize];
            let Some(w) = filter.weight(ph, v.p, v.n) else {
                return;
            };
            let f = v
                .bsdf
                .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
            let l = f * ph.flux * w;
            if l.is_finite() && !l.is_black() {
                out.push(Splat {
                    vertex: i,
                    radiance: l,
                });
            }
        });
        out.len() - before
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

    fn splats(map: &EyeMap, filter: &FootprintFilter) -> Vec<Splat> {
        let mut out = Vec::new();
        map.splat(&photon(), filter, &mut out);
        out.sort_by_key(|s| s.vertex);
        out
    }

    #[test]
    fn a_splat_reaches_exactly_the_vertices_inside_the_ellipse() {
        let map = EyeMap::new(vec![
            vertex(Vec3::ZERO, Vec3::Y, 0),                   // centre
            vertex(Vec3::new(0.15, 0.0, 0.0), Vec3::Y, 1),    // inside, along the long axis
            vertex(Vec3::new(0.0, 0.0, 0.06), Vec3::Y, 2),    // outside, across
            vertex(Vec3::new(0.21, 0.0, 0.0), Vec3::Y, 3),    // outside, along
            vertex(Vec3::new(0.0, 0.0, 0.0), Vec3::NEG_Y, 4), // the underside
        ]);
        let f = FootprintFilter::default();
        let s = splats(&map, &f);
        let ids: Vec<u32> = s.iter().map(|s| s.vertex).collect();
        assert_eq!(ids, vec![0, 1]);
        // Eq. 10–12 at the centre: f_r Φ π K(0) / A, K(0) = 3/π (eq. 11), A = π · 0.2 · 0.05.
        let area = PI * 0.2 * 0.05;
        let expected = ALBEDO / PI * 2.0 * 3.0 / area;
        let got = s[0].radiance.c[0];
        assert!((got / expected - 1.0).abs() < 1e-5, "{got} vs {expected}");
        // At 3/4 of the long semi-axis: K ∝ (1 − 0.75²)².
        let ratio = s[1].radiance.c[0] / got;
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
        let r = e[0].radiance.c[0] / got;
        assert!((r - 2.0 / 3.0).abs() < 1e-5, "{r}");
    }

    #[test]
    fn the_normal_distance_threshold_keeps_splats_off_nearby_surfaces() {
        // A vertex 0.04 m above the floor (a step), inside the footprint's projection: the gather
        // radius is 0.2 m, so it is reached with the threshold off, not with 0.1 · 0.2 = 0.02 m.
        let map = EyeMap::new(vec![vertex(Vec3::new(0.05, 0.04, 0.0), Vec3::Y, 0)]);
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
        let wall = EyeMap::new(vec![vertex(Vec3::ZERO, Vec3::X, 0)]);
        assert_eq!(splats(&wall, &off).len(), 0);
    }

    #[test]
    fn an_empty_map_or_a_degenerate_radius_splats_nothing() {
        let empty = EyeMap::new(Vec::new());
        assert_eq!(splats(&empty, &FootprintFilter::default()).len(), 0);
        assert!(empty.is_empty());
    }
}

//! The volume photon map and its two radiance estimates along a camera ray (seed 000 ch. 8):
//! ray marching with a k-NN estimate at each step (eq. 8.3, Jensen and Christensen 1998), and
//! the beam radiance estimate, one query per ray against every photon sphere it crosses with the
//! exact chord integral of the kernel (eq. 8.4, 8.9–8.13 with the misprints corrected:
//! `caustica_density::beam`; Jarosz et al. 2008).
//!
//! Volume photons are stored at real scattering events (`MapKind::Volume`) with flux
//! Φ = β/N (W), where β already holds the free flight's σ_s T/p. Their density per volume is
//! therefore the scattered flux density, and Σ p Φ / V over a region is in-scattered radiance per
//! metre of ray (W/m²/sr/m): no σ_s factor appears in eq. 8.3 or 8.4 (seed notes §2.1).
//!
//! Both estimates give the radiance (W/m²/sr) a span of a camera ray collects, measured at the
//! span's start:
//!
//! ```text
//! march (8.3):  L = Σ_i T_r(x, x_i) (Σ_{p ≤ k} p(x_i, ω, ω_p) ΔΦ_p / V_i) Δ_i,  V_i = 4π r_i³/3
//! beam  (8.4):  L = Σ_i T_r(x, x_i) p(x_i, ω_i, ω) (ΔΦ_i / V_i) w_i,          w_i = ∫ K dt
//! ```
//!
//! The phase function takes `wo` = toward the eye (−ray direction) and `wi` = the photon's
//! incident direction (toward where its light came from), the convention of
//! `caustica_scene::phase`. With a fixed radius and the uniform kernel the marched sum tends to
//! the beam estimate as the step shrinks (Σ Δ 1{|x_i − p| < h} → chord length, test TM4).

use crate::options::Smoothing;
use crate::photon::differential::volume_trace::Ellipsoid;
use crate::photon::kernel_boundary::{KernelBoundary, kept_fraction};
use crate::photon::tracer::Photon;
use crate::transport::medium::MediumSpan;
use caustica_core::{Mat3, Ray, Spectrum, Vec3};
use caustica_density::beam::{
    BeamKernel, Clip, RaySegment, ball_volume, ball_weight, ellipsoid_weight,
};
use caustica_density::kdtree::{KdTree, Neighbor};
use caustica_density::sphere_bvh::SphereBvh;
pub use caustica_differentials::AxesRule;
use caustica_scene::Scene;
use caustica_scene::medium::MediumKind;
use caustica_scene::phase::Phase;
use caustica_scene::shape::Aabb;
use rayon::prelude::*;

/// How a camera ray collects the volume photons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VolumeEstimate {
    /// The beam radiance estimate (eq. 8.4): one query per ray segment.
    #[default]
    Beam,
    /// Ray marching (eq. 8.3) with steps of at most `VolumeSettings::step` metres, jittered by
    /// one random number per span.
    March,
    /// The beam radiance estimate over photon-differential ellipsoids (eq. 8.4, 8.14–8.16): each
    /// photon's kernel is the beam it stands for (sec. 8.4, [`crate::photon::differential::volume_trace`]).
    Differentials,
}

impl VolumeEstimate {
    pub fn name(&self) -> &'static str {
        match self {
            VolumeEstimate::Beam => "beam",
            VolumeEstimate::March => "march",
            VolumeEstimate::Differentials => "photon-differential beam",
        }
    }
}

/// Settings of the volume photon map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeSettings {
    /// Volume photons to store (light paths are emitted until the map holds this many).
    pub photons: usize,
    pub estimate: VolumeEstimate,
    /// Photons per k-NN estimate (march) and per pilot radius (beam); ≥ 1.
    pub k: usize,
    /// A fixed photon radius (m) for both estimates instead of the k-NN one.
    pub radius: Option<f32>,
    /// Kernel of the beam estimate (the march uses the uniform kernel of eq. 8.3).
    pub kernel: BeamKernel,
    /// Step (m) of the march; `None` = half the median photon radius.
    pub step: Option<f32>,
    /// Smoothing `s` of the volume photon differentials (seed 002 eq. 5–6); `None` = the
    /// surface footprints' smoothing.
    pub smoothing: Option<Smoothing>,
    /// How photon differentials get their third vector (seed notes Q-M3).
    pub axes: AxesRule,
    /// Smallest semi-axis (m) of a photon-differential kernel; `None` (default) = as traced.
    pub min_semi_axis: Option<f32>,
    /// Photon differentials of collimated light spread like a point light's photons at this
    /// smoothing from their first non-delta scattering on (an extension; default none, as in
    /// the thesis).
    pub spread_collimated: Option<Smoothing>,
    /// How much of a kernel a segment that ends inside it receives (seed notes Q-M10).
    pub clip: Clip,
    /// What the beam estimates' kernels (balls and ellipsoids) keep where they reach through a
    /// surface ([`KernelBoundary`]; the march's query balls are not photon kernels).
    pub boundary: KernelBoundary,
}

impl Default for VolumeSettings {
    fn default() -> Self {
        Self {
            photons: 100_000,
            estimate: VolumeEstimate::Beam,
            k: 32,
            radius: None,
            kernel: BeamKernel::Epanechnikov,
            step: None,
            smoothing: None,
            axes: AxesRule::Projected,
            min_semi_axis: None,
            spread_collimated: None,
            clip: Clip::Exact,
            boundary: KernelBoundary::Open,
        }
    }
}

/// What [`VolumeMap::renormalise_at_boundaries`] did, for the render's notes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryReport {
    /// Kernels examined.
    pub kernels: usize,
    /// Kernels a surface cuts (`F < 1`).
    pub cut: usize,
    /// Mean `F` over the cut ones (1 if none).
    pub mean_kept: f32,
}

/// The kernels of a volume map's photons.
pub enum Kernels {
    /// Balls whose radii are [`VolumeMap::radii`] (eq. 8.5–8.13).
    Balls,
    /// Photon-differential ellipsoids (eq. 8.14–8.16), one per photon; [`VolumeMap::radii`]
    /// holds their bounding radii.
    Ellipsoids(Vec<Ellipsoid>),
}

/// Volume photons with a k-d tree (k-NN queries, for balls) and a BVH over their kernels'
/// bounding spheres (beam queries).
pub struct VolumeMap {
    pub photons: Vec<Photon>,
    /// Radius (m) of each photon's sphere in the beam estimate (a ball's radius, an
    /// ellipsoid's bounding radius).
    pub radii: Vec<f32>,
    kernels: Kernels,
    /// `1/F` per photon: its kernel's weight where surfaces cut it
    /// ([`VolumeMap::renormalise_at_boundaries`]); empty = 1 for every photon.
    inv_kept: Vec<f32>,
    /// The k-d tree of the march and the pilot radii (none for ellipsoids).
    tree: Option<KdTree>,
    bvh: SphereBvh,
    /// Box around every photon sphere (rays are clipped to it).
    bounds: Aabb,
    /// Light paths whose photons the map holds.
    pub paths: u64,
    settings: VolumeSettings,
    /// The march's step (m), resolved.
    step: f32,
}

impl VolumeMap {
    /// The map of `photons` (fluxes already divided by `paths`), with each photon's radius the
    /// fixed one or the distance to its k-th nearest neighbour (the pilot of Jarosz et al.
    /// 2008).
    pub fn new(mut photons: Vec<Photon>, paths: u64, settings: VolumeSettings) -> Self {
        photons.shrink_to_fit();
        let positions: Vec<Vec3> = photons.iter().map(|p| p.p).collect();
        let tree = KdTree::build(&positions);
        let radii: Vec<f32> = match settings.radius {
            Some(r) => vec![r; photons.len()],
            None => positions
                .par_iter()
                .map_init(Vec::new, |nn: &mut Vec<Neighbor>, &p| {
                    tree.knn_unsorted(p, settings.k + 1, f32::INFINITY, nn);
                    nn.iter().map(|n| n.dist2).fold(0.0f32, f32::max).sqrt()
                })
                .collect(),
        };
        let radii: Vec<f32> = radii.into_iter().map(|r| r.max(1e-6)).collect();
        let mut map =
            Self::with_kernels(photons, radii, Kernels::Balls, Some(tree), paths, settings);
        map.step = settings.step.unwrap_or(0.5 * map.median_radius()).max(1e-6);
        map
    }

    /// The map of photon differentials `photons` with their ellipsoids `kernels` (one each;
    /// fluxes already divided by `paths`), for the beam estimate of eq. 8.4 over them.
    ///
    /// # Panics
    /// If the two lengths differ (a programming error).
    pub fn from_ellipsoids(
        mut photons: Vec<Photon>,
        kernels: Vec<Ellipsoid>,
        paths: u64,
        settings: VolumeSettings,
    ) -> Self {
        assert_eq!(photons.len(), kernels.len(), "one kernel per photon");
        photons.shrink_to_fit();
        let radii = kernels.iter().map(|k| k.bound).collect();
        let mut settings = settings;
        settings.estimate = VolumeEstimate::Differentials;
        Self::with_kernels(
            photons,
            radii,
            Kernels::Ellipsoids(kernels),
            None,
            paths,
            settings,
        )
    }

    fn with_kernels(
        photons: Vec<Photon>,
        radii: Vec<f32>,
        kernels: Kernels,
        tree: Option<KdTree>,
        paths: u64,
        settings: VolumeSettings,
    ) -> Self {
        let positions: Vec<Vec3> = photons.iter().map(|p| p.p).collect();
        let bvh = SphereBvh::build(&positions, &radii);
        let mut bounds = Aabb::default();
        for (p, r) in positions.iter().zip(&radii) {
            bounds.grow(*p - Vec3::splat(*r));
            bounds.grow(*p + Vec3::splat(*r));
        }
        Self {
            photons,
            radii,
            kernels,
            inv_kept: Vec::new(),
            tree,
            bvh,
            bounds,
            paths,
            settings,
            step: 0.0,
        }
    }

    /// Cut and normalise ([`crate::photon::kernel_boundary`]): every photon's kernel divided by
    /// the fraction `F` of its mass that the photon sees without crossing a surface of `scene`,
    /// so that the part camera rays in the medium can meet holds the photon's whole flux.
    /// Deterministic for `seed` whatever the thread count. Returns how many kernels surfaces cut
    /// and the mean `F` over those.
    pub fn renormalise_at_boundaries(&mut self, scene: &Scene, seed: u64) -> BoundaryReport {
        let kernel = self.settings.kernel;
        let kept: Vec<f32> = (0..self.photons.len())
            .into_par_iter()
            .map(|i| {
                let axes = match &self.kernels {
                    Kernels::Balls => Mat3::from_diagonal(Vec3::splat(self.radii[i])),
                    Kernels::Ellipsoids(e) => e[i].m.inverse(),
                };
                kept_fraction(scene, self.photons[i].p, axes, kernel, seed, i as u64)
            })
            .collect();
        let cut: Vec<f32> = kept.iter().copied().filter(|&f| f < 1.0).collect();
        let report = BoundaryReport {
            kernels: kept.len(),
            cut: cut.len(),
            mean_kept: if cut.is_empty() {
                1.0
            } else {
                cut.iter().map(|&f| f as f64).sum::<f64>() as f32 / cut.len() as f32
            },
        };
        self.inv_kept = kept.into_iter().map(|f| 1.0 / f).collect();
        report
    }

    /// The weight `1/F` of photon `i`'s kernel (1 unless renormalised).
    #[inline]
    fn kernel_weight(&self, i: usize) -> f32 {
        self.inv_kept.get(i).copied().unwrap_or(1.0)
    }

    /// The march's step (m).
    pub fn step(&self) -> f32 {
        self.step
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }
    pub fn settings(&self) -> &VolumeSettings {
        &self.settings
    }
    /// Bytes held by the photons, radii, tree and BVH.
    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<Photon>()
            + self.radii.capacity() * 4
            + self.inv_kept.capacity() * 4
            + match &self.kernels {
                Kernels::Balls => 0,
                Kernels::Ellipsoids(e) => e.capacity() * std::mem::size_of::<Ellipsoid>(),
            }
            + self.tree.as_ref().map_or(0, |t| t.memory_bytes())
            + self.bvh.memory_bytes()
    }
    /// Median photon radius (m).
    pub fn median_radius(&self) -> f32 {
        let mut r = self.radii.clone();
        if r.is_empty() {
            return 0.0;
        }
        let mid = r.len() / 2;
        *r.select_nth_unstable_by(mid, f32::total_cmp).1
    }

    /// The span's parameter range inside the photons' box, or `None` if it misses it.
    fn clip(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        let (mut lo, mut hi) = (0.0f32, t_max);
        for a in 0..3 {
            let inv = 1.0 / ray.d[a];
            let (t0, t1) = (
                (self.bounds.min[a] - ray.o[a]) * inv,
                (self.bounds.max[a] - ray.o[a]) * inv,
            );
            let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
            if t0.is_nan() || t1.is_nan() {
                if ray.o[a] < self.bounds.min[a] || ray.o[a] > self.bounds.max[a] {
                    return None;
                }
                continue;
            }
            lo = lo.max(t0);
            hi = hi.min(t1);
        }
        (lo < hi).then_some((lo, hi))
    }

    /// In-scattered radiance (W/m²/sr) that the span collects, at the span's start, by the map's
    /// estimate; `u` jitters the march's sample points.
    pub fn radiance(&self, scene: &Scene, span: &MediumSpan, u: f32) -> Spectrum {
        if self.is_empty() {
            return Spectrum::ZERO;
        }
        match (&self.kernels, &self.tree, self.settings.estimate) {
            (Kernels::Balls, Some(tree), VolumeEstimate::March) => {
                self.march(tree, scene, span, self.step, u)
            }
            _ => self.beam(scene, span),
        }
    }

    /// Eq. 8.4: every photon kernel the span crosses (a ball, eq. 8.5–8.13, or an ellipsoid,
    /// eq. 8.14–8.16), weighted by its kernel's chord integral clipped to the span, times
    /// `T_r` to the (filter-space) closest point, the phase function and ΔΦ/V.
    pub fn beam(&self, scene: &Scene, span: &MediumSpan) -> Spectrum {
        let Some((t0, t1)) = self.clip(span.ray, span.t_max) else {
            return Spectrum::ZERO;
        };
        let medium = &scene.media[span.medium as usize];
        let tr = Transmittance::new(medium, span.ray, t1);
        let seg = RaySegment::new(span.ray.o, span.ray.d, t0, t1);
        let wo = -span.ray.d;
        let kernel = self.settings.kernel;
        let clip = self.settings.clip;
        let mut l = Spectrum::ZERO;
        match &self.kernels {
            Kernels::Balls => self.bvh.for_each_crossing(&seg, |i, centre, r| {
                let ph = &self.photons[i as usize];
                if let Some(hit) = ball_weight(kernel, &seg, centre, r, clip) {
                    let p = medium.phase.eval(wo, ph.wi) * self.kernel_weight(i as usize);
                    l += ph.flux * (tr.at(hit.t) * (p * hit.weight / ball_volume(r)));
                }
            }),
            Kernels::Ellipsoids(e) => self.bvh.for_each_crossing(&seg, |i, centre, _| {
                let (ph, e) = (&self.photons[i as usize], &e[i as usize]);
                if let Some(hit) = ellipsoid_weight(kernel, &seg, centre, e.m, clip) {
                    let p = medium.phase.eval(wo, ph.wi) * self.kernel_weight(i as usize);
                    l += ph.flux * (tr.at(hit.t) * (p * hit.weight * e.inv_volume));
                }
            }),
        }
        l
    }

    /// Eq. 8.3: k-NN estimates (or fixed-radius ones) at jittered points every `step` metres.
    fn march(
        &self,
        tree: &KdTree,
        scene: &Scene,
        span: &MediumSpan,
        step: f32,
        u: f32,
    ) -> Spectrum {
        let Some((t0, t1)) = self.clip(span.ray, span.t_max) else {
            return Spectrum::ZERO;
        };
        let medium = &scene.media[span.medium as usize];
        let tr = Transmittance::new(medium, span.ray, t1);
        let n = (((t1 - t0) / step.max(1e-6)).ceil() as usize).clamp(1, 1 << 20);
        let dt = (t1 - t0) / n as f32;
        let wo = -span.ray.d;
        let mut nn = Vec::new();
        let mut l = Spectrum::ZERO;
        for i in 0..n {
            let t = t0 + (i as f32 + u) * dt;
            let x = span.ray.at(t);
            let mut sum = Spectrum::ZERO;
            let volume = match self.settings.radius {
                Some(h) => {
                    tree.range(x, h * h, |j, _| {
                        let ph = &self.photons[j as usize];
                        sum += ph.flux * medium.phase.eval(wo, ph.wi);
                    });
                    ball_volume(h)
                }
                None => {
                    tree.knn_unsorted(x, self.settings.k, f32::INFINITY, &mut nn);
                    let r2 = nn.iter().map(|n| n.dist2).fold(0.0f32, f32::max);
                    // The tree's order is fixed for a given map and query: a deterministic sum.
                    for n in &nn {
                        let ph = &self.photons[n.index as usize];
                        sum += ph.flux * medium.phase.eval(wo, ph.wi);
                    }
                    ball_volume(r2.sqrt().max(1e-6))
                }
            };
            l += sum * (tr.at(t) * dt / volume);
        }
        l
    }
}

/// T_r from a span's start to a point on it: exact in homogeneous media, interpolated in a table
/// of optical depths (the midpoint rule of `Medium::optical_depth`) in grids — deterministic,
/// as a density estimate must be (seed notes Q-M7). In RGB in both modes: the camera side of the
/// photon methods is RGB (photons are stored in linear sRGB, docs/spectral.md).
enum Transmittance {
    Homogeneous(Spectrum),
    Table { depth: Vec<Spectrum>, dt: f32 },
}

/// Entries of a grid's optical-depth table per span.
const DEPTH_TABLE: usize = 64;

impl Transmittance {
    fn new(medium: &caustica_scene::medium::Medium, ray: &Ray, t_max: f32) -> Self {
        match &medium.kind {
            MediumKind::Homogeneous(_) => Transmittance::Homogeneous(medium.sigma_t()),
            MediumKind::Grid(_) => {
                let t_max = if t_max.is_finite() { t_max } else { 1e4 };
                let dt = t_max / DEPTH_TABLE as f32;
                let mut depth = Vec::with_capacity(DEPTH_TABLE + 1);
                let mut acc = Spectrum::ZERO;
                depth.push(acc);
                for i in 0..DEPTH_TABLE {
                    acc += medium.optical_depth(ray, i as f32 * dt, (i + 1) as f32 * dt);
                    depth.push(acc);
                }
                Transmittance::Table { depth, dt }
            }
        }
    }

    #[inline]
    fn at(&self, t: f32) -> Spectrum {
        match self {
            Transmittance::Homogeneous(sigma_t) => (*sigma_t * -t).exp(),
            Transmittance::Table { depth, dt } => {
                let x = (t / dt).clamp(0.0, DEPTH_TABLE as f32);
                let i = (x as usize).min(DEPTH_TABLE - 1);
                let f = x - i as f32;
                let od = depth[i] * (1.0 - f) + depth[i + 1] * f;
                (od * -1.0).exp()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::differential::volume_trace::{KernelRule, volume_kernel};
    use caustica_core::sampling::Pcg32;
    use caustica_scene::SceneBuilder;
    use caustica_scene::camera::PerspectiveCamera;
    use caustica_scene::medium::Medium;
    use caustica_scene::phase::PhaseFunction;

    /// A scene holding one medium (index 0) with extinction `sigma_t` and HG g = 0.4, so that
    /// phase values differ between photons.
    fn scene(sigma_t: f32) -> Scene {
        let mut b = SceneBuilder::new("medium only");
        b.add_medium(
            "m",
            Medium::homogeneous(
                Spectrum::splat(0.0),
                Spectrum::splat(sigma_t),
                PhaseFunction::henyey_greenstein(0.4).unwrap(),
            ),
        )
        .unwrap();
        b.set_camera(PerspectiveCamera::look_at(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            30.0,
            4,
            4,
        ));
        b.build().unwrap()
    }

    fn photons(n: usize, seed: u64) -> Vec<Photon> {
        let mut rng = Pcg32::new(seed, 1);
        let mut u = || rng.next_f32();
        (0..n)
            .map(|_| {
                let p = Vec3::new(u(), u(), u()) - 0.5;
                let wi = (Vec3::new(u(), u(), u()) - 0.5).normalize();
                Photon {
                    p,
                    wi,
                    n: Vec3::ZERO,
                    flux: Spectrum::splat(1.0 / n as f32),
                    depth: 1,
                    caustic: false,
                }
            })
            .collect()
    }

    #[test]
    fn the_march_tends_to_the_beam_estimate_as_the_step_shrinks() {
        // TM4: fixed radius, uniform kernel, the same photons: Σ Δ 1{|x_i − p| < h} tends to
        // the chord length 2√(h² − y²) (eq. 8.11), so eq. 8.3 tends to eq. 8.4.
        for sigma_t in [0.0f32, 1.5] {
            let scene = scene(sigma_t);
            let settings = VolumeSettings {
                radius: Some(0.08),
                kernel: BeamKernel::Uniform,
                ..VolumeSettings::default()
            };
            let map = VolumeMap::new(photons(4000, 3), 4000, settings);
            let mut rng = Pcg32::new(8, 2);
            for _ in 0..10 {
                let o = Vec3::new(-1.0, rng.next_f32() - 0.5, rng.next_f32() - 0.5);
                let d = (Vec3::new(1.0, 0.3 * (rng.next_f32() - 0.5), 0.2)).normalize();
                let ray = Ray::new(o, d);
                let span = MediumSpan {
                    ray: &ray,
                    t_max: 3.0,
                    medium: 0,
                    tr: Spectrum::ONE,
                };
                let beam = map.beam(&scene, &span)[0] as f64;
                let mut errs = Vec::new();
                for step in [0.04f32, 0.01, 0.0025, 0.000625] {
                    let tree = map.tree.as_ref().expect("balls have a k-d tree");
                    let m = map.march(tree, &scene, &span, step, 0.5)[0] as f64;
                    errs.push((m - beam).abs());
                }
                assert!(beam > 0.0);
                // At the finest steps the march is within 0.5 % of the beam estimate.
                assert!(errs[2] < 0.01 * beam, "march {errs:?} vs beam {beam}");
                assert!(errs[3] < 0.005 * beam, "march {errs:?} vs beam {beam}");
            }
        }
    }

    #[test]
    fn isotropic_equal_footprints_give_the_fixed_radius_beam_estimate() {
        // Seed notes TM4's last clause: photon differentials whose three vectors are orthogonal
        // and of equal length 2h (sec. 8.4 at storage, `volume_kernel`) are balls of radius h,
        // so the ellipsoid estimate (eq. 8.14–8.16) equals the fixed-radius beam estimate of
        // the same photons with the same kernel (eq. 8.13).
        let h = 0.06f32;
        let ph = photons(3000, 17);
        for sigma_t in [0.0f32, 1.2] {
            let scene = scene(sigma_t);
            let balls = VolumeMap::new(
                ph.clone(),
                3000,
                VolumeSettings {
                    radius: Some(h),
                    ..VolumeSettings::default()
                },
            );
            let kernels: Vec<Ellipsoid> = ph
                .iter()
                .map(|p| {
                    let f = caustica_core::Frame::from_normal(-p.wi);
                    volume_kernel(
                        f.s * (2.0 * h),
                        f.t * (2.0 * h),
                        -p.wi,
                        KernelRule::default(),
                    )
                    .unwrap()
                    .0
                })
                .collect();
            let ellipsoids =
                VolumeMap::from_ellipsoids(ph.clone(), kernels, 3000, VolumeSettings::default());
            let mut rng = Pcg32::new(4, 4);
            for _ in 0..20 {
                let o = Vec3::new(
                    -1.0,
                    0.6 * (rng.next_f32() - 0.5),
                    0.6 * (rng.next_f32() - 0.5),
                );
                let d = Vec3::new(1.0, 0.2 * (rng.next_f32() - 0.5), 0.1).normalize();
                let ray = Ray::new(o, d);
                // Ending inside the cloud: the clipped integral at the end too.
                let span = MediumSpan {
                    ray: &ray,
                    t_max: 0.8 + rng.next_f32(),
                    medium: 0,
                    tr: Spectrum::ONE,
                };
                let (a, b) = (
                    balls.beam(&scene, &span)[0],
                    ellipsoids.beam(&scene, &span)[0],
                );
                assert!(a > 0.0, "balls {a} vs ellipsoids {b}");
                assert!((a - b).abs() <= 2e-4 * a, "balls {a} vs ellipsoids {b}");
            }
        }
    }

    #[test]
    fn renormalised_kernels_cut_by_a_floor_keep_their_flux() {
        // One photon h above a floor (y = 0), its kernel a ball or a random ellipsoid reaching
        // through it. Vertical rays down to the floor on a dense grid: Σ L dA = ΔΦ p · (the
        // kernel's mass above the floor) — the exact marginal F with open kernels (the flux
        // below is lost), ΔΦ p with renormalised ones (to the accuracy of F's 64 directions).
        let scene = crate::photon::kernel_boundary::tests::floor(Some(Medium::homogeneous(
            Spectrum::splat(0.0),
            Spectrum::splat(0.0),
            PhaseFunction::henyey_greenstein(0.4).unwrap(),
        )));
        let r = 0.2f32;
        let photon = Photon {
            p: Vec3::new(0.0, 0.3 * r, 0.0),
            wi: Vec3::new(0.3, 0.5, -0.2).normalize(),
            n: Vec3::ZERO,
            flux: Spectrum::splat(2.0),
            depth: 1,
            caustic: false,
        };
        // Epanechnikov marginal along y: (1 − z²)², the mass above z = −0.3.
        let f = |z: f64| z - 2.0 * z.powi(3) / 3.0 + z.powi(5) / 5.0;
        let total = |map: &VolumeMap, scene: &Scene| {
            let (n, half) = (200, 0.5f32);
            let da = (2.0 * half / n as f32).powi(2) as f64;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let x = -half + (i as f32 + 0.5) * 2.0 * half / n as f32;
                    let z = -half + (j as f32 + 0.5) * 2.0 * half / n as f32;
                    let ray = Ray::new(Vec3::new(x, 1.0, z), -Vec3::Y);
                    let span = MediumSpan {
                        ray: &ray,
                        t_max: 1.0,
                        medium: 0,
                        tr: Spectrum::ONE,
                    };
                    sum += map.beam(scene, &span)[0] as f64 * da;
                }
            }
            sum
        };
        let p = PhaseFunction::henyey_greenstein(0.4)
            .unwrap()
            .eval(Vec3::Y, photon.wi) as f64;
        let phi_p = 2.0 * p;
        let settings = VolumeSettings {
            radius: Some(r),
            ..VolumeSettings::default()
        };
        let ball = || VolumeMap::new(vec![photon], 1, settings);
        // A flat ellipsoid tilted through the floor: its extent along y is |Aᵀ y|.
        let axes = [
            Vec3::new(0.18, 0.1, 0.0),
            Vec3::new(0.0, 0.05, 0.12),
            Vec3::new(0.01, -0.01, 0.01),
        ];
        let m = Mat3::from_cols(axes[0], axes[1], axes[2]).inverse();
        let e = Ellipsoid {
            m,
            inv_volume: 1.0 / (4.0 / 3.0 * std::f32::consts::PI * m.inverse().determinant().abs()),
            bound: 0.25,
        };
        let ellipsoid = || VolumeMap::from_ellipsoids(vec![photon], vec![e], 1, settings);
        let extent = Mat3::from_cols(axes[0], axes[1], axes[2])
            .transpose()
            .mul_vec3(Vec3::Y)
            .length() as f64;
        for (what, make, h) in [
            ("ball", &ball as &dyn Fn() -> VolumeMap, 0.3),
            ("ellipsoid", &ellipsoid, 0.3 * r as f64 / extent),
        ] {
            let kept = (f(1.0) - f(-h)) / (16.0 / 15.0);
            let open = total(&make(), &scene) / phi_p;
            assert!(
                (open - kept).abs() < 0.005,
                "{what} open: {open} vs F = {kept}"
            );
            let mut map = make();
            let report = map.renormalise_at_boundaries(&scene, 3);
            assert_eq!(report.cut, 1);
            assert!(
                (report.mean_kept as f64 - kept).abs() < 0.03,
                "{report:?} vs {kept}"
            );
            let renormalised = total(&map, &scene) / phi_p;
            assert!(
                (renormalised - 1.0).abs() < 0.03,
                "{what} renormalised: {renormalised}"
            );
        }
    }

    #[test]
    fn the_beam_estimate_of_a_uniform_photon_cloud_is_its_density_times_the_chord() {
        // Photons uniform in the unit cube with total flux 1 W and an isotropic-looking
        // average phase: along a ray through the middle (σ_t = 0) the estimate must approach
        // ∫ p Φ/V dt ≈ (1 W/m³) · 1 m · p̄ with p̄ the mean phase value, away from the faces.
        let scene = scene(0.0);
        let settings = VolumeSettings {
            k: 128,
            ..VolumeSettings::default()
        };
        // About 1500 photons cross the ray: 3 % noise.
        let map = VolumeMap::new(photons(200_000, 5), 200_000, settings);
        let ray = Ray::new(Vec3::new(-0.3, 0.01, -0.02), Vec3::X);
        let span = MediumSpan {
            ray: &ray,
            t_max: 0.6,
            medium: 0,
            tr: Spectrum::ONE,
        };
        let got = map.beam(&scene, &span)[0] as f64;
        // Mean of p(wo, wi) over uniform wi is 1/(4π) for any normalised phase function.
        let want = 0.6 / (4.0 * std::f64::consts::PI);
        assert!((got / want - 1.0).abs() < 0.1, "{got} vs {want}");
    }
}

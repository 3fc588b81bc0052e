//! Diffuse area lights on triangle lists, spheres and disks.

use super::{EmissionSample, LightSample, LightSource};
use crate::shape::Sphere;
use caustica_core::sampling::{Distribution1D, warp};
use caustica_core::{Frame, PI, Ray, Spectrum, Vec2, Vec3, Vec3A};

/// Diffuse (Lambertian) emitter of constant radiance. Emits on the side its geometric normal
/// points to (triangle winding normal `(p1 − p0) × (p2 − p0)`, sphere outward, disk `normal`)
/// unless `two_sided`.
#[derive(Clone, Debug)]
pub struct AreaLight {
    pub shape: AreaShape,
    /// Emitted radiance (W/m²/sr).
    pub radiance: Spectrum,
    pub two_sided: bool,
    /// Total surface area (m²).
    area: f32,
    /// Triangle selection proportional to area (triangle lists only).
    tri_dist: Option<Distribution1D>,
    /// Each triangle's vertices and unit winding normal (zero for degenerate ones), in SIMD
    /// vectors for sampling: four aligned loads and three-lane arithmetic, the same operations
    /// lane by lane as on `shape`'s `Vec3`s, so the same bits.
    tri_points: Vec<[Vec3A; 4]>,
}

/// The surface an area light emits from (world space).
#[derive(Clone, Debug)]
pub enum AreaShape {
    Triangles(Vec<[Vec3; 3]>),
    Sphere(crate::shape::Sphere),
    Disk(crate::shape::Disk),
}

/// A point sampled uniformly by area on the light.
#[derive(Clone, Copy, Debug)]
struct AreaPoint {
    p: Vec3,
    n: Vec3,
}

/// sin²(1.5°): below it the sphere cone is sampled with a Taylor expansion (pbrt-v4).
const SIN2_SMALL: f32 = 0.000_685_23;

impl AreaLight {
    /// Diffuse emitter of radiance `radiance` (W/m²/sr) on `shape`, one-sided unless `two_sided`.
    pub fn new(shape: AreaShape, radiance: Spectrum, two_sided: bool) -> Self {
        let (area, tri_dist) = match &shape {
            AreaShape::Triangles(tris) => {
                let areas: Vec<f32> = tris
                    .iter()
                    .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
                    .collect();
                let dist = Distribution1D::new(&areas);
                let total = dist.as_ref().map_or(0.0, |d| d.total() as f32);
                (total, dist)
            }
            AreaShape::Sphere(s) => (4.0 * PI * s.radius * s.radius, None),
            AreaShape::Disk(d) => (PI * d.radius * d.radius, None),
        };
        let tri_points = match &shape {
            AreaShape::Triangles(tris) => tris
                .iter()
                .map(|t| {
                    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
                    [t[0], t[1], t[2], n].map(Vec3A::from)
                })
                .collect(),
            _ => Vec::new(),
        };
        let area = if area.is_finite() && area > 0.0 {
            area
        } else {
            0.0
        };
        Self {
            shape,
            radiance,
            two_sided,
            area,
            tri_dist,
            tri_points,
        }
    }

    /// Total emitting area (m²).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// The triangle of a triangle list that [`Self::sample_li`] samples with `u` (chosen by
    /// area), as its vertices and unit normal `[p0, p1, p2, n]`, and the point of the square
    /// that [`warp::square_to_uniform_triangle`] maps to its barycentrics. `None` where
    /// `sample_li` finds no point: not a triangle list, no area, a degenerate triangle. For
    /// code that samples triangle lights its own way with the same numbers (the path tracer's
    /// next-event estimation in lanes).
    #[inline(always)]
    pub fn triangle_sample(&self, u: Vec2) -> Option<(&[Vec3A; 4], Vec2)> {
        if self.area <= 0.0 || !matches!(self.shape, AreaShape::Triangles(_)) {
            return None;
        }
        let (i, _, ux) = self.tri_dist.as_ref()?.sample(u.x);
        let tri = self.tri_points.get(i)?;
        if tri[3] == Vec3A::ZERO {
            return None;
        }
        Some((tri, Vec2::new(ux, u.y)))
    }

    /// Uniform point by area; `None` for an empty or degenerate shape.
    #[inline(always)]
    fn sample_area(&self, u: Vec2) -> Option<AreaPoint> {
        if self.area <= 0.0 {
            return None;
        }
        match &self.shape {
            AreaShape::Triangles(_) => {
                let (&[p0, p1, p2, n], w) = self.triangle_sample(u)?;
                let b = warp::square_to_uniform_triangle(w);
                let p = p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y;
                Some(AreaPoint {
                    p: p.into(),
                    n: n.into(),
                })
            }
            AreaShape::Sphere(s) => {
                let n = warp::square_to_uniform_sphere(u);
                Some(AreaPoint {
                    p: s.center + n * s.radius,
                    n,
                })
            }
            AreaShape::Disk(d) => {
                let n = d.normal.try_normalize()?;
                let f = Frame::from_normal(n);
                let c = warp::square_to_disk_concentric(u) * d.radius;
                Some(AreaPoint {
                    p: d.center + f.s * c.x + f.t * c.y,
                    n,
                })
            }
        }
    }

    /// True if radiance leaves a point of normal `n` in direction `w`.
    #[inline]
    fn emits(&self, n: Vec3, w: Vec3) -> bool {
        let c = n.dot(w);
        if self.two_sided { c != 0.0 } else { c > 0.0 }
    }

    /// Solid-angle pdf from an area pdf for a light point seen from `p`.
    fn area_to_solid_angle(&self, p: Vec3, lp: Vec3, ln: Vec3) -> f32 {
        let v = lp - p;
        let d2 = v.length_squared();
        if d2 <= 0.0 || d2.is_nan() {
            return 0.0;
        }
        let cos = ln.dot(v).abs() / d2.sqrt();
        if cos <= 0.0 || cos.is_nan() {
            return 0.0;
        }
        d2 / (cos * self.area)
    }

    /// Samples the cone of directions from `p` (outside) subtended by sphere `s` (pbrt-v4):
    /// returns the visible sphere point, its normal and the solid-angle pdf.
    fn sample_sphere_cone(s: &Sphere, p: Vec3, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let to_c = s.center - p;
        let dc = to_c.length();
        let sin_max = s.radius / dc;
        let sin2_max = sin_max * sin_max;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        let mut one_minus_cos_max = 1.0 - cos_max;
        let mut cos_t = (cos_max - 1.0) * u.x + 1.0;
        let mut sin2_t = 1.0 - cos_t * cos_t;
        if sin2_max < SIN2_SMALL {
            sin2_t = sin2_max * u.x;
            cos_t = (1.0 - sin2_t).sqrt();
            one_minus_cos_max = 0.5 * sin2_max;
        }
        // Angle α at the sphere centre between −(direction to centre) and the sampled point.
        let cos_a = sin2_t / sin_max + cos_t * (1.0 - sin2_t / sin2_max).max(0.0).sqrt();
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let w = Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a);
        let f = Frame::from_normal(to_c / dc);
        let n = f.to_world(-w).try_normalize()?;
        let lp = s.center + n * s.radius;
        let pdf = 1.0 / (2.0 * PI * one_minus_cos_max);
        if !pdf.is_finite() {
            return None;
        }
        Some((lp, n, pdf))
    }

    /// Solid-angle pdf of the sphere cone sampling from `p`, for direction `wi`.
    fn sphere_cone_pdf(s: &Sphere, p: Vec3, wi: Vec3) -> f32 {
        let to_c = s.center - p;
        let dc2 = to_c.length_squared();
        let sin2_max = s.radius * s.radius / dc2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        let one_minus_cos_max = if sin2_max < SIN2_SMALL {
            0.5 * sin2_max
        } else {
            1.0 - cos_max
        };
        // Accept directions in the cone with a little slack for rounding.
        let cos_w = wi.dot(to_c) / (wi.length() * dc2.sqrt());
        if cos_w < cos_max - 1e-5 * (1.0 + one_minus_cos_max) - 1e-6 {
            return 0.0;
        }
        1.0 / (2.0 * PI * one_minus_cos_max)
    }
}

impl LightSource for AreaLight {
    /// Spheres seen from outside: uniform in the subtended cone; otherwise uniform by area,
    /// converted to solid angle (d² / (|cos θ_l| A)). `weight` = Le / pdf (W/m²/sr · sr).
    /// `None` if the sampled point does not emit toward `p`.
    fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let (lp, ln, pdf) = match &self.shape {
            AreaShape::Sphere(s) if (p - s.center).length_squared() > s.radius * s.radius => {
                Self::sample_sphere_cone(s, p, u)?
            }
            _ => {
                // Area sampling: d² / (|cos θ_l| A), sharing d with the returned sample.
                let a = self.sample_area(u)?;
                let v = a.p - p;
                let d2 = v.length_squared();
                if d2 <= 0.0 || d2.is_nan() {
                    return None;
                }
                let dist = d2.sqrt();
                let wi = v / dist;
                let cos = a.n.dot(wi).abs();
                if cos <= 0.0 || cos.is_nan() || !self.emits(a.n, -wi) {
                    return None;
                }
                let pdf = d2 / (cos * self.area);
                if pdf <= 0.0 || !pdf.is_finite() {
                    return None;
                }
                return Some(LightSample {
                    wi,
                    dist,
                    p: a.p,
                    weight: self.radiance / pdf,
                    pdf,
                    delta: false,
                });
            }
        };
        let v = lp - p;
        let dist = v.length();
        if (dist <= 0.0 || dist.is_nan()) || (pdf <= 0.0 || pdf.is_nan()) || !pdf.is_finite() {
            return None;
        }
        let wi = v / dist;
        if !self.emits(ln, -wi) {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            p: lp,
            weight: self.radiance / pdf,
            pdf,
            delta: false,
        })
    }

    /// Density of `sample_li(p, ·)` for direction `wi` reaching the light at `light_p` with normal
    /// `light_n` (0 if that side does not emit toward `p`).
    fn pdf_li(&self, p: Vec3, wi: Vec3, light_p: Vec3, light_n: Vec3) -> f32 {
        if self.area <= 0.0 || !self.emits(light_n, -wi) {
            return 0.0;
        }
        match &self.shape {
            AreaShape::Sphere(s) if (p - s.center).length_squared() > s.radius * s.radius => {
                Self::sphere_cone_pdf(s, p, wi)
            }
            _ => self.area_to_solid_angle(p, light_p, light_n),
        }
    }

    /// Le if `w` leaves the emitting side of a point with geometric normal `n`, else 0.
    fn le(&self, n: Vec3, w: Vec3) -> Spectrum {
        if self.emits(n, w) {
            self.radiance
        } else {
            Spectrum::ZERO
        }
    }

    /// Uniform point by area (`pdf_pos` = 1/A) and cosine-weighted direction around the emitting
    /// normal (`pdf_dir` = cos θ/π, halved for two-sided lights, whose side is chosen with
    /// `u_dir.x`); `weight` = Le cos θ/(pdf_pos pdf_dir) = π A Le (×2 two-sided). `normal` is the
    /// normal of the emitting side. The origin lies exactly on the surface (not offset).
    fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let Some(a) = self.sample_area(u_pos) else {
            return EmissionSample {
                ray: Ray::new(Vec3::ZERO, Vec3::Z),
                normal: None,
                weight: Spectrum::ZERO,
                pdf_pos: 0.0,
                pdf_dir: 0.0,
                delta_pos: false,
                delta_dir: false,
            };
        };
        let (n, u, side_p) = if self.two_sided {
            if u_dir.x < 0.5 {
                (a.n, Vec2::new(u_dir.x * 2.0, u_dir.y), 0.5)
            } else {
                (-a.n, Vec2::new((u_dir.x - 0.5) * 2.0, u_dir.y), 0.5)
            }
        } else {
            (a.n, u_dir, 1.0)
        };
        let u = u.min(Vec2::splat(
            caustica_core::sampling::sampler::ONE_MINUS_EPSILON,
        ));
        let local = warp::square_to_cosine_hemisphere(u);
        let f = Frame::from_normal(n);
        let d = f.to_world(local).normalize();
        let pdf_dir = warp::cosine_hemisphere_pdf(local) * side_p;
        let pdf_pos = 1.0 / self.area;
        let weight = if pdf_dir > 0.0 {
            self.radiance * (local.z / (pdf_pos * pdf_dir))
        } else {
            Spectrum::ZERO
        };
        EmissionSample {
            ray: Ray::new(a.p, d),
            normal: Some(n),
            weight,
            pdf_pos,
            pdf_dir,
            delta_pos: false,
            delta_dir: false,
        }
    }

    /// π A Le (W), doubled for two-sided lights.
    fn power(&self) -> Spectrum {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (sides * PI * self.area)
    }
    fn is_delta(&self) -> bool {
        false
    }
    /// (A, 2π), or (A, 4π) if two-sided: the emitting hemisphere(s).
    fn emission_extent(&self) -> (f32, f32) {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        (self.area, sides * 2.0 * PI)
    }
}

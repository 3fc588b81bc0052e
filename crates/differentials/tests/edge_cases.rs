//! Defined results at the edges: parallel rays, planes behind the origin, total internal
//! reflection, degenerate triangles and normals — errors, never NaN.

use caustica_core::Vec3;
use caustica_differentials::{
    DiffError, FlatTriangle, PhongTriangle, RayDiff, TriangleMotion, reflect, refract,
    refract_direction, transfer_to_plane,
};

const N: usize = 4;

fn ray(p: Vec3, v: Vec3) -> RayDiff<N> {
    let v = v.normalize();
    let t1 = v.any_orthonormal_vector();
    let t2 = v.cross(t1);
    RayDiff::new(
        p,
        v,
        [t1, t2, Vec3::ZERO, Vec3::ZERO],
        [Vec3::ZERO, Vec3::ZERO, t1, t2],
    )
}

fn tri() -> [Vec3; 3] {
    [
        Vec3::new(-1.0, -1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ]
}

#[test]
fn parallel_ray_is_an_error() {
    let q = tri();
    let n = [Vec3::Z; 3];
    for v in [
        Vec3::X,
        Vec3::new(1.0, 1.0, 1e-8),
        Vec3::new(1.0, 0.0, -1e-9),
    ] {
        let r = ray(Vec3::ZERO, v);
        assert_eq!(FlatTriangle { q }.hit(&r), Err(DiffError::Parallel));
        assert_eq!(PhongTriangle { q, n }.hit(&r), Err(DiffError::Parallel));
        assert_eq!(
            transfer_to_plane(&r, q[0], &[Vec3::ZERO; N], Vec3::Z, &[Vec3::ZERO; N]),
            Err(DiffError::Parallel)
        );
    }
}

#[test]
fn plane_behind_origin_is_an_error() {
    let r = ray(Vec3::ZERO, -Vec3::Z);
    assert_eq!(
        FlatTriangle { q: tri() }.hit(&r),
        Err(DiffError::BehindOrigin)
    );
}

#[test]
fn total_internal_reflection_is_an_error() {
    // Inside glass (η = 1.5) at 60° incidence: sin θ_t = 1.5 · 0.866 > 1.
    let v = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
    let r = ray(Vec3::ZERO, v);
    let hit = FlatTriangle { q: tri() }.hit(&r).unwrap();
    assert_eq!(hit.refract(1.5), Err(DiffError::TotalInternalReflection));
    assert_eq!(refract_direction(hit.ray.v, hit.normal, 1.5), None);
    // The same ray reflects fine, and refracts when leaving into a denser medium.
    assert!(hit.reflect().unwrap().is_finite());
    assert!(hit.refract(1.0 / 1.5).unwrap().is_finite());
    // Phong too.
    let phong = PhongTriangle {
        q: tri(),
        n: [
            Vec3::new(0.1, 0.0, -1.0),
            Vec3::new(-0.1, 0.1, -1.0),
            Vec3::NEG_Z,
        ],
    };
    let hit = phong.hit(&r).unwrap();
    assert_eq!(hit.refract(1.5), Err(DiffError::TotalInternalReflection));
}

#[test]
fn near_critical_angle_is_finite_or_an_error() {
    let crit = (1.0f32 / 1.5).asin();
    for k in -20..=20 {
        let a = crit + k as f32 * 1e-7;
        let v = Vec3::new(a.sin(), 0.0, a.cos());
        let hit = FlatTriangle { q: tri() }.hit(&ray(Vec3::ZERO, v)).unwrap();
        match hit.refract(1.5) {
            Ok(r) => assert!(r.is_finite()),
            Err(e) => assert!(matches!(
                e,
                DiffError::TotalInternalReflection | DiffError::NonFinite
            )),
        }
    }
}

#[test]
fn degenerate_triangles_are_errors() {
    let r = ray(Vec3::ZERO, Vec3::Z);
    let a = Vec3::new(0.0, 0.0, 1.0);
    let cases = [
        [a, a, a],                                                    // a point
        [a, a, Vec3::new(1.0, 0.0, 1.0)],                             // coincident vertices
        [a, Vec3::new(1.0, 0.0, 1.0), Vec3::new(2.0, 0.0, 1.0)],      // collinear
        [a, Vec3::new(1.0, 0.0, 1.0), Vec3::new(-1.0, 1e-9, 1.0)],    // nearly collinear
        [a, Vec3::new(f32::NAN, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)], // garbage in
    ];
    for q in cases {
        assert_eq!(
            FlatTriangle { q }.hit(&r),
            Err(DiffError::DegenerateTriangle),
            "{q:?}"
        );
        let n = [Vec3::Z; 3];
        assert_eq!(
            PhongTriangle { q, n }.hit(&r),
            Err(DiffError::DegenerateTriangle)
        );
        assert!(FlatTriangle { q }.transfer_jacobians(r.p, r.v).is_err());
    }
}

#[test]
fn vanishing_interpolated_normal_is_an_error() {
    // N₀ = −N₁ and the ray hits the midpoint of edge Q₀Q₁: n = ½N₀ + ½N₁ = 0.
    let q = tri();
    let n = [
        Vec3::new(0.0, 0.3, 1.0),
        Vec3::new(0.0, -0.3, -1.0),
        Vec3::Z,
    ];
    let r = ray(Vec3::new(0.0, -1.0, 0.0), Vec3::Z);
    assert_eq!(
        PhongTriangle { q, n }.hit(&r),
        Err(DiffError::DegenerateNormal)
    );
    let zero = [Vec3::ZERO; 3];
    assert_eq!(
        PhongTriangle { q, n: zero }.hit(&r),
        Err(DiffError::DegenerateNormal)
    );
}

#[test]
fn zero_direction_is_an_error() {
    assert_eq!(
        RayDiff::<N>::from_unnormalized(Vec3::ZERO, Vec3::ZERO, [Vec3::ZERO; N], [Vec3::X; N]),
        Err(DiffError::ZeroDirection)
    );
}

/// A deterministic sweep over random rays, triangles, normals and η: every result is either
/// an error or entirely finite.
#[test]
fn never_nan() {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let mut v3 = |s: f32| Vec3::new(rnd(), rnd(), rnd()) * s;
    let (mut ok, mut err) = (0, 0);
    for k in 0..20_000 {
        // Every 4th case is pushed towards degeneracy: tiny triangles, parallel rays.
        let tiny = if k % 4 == 0 { 1e-7 } else { 1.0 };
        let q0 = v3(2.0);
        let q = [q0, q0 + v3(1.0), q0 + v3(1.0) * tiny];
        let n = [v3(1.0), v3(1.0), v3(1.0)];
        let p = v3(3.0);
        let mut v = v3(1.0);
        if k % 4 == 1 {
            v = v.reject_from((q[1] - q[0]).cross(q[2] - q[0])); // parallel to the plane
        }
        let motion = TriangleMotion::<N> {
            dq: [
                std::array::from_fn(|_| v3(0.5)),
                std::array::from_fn(|_| v3(0.5)),
                std::array::from_fn(|_| v3(0.5)),
            ],
            dn: [
                std::array::from_fn(|_| v3(0.5)),
                std::array::from_fn(|_| v3(0.5)),
                std::array::from_fn(|_| v3(0.5)),
            ],
        };
        let eta = 0.5 + 1.5 * (v3(1.0).x + 1.0) / 2.0;
        let Ok(r) = RayDiff::from_unnormalized(
            p,
            v,
            std::array::from_fn(|_| v3(1.0)),
            std::array::from_fn(|_| v3(1.0)),
        ) else {
            err += 1;
            continue;
        };
        for hit in [
            FlatTriangle { q }.hit_moving(&r, &motion),
            PhongTriangle { q, n }.hit_moving(&r, &motion),
        ] {
            match hit {
                Ok(h) => {
                    assert!(h.ray.is_finite() && h.s.is_finite());
                    assert!(h.normal.is_finite() && h.dnormal.iter().all(|d| d.is_finite()));
                    assert!(h.ds.iter().all(|d| d.is_finite()));
                    for res in [h.reflect(), h.refract(eta)] {
                        match res {
                            Ok(o) => {
                                assert!(o.is_finite());
                                ok += 1;
                            }
                            Err(_) => err += 1,
                        }
                    }
                    let _ = reflect(&h.ray, h.normal, &h.dnormal).map(|o| assert!(o.is_finite()));
                    let _ =
                        refract(&h.ray, h.normal, &h.dnormal, eta).map(|o| assert!(o.is_finite()));
                }
                Err(_) => err += 1,
            }
        }
    }
    println!("never_nan: {ok} finite results, {err} errors");
    assert!(ok > 10_000 && err > 1_000);
}

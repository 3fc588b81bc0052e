//! `Shape` directives: `trianglemesh`, `bilinearmesh` (two triangles per patch), `plymesh`
//! (through [`crate::ply`], polygons fan-triangulated), `sphere` and `disk`, under the CTM and
//! `ReverseOrientation`, with the area light in effect.

use super::Loader;
use super::graphics_state::Xf;
use super::params::Params;
use super::tokenizer::clip;
use crate::error::LoadError;
use crate::similarity::uniform_scale;
use caustica_core::{Affine3A, Vec2, Vec3, Vec3A};
use caustica_scene::shape::{Disk, ShapeGeometry, Sphere, TriangleMesh};
use glam::Vec4;

/// The affine part of the CTM, if its bottom row is (0, 0, 0, 1) and it is finite.
pub(crate) fn affine(x: &Xf) -> Option<Affine3A> {
    if !x.m.row(3).abs_diff_eq(Vec4::W, 1e-6) || !x.m.is_finite() {
        return None;
    }
    Some(Affine3A::from_mat4(x.m))
}

/// A sphere, disk or mesh of an object definition moved by an instance's transform `a`.
/// Spheres and disks flip their orientation under a mirroring transform, as pbrt's do.
pub(crate) fn transform_geometry(
    g: ShapeGeometry,
    flip: bool,
    a: &Affine3A,
    x: &Xf,
) -> Result<(ShapeGeometry, bool), String> {
    let swaps = x.swaps_handedness();
    Ok(match g {
        ShapeGeometry::Mesh(mut m) => {
            m.transform(a);
            (ShapeGeometry::Mesh(m), flip)
        }
        ShapeGeometry::Sphere(s) => {
            let k = uniform_scale(a).ok_or(
                "a sphere's transform must be a uniform scale with rotation and translation",
            )?;
            (
                ShapeGeometry::Sphere(Sphere {
                    center: a.transform_point3(s.center),
                    radius: s.radius * k,
                }),
                flip ^ swaps,
            )
        }
        ShapeGeometry::Disk(d) => {
            let k = uniform_scale(a).ok_or(
                "a disk's transform must be a uniform scale with rotation and translation",
            )?;
            let nm = a.matrix3.inverse().transpose();
            (
                ShapeGeometry::Disk(Disk {
                    center: a.transform_point3(d.center),
                    normal: Vec3::from(nm * Vec3A::from(d.normal)).normalize_or_zero(),
                    radius: d.radius * k,
                }),
                flip ^ swaps,
            )
        }
    })
}

/// Surface area of a shape (for an area light's `power`).
fn area(g: &ShapeGeometry) -> f32 {
    match g {
        ShapeGeometry::Mesh(m) => m
            .indices
            .iter()
            .filter_map(|t| {
                let p = t.map(|k| m.positions.get(k as usize).copied());
                match p {
                    [Some(a), Some(b), Some(c)] => Some(0.5 * (b - a).cross(c - a).length()),
                    _ => None,
                }
            })
            .filter(|a| a.is_finite())
            .sum(),
        ShapeGeometry::Sphere(s) => 4.0 * std::f32::consts::PI * s.radius * s.radius,
        ShapeGeometry::Disk(d) => std::f32::consts::PI * d.radius * d.radius,
    }
}

/// pbrt orients a triangle with vertex normals toward them (`FaceForward`), which decides the
/// side an area light emits from; caustica's emitting triangles emit on their winding's side,
/// so each triangle is rewound to agree with its normals.
fn orient_to_normals(m: &mut TriangleMesh) {
    let Some(ns) = &m.normals else { return };
    for t in &mut m.indices {
        let [Some(a), Some(b), Some(c)] = t.map(|k| m.positions.get(k as usize).copied()) else {
            continue;
        };
        let [Some(na), Some(nb), Some(nc)] = t.map(|k| ns.get(k as usize).copied()) else {
            continue;
        };
        if (b - a).cross(c - a).dot(na + nb + nc) < 0.0 {
            t.swap(1, 2);
        }
    }
}

/// Vertex indices as `u32`, each below `n`; `per` indices per primitive.
fn indices(
    lo: &Loader,
    ps: &mut Params,
    n: usize,
    per: usize,
    ty: &str,
    line: usize,
    col: usize,
) -> Result<Vec<u32>, LoadError> {
    let pos = ps.pos("indices");
    let idx = match ps.ints("indices").map_err(|e| lo.perr(e))? {
        Some(v) => v,
        None if n == per => (0..per as i64).collect(),
        None => {
            return Err(lo.err(
                line,
                col,
                format!(
                    "{ty}: \"integer indices\" is required unless there are exactly {per} vertices"
                ),
            ));
        }
    };
    let (l, c) = pos.unwrap_or((line, col));
    if idx.len() % per != 0 {
        return Err(lo.err(
            l,
            c,
            format!(
                "{ty}: the number of indices must be a multiple of {per}, got {}",
                idx.len()
            ),
        ));
    }
    idx.iter()
        .map(|&k| {
            usize::try_from(k)
                .ok()
                .filter(|&k| k < n)
                .map(|k| k as u32)
                .ok_or_else(|| {
                    lo.err(
                        l,
                        c,
                        format!("{ty}: vertex index {k} out of range (there are {n} vertices)"),
                    )
                })
        })
        .collect()
}

/// `N` and `uv` of a mesh: as many as vertices.
fn mesh_attributes(
    lo: &mut Loader,
    ps: &mut Params,
    m: &mut TriangleMesh,
    ty: &str,
    line: usize,
) -> Result<(), LoadError> {
    let n = m.positions.len();
    let npos = ps.pos("N");
    if let Some(ns) = ps
        .vec3s("N", &["normal", "normal3"])
        .map_err(|e| lo.perr(e))?
    {
        if ns.len() != n {
            let (l, c) = npos.unwrap_or((line, 1));
            return Err(lo.err(l, c, format!("{ty}: {} normals for {n} vertices", ns.len())));
        }
        m.normals = Some(ns);
    }
    let uvpos = ps.pos("uv").or(ps.pos("st"));
    let uv = match ps.vec2s("uv").map_err(|e| lo.perr(e))? {
        Some(v) => Some(v),
        None => ps.vec2s("st").map_err(|e| lo.perr(e))?,
    };
    if let Some(uv) = uv {
        if uv.len() != n {
            let (l, c) = uvpos.unwrap_or((line, 1));
            return Err(lo.err(
                l,
                c,
                format!("{ty}: {} texture coordinates for {n} vertices", uv.len()),
            ));
        }
        m.uvs = Some(uv.into_iter().map(Vec2::from).collect());
    }
    for k in ["S", "faceIndices"] {
        if ps.has(k) {
            ps.ignore(k);
            lo.unsupported(
                line,
                format!("parameter '{k}' of Shape \"{ty}\" (not used by caustica)"),
            );
        }
    }
    Ok(())
}

pub(super) fn shape(
    lo: &mut Loader,
    ty: &str,
    tl: usize,
    tc: usize,
    ps: &mut Params,
    line: usize,
    col: usize,
) -> Result<(), LoadError> {
    let ctm = lo.gs.ctm;
    let a = affine(&ctm).ok_or_else(|| {
        lo.err(
            line,
            col,
            "Shape: the CTM must be affine (bottom row 0 0 0 1) and finite",
        )
    })?;
    let reverse = lo.gs.reverse_orientation;
    let emitting = lo.gs.area_light.is_some();
    // A constant alpha of 1 changes nothing; cut-outs would.
    if ps.has("alpha") {
        let pos = ps.pos("alpha").unwrap_or((line, col));
        match ps.float("alpha") {
            Ok(Some(1.0)) => {}
            _ => {
                return Err(lo.err(pos.0, pos.1, "Shape: \"alpha\" cut-outs are not supported (expected \"float alpha\" 1 or none)"));
            }
        }
    }
    let (geometry, flip) = match ty {
        "trianglemesh" | "bilinearmesh" => {
            let ppos = ps.pos("P");
            let p = ps
                .vec3s("P", &["point3", "point"])
                .map_err(|e| lo.perr(e))?
                .ok_or_else(|| lo.err(line, col, format!("Shape \"{ty}\" needs \"point3 P\"")))?;
            let _ = ppos;
            let per = if ty == "trianglemesh" { 3 } else { 4 };
            let idx = indices(lo, ps, p.len(), per, ty, line, col)?;
            let mut m = TriangleMesh {
                positions: p,
                ..Default::default()
            };
            if per == 3 {
                m.indices = idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            } else {
                // pbrt's patch vertices are p00 p10 p01 p11: two triangles with the winding
                // of ∂p/∂u × ∂p/∂v.
                let mut curved = false;
                for c in idx.chunks_exact(4) {
                    let [p00, p10, p01, p11] = [c[0], c[1], c[2], c[3]];
                    m.indices.push([p00, p10, p11]);
                    m.indices.push([p00, p11, p01]);
                    let q = [p00, p10, p01, p11].map(|k| m.positions[k as usize]);
                    let n = (q[1] - q[0]).cross(q[2] - q[0]);
                    let off = n.dot(q[3] - q[0]).abs();
                    if off > 1e-5 * n.length() * (q[3] - q[0]).length().max(f32::MIN_POSITIVE) {
                        curved = true;
                    }
                }
                if curved {
                    lo.approximated(
                        line,
                        "non-planar bilinear patches split into two flat triangles each",
                    );
                }
            }
            mesh_attributes(lo, ps, &mut m, ty, line)?;
            if m.indices.is_empty() {
                return Err(lo.err(line, col, format!("Shape \"{ty}\" has no primitives")));
            }
            m.transform(&a);
            if emitting {
                orient_to_normals(&mut m);
            }
            (ShapeGeometry::Mesh(m), reverse)
        }
        "plymesh" => {
            let (file, fl, fc) = ps
                .string("filename")
                .map_err(|e| lo.perr(e))?
                .ok_or_else(|| lo.err(line, col, "Shape \"plymesh\" needs \"string filename\""))?;
            let path = lo.input_file(&file, fl, fc)?;
            let mut m = crate::load_ply(&path).map_err(|e| match e {
                LoadError::File { path, message } => {
                    lo.err(fl, fc, format!("{}: {message}", path.display()))
                }
                e => e,
            })?;
            for k in ["displacement", "edgelength"] {
                if ps.has(k) {
                    ps.ignore(k);
                    lo.approximated(line, format!("plymesh '{k}' ignored (no displacement)"));
                }
            }
            m.transform(&a);
            if emitting {
                orient_to_normals(&mut m);
            }
            (ShapeGeometry::Mesh(m), reverse)
        }
        "sphere" => {
            let r = ps.float("radius").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
            let zmin = ps.float("zmin").map_err(|e| lo.perr(e))?.unwrap_or(-r);
            let zmax = ps.float("zmax").map_err(|e| lo.perr(e))?.unwrap_or(r);
            let phimax = ps.float("phimax").map_err(|e| lo.perr(e))?.unwrap_or(360.0);
            if zmin > -r || zmax < r || phimax < 360.0 {
                let (l, c) = ps
                    .pos("zmin")
                    .or(ps.pos("zmax"))
                    .or(ps.pos("phimax"))
                    .unwrap_or((line, col));
                return Err(lo.err(l, c, "Shape \"sphere\": partial spheres (zmin, zmax, phimax) are not supported (expected a full sphere)"));
            }
            if !(r > 0.0 && r.is_finite()) {
                return Err(lo.err(
                    line,
                    col,
                    format!("Shape \"sphere\": radius must be positive, got {r}"),
                ));
            }
            let k = uniform_scale(&a).ok_or_else(|| {
                lo.err(line, col, "Shape \"sphere\": the CTM must be a uniform scale with rotation and translation (ellipsoids are not supported)")
            })?;
            (
                ShapeGeometry::Sphere(Sphere {
                    center: a.transform_point3(Vec3::ZERO),
                    radius: r * k,
                }),
                reverse ^ ctm.swaps_handedness(),
            )
        }
        "disk" => {
            let r = ps.float("radius").map_err(|e| lo.perr(e))?.unwrap_or(1.0);
            let h = ps.float("height").map_err(|e| lo.perr(e))?.unwrap_or(0.0);
            let ri = ps
                .float("innerradius")
                .map_err(|e| lo.perr(e))?
                .unwrap_or(0.0);
            let phimax = ps.float("phimax").map_err(|e| lo.perr(e))?.unwrap_or(360.0);
            if ri > 0.0 || phimax < 360.0 {
                let (l, c) = ps
                    .pos("innerradius")
                    .or(ps.pos("phimax"))
                    .unwrap_or((line, col));
                return Err(lo.err(l, c, "Shape \"disk\": annuli and partial disks (innerradius > 0, phimax < 360) are not supported"));
            }
            if !(r > 0.0 && r.is_finite()) {
                return Err(lo.err(
                    line,
                    col,
                    format!("Shape \"disk\": radius must be positive, got {r}"),
                ));
            }
            let ex = Vec3::from(a.matrix3.x_axis);
            let ey = Vec3::from(a.matrix3.y_axis);
            let (lx, ly) = (ex.length(), ey.length());
            if !(lx > 0.0 && (lx - ly).abs() <= 1e-4 * lx && ex.dot(ey).abs() <= 1e-4 * lx * ly) {
                return Err(lo.err(line, col, "Shape \"disk\": the CTM must scale the disk uniformly in its plane (ellipses are not supported)"));
            }
            let nm = a.matrix3.inverse().transpose();
            let normal = Vec3::from(nm * Vec3A::Z).normalize_or_zero();
            (
                ShapeGeometry::Disk(Disk {
                    center: a.transform_point3(Vec3::new(0.0, 0.0, h)),
                    normal,
                    radius: r * lx,
                }),
                reverse ^ ctm.swaps_handedness(),
            )
        }
        other => {
            return Err(lo.err(tl, tc, format!(
                "unknown or unsupported shape type \"{}\" (supported: trianglemesh, plymesh, bilinearmesh, sphere, disk)",
                clip(other)
            )));
        }
    };
    let emission = match lo.gs.area_light.clone() {
        None => None,
        Some(al) => {
            let mut radiance = al.radiance;
            if let Some(power) = al.power {
                let k = std::f32::consts::PI * area(&geometry);
                if !(k > 0.0 && k.is_finite()) {
                    return Err(lo.err(
                        line,
                        col,
                        "AreaLightSource \"power\": the shape has no area",
                    ));
                }
                radiance *= power / k;
            }
            Some((radiance, al.spectrum))
        }
    };
    lo.add_shape(geometry, flip, emission, line, col)
}

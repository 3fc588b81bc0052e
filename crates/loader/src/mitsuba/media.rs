//! Participating media: `<medium>` (homogeneous, heterogeneous), `<phase>` (isotropic, hg),
//! `<volume>` (constvolume, gridvolume with Mitsuba's `.vol` files) and `<ref>`s to media.
//!
//! A heterogeneous medium whose `sigma_t` is a constant (a `constvolume` or a plain value) is
//! loaded as a homogeneous medium: the density is constant inside its boundary either way.

use super::transform::affine;
use super::{Doc, Loader, Props, Val};
use crate::error::LoadError;
use crate::vol::read_vol;
use caustica_core::{Affine3A, Spectrum};
use caustica_scene::medium::{DensityGrid, Medium};
use caustica_scene::phase::PhaseFunction;
use roxmltree::Node;

/// Mitsuba 3's default single-scattering albedo of both medium plugins.
const DEFAULT_ALBEDO: f32 = 0.75;
/// Mitsuba 3's default mean cosine of `hg`.
const DEFAULT_HG_G: f32 = 0.8;

/// A coefficient: a constant with the byte offset of its value, or a density grid.
enum Coef {
    Const(Spectrum, usize),
    Grid(DensityGrid),
}

/// Adds the `<medium>` element `n` to the scene (its `id`, if any, is declared and names it)
/// and returns its index.
pub(super) fn add_medium(lo: &mut Loader, d: &Doc, n: Node) -> Result<u32, LoadError> {
    let id = lo.declare_id(d, n)?;
    let m = medium(lo, d, n)?;
    let name = id.clone().unwrap_or_else(|| lo.anonymous_name("medium"));
    let idx =
        lo.b.add_medium(&name, m)
            .map_err(|e| d.err_at(d.pos(n), e.to_string()))?;
    if let Some(id) = id {
        lo.media.insert(id, idx);
    }
    Ok(idx)
}

/// The medium a `<ref id=…/>` or a nested `<medium>` names.
pub(super) fn medium_child(lo: &mut Loader, d: &Doc, c: Node) -> Result<u32, LoadError> {
    if c.tag_name().name() == "medium" {
        return add_medium(lo, d, c);
    }
    let (id, pos) = lo.req_attr(d, c, "id")?;
    match lo.media.get(&id) {
        Some(&m) => Ok(m),
        None if lo.ids.contains(&id) => Err(d.err_at(pos, format!("'{id}' is not a medium"))),
        None => Err(d.err_at(
            pos,
            format!("medium '{id}' is referenced but not defined (declare <medium id=\"{id}\"> before it)"),
        )),
    }
}

/// A non-negative constant (rgb, spectrum or float) with the offset of its value.
fn constant(d: &Doc, p: &mut Props, name: &str) -> Result<Option<(Spectrum, usize)>, LoadError> {
    let Some(prop) = p.take(name) else {
        return Ok(None);
    };
    let s = match prop.val {
        Val::Rgb(s) => s,
        Val::Float(x) | Val::Flat(x) => Spectrum::splat(x),
        Val::Int(i) => Spectrum::splat(i as f32),
        _ => {
            return Err(d.err_at(
                prop.pos,
                format!("parameter '{name}' must be an rgb, spectrum or float value"),
            ));
        }
    };
    if !s.is_finite() || s.min_component() < 0.0 {
        return Err(d.err_at(
            prop.pos,
            format!("'{name}' must be finite and non-negative, got {:?}", s.c),
        ));
    }
    Ok(Some((s, prop.pos)))
}

/// Parameter `name` of a medium: a value, or a nested `<volume name="…">` (constvolume, or
/// gridvolume if `grid_ok`).
fn coefficient(
    lo: &mut Loader,
    d: &Doc,
    p: &mut Props,
    name: &str,
    grid_ok: bool,
) -> Result<Option<Coef>, LoadError> {
    let found = p
        .children
        .iter()
        .position(|c| c.tag_name().name() == "volume" && c.attribute("name") == Some(name));
    let value = constant(d, p, name)?;
    let Some(i) = found else {
        return Ok(value.map(|(s, pos)| Coef::Const(s, pos)));
    };
    let v = p.children.remove(i);
    if value.is_some() {
        return Err(d.err_at(d.pos(v), format!("parameter '{name}' given twice")));
    }
    let (t, tpos) = lo.req_attr(d, v, "type")?;
    let mut vp = lo.props(d, v)?;
    let out = match t.as_str() {
        "constvolume" | "const" => {
            let (s, pos) = constant(d, &mut vp, "value")?.unwrap_or((Spectrum::ONE, d.pos(v)));
            let _ = vp.transform(d, "to_world")?;
            Coef::Const(s, pos)
        }
        "gridvolume" | "grid" if grid_ok => Coef::Grid(grid_volume(lo, d, v, &mut vp)?),
        "gridvolume" | "grid" => {
            return Err(d.err_at(
                tpos,
                format!("'{name}' cannot be a gridvolume (only sigma_t of a heterogeneous medium can; give a constant or a constvolume)"),
            ));
        }
        other => {
            return Err(d.err_at(
                tpos,
                format!("unknown volume type '{other}' (supported: constvolume, gridvolume)"),
            ));
        }
    };
    for c in std::mem::take(&mut vp.children) {
        lo.unsupported(
            d,
            c,
            format!("<{}> inside {}", c.tag_name().name(), vp.desc),
        );
    }
    lo.leftovers(d, vp);
    Ok(Some(out))
}

/// A `<volume type="gridvolume">`: the `.vol` file (relative to the XML file) placed by
/// `to_world` (the unit cube; with `use_grid_bbox` the file's box, then `to_world`).
fn grid_volume(
    lo: &mut Loader,
    d: &Doc,
    v: Node,
    vp: &mut Props,
) -> Result<DensityGrid, LoadError> {
    let (file, fpos) = vp
        .string(d, "filename")?
        .ok_or_else(|| d.err_at(d.pos(v), "gridvolume needs a 'filename' string"))?;
    let path = d.input_file(&file, fpos)?;
    let g = read_vol(&path).map_err(|e| d.err_at(fpos, e))?;
    if g.channels == 3 {
        lo.approximated(
            d,
            v,
            format!("the 3 channels of '{file}' averaged into one density"),
        );
    }
    let mut to_world = match vp.transform(d, "to_world")? {
        Some((m, pos)) => affine(d, pos, m)?,
        None => Affine3A::IDENTITY,
    };
    if vp.bool(d, "use_grid_bbox")? == Some(true) {
        let [lo_, hi] = g.bbox;
        to_world *= crate::builtin::unit_cube_to_box(lo_, hi);
    }
    if let Some((f, _)) = vp.string(d, "filter_type")?
        && f != "trilinear"
    {
        lo.approximated(
            d,
            v,
            format!("gridvolume filter_type '{f}' replaced by trilinear"),
        );
    }
    if let Some((w, _)) = vp.string(d, "wrap_mode")?
        && w != "clamp"
    {
        lo.approximated(
            d,
            v,
            format!("gridvolume wrap_mode '{w}' replaced by clamp"),
        );
    }
    for k in ["raw", "accel"] {
        let _ = vp.bool(d, k)?;
    }
    let _ = vp.float(d, "max_value")?;
    DensityGrid::new(g.res, g.data, to_world)
        .map_err(|e| d.err_at(d.pos(v), format!("gridvolume '{file}': {e}")))
}

/// The medium's `<phase>` (isotropic when absent).
fn phase(lo: &mut Loader, d: &Doc, p: &mut Props) -> Result<PhaseFunction, LoadError> {
    let mut phases = p
        .children
        .iter()
        .copied()
        .filter(|c| c.tag_name().name() == "phase")
        .collect::<Vec<_>>()
        .into_iter();
    p.children.retain(|c| c.tag_name().name() != "phase");
    let Some(n) = phases.next() else {
        return Ok(PhaseFunction::default());
    };
    if let Some(extra) = phases.next() {
        return Err(d.err_at(d.pos(extra), "a medium takes one <phase>"));
    }
    let (t, tpos) = lo.req_attr(d, n, "type")?;
    let mut pp = lo.props(d, n)?;
    let out = match t.as_str() {
        "isotropic" => PhaseFunction::default(),
        "hg" => {
            let pos = pp.map.get("g").map_or(d.pos(n), |x| x.pos);
            let g = pp.float(d, "g")?.unwrap_or(DEFAULT_HG_G);
            PhaseFunction::henyey_greenstein(g).map_err(|e| d.err_at(pos, format!("hg: {e}")))?
        }
        other => {
            return Err(d.err_at(
                tpos,
                format!("unknown phase type '{other}' (supported: isotropic, hg)"),
            ));
        }
    };
    for c in std::mem::take(&mut pp.children) {
        lo.unsupported(
            d,
            c,
            format!("<{}> inside {}", c.tag_name().name(), pp.desc),
        );
    }
    lo.leftovers(d, pp);
    Ok(out)
}

/// Converts a `<medium>` element.
fn medium(lo: &mut Loader, d: &Doc, n: Node) -> Result<Medium, LoadError> {
    let (t, tpos) = lo.req_attr(d, n, "type")?;
    if t != "homogeneous" && t != "heterogeneous" {
        return Err(d.err_at(
            tpos,
            format!("unknown medium type '{t}' (supported: homogeneous, heterogeneous)"),
        ));
    }
    let mut p = lo.props(d, n)?;
    let phase = phase(lo, d, &mut p)?;
    let scale = match p.map.get("scale").map(|x| x.pos) {
        Some(pos) => {
            let s = p.float(d, "scale")?.unwrap_or(1.0);
            if s < 0.0 {
                return Err(d.err_at(pos, format!("'scale' must be non-negative, got {s}")));
            }
            s
        }
        None => 1.0,
    };
    let _ = p.bool(d, "sample_emitters")?;
    let heterogeneous = t == "heterogeneous";
    let sigma_t = coefficient(lo, d, &mut p, "sigma_t", heterogeneous)?;
    let albedo = coefficient(lo, d, &mut p, "albedo", false)?;
    let (sigma_a, sigma_s) = if heterogeneous {
        (None, None)
    } else {
        (
            constant(d, &mut p, "sigma_a")?,
            constant(d, &mut p, "sigma_s")?,
        )
    };
    let albedo = match albedo {
        Some(Coef::Const(a, pos)) => {
            if a.max_component() > 1.0 {
                return Err(d.err_at(pos, format!("'albedo' must lie in [0, 1], got {:?}", a.c)));
            }
            Some(a)
        }
        Some(Coef::Grid(_)) | None => None,
    };
    let medium = match (sigma_t, albedo, sigma_a, sigma_s) {
        (_, _, Some(_), None) | (_, _, None, Some(_)) => {
            return Err(d.err_at(
                d.pos(n),
                "medium: give both 'sigma_a' and 'sigma_s', or 'sigma_t' and 'albedo'",
            ));
        }
        (Some(_), _, Some(_), Some(_)) | (_, Some(_), Some(_), Some(_)) => {
            return Err(d.err_at(
                d.pos(n),
                "medium: give either 'sigma_a' and 'sigma_s', or 'sigma_t' and 'albedo', not both",
            ));
        }
        (None, None, Some((sa, _)), Some((ss, _))) => {
            Medium::homogeneous(sa * scale, ss * scale, phase)
        }
        // σ_t and albedo: upsampled in spectral mode as Mitsuba's scalar_spectral does.
        (Some(Coef::Grid(grid)), albedo, None, None) => {
            let albedo = albedo.unwrap_or(Spectrum::splat(DEFAULT_ALBEDO));
            Medium::grid_albedo(grid, scale, albedo, phase)
        }
        (sigma_t, albedo, None, None) => {
            let st = match sigma_t {
                Some(Coef::Const(s, _)) => s,
                _ => Spectrum::ONE,
            };
            let albedo = albedo.unwrap_or(Spectrum::splat(DEFAULT_ALBEDO));
            Medium::homogeneous_albedo(st, scale, albedo, phase)
        }
    };
    for c in std::mem::take(&mut p.children) {
        lo.unsupported(d, c, format!("<{}> inside {}", c.tag_name().name(), p.desc));
    }
    lo.leftovers(d, p);
    Ok(medium)
}

//! pbrt's typed parameter lists: `"float fov" [ 45 ]`, `"rgb reflectance" [ .5 .5 .5 ]`,
//! `"spectrum eta" "glass-BK7"`, `"blackbody L" 3000`, `"texture reflectance" "checks"`,
//! `"bool twosided" true`. Values are checked against their declared type when read; the
//! converters take (and mark) the parameters they understand, and the rest are reported as
//! leftovers.

use super::tokenizer::{Tok, Token, clip};
use caustica_core::{Spectrum, Vec3};

/// A parameter's values.
#[derive(Clone, Debug)]
pub(crate) enum Vals {
    Nums(Vec<f64>),
    Strs(Vec<String>),
    Bools(Vec<bool>),
}

/// One `"type name" value` pair.
#[derive(Clone, Debug)]
pub(crate) struct Param {
    pub ty: String,
    pub name: String,
    pub vals: Vals,
    pub line: usize,
    pub col: usize,
    used: bool,
}

/// An error at a line and column of the current file.
#[derive(Debug)]
pub(crate) struct PErr {
    pub line: usize,
    pub col: usize,
    pub message: String,
}

impl PErr {
    pub fn at(line: usize, col: usize, message: impl Into<String>) -> Self {
        Self {
            line,
            col,
            message: message.into(),
        }
    }
}

/// The types pbrt-v4 declares (plus `color`, an old name of `rgb`).
const TYPES: &[&str] = &[
    "float",
    "integer",
    "bool",
    "string",
    "point2",
    "vector2",
    "point3",
    "vector3",
    "normal3",
    "normal",
    "point",
    "vector",
    "rgb",
    "color",
    "blackbody",
    "spectrum",
    "texture",
];

/// A spectrum-valued parameter as written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SpecVal {
    Rgb(Spectrum),
    /// A `float` value or a one-number `spectrum` (constant over wavelength).
    Constant(f32),
    /// A named spectrum (`"glass-BK7"`, `"metal-Au-eta"`, `"stdillum-D65"`).
    Named(String),
    /// `blackbody` temperature (K).
    Blackbody(f32),
    /// `spectrum` as (wavelength nm, value) pairs.
    Sampled(Vec<(f32, f32)>),
    /// A `texture` reference by name.
    Texture(String),
}

/// The parameters of one directive.
#[derive(Clone, Debug, Default)]
pub(crate) struct Params {
    pub list: Vec<Param>,
}

/// Reads a parameter list from `toks` starting at `*i`: pairs of a quoted declaration and a
/// value (a bracketed list or one number, string or bare `true`/`false`).
pub(crate) fn parse_params(toks: &[Token], i: &mut usize) -> Result<Params, PErr> {
    let mut out = Params::default();
    let mut names = std::collections::HashSet::new();
    while let Some(t) = toks.get(*i) {
        let Tok::Str(decl) = &t.tok else { break };
        *i += 1;
        let words: Vec<&str> = decl.split_whitespace().collect();
        let (ty, name) = match words.as_slice() {
            [ty, name] => (*ty, *name),
            _ => {
                return Err(PErr::at(
                    t.line,
                    t.col,
                    format!(
                        "bad parameter declaration \"{}\" (expected \"type name\", e.g. \"float fov\")",
                        clip(decl)
                    ),
                ));
            }
        };
        if !TYPES.contains(&ty) {
            return Err(PErr::at(
                t.line,
                t.col,
                format!(
                    "unknown parameter type '{}' (expected one of: {})",
                    clip(ty),
                    TYPES.join(", ")
                ),
            ));
        }
        if !names.insert(name) {
            return Err(PErr::at(
                t.line,
                t.col,
                format!("parameter '{}' given twice", clip(name)),
            ));
        }
        let vals = parse_value(toks, i, t, ty, name)?;
        out.list.push(Param {
            ty: ty.to_string(),
            name: name.to_string(),
            vals,
            line: t.line,
            col: t.col,
            used: false,
        });
    }
    Ok(out)
}

fn parse_value(
    toks: &[Token],
    i: &mut usize,
    decl: &Token,
    ty: &str,
    name: &str,
) -> Result<Vals, PErr> {
    let Some(first) = toks.get(*i) else {
        return Err(PErr::at(
            decl.line,
            decl.col,
            format!(
                "parameter '{}' has no value (expected a value or '[')",
                clip(name)
            ),
        ));
    };
    let items: Vec<&Token> = if first.tok == Tok::Open {
        let mut v = Vec::new();
        *i += 1;
        loop {
            match toks.get(*i) {
                None => {
                    return Err(PErr::at(
                        first.line,
                        first.col,
                        format!(
                            "unterminated '[' of parameter '{}' (expected ']')",
                            clip(name)
                        ),
                    ));
                }
                Some(t) if t.tok == Tok::Close => {
                    *i += 1;
                    break;
                }
                Some(t) if t.tok == Tok::Open => {
                    return Err(PErr::at(
                        t.line,
                        t.col,
                        format!("nested '[' in parameter '{}' (expected ']')", clip(name)),
                    ));
                }
                Some(t) => {
                    v.push(t);
                    *i += 1;
                }
            }
        }
        v
    } else if first.tok == Tok::Close {
        return Err(PErr::at(
            first.line,
            first.col,
            format!("unexpected ']' as the value of parameter '{}'", clip(name)),
        ));
    } else {
        *i += 1;
        vec![first]
    };
    let want_bool = ty == "bool";
    if items.is_empty() {
        return Err(PErr::at(
            decl.line,
            decl.col,
            format!("parameter '{}' has an empty value list", clip(name)),
        ));
    }
    let vals = match &items[0].tok {
        Tok::Num(_) => {
            let mut v = Vec::with_capacity(items.len());
            for t in &items {
                match t.tok {
                    Tok::Num(x) => v.push(x),
                    _ => return Err(mixed(t, name)),
                }
            }
            Vals::Nums(v)
        }
        Tok::Str(_) if !want_bool => {
            let mut v = Vec::with_capacity(items.len());
            for t in &items {
                match &t.tok {
                    Tok::Str(s) => v.push(s.clone()),
                    _ => return Err(mixed(t, name)),
                }
            }
            Vals::Strs(v)
        }
        _ => {
            let mut v = Vec::with_capacity(items.len());
            for t in &items {
                let b = match &t.tok {
                    Tok::Str(s) | Tok::Word(s) if s == "true" => true,
                    Tok::Str(s) | Tok::Word(s) if s == "false" => false,
                    _ => {
                        return Err(PErr::at(
                            t.line,
                            t.col,
                            format!(
                                "parameter '{}': expected true or false, got {}",
                                clip(name),
                                t.describe()
                            ),
                        ));
                    }
                };
                v.push(b);
            }
            Vals::Bools(v)
        }
    };
    check_kind(&vals, items[0], ty, name)?;
    Ok(vals)
}

fn mixed(t: &Token, name: &str) -> PErr {
    PErr::at(
        t.line,
        t.col,
        format!(
            "parameter '{}' mixes value kinds: unexpected {}",
            clip(name),
            t.describe()
        ),
    )
}

/// Checks that values fit the declared type (numbers for numeric types, strings for strings,
/// and counts that are multiples of the tuple size).
fn check_kind(vals: &Vals, at: &Token, ty: &str, name: &str) -> Result<(), PErr> {
    let err = |m: String| Err(PErr::at(at.line, at.col, m));
    let tuple = match ty {
        "point2" | "vector2" => 2,
        "point3" | "vector3" | "normal3" | "normal" | "point" | "vector" | "rgb" | "color" => 3,
        _ => 1,
    };
    match (ty, vals) {
        ("bool", Vals::Bools(_)) => Ok(()),
        ("bool", _) => err(format!(
            "parameter '{name}' is a bool: expected true or false"
        )),
        ("string" | "texture", Vals::Strs(_)) => Ok(()),
        ("string" | "texture", _) => err(format!(
            "parameter '{name}' is a {ty}: expected a quoted string"
        )),
        ("spectrum", Vals::Nums(v)) if v.len() != 1 && v.len() % 2 != 0 => err(format!(
            "parameter '{name}': a sampled spectrum needs (wavelength, value) pairs, got {} numbers",
            v.len()
        )),
        ("spectrum", Vals::Nums(_) | Vals::Strs(_)) => Ok(()),
        ("spectrum", _) => err(format!(
            "parameter '{name}' is a spectrum: expected numbers or a spectrum name"
        )),
        (_, Vals::Nums(v)) => {
            if v.len() % tuple != 0 {
                return err(format!(
                    "parameter '{name}' is a {ty}: expected a multiple of {tuple} numbers, got {}",
                    v.len()
                ));
            }
            if ty == "integer"
                && let Some(x) = v
                    .iter()
                    .find(|x| x.fract() != 0.0 || x.abs() > 2f64.powi(53))
            {
                return err(format!("parameter '{name}' is an integer: got {x}"));
            }
            Ok(())
        }
        _ => err(format!("parameter '{name}' is a {ty}: expected numbers")),
    }
}

/// An f64 read from a file as f32, which must stay finite.
fn to_f32(x: f64, p: &Param) -> Result<f32, PErr> {
    let y = x as f32;
    if y.is_finite() {
        Ok(y)
    } else {
        Err(PErr::at(
            p.line,
            p.col,
            format!(
                "parameter '{}': {x} is out of single-precision range",
                p.name
            ),
        ))
    }
}

impl Params {
    fn find(&mut self, name: &str) -> Option<&mut Param> {
        let p = self.list.iter_mut().find(|p| p.name == name)?;
        p.used = true;
        Some(p)
    }

    /// True if the list has `name` (without taking it).
    pub fn has(&self, name: &str) -> bool {
        self.list.iter().any(|p| p.name == name)
    }

    /// Line and column of `name`'s declaration.
    pub fn pos(&self, name: &str) -> Option<(usize, usize)> {
        self.list
            .iter()
            .find(|p| p.name == name)
            .map(|p| (p.line, p.col))
    }

    fn numbers(
        &mut self,
        name: &str,
        types: &[&str],
        what: &str,
    ) -> Result<Option<(Vec<f64>, Param)>, PErr> {
        let Some(p) = self.find(name) else {
            return Ok(None);
        };
        if !types.contains(&p.ty.as_str()) {
            return Err(PErr::at(
                p.line,
                p.col,
                format!("parameter '{name}' must be {what}, got type '{}'", p.ty),
            ));
        }
        match &p.vals {
            Vals::Nums(v) => {
                let v = v.clone();
                let p = p.clone();
                Ok(Some((v, p)))
            }
            _ => Err(PErr::at(
                p.line,
                p.col,
                format!("parameter '{name}' must be {what}"),
            )),
        }
    }

    /// Float array (`float`, or `integer` values).
    pub fn floats(&mut self, name: &str) -> Result<Option<Vec<f32>>, PErr> {
        match self.numbers(name, &["float", "integer"], "a float")? {
            None => Ok(None),
            Some((v, p)) => v
                .iter()
                .map(|&x| to_f32(x, &p))
                .collect::<Result<_, _>>()
                .map(Some),
        }
    }

    /// One float.
    pub fn float(&mut self, name: &str) -> Result<Option<f32>, PErr> {
        let pos = self.pos(name);
        let v = self.floats(name)?;
        single(name, "float", pos, v)
    }

    /// Integer array.
    pub fn ints(&mut self, name: &str) -> Result<Option<Vec<i64>>, PErr> {
        Ok(self
            .numbers(name, &["integer"], "an integer")?
            .map(|(v, _)| v.iter().map(|&x| x as i64).collect()))
    }

    /// One integer.
    pub fn int(&mut self, name: &str) -> Result<Option<i64>, PErr> {
        let pos = self.pos(name);
        let v = self.ints(name)?;
        single(name, "integer", pos, v)
    }

    /// One bool.
    pub fn bool(&mut self, name: &str) -> Result<Option<bool>, PErr> {
        let Some(p) = self.find(name) else {
            return Ok(None);
        };
        match &p.vals {
            Vals::Bools(v) if v.len() == 1 && p.ty == "bool" => Ok(Some(v[0])),
            _ => Err(PErr::at(
                p.line,
                p.col,
                format!("parameter '{name}' must be one bool (\"bool {name}\" true or false)"),
            )),
        }
    }

    /// One string with its position.
    pub fn string(&mut self, name: &str) -> Result<Option<(String, usize, usize)>, PErr> {
        let Some(p) = self.find(name) else {
            return Ok(None);
        };
        match &p.vals {
            Vals::Strs(v) if v.len() == 1 && p.ty == "string" => {
                Ok(Some((v[0].clone(), p.line, p.col)))
            }
            _ => Err(PErr::at(
                p.line,
                p.col,
                format!("parameter '{name}' must be one string (\"string {name}\" \"…\")"),
            )),
        }
    }

    /// 3-vectors (`point3`, `vector3`, `normal`, … as `types` allows).
    pub fn vec3s(&mut self, name: &str, types: &[&str]) -> Result<Option<Vec<Vec3>>, PErr> {
        let what = format!("of type {}", types.join(" or "));
        match self.numbers(name, types, &what)? {
            None => Ok(None),
            Some((v, p)) => {
                let mut out = Vec::with_capacity(v.len() / 3);
                for c in v.chunks_exact(3) {
                    out.push(Vec3::new(
                        to_f32(c[0], &p)?,
                        to_f32(c[1], &p)?,
                        to_f32(c[2], &p)?,
                    ));
                }
                Ok(Some(out))
            }
        }
    }

    /// One point (`point3` or `point`).
    pub fn point3(&mut self, name: &str) -> Result<Option<Vec3>, PErr> {
        let pos = self.pos(name);
        match self.vec3s(name, &["point3", "point"])? {
            None => Ok(None),
            Some(v) if v.len() == 1 => Ok(Some(v[0])),
            Some(v) => {
                let (l, c) = pos.unwrap_or((0, 0));
                Err(PErr::at(
                    l,
                    c,
                    format!("parameter '{name}' must be one point, got {}", v.len()),
                ))
            }
        }
    }

    /// 2-vectors (`point2`, or `float` pairs as pbrt-v3 wrote `uv`).
    pub fn vec2s(&mut self, name: &str) -> Result<Option<Vec<[f32; 2]>>, PErr> {
        match self.numbers(name, &["point2", "vector2", "float"], "of type point2")? {
            None => Ok(None),
            Some((v, p)) => {
                if v.len() % 2 != 0 {
                    return Err(PErr::at(
                        p.line,
                        p.col,
                        format!("parameter '{name}' needs pairs of numbers, got {}", v.len()),
                    ));
                }
                v.chunks_exact(2)
                    .map(|c| Ok([to_f32(c[0], &p)?, to_f32(c[1], &p)?]))
                    .collect::<Result<_, _>>()
                    .map(Some)
            }
        }
    }

    /// A spectrum-valued parameter in any of its forms (`rgb`, `spectrum`, `blackbody`,
    /// `float`, `texture`).
    pub fn spectrum(&mut self, name: &str) -> Result<Option<(SpecVal, usize, usize)>, PErr> {
        let Some(p) = self.find(name) else {
            return Ok(None);
        };
        let p = p.clone();
        let bad = |m: &str| Err(PErr::at(p.line, p.col, format!("parameter '{name}': {m}")));
        let v = match (p.ty.as_str(), &p.vals) {
            ("rgb" | "color", Vals::Nums(v)) if v.len() == 3 => {
                let c = [to_f32(v[0], &p)?, to_f32(v[1], &p)?, to_f32(v[2], &p)?];
                if c.iter().any(|&x| x < 0.0) {
                    return bad("rgb values must be non-negative");
                }
                SpecVal::Rgb(Spectrum::from_rgb(c))
            }
            ("rgb" | "color", _) => return bad("expected 3 numbers"),
            ("blackbody", Vals::Nums(v)) if v.len() == 1 => {
                let t = to_f32(v[0], &p)?;
                if !(t > 0.0 && t <= 1e6) {
                    return bad(&format!(
                        "blackbody temperature must be in (0, 1e6] K, got {t}"
                    ));
                }
                SpecVal::Blackbody(t)
            }
            ("blackbody", _) => return bad("expected one temperature (K)"),
            ("float", Vals::Nums(v)) | ("spectrum", Vals::Nums(v)) if v.len() == 1 => {
                SpecVal::Constant(to_f32(v[0], &p)?)
            }
            ("spectrum", Vals::Nums(v)) => {
                let mut pairs = Vec::with_capacity(v.len() / 2);
                for c in v.chunks_exact(2) {
                    pairs.push((to_f32(c[0], &p)?, to_f32(c[1], &p)?));
                }
                if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
                    return bad("sampled spectrum wavelengths must increase");
                }
                SpecVal::Sampled(pairs)
            }
            ("spectrum", Vals::Strs(v)) if v.len() == 1 => SpecVal::Named(v[0].clone()),
            ("texture", Vals::Strs(v)) if v.len() == 1 => SpecVal::Texture(v[0].clone()),
            (ty, _) => {
                return bad(&format!(
                    "expected an rgb, spectrum, blackbody, float or texture value, got type '{ty}' with {} value(s)",
                    match &p.vals {
                        Vals::Nums(v) => v.len(),
                        Vals::Strs(v) => v.len(),
                        Vals::Bools(v) => v.len(),
                    }
                ));
            }
        };
        Ok(Some((v, p.line, p.col)))
    }

    /// Marks `name` used without reading it (a parameter deliberately ignored).
    pub fn ignore(&mut self, name: &str) {
        let _ = self.find(name);
    }

    /// The parameters nothing took: `'type name' (line L)`.
    pub fn leftovers(&self) -> Vec<(String, usize)> {
        self.list
            .iter()
            .filter(|p| !p.used)
            .map(|p| (format!("\"{} {}\"", p.ty, clip(&p.name)), p.line))
            .collect()
    }
}

/// The one value of parameter `name` (`what` it holds, for the error at its declaration `pos`).
fn single<T: Copy>(
    name: &str,
    what: &str,
    pos: Option<(usize, usize)>,
    values: Option<Vec<T>>,
) -> Result<Option<T>, PErr> {
    match values {
        None => Ok(None),
        Some(v) if v.len() == 1 => Ok(Some(v[0])),
        Some(v) => {
            let (l, c) = pos.unwrap_or((0, 0));
            Err(PErr::at(
                l,
                c,
                format!(
                    "parameter '{name}' must be one {what}, got {} values",
                    v.len()
                ),
            ))
        }
    }
}

//! Loader for Mitsuba 3 XML scenes (version 2.x/3.x), the subset documented in
//! `docs/mitsuba.md`.
//!
//! The document is walked once, in order (as Mitsuba does): `<default>` parameters and `id`s are
//! visible to the elements after them. Every plugin's parameters are collected into a property
//! list; the converter takes the ones it understands, and whatever is left over is reported in
//! ONE warning naming each element and its line. Elements whose absence would change what the
//! image means (unknown shape, emitter or BSDF types, missing mesh files) are errors, which
//! carry the file, line and column.

mod media;
mod plugins;
#[cfg(test)]
mod tests;
mod transform;

use crate::error::LoadError;
use caustica_core::{Mat4, Spectrum, Vec3};
use caustica_scene::scene::SceneBuilder;
use roxmltree::{Document, Node};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// Maximum `<include>` depth.
const MAX_INCLUDE_DEPTH: usize = 32;
/// Maximum nesting of plugin elements (e.g. `twosided` around `twosided` …).
const MAX_NESTING: usize = 32;
/// Maximum length in bytes of an attribute value after `$name` substitution: parameters
/// defined from parameters would otherwise grow exponentially ("billion laughs").
const MAX_SUBSTITUTED_LEN: usize = 1 << 16;

/// Reads the Mitsuba XML scene at `path`; `defines` (`-D name=value`) override `<default>`s.
pub fn load_mitsuba(path: &Path, defines: &[(String, String)]) -> Result<SceneBuilder, LoadError> {
    let text = read_text(path, "cannot read scene file")?;
    parse_mitsuba(&text, path, defines)
}

/// Parses Mitsuba XML `text`; `path` names the file in errors and anchors relative file names
/// (meshes, includes). `defines` override `<default>` parameters.
pub fn parse_mitsuba(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneBuilder, LoadError> {
    let name = path.file_stem().map_or_else(
        || "mitsuba".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    let mut lo = Loader {
        b: SceneBuilder::new(name),
        params: defines.iter().cloned().collect(),
        known: Default::default(),
        bsdfs: HashMap::new(),
        textures: HashMap::new(),
        media: HashMap::new(),
        ids: HashSet::new(),
        unsupported: Vec::new(),
        approximations: Vec::new(),
        include_stack: vec![canonical(path)],
        default_material: None,
        default_emitter_material: None,
        anonymous: 0,
    };
    lo.document(text, path)?;
    let known = lo.known.take();
    if let Some((name, _)) = defines.iter().find(|(n, _)| !known.contains(n)) {
        let names: Vec<&str> = known.iter().map(String::as_str).collect();
        return Err(LoadError::UnknownParameter {
            path: path.to_path_buf(),
            name: name.clone(),
            declared: if names.is_empty() {
                "it has none".to_string()
            } else {
                format!("its parameters are: {}", names.join(", "))
            },
        });
    }
    crate::report::push_warnings(
        &mut lo.b,
        "Mitsuba scene",
        &lo.unsupported,
        &lo.approximations,
    );
    Ok(lo.b)
}

fn read_text(path: &Path, what: &str) -> Result<String, LoadError> {
    std::fs::read_to_string(path).map_err(|e| LoadError::File {
        path: path.to_path_buf(),
        message: format!("{what}: {e}"),
    })
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

/// One parsed XML file: positions in errors refer to it.
pub(crate) struct Doc<'a, 'i> {
    doc: &'a Document<'i>,
    path: &'a Path,
}

impl Doc<'_, '_> {
    fn err_at(&self, pos: usize, message: impl Into<String>) -> LoadError {
        let p = self.doc.text_pos_at(pos);
        LoadError::Parse {
            path: self.path.to_path_buf(),
            line: p.row as usize,
            column: p.col as usize,
            message: message.into(),
        }
    }
    fn pos(&self, n: Node) -> usize {
        n.range().start
    }
    fn line(&self, n: Node) -> u32 {
        self.doc.text_pos_at(n.range().start).row
    }
    /// `file:line` of `n`, for warnings.
    fn loc(&self, n: Node) -> String {
        let file = self
            .path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
        format!("{file}:{}", self.line(n))
    }
    fn resolve(&self, file: &str) -> PathBuf {
        let p = Path::new(file);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.path.parent().unwrap_or(Path::new("")).join(p)
        }
    }
    /// `file` resolved relative to this document; it must be an existing regular file, so a
    /// scene cannot make the loader read a device (`/dev/zero`), a FIFO or a directory.
    fn input_file(&self, file: &str, pos: usize) -> Result<PathBuf, LoadError> {
        let path = self.resolve(file);
        match std::fs::metadata(&path) {
            Ok(m) if !m.is_file() => {
                Err(self.err_at(pos, format!("'{}' is not a regular file", path.display())))
            }
            // Missing files are reported by the reader, with the OS error.
            _ => Ok(path),
        }
    }
    /// One finite number (must also be finite in single precision).
    fn number(&self, s: &str, pos: usize) -> Result<f32, LoadError> {
        let t = s.trim();
        let v: f64 = t
            .parse()
            .map_err(|_| self.err_at(pos, format!("bad number '{t}'")))?;
        if !v.is_finite() || !(v as f32).is_finite() {
            return Err(self.err_at(pos, format!("number must be finite, got '{t}'")));
        }
        Ok(v as f32)
    }
    /// Numbers separated by spaces and/or commas.
    fn numbers(&self, s: &str, pos: usize) -> Result<Vec<f32>, LoadError> {
        s.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| self.number(t, pos))
            .collect()
    }
    fn vec3(&self, s: &str, pos: usize) -> Result<Vec3, LoadError> {
        let n = self.numbers(s, pos)?;
        match n.len() {
            3 => Ok(Vec3::new(n[0], n[1], n[2])),
            1 => Ok(Vec3::splat(n[0])),
            k => Err(self.err_at(pos, format!("expected 3 numbers, got {k}"))),
        }
    }
}

/// A parameter value.
#[derive(Clone, Debug)]
pub(crate) enum Val {
    Float(f32),
    Int(i64),
    Bool(bool),
    Str(String),
    Rgb(Spectrum),
    /// A `<spectrum value="x">` constant (or a tabulated one's mean): grey in RGB mode, a flat
    /// spectrum in spectral mode (Mitsuba's `scalar_spectral` convention; an emitter's flat
    /// spectrum is illuminant E, not D65).
    Flat(f32),
    Vector(Vec3),
    Transform(Mat4),
}

#[derive(Clone, Debug)]
pub(crate) struct Prop {
    val: Val,
    /// Byte offset of the value (for errors).
    pos: usize,
}

/// The parameters and nested objects of one plugin element.
pub(crate) struct Props<'a, 'i> {
    map: HashMap<String, Prop>,
    /// Nested plugin elements and `<ref>`s, in order.
    children: Vec<Node<'a, 'i>>,
    node: Node<'a, 'i>,
    desc: String,
}

pub(crate) struct Loader {
    b: SceneBuilder,
    params: HashMap<String, String>,
    /// Parameters the scene declares (`<default>`) or uses (`$name`), so that a `-D` for any
    /// other name is an error rather than silently ignored.
    known: std::cell::RefCell<std::collections::BTreeSet<String>>,
    /// BSDFs declared with an `id`: (material, index in the builder).
    bsdfs: HashMap<String, (caustica_scene::material::Material, u32)>,
    /// Textures declared with an `id` at the top level.
    textures: HashMap<String, caustica_scene::texture::Texture>,
    /// Media declared with an `id`: their index in the builder.
    media: HashMap<String, u32>,
    /// Every `id` declared so far (all kinds).
    ids: HashSet<String>,
    unsupported: Vec<String>,
    approximations: Vec<String>,
    include_stack: Vec<PathBuf>,
    default_material: Option<u32>,
    /// Black diffuse material of area-emitter shapes without a BSDF (Mitsuba's default).
    default_emitter_material: Option<u32>,
    anonymous: usize,
}

impl Loader {
    /// Attribute `name` of `n` after `$param` substitution, with the offset of its value.
    fn attr(&self, d: &Doc, n: Node, name: &str) -> Result<Option<(String, usize)>, LoadError> {
        let Some(a) = n.attribute_node(name) else {
            return Ok(None);
        };
        let pos = a.range_value().start;
        Ok(Some((self.substitute(d, a.value(), pos)?, pos)))
    }

    fn req_attr(&self, d: &Doc, n: Node, name: &str) -> Result<(String, usize), LoadError> {
        self.attr(d, n, name)?.ok_or_else(|| {
            d.err_at(
                d.pos(n),
                format!(
                    "<{}> is missing the attribute '{name}'",
                    n.tag_name().name()
                ),
            )
        })
    }

    fn substitute(&self, d: &Doc, s: &str, pos: usize) -> Result<String, LoadError> {
        if !s.contains('$') {
            return Ok(s.to_string());
        }
        let mut out = String::with_capacity(s.len());
        let mut rest = s;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let key = &after[..len];
            if key.is_empty() {
                out.push('$');
            } else {
                self.known.borrow_mut().insert(key.to_string());
                match self.params.get(key) {
                    Some(v) if out.len() + v.len() > MAX_SUBSTITUTED_LEN => {
                        return Err(d.err_at(
                            pos,
                            format!("attribute value longer than {MAX_SUBSTITUTED_LEN} bytes after substituting '${key}'"),
                        ));
                    }
                    Some(v) => out.push_str(v),
                    None => {
                        return Err(d.err_at(
                            pos,
                            format!("undefined parameter '${key}' (declare it with <default> or pass -D {key}=…)"),
                        ));
                    }
                }
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    fn unsupported(&mut self, d: &Doc, n: Node, what: impl Into<String>) {
        self.unsupported
            .push(format!("{} ({})", what.into(), d.loc(n)));
    }

    fn approximated(&mut self, d: &Doc, n: Node, what: impl Into<String>) {
        self.approximations
            .push(format!("{} ({})", what.into(), d.loc(n)));
    }

    fn document(&mut self, text: &str, path: &Path) -> Result<(), LoadError> {
        let doc = Document::parse(text).map_err(|e| {
            let p = e.pos();
            LoadError::Parse {
                path: path.to_path_buf(),
                line: p.row as usize,
                column: p.col as usize,
                message: format!("malformed XML: {e}"),
            }
        })?;
        let d = Doc { doc: &doc, path };
        let root = doc.root_element();
        if root.tag_name().name() != "scene" {
            return Err(d.err_at(
                d.pos(root),
                format!(
                    "the root element must be <scene>, got <{}>",
                    root.tag_name().name()
                ),
            ));
        }
        if let Some((v, pos)) = self.attr(&d, root, "version")? {
            let major = v.split('.').next().unwrap_or("");
            if major != "2" && major != "3" {
                return Err(d.err_at(
                    pos,
                    format!("unsupported scene version '{v}' (expected 2.x or 3.x; upgrade older scenes with Mitsuba's converter)"),
                ));
            }
        }
        for c in root.children().filter(|c| c.is_element()) {
            self.scene_element(&d, c)?;
        }
        Ok(())
    }

    fn scene_element(&mut self, d: &Doc, c: Node) -> Result<(), LoadError> {
        match c.tag_name().name() {
            "default" => {
                let (name, _) = self.req_attr(d, c, "name")?;
                let (value, _) = self.req_attr(d, c, "value")?;
                self.known.borrow_mut().insert(name.clone());
                self.params.entry(name).or_insert(value);
            }
            "include" => self.include(d, c)?,
            "bsdf" => {
                let id = self.declare_id(d, c)?;
                let m = plugins::bsdf(self, d, c, 0)?;
                let name = id.clone().unwrap_or_else(|| self.anonymous_name("bsdf"));
                let idx = self.add_material(d, c, &name, m.clone())?;
                if let Some(id) = id {
                    self.bsdfs.insert(id, (m, idx));
                }
            }
            "shape" => {
                self.declare_id(d, c)?;
                plugins::shape(self, d, c)?;
            }
            "emitter" => {
                self.declare_id(d, c)?;
                plugins::emitter(self, d, c)?;
            }
            "texture" if c.attribute("type") == Some("bitmap") => {
                let id = self.declare_id(d, c)?;
                let t = plugins::bitmap(self, d, c)?;
                if let Some(id) = id {
                    self.textures.insert(id, t);
                }
            }
            "medium" if c.attribute_node("id").is_some() => {
                media::add_medium(self, d, c)?;
            }
            "medium" => {
                let ty = c.attribute("type").unwrap_or("");
                self.unsupported(
                    d,
                    c,
                    format!("<medium type=\"{ty}\"> without an id (nothing can refer to it)"),
                );
            }
            "sensor" => plugins::sensor(self, d, c)?,
            "integrator" => plugins::integrator(self, d, c)?,
            other => {
                let ty = c.attribute("type").unwrap_or("");
                self.declare_id(d, c)?;
                self.unsupported(d, c, format!("<{other} type=\"{ty}\">"));
            }
        }
        Ok(())
    }

    fn anonymous_name(&mut self, kind: &str) -> String {
        self.anonymous += 1;
        format!("{kind}#{}", self.anonymous)
    }

    fn add_material(
        &mut self,
        d: &Doc,
        n: Node,
        name: &str,
        m: caustica_scene::material::Material,
    ) -> Result<u32, LoadError> {
        m.validate().map_err(|e| d.err_at(d.pos(n), e))?;
        Ok(self.b.add_material(name, m)?)
    }

    /// Records the element's `id`; a duplicate id is an error.
    fn declare_id(&mut self, d: &Doc, n: Node) -> Result<Option<String>, LoadError> {
        let Some((id, pos)) = self.attr(d, n, "id")? else {
            return Ok(None);
        };
        if !self.ids.insert(id.clone()) {
            return Err(d.err_at(pos, format!("duplicate id '{id}'")));
        }
        Ok(Some(id))
    }

    fn include(&mut self, d: &Doc, c: Node) -> Result<(), LoadError> {
        let (file, pos) = self.req_attr(d, c, "filename")?;
        let path = d.input_file(&file, pos)?;
        if self.include_stack.len() > MAX_INCLUDE_DEPTH {
            return Err(d.err_at(
                pos,
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        let key = canonical(&path);
        if self.include_stack.contains(&key) {
            return Err(d.err_at(pos, format!("cyclic include of '{}'", path.display())));
        }
        let text = read_text(&path, "cannot read included file")?;
        self.include_stack.push(key);
        let r = self.document(&text, &path);
        self.include_stack.pop();
        r
    }

    /// Collects the parameters of plugin element `n` (`<float name=… value=…/>`, …), its nested
    /// plugins and `<ref>`s.
    fn props<'a, 'i>(&mut self, d: &Doc, n: Node<'a, 'i>) -> Result<Props<'a, 'i>, LoadError> {
        let ty = n.attribute("type").unwrap_or("");
        let mut p = Props {
            map: HashMap::new(),
            children: Vec::new(),
            node: n,
            desc: format!("<{} type=\"{ty}\">", n.tag_name().name()),
        };
        for c in n.children().filter(|c| c.is_element()) {
            let tag = c.tag_name().name();
            let val = match tag {
                "float" => {
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    Some((Val::Float(d.number(&v, pos)?), pos))
                }
                "integer" => {
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    let i = v
                        .trim()
                        .parse::<i64>()
                        .map_err(|_| d.err_at(pos, format!("bad integer '{}'", v.trim())))?;
                    Some((Val::Int(i), pos))
                }
                "boolean" => {
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    let b = match v.trim().to_ascii_lowercase().as_str() {
                        "true" | "1" => true,
                        "false" | "0" => false,
                        _ => {
                            return Err(d.err_at(
                                pos,
                                format!("unknown boolean value '{v}' (expected true or false)"),
                            ));
                        }
                    };
                    Some((Val::Bool(b), pos))
                }
                "string" => {
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    Some((Val::Str(v), pos))
                }
                "rgb" | "color" => {
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    let rgb = d.vec3(&v, pos)?;
                    Some((Val::Rgb(Spectrum::from_rgb(rgb.to_array())), pos))
                }
                "spectrum" => {
                    if c.attribute_node("filename").is_some() {
                        return Err(d.err_at(
                            d.pos(c),
                            "<spectrum filename=…> is not supported (give a constant value or <rgb>)",
                        ));
                    }
                    let (v, pos) = self.req_attr(d, c, "value")?;
                    if v.contains(':') {
                        // wavelength:value pairs: use the mean value.
                        let mut vals = Vec::new();
                        for pair in v.split(',').filter(|s| !s.trim().is_empty()) {
                            let Some((_, val)) = pair.split_once(':') else {
                                return Err(
                                    d.err_at(pos, format!("bad spectrum entry '{}'", pair.trim()))
                                );
                            };
                            vals.push(d.number(val, pos)?);
                        }
                        let mean = vals.iter().sum::<f32>() / vals.len().max(1) as f32;
                        self.approximated(
                            d,
                            c,
                            format!("tabulated spectrum replaced by its mean {mean}"),
                        );
                        Some((Val::Flat(mean), pos))
                    } else {
                        let x = d.number(&v, pos)?;
                        Some((Val::Flat(x), pos))
                    }
                }
                "point" | "vector" => {
                    let pos = d.pos(c);
                    let v = if let Some((v, vpos)) = self.attr(d, c, "value")? {
                        d.vec3(&v, vpos)?
                    } else {
                        let mut out = [0.0f32; 3];
                        for (i, k) in ["x", "y", "z"].iter().enumerate() {
                            if let Some((v, vpos)) = self.attr(d, c, k)? {
                                out[i] = d.number(&v, vpos)?;
                            }
                        }
                        Vec3::from(out)
                    };
                    Some((Val::Vector(v), pos))
                }
                "transform" => {
                    let m = transform::parse_transform(self, d, c)?;
                    Some((Val::Transform(m), d.pos(c)))
                }
                "bsdf" | "emitter" | "shape" | "texture" | "film" | "rfilter" | "sampler"
                | "medium" | "phase" | "ref" | "volume" => {
                    p.children.push(c);
                    None
                }
                other => {
                    self.unsupported(d, c, format!("<{other}> inside {}", p.desc));
                    None
                }
            };
            if let Some((val, pos)) = val {
                let (name, npos) = self.req_attr(d, c, "name")?;
                if p.map.insert(name.clone(), Prop { val, pos }).is_some() {
                    return Err(d.err_at(npos, format!("parameter '{name}' given twice")));
                }
            }
        }
        Ok(p)
    }

    /// Reports every parameter left in `p` as unsupported.
    fn leftovers(&mut self, d: &Doc, p: Props) {
        let mut names: Vec<_> = p.map.keys().cloned().collect();
        names.sort();
        for name in names {
            self.unsupported(d, p.node, format!("parameter '{name}' of {}", p.desc));
        }
    }
}

impl Props<'_, '_> {
    fn take(&mut self, name: &str) -> Option<Prop> {
        self.map.remove(name)
    }
    fn float(&mut self, d: &Doc, name: &str) -> Result<Option<f32>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Float(x), ..
            }) => Ok(Some(x)),
            Some(Prop {
                val: Val::Int(i), ..
            }) => Ok(Some(i as f32)),
            Some(p) => Err(d.err_at(p.pos, format!("parameter '{name}' must be a float"))),
        }
    }
    fn int(&mut self, d: &Doc, name: &str) -> Result<Option<i64>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Int(i), ..
            }) => Ok(Some(i)),
            Some(p) => Err(d.err_at(p.pos, format!("parameter '{name}' must be an integer"))),
        }
    }
    fn bool(&mut self, d: &Doc, name: &str) -> Result<Option<bool>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Bool(b), ..
            }) => Ok(Some(b)),
            Some(p) => Err(d.err_at(p.pos, format!("parameter '{name}' must be a boolean"))),
        }
    }
    fn string(&mut self, d: &Doc, name: &str) -> Result<Option<(String, usize)>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Str(s),
                pos,
            }) => Ok(Some((s, pos))),
            Some(p) => Err(d.err_at(p.pos, format!("parameter '{name}' must be a string"))),
        }
    }
    /// True if parameter `name` is a `<spectrum value="x">` constant (before it is taken).
    fn is_flat_spectrum(&self, name: &str) -> bool {
        matches!(
            self.map.get(name),
            Some(Prop {
                val: Val::Flat(_),
                ..
            })
        )
    }
    /// An `rgb`, `spectrum` or `float` (grey) value.
    fn spectrum(&mut self, d: &Doc, name: &str) -> Result<Option<Spectrum>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Rgb(s), ..
            }) => Ok(Some(s)),
            Some(Prop {
                val: Val::Float(x) | Val::Flat(x),
                ..
            }) => Ok(Some(Spectrum::splat(x))),
            Some(Prop {
                val: Val::Int(i), ..
            }) => Ok(Some(Spectrum::splat(i as f32))),
            Some(p) => Err(d.err_at(
                p.pos,
                format!("parameter '{name}' must be an rgb, spectrum or float value"),
            )),
        }
    }
    fn vector(&mut self, d: &Doc, name: &str) -> Result<Option<Vec3>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Vector(v),
                ..
            }) => Ok(Some(v)),
            Some(p) => Err(d.err_at(
                p.pos,
                format!("parameter '{name}' must be a point or vector"),
            )),
        }
    }
    fn transform(&mut self, d: &Doc, name: &str) -> Result<Option<(Mat4, usize)>, LoadError> {
        match self.take(name) {
            None => Ok(None),
            Some(Prop {
                val: Val::Transform(m),
                pos,
            }) => Ok(Some((m, pos))),
            Some(p) => Err(d.err_at(p.pos, format!("parameter '{name}' must be a <transform>"))),
        }
    }
}

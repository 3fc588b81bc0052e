//! Loader for pbrt-v4 scene files (`.pbrt`), the subset documented in `docs/pbrt.md`.
//!
//! The file is tokenized (`tokenizer.rs`), then its directives run in order against pbrt's
//! graphics state (`graphics_state.rs`): transforms compose into the CTM, `AttributeBegin`/`End`
//! save and restore it with the material and area light, and shapes, lights and the camera
//! take the CTM in effect. Every directive's parameter list (`params.rs`) is checked against its
//! declared types; parameters a converter does not take, and directives caustica ignores, are
//! reported in ONE warning naming each with its line. Directives whose absence would change
//! what the image means (unknown shape, material or light types, media, missing files) are
//! errors naming the file, line and column and what was expected.

mod camera;
mod graphics_state;
mod lights;
mod materials;
mod params;
mod shapes;
#[cfg(test)]
mod tests;
mod tokenizer;

use crate::error::LoadError;
use caustica_core::{Mat4, Spectrum, Vec3};
use caustica_scene::light::EmissionSpectrum;
use caustica_scene::material::Material;
use caustica_scene::scene::SceneBuilder;
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::texture::Texture;
use graphics_state::{GraphicsState, MatRef, Push, Saved, Xf};
use params::{PErr, Params, parse_params};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tokenizer::{Tok, Token, clip, tokenize};

/// Maximum `Include`/`Import` depth.
const MAX_INCLUDE_DEPTH: usize = 32;
/// Most `Include`/`Import` directives a scene may run in all (a file including the next one
/// twice, 32 deep, would otherwise mean 2³² parses).
const MAX_INCLUDES: usize = 1 << 12;
/// Maximum depth of the attribute stack (`AttributeBegin` without `End` in a loop of
/// includes would otherwise grow without bound).
const MAX_ATTRIBUTE_DEPTH: usize = 1 << 12;
/// Most triangles object instances may add in total (each instance is a copy in caustica).
pub const MAX_INSTANCED_TRIANGLES: usize = 1 << 25;

/// Reads the pbrt-v4 scene at `path`.
pub fn load_pbrt(path: &Path) -> Result<SceneBuilder, LoadError> {
    let text = read_text(path, "cannot read scene file")?;
    parse_pbrt(&text, path)
}

/// Parses pbrt-v4 `text`; `path` names the file in errors and anchors relative file names
/// (`Include`, `plymesh`, `imagemap`).
pub fn parse_pbrt(text: &str, path: &Path) -> Result<SceneBuilder, LoadError> {
    let name = path
        .file_stem()
        .map_or_else(|| "pbrt".to_string(), |s| s.to_string_lossy().into_owned());
    let mut lo = Loader::new(SceneBuilder::new(name), path);
    camera::defaults(&mut lo);
    lo.file(text, path, 0)?;
    if let Some(s) = lo.stack.last() {
        return Err(LoadError::Parse {
            path: s.file.clone(),
            line: s.line,
            column: s.col,
            message: format!(
                "{} without a matching {} at the end of the scene",
                if s.kind == Push::Attribute {
                    "AttributeBegin"
                } else {
                    "TransformBegin"
                },
                if s.kind == Push::Attribute {
                    "AttributeEnd"
                } else {
                    "TransformEnd"
                },
            ),
        });
    }
    if let Some(o) = &lo.current_object {
        return Err(LoadError::Parse {
            path: o.file.clone(),
            line: o.line,
            column: o.col,
            message: format!(
                "ObjectBegin \"{}\" without a matching ObjectEnd",
                clip(&o.name)
            ),
        });
    }
    lo.finish()
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

/// A material made by `Material` or `MakeNamedMaterial`, added to the builder when a shape
/// first uses it.
struct MatDef {
    name: String,
    mat: Material,
    index: Option<u32>,
}

/// A shape of an object definition, in the object's world space, waiting for instances.
#[derive(Clone)]
pub(crate) struct ShapeRec {
    geometry: ShapeGeometry,
    material: u32,
    flip: bool,
    line: usize,
}

/// The object being defined by `ObjectBegin`.
struct ObjectDef {
    name: String,
    shapes: Vec<ShapeRec>,
    file: PathBuf,
    line: usize,
    col: usize,
}

/// A float texture: only constants can be used (caustica has no textured roughness or IOR).
#[derive(Clone, Debug)]
pub(crate) enum FloatTex {
    Constant(f32),
    Other(String),
}

pub(crate) struct Loader {
    pub b: SceneBuilder,
    gs: GraphicsState,
    stack: Vec<Saved>,
    in_world: bool,
    named_coords: HashMap<String, Xf>,
    materials: Vec<MatDef>,
    named_materials: HashMap<String, usize>,
    pub spectrum_textures: HashMap<String, Texture>,
    pub float_textures: HashMap<String, FloatTex>,
    objects: HashMap<String, Vec<ShapeRec>>,
    current_object: Option<ObjectDef>,
    instanced_triangles: usize,
    includes: usize,
    unsupported: Vec<String>,
    approximations: Vec<String>,
    include_stack: Vec<PathBuf>,
    /// The file whose directives run now (errors and relative names refer to it).
    path: PathBuf,
    default_material: Option<u32>,
    pub camera: Option<camera::CameraDesc>,
    pub film: camera::FilmDesc,
}

/// Reads the tokens of one directive.
pub(crate) struct Cur<'a> {
    toks: &'a [Token],
    i: usize,
    /// Position of the directive's name (errors at the end of the file point here).
    line: usize,
    col: usize,
}

impl Cur<'_> {
    /// One number.
    fn num(&mut self, what: &str) -> Result<f32, PErr> {
        match self.toks.get(self.i) {
            Some(Token {
                tok: Tok::Num(x),
                line,
                col,
            }) => {
                let y = *x as f32;
                if !y.is_finite() {
                    return Err(PErr::at(
                        *line,
                        *col,
                        format!("{what}: {x} is out of single-precision range"),
                    ));
                }
                self.i += 1;
                Ok(y)
            }
            Some(t) => Err(PErr::at(
                t.line,
                t.col,
                format!("{what}: expected a number, got {}", t.describe()),
            )),
            None => Err(PErr::at(
                self.line,
                self.col,
                format!("{what}: expected a number, got the end of the file"),
            )),
        }
    }
    fn nums<const N: usize>(&mut self, what: &str) -> Result<[f32; N], PErr> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.num(what)?;
        }
        Ok(out)
    }
    /// `N` numbers, optionally in brackets (`Transform [ … ]`).
    fn bracketed<const N: usize>(&mut self, what: &str) -> Result<[f32; N], PErr> {
        let open = matches!(self.toks.get(self.i), Some(Token { tok: Tok::Open, .. }));
        if open {
            self.i += 1;
        }
        let v = self.nums::<N>(what)?;
        if open {
            match self.toks.get(self.i) {
                Some(Token {
                    tok: Tok::Close, ..
                }) => self.i += 1,
                Some(t) => {
                    return Err(PErr::at(
                        t.line,
                        t.col,
                        format!(
                            "{what}: expected ']' after {N} numbers, got {}",
                            t.describe()
                        ),
                    ));
                }
                None => {
                    return Err(PErr::at(
                        self.line,
                        self.col,
                        format!("{what}: expected ']' after {N} numbers, got the end of the file"),
                    ));
                }
            }
        }
        Ok(v)
    }
    /// One quoted string with its position.
    fn string(&mut self, what: &str) -> Result<(String, usize, usize), PErr> {
        match self.toks.get(self.i) {
            Some(Token {
                tok: Tok::Str(s),
                line,
                col,
            }) => {
                self.i += 1;
                Ok((s.clone(), *line, *col))
            }
            Some(t) => Err(PErr::at(
                t.line,
                t.col,
                format!("{what}: expected a quoted string, got {}", t.describe()),
            )),
            None => Err(PErr::at(
                self.line,
                self.col,
                format!("{what}: expected a quoted string, got the end of the file"),
            )),
        }
    }
    fn params(&mut self) -> Result<Params, PErr> {
        parse_params(self.toks, &mut self.i)
    }
}

impl Loader {
    fn new(b: SceneBuilder, path: &Path) -> Self {
        Self {
            b,
            gs: GraphicsState::default(),
            stack: Vec::new(),
            in_world: false,
            named_coords: HashMap::new(),
            materials: Vec::new(),
            named_materials: HashMap::new(),
            spectrum_textures: HashMap::new(),
            float_textures: HashMap::new(),
            objects: HashMap::new(),
            current_object: None,
            instanced_triangles: 0,
            includes: 0,
            unsupported: Vec::new(),
            approximations: Vec::new(),
            include_stack: vec![canonical(path)],
            path: path.to_path_buf(),
            default_material: None,
            camera: None,
            film: camera::FilmDesc::default(),
        }
    }

    /// An error at `line:col` of the current file.
    pub fn err(&self, line: usize, col: usize, message: impl Into<String>) -> LoadError {
        LoadError::Parse {
            path: self.path.clone(),
            line,
            column: col,
            message: message.into(),
        }
    }

    pub fn perr(&self, e: PErr) -> LoadError {
        self.err(e.line, e.col, e.message)
    }

    fn loc(&self, line: usize) -> String {
        let file = self
            .path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
        format!("{file}:{line}")
    }

    /// Records something ignored, for the one warning.
    pub fn unsupported(&mut self, line: usize, what: impl Into<String>) {
        let s = format!("{} ({})", what.into(), self.loc(line));
        self.unsupported.push(s);
    }

    /// Records an approximation, for the one warning.
    pub fn approximated(&mut self, line: usize, what: impl Into<String>) {
        let s = format!("{} ({})", what.into(), self.loc(line));
        self.approximations.push(s);
    }

    /// Reports the parameters of `p` nothing took, as parameters of `desc`.
    pub fn leftovers(&mut self, p: &Params, desc: &str) {
        for (name, line) in p.leftovers() {
            self.unsupported(line, format!("parameter {name} of {desc}"));
        }
    }

    /// `file` relative to the current file's folder; it must be a regular file (a scene may
    /// not make the loader read a device, a FIFO or a directory).
    pub fn input_file(&self, file: &str, line: usize, col: usize) -> Result<PathBuf, LoadError> {
        let p = Path::new(file);
        let path = if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.path.parent().unwrap_or(Path::new("")).join(p)
        };
        match std::fs::metadata(&path) {
            Ok(m) if !m.is_file() => Err(self.err(
                line,
                col,
                format!("'{}' is not a regular file", path.display()),
            )),
            Err(e) => Err(self.err(line, col, format!("cannot read '{}': {e}", path.display()))),
            Ok(_) => Ok(path),
        }
    }

    /// Runs the directives of one file (`depth` includes deep).
    fn file(&mut self, text: &str, path: &Path, depth: usize) -> Result<(), LoadError> {
        let toks = tokenize(text).map_err(|e| LoadError::Parse {
            path: path.to_path_buf(),
            line: e.line,
            column: e.col,
            message: e.message,
        })?;
        let saved = std::mem::replace(&mut self.path, path.to_path_buf());
        let mut i = 0;
        let r = (|| {
            while i < toks.len() {
                self.directive(&toks, &mut i, depth)?;
            }
            Ok(())
        })();
        self.path = saved;
        r
    }

    fn directive(&mut self, toks: &[Token], i: &mut usize, depth: usize) -> Result<(), LoadError> {
        let t = &toks[*i];
        let Tok::Word(name) = &t.tok else {
            return Err(self.err(
                t.line,
                t.col,
                format!(
                    "expected a directive (e.g. Shape, LookAt, AttributeBegin), got {}",
                    t.describe()
                ),
            ));
        };
        let (line, col) = (t.line, t.col);
        let mut c = Cur {
            toks,
            i: *i + 1,
            line,
            col,
        };
        let r = self.run(name, &mut c, line, col, depth);
        *i = c.i;
        r
    }

    fn world_only(&self, name: &str, line: usize, col: usize) -> Result<(), LoadError> {
        if self.in_world {
            Ok(())
        } else {
            Err(self.err(
                line,
                col,
                format!("{name} is only allowed after WorldBegin"),
            ))
        }
    }

    fn options_only(&self, name: &str, line: usize, col: usize) -> Result<(), LoadError> {
        if self.in_world {
            Err(self.err(
                line,
                col,
                format!("{name} is only allowed before WorldBegin"),
            ))
        } else {
            Ok(())
        }
    }

    /// Applies `t` to the CTM (`ctm = ctm · t`) if the start transform is active.
    fn transform(&mut self, t: Xf, line: usize) {
        if self.gs.active_start {
            self.gs.ctm = self.gs.ctm.then(t);
        } else {
            self.unsupported(
                line,
                "a transform of the end time only (ActiveTransform EndTime: no motion blur)",
            );
        }
    }

    fn set_transform(&mut self, t: Xf, line: usize) {
        if self.gs.active_start {
            self.gs.ctm = t;
        } else {
            self.unsupported(
                line,
                "a transform of the end time only (ActiveTransform EndTime: no motion blur)",
            );
        }
    }

    fn run(
        &mut self,
        name: &str,
        c: &mut Cur,
        line: usize,
        col: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        macro_rules! p {
            ($e:expr) => {
                $e.map_err(|e| self.perr(e))?
            };
        }
        match name {
            "Identity" => self.set_transform(Xf::IDENTITY, line),
            "Translate" => {
                let v = p!(c.nums::<3>("Translate x y z"));
                self.transform(Xf::translate(Vec3::from(v)), line);
            }
            "Scale" => {
                let v = p!(c.nums::<3>("Scale x y z"));
                self.transform(Xf::scale(Vec3::from(v)), line);
            }
            "Rotate" => {
                let [a, x, y, z] = p!(c.nums::<4>("Rotate angle x y z"));
                let r = Xf::rotate(a, Vec3::new(x, y, z)).ok_or_else(|| {
                    self.err(line, col, "Rotate: the axis must be a non-zero vector")
                })?;
                self.transform(r, line);
            }
            "LookAt" => {
                let v =
                    p!(c.nums::<9>("LookAt eye_x eye_y eye_z look_x look_y look_z up_x up_y up_z"));
                let t = Xf::look_at(
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                    Vec3::new(v[6], v[7], v[8]),
                )
                .ok_or_else(|| {
                    self.err(line, col, "LookAt: the eye and the look-at point must differ and the up vector must not be parallel to the view direction")
                })?;
                self.transform(t, line);
            }
            "Transform" | "ConcatTransform" => {
                let v = p!(c.bracketed::<16>(&format!("{name} [ 16 numbers ]")));
                let m = Mat4::from_cols_slice(&v);
                let t = Xf::matrix(m);
                if name == "Transform" {
                    self.set_transform(t, line);
                } else {
                    self.transform(t, line);
                }
            }
            "CoordinateSystem" => {
                let (n, ..) = p!(c.string("CoordinateSystem \"name\""));
                self.named_coords.insert(n, self.gs.ctm);
            }
            "CoordSysTransform" => {
                let (n, l, cc) = p!(c.string("CoordSysTransform \"name\""));
                let t = *self.named_coords.get(&n).ok_or_else(|| {
                    self.err(l, cc, format!("unknown coordinate system \"{}\" (declare it with CoordinateSystem; \"camera\" and \"world\" exist after Camera and WorldBegin)", clip(&n)))
                })?;
                self.set_transform(t, line);
            }
            "ReverseOrientation" => self.gs.reverse_orientation = !self.gs.reverse_orientation,
            "AttributeBegin" | "TransformBegin" => {
                if self.stack.len() >= MAX_ATTRIBUTE_DEPTH {
                    return Err(self.err(
                        line,
                        col,
                        format!("attribute blocks nested deeper than {MAX_ATTRIBUTE_DEPTH}"),
                    ));
                }
                if name == "TransformBegin" {
                    self.unsupported(
                        line,
                        "TransformBegin (deprecated in pbrt-v4; read as saving the CTM)",
                    );
                }
                self.stack.push(Saved {
                    state: self.gs.clone(),
                    kind: if name == "AttributeBegin" {
                        Push::Attribute
                    } else {
                        Push::Transform
                    },
                    file: self.path.clone(),
                    line,
                    col,
                });
            }
            "AttributeEnd" | "TransformEnd" => {
                let want = if name == "AttributeEnd" {
                    Push::Attribute
                } else {
                    Push::Transform
                };
                match self.stack.pop() {
                    None => {
                        return Err(self.err(
                            line,
                            col,
                            format!(
                                "unbalanced {name}: no {} is open",
                                if want == Push::Attribute {
                                    "AttributeBegin"
                                } else {
                                    "TransformBegin"
                                }
                            ),
                        ));
                    }
                    Some(s) if s.kind != want => {
                        return Err(self.err(
                            line,
                            col,
                            format!(
                                "{name} closes the {} of line {}",
                                if s.kind == Push::Attribute {
                                    "AttributeBegin"
                                } else {
                                    "TransformBegin"
                                },
                                s.line
                            ),
                        ));
                    }
                    Some(s) => {
                        if want == Push::Attribute {
                            self.gs = s.state;
                        } else {
                            self.gs.ctm = s.state.ctm;
                        }
                    }
                }
            }
            "WorldBegin" => {
                if self.in_world {
                    return Err(self.err(line, col, "WorldBegin given twice"));
                }
                self.in_world = true;
                self.gs.ctm = Xf::IDENTITY;
                self.named_coords.insert("world".to_string(), Xf::IDENTITY);
            }
            "WorldEnd" => {
                self.unsupported(line, "WorldEnd (pbrt-v3; the scene ends with the file)")
            }
            "Camera" => {
                self.options_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string("Camera \"type\""));
                let mut ps = p!(c.params());
                camera::camera(self, &ty, tl, tc, &mut ps, line)?;
                self.leftovers(&ps, &format!("Camera \"{}\"", clip(&ty)));
            }
            "Film" | "Sampler" | "PixelFilter" | "Integrator" => {
                self.options_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string(&format!("{name} \"type\"")));
                let mut ps = p!(c.params());
                match name {
                    "Film" => camera::film(self, &ty, tl, tc, &mut ps, line)?,
                    "Sampler" => camera::sampler(self, &ty, &mut ps, line)?,
                    "PixelFilter" => camera::pixel_filter(self, &ty, &mut ps, line)?,
                    _ => camera::integrator(self, &ty, &mut ps, line)?,
                }
                self.leftovers(&ps, &format!("{name} \"{}\"", clip(&ty)));
            }
            "Accelerator" => {
                self.options_only(name, line, col)?;
                let _ = p!(c.string("Accelerator \"type\""));
                let _ = p!(c.params());
                self.unsupported(line, "Accelerator (caustica builds its own BVH)");
            }
            "ColorSpace" => {
                let (cs, ..) = p!(c.string("ColorSpace \"name\""));
                if cs != "srgb" {
                    return Err(self.err(line, col, format!("ColorSpace \"{}\" is not supported (caustica's RGB is linear sRGB: expected \"srgb\")", clip(&cs))));
                }
            }
            "Option" => {
                let ps = p!(c.params());
                for (n, l) in ps.leftovers() {
                    self.unsupported(l, format!("Option {n}"));
                }
            }
            "Attribute" => {
                let (target, ..) =
                    p!(c.string("Attribute \"shape|light|material|medium|texture\""));
                let ps = p!(c.params());
                if !ps.list.is_empty() {
                    self.unsupported(
                        line,
                        format!(
                            "Attribute \"{}\" defaults (give the parameters to each directive)",
                            clip(&target)
                        ),
                    );
                }
            }
            "TransformTimes" => {
                let _ = p!(c.nums::<2>("TransformTimes start end"));
                self.unsupported(line, "TransformTimes (no transform motion blur)");
            }
            "ActiveTransform" => {
                let which = match c.toks.get(c.i) {
                    Some(Token { tok: Tok::Word(w), .. }) => w.clone(),
                    Some(t) => return Err(self.err(t.line, t.col, format!("ActiveTransform: expected StartTime, EndTime or All, got {}", t.describe()))),
                    None => return Err(self.err(line, col, "ActiveTransform: expected StartTime, EndTime or All, got the end of the file")),
                };
                let (start, end) = match which.as_str() {
                    "StartTime" => (true, false),
                    "EndTime" => (false, true),
                    "All" => (true, true),
                    other => {
                        let t = &c.toks[c.i];
                        return Err(self.err(
                            t.line,
                            t.col,
                            format!(
                                "ActiveTransform: expected StartTime, EndTime or All, got '{}'",
                                clip(other)
                            ),
                        ));
                    }
                };
                c.i += 1;
                self.gs.active_start = start;
                self.gs.active_end = end;
            }
            "MakeNamedMedium" => {
                let _ = p!(c.string("MakeNamedMedium \"name\""));
                let _ = p!(c.params());
                return Err(self.err(line, col, "MakeNamedMedium: participating media in pbrt files are not supported (write the scene in caustica's TOML or Mitsuba XML, which support media)"));
            }
            "MediumInterface" => {
                let (inside, il, ic) = p!(c.string("MediumInterface \"inside\" [\"outside\"]"));
                let outside = if matches!(
                    c.toks.get(c.i),
                    Some(Token {
                        tok: Tok::Str(_),
                        ..
                    })
                ) {
                    p!(c.string("MediumInterface")).0
                } else {
                    inside.clone()
                };
                if !inside.is_empty() || !outside.is_empty() {
                    return Err(self.err(il, ic, "MediumInterface: participating media in pbrt files are not supported (expected \"\" \"\")"));
                }
            }
            "Include" | "Import" => {
                let (file, fl, fc) = p!(c.string(&format!("{name} \"file\"")));
                self.include(&file, fl, fc, depth)?;
            }
            "Material" => {
                self.world_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string("Material \"type\""));
                let mut ps = p!(c.params());
                let m = materials::material(self, &ty, tl, tc, &mut ps, line)?;
                self.leftovers(&ps, &format!("Material \"{}\"", clip(&ty)));
                self.materials.push(MatDef {
                    name: format!("{}#{}", clip(&ty), self.materials.len() + 1),
                    mat: m,
                    index: None,
                });
                self.gs.material = MatRef::Anonymous(self.materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                self.world_only(name, line, col)?;
                let (n, nl, nc) = p!(c.string("MakeNamedMaterial \"name\""));
                let mut ps = p!(c.params());
                if self.named_materials.contains_key(&n) {
                    return Err(self.err(
                        nl,
                        nc,
                        format!("named material \"{}\" defined twice", clip(&n)),
                    ));
                }
                let (ty, tl, tc) = p!(ps.string("type")).ok_or_else(|| {
                    self.err(
                        nl,
                        nc,
                        format!(
                            "MakeNamedMaterial \"{}\" needs a \"string type\" parameter",
                            clip(&n)
                        ),
                    )
                })?;
                let m = materials::material(self, &ty, tl, tc, &mut ps, line)?;
                self.leftovers(&ps, &format!("MakeNamedMaterial \"{}\"", clip(&n)));
                self.materials.push(MatDef {
                    name: n.clone(),
                    mat: m,
                    index: None,
                });
                self.named_materials.insert(n, self.materials.len() - 1);
            }
            "NamedMaterial" => {
                self.world_only(name, line, col)?;
                let (n, nl, nc) = p!(c.string("NamedMaterial \"name\""));
                self.gs.material = MatRef::Named(n, nl, nc);
            }
            "Texture" => {
                self.world_only(name, line, col)?;
                let (n, ..) = p!(c.string("Texture \"name\" \"spectrum|float\" \"type\""));
                let (class, cl, cc) = p!(c.string("Texture \"name\" \"spectrum|float\" \"type\""));
                let (ty, tl, tc) = p!(c.string("Texture \"name\" \"spectrum|float\" \"type\""));
                let mut ps = p!(c.params());
                materials::texture(self, &n, (&class, cl, cc), (&ty, tl, tc), &mut ps, line)?;
                self.leftovers(&ps, &format!("Texture \"{}\"", clip(&n)));
            }
            "LightSource" => {
                self.world_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string("LightSource \"type\""));
                let mut ps = p!(c.params());
                if self.current_object.is_some() {
                    return Err(self.err(
                        line,
                        col,
                        "LightSource inside ObjectBegin/ObjectEnd (pbrt does not instance lights)",
                    ));
                }
                lights::light_source(self, &ty, tl, tc, &mut ps, line)?;
                self.leftovers(&ps, &format!("LightSource \"{}\"", clip(&ty)));
            }
            "AreaLightSource" => {
                self.world_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string("AreaLightSource \"type\""));
                let mut ps = p!(c.params());
                if ty != "diffuse" {
                    return Err(self.err(
                        tl,
                        tc,
                        format!(
                            "unknown area light type \"{}\" (expected \"diffuse\")",
                            clip(&ty)
                        ),
                    ));
                }
                let al = lights::area_light(self, &mut ps, line, col)?;
                self.leftovers(&ps, "AreaLightSource \"diffuse\"");
                self.gs.area_light = Some(al);
            }
            "Shape" => {
                self.world_only(name, line, col)?;
                let (ty, tl, tc) = p!(c.string("Shape \"type\""));
                let mut ps = p!(c.params());
                shapes::shape(self, &ty, tl, tc, &mut ps, line, col)?;
                self.leftovers(&ps, &format!("Shape \"{}\"", clip(&ty)));
            }
            "ObjectBegin" => {
                self.world_only(name, line, col)?;
                let (n, nl, nc) = p!(c.string("ObjectBegin \"name\""));
                if let Some(o) = &self.current_object {
                    return Err(self.err(line, col, format!("ObjectBegin inside the definition of \"{}\" (line {}): objects cannot nest", clip(&o.name), o.line)));
                }
                if self.objects.contains_key(&n) {
                    return Err(self.err(nl, nc, format!("object \"{}\" defined twice", clip(&n))));
                }
                // pbrt-v4's ObjectBegin also begins an attribute block.
                self.stack.push(Saved {
                    state: self.gs.clone(),
                    kind: Push::Attribute,
                    file: self.path.clone(),
                    line,
                    col,
                });
                self.current_object = Some(ObjectDef {
                    name: n,
                    shapes: Vec::new(),
                    file: self.path.clone(),
                    line,
                    col,
                });
            }
            "ObjectEnd" => {
                let Some(o) = self.current_object.take() else {
                    return Err(self.err(
                        line,
                        col,
                        "unbalanced ObjectEnd: no ObjectBegin is open",
                    ));
                };
                match self.stack.pop() {
                    Some(s) if s.kind == Push::Attribute => self.gs = s.state,
                    _ => {
                        return Err(self.err(
                            line,
                            col,
                            "ObjectEnd does not match the attribute block its ObjectBegin opened",
                        ));
                    }
                }
                self.objects.insert(o.name, o.shapes);
            }
            "ObjectInstance" => {
                self.world_only(name, line, col)?;
                let (n, nl, nc) = p!(c.string("ObjectInstance \"name\""));
                if self.current_object.is_some() {
                    return Err(self.err(line, col, "ObjectInstance inside an object definition"));
                }
                self.instance(&n, nl, nc)?;
            }
            other => {
                return Err(self.err(line, col, format!(
                    "unknown directive '{}' (expected a pbrt-v4 directive such as LookAt, Camera, Film, WorldBegin, AttributeBegin, Shape, Material, LightSource)",
                    clip(other)
                )));
            }
        }
        Ok(())
    }

    fn include(
        &mut self,
        file: &str,
        line: usize,
        col: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        if depth + 1 > MAX_INCLUDE_DEPTH {
            return Err(self.err(
                line,
                col,
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        self.includes += 1;
        if self.includes > MAX_INCLUDES {
            return Err(self.err(
                line,
                col,
                format!("more than {MAX_INCLUDES} includes in all"),
            ));
        }
        let path = self.input_file(file, line, col)?;
        let key = canonical(&path);
        if self.include_stack.contains(&key) {
            return Err(self.err(line, col, format!("cyclic include of '{}'", path.display())));
        }
        let text = std::fs::read_to_string(&path).map_err(|e| {
            self.err(
                line,
                col,
                format!("cannot read included file '{}': {e}", path.display()),
            )
        })?;
        self.include_stack.push(key);
        let r = self.file(&text, &path, depth + 1);
        self.include_stack.pop();
        r
    }

    /// The builder index of the material in the graphics state (added on first use).
    pub fn current_material(&mut self) -> Result<u32, LoadError> {
        let def = match self.gs.material.clone() {
            MatRef::Default => {
                if let Some(i) = self.default_material {
                    return Ok(i);
                }
                let i = self.b.add_material(
                    "pbrt-default-diffuse",
                    Material::Diffuse {
                        reflectance: Texture::Constant(Spectrum::splat(0.5)),
                    },
                )?;
                self.default_material = Some(i);
                return Ok(i);
            }
            MatRef::Anonymous(k) => k,
            MatRef::Named(n, l, c) => *self.named_materials.get(&n).ok_or_else(|| {
                self.err(
                    l,
                    c,
                    format!(
                        "NamedMaterial \"{}\" was not defined by MakeNamedMaterial before its use",
                        clip(&n)
                    ),
                )
            })?,
        };
        let Some(d) = self.materials.get_mut(def) else {
            return Err(LoadError::File {
                path: self.path.clone(),
                message: "internal: material index out of range".into(),
            });
        };
        if let Some(i) = d.index {
            return Ok(i);
        }
        let i = self.b.add_material(&d.name, d.mat.clone())?;
        d.index = Some(i);
        Ok(i)
    }

    /// Adds a shape (or records it in the object being defined). `emission` is the area
    /// light's radiance and its emission spectrum.
    pub fn add_shape(
        &mut self,
        geometry: ShapeGeometry,
        flip: bool,
        emission: Option<(Spectrum, Option<EmissionSpectrum>)>,
        line: usize,
        col: usize,
    ) -> Result<(), LoadError> {
        let material = self.current_material()?;
        if let Some(o) = &mut self.current_object {
            if emission.is_some() {
                return Err(self.err(line, col, "area lights inside object definitions are not supported (pbrt-v4 does not support them either)"));
            }
            o.shapes.push(ShapeRec {
                geometry,
                material,
                flip,
                line,
            });
            return Ok(());
        }
        let lights_before = self.b.lights().len();
        self.b
            .add_shape(geometry, material, emission.map(|e| e.0), flip)
            .map_err(|e| self.err(line, col, e.to_string()))?;
        if let Some((_, Some(s))) = emission {
            for l in lights_before..self.b.lights().len() {
                self.b.set_light_spectrum(l, s);
            }
        }
        Ok(())
    }

    fn instance(&mut self, name: &str, line: usize, col: usize) -> Result<(), LoadError> {
        let Some(shapes) = self.objects.get(name) else {
            return Err(self.err(
                line,
                col,
                format!(
                    "unknown object \"{}\" (define it with ObjectBegin/ObjectEnd first)",
                    clip(name)
                ),
            ));
        };
        let shapes = shapes.clone();
        let ctm = self.gs.ctm;
        let a = shapes::affine(&ctm).ok_or_else(|| {
            self.err(
                line,
                col,
                "ObjectInstance: the CTM must be affine and finite",
            )
        })?;
        let tris: usize = shapes
            .iter()
            .map(|s| match &s.geometry {
                ShapeGeometry::Mesh(m) => m.indices.len(),
                _ => 1,
            })
            .sum();
        self.instanced_triangles = self.instanced_triangles.saturating_add(tris);
        if self.instanced_triangles > MAX_INSTANCED_TRIANGLES {
            return Err(self.err(line, col, format!(
                "object instances would copy more than {MAX_INSTANCED_TRIANGLES} triangles (caustica expands instances into meshes)"
            )));
        }
        for s in shapes {
            let (g, flip) =
                shapes::transform_geometry(s.geometry, s.flip, &a, &ctm).map_err(|m| {
                    self.err(
                        line,
                        col,
                        format!(
                            "ObjectInstance \"{}\" (shape of line {}): {m}",
                            clip(name),
                            s.line
                        ),
                    )
                })?;
            self.b
                .add_shape(g, s.material, None, flip)
                .map_err(|e| self.err(line, col, e.to_string()))?;
        }
        Ok(())
    }

    fn finish(mut self) -> Result<SceneBuilder, LoadError> {
        camera::finish_camera(&mut self)?;
        crate::report::push_warnings(
            &mut self.b,
            "pbrt scene",
            &self.unsupported,
            &self.approximations,
        );
        Ok(self.b)
    }
}

//! Keyword arguments of `caustica.render` → the command line's [`RenderSettings`].
//!
//! Every option of `caustica render` that decides what is computed is a keyword argument of
//! the same name with `_` for `-` (`min_footprint=0.5` is `--min-footprint 0.5`). The keywords
//! are turned into those arguments and parsed by the command line's own parser, so a render
//! from Python is the render of that command line, and a bad value gets the CLI's message.
//! Python types are checked first: each option's kind (flag, integer, number, text) is read from
//! the parser itself, by probing which values it accepts.

use caustica_cli::render_cmd::RenderSettings;
use clap::{ArgAction, Args, Command, FromArgMatches};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// What Python values an option takes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// A switch: `True` gives it, `False` leaves it out.
    Flag,
    /// An integer (Python `int`, not `bool`).
    Integer,
    /// A number (`int` or `float`).
    Number,
    /// Text that may also be a number (`str`, `int` or `float`).
    Text,
    /// Repeatable (a list or tuple of values).
    List,
}

/// The keyword arguments that are not command-line options of `render`, or are given elsewhere.
const NOT_OPTIONS: [(&str, &str); 2] = [
    (
        "scene",
        "the scene is the first argument of render(); load it with caustica.load()",
    ),
    (
        "define",
        "scene parameters (-D) are given to caustica.load(path, name=value)",
    ),
];

fn command() -> Command {
    RenderSettings::augment_args(Command::new("render").no_binary_name(true))
}

/// The `render` options by Python name, with their kinds (probed once).
fn options() -> &'static BTreeMap<String, (String, Kind)> {
    static OPTIONS: OnceLock<BTreeMap<String, (String, Kind)>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let cmd = command();
        cmd.get_arguments()
            .filter_map(|a| {
                let long = a.get_long()?.to_string();
                let kind = match a.get_action() {
                    ArgAction::SetTrue => Kind::Flag,
                    ArgAction::Append => Kind::List,
                    _ => probe(&long),
                };
                Some((long.replace('-', "_"), (long, kind)))
            })
            .filter(|(name, _)| !NOT_OPTIONS.iter().any(|(n, _)| n == name))
            .collect()
    })
}

/// The kind of a valued option: which of `1`, `0.5` and `x` its parser accepts.
fn probe(long: &str) -> Kind {
    let accepts = |v: &str| {
        command()
            .try_get_matches_from([format!("--{long}={v}")])
            .is_ok()
    };
    match (accepts("1"), accepts("0.5"), accepts("x")) {
        (_, _, true) => Kind::Text,
        (_, true, false) => Kind::Number,
        (true, false, false) => Kind::Integer,
        // Nothing simple parses (e.g. a list syntax): text, checked by the parser.
        (false, false, false) => Kind::Text,
    }
}

/// The command-line text of one Python value for an option of `kind`; a `TypeError` naming
/// the argument when the type is wrong.
fn value_text(name: &str, kind: Kind, v: &Bound<'_, PyAny>) -> PyResult<String> {
    let type_name = || {
        v.get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".to_string())
    };
    let wrong = |expected: &str| {
        PyTypeError::new_err(format!(
            "render() argument '{name}' must be {expected}, not {}",
            type_name()
        ))
    };
    let is_bool = v.is_instance_of::<PyBool>();
    let is_int = v.is_instance_of::<PyInt>() && !is_bool;
    let is_float = v.is_instance_of::<PyFloat>();
    match kind {
        Kind::Integer if is_int => Ok(v.str()?.to_string()),
        Kind::Integer => Err(wrong("an int")),
        Kind::Number if is_int || is_float => Ok(number_text(v)?),
        Kind::Number => Err(wrong("a number (int or float)")),
        Kind::Text if v.is_instance_of::<PyString>() => Ok(v.extract::<String>()?),
        Kind::Text if is_int || is_float => Ok(number_text(v)?),
        Kind::Text => Err(wrong("a str")),
        Kind::Flag | Kind::List => Err(wrong("a value")),
    }
}

/// A Python number as the command line writes it (`repr` of a float is the shortest text that
/// reads back to the same double).
fn number_text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(v.repr()?.to_string())
}

/// The command-line arguments of `kwargs`, in order; `TypeError`s for unknown names and wrong
/// types.
pub fn arguments(kwargs: &[(String, Bound<'_, PyAny>)]) -> PyResult<Vec<String>> {
    let opts = options();
    let mut args = Vec::new();
    for (name, v) in kwargs {
        if let Some((_, why)) = NOT_OPTIONS.iter().find(|(n, _)| n == name) {
            return Err(PyTypeError::new_err(format!(
                "render() got an unexpected keyword argument '{name}': {why}"
            )));
        }
        let Some((long, kind)) = opts.get(name) else {
            return Err(PyTypeError::new_err(format!(
                "render() got an unexpected keyword argument '{name}'{}",
                suggestion(name)
            )));
        };
        if v.is_none() {
            continue;
        }
        match kind {
            Kind::Flag => {
                if !v.is_instance_of::<PyBool>() {
                    return Err(PyTypeError::new_err(format!(
                        "render() argument '{name}' must be a bool, not {}",
                        v.get_type().name()?
                    )));
                }
                if v.extract::<bool>()? {
                    args.push(format!("--{long}"));
                }
            }
            Kind::List => {
                let items: Vec<Bound<'_, PyAny>> =
                    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
                        v.try_iter()?.collect::<PyResult<_>>()?
                    } else {
                        vec![v.clone()]
                    };
                for item in items {
                    args.push(format!("--{long}={}", value_text(name, Kind::Text, &item)?));
                }
            }
            _ => args.push(format!("--{long}={}", value_text(name, *kind, v)?)),
        }
    }
    Ok(args)
}

/// " (did you mean 'x'?)" for the closest option name, if one is close.
fn suggestion(name: &str) -> String {
    let best = options()
        .keys()
        .map(|k| (edit_distance(name, k), k))
        .min_by_key(|(d, _)| *d);
    match best {
        Some((d, k)) if d <= 2.max(name.len() / 4) => format!(" (did you mean '{k}'?)"),
        _ => String::new(),
    }
}

/// Levenshtein distance (short option names only).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Parses `args` with the command line's parser into the settings of a render of `source`;
/// a `ValueError` with the parser's message (as `caustica render` prints it) if a value is bad.
pub fn settings(source: Option<&str>, args: &[String]) -> PyResult<RenderSettings> {
    let matches = command()
        .try_get_matches_from(args)
        .map_err(|e| PyValueError::new_err(clap_message(&e)))?;
    let mut s = RenderSettings::from_arg_matches(&matches)
        .map_err(|e| PyValueError::new_err(clap_message(&e)))?;
    s.scene = source.map(str::to_string);
    Ok(s)
}

/// The first line of a parser error without its `error: ` prefix (the usage lines that follow
/// are about the command line).
fn clap_message(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let first = text.lines().next().unwrap_or_default();
    first.strip_prefix("error: ").unwrap_or(first).to_string()
}

/// The Python names of `render`'s options and their kinds, for `caustica.render_options()`.
pub fn names() -> Vec<(String, String)> {
    options()
        .iter()
        .map(|(name, (_, kind))| {
            let k = match kind {
                Kind::Flag => "bool",
                Kind::Integer => "int",
                Kind::Number => "float",
                Kind::Text => "str",
                Kind::List => "list",
            };
            (name.clone(), k.to_string())
        })
        .collect()
}

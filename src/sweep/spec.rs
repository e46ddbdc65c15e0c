//! Sweep files (`sweeps/*.ron`): the serde shape ([`SweepSpec`]), parsing with positions,
//! command-line overrides (`--set key=value[,value...]`) and validation. Every error names the
//! file, line and column, the key and what is allowed ([`SpecError`]).

use super::job::RunSettings;
use super::ranges::{RANGE_SYNTAX, RangeCall};
use super::readable::readable_numbers;
pub use super::suggest::did_you_mean;
use crate::engine::declare::ParamKind;
use crate::engine::{Clock, EngineDef, ParamValue, Values};
use crate::registry;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// Values of parameters by name: the `fixed` section and each extra point, written as a RON
/// struct `(restitution: 0.7, wall_model: "thermal")`. Which keys exist depends on the engine,
/// so they are checked against its declaration by [`validate`], not by serde.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamValues(pub Values);

/// Grid axes: a list of values per swept parameter (cartesian product). In a sweep file an
/// axis is a list `[v1, v2, ...]` or a range (`linspace(0.5, 0.9, 5)`, see [`super::ranges`]),
/// expanded when read; it is written back as the list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamAxes(pub BTreeMap<String, Vec<ParamValue>>);

/// One axis as written: a list of values, or a range `name(args...)` (RON reads a call
/// `linspace(0.5, 0.9, 5)` into the untagged form as a map of its name to its arguments).
#[derive(Deserialize)]
#[serde(
    untagged,
    expecting = "an axis is a list [v1, v2, ...] or a range: linspace(start, stop, count), \
                 logspace(start, stop, count) or range(start, stop[, step])"
)]
enum AxisInput {
    List(Vec<ParamValue>),
    Range(BTreeMap<String, Vec<ParamValue>>),
}

/// The values of one axis, a range expanded as it is read (so that an error is placed at it).
struct AxisValues(Vec<ParamValue>);

impl<'de> Deserialize<'de> for AxisValues {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let call = match AxisInput::deserialize(d)? {
            AxisInput::List(values) => return Ok(AxisValues(values)),
            AxisInput::Range(call) => call,
        };
        let (name, args) = call.into_iter().next().ok_or_else(|| {
            serde::de::Error::custom(format!("an empty range; allowed: {RANGE_SYNTAX}"))
        })?;
        let args = args
            .iter()
            .map(|a| {
                a.as_f64().ok_or_else(|| {
                    format!("{name}(...): the arguments of a range are numbers, not {a}")
                })
            })
            .collect::<Result<Vec<f64>, String>>()
            .map_err(serde::de::Error::custom)?;
        let values = RangeCall::new(&name, args)
            .and_then(|c| c.expand())
            .map_err(serde::de::Error::custom)?;
        Ok(AxisValues(
            values.into_iter().map(ParamValue::Number).collect(),
        ))
    }
}

/// A RON struct (or map) of parameter names to values, read field by field.
struct NamedVisitor<T>(std::marker::PhantomData<T>);

impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for NamedVisitor<T> {
    type Value = BTreeMap<String, T>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("parameters as (name: value, ...)")
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> Result<Self::Value, A::Error> {
        let mut out = BTreeMap::new();
        while let Some(key) = m.next_key::<String>()? {
            if out.contains_key(&key) {
                return Err(serde::de::Error::custom(format!(
                    "key `{key}` is given twice"
                )));
            }
            // `key: Some(v)` (the explicit form of older sweep files) and `key: v` both read
            // as v; `key: None` means not given
            if let Some(value) = m.next_value::<Option<T>>()? {
                out.insert(key, value);
            }
        }
        Ok(out)
    }
    fn visit_unit<E: serde::de::Error>(self) -> Result<Self::Value, E> {
        Ok(BTreeMap::new())
    }
}

/// The registry's own `&'static` spelling of a parameter name (RON writes struct fields from
/// static names).
fn static_name(key: &str) -> Option<&'static str> {
    registry::engines()
        .find_map(|e| e.param(key))
        .map(|d| d.name)
}

fn serialize_named<S: serde::Serializer, T: Serialize>(
    map: &BTreeMap<String, T>,
    s: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::{SerializeMap, SerializeStruct};
    if map.keys().all(|k| static_name(k).is_some()) {
        let mut st = s.serialize_struct("Parameters", map.len())?;
        for (k, v) in map {
            st.serialize_field(static_name(k).expect("checked"), v)?;
        }
        st.end()
    } else {
        let mut m = s.serialize_map(Some(map.len()))?;
        for (k, v) in map {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl<'de> Deserialize<'de> for ParamValues {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NamedVisitor(std::marker::PhantomData))
            .map(ParamValues)
    }
}

impl Serialize for ParamValues {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_named(&self.0, s)
    }
}

impl<'de> Deserialize<'de> for ParamAxes {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NamedVisitor::<AxisValues>(std::marker::PhantomData))
            .map(|axes| ParamAxes(axes.into_iter().map(|(k, v)| (k, v.0)).collect()))
    }
}

impl Serialize for ParamAxes {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_named(&self.0, s)
    }
}

/// A linked axis: `param` = `factor` x the value of `follows` (e.g. H/d follows W/d).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Link {
    /// the parameter that is set
    pub param: String,
    /// the swept (or fixed) parameter it follows
    pub follows: String,
    /// param = factor x follows
    #[serde(default = "one")]
    pub factor: f64,
}

fn one() -> f64 {
    1.0
}

fn is_empty_settings(v: &serde_json::Value) -> bool {
    v.is_null() || v.as_object().is_some_and(|m| m.is_empty())
}

fn default_seeds() -> Vec<u64> {
    vec![1]
}

/// The seeds as written: whole numbers from 0 to i64::MAX (tables hold them as signed 64-bit
/// integers); anything else is refused saying so.
fn seeds<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<u64>, D::Error> {
    struct Seed(u64);
    impl<'de> Deserialize<'de> for Seed {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            struct Visit;
            impl serde::de::Visitor<'_> for Visit {
                type Value = Seed;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    write!(f, "a seed: a whole number from 0 to {}", i64::MAX)
                }
                fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Seed, E> {
                    u64::try_from(v).map(Seed).map_err(|_| out_of_range(v))
                }
                fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Seed, E> {
                    if i64::try_from(v).is_ok() {
                        Ok(Seed(v))
                    } else {
                        Err(out_of_range(v))
                    }
                }
                fn visit_i128<E: serde::de::Error>(self, v: i128) -> Result<Seed, E> {
                    i64::try_from(v)
                        .map_err(|_| out_of_range(v))
                        .and_then(|v| self.visit_i64(v))
                }
                fn visit_u128<E: serde::de::Error>(self, v: u128) -> Result<Seed, E> {
                    Err(out_of_range(v))
                }
                fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Seed, E> {
                    Err(E::custom(format!(
                        "seed {v} is not a whole number: allowed whole numbers from 0 to {}",
                        i64::MAX
                    )))
                }
            }
            fn out_of_range<E: serde::de::Error>(v: impl fmt::Display) -> E {
                E::custom(format!(
                    "seed {v} is out of range: allowed whole numbers from 0 to {} (tables hold \
                     seeds as signed 64-bit integers)",
                    i64::MAX
                ))
            }
            d.deserialize_any(Visit)
        }
    }
    Ok(Vec::<Seed>::deserialize(d)?
        .into_iter()
        .map(|s| s.0)
        .collect())
}

/// A sweep file as written (see docs/sweeps.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// the sweep's name (results go to `results/<name>/`); default: the file stem
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// free text
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// the engine (a name of the registry, e.g. "edmd")
    pub engine: String,
    /// fixed parameter values (unset ones take their defaults)
    #[serde(default)]
    pub fixed: ParamValues,
    /// swept parameters: cartesian product, in the order of the parameter table
    #[serde(default)]
    pub axes: ParamAxes,
    /// parameters that follow a swept one
    #[serde(default)]
    pub linked: Vec<Link>,
    /// extra points (fixed values overridden by the point's values)
    #[serde(default)]
    pub points: Vec<ParamValues>,
    /// seeds (replicas): every grid point and extra point runs once per seed
    #[serde(default = "default_seeds", deserialize_with = "seeds")]
    pub seeds: Vec<u64>,
    /// run length and snapshot cadence
    pub run: RunSettings,
    /// analysis settings of the engine's analysis (keys it does not set take their defaults)
    #[serde(default, skip_serializing_if = "is_empty_settings")]
    pub analysis: serde_json::Value,
    /// adaptive refinement of one or two axes where the quantity changes (docs/sweeps.md)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<super::refine::RefineSpec>,
    /// the `--set` overrides already applied (written into the resolved sweep; informational)
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
}

/// Where in the input an error is.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// a file, 1-based line and column (0 when unknown)
    File {
        path: PathBuf,
        line: usize,
        col: usize,
    },
    /// a `--set` argument
    Override(String),
}

/// A bad sweep file or override: where, which key, what is wrong and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct SpecError {
    pub origin: Origin,
    /// the key concerned (e.g. `fixed.restitution`), when there is one
    pub key: Option<String>,
    pub message: String,
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.origin {
            Origin::File { path, line: 0, .. } => write!(f, "{}: ", path.display())?,
            Origin::File { path, line, col } => write!(f, "{}:{line}:{col}: ", path.display())?,
            Origin::Override(arg) => write!(f, "--set {arg}: ")?,
        }
        if let Some(key) = &self.key {
            write!(f, "key `{key}`: ")?;
        }
        f.write_str(&self.message)
    }
}

/// Source text with a path, to place errors.
pub(crate) struct Source<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl Source<'_> {
    /// An error at the position of `key` (searched after the section `section`, skipping
    /// `skip` earlier occurrences), or at 0:0 when it cannot be found.
    pub fn error_at(
        &self,
        section: Option<&str>,
        key: &str,
        skip: usize,
        message: String,
    ) -> SpecError {
        let (line, col) = self.locate(section, key, skip).unwrap_or((0, 0));
        let full_key = match section {
            Some(s) => format!("{s}.{key}"),
            None => key.to_string(),
        };
        SpecError {
            origin: Origin::File {
                path: self.path.to_path_buf(),
                line,
                col,
            },
            key: Some(full_key),
            message,
        }
    }

    fn locate(&self, section: Option<&str>, key: &str, skip: usize) -> Option<(usize, usize)> {
        let pos = self.offset(section, key, skip)?;
        Some(self.line_col(pos))
    }

    /// Byte offset of the `skip`-th (from 0) `key` after the section `section`.
    fn offset(&self, section: Option<&str>, key: &str, skip: usize) -> Option<usize> {
        let start = match section {
            Some(s) => find_key(self.text, 0, s)?,
            None => 0,
        };
        let mut at = start;
        let mut found = None;
        for _ in 0..=skip {
            let pos = find_key(self.text, at, key)?;
            found = Some(pos);
            at = pos + key.len();
        }
        found
    }

    /// 1-based line and column of a byte offset.
    fn line_col(&self, pos: usize) -> (usize, usize) {
        let before = &self.text[..pos];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, col)
    }

    /// An error at `key` of the `item`-th entry of the list `section`, an entry being found by
    /// `anchor`, a key every entry has: `key` may be missing from earlier entries (an optional
    /// key), so it is searched from the opening parenthesis of that entry on. At the entry
    /// when `key` is not written in it (a default), at 0:0 when nothing is found.
    pub fn error_in_item(
        &self,
        section: &str,
        anchor: &str,
        item: usize,
        key: &str,
        message: String,
    ) -> SpecError {
        let mut error = self.error_at(Some(section), anchor, item, message);
        error.key = Some(format!("{section}.{key}"));
        let Some(anchor_at) = self.offset(Some(section), anchor, item) else {
            return error;
        };
        let entry = self.text[..anchor_at].rfind('(').unwrap_or(anchor_at);
        let end = self.text[anchor_at..]
            .find(')')
            .map_or(self.text.len(), |e| anchor_at + e);
        if let Some(pos) = find_key(self.text, entry, key).filter(|&p| p < end) {
            let (line, col) = self.line_col(pos);
            error.origin = Origin::File {
                path: self.path.to_path_buf(),
                line,
                col,
            };
        }
        error
    }
}

/// Byte offset of the identifier `key` followed by `:` (or a quoted "key"), from `from` on.
fn find_key(text: &str, from: usize, key: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut at = from;
    while let Some(rel) = text.get(at..)?.find(key) {
        let pos = at + rel;
        let end = pos + key.len();
        let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
        let left_ok = pos == 0 || !ident(bytes[pos - 1]);
        let right_ok = end >= bytes.len() || !ident(bytes[end]);
        let rest = text[end..].trim_start_matches(['"', ' ', '\t', '\r', '\n']);
        if left_ok && right_ok && (rest.starts_with(':') || rest.starts_with('=')) {
            return Some(pos);
        }
        at = end;
    }
    None
}

/// Parse a sweep file's text (syntax, unknown sections, wrong types), with positions. The
/// parameter keys are checked later, against the engine's declaration ([`validate`]).
pub fn parse(path: &Path, text: &str) -> Result<SweepSpec, SpecError> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    options.from_str::<SweepSpec>(text).map_err(|e| {
        let src = Source { path, text };
        // the section of a struct, for errors that serde places at its end
        let section = |outer: &Option<String>| match outer.as_deref() {
            Some("RunSettings") => Some("run"),
            Some("Link") => Some("linked"),
            _ => None,
        };
        let (key, (line, col)) = match &e.code {
            ron::Error::NoSuchStructField { found, outer, .. } => (
                Some(found.clone()),
                src.locate(section(outer), found, 0)
                    .unwrap_or((e.span.start.line, e.span.start.col)),
            ),
            ron::Error::MissingStructField { field, outer } => (
                Some(field.to_string()),
                match section(outer) {
                    Some(s) => src.locate(None, s, 0).unwrap_or((1, 1)),
                    None => (1, 1),
                },
            ),
            _ => (
                key_before(text, e.span.start.line, e.span.start.col),
                (e.span.start.line, e.span.start.col),
            ),
        };
        SpecError {
            origin: Origin::File {
                path: path.to_path_buf(),
                line,
                col,
            },
            key,
            message: format!("{}{}", e.code, hint(&e.code)),
        }
    })
}

/// The last `identifier:` before (line, col) (1-based): the key an error position belongs to.
fn key_before(text: &str, line: usize, col: usize) -> Option<String> {
    let mut prefix = String::new();
    for (i, l) in text.lines().enumerate() {
        if i + 1 < line {
            prefix.push_str(l);
            prefix.push('\n');
        } else {
            prefix.extend(l.chars().take(col.saturating_sub(1)));
            break;
        }
    }
    let mut at = prefix.len();
    while let Some(colon) = prefix[..at].rfind(':') {
        let end = prefix[..colon].trim_end().len();
        let start = prefix[..end]
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |p| p + 1);
        if start < end {
            return Some(prefix[start..end].to_string());
        }
        at = colon;
    }
    None
}

fn hint(code: &ron::Error) -> String {
    match code {
        ron::Error::NoSuchStructField {
            found, expected, ..
        } => did_you_mean(found, expected.iter().copied())
            .map(|s| format!("; did you mean `{s}`?"))
            .unwrap_or_default(),
        _ => String::new(),
    }
}

/// The engine a spec names (None: unknown, reported by [`validate`]).
pub fn engine_of(spec: &SweepSpec) -> Option<&'static EngineDef> {
    registry::find(&spec.engine)
}

/// Apply `--set key=value[,value...]` overrides: one value replaces a fixed value (and removes
/// the axis or link that set it, and its alternatives, e.g. phi for N); several values, or a
/// range (`key=linspace(0.5, 0.9, 5)`, as in sweep files), make (or replace) an axis. `seeds=1,2,3`, a run length (`collisions_per_particle=X`, `steps=X`,
/// `time=X`), `snapshot_interval=X` and `until_steady=WINDOW` (or `off`) set the run. Extra points keep their own explicit
/// values.
pub fn apply_overrides(spec: &mut SweepSpec, overrides: &[String]) -> Result<(), SpecError> {
    // what each override set, to refuse a second one for the same thing
    let mut set: Vec<(String, &String)> = Vec::new();
    for arg in overrides {
        let bad = |key: Option<&str>, message: String| SpecError {
            origin: Origin::Override(arg.clone()),
            key: key.map(str::to_string),
            message,
        };
        let Some((key, value)) = arg.split_once('=') else {
            return Err(bad(None, "expected key=value or key=v1,v2,...".into()));
        };
        let key = key.trim();
        if let Some(engine) = engine_of(spec) {
            let slot = override_slot(key, engine);
            if let Some((_, earlier)) = set.iter().find(|(s, _)| *s == slot) {
                return Err(bad(
                    Some(key),
                    format!(
                        "{slot} is already set by --set {earlier}: give each key once (several \
                         values go into one --set as a list, {key}=v1,v2, or a range)"
                    ),
                ));
            }
            set.push((slot, arg));
        }
        // a range (`linspace(0.5, 0.9, 5)`) gives its values, else a comma-separated list
        let texts: Vec<String> = match RangeCall::parse(value) {
            Some(call) => call
                .and_then(|c| c.expand())
                .map_err(|m| bad(Some(key), m))?
                .iter()
                .map(f64::to_string)
                .collect(),
            None => value.split(',').map(|v| v.trim().to_string()).collect(),
        };
        let values: Vec<&str> = texts.iter().map(String::as_str).collect();
        let parse_f64 = |s: &str| -> Result<f64, SpecError> {
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                Ok(v) => Err(bad(Some(key), format!("{v} is not a finite number"))),
                Err(_) => Err(bad(Some(key), format!("`{s}` is not a number"))),
            }
        };
        let engine = engine_of(spec).ok_or_else(|| {
            bad(
                None,
                format!(
                    "engine \"{}\" does not exist; allowed: {}",
                    spec.engine,
                    registry::names()
                ),
            )
        })?;
        if key == "seed" || key == "seeds" {
            let mut seeds = Vec::new();
            for s in &values {
                seeds.push(s.parse::<u64>().map_err(|_| {
                    bad(
                        Some(key),
                        format!("`{s}` is not a seed: allowed whole numbers >= 0"),
                    )
                })?);
            }
            spec.seeds = seeds;
        } else if key == "until_steady" {
            if values.len() != 1 {
                return Err(bad(Some(key), "takes one window length, or `off`".into()));
            }
            spec.run.until_steady = match values[0] {
                "off" | "none" => None,
                v => Some(super::job::UntilSteady {
                    window: parse_f64(v)?,
                }),
            };
        } else if key == "snapshot_interval" || Clock::from_key(key).is_some() {
            if values.len() != 1 {
                return Err(bad(Some(key), "takes exactly one value".into()));
            }
            let v = parse_f64(values[0])?;
            match Clock::from_key(key) {
                Some(clock) => spec.run.set_length(clock, v),
                None => spec.run.snapshot_interval = v,
            }
        } else {
            let Some(def) = engine.param(key) else {
                let suggestion = did_you_mean(key, engine.params.iter().map(|d| d.name))
                    .map(|s| format!("did you mean `{s}`? "))
                    .unwrap_or_default();
                return Err(bad(
                    Some(key),
                    format!(
                        "{}{suggestion}allowed: {}, seeds, {}, snapshot_interval, until_steady",
                        unknown_key_message(key, engine),
                        engine.param_names(),
                        engine.clock_names()
                    ),
                ));
            };
            let mut parsed = values
                .iter()
                .map(|s| def.parse_text(s).map_err(|m| bad(Some(key), m)))
                .collect::<Result<Vec<_>, _>>()?;
            for v in &mut parsed {
                unsigned_zero(v);
                def.check_value(v)
                    .map_err(|m| bad(Some(key), readable_numbers(&m)))?;
            }
            let mut replaced = engine.alternatives_of(def.name);
            replaced.push(def.name);
            for name in &replaced {
                spec.fixed.0.remove(*name);
                spec.axes.0.remove(*name);
            }
            spec.linked
                .retain(|l| !replaced.contains(&l.param.as_str()));
            if parsed.len() == 1 {
                spec.fixed.0.insert(def.name.into(), parsed[0].clone());
            } else {
                spec.axes.0.insert(def.name.into(), parsed);
            }
        }
        spec.overrides.push(arg.clone());
    }
    Ok(())
}

/// What an override of `key` sets, in words: a parameter and its alternatives (phi and N) are
/// one thing, so are the run lengths on the engine's clocks, and `seed` and `seeds`.
fn override_slot(key: &str, engine: &EngineDef) -> String {
    if key == "seed" || key == "seeds" {
        return "`seeds`".into();
    }
    if Clock::from_key(key).is_some() {
        return "the run length".into();
    }
    match engine.param(key) {
        Some(def) => {
            let mut names = engine.alternatives_of(def.name);
            if names.is_empty() {
                return format!("`{}`", def.name);
            }
            names.push(def.name);
            names.sort();
            format!("`{}`", names.join("` or `"))
        }
        None => format!("`{key}`"),
    }
}

/// A value -0.0 as 0.0: the same physics, so the same job (id, name and value).
fn unsigned_zero(v: &mut ParamValue) {
    if let ParamValue::Number(x) = v
        && *x == 0.0
    {
        *x = 0.0;
    }
}

/// Every -0.0 among a spec's parameter values (fixed, axes, points) as 0.0.
pub fn unsign_zeros(spec: &mut SweepSpec) {
    spec.fixed.0.values_mut().for_each(unsigned_zero);
    for axis in spec.axes.0.values_mut() {
        axis.iter_mut().for_each(unsigned_zero);
    }
    for point in &mut spec.points {
        point.0.values_mut().for_each(unsigned_zero);
    }
}

/// "unknown key `x`" or, for a key of another engine, which engine has it.
fn unknown_key_message(key: &str, engine: &EngineDef) -> String {
    let others = registry::engines_with_param(key, engine.name);
    if others.is_empty() {
        format!("unknown key `{key}` for the {} engine; ", engine.name)
    } else {
        format!(
            "`{key}` is a parameter of {}, not of the {} engine; ",
            registry::engines_phrase(&others),
            engine.name
        )
    }
}

/// Longest sweep name: a directory name, with room for the paths under it.
const NAME_MAX: usize = 100;

/// A sweep name is one directory name: 1 to [`NAME_MAX`] letters, digits and `- _ . + = ,`,
/// not starting with a dot.
fn check_name(name: &str) -> Result<(), String> {
    let shown: String = name
        .chars()
        .take(40)
        .collect::<String>()
        .escape_debug()
        .to_string();
    let shown = if name.chars().count() > 40 {
        format!("{shown}...")
    } else {
        shown
    };
    if name.is_empty() || name.chars().count() > NAME_MAX {
        return Err(format!(
            "name \"{shown}\" has {} characters: allowed 1 to {NAME_MAX}",
            name.chars().count()
        ));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || "-_.+=,".contains(*c)))
    {
        return Err(format!(
            "name \"{shown}\" holds {:?}, which does not belong in a directory name: allowed \
             letters, digits and - _ . + = ,",
            c
        ));
    }
    if name.starts_with('.') {
        return Err(format!(
            "name \"{shown}\" starts with a dot (a hidden directory): start with a letter or digit"
        ));
    }
    Ok(())
}

/// An error about `key` that a `--set` override gave (the last one that set it): placed on
/// the option, not on the file's line.
fn at_override(spec: &SweepSpec, key: &str) -> Option<SpecError> {
    spec.overrides
        .iter()
        .rev()
        .find(|arg| arg.split_once('=').is_some_and(|(k, _)| k.trim() == key))
        .map(|arg| SpecError {
            origin: Origin::Override(arg.clone()),
            key: Some(key.to_string()),
            message: String::new(),
        })
}

impl SpecError {
    fn with_message(mut self, message: String) -> Self {
        self.message = message;
        self
    }
}

/// Check the parts of a spec that do not need the expansion, one phase per concern and in this
/// order (the first error is reported): the engine, the name, the run settings, the analysis
/// settings, the fixed and point values, the axes, the links, the seeds, the refinement.
pub(crate) fn validate(spec: &SweepSpec, src: &Source) -> Result<(), SpecError> {
    let engine = check_engine(spec, src)?;
    check_name_key(spec, src)?;
    check_run(spec, engine, src)?;
    check_analysis(spec, engine, src)?;
    check_values(spec, engine, src)?;
    check_axes(spec, engine, src)?;
    check_links(spec, engine, src)?;
    check_seeds(spec, src)?;
    check_refine(spec, engine, src)
}

/// The `refine` section: one or two refined axes, each a swept numeric axis of at least two
/// values; levels from 1 to [`super::refine::MAX_LEVELS`]; a budget that holds the base plan;
/// a numeric summary column of the engine's analysis for `Change` and `Minimum` (one axis),
/// a relative tolerance above 0.
fn check_refine(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    use super::refine::{MAX_LEVELS, Quantity};
    let Some(r) = &spec.refine else {
        return Ok(());
    };
    let at = |key: &str, message: String| src.error_at(Some("refine"), key, 0, message);
    let swept: Vec<&str> = spec.axes.0.keys().map(String::as_str).collect();
    if r.axes.is_empty() || r.axes.len() > 2 {
        return Err(at(
            "axes",
            format!(
                "{} axes given: refine one or two of the swept axes ({})",
                r.axes.len(),
                swept.join(", ")
            ),
        ));
    }
    for (i, name) in r.axes.iter().enumerate() {
        let Some(values) = spec.axes.0.get(name) else {
            return Err(at(
                "axes",
                format!(
                    "\"{name}\" is not a swept axis; allowed: {}",
                    swept.join(", ")
                ),
            ));
        };
        if r.axes[..i].contains(name) {
            return Err(at("axes", format!("\"{name}\" is given twice")));
        }
        let real = engine
            .param(name)
            .is_some_and(|d| matches!(d.kind, ParamKind::Real));
        if !real || values.len() < 2 || values.iter().any(|v| v.as_f64().is_none()) {
            return Err(at(
                "axes",
                format!(
                    "\"{name}\": a refined axis needs at least two values of a real (not \
                     integer or choice) parameter"
                ),
            ));
        }
        if spec.linked.iter().any(|l| &l.param == name) {
            return Err(at(
                "axes",
                format!("\"{name}\" is linked: refine the axis it follows"),
            ));
        }
    }
    if r.levels == 0 || r.levels > MAX_LEVELS {
        return Err(at(
            "levels",
            format!("levels = {}: allowed 1 to {MAX_LEVELS}", r.levels),
        ));
    }
    let grid: usize = spec.axes.0.values().map(Vec::len).product();
    let base = (grid + spec.points.len()) * spec.seeds.len();
    if r.budget < base {
        return Err(at(
            "budget",
            format!(
                "budget = {} jobs is less than the base plan's {base} jobs: allowed at least {base}",
                r.budget
            ),
        ));
    }
    let column = match &r.quantity {
        Quantity::Label => return Ok(()),
        Quantity::Change { column, relative } => {
            if !(relative.is_finite() && *relative > 0.0) {
                return Err(at(
                    "quantity",
                    format!("relative = {relative}: allowed a finite number above 0"),
                ));
            }
            column
        }
        Quantity::Minimum { column } => {
            if r.axes.len() != 1 {
                return Err(at(
                    "quantity",
                    "Minimum refines one axis: give one axis".into(),
                ));
            }
            column
        }
    };
    let numeric: Vec<String> = registry::analysis_of(engine)
        .summary_columns()
        .into_iter()
        .filter(|(_, k)| {
            matches!(
                k,
                crate::analysis::columns::ColumnKind::F64
                    | crate::analysis::columns::ColumnKind::I64
            )
        })
        .map(|(n, _)| n)
        .collect();
    if !numeric.contains(column) {
        return Err(at(
            "quantity",
            format!(
                "column \"{column}\" is not a numeric summary column of the {} analysis; allowed: {}",
                engine.name,
                numeric.join(", ")
            ),
        ));
    }
    Ok(())
}

/// The engine exists in the registry.
fn check_engine(spec: &SweepSpec, src: &Source) -> Result<&'static EngineDef, SpecError> {
    engine_of(spec).ok_or_else(|| {
        src.error_at(
            None,
            "engine",
            0,
            format!(
                "engine \"{}\" does not exist; allowed: {}",
                spec.engine,
                registry::names()
            ),
        )
    })
}

/// The sweep's name, when given, is one directory name ([`check_name`]).
fn check_name_key(spec: &SweepSpec, src: &Source) -> Result<(), SpecError> {
    match spec.name.as_deref().map(check_name) {
        Some(Err(why)) => Err(src.error_at(None, "name", 0, why)),
        _ => Ok(()),
    }
}

/// The run settings against the engine's clocks. The snapshot interval is checked against the
/// run length: an error is blamed on whichever of the two a `--set` gave, else on the file's
/// line of the key.
fn check_run(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    spec.run.validate(engine).map_err(|(key, message)| {
        let related = [key, spec.run.clock().key()];
        let keys = if key == "snapshot_interval" {
            &related[..]
        } else {
            &related[..1]
        };
        keys.iter()
            .find_map(|k| at_override(spec, k))
            .unwrap_or_else(|| src.error_at(Some("run"), key, 0, message.clone()))
            .with_message(message)
    })
}

/// The `analysis` settings are ones the engine's analysis reads.
fn check_analysis(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    match registry::analysis_of(engine).analyser(&spec.analysis) {
        Err(message) => Err(src.error_at(None, "analysis", 0, message.to_string())),
        Ok(_) => Ok(()),
    }
}

/// One value of `section` (the `skip`-th occurrence of `name` in it): a parameter of the engine,
/// within its declared range or choices.
fn check_param(
    engine: &EngineDef,
    src: &Source,
    section: &str,
    name: &str,
    v: &ParamValue,
    skip: usize,
) -> Result<(), SpecError> {
    let Some(def) = engine.param(name) else {
        let suggestion = did_you_mean(name, engine.params.iter().map(|d| d.name))
            .map(|s| format!("did you mean `{s}`? "))
            .unwrap_or_default();
        return Err(src.error_at(
            Some(section),
            name,
            skip,
            format!(
                "{}{suggestion}the {} engine's parameters are: {}",
                unknown_key_message(name, engine),
                engine.name,
                engine.param_names()
            ),
        ));
    };
    def.check_value(v)
        .map_err(|m| src.error_at(Some(section), name, skip, readable_numbers(&m)))
}

/// The `fixed` values, then each extra point's values ([`check_param`]).
fn check_values(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    for (name, v) in &spec.fixed.0 {
        check_param(engine, src, "fixed", name, v, 0)?;
    }
    for (i, point) in spec.points.iter().enumerate() {
        for (name, v) in &point.0 {
            let skip = spec.points[..i]
                .iter()
                .filter(|p| p.0.contains_key(name))
                .count();
            check_param(engine, src, "points", name, v, skip)?;
        }
    }
    Ok(())
}

/// Each axis: not empty, its values valid ([`check_param`]) and distinct, and not also fixed.
fn check_axes(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    let at = |name: &str, message: String| src.error_at(Some("axes"), name, 0, message);
    for (name, values) in &spec.axes.0 {
        if values.is_empty() {
            return Err(at(
                name,
                "the axis is empty: give at least one value (or move it to `fixed`)".into(),
            ));
        }
        for (i, v) in values.iter().enumerate() {
            check_param(engine, src, "axes", name, v, 0)?;
            if values[..i].contains(v) {
                return Err(at(
                    name,
                    format!("duplicate value {v} in the axis: each value may appear once"),
                ));
            }
        }
        if spec.fixed.0.contains_key(name) {
            return Err(at(
                name,
                "is both fixed and swept: keep it in one of `fixed` or `axes`".into(),
            ));
        }
    }
    Ok(())
}

/// Each link: its parameter exists, follows a swept or fixed parameter, both are numeric, it
/// has no other source, and its factor is finite and positive.
fn check_links(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    let axes = &spec.axes.0;
    let fixed = &spec.fixed.0;
    let numeric = |d: &crate::engine::ParamDef| !matches!(d.kind, ParamKind::Choice(_));
    for (i, link) in spec.linked.iter().enumerate() {
        // `param` and `follows` are in every link, `factor` may be left at its default
        let at = |key: &str, message: String| src.error_in_item("linked", "param", i, key, message);
        let Some(def) = engine.param(&link.param) else {
            return Err(at(
                "param",
                format!(
                    "unknown parameter \"{}\"; allowed: {}",
                    link.param,
                    engine.param_names()
                ),
            ));
        };
        if !axes.contains_key(&link.follows) && !fixed.contains_key(&link.follows) {
            return Err(at(
                "follows",
                format!(
                    "\"{}\" is neither swept nor fixed; allowed: {}",
                    link.follows,
                    axes.keys()
                        .chain(fixed.keys())
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        if !numeric(def) || !engine.param(&link.follows).is_some_and(numeric) {
            return Err(at(
                "param",
                format!(
                    "\"{}\" follows \"{}\": links are between numeric parameters",
                    link.param, link.follows
                ),
            ));
        }
        if axes.contains_key(def.name) || fixed.contains_key(def.name) {
            return Err(at(
                "param",
                format!(
                    "\"{}\" is also fixed or swept: a parameter has one source",
                    def.name
                ),
            ));
        }
        if !(link.factor.is_finite() && link.factor > 0.0) {
            return Err(at(
                "factor",
                format!(
                    "{} is out of range: allowed a finite value > 0",
                    link.factor
                ),
            ));
        }
    }
    Ok(())
}

/// At least one seed, each within a signed 64-bit integer, none twice.
fn check_seeds(spec: &SweepSpec, src: &Source) -> Result<(), SpecError> {
    let at = |message: String| src.error_at(None, "seeds", 0, message);
    if spec.seeds.is_empty() {
        return Err(at("no seeds: give at least one".into()));
    }
    for (i, s) in spec.seeds.iter().enumerate() {
        if i64::try_from(*s).is_err() {
            return Err(at(format!(
                "seed {s} is out of range: allowed 0 to {} (tables hold it as a signed 64-bit integer)",
                i64::MAX
            )));
        }
        if spec.seeds[..i].contains(s) {
            return Err(at(format!("duplicate seed {s}: each seed may appear once")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    //! [`validate`] phase by phase: each message, its key and its place (line, or the `--set`
    //! that gave the value), from small sweep files.
    use super::*;

    const PATH: &str = "t.ron";

    /// A small EDMD sweep file, one section a line: line 3 `fixed`, line 4 `axes`, line 5 `run`,
    /// line 6 `extra` (further sections, or nothing).
    fn edmd(fixed: &str, axes: &str, extra: &str) -> String {
        format!(
            "(\n    engine: \"edmd\",\n    fixed: ({fixed}),\n    axes: ({axes}),\n    \
             run: (collisions_per_particle: 100.0, snapshot_interval: 10.0),\n    {extra}\n)\n"
        )
    }

    const FIXED: &str =
        "width_over_diameter: 10.0, height_over_diameter: 10.0, volume_fraction: 0.15";
    const AXES: &str = "length_over_width: [1.0, 2.0]";

    /// A small DSMC sweep file (a choice parameter, `wall_model`, for the links).
    fn dsmc(extra: &str) -> String {
        format!(
            "(\n    engine: \"dsmc\",\n    fixed: (wall_model: \"thermal\"),\n    \
             axes: (knudsen_number: [0.1, 0.2]),\n    \
             run: (steps: 100.0, snapshot_interval: 10.0),\n    {extra}\n)\n"
        )
    }

    fn parsed(text: &str) -> SweepSpec {
        parse(Path::new(PATH), text).unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    fn check(spec: &SweepSpec, text: &str) -> Result<(), SpecError> {
        validate(
            spec,
            &Source {
                path: Path::new(PATH),
                text,
            },
        )
    }

    /// The error of a sweep file that parses but must not validate.
    fn error(text: &str) -> SpecError {
        match check(&parsed(text), text) {
            Ok(()) => panic!("validated, but should not have:\n{text}"),
            Err(e) => e,
        }
    }

    /// The error's key, message and line in the file.
    fn placed(e: &SpecError) -> (Option<&str>, &str, usize) {
        let Origin::File { line, .. } = &e.origin else {
            panic!("expected an error in the file, got {e}");
        };
        (e.key.as_deref(), e.message.as_str(), *line)
    }

    fn edmd_def() -> &'static EngineDef {
        registry::find("edmd").expect("edmd is registered")
    }

    #[test]
    fn the_small_files_validate() {
        for text in [edmd(FIXED, AXES, ""), dsmc("")] {
            check(&parsed(&text), &text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        }
    }

    #[test]
    fn an_unknown_engine_is_named_with_the_ones_there_are() {
        let text = edmd(FIXED, AXES, "").replace("\"edmd\"", "\"edmx\"");
        let e = error(&text);
        let message = format!(
            "engine \"edmx\" does not exist; allowed: {}",
            registry::names()
        );
        assert_eq!(placed(&e), (Some("engine"), message.as_str(), 2));
        assert_eq!(e.to_string(), format!("t.ron:2:5: key `engine`: {message}"));
    }

    #[test]
    fn a_name_is_one_directory_name() {
        let cases = [
            (
                "",
                "name \"\" has 0 characters: allowed 1 to 100".to_string(),
            ),
            (
                "a/b",
                "name \"a/b\" holds '/', which does not belong in a directory name: allowed \
                 letters, digits and - _ . + = ,"
                    .into(),
            ),
            (
                ".hidden",
                "name \".hidden\" starts with a dot (a hidden directory): start with a letter or \
                 digit"
                    .into(),
            ),
            (
                &"x".repeat(101),
                format!(
                    "name \"{}...\" has 101 characters: allowed 1 to 100",
                    "x".repeat(40)
                ),
            ),
        ];
        for (name, message) in cases {
            let e = error(&edmd(FIXED, AXES, &format!("name: \"{name}\",")));
            assert_eq!(placed(&e), (Some("name"), message.as_str(), 6), "{name}");
        }
        check(&parsed(&edmd(FIXED, AXES, "name: \"a-b_c.1+2=3,4\",")), "").unwrap();
    }

    #[test]
    fn run_settings_are_placed_in_the_run_section() {
        let text = edmd(FIXED, AXES, "").replace("collisions_per_particle", "steps");
        let e = error(&text);
        let message = format!(
            "the edmd engine cannot measure a run in `steps`; allowed: {}",
            edmd_def().clock_names()
        );
        assert_eq!(placed(&e), (Some("run.steps"), message.as_str(), 5));
    }

    #[test]
    fn a_run_error_is_blamed_on_the_set_that_caused_it() {
        // the interval (10, from the file) exceeds the length a --set gave: the --set is blamed
        let text = edmd(FIXED, AXES, "");
        for (arg, key) in [
            ("collisions_per_particle=5", "collisions_per_particle"),
            ("snapshot_interval=1000", "snapshot_interval"),
        ] {
            let mut spec = parsed(&text);
            apply_overrides(&mut spec, &[arg.to_string()]).unwrap();
            let e = check(&spec, &text).unwrap_err();
            assert_eq!(e.origin, Origin::Override(arg.into()), "{e}");
            assert_eq!(e.key.as_deref(), Some(key));
            assert!(
                e.message
                    .contains("is out of range: allowed 0 < snapshot_interval <="),
                "{e}"
            );
        }
    }

    #[test]
    fn analysis_settings_are_checked_by_the_engines_analysis() {
        let e = error(&edmd(FIXED, AXES, "analysis: (no_such_setting: 1),"));
        let (key, message, line) = placed(&e);
        assert_eq!((key, line), (Some("analysis"), 6));
        assert!(
            message.starts_with("unknown field `no_such_setting`")
                && message.ends_with(
                    "allowed keys: grid, profile_bins, cell_particles, min_steady_snapshots"
                ),
            "{message}"
        );
    }

    #[test]
    fn fixed_keys_and_values_are_checked_against_the_declaration() {
        let names = edmd_def().param_names();
        let e = error(&edmd(&format!("{FIXED}, restitutoin: 0.5"), AXES, ""));
        let message = format!(
            "unknown key `restitutoin` for the edmd engine; did you mean `restitution`? the edmd \
             engine's parameters are: {names}"
        );
        assert_eq!(placed(&e), (Some("fixed.restitutoin"), message.as_str(), 3));

        let e = error(&edmd(&format!("{FIXED}, knudsen_number: 0.5"), AXES, ""));
        let message = format!(
            "`knudsen_number` is a parameter of {}, not of the edmd engine; the edmd engine's \
             parameters are: {names}",
            registry::engines_phrase(&registry::engines_with_param("knudsen_number", "edmd"))
        );
        assert_eq!(
            placed(&e),
            (Some("fixed.knudsen_number"), message.as_str(), 3)
        );

        let e = error(&edmd(&format!("{FIXED}, restitution: 1.5"), AXES, ""));
        assert_eq!(
            placed(&e),
            (
                Some("fixed.restitution"),
                "restitution (e) = 1.5 is out of range: allowed [0, 1]",
                3
            )
        );
    }

    #[test]
    fn a_bad_point_value_is_placed_at_its_own_point() {
        let text = edmd(
            FIXED,
            AXES,
            "points: [\n        (restitution: 0.5),\n        (restitution: 2.0),\n    ],",
        );
        let e = error(&text);
        assert_eq!(
            placed(&e),
            (
                Some("points.restitution"),
                "restitution (e) = 2 is out of range: allowed [0, 1]",
                8
            )
        );
    }

    #[test]
    fn axes_are_non_empty_distinct_valid_and_not_fixed() {
        let cases = [
            (
                "length_over_width: []",
                "the axis is empty: give at least one value (or move it to `fixed`)",
            ),
            (
                "length_over_width: [1.0, 2.0, 1.0]",
                "duplicate value 1 in the axis: each value may appear once",
            ),
            (
                "length_over_width: [1.0, -2.0]",
                "length_over_width (L/W) = -2 is out of range: allowed a finite value > 0 with \
                 3 <= L = (L/W)(W/d) <= 1e7",
            ),
        ];
        for (axes, message) in cases {
            let e = error(&edmd(FIXED, axes, ""));
            assert_eq!(
                placed(&e),
                (Some("axes.length_over_width"), message, 4),
                "{axes}"
            );
        }
        let e = error(&edmd(&format!("{FIXED}, length_over_width: 1.0"), AXES, ""));
        assert_eq!(
            placed(&e),
            (
                Some("axes.length_over_width"),
                "is both fixed and swept: keep it in one of `fixed` or `axes`",
                4
            )
        );
    }

    /// `linked` with a first, valid link and a second one, `second` (placed on line 8).
    fn links(second: &str) -> String {
        format!(
            "linked: [\n        (param: \"height_over_diameter\", follows: \"length_over_width\"),\n        \
             {second},\n    ],"
        )
    }

    #[test]
    fn links_follow_a_swept_or_fixed_numeric_parameter_with_a_positive_factor() {
        let fixed = "width_over_diameter: 10.0, volume_fraction: 0.15";
        let text = edmd(
            fixed,
            AXES,
            &links("(param: \"gravity\", follows: \"width_over_diameter\", factor: 0.1)"),
        );
        check(&parsed(&text), &text).unwrap_or_else(|e| panic!("{e}"));

        let names = edmd_def().param_names();
        let cases = [
            (
                "(param: \"gravitee\", follows: \"width_over_diameter\")",
                "linked.param",
                format!("unknown parameter \"gravitee\"; allowed: {names}"),
            ),
            (
                "(param: \"gravity\", follows: \"restitution\")",
                "linked.follows",
                "\"restitution\" is neither swept nor fixed; allowed: length_over_width, \
                 volume_fraction, width_over_diameter"
                    .into(),
            ),
            (
                "(param: \"gravity\", follows: \"width_over_diameter\", factor: 0.0)",
                "linked.factor",
                "0 is out of range: allowed a finite value > 0".into(),
            ),
            (
                "(param: \"gravity\", follows: \"width_over_diameter\", factor: -2.0)",
                "linked.factor",
                "-2 is out of range: allowed a finite value > 0".into(),
            ),
            (
                "(param: \"volume_fraction\", follows: \"width_over_diameter\")",
                "linked.param",
                "\"volume_fraction\" is also fixed or swept: a parameter has one source".into(),
            ),
            (
                "(param: \"length_over_width\", follows: \"width_over_diameter\")",
                "linked.param",
                "\"length_over_width\" is also fixed or swept: a parameter has one source".into(),
            ),
        ];
        for (second, key, message) in cases {
            let e = error(&edmd(fixed, AXES, &links(second)));
            assert_eq!(placed(&e), (Some(key), message.as_str(), 8), "{second}");
        }
    }

    #[test]
    fn links_are_between_numeric_parameters() {
        for link in [
            "(param: \"wall_model\", follows: \"knudsen_number\")",
            "(param: \"forcing\", follows: \"wall_model\")",
        ] {
            let text = dsmc(&format!("linked: [\n        {link},\n    ],")).replace(
                "fixed: (wall_model: \"thermal\")",
                "fixed: (restitution: 1.0, wall_model: \"thermal\")",
            );
            let text = if link.contains("param: \"wall_model\"") {
                text.replace(", wall_model: \"thermal\"", "")
            } else {
                text
            };
            let e = error(&text);
            let (from, to) = if link.contains("param: \"wall_model\"") {
                ("wall_model", "knudsen_number")
            } else {
                ("forcing", "wall_model")
            };
            let message =
                format!("\"{from}\" follows \"{to}\": links are between numeric parameters");
            assert_eq!(
                placed(&e),
                (Some("linked.param"), message.as_str(), 7),
                "{link}"
            );
        }
    }

    #[test]
    fn seeds_are_given_in_range_and_once_each() {
        let e = error(&edmd(FIXED, AXES, "seeds: [],"));
        assert_eq!(
            placed(&e),
            (Some("seeds"), "no seeds: give at least one", 6)
        );
        let e = error(&edmd(FIXED, AXES, "seeds: [3, 1, 2, 1],"));
        assert_eq!(
            placed(&e),
            (
                Some("seeds"),
                "duplicate seed 1: each seed may appear once",
                6
            )
        );
        // the file's reader refuses seeds above i64::MAX; a spec built otherwise is checked too
        let text = edmd(FIXED, AXES, "seeds: [1, 2],");
        let mut spec = parsed(&text);
        spec.seeds[1] = u64::MAX;
        let e = check(&spec, &text).unwrap_err();
        let message = format!(
            "seed {} is out of range: allowed 0 to {} (tables hold it as a signed 64-bit integer)",
            u64::MAX,
            i64::MAX
        );
        assert_eq!(placed(&e), (Some("seeds"), message.as_str(), 6));
    }

    #[test]
    fn the_first_failing_phase_reports() {
        // a bad engine hides the rest; a bad fixed value comes before a duplicate seed
        let text = edmd(
            &format!("{FIXED}, restitution: 1.5"),
            AXES,
            "seeds: [1, 1],",
        );
        assert_eq!(error(&text).key.as_deref(), Some("fixed.restitution"));
        let text = text.replace("\"edmd\"", "\"nope\"");
        assert_eq!(error(&text).key.as_deref(), Some("engine"));
    }

    #[test]
    fn refine_is_checked_key_by_key() {
        let refine = |section: &str| edmd(FIXED, AXES, &format!("refine: ({section}),"));
        let ok = refine("axes: [\"length_over_width\"], levels: 3, budget: 10");
        check(&parsed(&ok), &ok).unwrap();
        let cases = [
            (
                "axes: [\"restitution\"], levels: 3, budget: 10",
                "refine.axes",
                "\"restitution\" is not a swept axis; allowed: length_over_width",
            ),
            (
                "axes: [], levels: 3, budget: 10",
                "refine.axes",
                "0 axes given: refine one or two of the swept axes (length_over_width)",
            ),
            (
                "axes: [\"length_over_width\"], levels: 0, budget: 10",
                "refine.levels",
                "levels = 0: allowed 1 to 16",
            ),
            (
                "axes: [\"length_over_width\"], levels: 3, budget: 1",
                "refine.budget",
                "budget = 1 jobs is less than the base plan's 2 jobs: allowed at least 2",
            ),
            (
                "axes: [\"length_over_width\"], levels: 3, budget: 10, \
                 quantity: Change(column: \"slip_velocity\", relative: 0.0)",
                "refine.quantity",
                "relative = 0: allowed a finite number above 0",
            ),
        ];
        for (section, key, message) in cases {
            let text = refine(section);
            let e = error(&text);
            assert_eq!(placed(&e), (Some(key), message, 6), "{text}");
        }
        let text = refine(
            "axes: [\"length_over_width\"], levels: 3, budget: 10, \
             quantity: Minimum(column: \"nope\")",
        );
        let e = error(&text);
        assert_eq!(e.key.as_deref(), Some("refine.quantity"));
        assert!(
            e.message.starts_with(
                "column \"nope\" is not a numeric summary column of the edmd analysis; allowed: "
            ) && e.message.contains("slip_velocity"),
            "{e}"
        );
        // an integer axis cannot be bisected
        let text = edmd(
            "width_over_diameter: 10.0, height_over_diameter: 10.0",
            "particles: [40, 80]",
            "refine: (axes: [\"particles\"], levels: 2, budget: 10),",
        );
        assert_eq!(
            error(&text).message,
            "\"particles\": a refined axis needs at least two values of a real (not integer \
             or choice) parameter"
        );
    }
}

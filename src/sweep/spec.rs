//! Sweep files (`sweeps/*.ron`): the serde shape ([`SweepSpec`]), parsing with positions,
//! command-line overrides (`--set key=value[,value...]`) and validation. Every error names the
//! file, line and column, the key and what is allowed ([`SpecError`]).

use super::job::{PARAMS, RunSettings, param_def, param_names};
use crate::analysis::AnalysisSettings;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// Engines a sweep may name.
pub const ENGINES: &[&str] = &["edmd"];

/// Values of parameters (each optional): the `fixed` section and each extra point.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamValues {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_over_width: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_over_diameter: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_over_diameter: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume_fraction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_restitution: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_roughness: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia_factor: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tc: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_temperature: Option<f64>,
}

/// Grid axes: a list of values per swept parameter (cartesian product).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamAxes {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_over_width: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_over_diameter: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_over_diameter: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume_fraction: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<Vec<u64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_restitution: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_roughness: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia_factor: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tc: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_temperature: Option<Vec<f64>>,
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

fn default_seeds() -> Vec<u64> {
    vec![1]
}

/// A sweep file as written (see README "## Sweeps").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// the sweep's name (results go to `results/<name>/`); default: the file stem
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// free text
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// the engine ("edmd")
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
    #[serde(default = "default_seeds")]
    pub seeds: Vec<u64>,
    /// run length and snapshot cadence
    pub run: RunSettings,
    /// analysis settings
    #[serde(default)]
    pub analysis: AnalysisSettings,
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
        let pos = found?;
        let before = &self.text[..pos];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Some((line, col))
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

/// Parse a sweep file's text (syntax, unknown keys, wrong types), with positions.
pub fn parse(path: &Path, text: &str) -> Result<SweepSpec, SpecError> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    options.from_str::<SweepSpec>(text).map_err(|e| {
        let key = key_before(text, e.span.start.line, e.span.start.col);
        let allowed = key
            .as_deref()
            .and_then(param_def)
            .map(|d| format!("; allowed: {}", d.allowed))
            .unwrap_or_default();
        SpecError {
            origin: Origin::File {
                path: path.to_path_buf(),
                line: e.span.start.line,
                col: e.span.start.col,
            },
            key,
            message: format!("{}{}{allowed}", e.code, hint(&e.code)),
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
        ron::Error::NoSuchStructField { .. } => {
            format!("; sweepable parameters are: {}", param_names())
        }
        _ => String::new(),
    }
}

impl ParamValues {
    /// The set values by parameter name (in table order).
    pub fn to_map(&self) -> BTreeMap<String, f64> {
        to_map(self)
    }
}

impl ParamAxes {
    /// The axes by parameter name.
    pub fn to_map(&self) -> BTreeMap<String, Vec<f64>> {
        to_map(self)
    }
}

fn to_map<T: Serialize, V: serde::de::DeserializeOwned>(value: &T) -> BTreeMap<String, V> {
    let json = serde_json::to_value(value).unwrap_or(serde_json::Value::Null);
    let mut out = BTreeMap::new();
    if let serde_json::Value::Object(map) = json {
        for (k, v) in map {
            if !v.is_null()
                && let Ok(v) = serde_json::from_value(v)
            {
                out.insert(k, v);
            }
        }
    }
    out
}

fn from_map<T: serde::de::DeserializeOwned, V: Serialize>(map: &BTreeMap<String, V>) -> T {
    let mut obj = serde_json::Map::new();
    for (k, v) in map {
        let json = serde_json::to_value(v).unwrap_or(serde_json::Value::Null);
        // integer parameters are stored as whole f64 values; give serde an integer
        let json = match json {
            serde_json::Value::Number(n) if param_def(k).is_some_and(|d| d.integer) => {
                n.as_f64().map_or(serde_json::Value::Null, |f| {
                    serde_json::Value::from(f as u64)
                })
            }
            serde_json::Value::Array(items) if param_def(k).is_some_and(|d| d.integer) => {
                serde_json::Value::Array(
                    items
                        .into_iter()
                        .map(|n| serde_json::Value::from(n.as_f64().unwrap_or(0.0) as u64))
                        .collect(),
                )
            }
            other => other,
        };
        obj.insert(k.clone(), json);
    }
    serde_json::from_value(serde_json::Value::Object(obj)).expect("maps of known parameters")
}

/// Apply `--set key=value[,value...]` overrides: one value replaces a fixed value (and removes
/// the axis or link that set it); several values make (or replace) an axis. `seeds=1,2,3`,
/// `collisions_per_particle=X` and `snapshot_interval=X` set the run. Extra points keep their
/// own explicit values.
pub fn apply_overrides(spec: &mut SweepSpec, overrides: &[String]) -> Result<(), SpecError> {
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
        let values: Vec<&str> = value.split(',').map(str::trim).collect();
        let parse_f64 = |s: &str| -> Result<f64, SpecError> {
            s.parse::<f64>()
                .map_err(|_| bad(Some(key), format!("`{s}` is not a number")))
        };
        match key {
            "seed" | "seeds" => {
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
            }
            "collisions_per_particle" | "snapshot_interval" => {
                if values.len() != 1 {
                    return Err(bad(Some(key), "takes exactly one value".into()));
                }
                let v = parse_f64(values[0])?;
                if key == "collisions_per_particle" {
                    spec.run.collisions_per_particle = v;
                } else {
                    spec.run.snapshot_interval = v;
                }
            }
            _ => {
                let Some(def) = param_def(key) else {
                    return Err(bad(
                        Some(key),
                        format!(
                            "unknown key; allowed: {}, seeds, collisions_per_particle, snapshot_interval",
                            param_names()
                        ),
                    ));
                };
                let parsed = values
                    .iter()
                    .map(|s| parse_f64(s))
                    .collect::<Result<Vec<_>, _>>()?;
                for &v in &parsed {
                    if !(def.check)(v) {
                        return Err(bad(
                            Some(key),
                            format!(
                                "{} ({}) = {v} is out of range: allowed {}",
                                def.name, def.symbol, def.allowed
                            ),
                        ));
                    }
                }
                let mut fixed = spec.fixed.to_map();
                let mut axes = spec.axes.to_map();
                if parsed.len() == 1 {
                    fixed.insert(def.name.into(), parsed[0]);
                    axes.remove(def.name);
                } else {
                    axes.insert(def.name.into(), parsed);
                    fixed.remove(def.name);
                }
                spec.linked.retain(|l| l.param != def.name);
                spec.fixed = from_map(&fixed);
                spec.axes = from_map(&axes);
            }
        }
        spec.overrides.push(arg.clone());
    }
    Ok(())
}

/// Check the parts of a spec that do not need the expansion: engine, run settings, each value
/// against its allowed range, axes non-empty without duplicates, links, seeds.
pub(crate) fn validate(spec: &SweepSpec, src: &Source) -> Result<(), SpecError> {
    if !ENGINES.contains(&spec.engine.as_str()) {
        return Err(src.error_at(
            None,
            "engine",
            0,
            format!(
                "engine \"{}\" does not exist; allowed: {}",
                spec.engine,
                ENGINES
                    .iter()
                    .map(|e| format!("\"{e}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    if let Some(name) = &spec.name
        && (name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.'))
    {
        return Err(src.error_at(
            None,
            "name",
            0,
            format!("name \"{name}\" is not a directory name: allowed letters, digits, - _ + = ,"),
        ));
    }
    let run = &spec.run;
    if !(run.collisions_per_particle.is_finite() && run.collisions_per_particle > 0.0) {
        return Err(src.error_at(
            Some("run"),
            "collisions_per_particle",
            0,
            format!(
                "{} is out of range: allowed a finite value > 0",
                run.collisions_per_particle
            ),
        ));
    }
    if !(run.snapshot_interval.is_finite()
        && run.snapshot_interval > 0.0
        && run.snapshot_interval <= run.collisions_per_particle
        && run.collisions_per_particle / run.snapshot_interval <= 1e6)
    {
        return Err(src.error_at(
            Some("run"),
            "snapshot_interval",
            0,
            format!(
                "{} is out of range: allowed 0 < snapshot_interval <= collisions_per_particle ({}), at most 1e6 snapshots",
                run.snapshot_interval, run.collisions_per_particle
            ),
        ));
    }
    if run.checkpoint_every == 0 {
        return Err(src.error_at(
            Some("run"),
            "checkpoint_every",
            0,
            "0 is out of range: allowed a whole number >= 1 (snapshots between checkpoints)".into(),
        ));
    }
    if spec.analysis.profile_bins == 0 {
        return Err(src.error_at(
            Some("analysis"),
            "profile_bins",
            0,
            "0 is out of range: allowed a whole number >= 1".into(),
        ));
    }
    let check = |section: &str, name: &str, v: f64, skip: usize| -> Result<(), SpecError> {
        let def = param_def(name).expect("known parameter");
        if (def.check)(v) {
            Ok(())
        } else {
            Err(src.error_at(
                Some(section),
                name,
                skip,
                format!(
                    "{} ({}) = {v} is out of range: allowed {}",
                    name, def.symbol, def.allowed
                ),
            ))
        }
    };
    for (name, v) in spec.fixed.to_map() {
        check("fixed", &name, v, 0)?;
    }
    for (i, point) in spec.points.iter().enumerate() {
        for (name, v) in point.to_map() {
            let skip = spec.points[..i]
                .iter()
                .filter(|p| p.to_map().contains_key(&name))
                .count();
            check("points", &name, v, skip)?;
        }
    }
    let axes = spec.axes.to_map();
    for (name, values) in &axes {
        if values.is_empty() {
            return Err(src.error_at(
                Some("axes"),
                name,
                0,
                "the axis is empty: give at least one value (or move it to `fixed`)".into(),
            ));
        }
        for (i, &v) in values.iter().enumerate() {
            check("axes", name, v, 0)?;
            if values[..i].contains(&v) {
                return Err(src.error_at(
                    Some("axes"),
                    name,
                    0,
                    format!("duplicate value {v} in the axis: each value may appear once"),
                ));
            }
        }
        if spec.fixed.to_map().contains_key(name) {
            return Err(src.error_at(
                Some("axes"),
                name,
                0,
                "is both fixed and swept: keep it in one of `fixed` or `axes`".into(),
            ));
        }
    }
    for (i, link) in spec.linked.iter().enumerate() {
        let Some(def) = param_def(&link.param) else {
            return Err(src.error_at(
                Some("linked"),
                "param",
                i,
                format!(
                    "unknown parameter \"{}\"; allowed: {}",
                    link.param,
                    param_names()
                ),
            ));
        };
        let fixed = spec.fixed.to_map();
        if !axes.contains_key(&link.follows) && !fixed.contains_key(&link.follows) {
            return Err(src.error_at(
                Some("linked"),
                "follows",
                i,
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
        if axes.contains_key(def.name) || spec.fixed.to_map().contains_key(def.name) {
            return Err(src.error_at(
                Some("linked"),
                "param",
                i,
                format!(
                    "\"{}\" is also fixed or swept: a parameter has one source",
                    def.name
                ),
            ));
        }
        if !(link.factor.is_finite() && link.factor > 0.0) {
            return Err(src.error_at(
                Some("linked"),
                "factor",
                i,
                format!(
                    "{} is out of range: allowed a finite value > 0",
                    link.factor
                ),
            ));
        }
    }
    if spec.seeds.is_empty() {
        return Err(src.error_at(None, "seeds", 0, "no seeds: give at least one".into()));
    }
    for (i, s) in spec.seeds.iter().enumerate() {
        if spec.seeds[..i].contains(s) {
            return Err(src.error_at(
                None,
                "seeds",
                0,
                format!("duplicate seed {s}: each seed may appear once"),
            ));
        }
    }
    let _ = PARAMS;
    Ok(())
}

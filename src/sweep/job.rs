//! Sweep parameters and job identity: the parameter table (names, symbols, defaults, allowed
//! ranges), a job's resolved parameters ([`JobParams`]) and its id ([`JobId`]), the hash of
//! their canonical form.
//!
//! Canonical form (the id contract, documented in README "## Sweeps"): a JSON object with keys
//! sorted, no whitespace, numbers in Rust's shortest round-trip notation:
//! `{"analysis":{..},"engine":"edmd","params":{..},"run":{..},"seed":S}` where `params` holds
//! every physical parameter of [`PARAMS`] with `in_id_at_default = true` (the resolved value,
//! even when it equals the default) plus the others only when they differ from their default,
//! and `analysis` holds only the analysis settings that differ from their defaults. The id is
//! the first 16 hex digits of SHA-256 of that text. So adding a new optional parameter (entered
//! in [`PARAMS`] with `in_id_at_default = false`) or a new analysis setting leaves every
//! existing id unchanged.

use crate::analysis::AnalysisSettings;
use crate::engine::edmd::{EdmdParams, particles_for_volume_fraction};
use crate::engine::{BoxGeometry, EngineSpec};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::fmt;

/// One sweepable parameter.
#[derive(Clone, Copy, Debug)]
pub struct ParamDef {
    /// the key in sweep files, `--set`, tables
    pub name: &'static str,
    /// the physics symbol
    pub symbol: &'static str,
    /// default value; None: the sweep must give it
    pub default: Option<f64>,
    /// the value must be a whole number
    pub integer: bool,
    /// the allowed range, as told to the user
    pub allowed: &'static str,
    /// the range check
    pub check: fn(f64) -> bool,
    /// true for the parameters of the first id scheme: always part of the canonical form.
    /// Parameters added later must say false (they enter the id only away from their default).
    pub in_id_at_default: bool,
}

fn finite_positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}
fn side(v: f64) -> bool {
    v.is_finite() && v >= 3.0
}
fn unit(v: f64) -> bool {
    (0.0..=1.0).contains(&v)
}
fn signed_unit(v: f64) -> bool {
    (-1.0..=1.0).contains(&v)
}
fn non_negative(v: f64) -> bool {
    v.is_finite() && v >= 0.0
}
fn fraction(v: f64) -> bool {
    v.is_finite() && v > 0.0 && v < std::f64::consts::PI / 6.0
}
fn inertia(v: f64) -> bool {
    v.is_finite() && v > 0.0 && v <= 1.0
}
fn count(v: f64) -> bool {
    v.is_finite() && v >= 1.0 && v.fract() == 0.0 && v <= 1e9
}

/// The sweepable parameters, in expansion order (the last swept one varies fastest).
pub const PARAMS: &[ParamDef] = &[
    ParamDef {
        name: "length_over_width",
        symbol: "L/W",
        default: None,
        integer: false,
        allowed: "a finite value > 0 with L = (L/W)(W/d) >= 3",
        check: finite_positive,
        in_id_at_default: true,
    },
    ParamDef {
        name: "width_over_diameter",
        symbol: "W/d",
        default: None,
        integer: false,
        allowed: "a finite value >= 3 (channel width in particle diameters)",
        check: side,
        in_id_at_default: true,
    },
    ParamDef {
        name: "height_over_diameter",
        symbol: "H/d",
        default: None,
        integer: false,
        allowed: "a finite value >= 3 (spanwise extent in particle diameters)",
        check: side,
        in_id_at_default: true,
    },
    ParamDef {
        name: "volume_fraction",
        symbol: "phi",
        default: None,
        integer: false,
        allowed: "0 < phi < pi/6 (and placeable in the box)",
        check: fraction,
        in_id_at_default: false,
    },
    ParamDef {
        name: "particles",
        symbol: "N",
        default: None,
        integer: true,
        allowed: "a whole number >= 1 (default: from volume_fraction)",
        check: count,
        in_id_at_default: true,
    },
    ParamDef {
        name: "restitution",
        symbol: "e",
        default: Some(0.7),
        integer: false,
        allowed: "[0, 1]",
        check: unit,
        in_id_at_default: true,
    },
    ParamDef {
        name: "roughness",
        symbol: "beta",
        default: Some(0.1),
        integer: false,
        allowed: "[-1, 1]",
        check: signed_unit,
        in_id_at_default: true,
    },
    ParamDef {
        name: "wall_restitution",
        symbol: "e_w",
        default: Some(0.99),
        integer: false,
        allowed: "[0, 1]",
        check: unit,
        in_id_at_default: true,
    },
    ParamDef {
        name: "wall_roughness",
        symbol: "beta_w",
        default: Some(0.99),
        integer: false,
        allowed: "[-1, 1]",
        check: signed_unit,
        in_id_at_default: true,
    },
    ParamDef {
        name: "inertia_factor",
        symbol: "K",
        default: Some(0.4),
        integer: false,
        allowed: "(0, 1] (2/5 solid sphere, 2/3 thin shell)",
        check: inertia,
        in_id_at_default: true,
    },
    ParamDef {
        name: "gravity",
        symbol: "g",
        default: Some(1.0),
        integer: false,
        allowed: "a finite value >= 0",
        check: non_negative,
        in_id_at_default: true,
    },
    ParamDef {
        name: "tc",
        symbol: "t_c",
        default: Some(EdmdParams::DEFAULT_TC),
        integer: false,
        allowed: "a finite time >= 0 (0 switches the TC model off)",
        check: non_negative,
        in_id_at_default: true,
    },
    ParamDef {
        name: "initial_temperature",
        symbol: "T_0",
        default: Some(0.01),
        integer: false,
        allowed: "a finite value > 0",
        check: finite_positive,
        in_id_at_default: true,
    },
];

/// The definition of a parameter by name.
pub fn param_def(name: &str) -> Option<&'static ParamDef> {
    PARAMS.iter().find(|d| d.name == name)
}

/// The names of all parameters (for error messages).
pub fn param_names() -> String {
    PARAMS.iter().map(|d| d.name).collect::<Vec<_>>().join(", ")
}

/// Run length and snapshot cadence of a job, in collisions per particle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSettings {
    /// run length in collisions per particle
    pub collisions_per_particle: f64,
    /// a snapshot (analysis record) every this many collisions per particle
    pub snapshot_interval: f64,
    /// write a checkpoint every this many snapshots (a deterministic cadence of simulated
    /// progress; it does not change results, so it is not part of the job id)
    #[serde(default = "default_checkpoint_every")]
    pub checkpoint_every: u32,
}

fn default_checkpoint_every() -> u32 {
    1
}

impl RunSettings {
    /// Number of snapshots after the initial one: ceil(run length / interval).
    pub fn snapshot_count(&self) -> u32 {
        (self.collisions_per_particle / self.snapshot_interval).ceil() as u32
    }

    /// Collisions per particle of snapshot k (k = 0 is the initial state).
    pub fn snapshot_target(&self, k: u32) -> f64 {
        (k as f64 * self.snapshot_interval).min(self.collisions_per_particle)
    }
}

/// Everything that defines one job, resolved (defaults filled in, N computed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobParams {
    /// the engine name ("edmd")
    pub engine: String,
    /// every parameter of [`PARAMS`] by name (volume_fraction is the one N gives)
    pub values: BTreeMap<String, f64>,
    /// seed of the engine's RNG
    pub seed: u64,
    /// run length and snapshots
    pub run: RunSettings,
    /// analysis settings
    pub analysis: AnalysisSettings,
}

/// A job's id: 16 hex digits of the SHA-256 of its canonical parameters.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct JobId(pub String);

impl fmt::Display for JobId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl JobParams {
    /// Value of a parameter (every parameter is present after resolution).
    pub fn get(&self, name: &str) -> f64 {
        self.values.get(name).copied().unwrap_or(f64::NAN)
    }

    /// Number of spheres N.
    pub fn particles(&self) -> usize {
        self.get("particles") as usize
    }

    /// The channel box: L = (L/W) W, W, H, walls at y = 0, W.
    pub fn geometry(&self) -> BoxGeometry {
        let w = self.get("width_over_diameter");
        BoxGeometry {
            length: self.get("length_over_width") * w,
            width: w,
            height: self.get("height_over_diameter"),
            walls: true,
        }
    }

    /// The engine spec of this job.
    pub fn engine_spec(&self) -> EngineSpec {
        let mut p = EdmdParams::channel(1.0, 1.0, 1.0, 0.0, self.seed);
        p.geometry = self.geometry();
        p.particles = self.particles();
        p.restitution = self.get("restitution");
        p.roughness = self.get("roughness");
        p.wall_restitution = self.get("wall_restitution");
        p.wall_roughness = self.get("wall_roughness");
        p.inertia_factor = self.get("inertia_factor");
        p.gravity = self.get("gravity");
        p.tc = self.get("tc");
        p.initial_temperature = self.get("initial_temperature");
        EngineSpec::Edmd(p)
    }

    /// Estimated work in collisions: N x collisions per particle / 2 (the sort key of the pool).
    pub fn estimated_work(&self) -> f64 {
        self.particles() as f64 * self.run.collisions_per_particle / 2.0
    }

    /// The canonical text that the id hashes (see the module docs).
    pub fn canonical(&self) -> String {
        canonical_with(PARAMS, self)
    }

    /// The job id.
    pub fn id(&self) -> JobId {
        id_of_canonical(&self.canonical())
    }
}

/// Resolve N from phi (when N is not given) and phi from N: N = round(phi L W H / (pi/6)).
pub fn resolve_particles(values: &mut BTreeMap<String, f64>) {
    let w = values["width_over_diameter"];
    let geometry = BoxGeometry {
        length: values["length_over_width"] * w,
        width: w,
        height: values["height_over_diameter"],
        walls: true,
    };
    if !values.contains_key("particles") {
        let phi = values.get("volume_fraction").copied().unwrap_or(f64::NAN);
        values.insert(
            "particles".into(),
            particles_for_volume_fraction(&geometry, phi) as f64,
        );
    }
    let n = values["particles"];
    values.insert(
        "volume_fraction".into(),
        n * std::f64::consts::PI / 6.0 / geometry.volume(),
    );
}

/// How many spheres fit on a lattice of spacing d in the channel (what the engine's lattice
/// placement can do at best): floor(L) x (floor(W - 1) + 1) x floor(H).
pub fn lattice_capacity(geometry: &BoxGeometry) -> f64 {
    geometry.length.floor() * ((geometry.width - 1.0).floor() + 1.0) * geometry.height.floor()
}

/// The canonical form over a given parameter table (the table is an argument so that tests can
/// show that extending it leaves ids unchanged).
pub fn canonical_with(table: &[ParamDef], job: &JobParams) -> String {
    let mut params = BTreeMap::new();
    for def in table {
        if def.name == "volume_fraction" {
            continue; // derived from N and the box: N is the physical input
        }
        let Some(&v) = job.values.get(def.name) else {
            continue;
        };
        if def.in_id_at_default || def.default != Some(v) {
            params.insert(def.name.to_string(), number(v));
        }
    }
    let analysis_default = serde_json::to_value(AnalysisSettings::default()).unwrap_or(Value::Null);
    let analysis_now = serde_json::to_value(&job.analysis).unwrap_or(Value::Null);
    let mut analysis = BTreeMap::new();
    if let Value::Object(now) = analysis_now {
        for (k, v) in now {
            if analysis_default.get(&k) != Some(&v) {
                analysis.insert(k, v);
            }
        }
    }
    let mut run = BTreeMap::new();
    run.insert(
        "collisions_per_particle".to_string(),
        number(job.run.collisions_per_particle),
    );
    run.insert(
        "snapshot_interval".to_string(),
        number(job.run.snapshot_interval),
    );
    let mut top = BTreeMap::new();
    top.insert(
        "analysis".to_string(),
        Value::Object(analysis.into_iter().collect()),
    );
    top.insert("engine".to_string(), Value::String(job.engine.clone()));
    top.insert(
        "params".to_string(),
        Value::Object(params.into_iter().collect()),
    );
    top.insert("run".to_string(), Value::Object(run.into_iter().collect()));
    top.insert("seed".to_string(), Value::from(job.seed));
    let mut out = String::new();
    write_canonical(&Value::Object(top.into_iter().collect()), &mut out);
    out
}

/// The id of a canonical text: the first 16 hex digits of its SHA-256.
pub fn id_of_canonical(canonical: &str) -> JobId {
    let digest = Sha256::digest(canonical.as_bytes());
    JobId(
        digest[..8]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<String>(),
    )
}

fn number(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// Compact JSON with object keys sorted, whatever map type serde_json was built with.
fn write_canonical(v: &Value, out: &mut String) {
    match v {
        Value::Object(map) => {
            let sorted: BTreeMap<&String, &Value> = map.iter().collect();
            out.push('{');
            for (i, (k, v)) in sorted.into_iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String(k.clone()).to_string());
                out.push(':');
                write_canonical(v, out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                write_canonical(item, out);
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}

//! The analyses a job can run, one per kind of snapshot content, behind one interface: settings
//! parsed from a sweep's `analysis` section (with defaults), a compact record per snapshot (what
//! checkpoints keep), and the analysis of a job's records (label, summary row, tables). An
//! engine's declaration names its kind; a new kind of analysis is added here.

use super::columns::{Cell, ColumnDef, ColumnKind, TableDef};
use super::dense::{DenseAnalysis, DenseRecord, DenseSettings};
use super::lattice::{LatticeAnalysis, LatticeRecord, LatticeSettings};
use super::rarefied::{RarefiedAnalysis, RarefiedRecord, RarefiedSettings};
use super::{AnalysisSettings, JobAnalysis, SnapshotRecord};
use crate::engine::Snapshot;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// Which analysis an engine's snapshots feed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnalysisKind {
    /// density-wave structure of a particle channel (thesis ch. 3 and 5): fields, spectra,
    /// families against shot noise, labels, profiles, steady state
    Structure,
    /// density waves of a lattice gas in a pipe (Peng & Herrmann 1994): bin densities over
    /// time, the power spectrum of a region's count, 1/f^alpha, the wave peak
    Lattice,
    /// a rarefied channel gas sampled by DSMC (Gupta 2017): time-averaged cross-channel
    /// profiles, flow rate, slips, normal-stress differences, balances, mixture segregation,
    /// each with a block-average error over the detected steady window
    Rarefied,
    /// a dense frictional flow by DEM (Debnath, Rao & Kumaran 2022): for now the mean
    /// centre-of-mass velocity and the wall-force balance with block errors, and a label
    Dense,
}

/// A kind's settings, ready to record and analyse.
#[derive(Clone, Debug, PartialEq)]
pub enum Analyser {
    Structure(AnalysisSettings),
    Lattice(LatticeSettings),
    Rarefied(RarefiedSettings),
    Dense(DenseSettings),
}

/// What one snapshot contributes, by kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Record {
    Structure(SnapshotRecord),
    Lattice(LatticeRecord),
    Rarefied(Box<RarefiedRecord>),
    Dense(Box<DenseRecord>),
}

/// A job's analysis, by kind (untagged in `result.ron`: results written before there were
/// kinds read as [`Analysis::Structure`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Analysis {
    Structure(JobAnalysis),
    Lattice(LatticeAnalysis),
    Rarefied(RarefiedAnalysis),
    Dense(DenseAnalysis),
}

impl AnalysisKind {
    /// Version of the analysis: bump it when a change alters results of the same records
    /// (results of older versions are flagged as outdated). Structure: 1 until the label
    /// probabilities and the balances, 2 since.
    pub fn version(self) -> u32 {
        match self {
            AnalysisKind::Structure => 2,
            AnalysisKind::Lattice => 1,
            AnalysisKind::Rarefied => 1,
            AnalysisKind::Dense => 1,
        }
    }

    /// Whether a run of this kind can stop once steady (`run.until_steady`).
    pub fn supports_until_steady(self) -> bool {
        matches!(self, AnalysisKind::Structure)
    }

    /// Parse and check the settings of a sweep's `analysis` section (missing keys take their
    /// defaults; an empty or null section is all defaults).
    pub fn analyser(self, given: &Value) -> Result<Analyser, String> {
        let given = match given {
            Value::Null => Value::Object(Map::new()),
            other => other.clone(),
        };
        match self {
            AnalysisKind::Structure => {
                let s: AnalysisSettings = serde_json::from_value(given).map_err(|e| {
                    format!("{e}; allowed keys: grid, profile_bins, cell_particles, min_steady_snapshots")
                })?;
                s.validate()?;
                Ok(Analyser::Structure(s))
            }
            AnalysisKind::Lattice => {
                let s: LatticeSettings = serde_json::from_value(given).map_err(|e| {
                    format!("{e}; allowed keys: bin_length, region_bin, segments, fit_min, fit_max, false_alarm, transient_fraction, spacetime_rows")
                })?;
                s.validate()?;
                Ok(Analyser::Lattice(s))
            }
            AnalysisKind::Rarefied => {
                let s: RarefiedSettings = serde_json::from_value(given).map_err(|e| {
                    format!("{e}; allowed keys: blocks, min_steady_records, steady_tolerance")
                })?;
                s.validate()?;
                Ok(Analyser::Rarefied(s))
            }
            AnalysisKind::Dense => {
                let s: DenseSettings = serde_json::from_value(given)
                    .map_err(|e| format!("{e}; allowed keys: blocks"))?;
                s.validate()?;
                Ok(Analyser::Dense(s))
            }
        }
    }

    /// The default settings as JSON (the id holds only settings that differ from these).
    pub fn default_settings(self) -> Value {
        match self {
            AnalysisKind::Structure => {
                serde_json::to_value(AnalysisSettings::default()).expect("settings serialise")
            }
            AnalysisKind::Lattice => {
                serde_json::to_value(LatticeSettings::default()).expect("settings serialise")
            }
            AnalysisKind::Rarefied => {
                serde_json::to_value(RarefiedSettings::default()).expect("settings serialise")
            }
            AnalysisKind::Dense => {
                serde_json::to_value(DenseSettings::default()).expect("settings serialise")
            }
        }
    }

    /// The summary columns of `jobs.parquet`, in order, with their types: the fields of the
    /// kind's summary (fixed, whatever jobs are done). Integers are i64, NaN-able numbers f64,
    /// lists are lists of the structs [`super::modes::list_column`] declares.
    pub fn summary_columns(self) -> Vec<(String, ColumnKind)> {
        let empty = match self {
            AnalysisKind::Structure => {
                serde_json::to_value(super::report::empty_summary()).expect("summary serialises")
            }
            AnalysisKind::Lattice => serde_json::to_value(
                super::lattice::analyse(&[], &LatticeSettings::default()).summary,
            )
            .expect("summary serialises"),
            AnalysisKind::Rarefied => Value::Object(rarefied_summary(
                &super::rarefied::RarefiedSummary::default(),
            )),
            AnalysisKind::Dense => serde_json::to_value(super::dense::DenseSummary::default())
                .expect("summary serialises"),
        };
        let Value::Object(map) = empty else {
            return Vec::new();
        };
        map.into_iter()
            .map(|(name, v)| {
                let kind = column_kind(&name, &v);
                (name, kind)
            })
            .collect()
    }

    /// The per-job row tables of this kind (each written with a `job_id` column first).
    pub fn tables(self) -> &'static [TableDef] {
        match self {
            AnalysisKind::Structure => STRUCTURE_TABLES,
            AnalysisKind::Lattice => LATTICE_TABLES,
            AnalysisKind::Rarefied => RAREFIED_TABLES,
            AnalysisKind::Dense => &[],
        }
    }
}

/// The column type of a summary field from its value in an empty summary (a float that is NaN
/// there serialises as null).
fn column_kind(name: &str, v: &Value) -> ColumnKind {
    match v {
        Value::Bool(_) => ColumnKind::Bool,
        Value::String(_) => ColumnKind::Str,
        Value::Number(n) if n.is_u64() || n.is_i64() => ColumnKind::I64,
        Value::Array(_) => ColumnKind::List(super::modes::list_column(name).unwrap_or_else(|| {
            panic!("summary field `{name}` is a list: declare its struct fields in analysis::modes::list_column")
        })),
        _ => ColumnKind::F64,
    }
}

/// The summary row of a DSMC job: the label (`steady` or `not-steady`), the steady rule's
/// reason, then the numeric columns in [`RarefiedSummary::columns`] order (`steady` as a
/// boolean, the window's counts as integers; NaN, for measures that do not apply, as null).
///
/// [`RarefiedSummary::columns`]: super::rarefied::RarefiedSummary::columns
fn rarefied_summary(s: &super::rarefied::RarefiedSummary) -> Map<String, Value> {
    let mut m = Map::new();
    let label = if s.steady { "steady" } else { "not-steady" };
    m.insert("label".into(), Value::String(label.into()));
    m.insert("steady_reason".into(), Value::String(s.reason.clone()));
    for (name, value) in s.columns() {
        let v = match name.as_str() {
            "steady" => Value::Bool(s.steady),
            "window_start_step" | "window_end_step" | "window_records" | "blocks" => {
                Value::from(value as u64)
            }
            _ => serde_json::Number::from_f64(value)
                .map(Value::Number)
                .unwrap_or(Value::Null),
        };
        m.insert(name, v);
    }
    m
}

const LATTICE_TABLES: &[TableDef] = &[
    TableDef {
        name: "spectra",
        columns: &[
            ColumnDef {
                name: "frequency",
                kind: ColumnKind::F64,
                doc: "f in the seed's unit (327680 / period in steps)",
            },
            ColumnDef {
                name: "period",
                kind: ColumnKind::F64,
                doc: "period in time steps",
            },
            ColumnDef {
                name: "power",
                kind: ColumnKind::F64,
                doc: "segment-averaged power of the region's particle count",
            },
            ColumnDef {
                name: "fitted",
                kind: ColumnKind::Bool,
                doc: "in the 1/f^alpha fit (inside the band, not part of the sharp peak)",
            },
        ],
    },
    TableDef {
        name: "spacetime",
        columns: &[
            ColumnDef {
                name: "step",
                kind: ColumnKind::I64,
                doc: "time step of the record",
            },
            ColumnDef {
                name: "bin",
                kind: ColumnKind::I64,
                doc: "bin along the pipe",
            },
            ColumnDef {
                name: "count",
                kind: ColumnKind::I64,
                doc: "particles in the bin",
            },
        ],
    },
];

const STRUCTURE_TABLES: &[TableDef] = &[
    TableDef {
        name: "spectra",
        columns: &[
            ColumnDef {
                name: "plane",
                kind: ColumnKind::Str,
                doc: "xy, xz or yz",
            },
            ColumnDef {
                name: "k1",
                kind: ColumnKind::I64,
                doc: "wave number along the plane's first axis",
            },
            ColumnDef {
                name: "k2",
                kind: ColumnKind::I64,
                doc: "wave number along the plane's second axis",
            },
            ColumnDef {
                name: "power",
                kind: ColumnKind::F64,
                doc: "folded power, window average",
            },
        ],
    },
    TableDef {
        name: "profiles",
        columns: &[
            ColumnDef {
                name: "quantity",
                kind: ColumnKind::Str,
                doc: "phi, u_x, omega_z, T or theta",
            },
            ColumnDef {
                name: "bin",
                kind: ColumnKind::I64,
                doc: "bin across the channel",
            },
            ColumnDef {
                name: "y",
                kind: ColumnKind::F64,
                doc: "bin centre, in d",
            },
            ColumnDef {
                name: "value",
                kind: ColumnKind::F64,
                doc: "window average",
            },
        ],
    },
    TableDef {
        name: "energy",
        columns: &[
            ColumnDef {
                name: "collisions_per_particle",
                kind: ColumnKind::F64,
                doc: "clock of the snapshot",
            },
            ColumnDef {
                name: "time",
                kind: ColumnKind::F64,
                doc: "simulated time of the snapshot",
            },
            ColumnDef {
                name: "translational_energy",
                kind: ColumnKind::F64,
                doc: "per particle",
            },
            ColumnDef {
                name: "rotational_energy",
                kind: ColumnKind::F64,
                doc: "per particle",
            },
        ],
    },
];

const RAREFIED_TABLES: &[TableDef] = &[TableDef {
    name: "profiles",
    columns: RAREFIED_PROFILE_COLUMNS,
}];

/// The columns of a DSMC job's profiles (one row per layer cell; normalisation as in the
/// thesis: y / W, rho / rho_avg, u / u_c, T / T_w, stresses and heat flux in their reduced
/// units; `_error`: block-average standard error).
const RAREFIED_PROFILE_COLUMNS: &[ColumnDef] = &[
    f64_column("y", "y / W about the centre, in (-1/2, 1/2)"),
    f64_column("density", "rho / rho_avg"),
    f64_column("density_error", "its standard error"),
    f64_column("velocity", "u_x / u_c (mass-weighted)"),
    f64_column("velocity_error", "its standard error"),
    f64_column(
        "velocity_hat",
        "u_x / sqrt(a W) (athermal walls, thesis ch. 4)",
    ),
    f64_column("temperature", "T / T_w"),
    f64_column("temperature_error", "its standard error"),
    f64_column("temperature_over_centre", "T / T(0)"),
    f64_column("pressure", "p / P_c"),
    f64_column("pxx", "P_xx / P_c"),
    f64_column("pyy", "P_yy / P_c"),
    f64_column("pzz", "P_zz / P_c"),
    f64_column("pxy", "P_xy / P_c (shear stress)"),
    f64_column("pxy_error", "its standard error"),
    f64_column("qx", "q_x / q_c"),
    f64_column("qx_error", "its standard error"),
    f64_column("qy", "q_y / q_c"),
    f64_column("qy_error", "its standard error"),
    f64_column("n1", "first normal-stress difference N1 (eq. 3.29)"),
    f64_column("n2", "second normal-stress difference N2 (eq. 3.30)"),
    f64_column("local_knudsen", "local Knudsen number Kn_y (eq. 3.25)"),
    f64_column("species1_density", "n_1 / n_avg"),
    f64_column("species2_density", "n_2 / n_avg (null when monodisperse)"),
    f64_column("species1_temperature", "T_1 / T_w (eq. 5.9)"),
    f64_column("species2_temperature", "T_2 / T_w (eq. 5.10)"),
    f64_column("species1_velocity", "u_x,1 / u_c"),
    f64_column("species2_velocity", "u_x,2 / u_c"),
];

const fn f64_column(name: &'static str, doc: &'static str) -> ColumnDef {
    ColumnDef {
        name,
        kind: ColumnKind::F64,
        doc,
    }
}

impl Analyser {
    /// The settings as JSON (all keys, resolved).
    pub fn settings(&self) -> Value {
        match self {
            Analyser::Structure(s) => serde_json::to_value(s).expect("settings serialise"),
            Analyser::Lattice(s) => serde_json::to_value(s).expect("settings serialise"),
            Analyser::Rarefied(s) => serde_json::to_value(s).expect("settings serialise"),
            Analyser::Dense(s) => serde_json::to_value(s).expect("settings serialise"),
        }
    }

    /// The record of one snapshot.
    pub fn record(&self, snapshot: &Snapshot) -> Result<Record, String> {
        match self {
            Analyser::Structure(s) => {
                if snapshot.particles().is_none() {
                    return Err("the structure analysis needs particles, and this engine's snapshots carry none".into());
                }
                Ok(Record::Structure(super::record_snapshot(snapshot, s)))
            }
            Analyser::Lattice(s) => {
                let lattice = snapshot.lattice().ok_or(
                    "the lattice analysis needs a lattice, and this engine's snapshots carry none",
                )?;
                Ok(Record::Lattice(super::lattice::record_of(
                    snapshot.progress.steps,
                    lattice,
                    s,
                )))
            }
            Analyser::Rarefied(_) => {
                let sample = snapshot.sampled().ok_or(
                    "the rarefied analysis needs sampled moments, and this engine's snapshots carry none",
                )?;
                Ok(Record::Rarefied(Box::new(sample.clone())))
            }
            Analyser::Dense(_) => {
                let sample = snapshot.dem().ok_or(
                    "the dense analysis needs DEM bin sums, and this engine's snapshots carry none",
                )?;
                Ok(Record::Dense(Box::new(sample.record.clone())))
            }
        }
    }

    /// Analyse a job's records (in order of simulated time); records of another kind are
    /// ignored. Err: the records cannot be analysed (e.g. none holds a sample).
    pub fn analyse(&self, records: &[Record]) -> Result<Analysis, String> {
        match self {
            Analyser::Structure(s) => {
                let records: Vec<SnapshotRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Structure(r) => Some(r.clone()),
                        _ => None,
                    })
                    .collect();
                Ok(Analysis::Structure(super::analyse_job(&records, s)))
            }
            Analyser::Lattice(s) => {
                let records: Vec<LatticeRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Lattice(r) => Some(r.clone()),
                        _ => None,
                    })
                    .collect();
                Ok(Analysis::Lattice(super::lattice::analyse(&records, s)))
            }
            Analyser::Rarefied(s) => {
                let records: Vec<RarefiedRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Rarefied(r) => Some((**r).clone()),
                        _ => None,
                    })
                    .collect();
                super::rarefied::analyse(&records, s).map(Analysis::Rarefied)
            }
            Analyser::Dense(s) => {
                let records: Vec<DenseRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Dense(r) => Some((**r).clone()),
                        _ => None,
                    })
                    .collect();
                Ok(Analysis::Dense(super::dense::analyse(&records, s)))
            }
        }
    }
}

/// What a kind keeps between the checks of run-until-steady.
#[derive(Clone, Debug, Default)]
pub struct StopCheck {
    structure: super::SteadyCheck,
}

impl Analyser {
    /// Run-until-steady's question after a snapshot, from the records alone: why the run may
    /// stop (steady over at least `window` on `clock` with a stable label), or None.
    pub fn steady_over(
        &self,
        records: &[Record],
        clock: crate::engine::Clock,
        window: f64,
        check: &mut StopCheck,
    ) -> Option<String> {
        match self {
            Analyser::Structure(s) => {
                let records: Vec<SnapshotRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Structure(r) => Some(r.clone()),
                        _ => None,
                    })
                    .collect();
                super::steady_over(&records, s, clock, window, &mut check.structure)
            }
            // validation refuses `until_steady` for kinds without a steady rule
            Analyser::Lattice(_) | Analyser::Rarefied(_) | Analyser::Dense(_) => None,
        }
    }
}

impl Record {
    /// Simulated time at the snapshot.
    pub fn time(&self) -> f64 {
        match self {
            Record::Structure(r) => r.time,
            Record::Lattice(r) => r.step as f64,
            Record::Rarefied(r) => r.sums.end_step as f64,
            Record::Dense(r) => r.sums.end_step as f64 * r.constants.time_step,
        }
    }
}

impl Analysis {
    /// The structure label and the S-wave humps (0 where there are none).
    pub fn label(&self) -> (&str, u32) {
        match self {
            Analysis::Structure(a) => (&a.summary.label, a.summary.humps),
            Analysis::Lattice(a) => (&a.summary.label, 0),
            Analysis::Rarefied(a) => (
                if a.summary.steady {
                    "steady"
                } else {
                    "not-steady"
                },
                0,
            ),
            Analysis::Dense(a) => (&a.dense_summary.label, 0),
        }
    }

    /// Write the analysis' per-job figures into a job directory (`<name>.png`); the names
    /// written.
    pub fn write_figures(&self, dir: &std::path::Path) -> anyhow::Result<Vec<String>> {
        match self {
            Analysis::Structure(_) | Analysis::Rarefied(_) | Analysis::Dense(_) => Ok(Vec::new()),
            Analysis::Lattice(a) => {
                super::lattice::plot_spacetime(a, &dir.join("spacetime.png"))?;
                Ok(vec!["spacetime.png".into()])
            }
        }
    }

    /// The kind this analysis is of.
    pub fn kind(&self) -> AnalysisKind {
        match self {
            Analysis::Structure(_) => AnalysisKind::Structure,
            Analysis::Lattice(_) => AnalysisKind::Lattice,
            Analysis::Rarefied(_) => AnalysisKind::Rarefied,
            Analysis::Dense(_) => AnalysisKind::Dense,
        }
    }

    /// The summary row: field name -> value (columns of `jobs.parquet`).
    pub fn summary(&self) -> Map<String, Value> {
        let v = match self {
            Analysis::Structure(a) => serde_json::to_value(&a.summary),
            Analysis::Lattice(a) => serde_json::to_value(&a.summary),
            Analysis::Rarefied(a) => return rarefied_summary(&a.summary),
            Analysis::Dense(a) => serde_json::to_value(&a.dense_summary),
        };
        match v {
            Ok(Value::Object(m)) => m,
            _ => Map::new(),
        }
    }

    /// The rows of one of the kind's tables (cells in the declared column order).
    pub fn rows(&self, table: &str) -> Vec<Vec<Cell>> {
        match self {
            Analysis::Structure(a) => match table {
                "spectra" => a
                    .spectra
                    .iter()
                    .map(|r| {
                        vec![
                            r.plane.as_str().into(),
                            r.k1.into(),
                            r.k2.into(),
                            r.power.into(),
                        ]
                    })
                    .collect(),
                "profiles" => a
                    .profiles
                    .iter()
                    .map(|r| {
                        vec![
                            r.quantity.as_str().into(),
                            r.bin.into(),
                            r.y.into(),
                            r.value.into(),
                        ]
                    })
                    .collect(),
                "energy" => a
                    .energy
                    .iter()
                    .map(|r| {
                        vec![
                            r.collisions_per_particle.into(),
                            r.time.into(),
                            r.translational.into(),
                            r.rotational.into(),
                        ]
                    })
                    .collect(),
                _ => Vec::new(),
            },
            Analysis::Lattice(a) => match table {
                "spectra" => a
                    .spectrum
                    .iter()
                    .map(|r| {
                        vec![
                            r.frequency.into(),
                            r.period.into(),
                            r.power.into(),
                            Cell::Bool(r.fitted),
                        ]
                    })
                    .collect(),
                "spacetime" => a
                    .spacetime
                    .iter()
                    .map(|r| vec![r.step.into(), r.bin.into(), r.count.into()])
                    .collect(),
                _ => Vec::new(),
            },
            Analysis::Rarefied(a) => match table {
                "profiles" => a
                    .profiles
                    .iter()
                    .map(|r| r.values().into_iter().map(Cell::from).collect())
                    .collect(),
                _ => Vec::new(),
            },
            Analysis::Dense(_) => Vec::new(),
        }
    }
}

//! The analyses a job can run, one per kind of snapshot content, behind one interface: settings
//! parsed from a sweep's `analysis` section (with defaults), a compact record per snapshot (what
//! checkpoints keep), and the analysis of a job's records (label, summary row, tables). An
//! engine's declaration names its kind; a new kind of analysis is added here.

use super::columns::{Cell, ColumnDef, ColumnKind, TableDef};
use super::dense::{DenseAnalysis, DenseRecord, DenseSettings};
use super::lattice::{LatticeAnalysis, LatticeRecord, LatticeSettings};
use super::rarefied::{RarefiedAnalysis, RarefiedRecord, RarefiedSettings};
use super::statistics::{StatisticsPlan, StatisticsRecord};
use super::{AnalysisSettings, JobAnalysis, SnapshotRecord};
use crate::engine::{FreePathTally, Snapshot};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// Why an analysis could not be set up, fed or run, by kind (a job decides by it: bad settings
/// are the sweep's input, the others fail the job). The messages are the analysis' own.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// the sweep's `analysis` section does not suit the kind (with the allowed keys or range)
    #[error("{0}")]
    Settings(String),
    /// the snapshot carries nothing this analysis reads (an engine paired with another kind)
    #[error("{0}")]
    Content(&'static str),
    /// the records cannot be analysed (e.g. none holds a sample)
    #[error("{0}")]
    Records(String),
}

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
    /// a dense frictional flow by DEM (Debnath, Rao & Kumaran 2022): time-averaged profiles
    /// across the channel with block errors, slip and shear-layer numbers, the exact
    /// wall-force balance, zones, the centre-of-mass series and a regime label
    Dense,
}

/// A kind's settings, ready to record and analyse.
#[derive(Clone, Debug, PartialEq)]
pub enum Analyser {
    Structure(AnalysisSettings),
    Lattice(LatticeSettings),
    Rarefied(RarefiedSettings),
    /// the structure analysis and the thesis' statistics (runs with `run.statistics`)
    StructureWithStatistics(AnalysisSettings, Box<StatisticsPlan>),
    Dense(DenseSettings),
}

/// What one snapshot contributes, by kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Record {
    Structure(SnapshotRecord),
    Lattice(LatticeRecord),
    Rarefied(Box<RarefiedRecord>),
    /// a structure record with the statistics of the same snapshot
    Statistics(Box<StatisticsSnapshot>),
    Dense(Box<DenseRecord>),
}

/// The structure record and the statistics record of one snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatisticsSnapshot {
    pub structure: SnapshotRecord,
    pub statistics: StatisticsRecord,
}

/// A job's analysis, by kind (untagged in `result.ron`: results written before there were
/// kinds read as [`Analysis::Structure`]).
// (a handful of these exist at a time, one per job being written or read: their size does not
// matter, and boxing would only add indirection to every match)
#[allow(clippy::large_enum_variant)]
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
    /// probabilities and the balances, 2 since, 3 since an S-wave is recognised by its glide
    /// symmetry (humps = the fundamental k_x, its even harmonics along x not a slug) and labels
    /// show the 3D mark. Dense: 3 since Q6 (profile and plug), 4 since
    /// the plug is found at the change of slope in phi (zones.rs), 5 since the summary states
    /// the wall's e_n (`wall_restitution`: which wall damping made the records).
    pub fn version(self) -> u32 {
        match self {
            AnalysisKind::Structure => 3,
            AnalysisKind::Lattice => 1,
            AnalysisKind::Rarefied => 1,
            AnalysisKind::Dense => 5,
        }
    }

    /// Whether runs of this kind can gather the thesis' statistics (`run.statistics`): the
    /// structure analysis, whose snapshots carry particles with velocities.
    pub fn supports_statistics(self) -> bool {
        matches!(self, AnalysisKind::Structure)
    }

    /// Whether a run of this kind can stop once steady (`run.until_steady`).
    pub fn supports_until_steady(self) -> bool {
        matches!(self, AnalysisKind::Structure | AnalysisKind::Dense)
    }

    /// Parse and check the settings of a sweep's `analysis` section (missing keys take their
    /// defaults; an empty or null section is all defaults).
    pub fn analyser(self, given: &Value) -> Result<Analyser, AnalysisError> {
        let given = match given {
            Value::Null => Value::Object(Map::new()),
            other => other.clone(),
        };
        match self {
            AnalysisKind::Structure => {
                let s: AnalysisSettings = serde_json::from_value(given).map_err(|e| {
                    AnalysisError::Settings(format!("{e}; allowed keys: grid, profile_bins, cell_particles, min_steady_snapshots"))
                })?;
                s.validate().map_err(AnalysisError::Settings)?;
                Ok(Analyser::Structure(s))
            }
            AnalysisKind::Lattice => {
                let s: LatticeSettings = serde_json::from_value(given).map_err(|e| {
                    AnalysisError::Settings(format!("{e}; allowed keys: bin_length, region_bin, segments, fit_min, fit_max, false_alarm, transient_fraction, spacetime_rows, spacetime_periods"))
                })?;
                s.validate().map_err(AnalysisError::Settings)?;
                Ok(Analyser::Lattice(s))
            }
            AnalysisKind::Rarefied => {
                let s: RarefiedSettings = serde_json::from_value(given).map_err(|e| {
                    AnalysisError::Settings(format!(
                        "{e}; allowed keys: blocks, min_steady_records, steady_tolerance"
                    ))
                })?;
                s.validate().map_err(AnalysisError::Settings)?;
                Ok(Analyser::Rarefied(s))
            }
            AnalysisKind::Dense => {
                let s: DenseSettings = serde_json::from_value(given).map_err(|e| {
                    AnalysisError::Settings(format!(
                        "{e}; allowed keys: blocks, window_fraction, jam_froude, balance_tolerance"
                    ))
                })?;
                s.validate().map_err(AnalysisError::Settings)?;
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

    /// The headline summary columns of this kind, which the report's jobs table shows:
    /// (column, heading).
    pub fn key_columns(self) -> &'static [(&'static str, &'static str)] {
        match self {
            AnalysisKind::Structure => &[
                ("label_probability", "p(label)"),
                ("three_dimensional", "3D"),
                ("window_start", "window from"),
                ("window_end", "window to"),
                ("mean_translational_energy", "E_tr/N"),
                ("mean_rotational_energy", "E_rot/N"),
                ("slip_velocity", "u_slip"),
            ],
            AnalysisKind::Lattice => &[
                ("alpha", "alpha"),
                ("alpha_error", "+-"),
                ("peak_frequency", "f_peak"),
                ("wave_velocity", "v_wave"),
                ("peak_ratio", "P/B peak"),
            ],
            AnalysisKind::Rarefied => &[
                ("flow_rate", "flow rate"),
                ("flow_rate_error", "+-"),
                ("centre_temperature", "T_centre"),
                ("slip_velocity", "u_slip"),
                ("momentum_balance", "momentum bal."),
            ],
            AnalysisKind::Dense => &[
                ("com_velocity", "u_cm"),
                ("com_velocity_error", "+-"),
                ("wall_force_balance", "wall force / weight"),
                ("wall_force_balance_error", "+-"),
            ],
        }
    }

    /// The per-job row tables of this kind (each written with a `job_id` column first).
    pub fn tables(self) -> &'static [TableDef] {
        match self {
            AnalysisKind::Structure => STRUCTURE_TABLES,
            AnalysisKind::Lattice => LATTICE_TABLES,
            AnalysisKind::Rarefied => RAREFIED_TABLES,
            AnalysisKind::Dense => DENSE_TABLES,
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
    PROFILES_TABLE,
    EVOLUTION_TABLE,
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

const RAREFIED_TABLES: &[TableDef] = &[PROFILES_TABLE];

const DENSE_TABLES: &[TableDef] = &[PROFILES_TABLE, SERIES_TABLE];

/// The DEM centre-of-mass series, one row per record.
const SERIES_TABLE: TableDef = TableDef {
    name: "series",
    columns: &[
        f64_column("time", "flow time at the end of the record's interval"),
        f64_column(
            "com_velocity",
            "mean u_cm along the flow over the record's samples",
        ),
        f64_column(
            "wall_force_balance",
            "both walls' flow-wise force over M g over the record's steps",
        ),
        f64_column("translational_energy", "mean m v^2 / 2 per particle"),
        f64_column("rotational_energy", "mean I w^2 / 2 per particle"),
        f64_column("coordination_number", "mean contacts per particle"),
        ColumnDef {
            name: "in_window",
            kind: ColumnKind::Bool,
            doc: "the record is in the analysis window",
        },
    ],
};

/// The fields of a milestone's `peaks`.
const PLANE_PEAK_FIELDS: &[ColumnDef] = &[
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
        name: "ratio",
        kind: ColumnKind::F64,
        doc: "power over its shot-noise power",
    },
];

/// The structure at the run's milestones (`run.milestones`), one row per milestone reached.
const EVOLUTION_TABLE: TableDef = TableDef {
    name: "evolution",
    columns: &[
        f64_column("milestone", "the reading asked for, on milestone_clock"),
        ColumnDef {
            name: "milestone_clock",
            kind: ColumnKind::Str,
            doc: "collisions_per_particle or time",
        },
        f64_column(
            "milestone_collisions_per_particle",
            "collisions per particle of the record nearest to the milestone",
        ),
        f64_column("milestone_time", "simulated time of that record"),
        ColumnDef {
            name: "window_snapshots",
            kind: ColumnKind::I64,
            doc: "snapshots in the milestone's window",
        },
        ColumnDef {
            name: "structure",
            kind: ColumnKind::Str,
            doc: "the window's label with its humps and a 3d mark, mixed without a clear majority",
        },
        ColumnDef {
            name: "window_three_dimensional",
            kind: ColumnKind::Bool,
            doc: "structure along z above noise in the window-averaged spectrum",
        },
        ColumnDef {
            name: "candidate",
            kind: ColumnKind::Str,
            doc: "what the families present in most snapshots name",
        },
        f64_column(
            "probability",
            "fraction of the window's snapshots whose own label is the candidate",
        ),
        ColumnDef {
            name: "peaks",
            kind: ColumnKind::List(PLANE_PEAK_FIELDS),
            doc: "the strongest modes of each plane of the window-averaged spectrum",
        },
        f64_column(
            "translational",
            "mean translational energy per particle over the window",
        ),
        f64_column(
            "rotational",
            "mean rotational energy per particle over the window",
        ),
    ],
};

/// Cross-channel profiles of every engine that has them, in one long layout: one row per
/// quantity and bin (quantities and their scaling as each analysis defines them, listed in
/// `results/README.md`).
pub const PROFILES_TABLE: TableDef = TableDef {
    name: "profiles",
    columns: &[
        ColumnDef {
            name: "quantity",
            kind: ColumnKind::Str,
            doc: "the profiled quantity (names per engine in results/README.md)",
        },
        ColumnDef {
            name: "bin",
            kind: ColumnKind::I64,
            doc: "bin across the channel, from the wall at y = 0",
        },
        f64_column(
            "coordinate",
            "bin centre as y / W, from the wall at y = 0 (0) to the wall at y = W (1)",
        ),
        f64_column("value", "window average"),
        f64_column(
            "standard_error",
            "standard error of the window average (block averages) where the analysis estimates one; null otherwise",
        ),
    ],
};

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
            Analyser::Structure(s) | Analyser::StructureWithStatistics(s, _) => {
                serde_json::to_value(s).expect("settings serialise")
            }
            Analyser::Lattice(s) => serde_json::to_value(s).expect("settings serialise"),
            Analyser::Rarefied(s) => serde_json::to_value(s).expect("settings serialise"),
            Analyser::Dense(s) => serde_json::to_value(s).expect("settings serialise"),
        }
    }

    /// The same analysis with the statistics of `plan` (kinds other than the structure
    /// analysis, whose snapshots carry no particles, are returned unchanged).
    pub fn with_statistics(self, plan: StatisticsPlan) -> Analyser {
        match self {
            Analyser::Structure(s) | Analyser::StructureWithStatistics(s, _) => {
                Analyser::StructureWithStatistics(s, Box::new(plan))
            }
            other => other,
        }
    }

    /// The slabs over which the engine should tally free paths (None: no statistics).
    pub fn free_path_slabs(&self) -> Option<usize> {
        match self {
            Analyser::StructureWithStatistics(_, plan) => Some(plan.settings.bins),
            _ => None,
        }
    }

    /// The record of one snapshot (without free paths, as snapshot 1: see
    /// [`Analyser::record_with`]).
    pub fn record(&self, snapshot: &Snapshot) -> Result<Record, AnalysisError> {
        self.record_with(snapshot, 1, None)
    }

    /// The record of snapshot `index` (0: the initial state) with the free paths the engine
    /// handed over after it.
    pub fn record_with(
        &self,
        snapshot: &Snapshot,
        index: u32,
        free_paths: Option<FreePathTally>,
    ) -> Result<Record, AnalysisError> {
        match self {
            Analyser::Structure(s) | Analyser::StructureWithStatistics(s, _) => {
                if snapshot.particles().is_none() {
                    return Err(AnalysisError::Content(
                        "the structure analysis needs particles, and this engine's snapshots carry none",
                    ));
                }
                let structure = super::record_snapshot(snapshot, s);
                Ok(match self {
                    Analyser::StructureWithStatistics(_, plan) => {
                        Record::Statistics(Box::new(StatisticsSnapshot {
                            structure,
                            statistics: plan.record(index, snapshot, free_paths),
                        }))
                    }
                    _ => Record::Structure(structure),
                })
            }
            Analyser::Lattice(s) => {
                let lattice = snapshot.lattice().ok_or(AnalysisError::Content(
                    "the lattice analysis needs a lattice, and this engine's snapshots carry none",
                ))?;
                Ok(Record::Lattice(super::lattice::record_of(
                    snapshot.progress.steps,
                    lattice,
                    s,
                )))
            }
            Analyser::Rarefied(_) => {
                let sample = snapshot.sample::<crate::engine::dsmc::channel::Sample>().ok_or(AnalysisError::Content(
                    "the rarefied analysis needs sampled moments, and this engine's snapshots carry none")
                )?;
                Ok(Record::Rarefied(Box::new(sample.clone())))
            }
            Analyser::Dense(_) => {
                let sample = snapshot.sample::<crate::engine::dem::Sample>().ok_or(AnalysisError::Content(
                    "the dense analysis needs DEM bin sums, and this engine's snapshots carry none")
                )?;
                Ok(Record::Dense(Box::new(sample.record.clone())))
            }
        }
    }

    /// Analyse a job's records (in order of simulated time); records of another kind are
    /// ignored. Err: the records cannot be analysed (e.g. none holds a sample).
    pub fn analyse(&self, records: &[Record]) -> Result<Analysis, AnalysisError> {
        match self {
            Analyser::Structure(s) => {
                let records: Vec<SnapshotRecord> = records
                    .iter()
                    .filter_map(|r| r.structure().cloned())
                    .collect();
                Ok(Analysis::Structure(super::analyse_job(&records, s)))
            }
            Analyser::StructureWithStatistics(s, plan) => {
                let structure: Vec<SnapshotRecord> = records
                    .iter()
                    .filter_map(|r| r.structure().cloned())
                    .collect();
                let mut a = super::analyse_job(&structure, s);
                let with: Vec<super::statistics::WindowRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Statistics(r) => Some(super::statistics::WindowRecord {
                            structure: &r.structure,
                            statistics: &r.statistics,
                        }),
                        _ => None,
                    })
                    .collect();
                let window = (a.summary.window_start, a.summary.window_end);
                a.statistics = Some(Box::new(super::statistics::analyse(
                    &with,
                    plan,
                    window,
                    &a.profiles,
                )));
                Ok(Analysis::Structure(a))
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
                super::rarefied::analyse(&records, s)
                    .map(Analysis::Rarefied)
                    .map_err(AnalysisError::Records)
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
            Analyser::Structure(s) | Analyser::StructureWithStatistics(s, _) => {
                let records: Vec<SnapshotRecord> = records
                    .iter()
                    .filter_map(|r| r.structure().cloned())
                    .collect();
                super::steady_over(&records, s, clock, window, &mut check.structure)
            }
            Analyser::Dense(s) => {
                let records: Vec<DenseRecord> = records
                    .iter()
                    .filter_map(|r| match r {
                        Record::Dense(r) => Some((**r).clone()),
                        _ => None,
                    })
                    .collect();
                // the window in flow time (a run on the steps clock gives steps)
                let span = match (clock, records.first()) {
                    (crate::engine::Clock::Steps, Some(r)) => window * r.constants.time_step,
                    _ => window,
                };
                super::dense::stop_reason(&records, s, span)
            }
            // validation refuses `until_steady` for kinds without a steady rule
            Analyser::Lattice(_) | Analyser::Rarefied(_) => None,
        }
    }
}

impl Record {
    /// The structure record (of structure and statistics records), else None.
    pub fn structure(&self) -> Option<&SnapshotRecord> {
        match self {
            Record::Structure(r) => Some(r),
            Record::Statistics(r) => Some(&r.structure),
            _ => None,
        }
    }

    /// Simulated time at the snapshot.
    pub fn time(&self) -> f64 {
        match self {
            Record::Structure(r) => r.time,
            Record::Statistics(r) => r.structure.time,
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

    /// The label as a reader sees it: with its humps (`s-wave(2)`) and, for a structure that
    /// varies along z, the ` 3d` mark ([`super::labels::shown`]).
    pub fn shown_label(&self) -> String {
        let (label, humps) = self.label();
        let three_dimensional = match self {
            Analysis::Structure(a) => a.summary.three_dimensional,
            _ => false,
        };
        super::labels::shown(label, humps, three_dimensional)
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
        let mut m = match v {
            Ok(Value::Object(m)) => m,
            _ => Map::new(),
        };
        if let Analysis::Structure(a) = self
            && let Some(s) = &a.statistics
            && let Ok(Value::Object(more)) = serde_json::to_value(&s.summary)
        {
            m.extend(more);
        }
        m
    }

    /// The rows of one of the kind's tables (cells in the declared column order).
    pub fn rows(&self, table: &str) -> Vec<Vec<Cell>> {
        match self {
            Analysis::Structure(a) => structure_rows(a, table),
            Analysis::Lattice(a) => lattice_rows(a, table),
            Analysis::Rarefied(a) => rarefied_rows(a, table),
            Analysis::Dense(a) => dense_rows(a, table),
        }
    }
}

/// The rows of one of the structure analysis' tables.
fn structure_rows(a: &JobAnalysis, table: &str) -> Vec<Vec<Cell>> {
    match table {
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
        "profiles" => {
            // the structure's profiles and, with statistics, lambda(y) and Kn(y)
            let rows: Vec<super::ProfileRow> = a
                .profiles
                .iter()
                .cloned()
                .chain(
                    a.statistics
                        .as_deref()
                        .map_or_else(Vec::new, super::statistics::tables::profile_rows),
                )
                .collect();
            // bins of equal width across W: the centre of bin b of n is (b + 1/2) / n
            let bins = |q: &str| {
                rows.iter()
                    .filter(|r| r.quantity == q)
                    .map(|r| r.bin + 1)
                    .max()
                    .unwrap_or(1)
            };
            rows.iter()
                .map(|r| {
                    vec![
                        r.quantity.as_str().into(),
                        r.bin.into(),
                        ((f64::from(r.bin) + 0.5) / f64::from(bins(&r.quantity))).into(),
                        r.value.into(),
                        Cell::Null,
                    ]
                })
                .collect()
        }
        "evolution" => a
            .milestones
            .iter()
            .map(|m| {
                vec![
                    m.milestone.into(),
                    m.clock.as_str().into(),
                    m.collisions_per_particle.into(),
                    m.time.into(),
                    m.window_snapshots.into(),
                    m.structure.as_str().into(),
                    m.three_dimensional.into(),
                    m.candidate.as_str().into(),
                    m.probability.into(),
                    Cell::List(
                        m.peaks
                            .iter()
                            .map(|p| {
                                vec![
                                    p.plane.as_str().into(),
                                    p.k1.into(),
                                    p.k2.into(),
                                    p.ratio.into(),
                                ]
                            })
                            .collect(),
                    ),
                    m.translational.into(),
                    m.rotational.into(),
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
        other => a
            .statistics
            .as_deref()
            .map(|s| super::statistics::tables::rows(s, other))
            .unwrap_or_default(),
    }
}

/// The rows of one of the lattice analysis' tables.
fn lattice_rows(a: &LatticeAnalysis, table: &str) -> Vec<Vec<Cell>> {
    match table {
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
    }
}

/// The rows of one of the rarefied analysis' tables.
fn rarefied_rows(a: &RarefiedAnalysis, table: &str) -> Vec<Vec<Cell>> {
    match table {
        "profiles" => a
            .profiles
            .iter()
            .enumerate()
            .flat_map(|(bin, r)| {
                // y / W about the centre -> y / W from the wall at y = 0
                let coordinate = r.y + 0.5;
                r.quantities().map(|(name, value, error)| {
                    vec![
                        name.into(),
                        bin.into(),
                        coordinate.into(),
                        value.into(),
                        error.into(),
                    ]
                })
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// The rows of one of the dense analysis' tables.
fn dense_rows(a: &DenseAnalysis, table: &str) -> Vec<Vec<Cell>> {
    match table {
        "profiles" => a
            .profiles
            .iter()
            .map(|r| {
                vec![
                    r.quantity.as_str().into(),
                    r.bin.into(),
                    r.coordinate.into(),
                    r.value.into(),
                    r.error.into(),
                ]
            })
            .collect(),
        "series" => a
            .series
            .iter()
            .map(|r| {
                vec![
                    r.time.into(),
                    r.com_velocity.into(),
                    r.wall_force_balance.into(),
                    r.translational_energy.into(),
                    r.rotational_energy.into(),
                    r.coordination_number.into(),
                    Cell::Bool(r.in_window),
                ]
            })
            .collect(),
        _ => Vec::new(),
    }
}

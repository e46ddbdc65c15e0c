//! The statistics' tables (long format, one block of rows per job, written only by sweeps with
//! statistics) and their columns of `jobs.parquet`, with units in the Parquet field metadata.
//! Column names are unique across an engine's tables (each table's slab column has its own
//! name), so the tables join on `job_id` alone. The mean free path and Kn profiles are rows of
//! `profiles.parquet` (quantities `mean_free_path`, `Kn`), next to the other cross-channel
//! profiles.

use super::{Statistics, StatisticsSummary};
use crate::analysis::ProfileRow;
use crate::analysis::columns::{Cell, ColumnDef, ColumnKind, TableDef};

const fn column(name: &'static str, kind: ColumnKind, doc: &'static str) -> ColumnDef {
    ColumnDef { name, kind, doc }
}

use ColumnKind::{F64, I64, Str};

/// The statistics tables, in the order they are written.
pub const TABLES: &[TableDef] = &[
    TableDef {
        name: "vdf",
        columns: &[
            column("vdf_bin", I64, "slab across the channel (0 at y = 0)"),
            column("vdf_y", F64, "slab centre, d"),
            column(
                "component",
                Str,
                "C_x, C_y, C_z, Omega_x, Omega_y or Omega_z",
            ),
            column(
                "x",
                F64,
                "fluctuation over the slab's standard deviation (bin centre)",
            ),
            column(
                "p",
                F64,
                "probability density scaled so that P(0) = 1 (thesis); Gaussian: exp(-x^2/2)",
            ),
            column("density", F64, "probability density of x"),
            column("gaussian", F64, "the reference exp(-x^2/2)"),
        ],
    },
    TableDef {
        name: "vdf_moments",
        columns: &[
            column("moment_bin", I64, "slab across the channel"),
            column("moment_y", F64, "slab centre, d"),
            column("moment_component", Str, "C_x .. Omega_z"),
            column(
                "moment_samples",
                I64,
                "fluctuations counted over the window",
            ),
            column(
                "sigma",
                F64,
                "standard deviation: sqrt(g d) for C, sqrt(g/d) for Omega",
            ),
            column("skewness", F64, "m3 / m2^(3/2) (new, not in the thesis)"),
            column("skewness_error", F64, "batch-means standard error"),
            column(
                "kurtosis",
                F64,
                "m4 / m2^2, 3 for a Gaussian (new, not in the thesis)",
            ),
            column("kurtosis_error", F64, "batch-means standard error"),
        ],
    },
    TableDef {
        name: "pair_correlation",
        columns: &[
            column("g_bin", I64, "slab of the test particle; null: all slabs"),
            column("g_y", F64, "slab centre, d; null for all slabs"),
            column("r", F64, "pair distance (bin centre), d"),
            column(
                "g",
                F64,
                "g(r): pairs over those of an uncorrelated gas with the same density profile",
            ),
            column("g_pairs", I64, "ordered pairs counted"),
        ],
    },
    TableDef {
        name: "orientation",
        columns: &[
            column("lambda_bin", I64, "slab across the channel"),
            column("lambda_y", F64, "slab centre, d"),
            column(
                "lambda",
                F64,
                "Lambda = <cos^2 Psi>, 1/3 for a molecular gas",
            ),
            column("lambda_error", F64, "batch-means standard error"),
            column("lambda_samples", I64, "particles counted over the window"),
        ],
    },
    TableDef {
        name: "velocity_correlation",
        columns: &[
            column("c_bin", I64, "slab of the test particle"),
            column("c_y", F64, "slab centre, d"),
            column("c_pair", Str, "xx, yy, zz, xy, xz or yz"),
            column("c_r", F64, "pair distance (bin centre), d"),
            column(
                "c",
                F64,
                "C_ab(r): mean symmetrised product over sqrt(<C_a^2><C_b^2>); 0 uncorrelated",
            ),
            column("c_pairs", I64, "ordered pairs counted"),
        ],
    },
    TableDef {
        name: "free_paths",
        columns: &[
            column(
                "l_bin",
                I64,
                "slab of the paths' midpoints; null: all slabs",
            ),
            column("l_y", F64, "slab centre, d; null for all slabs"),
            column("l", F64, "free path (bin centre), d"),
            column("p_l", F64, "probability density P(l), per d"),
        ],
    },
];

/// The statistics' columns of `jobs.parquet` with their types, in order.
pub fn summary_columns() -> Vec<(String, ColumnKind)> {
    let empty = serde_json::to_value(StatisticsSummary::default()).expect("summary serialises");
    let serde_json::Value::Object(map) = empty else {
        return Vec::new();
    };
    map.into_iter()
        .map(|(name, v)| {
            let kind = if v.is_u64() { I64 } else { F64 };
            (name, kind)
        })
        .collect()
}

/// The rows of one statistics table (cells in the declared order).
pub fn rows(s: &Statistics, table: &str) -> Vec<Vec<Cell>> {
    let slab = |b: Option<u32>| b.map_or(Cell::Null, Cell::from);
    match table {
        "vdf" => s
            .vdf
            .iter()
            .map(|r| {
                vec![
                    r.slab.into(),
                    r.y.into(),
                    r.component.as_str().into(),
                    r.x.into(),
                    r.p.into(),
                    r.density.into(),
                    (-0.5 * r.x * r.x).exp().into(),
                ]
            })
            .collect(),
        "vdf_moments" => s
            .vdf_moments
            .iter()
            .map(|r| {
                vec![
                    r.slab.into(),
                    r.y.into(),
                    r.component.as_str().into(),
                    r.samples.into(),
                    r.sigma.into(),
                    r.skewness.into(),
                    r.skewness_error.into(),
                    r.kurtosis.into(),
                    r.kurtosis_error.into(),
                ]
            })
            .collect(),
        "pair_correlation" => s
            .pair_correlation
            .iter()
            .map(|r| {
                vec![
                    slab(r.slab),
                    r.y.into(),
                    r.r.into(),
                    r.g.into(),
                    r.pairs.into(),
                ]
            })
            .collect(),
        "orientation" => s
            .orientation
            .iter()
            .map(|r| {
                vec![
                    r.slab.into(),
                    r.y.into(),
                    r.lambda.into(),
                    r.error.into(),
                    r.samples.into(),
                ]
            })
            .collect(),
        "velocity_correlation" => s
            .velocity_correlation
            .iter()
            .map(|r| {
                vec![
                    r.slab.into(),
                    r.y.into(),
                    r.pair.as_str().into(),
                    r.r.into(),
                    r.c.into(),
                    r.pairs.into(),
                ]
            })
            .collect(),
        "free_paths" => s
            .free_paths
            .iter()
            .map(|r| vec![slab(r.slab), r.y.into(), r.l.into(), r.p.into()])
            .collect(),
        _ => Vec::new(),
    }
}

/// The statistics' rows of `profiles.parquet`: lambda(y) (`mean_free_path`, d) and
/// Kn(y) = lambda / W (`Kn`).
pub fn profile_rows(s: &Statistics) -> Vec<ProfileRow> {
    let mut rows = Vec::new();
    for (quantity, pick) in [
        (
            "mean_free_path",
            (|k: &super::free_path::KnudsenRow| k.mean_free_path) as fn(&_) -> f64,
        ),
        ("Kn", |k| k.knudsen),
    ] {
        rows.extend(s.knudsen.iter().map(|k| ProfileRow {
            quantity: quantity.into(),
            bin: k.slab,
            y: k.y,
            value: pick(k),
        }));
    }
    rows
}

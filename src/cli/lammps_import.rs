//! `granflow lammps-import SWEEP.ron --job ID --dump FILE --out DIR`: a LAMMPS run of one DEM
//! job (written by `granflow lammps`, run by LAMMPS) read back from its `dump custom` file
//! into granflow's DEM analysis: the same `jobs`, `profiles` and `series` tables and job
//! figures as a granflow run of that job, with the quantities a dump cannot give left null
//! ([`crate::engine::dem::imported`]; docs/lammps.md).

use super::lammps::dem_job;
use super::out::outln;
use crate::analysis::Record;
use crate::engine::Counters;
use crate::engine::dem::{imported, lammps, params_of};
use crate::provenance::Provenance;
use crate::sweep::store::{JobResult, JobState, RESULT_FORMAT};
use crate::sweep::tables::{self, GatheredJob};
use crate::sweep::{BadInput, load_sweep};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow lammps sweeps/dem-width-loading.ron --job 0 --out lmp-w60 --dump-every 10000
  (cd lmp-w60 && mpirun -np 64 lmp -in in.dem)
  granflow lammps-import sweeps/dem-width-loading.ron --job 0 --dump lmp-w60/dump.dem --out lmp-w60/tables
Each interval between two frames is one record with one sample (the later frame): dump often
enough for the block errors (the analysis window is its last part, in blocks). The walls'
force along the flow comes from the momentum balance between frames, the contact stress (sigma,
mu, I) from the c_pairstress columns that granflow lammps' script dumps; the dissipation, the
contact counts and each wall's own forces are not in a dump and stay null.")]
pub struct LammpsImportArgs {
    /// the sweep file (sweeps/*.ron) of the DEM sweep the LAMMPS run was written from
    pub sweep: PathBuf,
    /// the job: its id (16 hex digits, as `granflow plan` lists them) or its plan index
    #[arg(long)]
    pub job: String,
    /// the LAMMPS `dump custom` text file (columns id, diameter or radius, x y z, vx vy vz,
    /// omegax omegay omegaz, optionally c_pairstress[1..6]; `granflow lammps` writes such a
    /// dump: dump.dem)
    #[arg(long)]
    pub dump: PathBuf,
    /// directory to write the tables (jobs, profiles, series .parquet) and figures into
    /// (created if missing)
    #[arg(long)]
    pub out: PathBuf,
    /// override a fixed value or an axis of the sweep: key=value (repeatable; as in `plan`)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: LammpsImportArgs) -> anyhow::Result<()> {
    let sweep = load_sweep(&args.sweep, &args.set)?;
    let job = dem_job(
        &sweep,
        &args.sweep,
        &args.job,
        "`granflow lammps-import` reads runs of DEM jobs",
    )?;
    let params = params_of(&job.params.values, job.params.seed);
    // a dump that cannot be read, or is not of this job's channel, is bad input (exit 2)
    let (frames, digest) =
        lammps::read_dump_file_with_digest(&args.dump).map_err(|e| BadInput(format!("{e:#}")))?;
    let dump = args.dump.display();
    let records = imported::records_from_frames(&params, &frames).map_err(|e| {
        BadInput(format!(
            "{dump}: not a run of job {} of {}: {e}",
            job.id,
            args.sweep.display()
        ))
    })?;
    let records: Vec<Record> = records
        .into_iter()
        .map(|r| Record::Dense(Box::new(r)))
        .collect();
    let analyser = job
        .params
        .analyser()
        .map_err(|e| anyhow::anyhow!("{}: key `analysis`: {e}", args.sweep.display()))?;
    let analysis = analyser
        .analyse(&records)
        .map_err(|e| anyhow::anyhow!("analysing the dump's {} records: {e}", records.len()))?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create", args.out.display()))?;
    let figures = crate::job_figures::figures(&job.heading(), &analysis, &records);
    let drawn = crate::job_figures::write(&args.out, &figures)?;

    let (first, last) = (&frames[0], &frames[frames.len() - 1]);
    let source = format!(
        "LAMMPS dump {dump} (sha256 {digest}): {} frames, steps {} to {}",
        frames.len(),
        first.timestep,
        last.timestep
    );
    let flow_steps = last.timestep - first.timestep;
    let def = job.params.def();
    // the granflow build that analysed the dump; engine version 0: the run is LAMMPS'
    let mut provenance = Provenance::here(0, crate::registry::analysis_of(def).version());
    provenance.finished = crate::provenance::now();
    let result = JobResult {
        format: RESULT_FORMAT,
        id: job.id.0.clone(),
        engine: job.params.engine.clone(),
        particles: first.states.len(),
        snapshots: records.len() as u32,
        collisions_per_particle: 0.0,
        time: last.timestep as f64 * params.time_step,
        steps: last.timestep,
        // what a dump counts; the other counters are null in the table
        counters: Counters::from_pairs([("steps", flow_steps), ("samples", records.len() as u64)]),
        wall_seconds: f64::NAN,
        events_per_second: f64::NAN,
        stop_reason: format!("imported from {source}"),
        provenance,
        checksum: String::new(),
        analysis,
    };
    let summary = result.analysis.summary();
    let gathered = [GatheredJob {
        job,
        state: JobState::Done,
        result: Some(result),
    }];
    let _one_at_a_time = tables::lock_gathering(&args.out)?;
    let written = tables::write_set(
        &sweep,
        &gathered,
        &args.out,
        &[("granflow.source".to_string(), source.clone())],
    )?;
    let number = |key: &str| {
        summary
            .get(key)
            .and_then(|v| v.as_f64())
            .map_or("null".to_string(), |v| format!("{v:.4}"))
    };
    outln!(
        "read {source}\njob {} (index {}): {}; u_max / u_slip = {}, beta = {} +- {}",
        job.id,
        job.index,
        summary.get("label").and_then(|v| v.as_str()).unwrap_or("?"),
        number("velocity_ratio"),
        number("wall_force_balance"),
        number("wall_force_balance_error"),
    );
    outln!(
        "wrote {} and {} figures in {}",
        written
            .tables
            .iter()
            .map(|n| format!("{n}.parquet"))
            .collect::<Vec<_>>()
            .join(", "),
        drawn.len(),
        args.out.display()
    );
    Ok(())
}

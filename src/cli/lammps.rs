//! `granflow lammps SWEEP.ron --job ID --out DIR`: write one DEM job of a sweep as LAMMPS
//! input (`data.dem`, `in.dem`) from its prepared state (after granflow's preparation,
//! optionally after some flow steps), for runs that need LAMMPS on many nodes; the format and
//! its conventions are in [`crate::engine::dem::lammps`] and docs/lammps.md.

use super::out::outln;
use crate::engine::dem::lammps::{self, ScriptOptions};
use crate::engine::dem::{DemEngine, params_of};
use crate::sweep::{BadInput, PlannedJob, Sweep, load_sweep};
use anyhow::Context;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow lammps sweeps/dem-width-loading.ron --job 0 --out lmp-w60      # the first job, prepared
  granflow lammps sweeps/dem-width-loading.ron --job 3f2a9c0d1e4b5a67 --out lmp --steps 2000000
  cd lmp-w60 && mpirun -np 64 lmp -in in.dem                      # then read dump.dem back
The data file holds the particles (atom id = granflow index + 1); the input script the
contact law (gran/hooke/history, dampflag 1), the walls (wall/gran yplane 0 W), gravity along
+x, nve/sphere, the time step, the skin and a full-precision `dump custom` (dump.dem).
Contact histories start at zero in LAMMPS (a data file cannot carry them).")]
pub struct LammpsArgs {
    /// the sweep file (sweeps/*.ron) of a DEM sweep (engine: "dem")
    pub sweep: PathBuf,
    /// the job: its id (16 hex digits, as `granflow plan` lists them) or its plan index
    #[arg(long)]
    pub job: String,
    /// directory to write data.dem and in.dem into (created if missing)
    #[arg(long)]
    pub out: PathBuf,
    /// steps for LAMMPS to run (`run N` in in.dem); default: the job's run length in steps
    #[arg(long)]
    pub steps: Option<u64>,
    /// steps between dump frames (default: the LAMMPS run length, i.e. the first and last)
    #[arg(long)]
    pub dump_every: Option<u64>,
    /// flow steps granflow runs after its preparation before writing the state (default 0:
    /// the prepared state, just after the floor was removed)
    #[arg(long, default_value_t = 0)]
    pub after: u64,
    /// override a fixed value or an axis of the sweep: key=value (repeatable; as in `plan`)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: LammpsArgs) -> anyhow::Result<()> {
    let sweep = load_sweep(&args.sweep, &args.set)?;
    let shown = args.sweep.display();
    let job = dem_job(
        &sweep,
        &args.sweep,
        &args.job,
        "`granflow lammps` writes DEM jobs",
    )?;
    let params = params_of(&job.params.values, job.params.seed);
    let steps = match args.steps {
        Some(s) => s,
        None => {
            let run = &job.params.run;
            let length = run.length();
            match run.clock() {
                crate::engine::Clock::Steps => length.ceil() as u64,
                crate::engine::Clock::Time => (length / params.time_step).ceil() as u64,
                crate::engine::Clock::CollisionsPerParticle => {
                    return Err(BadInput(format!(
                        "{shown}: key `run`: a DEM run is measured in time or steps; give \
                         --steps"
                    ))
                    .into());
                }
            }
        }
    };
    eprintln!(
        "job {} (index {}): N = {}, preparing (raining and settling)...",
        job.id,
        job.index,
        params.particle_count()
    );
    let mut engine = DemEngine::new(params.clone())
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("{shown}: job {}: the preparation failed", job.id))?;
    if args.after > 0 {
        engine
            .advance_to_step(args.after)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("{shown}: job {}: the flow failed", job.id))?;
    }
    let states = engine.states();
    let opts = ScriptOptions {
        dump_every: args.dump_every.unwrap_or(steps.max(1)),
        ..ScriptOptions::new(steps)
    };
    let (data, input) = lammps::write(&args.out, engine.params(), &states, &opts)?;
    outln!(
        "wrote {} ({} particles, after {} preparation and {} flow steps) and {} ({} steps, dump \
         every {} into {})",
        data.display(),
        states.len(),
        engine.counters().prep_steps,
        engine.steps(),
        input.display(),
        steps,
        opts.dump_every,
        lammps::DUMP_FILE
    );
    outln!(
        "run: cd {} && lmp -in {} (or mpirun -np P lmp -in {})",
        args.out.display(),
        lammps::INPUT_FILE,
        lammps::INPUT_FILE
    );
    Ok(())
}

/// The DEM job of a sweep that `--job` names (its id or its plan index); `what` says why a
/// sweep of another engine is refused.
pub(super) fn dem_job<'a>(
    sweep: &'a Sweep,
    file: &Path,
    id: &str,
    what: &str,
) -> anyhow::Result<&'a PlannedJob> {
    let shown = file.display();
    if sweep.spec.engine != "dem" {
        return Err(BadInput(format!(
            "{shown}: key `engine` is \"{}\": {what} (engine: \"dem\")",
            sweep.spec.engine
        ))
        .into());
    }
    let job = match id.parse::<usize>() {
        Ok(index) if id.len() < 16 => sweep.plan.get(index),
        _ => sweep.plan.iter().find(|j| j.id.0 == id),
    };
    job.ok_or_else(|| {
        BadInput(format!(
            "{shown}: --job {id}: no such job; the sweep has {} jobs (plan index 0 to {}, or \
             their ids: `granflow plan {shown}`)",
            sweep.plan.len(),
            sweep.plan.len().saturating_sub(1)
        ))
        .into()
    })
}

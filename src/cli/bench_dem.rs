//! `granflow bench` DEM workloads: dense channels at phi-bar = 0.6 with the paper's law
//! (Debnath, Rao & Kumaran 2022: k_n = 1e6, k_t = 2/7 k_n, e_n = 0.82, xi_t = xi_n / 2,
//! mu = 0.5, the 0.9/1.0/1.1 mix, Delta t = 1.2e-4, skin 0.1 d_p), prepared as a job is
//! (rained, settled, floor removed) and warmed up by a flow (both states kept in a cache
//! directory, since they take minutes), then timed: particle-steps per second
//! (N times steps over wall seconds), on the threads of the pool (`--threads`, default 1).
//! `--lammps-out DIR` also writes the warmed state as a LAMMPS data file and input
//! (`bench/peers/peers.py lammps-dem` times LAMMPS on it).

use super::bench_result::{BenchResult, bytes_per_particle, memory_baseline};
use crate::engine::dem::lammps::{self, ScriptOptions};
use crate::engine::dem::{DemEngine, DemParams};
use anyhow::Context;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A DEM workload: its name and channel (W, B, L in d_p at phi-bar 0.6).
pub struct DemWorkload {
    pub name: &'static str,
    pub params: DemParams,
}

/// The dense channels: about 4000 and 40 000 particles at phi-bar = 0.6 (W x B x L = 20 x 10
/// x 18 and 40 x 20 x 45 d_p), the paper's law and step.
pub fn workloads() -> Vec<DemWorkload> {
    vec![
        DemWorkload {
            name: "dem-channel-4k-phi0.60",
            params: DemParams::channel(20.0, 10.0, 18.0, 0.6, 1),
        },
        DemWorkload {
            name: "dem-channel-40k-phi0.60",
            params: DemParams::channel(40.0, 20.0, 45.0, 0.6, 1),
        },
    ]
}

/// Options of the DEM workloads.
pub struct DemBenchOptions {
    /// untimed flow steps after the preparation
    pub warmup: u64,
    /// timed steps
    pub steps: u64,
    /// threads of the pool the workload runs on
    pub threads: usize,
    /// where prepared states are kept
    pub cache: PathBuf,
    /// write the warmed state as LAMMPS input here (timed steps as `run N`)
    pub lammps_out: Option<PathBuf>,
}

/// The cache directory of prepared states: `$GRANFLOW_BENCH_CACHE`, else
/// `$XDG_CACHE_HOME/granflow/bench`, else `~/.cache/granflow/bench`, else the temp dir.
pub fn default_cache() -> PathBuf {
    if let Some(d) = std::env::var_os("GRANFLOW_BENCH_CACHE") {
        return d.into();
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir);
    base.join("granflow").join("bench")
}

/// The engine of a workload after its preparation and `warmup` flow steps: from the cache
/// when there (each file holds the parameters and the step: one of other parameters is not
/// used), else computed (from the cached prepared state when there) and cached, both the
/// prepared and the warmed state.
fn warmed(w: &DemWorkload, cache: &Path, warmup: u64) -> anyhow::Result<DemEngine> {
    let key = {
        use sha2::{Digest, Sha256};
        let text = format!("{:?}", w.params);
        let digest = Sha256::digest(text.as_bytes());
        crate::provenance::hex(&digest[..8])
    };
    let load = |path: &Path, step: u64| {
        std::fs::read(path)
            .ok()
            .and_then(|bytes| DemEngine::from_payload(&bytes).ok())
            .filter(|e| e.params() == &w.params && e.steps() == step)
    };
    let save = |path: &Path, e: &DemEngine| -> anyhow::Result<()> {
        std::fs::create_dir_all(cache)
            .with_context(|| format!("{}: cannot create", cache.display()))?;
        std::fs::write(path, e.to_payload())
            .with_context(|| format!("{}: cannot write", path.display()))
    };
    let warm_path = cache.join(format!("{}-{key}-flow{warmup}.dem", w.name));
    if let Some(e) = load(&warm_path, warmup) {
        return Ok(e);
    }
    let path = cache.join(format!("{}-{key}.dem", w.name));
    let mut e = match load(&path, 0) {
        Some(e) => e,
        None => {
            eprintln!(
                "{}: preparing N = {} (raining and settling; once, kept in {})",
                w.name,
                w.params.particle_count(),
                path.display()
            );
            let clock = Instant::now();
            let e = DemEngine::new(w.params.clone()).map_err(anyhow::Error::msg)?;
            eprintln!(
                "{}: prepared in {:.0} s ({} steps)",
                w.name,
                clock.elapsed().as_secs_f64(),
                e.counters().prep_steps
            );
            save(&path, &e)?;
            e
        }
    };
    if warmup > 0 {
        eprintln!(
            "{}: {warmup} warm-up steps (once, kept in {})",
            w.name,
            warm_path.display()
        );
        e.advance_to_step(warmup).map_err(anyhow::Error::msg)?;
        save(&warm_path, &e)?;
    }
    Ok(e)
}

/// Time one DEM workload: prepared (cached), `warmup` untimed steps, `steps` timed.
pub fn measure(w: &DemWorkload, o: &DemBenchOptions) -> anyhow::Result<BenchResult> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.threads)
        .build()?;
    let baseline = memory_baseline();
    let engine = pool.install(|| warmed(w, &o.cache, o.warmup))?;
    timed(w.name, engine, &pool, baseline, o)
}

/// Time `steps` steps of the DEM job in `dir` continued from its checkpoint `sealed` (e.g. a
/// channel at the paper's width, where the standard workloads' sizes say little); the
/// `warmup` of the options is not used (the job's own run is the warm-up).
pub fn measure_from_job(
    dir: &Path,
    sealed: crate::engine::envelope::Sealed<'_>,
    o: &DemBenchOptions,
) -> anyhow::Result<BenchResult> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.threads)
        .build()?;
    let baseline = memory_baseline();
    let engine = DemEngine::from_payload_of_version(sealed.version, sealed.payload)
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("{}: not a DEM job's checkpoint", dir.display()))?;
    let at = engine.steps() as f64 * engine.params().time_step;
    timed(
        &super::bench_job::workload_name(dir, at),
        engine,
        &pool,
        baseline,
        o,
    )
}

/// Time `o.steps` steps of `engine` on `pool` (after writing it as LAMMPS input when asked).
fn timed(
    name: &str,
    mut engine: DemEngine,
    pool: &rayon::ThreadPool,
    baseline: Option<f64>,
    o: &DemBenchOptions,
) -> anyhow::Result<BenchResult> {
    if let Some(dir) = &o.lammps_out {
        // LAMMPS starts without contact histories: so does the run timed here
        let mut states = engine.states();
        for s in &mut states {
            s.wall_shear = [0.0; 3];
        }
        let opts = ScriptOptions {
            dump_every: 0,
            thermo_every: o.steps.max(1),
            ..ScriptOptions::new(o.steps)
        };
        lammps::write(dir, engine.params(), &states, &opts)?;
        engine = DemEngine::from_state(engine.params().clone(), &states, &[])
            .map_err(anyhow::Error::msg)?;
    }
    let n = engine.particle_count();
    let before = engine.counters();
    let start = engine.steps();
    let stages = engine.stage_times();
    let clock = Instant::now();
    pool.install(|| engine.advance_to_step(start + o.steps))
        .map_err(anyhow::Error::msg)?;
    let secs = clock.elapsed().as_secs_f64();
    let after = engine.counters();
    let steps = (after.steps - before.steps) as f64;
    let particle_steps = n as f64 * steps / secs;
    let contacts = (after.contacts - before.contacts) as f64;
    let now = engine.stage_times();
    eprintln!(
        "{}: {:.3} s timed: pair forces {:.3} s, particle pass (gather, walls, gravity, kicks, \
         drifts) {:.3} s, list rebuilds {:.3} s ({} rebuilds), samples {:.3} s; {:.2} listed \
         pairs per particle at the end",
        name,
        secs,
        now.pairs - stages.pairs,
        now.particles - stages.particles,
        now.rebuilds - stages.rebuilds,
        after.rebuilds - before.rebuilds,
        now.samples - stages.samples,
        engine.listed_pairs() as f64 / n as f64
    );
    Ok(BenchResult {
        workload: name.to_string(),
        n,
        phi: engine.params().volume_fraction,
        // pair contacts evaluated per second (pair-steps in contact)
        collisions_per_s: contacts / secs,
        events_per_s: particle_steps,
        bytes_per_particle: bytes_per_particle(baseline, n, 1200.0),
        site_updates_per_s: None,
        moves_per_s: None,
        record_seconds: None,
        particle_steps_per_s: Some(particle_steps),
        contacts_per_particle: Some(contacts / steps / n as f64),
        threads: Some(o.threads),
    })
}

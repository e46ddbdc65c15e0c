//! `granflow bench`: engine speed on the standard workloads (collisions/s, events/s, memory per
//! particle) on one core, with the machine it ran on. `--json` prints a JSON array of objects
//! with the keys `workload`, `n`, `phi`, `collisions_per_s`, `events_per_s`,
//! `bytes_per_particle` (scripts compare runs with it; keep the keys); the lattice-gas
//! workloads add `site_updates_per_s` (their `phi` is the mean density rho per site, their
//! collisions are applications of rules (1)-(5), their events site updates).
//! The DSMC workloads (the Poiseuille case of issue 15: 6000 simulators in 200 layer cells,
//! dt = 0.1 mean collision times, e_n = 1, thermal walls) add `moves_per_s` (simulator
//! flights; also their `events_per_s`); their `collisions_per_s` are accepted collisions and
//! their `phi` is null (a DSMC gas has no volume fraction).
//! The DEM workloads (dense channels of about 4000 and 40 000 particles at phi-bar = 0.6 with
//! the paper's law, [`super::bench_dem`]; run only when `--workload` names them, e.g.
//! `--workload dem`, since their first run prepares the channel for many minutes) add `particle_steps_per_s` (N times timed steps over
//! wall seconds; also their `events_per_s`), `contacts_per_particle` (pair contacts per
//! particle and step) and `threads`; their `collisions_per_s` are pair contacts evaluated
//! per second.
//! `bytes_per_particle` is what a particle really costs: the growth of the process's peak
//! resident memory over the workload (set-up and snapshots included), over N (Linux; elsewhere
//! the engine's own count of its data structures).

use super::bench_dem::{self, DemBenchOptions, DemWorkload};
use super::bench_result::{BenchResult, SearchChoice, bytes_per_particle, memory_baseline};
use super::out::outln;
use crate::engine::dsmc::{DsmcEngine, DsmcParams};
use crate::engine::edmd::{EdmdEngine, EdmdParams, NeighbourSearch, Placement, SearchPolicy};
use crate::engine::lga::{LgaEngine, LgaParams};
use crate::engine::{Engine, StopAt};
use clap::Args;
use std::time::Instant;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow bench                              # every standard workload, as a table
  granflow bench --workload channel --json    # the workloads named *channel*, as JSON
  granflow bench --workload dem-channel-4k --threads 2   # the dense DEM channel on 2 threads
  granflow bench --from-job results/thesis-fig5-25/jobs/492eb82c0804cd46 --search cells")]
pub struct BenchArgs {
    /// print a JSON array instead of a table
    #[arg(long)]
    pub json: bool,
    /// run only the workloads whose name contains this text (a workload's whole name: that one)
    #[arg(long)]
    pub workload: Option<String>,
    /// measured collisions per particle in each workload (after the warm-up)
    #[arg(long, default_value_t = 20.0)]
    pub collisions_per_particle: f64,
    /// warm-up of the channel workload, in collisions per particle (not timed)
    #[arg(long, default_value_t = 100.0)]
    pub channel_warmup: f64,
    /// neighbour search: what a run would choose (auto: cell lists below phi = 0.3, neighbour
    /// lists from there on, then re-chosen from the run's bookkeeping), or force one
    #[arg(long, value_enum, default_value_t = SearchChoice::Auto)]
    pub search: SearchChoice,
    /// skin of the neighbour lists, in d (with lists)
    #[arg(long, default_value_t = NeighbourSearch::DEFAULT_SKIN)]
    pub skin: f64,
    /// timed site updates of each lattice-gas workload (after 1000 untimed steps)
    #[arg(long, default_value_t = 1e9)]
    pub site_updates: f64,
    /// continue the job in this directory from its checkpoint (results/SWEEP/jobs/ID)
    /// instead of running the standard workloads. EDMD: timed over --collisions-per-particle,
    /// a snapshot every tenth, after 2.5 untimed; DEM: --dem-steps on --threads (with
    /// --lammps-out, the checkpoint's state also written for LAMMPS)
    #[arg(long, value_name = "JOB_DIR")]
    pub from_job: Option<std::path::PathBuf>,
    /// timed simulator moves of each DSMC workload (after 500 untimed steps)
    #[arg(long, default_value_t = 3e8)]
    pub moves: f64,
    /// EDMD workloads: tally free paths between collisions (25 slabs) through the timed
    /// stretch, as a run with statistics does
    #[arg(long)]
    pub free_paths: bool,
    /// EDMD workloads: take this many snapshots evenly through the timed stretch, each reduced
    /// to the analysis record a job keeps (the structure record; with --statistics also the
    /// statistics), as a job's snapshot cadence
    #[arg(long, default_value_t = 0)]
    pub snapshots: u32,
    /// with --snapshots: the statistics (those of sweeps/thesis-ch4-dense.ron: 25 slabs,
    /// r_max = 8 d) at every snapshot, and free paths tallied throughout
    #[arg(long)]
    pub statistics: bool,
    /// DEM workloads: threads to run on (the other workloads use one)
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// DEM workloads: timed steps (after the untimed warm-up)
    #[arg(long, default_value_t = 2000)]
    pub dem_steps: u64,
    /// DEM workloads: untimed flow steps after the preparation (the state after them is kept
    /// in the cache: computed once); by 100 000 steps (12 sqrt(d_p/g)) the flow has about one
    /// contact per particle
    #[arg(long, default_value_t = 100_000)]
    pub dem_warmup: u64,
    /// DEM workloads: directory of the prepared states (default: $GRANFLOW_BENCH_CACHE, else
    /// ~/.cache/granflow/bench); the preparation runs once per workload
    #[arg(long, value_name = "DIR")]
    pub dem_cache: Option<std::path::PathBuf>,
    /// DEM workloads: also write the warmed state as LAMMPS input (data.dem, in.dem running the
    /// timed steps) into this directory; the timed run then starts, as LAMMPS does, without
    /// contact histories (one workload only)
    #[arg(long, value_name = "DIR")]
    pub lammps_out: Option<std::path::PathBuf>,
}

impl BenchArgs {
    /// The neighbour search of a workload: as a run would have it (auto: starting from the
    /// parameters, re-chosen at rebuilds), or forced throughout.
    fn search_for(&self, params: &EdmdParams) -> SearchPolicy {
        let lists = NeighbourSearch::Lists { skin: self.skin };
        match self.search {
            SearchChoice::Cells => SearchPolicy::fixed(NeighbourSearch::Cells),
            SearchChoice::Lists => SearchPolicy::fixed(lists),
            SearchChoice::Auto => {
                let start = match NeighbourSearch::automatic(params) {
                    NeighbourSearch::Cells => NeighbourSearch::Cells,
                    NeighbourSearch::Lists { .. } => lists,
                };
                SearchPolicy::adaptive(start, &Default::default())
            }
        }
    }
}

/// A DSMC workload: the Poiseuille case at one Kn.
struct DsmcWorkload {
    name: &'static str,
    params: DsmcParams,
}

/// The case the issue measured SPARTA on: 6000 simulators, 200 cells, dt = 0.1 tau_c, e_n = 1,
/// thermal walls, a-hat = 0.5; at Kn = 0.1 and 1, sampled every step or not at all. And the
/// same on the grid a SPARTA user would choose, about 3 cells per mean free path (30 cells at
/// Kn = 0.1, 3 at Kn = 1; `-3mfp` in the name): 200 cells are 20 and 200 per mean free path,
/// which SPARTA's regular mover pays for in cell crossings (bench/peers/README.md).
fn dsmc_workloads() -> Vec<DsmcWorkload> {
    let case = |kn: f64, cells: usize, sample_every: u64| DsmcParams {
        knudsen_number: kn,
        cells,
        particles_per_cell: 6000.0 / cells as f64,
        time_step: 0.1,
        sample_every,
        ..DsmcParams::default()
    };
    let (sampled, unsampled) = (1, u64::MAX / 2);
    vec![
        DsmcWorkload {
            name: "dsmc-kn0.1-6000-sampled",
            params: case(0.1, 200, sampled),
        },
        DsmcWorkload {
            name: "dsmc-kn0.1-6000-unsampled",
            params: case(0.1, 200, unsampled),
        },
        DsmcWorkload {
            name: "dsmc-kn1-6000-sampled",
            params: case(1.0, 200, sampled),
        },
        DsmcWorkload {
            name: "dsmc-kn1-6000-unsampled",
            params: case(1.0, 200, unsampled),
        },
        DsmcWorkload {
            name: "dsmc-kn0.1-6000-3mfp-sampled",
            params: case(0.1, 30, sampled),
        },
        DsmcWorkload {
            name: "dsmc-kn0.1-6000-3mfp-unsampled",
            params: case(0.1, 30, unsampled),
        },
        DsmcWorkload {
            name: "dsmc-kn1-6000-3mfp-sampled",
            params: case(1.0, 3, sampled),
        },
        DsmcWorkload {
            name: "dsmc-kn1-6000-3mfp-unsampled",
            params: case(1.0, 3, unsampled),
        },
    ]
}

/// Time a DSMC workload: 500 untimed steps, then `moves` timed.
fn measure_dsmc(w: &DsmcWorkload, moves: f64) -> anyhow::Result<BenchResult> {
    let baseline = memory_baseline();
    let mut engine = DsmcEngine::new(w.params.clone()).map_err(anyhow::Error::msg)?;
    engine.advance_to_step(500);
    let n = engine.species_counts().iter().sum::<usize>();
    let steps = (moves / n as f64).ceil().max(1.0) as u64;
    let before = engine.counter_values();
    let started = Instant::now();
    engine.advance_to_step(500 + steps);
    let secs = started.elapsed().as_secs_f64();
    let after = engine.counter_values();
    let moves_per_s = (after.moves - before.moves) as f64 / secs;
    Ok(BenchResult {
        workload: w.name.to_string(),
        n,
        phi: f64::NAN,
        collisions_per_s: (after.collisions - before.collisions) as f64 / secs,
        events_per_s: moves_per_s,
        bytes_per_particle: bytes_per_particle(baseline, n, 64.0),
        site_updates_per_s: None,
        moves_per_s: Some(moves_per_s),
        record_seconds: None,
        particle_steps_per_s: None,
        contacts_per_particle: None,
        threads: None,
    })
}

/// A lattice-gas workload: the seed's runs.
struct LgaWorkload {
    name: &'static str,
    params: LgaParams,
}

fn lga_workloads() -> Vec<LgaWorkload> {
    vec![
        LgaWorkload {
            // the seed's spectrum runs (Fig. 2): 220 x 11, rho = 1, p = g = b = 0.5
            name: "lga-fig2-220x11",
            params: LgaParams::default(),
        },
        LgaWorkload {
            // the seed's pictures (Fig. 1a): 2200 x 11, p = 0.1
            name: "lga-fig1-2200x11",
            params: LgaParams {
                length: 2200,
                dissipation: 0.1,
                ..LgaParams::default()
            },
        },
    ]
}

/// Time a lattice-gas workload: 1000 untimed steps, then `site_updates` timed.
fn measure_lga(w: &LgaWorkload, site_updates: f64) -> anyhow::Result<BenchResult> {
    let baseline = memory_baseline();
    let mut engine = LgaEngine::new(w.params.clone()).map_err(anyhow::Error::msg)?;
    engine.advance_to(1000);
    let sites = (w.params.length * w.params.width) as f64;
    let steps = (site_updates / sites).ceil().max(1.0) as u64;
    let rules = |e: &LgaEngine| {
        let c = e.counts();
        c.head_on + c.dissipative_pairs + c.three_body + c.rest_head_on + c.rest_pairs
    };
    let before = rules(&engine);
    let started = Instant::now();
    engine.advance_to(1000 + steps);
    let secs = started.elapsed().as_secs_f64();
    let n = engine.particle_count() as usize;
    let updates = steps as f64 * sites / secs;
    Ok(BenchResult {
        workload: w.name.to_string(),
        n,
        phi: w.params.density,
        collisions_per_s: (rules(&engine) - before) as f64 / secs,
        events_per_s: updates,
        bytes_per_particle: bytes_per_particle(
            baseline,
            n,
            engine.bytes() as f64 / n.max(1) as f64,
        ),
        site_updates_per_s: Some(updates),
        moves_per_s: None,
        record_seconds: None,
        particle_steps_per_s: None,
        contacts_per_particle: None,
        threads: None,
    })
}

/// A standard workload: its name, parameters and untimed warm-up (collisions per particle).
struct Workload {
    name: &'static str,
    params: EdmdParams,
    warmup: f64,
}

/// Elastic smooth hard spheres, periodic cube, fcc start, kT = 1.
fn periodic_fcc(particles: usize, phi: f64) -> EdmdParams {
    let side = (particles as f64 * std::f64::consts::PI / 6.0 / phi).cbrt();
    let mut p = EdmdParams::periodic_elastic(side, particles, 1.0, 1);
    p.placement = Placement::Fcc;
    p
}

fn workloads(args: &BenchArgs) -> Vec<Workload> {
    // the fcc lattice of the periodic workloads melts within a collision or two
    let melt = 2.0;
    vec![
        // small boxes: most of a sweep's jobs are channels of 600-5000 spheres
        Workload {
            name: "periodic-fcc-4k-phi0.15",
            params: periodic_fcc(4_000, 0.15),
            warmup: melt,
        },
        Workload {
            name: "periodic-fcc-4k-phi0.40",
            params: periodic_fcc(4_000, 0.40),
            warmup: melt,
        },
        Workload {
            name: "periodic-fcc-32k-phi0.15",
            params: periodic_fcc(32_000, 0.15),
            warmup: melt,
        },
        Workload {
            name: "periodic-fcc-32k-phi0.40",
            params: periodic_fcc(32_000, 0.40),
            warmup: melt,
        },
        Workload {
            name: "periodic-fcc-108k-phi0.15",
            params: periodic_fcc(108_000, 0.15),
            warmup: melt,
        },
        Workload {
            // a box whose engine state (~200 MB) is far beyond the last-level cache:
            // 4 x 64^3 spheres
            name: "periodic-fcc-1M-phi0.15",
            params: periodic_fcc(1_048_576, 0.15),
            warmup: melt,
        },
        Workload {
            // the thesis channel: L/W = 3, W/d = H/d = 30, phi = 0.15, e = 0.7, beta = 0.1,
            // e_w = beta_w = 0.99
            name: "channel-thesis-LW3-W30",
            params: EdmdParams::channel(90.0, 30.0, 30.0, 0.15, 1),
            warmup: args.channel_warmup,
        },
        Workload {
            // the thesis' dense case (ch. 4.2, sweeps/thesis-ch4-dense.ron): N = 19 600 in
            // 20 x 50 x 20, phi = 0.51, e = beta = 0.9, e_w = beta_w = 1
            name: "channel-ch4-dense-N19600",
            params: thesis_dense_channel(),
            warmup: args.channel_warmup,
        },
        Workload {
            // the same as its steady sweep runs it (sweeps/thesis-ch4-dense-steady.ron): from
            // the thermalised start, at the t_c valid at phi = 0.5 (docs/dense-flows.md)
            name: "channel-ch4-dense-N19600-steady",
            params: EdmdParams {
                tc: DENSE_STEADY_TC,
                placement: Placement::Thermalised {
                    collisions_per_particle: 100,
                },
                ..thesis_dense_channel()
            },
            warmup: args.channel_warmup,
        },
    ]
}

/// t_c of the dense case's steady sweep (the t_c scan at phi = 0.5, docs/dense-flows.md).
const DENSE_STEADY_TC: f64 = 1e-6;

/// The thesis' dense channel (section 4.2): N = 19 600 in 20 x 50 x 20 d, e = beta = 0.9,
/// walls e_w = beta_w = 1.
fn thesis_dense_channel() -> EdmdParams {
    let mut p = EdmdParams::channel(20.0, 50.0, 20.0, 0.5, 1);
    p.particles = 19_600;
    p.restitution = 0.9;
    p.roughness = 0.9;
    p.wall_restitution = 1.0;
    p.wall_roughness = 1.0;
    p
}

/// Run one workload: untimed set-up and warm-up, then the timed stretch.
fn measure(w: &Workload, search: SearchPolicy, args: &BenchArgs) -> anyhow::Result<BenchResult> {
    let measured_cpp = args.collisions_per_particle;
    let baseline = memory_baseline();
    let mut engine = EdmdEngine::with_policy(w.params.clone(), search)?;
    engine.advance(StopAt::CollisionsPerParticle(w.warmup))?;
    let before = engine.snapshot().progress;
    let analyser = snapshot_analyser(args)?;
    if args.free_paths || args.statistics {
        engine.record_free_paths(crate::analysis::statistics::DEFAULT_BINS);
    }
    let started = Instant::now();
    let stops = args.snapshots.max(1);
    let mut recording = 0.0;
    for k in 1..=stops {
        let at = w.warmup + measured_cpp * k as f64 / stops as f64;
        engine.advance(StopAt::CollisionsPerParticle(at))?;
        if args.snapshots > 0 {
            let snap = engine.snapshot();
            let paths = engine.take_free_paths();
            let t = Instant::now();
            std::hint::black_box(
                analyser
                    .record_with(&snap, k, paths)
                    .map_err(anyhow::Error::msg)?,
            );
            recording += t.elapsed().as_secs_f64();
        }
    }
    let secs = started.elapsed().as_secs_f64();
    let after = engine.progress();
    let collisions = (after.collisions_per_particle - w.warmup) * w.params.particles as f64 / 2.0;
    Ok(BenchResult {
        workload: w.name.to_string(),
        n: w.params.particles,
        phi: w.params.volume_fraction(),
        collisions_per_s: collisions / secs,
        events_per_s: (after.events - before.events) as f64 / secs,
        bytes_per_particle: bytes_per_particle(
            baseline,
            w.params.particles,
            engine.bytes_per_particle(),
        ),
        site_updates_per_s: None,
        moves_per_s: None,
        record_seconds: (args.snapshots > 0).then(|| recording / args.snapshots as f64),
        particle_steps_per_s: None,
        contacts_per_particle: None,
        threads: None,
    })
}

/// The analysis a job would run on the workloads' snapshots: the structure analysis with
/// default settings, with the default statistics when asked.
fn snapshot_analyser(args: &BenchArgs) -> anyhow::Result<crate::analysis::Analyser> {
    let kind = crate::analysis::AnalysisKind::Structure;
    let structure = kind
        .analyser(&kind.default_settings())
        .map_err(anyhow::Error::msg)?;
    Ok(if args.statistics {
        // the settings of sweeps/thesis-ch4-dense.ron: 25 slabs, r_max = 8 d
        let settings = crate::analysis::statistics::StatisticsSettings {
            r_max: 8.0,
            ..Default::default()
        };
        structure.with_statistics(crate::analysis::statistics::StatisticsPlan::every_snapshot(
            settings,
        ))
    } else {
        structure
    })
}

/// CPU model and core count, from /proc/cpuinfo where available, and the threads used.
fn machine(threads: usize) -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{model}, {cores} cores available, {threads} used")
}

/// Measure one workload in a process of its own (a fresh heap: its memory and speed do not
/// depend on the workloads before it): `granflow bench --json --workload NAME ...`.
fn measure_isolated(name: &str, args: &BenchArgs) -> anyhow::Result<BenchResult> {
    let search = match args.search {
        SearchChoice::Auto => "auto",
        SearchChoice::Cells => "cells",
        SearchChoice::Lists => "lists",
    };
    let out = std::process::Command::new(std::env::current_exe()?)
        .args(["bench", "--json", "--workload", name])
        .args([
            "--collisions-per-particle",
            &args.collisions_per_particle.to_string(),
        ])
        .args(["--channel-warmup", &args.channel_warmup.to_string()])
        .args(["--search", search, "--skin", &args.skin.to_string()])
        .args(["--site-updates", &args.site_updates.to_string()])
        .args(["--moves", &args.moves.to_string()])
        .args(["--snapshots", &args.snapshots.to_string()])
        .args(args.free_paths.then_some("--free-paths"))
        .args(args.statistics.then_some("--statistics"))
        .args(["--threads", &args.threads.to_string()])
        .args(["--dem-steps", &args.dem_steps.to_string()])
        .args(["--dem-warmup", &args.dem_warmup.to_string()])
        .args(["--dem-cache".as_ref(), dem_cache(args).as_os_str()])
        .stderr(std::process::Stdio::null())
        .output()?;
    anyhow::ensure!(
        out.status.success(),
        "the benchmark of {name} failed ({})",
        out.status
    );
    let mut rows: Vec<BenchResult> = serde_json::from_slice(&out.stdout)?;
    anyhow::ensure!(rows.len() == 1, "{name}: expected one result");
    Ok(rows.remove(0))
}

/// The DEM workloads' cache directory.
fn dem_cache(args: &BenchArgs) -> std::path::PathBuf {
    args.dem_cache
        .clone()
        .unwrap_or_else(bench_dem::default_cache)
}

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.collisions_per_particle > 0.0,
        "--collisions-per-particle must be > 0"
    );
    if let Some(dir) = &args.from_job {
        return run_from_job(dir, &args);
    }
    let Selection {
        edmd,
        lattice,
        dsmc,
        dem,
    } = select(&args)?;
    anyhow::ensure!(args.site_updates > 0.0, "--site-updates must be > 0");
    print_header(&args, !dem.is_empty());
    // several workloads: each in a process of its own
    anyhow::ensure!(args.moves > 0.0, "--moves must be > 0");
    anyhow::ensure!(args.threads >= 1, "--threads must be >= 1");
    anyhow::ensure!(args.dem_steps >= 1, "--dem-steps must be >= 1");
    let isolate = edmd.len() + lattice.len() + dsmc.len() + dem.len() > 1;
    anyhow::ensure!(
        args.lammps_out.is_none() || (dem.len() == 1 && !isolate),
        "--lammps-out writes one DEM workload: choose one with --workload (DEM workloads: {})",
        bench_dem::workloads()
            .iter()
            .map(|w| w.name)
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut results = bench_edmd(&edmd, isolate, &args)?;
    results.extend(bench_lga(&lattice, isolate, &args)?);
    results.extend(bench_dsmc(&dsmc, isolate, &args)?);
    results.extend(bench_dem(&dem, isolate, &args)?);
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&results)?);
    }
    Ok(())
}

/// The DEM options of the command line.
fn dem_options(args: &BenchArgs) -> DemBenchOptions {
    DemBenchOptions {
        warmup: args.dem_warmup,
        steps: args.dem_steps,
        threads: args.threads,
        cache: dem_cache(args),
        lammps_out: args.lammps_out.clone(),
    }
}

/// `--from-job`: the engine of a job's checkpoint (EDMD or DEM), measured as the job would run.
fn run_from_job(dir: &std::path::Path, args: &BenchArgs) -> anyhow::Result<()> {
    let saved = super::bench_job::saved_state(dir)?;
    let dem = crate::engine::envelope::open(&saved.engine)
        .ok()
        .filter(|s| s.engine == "dem");
    let dem_job = dem.is_some();
    let r = match dem {
        Some(sealed) => bench_dem::measure_from_job(dir, sealed, &dem_options(args))?,
        None => super::bench_job::measure(
            dir,
            &saved,
            args.search,
            args.skin,
            args.collisions_per_particle,
        )?,
    };
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&[r])?);
    } else if dem_job {
        outln!(
            "{}: N = {}: {:.4e} particle-steps/s on {} thread(s), {:.2} contacts per particle",
            r.workload,
            r.n,
            r.particle_steps_per_s.unwrap_or(f64::NAN),
            r.threads.unwrap_or(1),
            r.contacts_per_particle.unwrap_or(f64::NAN)
        );
    } else {
        outln!(
            "{}: N = {}, phi = {:.3}: {:.4e} collisions/s, {:.4e} events/s, {:.0} bytes/particle (engine)",
            r.workload,
            r.n,
            r.phi,
            r.collisions_per_s,
            r.events_per_s,
            r.bytes_per_particle
        );
    }
    Ok(())
}

/// The workloads `--workload` selects, by engine (DEM only when named).
struct Selection {
    edmd: Vec<Workload>,
    lattice: Vec<LgaWorkload>,
    dsmc: Vec<DsmcWorkload>,
    dem: Vec<DemWorkload>,
}

/// The workloads `--workload` names; none is an error listing them all.
fn select(args: &BenchArgs) -> anyhow::Result<Selection> {
    let names: Vec<&str> = workloads(args)
        .iter()
        .map(|w| w.name)
        .chain(lga_workloads().iter().map(|w| w.name))
        .chain(dsmc_workloads().iter().map(|w| w.name))
        .chain(bench_dem::workloads().iter().map(|w| w.name))
        .collect();
    // a workload's whole name selects that one alone, even where it is part of another's
    // (as the process of its own that measures it asks: `--workload NAME`)
    let exact = args.workload.as_deref().filter(|s| names.contains(s));
    let wanted = |name: &str| match exact {
        Some(whole) => name == whole,
        None => args
            .workload
            .as_ref()
            .is_none_or(|s| name.contains(s.as_str())),
    };
    let selected: Vec<Workload> = workloads(args)
        .into_iter()
        .filter(|w| wanted(w.name))
        .collect();
    let lattice: Vec<LgaWorkload> = lga_workloads()
        .into_iter()
        .filter(|w| wanted(w.name))
        .collect();
    let dsmc: Vec<DsmcWorkload> = dsmc_workloads()
        .into_iter()
        .filter(|w| wanted(w.name))
        .collect();
    // the DEM workloads only when named (their first run prepares and warms a channel for
    // many minutes): `--workload dem`
    let dem: Vec<DemWorkload> = bench_dem::workloads()
        .into_iter()
        .filter(|w| args.workload.is_some() && wanted(w.name))
        .collect();
    anyhow::ensure!(
        !selected.is_empty() || !lattice.is_empty() || !dsmc.is_empty() || !dem.is_empty(),
        "no workload matches {:?}; workloads: {}",
        args.workload.as_deref().unwrap_or(""),
        names.join(", ")
    );
    Ok(Selection {
        edmd: selected,
        lattice,
        dsmc,
        dem,
    })
}

/// The machine line and, for the table, its column titles.
fn print_header(args: &BenchArgs, dem: bool) {
    // only the DEM workloads run on more than one thread
    let machine = machine(if dem { args.threads } else { 1 });
    if args.json {
        eprintln!("machine: {machine}");
    } else {
        outln!("machine: {machine}");
        outln!(
            "{:<28} {:>7} {:>6} {:>14} {:>14} {:>10}  search",
            "workload",
            "n",
            "phi",
            "collisions/s",
            "events/s",
            "bytes/part"
        );
    }
}

/// The EDMD workloads, each line printed as it is measured.
fn bench_edmd(
    workloads: &[Workload],
    isolate: bool,
    args: &BenchArgs,
) -> anyhow::Result<Vec<BenchResult>> {
    let mut results = Vec::new();
    for w in workloads {
        let search = args.search_for(&w.params);
        let r = if isolate {
            measure_isolated(w.name, args)?
        } else {
            measure(w, search, args)?
        };
        if !args.json {
            let name = match search.search {
                NeighbourSearch::Cells => "cells".to_string(),
                NeighbourSearch::Lists { skin } => format!("lists, skin {skin}"),
            };
            let search = if search.adaptive {
                format!("auto, from {name}")
            } else {
                name
            };
            let record = r
                .record_seconds
                .map(|s| format!(", {:.1} ms per snapshot record", 1e3 * s))
                .unwrap_or_default();
            outln!(
                "{:<28} {:>7} {:>6.3} {:>14.4e} {:>14.4e} {:>10.0}  {search}{record}",
                r.workload,
                r.n,
                r.phi,
                r.collisions_per_s,
                r.events_per_s,
                r.bytes_per_particle
            );
        }
        results.push(r);
    }
    Ok(results)
}

/// The lattice-gas workloads.
fn bench_lga(
    workloads: &[LgaWorkload],
    isolate: bool,
    args: &BenchArgs,
) -> anyhow::Result<Vec<BenchResult>> {
    let mut results = Vec::new();
    for w in workloads {
        let r = if isolate {
            measure_isolated(w.name, args)?
        } else {
            measure_lga(w, args.site_updates)?
        };
        if !args.json {
            outln!(
                "{:<28} {:>7} {:>6.3} {:>14.4e} {:>14.4e} {:>10.1}  {:.4e} site updates/s",
                r.workload,
                r.n,
                r.phi,
                r.collisions_per_s,
                r.events_per_s,
                r.bytes_per_particle,
                r.site_updates_per_s.unwrap_or(f64::NAN)
            );
        }
        results.push(r);
    }
    Ok(results)
}

/// The DSMC workloads.
fn bench_dsmc(
    workloads: &[DsmcWorkload],
    isolate: bool,
    args: &BenchArgs,
) -> anyhow::Result<Vec<BenchResult>> {
    let mut results = Vec::new();
    for w in workloads {
        let r = if isolate {
            measure_isolated(w.name, args)?
        } else {
            measure_dsmc(w, args.moves)?
        };
        if !args.json {
            outln!(
                "{:<28} {:>7} {:>6} {:>14.4e} {:>14.4e} {:>10.1}  {:.4e} moves/s",
                r.workload,
                r.n,
                "-",
                r.collisions_per_s,
                r.events_per_s,
                r.bytes_per_particle,
                r.moves_per_s.unwrap_or(f64::NAN)
            );
        }
        results.push(r);
    }
    Ok(results)
}

/// The DEM workloads (on `--threads` threads).
fn bench_dem(
    workloads: &[DemWorkload],
    isolate: bool,
    args: &BenchArgs,
) -> anyhow::Result<Vec<BenchResult>> {
    let mut results = Vec::new();
    for w in workloads {
        let r = if isolate {
            measure_isolated(w.name, args)?
        } else {
            bench_dem::measure(w, &dem_options(args))?
        };
        if !args.json {
            outln!(
                "{:<28} {:>7} {:>6.3} {:>14.4e} {:>14.4e} {:>10.0}  {:.4e} particle-steps/s on {} \
                 thread(s), {:.2} contacts per particle",
                r.workload,
                r.n,
                r.phi,
                r.collisions_per_s,
                r.events_per_s,
                r.bytes_per_particle,
                r.particle_steps_per_s.unwrap_or(f64::NAN),
                r.threads.unwrap_or(1),
                r.contacts_per_particle.unwrap_or(f64::NAN)
            );
        }
        results.push(r);
    }
    Ok(results)
}

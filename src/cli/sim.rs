//! `granflow sim`: run one simulation of any registered engine from flags (or a RON file of
//! parameter values) and print progress, the engine's counters and, with `--analyse`, its
//! analysis. Bad input is rejected (exit 2) before anything is printed.

use super::out::outln;
use super::params::ParamFlags;
use crate::analysis::{self, Analyser, Analysis, JobAnalysis};
use crate::engine::{Clock, EngineDef, ParamValue, Snapshot, StopAt, Values};
use crate::registry;
use crate::sweep::BadInput;
use crate::sweep::ranges::RangeCall;
use crate::sweep::spec::{ParamValues, did_you_mean};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  # an EDMD channel (L/W = 2, W/d = H/d = 10, phi = 0.15), analysed at the end
  granflow sim --length-over-width 2 --width-over-diameter 10 --height-over-diameter 10 \\
      --volume-fraction 0.15 --restitution 0.7 --collisions-per-particle 2000 --analyse
  # snapshots for viewers every 100 collisions per particle: XYZ (ASE, OVITO), VTK (ParaView)
  granflow sim --length-over-width 2 --width-over-diameter 10 --height-over-diameter 10 \\
      --volume-fraction 0.15 --collisions-per-particle 1000 --report-every 100 \\
      --xyz frames --vtk fields
  # another engine, with its example values and one set
  granflow sim --engine dsmc --set knudsen_number=0.5 --time 20")]
pub struct SimArgs {
    /// the engine (see `granflow engines`)
    #[arg(long, default_value = "edmd")]
    pub engine: String,
    /// RON file of parameter values, as a sweep's `fixed` section: (restitution: 0.9, ...);
    /// flags and --set override it
    #[arg(long)]
    pub params: Option<PathBuf>,
    #[command(flatten)]
    pub flags: ParamFlags,
    /// set a parameter: key=value (repeatable; as in `granflow run --set`)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// seed of the portable RNG
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// run length in collisions per particle
    #[arg(long, group = "run_length")]
    pub collisions_per_particle: Option<f64>,
    /// run length in time steps
    #[arg(long, group = "run_length")]
    pub steps: Option<f64>,
    /// run length in simulated time
    #[arg(long, group = "run_length")]
    pub time: Option<f64>,
    /// report (and snapshot) every this much of the run's clock (default: the engine's
    /// example cadence, or a tenth of the run)
    #[arg(long)]
    pub report_every: Option<f64>,
    /// analyse the snapshots (the engine's analysis: steady window, spectra, profiles,
    /// structure label) and print it
    #[arg(long)]
    pub analyse: bool,
    /// write every snapshot, the initial one too, as extended XYZ (ASE, OVITO, ParaView) into
    /// this directory, named by the clock (snapshot-cpp0000100.xyz); particle engines
    #[arg(long, value_name = "DIR")]
    pub xyz: Option<PathBuf>,
    /// write the cellwise fields of every snapshot as legacy VTK cell data (ParaView) into this
    /// directory, named by the clock (fields-cpp0000100.vtk); particle engines
    #[arg(long, value_name = "DIR")]
    pub vtk: Option<PathBuf>,
    /// coarse-graining grid for --analyse and --vtk, as N1,N2,N3 (default: about 4 particles
    /// per cell)
    #[arg(long, value_name = "N1,N2,N3", value_delimiter = ',')]
    pub grid: Option<Vec<usize>>,
}

/// Everything `sim` needs, checked before anything runs.
struct Plan {
    engine: &'static EngineDef,
    values: Values,
    clock: Clock,
    length: f64,
    every: f64,
    analyser: Analyser,
}

fn bad(message: String) -> anyhow::Error {
    BadInput(message).into()
}

/// Gather and check the parameters: the engine's example values, then the RON file, the
/// flags, `--set`; then resolve them as a sweep would.
fn plan(args: &SimArgs) -> anyhow::Result<Plan> {
    let engine = registry::find(&args.engine).ok_or_else(|| {
        bad(format!(
            "--engine {}: no such engine; allowed: {}",
            args.engine,
            registry::names()
        ))
    })?;
    let values = resolve(engine, &given_values(args)?)?;
    let (clock, length, every) = run_length(args, engine)?;
    let analyser = analyser(args, engine)?;
    Ok(Plan {
        engine,
        values,
        clock,
        length,
        every,
        analyser,
    })
}

/// The values given, as (key, text, origin): the RON file, the flags, `--set`, in that order.
fn given_values(args: &SimArgs) -> anyhow::Result<Vec<(String, String, String)>> {
    let mut given: Vec<(String, String, String)> = Vec::new(); // (key, text, origin)
    if let Some(path) = &args.params {
        let text = std::fs::read_to_string(path)
            .map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))?;
        // read as a sweep file's `fixed` section is (values with or without `Some(..)`)
        let values: ParamValues = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(&text)
            .map_err(|e| bad(format!("{}: {e}", path.display())))?;
        for (k, v) in values.0 {
            let text = match v {
                ParamValue::Number(x) => format!("{x}"),
                ParamValue::Text(s) => s,
            };
            given.push((k, text, path.display().to_string()));
        }
    }
    for (k, v) in &args.flags.0 {
        given.push((
            k.to_string(),
            v.clone(),
            format!("--{}", k.replace('_', "-")),
        ));
    }
    for s in &args.set {
        let (k, v) = s
            .split_once('=')
            .ok_or_else(|| bad(format!("--set {s}: expected key=value")))?;
        if v.contains(',') || RangeCall::parse(v).is_some() {
            return Err(bad(format!(
                "--set {s}: sim runs one simulation, with one value per parameter; sweep \
                 lists and ranges with `granflow run` (a sweep file, or `run --set`)"
            )));
        }
        given.push((
            k.trim().to_string(),
            v.trim().to_string(),
            format!("--set {s}"),
        ));
    }
    Ok(given)
}

/// The engine's example values, replaced by those given (each checked, naming its origin),
/// resolved as a sweep would; the job's memory checked.
fn resolve(
    engine: &'static EngineDef,
    given: &[(String, String, String)],
) -> anyhow::Result<Values> {
    let mut values = Values::new();
    for (k, v) in engine.example {
        let def = engine.param(k).expect("examples name declared parameters");
        values.insert(k.to_string(), def.parse_text(v).map_err(bad)?);
    }
    for (key, text, origin) in given {
        let Some(def) = engine.param(key) else {
            let others = registry::engines_with_param(key, engine.name);
            let hint = did_you_mean(key, engine.params.iter().map(|d| d.name))
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            return Err(bad(if others.is_empty() {
                format!(
                    "{origin}: `{key}` is not a parameter of the {} engine{hint}; its parameters: {}",
                    engine.name,
                    engine.param_names()
                )
            } else {
                format!(
                    "{origin}: `{key}` is a parameter of {}, not of {} (use --engine)",
                    registry::engines_phrase(&others),
                    engine.name
                )
            }));
        };
        let value = def
            .parse_text(text)
            .map_err(|m| bad(format!("{origin}: {m}")))?;
        def.check_value(&value)
            .map_err(|m| bad(format!("{origin}: {m}")))?;
        for alt in engine.alternatives_of(key) {
            values.remove(alt);
        }
        values.insert(key.clone(), value);
    }
    let values = engine
        .resolve_values(&values)
        .map_err(|p| bad(format!("{}: {}", p.key, p.message)))?;
    crate::sweep::grid::check_job_memory(engine, &values).map_err(bad)?;
    Ok(values)
}

/// The run's clock, length and report interval: as given, else the engine's example run.
fn run_length(args: &SimArgs, engine: &'static EngineDef) -> anyhow::Result<(Clock, f64, f64)> {
    let lengths = [
        (Clock::CollisionsPerParticle, args.collisions_per_particle),
        (Clock::Steps, args.steps),
        (Clock::Time, args.time),
    ];
    let (clock, length, every) = match lengths.into_iter().find(|(_, v)| v.is_some()) {
        Some((clock, Some(length))) => {
            let every = args
                .report_every
                .unwrap_or(if clock == engine.example_run.0 {
                    engine.example_run.2.min(length)
                } else {
                    length / 10.0
                });
            (clock, length, every)
        }
        _ => {
            let (clock, length, every) = engine.example_run;
            (clock, length, args.report_every.unwrap_or(every))
        }
    };
    let mut run = crate::sweep::RunSettings::new(clock, length, every);
    run.checkpoint_every = 1;
    run.validate(engine).map_err(|(key, m)| {
        bad(format!(
            "--{}: {m}",
            if key == "snapshot_interval" {
                "report-every".to_string()
            } else {
                key.replace('_', "-")
            }
        ))
    })?;
    Ok((clock, length, every))
}

/// The analysis of the engine's snapshots with `--grid`; `--xyz` and `--vtk` only for
/// particles.
fn analyser(args: &SimArgs, engine: &'static EngineDef) -> anyhow::Result<Analyser> {
    let kind = registry::analysis_of(engine);
    let mut settings = kind.default_settings();
    if let Some(g) = &args.grid {
        if g.len() != 3 || g.contains(&0) {
            return Err(bad(format!(
                "--grid needs three cell counts >= 1, as N1,N2,N3 (got {g:?})"
            )));
        }
        settings["grid"] = serde_json::json!(g);
    }
    let analyser = kind
        .analyser(&settings)
        .map_err(|m| bad(format!("--grid: {m}")))?;
    if !matches!(analyser, Analyser::Structure(_)) {
        for (flag, given) in [("--xyz", args.xyz.is_some()), ("--vtk", args.vtk.is_some())] {
            if given {
                return Err(bad(format!(
                    "{flag}: the {} engine's snapshots carry no particles to write (engines \
                     with particles: {})",
                    engine.name,
                    particle_engines()
                )));
            }
        }
    }
    Ok(analyser)
}

pub fn run(args: SimArgs) -> anyhow::Result<()> {
    let plan = plan(&args)?;
    let engine_def = plan.engine;
    let mut engine = (engine_def.build)(&plan.values, args.seed)?;
    if let Some(p) = engine.preparation() {
        outln!(
            "preparing the initial state ({}, at most {} steps)",
            p.stage,
            p.max_steps
        );
        engine.prepare(u64::MAX)?;
    }
    for dir in [&args.xyz, &args.vtk].into_iter().flatten() {
        std::fs::create_dir_all(dir)
            .map_err(|e| anyhow::anyhow!("creating {}: {e}", dir.display()))?;
    }
    outln!("{}: {}", engine_def.name, engine_def.title);
    let shown: Vec<String> = engine_def
        .params
        .iter()
        .filter_map(|d| {
            plan.values
                .get(d.name)
                .map(|v| format!("{} = {}", d.symbol, crate::sweep::phase::fmt_value(v)))
        })
        .collect();
    outln!("{}; seed {}", shown.join(", "), args.seed);
    let clock = plan.clock;
    let started = Instant::now();
    let first = engine.snapshot();
    let mut header = format!("{:>12} {:>12}", clock.unit(), "time");
    if first.particles().is_some() {
        header.push_str(&format!(" {:>12} {:>12}", "E_trans/N", "E_rot/N"));
    }
    for ratio in engine_def.ratios {
        header.push_str(&format!(" {:>12}", short(ratio.name)));
    }
    header.push_str(&format!(" {:>12}", "events/s"));
    let mut records = Vec::new();
    let names = analysis::SnapshotNames::new(clock, plan.length, plan.every);
    write_snapshot_files(&args, &first, 0.0, &names, &plan)?;
    if args.analyse {
        records.push(plan.analyser.record(&first).map_err(anyhow::Error::msg)?);
    }
    outln!("{header}");
    let mut next = 0.0;
    while next < plan.length {
        next = (next + plan.every).min(plan.length);
        engine.advance(StopAt::on(clock, next))?;
        let s = engine.snapshot();
        write_snapshot_files(&args, &s, next, &names, &plan)?;
        if args.analyse {
            records.push(plan.analyser.record(&s).map_err(anyhow::Error::msg)?);
        }
        let mut line = format!("{:>12.1} {:>12.4}", s.progress.on(clock), s.progress.time);
        if let Some(p) = s.particles() {
            let n = p.len().max(1) as f64;
            line.push_str(&format!(
                " {:>12.5} {:>12.5}",
                p.translational_energy / n,
                p.rotational_energy / n
            ));
        }
        for ratio in engine_def.ratios {
            line.push_str(&format!(
                " {:>12.3e}",
                s.counters.get(ratio.numerator) as f64
                    / s.counters.get(ratio.denominator).max(1) as f64
            ));
        }
        line.push_str(&format!(
            " {:>12.3e}",
            s.progress.events as f64 / started.elapsed().as_secs_f64()
        ));
        outln!("{line}");
    }
    let s = engine.snapshot();
    let secs = started.elapsed().as_secs_f64();
    let counters: Vec<String> = s
        .counters
        .0
        .iter()
        .map(|(k, v)| format!("{v} {}", k.replace('_', " ")))
        .collect();
    outln!(
        "done in {secs:.1} s: {}; {:.3e} events/s",
        counters.join(", "),
        s.progress.events as f64 / secs
    );
    if args.analyse {
        match plan
            .analyser
            .analyse(&records)
            .map_err(anyhow::Error::msg)?
        {
            Analysis::Structure(a) => print_structure(&a),
            other => print_summary(&other),
        }
    }
    Ok(())
}

/// Print an analysis' summary as `key: value` lines (kinds without a dedicated printout).
fn print_summary(a: &Analysis) {
    outln!("\n== analysis ==");
    for (k, v) in a.summary() {
        outln!("{k}: {v}");
    }
}

/// The engines whose snapshots carry particles (those with the structure analysis).
fn particle_engines() -> String {
    registry::engines_analysed_by(|a| {
        matches!(
            a.analyser(&a.default_settings()),
            Ok(Analyser::Structure(_))
        )
    })
}

/// A column title from a ratio name (`tc_elastic_fraction` -> `TC frac`).
fn short(name: &str) -> String {
    match name {
        "tc_elastic_fraction" => "TC frac".into(),
        other => other.chars().take(12).collect(),
    }
}

/// Write the requested XYZ / VTK files of the snapshot `s`, taken at `reading` on the run's
/// clock (the planned point, so that names are round numbers; the files' headers carry the
/// exact time and collisions per particle).
fn write_snapshot_files(
    args: &SimArgs,
    s: &Snapshot,
    reading: f64,
    names: &analysis::SnapshotNames,
    plan: &Plan,
) -> anyhow::Result<()> {
    if let Some(dir) = &args.xyz {
        let path = dir.join(names.name("snapshot", reading, "xyz"));
        analysis::write_xyz(&path, s)
            .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))?;
    }
    if let (Some(dir), Analyser::Structure(settings)) = (&args.vtk, &plan.analyser) {
        let path = dir.join(names.name("fields", reading, "vtk"));
        analysis::write_vtk_density(&path, s, settings)
            .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))?;
    }
    Ok(())
}

/// Print a structure analysis: label and the numbers behind it, evolution, profiles.
fn print_structure(a: &JobAnalysis) {
    let s = &a.summary;
    outln!("\n== analysis ==");
    outln!(
        "label: {}{}{}",
        s.label,
        if s.humps > 0 {
            format!(" ({} humps)", s.humps)
        } else {
            String::new()
        },
        if s.three_dimensional {
            ", three-dimensional"
        } else {
            ""
        }
    );
    outln!(
        "steady: {}; window {:.0} .. {:.0} collisions/particle ({} snapshots)",
        s.steady,
        s.window_start,
        s.window_end,
        s.steady_snapshots
    );
    if !s.note.is_empty() {
        outln!("note: {}", s.note);
    }
    outln!(
        "grid {} x {} x {}, N = {}, shot-noise power per mode P0 = {:.3e}",
        s.grid_x,
        s.grid_y,
        s.grid_z,
        s.particles,
        s.noise_level
    );
    outln!(
        "{:<16} {:>12} {:>10} {:>10} {:>13}",
        "family",
        "power",
        "P/noise",
        "threshold",
        "significance"
    );
    let rows = [
        ("transverse", s.power_transverse, s.ratio_transverse),
        ("along-flow", s.power_along_flow, s.ratio_along_flow),
        (
            "antisymmetric",
            s.power_antisymmetric,
            s.ratio_antisymmetric,
        ),
        (
            "symmetric-rest",
            s.power_symmetric_rest,
            s.ratio_symmetric_rest,
        ),
        ("spanwise", s.power_spanwise, s.ratio_spanwise),
    ];
    let thresholds = [
        s.threshold_transverse,
        s.threshold_along_flow,
        s.threshold_antisymmetric,
        s.threshold_symmetric_rest,
        s.threshold_spanwise,
    ];
    let significance = [
        s.significance_transverse,
        s.significance_along_flow,
        s.significance_antisymmetric,
        s.significance_symmetric_rest,
        s.significance_spanwise,
    ];
    for (((name, p, r), t), g) in rows.into_iter().zip(thresholds).zip(significance) {
        outln!("{name:<16} {p:>12.4e} {r:>10.2} {t:>10.2} {g:>13.2}");
    }
    outln!(
        "family peaks (ratio/threshold): {}",
        analysis::modes::joined(&s.family_peaks)
    );
    outln!(
        "antisymmetric: fundamental k_x = {}, share in its odd harmonics {:.2}; slug significance {:.2}",
        s.antisymmetric_kx,
        s.antisymmetric_coherence,
        s.significance_slug
    );
    outln!(
        "dominant xy modes: {}",
        analysis::modes::joined(&s.dominant_modes)
    );
    outln!(
        "mean E_trans/N = {:.5}, E_rot/N = {:.5}, slip velocity U_x(wall) = {:.4}",
        s.mean_translational_energy,
        s.mean_rotational_energy,
        s.slip_velocity
    );
    let evolution: Vec<String> = a
        .evolution
        .iter()
        .map(|c| match c.humps {
            0 => format!("{} @ {:.0}", c.label, c.collisions_per_particle),
            h => format!("{} ({h}) @ {:.0}", c.label, c.collisions_per_particle),
        })
        .collect();
    outln!("evolution (per snapshot): {}", evolution.join(" -> "));
    let bins = a.profiles.iter().filter(|p| p.quantity == "phi").count();
    outln!(
        "{:>4} {:>7} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "bin",
        "y",
        "phi",
        "u_x",
        "omega_z",
        "T",
        "theta"
    );
    for b in 0..bins as u32 {
        let v = |q: &str| {
            a.profiles
                .iter()
                .find(|p| p.quantity == q && p.bin == b)
                .map_or(f64::NAN, |p| p.value)
        };
        let y = a
            .profiles
            .iter()
            .find(|p| p.bin == b)
            .map_or(f64::NAN, |p| p.y);
        outln!(
            "{b:>4} {y:>7.2} {:>8.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
            v("phi"),
            v("u_x"),
            v("omega_z"),
            v("T"),
            v("theta")
        );
    }
}

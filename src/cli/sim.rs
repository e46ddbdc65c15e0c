//! `granflow sim`: run one simulation from flags (or a small RON file of `EdmdParams`) and
//! print progress, the energies and the event counters.

use crate::analysis::{self, AnalysisSettings, JobAnalysis};
use crate::engine::edmd::{EdmdEngine, EdmdParams};
use crate::engine::{Engine, StopAt};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct SimArgs {
    /// RON file with the full engine parameters (EdmdParams); replaces the geometry and material flags
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// L/W, channel length over width
    #[arg(long, default_value_t = 3.0)]
    pub length_over_width: f64,
    /// W/d, channel width in particle diameters
    #[arg(long, default_value_t = 15.0)]
    pub width_over_diameter: f64,
    /// H/d, channel height (span) in particle diameters
    #[arg(long, default_value_t = 15.0)]
    pub height_over_diameter: f64,
    /// phi, volume fraction
    #[arg(long, default_value_t = 0.15)]
    pub volume_fraction: f64,
    /// e, particle-particle normal restitution
    #[arg(long, default_value_t = 0.7)]
    pub restitution: f64,
    /// beta, particle-particle tangential restitution
    #[arg(long, default_value_t = 0.1)]
    pub roughness: f64,
    /// e_w, particle-wall normal restitution
    #[arg(long, default_value_t = 0.99)]
    pub wall_restitution: f64,
    /// beta_w, particle-wall tangential restitution
    #[arg(long, default_value_t = 0.99)]
    pub wall_roughness: f64,
    /// t_c of the TC model (0 switches it off)
    #[arg(long, default_value_t = EdmdParams::DEFAULT_TC)]
    pub tc: f64,
    /// seed of the portable RNG
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// run length in collisions per particle
    #[arg(long, default_value_t = 1000.0)]
    pub collisions_per_particle: f64,
    /// report (and snapshot) every this many collisions per particle
    #[arg(long, default_value_t = 100.0)]
    pub report_every: f64,
    /// analyse the snapshots (steady window, spectra, profiles, structure label) and print it
    #[arg(long)]
    pub analyse: bool,
    /// write every snapshot as extended XYZ (OVITO, ParaView) into this directory
    #[arg(long, value_name = "DIR")]
    pub xyz: Option<PathBuf>,
    /// write the cellwise fields of every snapshot as legacy VTK (ParaView) into this directory
    #[arg(long, value_name = "DIR")]
    pub vtk: Option<PathBuf>,
    /// coarse-graining grid for --analyse and --vtk, as N1,N2,N3 (default: about 4 particles
    /// per cell)
    #[arg(long, value_name = "N1,N2,N3", value_delimiter = ',')]
    pub grid: Option<Vec<usize>>,
}

pub fn run(args: SimArgs) -> anyhow::Result<()> {
    let params = match &args.params {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            ron::from_str::<EdmdParams>(&text)
                .with_context(|| format!("parsing {}", path.display()))?
        }
        None => {
            let w = args.width_over_diameter;
            let mut p = EdmdParams::channel(
                args.length_over_width * w,
                w,
                args.height_over_diameter,
                args.volume_fraction,
                args.seed,
            );
            p.restitution = args.restitution;
            p.roughness = args.roughness;
            p.wall_restitution = args.wall_restitution;
            p.wall_roughness = args.wall_roughness;
            p.tc = args.tc;
            p
        }
    };
    anyhow::ensure!(args.report_every > 0.0, "--report-every must be > 0");
    let g = params.geometry;
    println!(
        "EDMD: N = {}, box {} x {} x {} ({}), phi = {:.4}, e = {}, beta = {}, e_w = {}, beta_w = {}, tc = {:e}",
        params.particles,
        g.length,
        g.width,
        g.height,
        if g.walls {
            "walls at y = 0, W"
        } else {
            "periodic"
        },
        params.volume_fraction(),
        params.restitution,
        params.roughness,
        params.wall_restitution,
        params.wall_roughness,
        params.tc
    );
    let mut settings = AnalysisSettings::default();
    if let Some(g) = &args.grid {
        anyhow::ensure!(
            g.len() == 3 && g.iter().all(|&k| k >= 1),
            "--grid needs three cell counts >= 1, as N1,N2,N3 (got {g:?})"
        );
        settings.grid = Some([g[0], g[1], g[2]]);
    }
    settings.validate().map_err(anyhow::Error::msg)?;
    for dir in [&args.xyz, &args.vtk].into_iter().flatten() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut records = Vec::new();
    let mut snapshots = 0usize;
    let mut engine = EdmdEngine::new(params)?;
    let n = engine.particle_count() as f64;
    let started = Instant::now();
    println!(
        "{:>10} {:>12} {:>12} {:>12} {:>10} {:>12}",
        "coll/part", "time", "E_trans/N", "E_rot/N", "TC frac", "events/s"
    );
    let mut next = 0.0;
    while next < args.collisions_per_particle {
        next = (next + args.report_every).min(args.collisions_per_particle);
        engine.advance(StopAt::CollisionsPerParticle(next))?;
        let s = engine.snapshot();
        write_snapshot_files(&args, &s, &settings, snapshots)?;
        snapshots += 1;
        if args.analyse {
            records.push(analysis::record_snapshot(&s, &settings));
        }
        let c = s.counters;
        println!(
            "{:>10.1} {:>12.4} {:>12.5} {:>12.5} {:>10.2e} {:>12.3e}",
            s.collisions_per_particle,
            s.time,
            s.translational_energy / n,
            s.rotational_energy / n,
            c.tc_elastic_collisions as f64 / c.pair_collisions.max(1) as f64,
            c.events as f64 / started.elapsed().as_secs_f64()
        );
    }
    let s = engine.snapshot();
    let c = s.counters;
    let secs = started.elapsed().as_secs_f64();
    println!(
        "done: {} pair collisions, {} wall collisions, {} cell crossings, {} events in {secs:.1} s \
         ({:.3e} collisions/s); TC-elastic fraction {:.3e}",
        c.pair_collisions,
        c.wall_collisions,
        c.cell_crossings,
        c.events,
        c.pair_collisions as f64 / secs,
        c.tc_elastic_collisions as f64 / c.pair_collisions.max(1) as f64
    );
    if args.analyse {
        print_analysis(&analysis::analyse_job(&records, &settings));
    }
    Ok(())
}

/// Write the requested XYZ / VTK files of snapshot number `index`.
fn write_snapshot_files(
    args: &SimArgs,
    s: &crate::engine::Snapshot,
    settings: &AnalysisSettings,
    index: usize,
) -> anyhow::Result<()> {
    if let Some(dir) = &args.xyz {
        let path = dir.join(format!("snapshot_{index:05}.xyz"));
        analysis::write_xyz(&path, s).with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(dir) = &args.vtk {
        let path = dir.join(format!("fields_{index:05}.vtk"));
        analysis::write_vtk_density(&path, s, settings)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// Print a job analysis: label and the numbers behind it, evolution, profiles.
fn print_analysis(a: &JobAnalysis) {
    let s = &a.summary;
    println!("\n== analysis ==");
    println!(
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
    println!(
        "steady: {}; window {:.0} .. {:.0} collisions/particle ({} snapshots)",
        s.steady, s.window_start, s.window_end, s.steady_snapshots
    );
    if !s.note.is_empty() {
        println!("note: {}", s.note);
    }
    println!(
        "grid {} x {} x {}, N = {}, shot-noise power per mode P0 = {:.3e}",
        s.grid_x, s.grid_y, s.grid_z, s.particles, s.noise_level
    );
    println!(
        "{:<16} {:>12} {:>10} {:>10} {:>13}",
        "family", "power", "P/noise", "threshold", "significance"
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
        println!("{name:<16} {p:>12.4e} {r:>10.2} {t:>10.2} {g:>13.2}");
    }
    println!("family peaks (ratio/threshold): {}", s.family_peaks);
    println!(
        "antisymmetric: dominant k_x = {}, coherence {:.2}",
        s.antisymmetric_kx, s.antisymmetric_coherence
    );
    println!("dominant xy modes: {}", s.dominant_modes);
    println!(
        "mean E_trans/N = {:.5}, E_rot/N = {:.5}, slip velocity U_x(wall) = {:.4}",
        s.mean_translational_energy, s.mean_rotational_energy, s.slip_velocity
    );
    let evolution: Vec<String> = a
        .evolution
        .iter()
        .map(|c| match c.humps {
            0 => format!("{} @ {:.0}", c.label, c.collisions_per_particle),
            h => format!("{} ({h}) @ {:.0}", c.label, c.collisions_per_particle),
        })
        .collect();
    println!("evolution (per snapshot): {}", evolution.join(" -> "));
    let bins = a.profiles.iter().filter(|p| p.quantity == "phi").count();
    println!(
        "{:>4} {:>7} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "bin", "y", "phi", "u_x", "omega_z", "T", "theta"
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
        println!(
            "{b:>4} {y:>7.2} {:>8.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
            v("phi"),
            v("u_x"),
            v("omega_z"),
            v("T"),
            v("theta")
        );
    }
}

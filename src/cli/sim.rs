//! `granflow sim`: run one simulation from flags (or a small RON file of `EdmdParams`) and
//! print progress, the energies and the event counters.

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
    Ok(())
}

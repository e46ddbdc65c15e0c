//! Refinement bookkeeping at scale (docs/sweeps.md, "Refinement"; target: 10 000 jobs in
//! under a second): the refine stage's replay of every round from the jobs' outcomes
//! (`granflow::sweep::rounds::replay_with`, what `run`, `status`, `gather` and `report` do
//! before they start), on a 2D sweep whose label changes across a circle. The outcomes come
//! from memory, so this times the rules, the expansion of the refined points and their ids,
//! not the reading of the job directories.
//!
//!     cargo bench --bench refine_bookkeeping
//!
//! Prints the jobs and rounds of the refined sweep, the finest spacing reached, the jobs a
//! regular grid of that spacing would need, and the replay's wall time (median of 5).

use granflow::sweep::{load_sweep, rounds::replay_with};
use std::time::Instant;

/// 11 x 11 base densities x bounce-back probabilities of the lattice gas (any engine would do:
/// nothing runs), refined on the label over 7 levels with a budget of 10 000 jobs.
const SWEEP: &str = r#"(
    engine: "lga",
    fixed: (length: 220, width: 11, gravity_probability: 0.5, dissipation: 0.5),
    axes: (
        density: [0.2, 0.48, 0.76, 1.04, 1.32, 1.6, 1.88, 2.16, 2.44, 2.72, 3.0],
        bounce_back: [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0],
    ),
    refine: (axes: ["density", "bounce_back"], levels: 7, budget: 10000),
    run: (steps: 1000, snapshot_interval: 10, checkpoint_every: 100),
)"#;

fn main() {
    let dir = std::env::temp_dir().join(format!("granflow-refine-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("refine-bench.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    // "waves" inside a circle of radius 0.9 (in density) around (1.6, 0.5), "homogeneous" outside
    let label = |rho: f64, b: f64| {
        let r2 = (rho - 1.6).powi(2) + ((b - 0.5) * 2.8).powi(2);
        if r2 < 0.81 { "waves" } else { "homogeneous" }
    };
    let outcome = |job: &granflow::sweep::PlannedJob| {
        let l = label(job.params.get("density"), job.params.get("bounce_back"));
        Some(Some((l.to_string(), serde_json::Map::new())))
    };
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        let start = Instant::now();
        let refined = replay_with(&sweep, &outcome).unwrap();
        times.push(start.elapsed().as_secs_f64());
        last = Some(refined);
    }
    times.sort_by(f64::total_cmp);
    let refined = last.unwrap();
    let jobs = refined.sweep.plan.len();
    let finest = refined
        .sweep
        .plan
        .iter()
        .map(|j| j.level)
        .max()
        .unwrap_or(0);
    let per_axis = 10 * (1usize << finest) + 1;
    println!(
        "refine_bookkeeping: {jobs} jobs ({} base + {} refined in {} rounds, complete: {}), \
         finest level {finest} (1/{} of the base spacing); a regular grid of that spacing: \
         {per_axis} x {per_axis} = {} jobs ({:.1}x more)",
        121,
        jobs - 121,
        refined.rounds.len(),
        refined.complete,
        1usize << finest,
        per_axis * per_axis,
        (per_axis * per_axis) as f64 / jobs as f64
    );
    println!(
        "replay of all rounds: median {:.3} s (min {:.3}, max {:.3}) over 5",
        times[2], times[0], times[4]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

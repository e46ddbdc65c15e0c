//! `granflow bench --from-job DIR`: the engine's speed on a state a job saved (its last
//! checkpoint), e.g. a dense slug of a channel, where the standard workloads say little. The
//! run goes on as a job would, a snapshot every tenth of the timed stretch, so that the
//! automatic neighbour search re-chooses at the same points as in a run.

use super::bench_result::{BenchResult, SearchChoice};
use crate::engine::edmd::{EdmdEngine, NeighbourSearch};
use crate::engine::{Engine, StopAt};
use crate::sweep::store::JobCheckpoint;
use anyhow::Context;
use std::path::Path;
use std::time::Instant;

/// Untimed collisions per particle before the timed stretch: the automatic search has chosen
/// by then (it needs two; the first snapshot after them decides).
const WARMUP: f64 = 2.5;

/// The last checkpoint of the job in `dir`, which a measurement continues from.
pub fn saved_state(dir: &Path) -> anyhow::Result<JobCheckpoint> {
    crate::sweep::store::read_checkpoint(dir)?.ok_or_else(|| {
        anyhow::anyhow!("{}: the job has no checkpoint to start from", dir.display())
    })
}

/// The workload name of a measurement from the job in `dir` at simulated time `time`.
pub fn workload_name(dir: &Path, time: f64) -> String {
    let name = dir.file_name().map_or_else(
        || dir.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    format!("job {name} at t = {time:.1}")
}

/// Time `measured_cpp` collisions per particle of the EDMD job in `dir`, continued from its
/// checkpoint `saved` with the given search.
pub fn measure(
    dir: &Path,
    saved: &JobCheckpoint,
    search: SearchChoice,
    skin: f64,
    measured_cpp: f64,
) -> anyhow::Result<BenchResult> {
    // the engine's own decoding refuses another engine's checkpoint, saying whose it is
    let restored = match search {
        SearchChoice::Auto => EdmdEngine::restore(&saved.engine),
        SearchChoice::Cells => {
            EdmdEngine::restore_with_search(&saved.engine, NeighbourSearch::Cells)
        }
        SearchChoice::Lists => {
            EdmdEngine::restore_with_search(&saved.engine, NeighbourSearch::Lists { skin })
        }
    };
    let mut engine = restored.with_context(|| {
        format!(
            "{}: --from-job measures EDMD jobs from their checkpoint",
            dir.display()
        )
    })?;
    let n = engine.params().particles;
    let start = engine.progress().collisions_per_particle + WARMUP;
    engine.advance(StopAt::CollisionsPerParticle(start))?;
    engine.snapshot();
    let before = engine.progress();
    let started = Instant::now();
    for k in 1..=10 {
        let at = start + measured_cpp * k as f64 / 10.0;
        engine.advance(StopAt::CollisionsPerParticle(at))?;
        engine.snapshot();
    }
    let secs = started.elapsed().as_secs_f64();
    let after = engine.progress();
    let collisions =
        (after.collisions_per_particle - before.collisions_per_particle) * n as f64 / 2.0;
    Ok(BenchResult {
        workload: workload_name(dir, before.time),
        n,
        phi: engine.params().volume_fraction(),
        collisions_per_s: collisions / secs,
        events_per_s: (after.events - before.events) as f64 / secs,
        bytes_per_particle: engine.bytes_per_particle(),
        site_updates_per_s: None,
        moves_per_s: None,
        record_seconds: None,
        particle_steps_per_s: None,
        contacts_per_particle: None,
        threads: None,
    })
}

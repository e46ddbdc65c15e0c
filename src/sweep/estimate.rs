//! What a sweep will cost, from what is known: each job's work (in its engine's work units) on
//! its own clock, calibrated by what the sweep's own jobs have measured, and the wall time of
//! the sweep on a number of threads scheduled as the runner schedules it (longest job first).
//!
//! Calibration, from the job directories alone:
//! - the **rate** (work units per core-second): the summed work of the sweep's finished jobs
//!   and of its unfinished jobs to their checkpoints, over the wall seconds each took (a
//!   checkpoint keeps them); without either, each job's engine's typical rate at the job's
//!   size (its declaration's `work_rate`);
//! - for runs measured in simulated time on an engine that counts collisions, the **collisions
//!   per particle per time unit**: the job's own, when its checkpoint says how far it got;
//!   else the median over the sweep's finished and checkpointed jobs; else the engine's
//!   assumption (inside its `work`);
//! - a run **until steady** may stop anywhere between its last milestone (or the length of its
//!   steady window, which it must span first) and its cap: its work is given as that range, the estimate uses the cap unless finished jobs of
//!   the sweep stopped earlier, then the median of their stopping points as a fraction of the
//!   cap.

use super::PlannedJob;
use super::store::{self, JobResult, JobState};
use super::tables::GatheredJob;
use crate::engine::{Clock, Progress};

/// The estimate of one job.
#[derive(Clone, Debug, PartialEq)]
pub struct JobEstimate {
    /// work still to do (0 when done), in the engine's work units
    pub remaining: f64,
    /// the least and most work the whole job may take (equal unless it runs until steady)
    pub least: f64,
    pub most: f64,
    /// core-seconds still to go at the calibrated rate
    pub seconds: f64,
}

/// The estimates of a sweep's jobs and how they were calibrated.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepEstimate {
    pub jobs: Vec<JobEstimate>,
    /// work units per core-second measured on the sweep's own jobs (None: each job's
    /// engine's typical rate at its size was used)
    pub measured_rate: Option<f64>,
    /// where the rate comes from (for the reader)
    pub rate_basis: String,
}

impl SweepEstimate {
    /// Core-seconds still to go.
    pub fn core_seconds(&self) -> f64 {
        self.jobs.iter().map(|j| j.seconds).sum()
    }

    /// Wall seconds on `threads` threads: the remaining jobs, longest first, each to the
    /// thread that frees first (the runner's order).
    pub fn wall_seconds(&self, threads: usize) -> f64 {
        super::eta::longest_first_wall_seconds(
            self.jobs.iter().map(|j| j.seconds).collect(),
            threads,
        )
    }
}

/// The work a finished job did, on the clock its engine's work counts best (collisions per
/// particle where it has them), from its final readings.
fn work_done(job: &PlannedJob, result: &JobResult) -> f64 {
    let def = job.params.def();
    let clock = work_clock(job);
    (def.work)(&job.params.values, clock, result.clock(clock))
}

fn work_clock(job: &PlannedJob) -> Clock {
    let def = job.params.def();
    if def.has_clock(Clock::CollisionsPerParticle) {
        Clock::CollisionsPerParticle
    } else {
        job.params.run.clock()
    }
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    })
}

/// Estimate every job of a gathered sweep (see the module doc).
pub fn estimate(
    jobs: &[GatheredJob],
    sweep_dir: &dyn Fn(&PlannedJob) -> std::path::PathBuf,
) -> SweepEstimate {
    let finished: Vec<(&PlannedJob, &JobResult)> = jobs
        .iter()
        .filter_map(|j| j.result.as_ref().map(|r| (j.job, r)))
        .collect();
    // each unfinished job's checkpoint, read once: its clocks and the wall seconds to reach it
    let measured: Vec<Option<(Progress, f64)>> = jobs
        .iter()
        .map(|j| match j.state {
            JobState::Running | JobState::Partial(_) => {
                store::checkpoint_measure(&sweep_dir(j.job))
            }
            _ => None,
        })
        .collect();
    // unfinished jobs that got somewhere: the work to their checkpoint over the wall seconds
    // they had run to reach it
    let checkpointed: Vec<(f64, f64)> = jobs
        .iter()
        .zip(&measured)
        .filter_map(|(j, m)| {
            let (progress, secs) = (*m)?;
            let clock = work_clock(j.job);
            let work = (j.job.params.def().work)(&j.job.params.values, clock, progress.on(clock));
            (work > 0.0 && secs > 0.0).then_some((work, secs))
        })
        .collect();
    let (work, secs) = finished
        .iter()
        .map(|(job, r)| (work_done(job, r), r.wall_seconds))
        .chain(checkpointed.iter().copied())
        .fold((0.0, 0.0), |(w, s), (dw, ds)| (w + dw, s + ds));
    let engine = jobs.first().map(|j| j.job.params.def());
    let measured_on = match checkpointed.len() {
        0 => format!("{} finished jobs", finished.len()),
        n => format!(
            "{} finished and {n} unfinished jobs (to their checkpoints)",
            finished.len()
        ),
    };
    // the sweep's measured rate, else each job's engine's typical rate at its size
    let typical = |j: &GatheredJob| (j.job.params.def().work_rate)(&j.job.params.values);
    let (measured_rate, rate_basis) = match engine {
        Some(def) if secs > 0.0 && work > 0.0 => (
            Some(work / secs),
            format!(
                "the rate measured on {measured_on} of this sweep ({:.3e} {}/s)",
                work / secs,
                def.work_unit
            ),
        ),
        Some(def) => {
            let rates: Vec<f64> = jobs.iter().map(typical).collect();
            let (lo, hi) = rates.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
                (lo.min(r), hi.max(r))
            });
            let range = if hi > lo * 1.0001 {
                format!("{lo:.1e}-{hi:.1e} (by size)")
            } else {
                format!("{lo:.1e}")
            };
            (
                None,
                format!(
                    "the {} engine's typical {range} {}/s (no job of this sweep has run yet)",
                    def.name, def.work_unit
                ),
            )
        }
        None => (Some(1.0), String::new()),
    };
    // collisions per particle per time unit, from every job that got somewhere
    let progress_of = |j: &GatheredJob, m: &Option<(Progress, f64)>| match &j.state {
        JobState::Done => j
            .result
            .as_ref()
            .map(|r| (r.collisions_per_particle, r.time)),
        JobState::Partial(p) => Some((p.collisions_per_particle, p.time)),
        JobState::Running => m.map(|(p, _)| (p.collisions_per_particle, p.time)),
        _ => None,
    };
    let ratio = |p: Option<(f64, f64)>| p.and_then(|(c, t)| (t > 0.0 && c > 0.0).then(|| c / t));
    let sweep_cpp_per_time = median(
        jobs.iter()
            .zip(&measured)
            .filter_map(|(j, m)| ratio(progress_of(j, m)))
            .collect(),
    );
    // runs until steady: where the finished ones stopped, as a fraction of their cap
    let stopped_fraction = median(
        finished
            .iter()
            .filter(|(job, _)| job.params.run.until_steady.is_some())
            .map(|(job, r)| r.clock(job.params.run.clock()) / job.params.run.length())
            .collect(),
    );
    let estimates = jobs
        .iter()
        .zip(&measured)
        .map(|(j, m)| {
            let p = &j.job.params;
            let def = p.def();
            let run = &p.run;
            let clock = run.clock();
            let cpp_per_time = ratio(progress_of(j, m)).or(sweep_cpp_per_time);
            // work of a run to `reading` on the run's clock
            let work_to = |reading: f64| match (clock, cpp_per_time) {
                (Clock::Time, Some(rate)) if def.has_clock(Clock::CollisionsPerParticle) => {
                    (def.work)(&p.values, Clock::CollisionsPerParticle, reading * rate)
                }
                _ => (def.work)(&p.values, clock, reading),
            };
            let most = work_to(run.length());
            let least = if let Some(until) = &run.until_steady {
                // it cannot stop before its steady window spans `window` on its clock
                let window = work_to(until.window.min(run.length()));
                let floor = run
                    .milestone_plan(def)
                    .filter(|plan| {
                        plan.clock == clock || plan.clock == Clock::CollisionsPerParticle
                    })
                    .and_then(|plan| plan.readings.last().copied().map(|m| (plan.clock, m)));
                match floor {
                    Some((Clock::CollisionsPerParticle, m)) => {
                        (def.work)(&p.values, Clock::CollisionsPerParticle, m).min(most)
                    }
                    Some((_, m)) => work_to(m).min(most),
                    None => 0.0,
                }
                .max(window)
            } else {
                most
            };
            let expected = match (run.until_steady.is_some(), stopped_fraction) {
                (true, Some(f)) => (f * most).clamp(least, most),
                _ => most,
            };
            let done_so_far = match &j.state {
                JobState::Done => f64::INFINITY,
                JobState::Partial(pr) => work_to(pr.on(clock)),
                JobState::Running => m.map_or(0.0, |(pr, _)| work_to(pr.on(clock))),
                _ => 0.0,
            };
            let remaining = (expected - done_so_far).max(0.0);
            JobEstimate {
                remaining,
                least,
                most,
                seconds: remaining / measured_rate.unwrap_or_else(|| typical(j)),
            }
        })
        .collect();
    SweepEstimate {
        jobs: estimates,
        measured_rate,
        rate_basis,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_skips_what_is_not_finite() {
        assert_eq!(median(vec![3.0, f64::NAN, 1.0]), Some(2.0));
        assert_eq!(median(vec![f64::NAN]), None);
    }
}

//! The local runner: claims jobs that are not done, runs them on a rayon pool (largest estimated
//! work first), shows one progress line for the sweep and one per running job, and hands every
//! outcome to a single writer thread over a crossbeam channel.

use super::eta::SweepEta;
use super::execute::{self, JobEnd};
use super::grid::PlannedJob;
use super::store::{self, Claim, JobResult, JobState, NotClaimed};
use super::{Sweep, SweepDirs, tables};
use crossbeam_channel::unbounded;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Options of a run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// worker threads (jobs run at once)
    pub threads: usize,
    /// retry jobs that failed before
    pub retry_failed: bool,
    /// rerun done jobs made by another engine or analysis version
    pub rerun_outdated: bool,
    /// only jobs whose plan index lies in [start, end)
    pub job_range: Option<(usize, usize)>,
    /// write the tables at the end
    pub write_tables: bool,
    /// write the resolved sweep into the results directory first (not for Slurm tasks that
    /// run a submission's job ids: the file is the submission's, written once)
    pub write_resolved: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            retry_failed: false,
            rerun_outdated: false,
            job_range: None,
            write_tables: true,
            write_resolved: true,
        }
    }
}

/// What a run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// jobs selected (plan or range)
    pub selected: usize,
    /// done before this run started
    pub already_done: usize,
    /// finished by this run
    pub finished: usize,
    /// failed in this run
    pub failed: usize,
    /// skipped: failed earlier (without --retry-failed)
    pub skipped_failed: usize,
    /// skipped: held by another runner
    pub busy: usize,
    /// done but outdated, set aside and run again (`rerun_outdated`)
    pub outdated: usize,
    /// the first resource error (full disk, quota, I/O error) that stopped the run from
    /// starting new jobs; the jobs it hit stay resumable
    pub halted: Option<String>,
}

enum Outcome {
    Finished(Box<JobResult>),
    Failed(String),
    /// the job's lock file was deleted or replaced: no result, not failed
    ClaimLost(String),
    /// a resource error (full disk, ...): the job stays resumable, the run stops starting jobs
    Halted(String),
}

struct Message<'a> {
    job: &'a PlannedJob,
    claim: Claim,
    outcome: Outcome,
}

/// Wall-clock seconds between the plain progress lines of a run without a terminal:
/// `GRANFLOW_PROGRESS_SECONDS`, default 60.
fn progress_interval() -> std::time::Duration {
    let secs = std::env::var("GRANFLOW_PROGRESS_SECONDS")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v >= 0.0)
        .unwrap_or(60.0);
    std::time::Duration::from_secs_f64(secs)
}

/// Select the jobs of a plan in `range` (plan indices [start, end)).
pub fn select(plan: &[PlannedJob], range: Option<(usize, usize)>) -> Vec<&PlannedJob> {
    plan.iter()
        .filter(|j| range.is_none_or(|(a, b)| j.index >= a && j.index < b))
        .collect()
}

/// Run the jobs of a sweep that are not done yet; write the tables at the end.
pub fn run_sweep(sweep: &Sweep, dirs: &SweepDirs, opts: &RunOptions) -> anyhow::Result<RunSummary> {
    if opts.write_resolved {
        sweep.write_resolved(dirs)?;
    }
    let selected = select(&sweep.plan, opts.job_range);
    let mut summary = RunSummary {
        selected: selected.len(),
        ..Default::default()
    };
    let mut todo = Vec::new();
    for job in &selected {
        let dir = dirs.job_dir(&job.id);
        store::init_job_dir(&dir, job)?;
        // with --retry-failed, done results are read and checked too (damaged ones are then
        // set aside and recomputed; a damaged parameters file is set aside and written anew)
        let mut state = store::job_state_checked(&dir, opts.retry_failed);
        if let JobState::Damaged {
            file: store::PARAMS_FILE,
            reason,
        } = &state
            && opts.retry_failed
            && store::repair_params(&dir, job, reason)?
        {
            state = store::job_state_checked(&dir, true);
        }
        match state {
            JobState::Done if opts.rerun_outdated => {
                let def = job.params.def();
                match store::retire_if_outdated(
                    &dir,
                    def.version,
                    crate::registry::analysis_of(def).version(),
                )? {
                    Some(_) => {
                        summary.outdated += 1;
                        todo.push(*job)
                    }
                    None => summary.already_done += 1,
                }
            }
            JobState::Done => {
                store::complete_done_log(&dir)?;
                summary.already_done += 1
            }
            JobState::Failed(_) | JobState::Damaged { .. } if !opts.retry_failed => {
                summary.skipped_failed += 1
            }
            _ => todo.push(*job),
        }
    }
    // largest estimated work first; plan order among equals
    todo.sort_by(|a, b| {
        b.params
            .estimated_work()
            .total_cmp(&a.params.estimated_work())
            .then(a.index.cmp(&b.index))
    });

    let interactive = std::io::stderr().is_terminal();
    let progress_every = progress_interval();
    let multi = MultiProgress::new();
    if !interactive {
        multi.set_draw_target(ProgressDrawTarget::hidden());
    }
    let say = |line: String| {
        if interactive {
            let _ = multi.println(line);
        } else {
            super::say(&line);
        }
    };
    let total_work: f64 = todo.iter().map(|j| j.params.estimated_work()).sum();
    let eta = SweepEta::new(
        todo.iter().map(|j| j.params.estimated_work()).collect(),
        opts.threads.max(1),
    );
    let overall = multi.add(ProgressBar::new(total_work.max(1.0) as u64));
    overall.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {msg}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    overall.set_message("ETA ?");
    // jobs done and failed in this run
    let counts = Mutex::new((0usize, 0usize));
    // jobs with a result: the sweep line counts them, failed and stopped jobs apart
    let done_count = AtomicUsize::new(summary.already_done);
    super::running::set_done(summary.already_done);
    let set_overall = |done: usize| {
        overall.set_prefix(format!(
            "{}: {done}/{} jobs done",
            sweep.name,
            selected.len()
        ));
    };
    set_overall(summary.already_done);
    // without a terminal: the sweep's progress as a plain line, after each finished job and at
    // most once per progress interval while jobs run
    let last_sweep_line = Mutex::new(std::time::Instant::now());
    let sweep_line = |done: usize| {
        let fraction = overall.position() as f64 / overall.length().unwrap_or(1).max(1) as f64;
        let eta = if fraction < 1.0 {
            eta.text()
        } else {
            String::new()
        };
        let failed = counts.lock().expect("counts").1;
        format!(
            "sweep   {}: {done}/{} jobs done{}, {:.0} % of the estimated work{eta}",
            sweep.name,
            selected.len(),
            if failed > 0 {
                format!(" ({failed} failed)")
            } else {
                String::new()
            },
            100.0 * fraction
        )
    };
    say(format!(
        "sweep {}: {} selected, {} done, {} to run{} on {} (results in {})",
        sweep.name,
        counted(selected.len(), "job"),
        summary.already_done,
        todo.len(),
        if summary.outdated > 0 {
            format!(" ({} of them outdated results)", summary.outdated)
        } else {
            String::new()
        },
        counted(opts.threads, "thread"),
        dirs.tables.display()
    ));

    // a job is named by its swept parameters in progress lines (its id where nothing varies)
    let swept = super::phase::swept_in(sweep);
    let point_of = |job: &PlannedJob| super::phase::point_text(sweep.engine(), &job.params, &swept);
    let point = swept.clone();
    let (tx, rx) = unbounded::<Message>();
    let next = AtomicUsize::new(0);
    let busy = AtomicUsize::new(0);
    let halted: Mutex<Option<String>> = Mutex::new(None);
    // a resource error: the job stays resumable (not failed), and the run stops starting jobs
    let halt = |job: &PlannedJob, dir: &std::path::Path, err: &str| {
        let _ = store::log(dir, &format!("stopped by a resource error: {err}"));
        halted
            .lock()
            .expect("halted")
            .get_or_insert_with(|| err.to_string());
        format!(
            "STOPPED {} [{}]: {err}; the job stays resumable from its last checkpoint, no new job starts",
            job.id, job.index
        )
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.max(1))
        .build()?;
    std::thread::scope(|scope| {
        // the single writer: stores outcomes, then releases the claim
        let writer = scope.spawn(|| {
            for msg in rx {
                let job = msg.job;
                let dir = &msg.claim.dir;
                // a claim lost while the job ran (or while its result waited here) writes
                // nothing: another runner may hold the job now
                let lost = match &msg.outcome {
                    Outcome::ClaimLost(why) => Some(why.clone()),
                    _ => msg.claim.still_held().err(),
                };
                let line = match &msg.outcome {
                    _ if lost.is_some() => {
                        let why = lost.unwrap_or_default();
                        let _ = store::log(
                            dir,
                            &format!("claim lost: {why}; stopped without a result"),
                        );
                        busy.fetch_add(1, Ordering::Relaxed);
                        format!(
                            "lost    {} [{}]: {why}; stopped without a result",
                            job.id, job.index
                        )
                    }
                    Outcome::ClaimLost(_) => unreachable!("handled above"),
                    Outcome::Halted(err) => halt(job, dir, err),
                    Outcome::Finished(result) => match store::write_result(dir, result) {
                        Ok(checksum) => {
                            let _ = store::log(dir, &store::done_line(&checksum));
                            counts.lock().expect("counts").0 += 1;
                            done_count.fetch_add(1, Ordering::Relaxed);
                            super::running::add_done();
                            format!(
                                "done    {} [{}] {}: {}, {:.1} s, {:.3e} events/s",
                                job.id,
                                job.index,
                                point_of(job),
                                crate::analysis::labels::label_key(
                                    result.analysis.label().0,
                                    result.analysis.label().1
                                ),
                                result.wall_seconds,
                                result.events_per_second
                            )
                        }
                        Err(e) if super::fs_error::is_resource_error(&e) => {
                            halt(job, dir, &format!("writing the result: {e:#}"))
                        }
                        Err(e) => {
                            let _ = store::mark_failed(dir, &format!("writing the result: {e:#}"));
                            counts.lock().expect("counts").1 += 1;
                            format!(
                                "FAILED  {} [{}] {}: writing the result: {e:#}",
                                job.id,
                                job.index,
                                point_of(job)
                            )
                        }
                    },
                    Outcome::Failed(err) => {
                        let _ = store::mark_failed(dir, err);
                        counts.lock().expect("counts").1 += 1;
                        format!(
                            "FAILED  {} [{}] {}: {err}",
                            job.id,
                            job.index,
                            point_of(job)
                        )
                    }
                };
                super::running::ended(dir);
                drop(msg.claim);
                let done = done_count.load(Ordering::Relaxed);
                set_overall(done);
                say(line);
                if !interactive {
                    say(sweep_line(done));
                }
            }
        });
        pool.scope(|s| {
            for _ in 0..opts.threads.max(1) {
                let tx = tx.clone();
                s.spawn(|_| {
                    let tx = tx;
                    loop {
                        // after a resource error no new job starts
                        if halted.lock().expect("halted").is_some() {
                            break;
                        }
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(job) = todo.get(i) else { break };
                        let dir = dirs.job_dir(&job.id);
                        let claim = match store::try_claim(&dir, opts.retry_failed) {
                            Ok(Ok(c)) => c,
                            Ok(Err(NotClaimed::Busy)) => {
                                busy.fetch_add(1, Ordering::Relaxed);
                                say(format!(
                                    "busy    {} [{}]: held by another runner",
                                    job.id, job.index
                                ));
                                eta.end(i);
                                continue;
                            }
                            Ok(Err(NotClaimed::Damaged(reason))) => {
                                say(format!(
                                    "damaged {} [{}]: {reason} (rerun with --retry-failed)",
                                    job.id, job.index
                                ));
                                eta.end(i);
                                continue;
                            }
                            Ok(Err(_)) => {
                                eta.end(i);
                                continue;
                            }
                            Err(e) => {
                                say(format!(
                                    "error   {} [{}]: cannot claim: {e}",
                                    job.id, job.index
                                ));
                                eta.end(i);
                                continue;
                            }
                        };
                        super::running::started(&dir);
                        let bar = multi.insert_before(&overall, ProgressBar::new(1000));
                        bar.set_style(
                            ProgressStyle::with_template("  {prefix} [{bar:20}] {msg}")
                                .expect("valid template")
                                .progress_chars("=> "),
                        );
                        bar.set_prefix(if point.is_empty() {
                            job.id.0.clone()
                        } else {
                            point_of(job)
                        });
                        // work per unit of the run's clock (the estimate is linear in it)
                        let work_per_clock = job.params.estimated_work() / job.params.run.length();
                        let unit = job.params.run.clock().unit();
                        let clock = job.params.run.clock();
                        let mut last =
                            store::checkpoint_progress(&dir).map_or(0.0, |p| p.on(clock));
                        overall.inc((last * work_per_clock) as u64);
                        eta.start(i, (job.params.run.length() - last) * work_per_clock);
                        let started = std::time::Instant::now();
                        let (start_clock, mut printed) = (last, std::time::Instant::now());
                        let mut on_progress = |p: execute::JobProgress| {
                            bar.set_position((1000.0 * p.clock / p.target) as u64);
                            bar.set_message(format!(
                                "{:.0}/{:.0} {unit}, {:.2e} events/s",
                                p.clock, p.target, p.events_per_second
                            ));
                            let delta = (p.clock - last).max(0.0);
                            overall.inc((delta * work_per_clock) as u64);
                            eta.progress(
                                i,
                                delta * work_per_clock,
                                (p.target - p.clock) * work_per_clock,
                            );
                            if interactive {
                                overall.set_message(eta.text().trim_start_matches(", ").to_string());
                            }
                            last = p.clock;
                            // without a terminal (a Slurm log, a file): a plain line per job at
                            // a fixed wall-clock interval (output only; the run never depends
                            // on it)
                            if !interactive && printed.elapsed() >= progress_every {
                                printed = std::time::Instant::now();
                                let rate = (p.clock - start_clock)
                                    / started.elapsed().as_secs_f64().max(1e-9);
                                let eta = if rate > 0.0 {
                                    format!("{:.0} s", (p.target - p.clock) / rate)
                                } else {
                                    "?".into()
                                };
                                say(format!(
                                    "running {} [{}] {}: {:.0}/{:.0} {unit}, {:.2e} events/s, ETA {eta}",
                                    job.id,
                                    job.index,
                                    point_of(job),
                                    p.clock,
                                    p.target,
                                    p.events_per_second
                                ));
                                let mut last_sweep = last_sweep_line.lock().expect("sweep line");
                                if last_sweep.elapsed() >= progress_every {
                                    *last_sweep = std::time::Instant::now();
                                    say(sweep_line(done_count.load(Ordering::Relaxed)));
                                }
                            }
                        };
                        let outcome =
                            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                                execute::run_job(job, &claim, None, &mut on_progress)
                            }));
                        bar.finish_and_clear();
                        multi.remove(&bar);
                        eta.end(i);
                        let outcome = match outcome {
                            Ok(Ok(JobEnd::Finished(result))) => Outcome::Finished(result),
                            Ok(Ok(JobEnd::Stopped)) => Outcome::Failed("stopped early".into()),
                            Ok(Ok(JobEnd::ClaimLost(why))) => Outcome::ClaimLost(why),
                            Ok(Err(e)) if super::fs_error::is_resource_error(&e) => {
                                // stop the other workers from starting jobs right away
                                let err = format!("{e:#}");
                                halted
                                    .lock()
                                    .expect("halted")
                                    .get_or_insert_with(|| err.clone());
                                Outcome::Halted(err)
                            }
                            Ok(Err(e)) => Outcome::Failed(format!("{e:#}")),
                            Err(panic) => Outcome::Failed(format!(
                                "panic: {}",
                                panic
                                    .downcast_ref::<String>()
                                    .cloned()
                                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                                    .unwrap_or_default()
                            )),
                        };
                        let _ = tx.send(Message {
                            job,
                            claim,
                            outcome,
                        });
                    }
                });
            }
        });
        drop(tx);
        writer.join().expect("writer thread");
    });
    overall.finish_and_clear();
    let (finished, failed) = *counts.lock().expect("counts");
    summary.finished = finished;
    summary.failed = failed;
    summary.busy = busy.load(Ordering::Relaxed);
    summary.halted = halted.into_inner().expect("halted");
    if opts.write_tables && summary.halted.is_none() {
        let written = tables::gather(sweep, dirs)?;
        say(format!(
            "tables: {} in {}",
            written.counts(),
            dirs.tables.display()
        ));
    }
    say(format!(
        "run finished: {} done now ({} before), {} failed, {} skipped as failed, {} held by another runner",
        summary.finished,
        summary.already_done,
        summary.failed,
        summary.skipped_failed,
        summary.busy
    ));
    Ok(summary)
}

/// "1 job", "2 jobs": a count with its noun in the right number.
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

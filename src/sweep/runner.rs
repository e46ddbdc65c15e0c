//! The local runner: claims jobs that are not done, runs them on a rayon pool (largest estimated
//! work first), shows one progress line for the sweep and one per running job, and hands every
//! outcome to a single writer thread over a crossbeam channel.

use super::eta::SweepEta;
use super::execute::{self, JobEnd, JobError};
use super::grid::PlannedJob;
use super::rounds::{self, Refined};
use super::store::{self, Claim, JobDir, JobResult, JobState, NotClaimed};
use super::{Sweep, SweepDirs, tables};
use crossbeam_channel::{Receiver, Sender, unbounded};
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

/// The jobs of a plan in `range` (plan indices [start, end)).
fn in_range(plan: &[PlannedJob], range: Option<(usize, usize)>) -> Vec<&PlannedJob> {
    plan.iter()
        .filter(|j| range.is_none_or(|(a, b)| j.index >= a && j.index < b))
        .collect()
}

/// Run the jobs of a sweep that are not done yet; write the tables at the end. The stages, in
/// order: [`expand`] (the jobs this round is about), [`select`] (which of them to run, largest
/// first), [`run`] (run them: workers and one writer), [`refine`] (the next round's points,
/// for a sweep with a `refine` section; again from [`expand`] while a round adds points),
/// [`gather`] (the tables).
pub fn run_sweep(sweep: &Sweep, dirs: &SweepDirs, opts: &RunOptions) -> anyhow::Result<RunSummary> {
    if opts.write_resolved {
        sweep.write_resolved(dirs)?;
    }
    let mut current = refine(sweep, dirs, opts)?;
    let mut total = RunSummary::default();
    // the plan jobs before this round's (earlier rounds', already run)
    let mut from = 0;
    let mut last_show = None;
    for round in 0.. {
        let jobs = expand(&current.sweep, opts, from);
        let (todo, mut summary) = select(&jobs, dirs, opts)?;
        let show = Show::new(sweep, opts, jobs.len(), &todo, summary.already_done);
        show.say(format!(
            "sweep {}{}: {} selected, {} done, {} to run{} on {} (results in {})",
            sweep.name,
            if round > 0 {
                format!(" round {round} of the refinement")
            } else {
                String::new()
            },
            counted(jobs.len(), "job"),
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
        run(sweep, dirs, opts, &todo, &show, &mut summary)?;
        total.add(&summary);
        last_show = Some(show);
        if total.halted.is_some() {
            break;
        }
        from = current.sweep.plan.len();
        current = refine(sweep, dirs, opts)?;
        if current.sweep.plan.len() == from {
            break;
        }
    }
    let show = last_show.expect("at least one round");
    gather(&current.sweep, dirs, opts, &show, &total)?;
    if !current.rounds.is_empty() {
        show.say(format!(
            "refinement: {} rounds adding {} points ({}), {}",
            current.rounds.len(),
            current.rounds.iter().sum::<usize>(),
            current
                .rounds
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(" + "),
            if current.complete {
                "complete"
            } else {
                "waiting for unfinished jobs"
            }
        ));
    }
    show.say(format!(
        "run finished: {} done now ({} before), {} failed, {} skipped as failed, {} held by another runner",
        total.finished, total.already_done, total.failed, total.skipped_failed, total.busy
    ));
    Ok(total)
}

impl RunSummary {
    /// Add a round's counts (the first resource error stays).
    fn add(&mut self, round: &RunSummary) {
        self.selected += round.selected;
        self.already_done += round.already_done;
        self.finished += round.finished;
        self.failed += round.failed;
        self.skipped_failed += round.skipped_failed;
        self.busy += round.busy;
        self.outdated += round.outdated;
        if self.halted.is_none() {
            self.halted.clone_from(&round.halted);
        }
    }
}

/// Stage 1: the jobs this round is about: the plan's from index `from` on (the jobs of the
/// rounds before are run), in `job_range`.
fn expand<'a>(sweep: &'a Sweep, opts: &RunOptions, from: usize) -> Vec<&'a PlannedJob> {
    in_range(&sweep.plan[from..], opts.job_range)
}

/// The refine stage: the sweep with the points of every round whose predecessors are done
/// ([`rounds::replay`]); the sweep itself without a `refine` section, and for a run of a
/// `--job-range` (a Slurm task runs the jobs it was given).
fn refine(sweep: &Sweep, dirs: &SweepDirs, opts: &RunOptions) -> anyhow::Result<Refined> {
    if opts.job_range.is_some() {
        return Ok(Refined {
            sweep: sweep.clone(),
            rounds: Vec::new(),
            complete: true,
        });
    }
    Ok(rounds::replay(sweep, dirs)?)
}

/// Stage 2: which jobs to run, from the state of each one's directory (made when missing):
/// done ones are counted (or set aside when outdated and `rerun_outdated`), failed and damaged
/// ones skipped unless `retry_failed`. The jobs to run come largest estimated work first, in
/// plan order among equals; the summary counts the rest.
fn select<'a>(
    jobs: &[&'a PlannedJob],
    dirs: &SweepDirs,
    opts: &RunOptions,
) -> anyhow::Result<(Vec<&'a PlannedJob>, RunSummary)> {
    let mut summary = RunSummary {
        selected: jobs.len(),
        ..Default::default()
    };
    let mut todo = Vec::new();
    for job in jobs {
        let dir = dirs.job(&job.id);
        dir.init(job)?;
        // with --retry-failed, done results are read and checked too (damaged ones are then
        // set aside and recomputed; a damaged parameters file is set aside and written anew)
        let mut state = dir.state(opts.retry_failed);
        if let JobState::Damaged {
            file: store::PARAMS_FILE,
            reason,
        } = &state
            && opts.retry_failed
            && dir.repair_params(job, reason)?
        {
            state = dir.state(true);
        }
        match state {
            JobState::Done if opts.rerun_outdated => {
                let def = job.params.def();
                match dir
                    .retire_if_outdated(def.version, crate::registry::analysis_of(def).version())?
                {
                    Some(_) => {
                        summary.outdated += 1;
                        todo.push(*job)
                    }
                    None => summary.already_done += 1,
                }
            }
            JobState::Done => {
                dir.complete_done_log()?;
                summary.already_done += 1
            }
            JobState::Failed(_) | JobState::Damaged { .. } if !opts.retry_failed => {
                summary.skipped_failed += 1
            }
            _ => todo.push(*job),
        }
    }
    todo.sort_by(|a, b| {
        b.params
            .estimated_work()
            .total_cmp(&a.params.estimated_work())
            .then(a.index.cmp(&b.index))
    });
    Ok((todo, summary))
}

/// Stage 3: run the selected jobs on a pool of `threads` workers, each outcome stored by one
/// writer thread; the summary gets what happened.
fn run(
    sweep: &Sweep,
    dirs: &SweepDirs,
    opts: &RunOptions,
    todo: &[&PlannedJob],
    show: &Show,
    summary: &mut RunSummary,
) -> anyhow::Result<()> {
    let run = Run {
        dirs,
        opts,
        todo,
        show,
        // a job is named by its swept parameters in progress lines (its id where nothing varies)
        swept: super::phase::swept_in(sweep),
        engine: sweep.engine(),
        next: AtomicUsize::new(0),
        busy: AtomicUsize::new(0),
        halted: Mutex::new(None),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.max(1))
        .build()?;
    let (tx, rx) = unbounded::<Message>();
    std::thread::scope(|scope| {
        let writer = scope.spawn(|| run.write(rx));
        pool.scope(|s| {
            for _ in 0..opts.threads.max(1) {
                let tx = tx.clone();
                s.spawn(|_| run.work(tx));
            }
        });
        drop(tx);
        writer.join().expect("writer thread");
    });
    show.overall.finish_and_clear();
    let (finished, failed) = *show.counts.lock().expect("counts");
    summary.finished = finished;
    summary.failed = failed;
    summary.busy = run.busy.load(Ordering::Relaxed);
    summary.halted = run.halted.into_inner().expect("halted");
    Ok(())
}

/// Stage 4: the sweep's tables, unless not asked or a resource error stopped the run.
fn gather(
    sweep: &Sweep,
    dirs: &SweepDirs,
    opts: &RunOptions,
    show: &Show,
    summary: &RunSummary,
) -> anyhow::Result<()> {
    if opts.write_tables && summary.halted.is_none() {
        let written = tables::gather(sweep, dirs)?;
        show.say(format!(
            "tables: {} in {}",
            written.counts(),
            dirs.tables.display()
        ));
    }
    Ok(())
}

/// What a run shows: the sweep's progress bar and ETA and one bar per running job on a
/// terminal; plain lines otherwise (a Slurm log, a file).
struct Show<'a> {
    name: &'a str,
    /// jobs selected
    selected: usize,
    interactive: bool,
    /// wall-clock time between plain progress lines
    every: std::time::Duration,
    multi: MultiProgress,
    overall: ProgressBar,
    eta: SweepEta,
    /// jobs done and failed in this run
    counts: Mutex<(usize, usize)>,
    /// jobs with a result: the sweep line counts them, failed and stopped jobs apart
    done: AtomicUsize,
    /// when the last plain sweep line was shown
    last_sweep_line: Mutex<std::time::Instant>,
}

impl<'a> Show<'a> {
    fn new(
        sweep: &'a Sweep,
        opts: &RunOptions,
        selected: usize,
        todo: &[&PlannedJob],
        already_done: usize,
    ) -> Self {
        let interactive = std::io::stderr().is_terminal();
        let multi = MultiProgress::new();
        if !interactive {
            multi.set_draw_target(ProgressDrawTarget::hidden());
        }
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
        super::running::set_done(already_done);
        let show = Show {
            name: &sweep.name,
            selected,
            interactive,
            every: progress_interval(),
            multi,
            overall,
            eta,
            counts: Mutex::new((0, 0)),
            done: AtomicUsize::new(already_done),
            last_sweep_line: Mutex::new(std::time::Instant::now()),
        };
        show.set_overall(already_done);
        show
    }

    fn say(&self, line: String) {
        if self.interactive {
            let _ = self.multi.println(line);
        } else {
            super::say(&line);
        }
    }

    fn set_overall(&self, done: usize) {
        self.overall
            .set_prefix(format!("{}: {done}/{} jobs done", self.name, self.selected));
    }

    /// The sweep's progress as a plain line.
    fn sweep_line(&self, done: usize) -> String {
        let overall = &self.overall;
        let fraction = overall.position() as f64 / overall.length().unwrap_or(1).max(1) as f64;
        let eta = if fraction < 1.0 {
            self.eta.text()
        } else {
            String::new()
        };
        let failed = self.counts.lock().expect("counts").1;
        format!(
            "sweep   {}: {done}/{} jobs done{}, {:.0} % of the estimated work{eta}",
            self.name,
            self.selected,
            if failed > 0 {
                format!(" ({failed} failed)")
            } else {
                String::new()
            },
            100.0 * fraction
        )
    }

    /// A job's outcome line; without a terminal the sweep line after it.
    fn ended(&self, line: String) {
        let done = self.done.load(Ordering::Relaxed);
        self.set_overall(done);
        self.say(line);
        if !self.interactive {
            self.say(self.sweep_line(done));
        }
    }

    /// Without a terminal: the sweep line at most once per progress interval.
    fn sweep_line_now_and_then(&self) {
        let mut last = self.last_sweep_line.lock().expect("sweep line");
        if last.elapsed() >= self.every {
            *last = std::time::Instant::now();
            self.say(self.sweep_line(self.done.load(Ordering::Relaxed)));
        }
    }
}

/// The stage [`run`]: what its workers and its writer share.
struct Run<'a> {
    dirs: &'a SweepDirs,
    opts: &'a RunOptions,
    todo: &'a [&'a PlannedJob],
    show: &'a Show<'a>,
    swept: Vec<&'static str>,
    engine: &'static crate::engine::EngineDef,
    /// the index in `todo` of the next job a worker takes
    next: AtomicUsize,
    /// jobs held by another runner (or lost to one)
    busy: AtomicUsize,
    /// the first resource error: no job starts after it
    halted: Mutex<Option<String>>,
}

impl<'a> Run<'a> {
    /// A job named by its swept parameters.
    fn point_of(&self, job: &PlannedJob) -> String {
        super::phase::point_text(self.engine, &job.params, &self.swept)
    }

    /// A worker: claims the next job, runs it and sends its outcome to the writer, until no job
    /// is left or a resource error stopped the run.
    fn work(&self, tx: Sender<Message<'a>>) {
        loop {
            // after a resource error no new job starts
            if self.halted.lock().expect("halted").is_some() {
                break;
            }
            let i = self.next.fetch_add(1, Ordering::Relaxed);
            let Some(&job) = self.todo.get(i) else { break };
            let Some(claim) = self.claim(job) else {
                self.show.eta.end(i);
                continue;
            };
            let outcome = self.run_claimed(i, job, &claim);
            let _ = tx.send(Message {
                job,
                claim,
                outcome,
            });
        }
    }

    /// The job's claim, or why not (said; None).
    fn claim(&self, job: &PlannedJob) -> Option<Claim> {
        match self.dirs.job(&job.id).claim(self.opts.retry_failed) {
            Ok(c) => Some(c),
            Err(NotClaimed::Busy) => {
                self.busy.fetch_add(1, Ordering::Relaxed);
                self.show.say(format!(
                    "busy    {} [{}]: held by another runner",
                    job.id, job.index
                ));
                None
            }
            Err(NotClaimed::Damaged(reason)) => {
                self.show.say(format!(
                    "damaged {} [{}]: {reason} (rerun with --retry-failed)",
                    job.id, job.index
                ));
                None
            }
            Err(NotClaimed::Unreadable(e)) => {
                self.show.say(format!(
                    "error   {} [{}]: cannot claim: {e}",
                    job.id, job.index
                ));
                None
            }
            Err(NotClaimed::Done | NotClaimed::Failed(_)) => None,
        }
    }

    /// Run a claimed job (the `i`-th to run) with its progress bar; a panic is a failure.
    fn run_claimed(&self, i: usize, job: &PlannedJob, claim: &Claim) -> Outcome {
        let show = self.show;
        super::running::started(claim.dir.path());
        let bar = show
            .multi
            .insert_before(&show.overall, ProgressBar::new(1000));
        bar.set_style(
            ProgressStyle::with_template("  {prefix} [{bar:20}] {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_prefix(if self.swept.is_empty() {
            job.id.0.clone()
        } else {
            self.point_of(job)
        });
        let mut progress = JobBar::new(self, i, job, &bar, &claim.dir);
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            execute::run_job(job, claim, None, &mut |p| progress.update(p))
        }));
        bar.finish_and_clear();
        show.multi.remove(&bar);
        show.eta.end(i);
        let outcome = outcome_of(result);
        if let Outcome::Halted(err) = &outcome {
            // stop the other workers from starting jobs right away
            self.halted
                .lock()
                .expect("halted")
                .get_or_insert_with(|| err.clone());
        }
        outcome
    }

    /// A resource error: the job stays resumable (not failed), and the run stops starting jobs.
    fn halt(&self, job: &PlannedJob, dir: &JobDir, err: &str) -> String {
        let _ = dir.log(&format!("stopped by a resource error: {err}"));
        self.halted
            .lock()
            .expect("halted")
            .get_or_insert_with(|| err.to_string());
        format!(
            "STOPPED {} [{}]: {err}; the job stays resumable from its last checkpoint, no new job starts",
            job.id, job.index
        )
    }

    /// The single writer: stores each outcome, then releases the claim.
    fn write(&self, rx: Receiver<Message>) {
        for msg in rx {
            let line = self.store(&msg);
            super::running::ended(msg.claim.dir.path());
            drop(msg.claim);
            self.show.ended(line);
        }
    }

    /// Store one outcome (a result, a failure, nothing when the claim was lost or a resource
    /// error stopped the job); the line that says so.
    fn store(&self, msg: &Message) -> String {
        let job = msg.job;
        let dir = &msg.claim.dir;
        let counts = &self.show.counts;
        // a claim lost while the job ran (or while its result waited here) writes nothing:
        // another runner may hold the job now
        let lost = match &msg.outcome {
            Outcome::ClaimLost(why) => Some(why.clone()),
            _ => msg.claim.still_held().err(),
        };
        if let Some(why) = lost {
            let _ = dir.log(&format!("claim lost: {why}; stopped without a result"));
            self.busy.fetch_add(1, Ordering::Relaxed);
            return format!(
                "lost    {} [{}]: {why}; stopped without a result",
                job.id, job.index
            );
        }
        let failed = |err: &str| {
            let _ = dir.mark_failed(err);
            counts.lock().expect("counts").1 += 1;
            format!(
                "FAILED  {} [{}] {}: {err}",
                job.id,
                job.index,
                self.point_of(job)
            )
        };
        match &msg.outcome {
            Outcome::ClaimLost(_) => unreachable!("handled above"),
            Outcome::Halted(err) => self.halt(job, dir, err),
            Outcome::Failed(err) => failed(err),
            Outcome::Finished(result) => match dir.write_result(result) {
                Ok(checksum) => {
                    let _ = dir.log(&store::done_line(&checksum));
                    counts.lock().expect("counts").0 += 1;
                    self.show.done.fetch_add(1, Ordering::Relaxed);
                    super::running::add_done();
                    format!(
                        "done    {} [{}] {}: {}, {:.1} s, {:.3e} events/s",
                        job.id,
                        job.index,
                        self.point_of(job),
                        crate::analysis::labels::label_key(
                            result.analysis.label().0,
                            result.analysis.label().1
                        ),
                        result.wall_seconds,
                        result.events_per_second
                    )
                }
                Err(e) => match JobError::from(e) {
                    e if e.is_resource() => {
                        self.halt(job, dir, &format!("writing the result: {e}"))
                    }
                    e => failed(&format!("writing the result: {e}")),
                },
            },
        }
    }
}

/// How a job's run ended, for the writer.
fn outcome_of(result: std::thread::Result<Result<JobEnd, JobError>>) -> Outcome {
    match result {
        Ok(Ok(JobEnd::Finished(result))) => Outcome::Finished(result),
        Ok(Ok(JobEnd::Stopped)) => Outcome::Failed("stopped early".into()),
        Ok(Ok(JobEnd::ClaimLost(why))) => Outcome::ClaimLost(why),
        Ok(Err(e)) if e.is_resource() => Outcome::Halted(e.to_string()),
        Ok(Err(e)) => Outcome::Failed(e.to_string()),
        Err(panic) => Outcome::Failed(format!(
            "panic: {}",
            panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        )),
    }
}

/// A running job's progress: its bar, the sweep's bar and ETA, and (without a terminal) a
/// plain line per progress interval.
struct JobBar<'r, 'a> {
    run: &'r Run<'a>,
    /// the job's index among those to run (the ETA's)
    i: usize,
    job: &'r PlannedJob,
    bar: &'r ProgressBar,
    /// work per unit of the run's clock (the estimate is linear in it)
    work_per_clock: f64,
    /// the clock when last reported, and when the job started in this run
    last: f64,
    start_clock: f64,
    started: std::time::Instant,
    printed: std::time::Instant,
}

impl<'r, 'a> JobBar<'r, 'a> {
    fn new(
        run: &'r Run<'a>,
        i: usize,
        job: &'r PlannedJob,
        bar: &'r ProgressBar,
        dir: &JobDir,
    ) -> Self {
        let params = &job.params;
        let work_per_clock = params.estimated_work() / params.run.length();
        let last = dir
            .checkpoint_progress()
            .map_or(0.0, |p| p.on(params.run.clock()));
        run.show.overall.inc((last * work_per_clock) as u64);
        run.show
            .eta
            .start(i, (params.run.length() - last) * work_per_clock);
        JobBar {
            run,
            i,
            job,
            bar,
            work_per_clock,
            last,
            start_clock: last,
            started: std::time::Instant::now(),
            printed: std::time::Instant::now(),
        }
    }

    fn update(&mut self, p: execute::JobProgress) {
        if let Some(prep) = &p.preparing {
            self.preparing(prep, p.events_per_second);
            return;
        }
        let show = self.run.show;
        let unit = self.job.params.run.clock().unit();
        self.bar.set_position((1000.0 * p.clock / p.target) as u64);
        self.bar.set_message(format!(
            "{:.0}/{:.0} {unit}, {:.2e} events/s",
            p.clock, p.target, p.events_per_second
        ));
        let delta = (p.clock - self.last).max(0.0);
        show.overall.inc((delta * self.work_per_clock) as u64);
        show.eta.progress(
            self.i,
            delta * self.work_per_clock,
            (p.target - p.clock) * self.work_per_clock,
        );
        if show.interactive {
            show.overall
                .set_message(show.eta.text().trim_start_matches(", ").to_string());
        }
        self.last = p.clock;
        // without a terminal (a Slurm log, a file): a plain line per job at a fixed wall-clock
        // interval (output only; the run never depends on it)
        if !show.interactive && self.printed.elapsed() >= show.every {
            self.printed = std::time::Instant::now();
            let rate =
                (p.clock - self.start_clock) / self.started.elapsed().as_secs_f64().max(1e-9);
            let eta = if rate > 0.0 {
                format!("{:.0} s", ((p.target - p.clock) / rate).max(0.0))
            } else {
                "?".into()
            };
            show.say(format!(
                "running {} [{}] {}: {:.0}/{:.0} {unit}, {:.2e} events/s, ETA {eta}",
                self.job.id,
                self.job.index,
                self.run.point_of(self.job),
                p.clock,
                p.target,
                p.events_per_second
            ));
            show.sweep_line_now_and_then();
        }
    }
}

impl JobBar<'_, '_> {
    /// A chunk of the engine's preparation done: its stage and steps in the bar's message
    /// (the clock has not started; the sweep's bar and ETA wait for it), and without a
    /// terminal a plain line at the fixed interval.
    fn preparing(&mut self, p: &crate::engine::PreparationProgress, events_per_second: f64) {
        // the run's rate (and ETA) counts from the end of the preparation
        self.started = std::time::Instant::now();
        let text = format!(
            "preparing ({}): step {} of at most {}, {}",
            p.stage, p.steps, p.max_steps, p.measure
        );
        self.bar
            .set_message(format!("{text}, {events_per_second:.2e} events/s"));
        let show = self.run.show;
        if !show.interactive && self.printed.elapsed() >= show.every {
            self.printed = std::time::Instant::now();
            show.say(format!(
                "preparing {} [{}] {}: {text}, {events_per_second:.2e} events/s",
                self.job.id,
                self.job.index,
                self.run.point_of(self.job),
            ));
            show.sweep_line_now_and_then();
        }
    }
}

/// "1 job", "2 jobs": a count with its noun in the right number.
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

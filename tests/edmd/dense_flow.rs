//! The exact balances as steady-state evidence, and run-until-steady.
//! - the balance totals a job records obey the exact identities at every snapshot (to
//!   round-off), and the window's `momentum_balance` and `energy_balance` are the ratios of
//!   those totals, consistent with 1 for a steady run;
//! - a run until steady stops at the same snapshot, with the same result, whether it runs
//!   straight through, is stopped and resumed at chosen snapshots, or is killed (SIGKILL) at
//!   random moments and rerun;
//! - a job from the thermalised start keeps its id scheme and survives kill -9 during and
//!   after the start.

use granflow::analysis::{Analysis, Record};
use granflow::engine::edmd::{self, Placement};
use granflow::sweep::execute::{self, JobEnd};
use granflow::sweep::{PlannedJob, load_sweep, store};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{BIN, kill_until_exit};

use crate::common::scratch;

/// A one-job EDMD sweep file `<name>.ron` in `dir`: the channel `fixed`, one seed, `run`.
fn channel_sweep(dir: &Path, name: &str, fixed: &str, seed: u64, run: &str) -> PathBuf {
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(
        &path,
        format!(
            "(\n    engine: \"edmd\",\n    fixed: ({fixed}),\n    seeds: [{seed}],\n    run: {run},\n)\n"
        ),
    )
    .unwrap();
    path
}

/// The small channel of the balance test in tests/edmd/channel.rs: L = W = H = 10,
/// phi = 0.15 (N = 286), e = 0.8, steady after about 250 collisions per particle.
fn sweep_file(dir: &Path, run: &str) -> PathBuf {
    channel_sweep(
        dir,
        "small",
        "length_over_width: 1.0, width_over_diameter: 10.0, height_over_diameter: 10.0, \
         volume_fraction: 0.15, restitution: 0.8",
        5,
        run,
    )
}

/// `granflow run FILE --results RESULTS --threads 1`.
fn run_args(file: &Path, results: &Path) -> Vec<String> {
    vec![
        "run".to_string(),
        file.to_str().unwrap().to_string(),
        "--results".into(),
        results.to_str().unwrap().to_string(),
        "--threads".into(),
        "1".into(),
    ]
}

fn finish(job: &PlannedJob, dir: &Path) -> store::JobResult {
    let claim = store::try_claim(dir, false).unwrap().unwrap();
    match execute::run_job(job, &claim, None, &mut |_| {}).unwrap() {
        JobEnd::Finished(r) => *r,
        other => panic!("not finished: {other:?}"),
    }
}

#[test]
fn recorded_balances_obey_the_exact_identities_and_are_one_when_steady() {
    let dir = scratch("balances");
    let file = sweep_file(
        &dir,
        "(collisions_per_particle: 1600.0, snapshot_interval: 25.0)",
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    let jd = dir.join("job").join(&job.id.0);
    store::init_job_dir(&jd, job).unwrap();
    let result = finish(job, &jd);
    let cp = store::read_checkpoint(&jd).unwrap().unwrap();
    let records: Vec<_> = store::load_records(&jd, &cp)
        .unwrap()
        .into_iter()
        .map(|r| match r {
            Record::Structure(r) => r,
            other => panic!("a structure record, not {other:?}"),
        })
        .collect();
    let n = records[0].particles as f64;
    let (p0, e0) = (
        records[0].momentum_x,
        n * (records[0].translational_energy + records[0].rotational_energy),
    );
    for r in &records[1..] {
        // wall impulse = N m g t - (P_x(t) - P_x(0)); work of gravity - dissipation = growth
        // of the kinetic energy
        let scale = n * r.gravity * r.time;
        let momentum = r.wall_impulse_x - (scale - (r.momentum_x - p0));
        assert!(momentum.abs() <= 1e-9 * scale, "momentum defect {momentum}");
        let kinetic = n * (r.translational_energy + r.rotational_energy) - e0;
        let energy = r.gravity_work - r.energy_dissipated - kinetic;
        assert!(
            energy.abs() <= 1e-9 * r.gravity_work,
            "energy defect {energy}"
        );
    }
    let Analysis::Structure(a) = &result.analysis else {
        panic!("a structure analysis")
    };
    let s = &a.summary;
    assert!(s.steady, "{}", s.note);
    // the window's balances are the ratios of the recorded totals across it
    let first = records
        .iter()
        .position(|r| r.collisions_per_particle == s.window_start)
        .unwrap();
    let (w0, w1) = (&records[first], records.last().unwrap());
    let momentum = (w1.wall_impulse_x - w0.wall_impulse_x) / (n * (w1.time - w0.time));
    let energy =
        (w1.energy_dissipated - w0.energy_dissipated) / (w1.gravity_work - w0.gravity_work);
    assert!((s.momentum_balance - momentum).abs() < 1e-12);
    assert!((s.energy_balance - energy).abs() < 1e-12);
    // and, the run being steady, consistent with 1 with errors small enough to mean something
    for (name, b, e) in [
        ("momentum", s.momentum_balance, s.momentum_balance_error),
        ("energy", s.energy_balance, s.energy_balance_error),
    ] {
        eprintln!("{name} balance {b:.4} +- {e:.4}");
        assert!(e > 0.0 && e < 0.05, "{name}: error {e}");
        assert!((b - 1.0).abs() <= 3.0 * e, "{name}: {b} +- {e}");
    }
}

/// The comparable part of a result: everything except wall-clock figures and times.
fn deterministic(r: store::JobResult) -> String {
    ron::to_string(&r.without_wall_clock()).unwrap()
}

const UNTIL_STEADY: &str = "(collisions_per_particle: 6000.0, snapshot_interval: 20.0, checkpoint_every: 3, until_steady: (window: 300.0))";

#[test]
fn run_until_steady_stops_at_the_same_snapshot_when_interrupted() {
    let dir = scratch("until-steady");
    let file = sweep_file(&dir, UNTIL_STEADY);
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    let run_in = |sub: &str, stops: &[u32]| -> store::JobResult {
        let jd = dir.join(sub).join(&job.id.0);
        store::init_job_dir(&jd, job).unwrap();
        for &stop in stops {
            let claim = store::try_claim(&jd, false).unwrap().unwrap();
            match execute::run_job(
                job,
                &claim,
                Some(execute::StopAfter::Snapshot(stop)),
                &mut |_| {},
            )
            .unwrap()
            {
                JobEnd::Stopped => {}
                other => panic!("finished before snapshot {stop}: {other:?}"),
            }
        }
        finish(job, &jd)
    };
    let straight = run_in("straight", &[]);
    let k = straight.snapshots;
    assert!(
        k < 300
            && straight
                .stop_reason
                .starts_with(&format!("stopped at snapshot {k}: steady")),
        "{}",
        straight.stop_reason
    );
    let Analysis::Structure(a) = &straight.analysis else {
        panic!("a structure analysis")
    };
    assert!(a.summary.steady, "{}", a.summary.note);
    assert!(a.summary.window_end - a.summary.window_start >= 300.0);
    // interrupted at checkpoints before the stop, and resumed from them
    let resumed = run_in("resumed", &[k / 3, k - 2]);
    assert_eq!(deterministic(straight.clone()), deterministic(resumed));
    // without the rule the same job runs to its cap: the rule changes the id
    let capped = load_sweep(&file, &["until_steady=off".into()]).unwrap();
    assert_ne!(capped.plan[0].id, job.id);
}

#[test]
fn run_until_steady_survives_kill_9() {
    let dir = scratch("until-steady-kill");
    let file = sweep_file(&dir, UNTIL_STEADY);
    let reference = dir.join("reference");
    let args = |results: &Path| run_args(&file, results);
    let out = Command::new(BIN).args(args(&reference)).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let id = &sweep.plan[0].id;
    let expect = store::read_result(&reference.join("small/jobs").join(&id.0)).unwrap();

    let results = dir.join("results");
    let job_dir = results.join("small/jobs").join(&id.0);
    // kill at spread-out moments until a run ends by itself (each rerun resumes)
    let (kills, status) = kill_until_exit(
        &args(&results),
        Duration::from_millis(40),
        Duration::from_millis(37),
        Duration::from_secs(60),
    );
    assert!(status.success(), "{status}");
    assert!(
        kills >= 2,
        "only {kills} kills: the job is too short to test resumption"
    );
    let got = store::read_result(&job_dir).unwrap();
    assert_eq!(
        deterministic(got),
        deterministic(expect),
        "after {kills} kills"
    );
}

/// A dense channel (phi = 0.5, N = 489, e = beta = 0.9, e_w = beta_w = 1) with `thermalise`
/// as given: at 2000, about half a million elastic collisions before t = 0, then 8000
/// collisions per particle (2 million) with a checkpoint every 400: both stages long against
/// the 97 ms by which the kills below move.
fn thermalised_sweep(dir: &Path, thermalise: &str) -> PathBuf {
    channel_sweep(
        dir,
        "dense",
        &format!(
            "length_over_width: 1.0, width_over_diameter: 8.0, height_over_diameter: 8.0, \
             volume_fraction: 0.5, restitution: 0.9, roughness: 0.9, wall_restitution: 1.0, \
             wall_roughness: 1.0, {thermalise}"
        ),
        3,
        "(collisions_per_particle: 8000.0, snapshot_interval: 400.0, checkpoint_every: 1)",
    )
}

/// `thermalise` is in a job's id only when it is not 0 (existing jobs keep their ids), and a
/// job from the thermalised start killed with SIGKILL before its first checkpoint (while it
/// thermalises) and after it, and rerun each time, ends identical to the uninterrupted job.
#[test]
fn a_thermalised_start_survives_kill_9_during_and_after_the_start() {
    let dir = scratch("thermalised-kill");
    let plain = load_sweep(&thermalised_sweep(&dir, ""), &[]).unwrap();
    let zero = load_sweep(&thermalised_sweep(&dir, "thermalise: 0"), &[]).unwrap();
    let file = thermalised_sweep(&dir, "thermalise: 2000");
    let sweep = load_sweep(&file, &[]).unwrap();
    assert_eq!(plain.plan[0].id, zero.plan[0].id);
    assert_ne!(plain.plan[0].id, sweep.plan[0].id);
    let placement = |s: &granflow::sweep::Sweep| {
        let job = &s.plan[0].params;
        edmd::params_of(&job.values, job.seed).placement
    };
    assert_eq!(placement(&plain), Placement::Auto);
    assert_eq!(
        placement(&sweep),
        Placement::Thermalised {
            collisions_per_particle: 2000
        }
    );

    let args = |results: &Path| run_args(&file, results);
    let reference = dir.join("reference");
    crate::common::granflow_ok(
        &args(&reference)
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>(),
    );
    let id = &sweep.plan[0].id;
    let expect = store::read_result(&reference.join("dense/jobs").join(&id.0)).unwrap();

    let results = dir.join("results");
    let job_dir = results.join("dense/jobs").join(&id.0);
    let (mut before_checkpoint, mut after_checkpoint) = (0u64, 0u64);
    let started = Instant::now();
    let mut delay = Duration::from_millis(100);
    while !job_dir.join(store::RESULT_FILE).exists() {
        let mut child = Command::new(BIN)
            .args(args(&results))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(delay);
        if child.try_wait().unwrap().is_none() {
            if job_dir.join(store::CHECKPOINT_FILE).exists() {
                after_checkpoint += 1;
            } else {
                before_checkpoint += 1;
            }
            child.kill().unwrap();
        }
        child.wait().unwrap();
        delay += Duration::from_millis(97);
        assert!(started.elapsed() < Duration::from_secs(300), "no progress");
    }
    eprintln!("kills before the first checkpoint: {before_checkpoint}, after: {after_checkpoint}");
    assert!(
        before_checkpoint >= 1 && after_checkpoint >= 1,
        "kills before the first checkpoint: {before_checkpoint}, after: {after_checkpoint}"
    );
    let got = store::read_result(&job_dir).unwrap();
    assert_eq!(
        deterministic(got),
        deterministic(expect),
        "after {before_checkpoint} kills before the first checkpoint and {after_checkpoint} after"
    );
}

//! Slurm array tasks run the jobs they were submitted for: a submission records the
//! job ids of its tasks, and a task runs those ids even after the sweep file was edited and
//! resubmitted (which rewrites the sweep directory's resolved sweep). The tasks' scripts run
//! here in bash with the variables Slurm would set; no Slurm needed.

use granflow::sweep::{load_sweep, store};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::BIN;

use crate::common::scratch;

fn sweep_text(restitutions: &str) -> String {
    format!(
        "(name: \"arr\", engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15, length_over_width: 1.0),\n axes: (restitution: [{restitutions}]), run: (collisions_per_particle: 40, snapshot_interval: 20))"
    )
}

/// Stand-ins for Slurm's `sbatch` (prints a new array id) and `scontrol` (a config with
/// MaxArraySize), so that submissions are recorded as on a real cluster.
fn fake_slurm(dir: &Path) -> PathBuf {
    let bin = dir.join("fake-slurm");
    std::fs::create_dir_all(&bin).unwrap();
    let write = |name: &str, body: &str| {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        let mut perm = std::fs::metadata(&path).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut perm, 0o755);
        std::fs::set_permissions(&path, perm).unwrap();
    };
    let counter = bin.join("count");
    write(
        "sbatch",
        &format!(
            "n=$(cat {c} 2>/dev/null || echo 40); n=$((n + 1)); echo $n > {c}; echo $n",
            c = counter.display()
        ),
    );
    write("scontrol", "echo 'MaxArraySize            = 1001'");
    bin
}

fn submit(file: &Path, results: &Path, fake: &Path) {
    let path = format!(
        "{}:{}",
        fake.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new(BIN)
        .args([
            "slurm",
            "submit",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ])
        .env("PATH", path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_task_runs_its_submitted_ids_after_the_sweep_was_edited_and_resubmitted() {
    let dir = scratch("edited");
    let file = dir.join("arr.ron");
    let results = dir.join("results");
    let fake = fake_slurm(&dir);
    std::fs::write(&file, sweep_text("0.7, 0.8")).unwrap();
    submit(&file, &results, &fake);
    let first = load_sweep(&file, &[]).unwrap();
    // the user edits the sweep (other restitutions: other jobs) and submits again: the
    // sweep directory's resolved sweep is now the second one
    std::fs::write(&file, sweep_text("0.9, 0.95")).unwrap();
    submit(&file, &results, &fake);
    let second = load_sweep(&file, &[]).unwrap();
    let sweep_dir = results.join("arr");
    let resolved = std::fs::read_to_string(sweep_dir.join("sweep.ron")).unwrap();
    assert!(resolved.contains("0.95"), "{resolved}");

    // task 1 of the first submission (a requeued or late task) runs now
    let script = sweep_dir.join("slurm/scripts/submit0-array0.sbatch");
    let out = Command::new("bash")
        .arg(&script)
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_JOB_ID", "41")
        .env("SLURM_CPUS_PER_TASK", "1")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let dirs = first.results_dir(&results);
    let done = |id: &granflow::sweep::JobId| dirs.job_dir(id).join(store::RESULT_FILE).exists();
    assert!(
        done(&first.plan[1].id),
        "the task did not run its job (e = 0.8)"
    );
    assert!(!done(&first.plan[0].id), "task 1 ran task 0's job");
    for j in &second.plan {
        assert!(!done(&j.id), "the task ran a job of the later submission");
    }
    // the task did not rewrite the resolved sweep
    assert_eq!(
        std::fs::read_to_string(sweep_dir.join("sweep.ron")).unwrap(),
        resolved
    );
}

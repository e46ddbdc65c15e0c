//! The running sweep's ETA, from what this run has measured: the work its jobs did per core-second
//! so far, applied to the work each job still has, scheduled over the threads longest job first
//! (the runner's order). It converges as the run goes, whatever the engine's typical rate.
//!
//! Work is in the runner's units (`estimated_work`, linear in each job's clock); a job running
//! until steady counts its cap, so the ETA is an upper bound for such sweeps.

use std::sync::Mutex;
use std::time::Instant;

/// Core-seconds of work per job, to the wall seconds `threads` threads take when each job goes,
/// longest first, to the thread that frees first.
pub fn longest_first_wall_seconds(mut seconds: Vec<f64>, threads: usize) -> f64 {
    seconds.retain(|s| *s > 0.0);
    seconds.sort_by(|a, b| b.total_cmp(a));
    let mut free = vec![0.0f64; threads.max(1)];
    for s in seconds {
        let first = free
            .iter_mut()
            .min_by(|a, b| a.total_cmp(b))
            .expect("at least one thread");
        *first += s;
    }
    free.into_iter().fold(0.0, f64::max)
}

/// The ETA in wall seconds: `remaining` work per job at `work_done / core_seconds` work per
/// core-second, on `threads` threads; `None` before anything was measured.
pub fn eta_seconds(
    remaining: &[f64],
    work_done: f64,
    core_seconds: f64,
    threads: usize,
) -> Option<f64> {
    if !(work_done > 0.0 && core_seconds > 0.0) {
        return None;
    }
    let rate = work_done / core_seconds;
    Some(longest_first_wall_seconds(
        remaining.iter().map(|w| w / rate).collect(),
        threads,
    ))
}

/// What the run has measured so far, shared by the worker threads.
struct Measured {
    /// work still to do, per job of the run (its full estimate until it starts)
    remaining: Vec<f64>,
    /// work done by this run (progress made here, not what resumed jobs had done before)
    work_done: f64,
    /// core-seconds of the jobs that ended in this run
    ended_core_seconds: f64,
    /// start of each job running now
    running: Vec<Option<Instant>>,
}

/// The ETA of a running sweep (see the module doc).
pub struct SweepEta {
    threads: usize,
    measured: Mutex<Measured>,
}

impl SweepEta {
    /// A run of jobs with these estimated works on `threads` threads.
    pub fn new(work: Vec<f64>, threads: usize) -> SweepEta {
        let n = work.len();
        SweepEta {
            threads,
            measured: Mutex::new(Measured {
                remaining: work,
                work_done: 0.0,
                ended_core_seconds: 0.0,
                running: vec![None; n],
            }),
        }
    }

    /// Job `job` starts with `remaining` work (less than its estimate when it resumes).
    pub fn start(&self, job: usize, remaining: f64) {
        let mut m = self.measured.lock().expect("eta");
        m.remaining[job] = remaining.max(0.0);
        m.running[job] = Some(Instant::now());
    }

    /// Job `job` did `work` more and has `remaining` left.
    pub fn progress(&self, job: usize, work: f64, remaining: f64) {
        let mut m = self.measured.lock().expect("eta");
        m.work_done += work.max(0.0);
        m.remaining[job] = remaining.max(0.0);
    }

    /// Job `job` ended (finished, failed or stopped): nothing of it remains.
    pub fn end(&self, job: usize) {
        let mut m = self.measured.lock().expect("eta");
        if let Some(started) = m.running[job].take() {
            m.ended_core_seconds += started.elapsed().as_secs_f64();
        }
        m.remaining[job] = 0.0;
    }

    /// Wall seconds still to go, `None` until the run has measured some work.
    pub fn seconds(&self) -> Option<f64> {
        let m = self.measured.lock().expect("eta");
        let core_seconds = m.ended_core_seconds
            + m.running
                .iter()
                .flatten()
                .map(|s| s.elapsed().as_secs_f64())
                .sum::<f64>();
        eta_seconds(&m.remaining, m.work_done, core_seconds, self.threads)
    }

    /// The ETA as text: ", ETA 1h 2m 3s", or ", ETA ?" before anything was measured.
    pub fn text(&self) -> String {
        match self.seconds() {
            Some(s) => format!(
                ", ETA {}",
                humantime::format_duration(std::time::Duration::from_secs(s.round() as u64))
            ),
            None => ", ETA ?".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_time_schedules_the_longest_job_first() {
        // 2 threads: 5 and 4 start; 3 joins the 4 (free first), 2 joins the 5: [7, 7]
        assert_eq!(longest_first_wall_seconds(vec![3.0, 5.0, 2.0, 4.0], 2), 7.0);
        assert_eq!(
            longest_first_wall_seconds(vec![3.0, 5.0, 2.0, 4.0], 1),
            14.0
        );
        // one job longer than all others together sets the wall time
        assert_eq!(longest_first_wall_seconds(vec![10.0, 1.0, 1.0], 2), 10.0);
        assert_eq!(longest_first_wall_seconds(vec![], 2), 0.0);
    }

    #[test]
    fn the_eta_is_the_remaining_work_at_the_measured_rate_per_core() {
        // 100 work units in 50 core-seconds: 2 per core-second; 4 jobs of 40 left on 2 threads
        // take 2 x 20 s each per thread
        assert_eq!(eta_seconds(&[40.0; 4], 100.0, 50.0, 2), Some(40.0));
        // the same work measured on twice the core-seconds: half the rate, twice the time
        assert_eq!(eta_seconds(&[40.0; 4], 100.0, 100.0, 2), Some(80.0));
        // nothing measured yet: no ETA rather than a guess
        assert_eq!(eta_seconds(&[40.0; 4], 0.0, 10.0, 2), None);
        assert_eq!(eta_seconds(&[40.0; 4], 10.0, 0.0, 2), None);
    }

    #[test]
    fn a_resumed_job_counts_only_the_work_this_run_did() {
        let eta = SweepEta::new(vec![100.0, 100.0], 1);
        assert_eq!(eta.seconds(), None);
        // job 0 resumes with 30 left: the 70 done before this run do not make it look fast
        eta.start(0, 30.0);
        std::thread::sleep(std::time::Duration::from_millis(20));
        eta.progress(0, 10.0, 20.0);
        let s = eta.seconds().expect("measured");
        let m = eta.measured.lock().unwrap();
        assert_eq!(m.work_done, 10.0);
        assert_eq!(m.remaining, vec![20.0, 100.0]);
        drop(m);
        // 10 units took >= 20 ms: the 120 left take at least 12 x 20 ms on one thread
        assert!(s >= 0.24, "{s}");
        eta.end(0);
        assert_eq!(eta.measured.lock().unwrap().remaining, vec![0.0, 100.0]);
    }
}

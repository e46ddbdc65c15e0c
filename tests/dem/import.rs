//! The import of another code's run (`engine::dem::imported`, `granflow lammps-import`) held
//! to granflow's own records of the same run: granflow's engine runs a flowing channel and
//! samples it; its states at the samples, given to the import as dump frames, must give the
//! same kinetic bin sums, the walls' flow-wise impulse its force sums measured, and the same
//! kinetic profiles and numbers through the analysis, with what a dump lacks left NaN. A
//! LAMMPS dump read end to end by the command is in tests/dem/lammps.rs.

use crate::common;

use crate::dem::support::{jittered, params};
use granflow::analysis::dense::{DenseSettings, analyse};
use granflow::engine::dem::imported::{ImportError, records_from_frames};
use granflow::engine::dem::lammps::DumpFrame;
use granflow::engine::dem::{DemEngine, DemParams, Record};

/// Steps between samples (and frames), and the number of intervals.
const EVERY: u64 = 400;
const INTERVALS: u64 = 8;

/// A flowing channel: W = 8, B = 5, L = 10 at k_n = 1e5, gravity along the flow, from a
/// jittered lattice with some agitation; granflow's records of `INTERVALS` intervals and the
/// states at their ends (and at the start) as dump frames.
fn run() -> (DemParams, Vec<Record>, Vec<DumpFrame>) {
    let mut p = params(1e5, 8.0, 5.0, 10.0);
    p.gravity = [1.0, 0.0, 0.0];
    p.sample_every = EVERY;
    let states = jittered(&p, 1.12, 0.5, 7);
    let mut engine = DemEngine::from_state(p.clone(), &states, &[]).unwrap();
    let frame = |engine: &DemEngine| DumpFrame {
        timestep: engine.steps(),
        bounds: [[0.0, p.length], [0.0, p.width], [0.0, p.span]],
        ids: (1..=states.len() as u64).collect(),
        states: engine.states(),
        pair_virial: None,
    };
    let mut frames = vec![frame(&engine)];
    let mut records = Vec::new();
    for k in 1..=INTERVALS {
        engine.advance_to_step(k * EVERY).unwrap();
        records.push(engine.take_sample().record);
        frames.push(frame(&engine));
    }
    (p, records, frames)
}

/// Largest |a - b| over two lists.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The kinetic sums of one bin, flattened.
fn kinetic(b: &granflow::engine::dem::sampling::BinSums) -> Vec<f64> {
    let mut v = vec![b.count, b.volume, b.mass, b.inertia];
    v.extend(b.momentum);
    v.extend(b.momentum_flux);
    v.extend(b.spin_momentum);
    v.extend(b.spin_flux);
    v.extend(b.mean_momentum_flux);
    v.extend(b.mean_spin_flux);
    v
}

/// Tolerance of the kinetic sums: granflow sums a bin's particles in its working (cell)
/// order, the import in tag order, so the sums differ by round-off only: at most ~100
/// particles per bin and sample, terms below 10 in these units (m v^2 with |v| < 3), so
/// about 100 * 10 * 2.2e-16 = 2e-13. 1e-11 leaves a margin of 50 and still fails any real
/// difference (a particle in the wrong bin moves a count by 1, a mass by 0.38 or more).
const KINETIC_TOLERANCE: f64 = 1e-11;

/// Tolerance of the walls' impulse, relative to M g T: granflow sums the walls' forces
/// step by step as velocity Verlet delivers them (dt/2 (F_start + F_end)); the import forms
/// M g T - (P_end - P_start) from the frames. The two are the same impulse (the pair forces
/// cancel in pairs, only the walls and gravity change the total momentum) up to round-off in
/// summing N = 192 momenta (each up to about 1) and the pair forces' cancellation per step
/// (forces up to k_n times overlaps of 1e-2, i.e. 1e3, times dt = 3.8e-4, over 400 steps):
/// about 192 * 400 * 0.4 * 2.2e-16 = 7e-12 against M g T = 15. Measured: 2.7e-13 of M g T
/// (2026-12-06). 1e-9 relative leaves room for other summation orders and still fails a
/// wrong term (a missing half step of gravity alone is 1/800 of M g T).
const IMPULSE_TOLERANCE: f64 = 1e-9;

#[test]
fn a_dump_of_granflow_own_run_gives_its_kinetic_sums_and_wall_impulse() {
    let (p, ours, frames) = run();
    let imported = records_from_frames(&p, &frames).unwrap();
    assert_eq!(imported.len(), ours.len());
    let mut worst_kinetic = 0.0f64;
    let mut worst_impulse = 0.0f64;
    let mut carried = 0.0f64;
    for (k, (a, b)) in ours.iter().zip(&imported).enumerate() {
        let (sa, sb) = (&a.sums, &b.sums);
        assert_eq!(sa.samples, 1, "interval {k}: granflow sampled once");
        assert_eq!(sb.samples, 1);
        assert_eq!((sa.start_step, sa.end_step), (sb.start_step, sb.end_step));
        assert_eq!(sa.force_steps, sb.force_steps);
        // the run's constants; granflow sums M and the particle volume in its working
        // order, the import in tag order: those two to round-off
        let (ca, mut cb) = (&a.constants, b.constants.clone());
        assert!((ca.total_mass - cb.total_mass).abs() < 1e-13 * ca.total_mass);
        assert!((ca.volume_fraction - cb.volume_fraction).abs() < 1e-13);
        (cb.total_mass, cb.volume_fraction) = (ca.total_mass, ca.volume_fraction);
        assert_eq!(ca, &cb, "interval {k}: the run's constants");
        for (ba, bb) in sa.bins.iter().zip(&sb.bins) {
            worst_kinetic = worst_kinetic.max(largest_difference(&kinetic(ba), &kinetic(bb)));
            assert!(bb.contact_stress.iter().all(|s| s.is_nan()));
            assert!(bb.dissipation.is_nan() && bb.contacts.is_nan());
        }
        worst_kinetic = worst_kinetic
            .max(largest_difference(&sa.com_velocity, &sb.com_velocity))
            .max(largest_difference(&sa.kinetic_energy, &sb.kinetic_energy));
        assert_eq!(
            a.bonds, b.bonds,
            "interval {k}: the bond sums of the same positions"
        );
        let weight = a.constants.total_mass * p.gravity[0] * sa.duration;
        let measured = sa.wall_impulse[0][0] + sa.wall_impulse[1][0];
        let from_momentum = sb.wall_impulse[0][0] + sb.wall_impulse[1][0];
        println!(
            "interval {k}: walls' impulse {measured:.6e} (granflow), {from_momentum:.6e} \
             (from the momentum), M g T {weight:.6e}"
        );
        worst_impulse = worst_impulse.max((measured - from_momentum).abs() / weight);
        carried = carried.max(measured / weight);
        assert!(sb.wall_force[0][1].is_nan() && sb.wall_force[1][1].is_nan());
    }
    println!(
        "largest differences: kinetic sums {worst_kinetic:.3e}, walls' impulse / M g T \
         {worst_impulse:.3e}; the walls carried up to {carried:.3} of the weight"
    );
    assert!(
        worst_kinetic < KINETIC_TOLERANCE,
        "kinetic sums differ by {worst_kinetic:e}"
    );
    assert!(
        worst_impulse < IMPULSE_TOLERANCE,
        "the walls' impulse from the momentum differs from granflow's by {worst_impulse:e} of \
         M g T"
    );
    // not trivially met: the particles hit the walls (in a dilute, falling channel the
    // walls carry a part of the weight, the rest accelerates the flow)
    assert!(
        carried > 0.05,
        "the walls carried at most {carried:e} of the weight: nothing to compare"
    );
}

#[test]
fn the_analysis_of_the_import_matches_granflow_kinetic_profiles() {
    let (p, ours, frames) = run();
    let imported = records_from_frames(&p, &frames).unwrap();
    let settings = DenseSettings {
        blocks: 4,
        window_fraction: 1.0,
        ..DenseSettings::default()
    };
    let a = analyse(&ours, &settings);
    let b = analyse(&imported, &settings);
    let (sa, sb) = (&a.dense_summary, &b.dense_summary);
    for (name, x, y) in [
        ("com_velocity", sa.com_velocity, sb.com_velocity),
        ("slip_velocity", sa.slip_velocity, sb.slip_velocity),
        ("max_velocity", sa.max_velocity, sb.max_velocity),
        ("q6_plug", sa.q6_plug, sb.q6_plug),
    ] {
        // Q6 is NaN in both when the loose channel has no dense zone (the bond sums
        // themselves are compared in the test above)
        let same = (x - y).abs() <= 1e-9 * x.abs().max(1.0) || (x.is_nan() && y.is_nan());
        assert!(same, "{name}: granflow {x}, import {y}");
    }
    assert!(sa.max_velocity.is_finite() && sa.slip_velocity.is_finite());
    // what a dump lacks is NaN, never a number
    for (name, y) in [
        ("normal_stress", sb.normal_stress),
        ("wall_normal_stress", sb.wall_normal_stress),
        ("wall_friction_coefficient", sb.wall_friction_coefficient),
    ] {
        assert!(y.is_nan(), "{name}: the import gave {y}");
    }
    assert!(sa.normal_stress.is_finite());
    let kinetic = [
        "volume_fraction",
        "velocity",
        "spin",
        "temperature",
        "shear_rate",
    ];
    let lacking = [
        "stress_xx",
        "stress_xy",
        "dissipation",
        "mu",
        "inertial_number",
    ];
    let mut compared = 0;
    for (ra, rb) in a.profiles.iter().zip(&b.profiles) {
        assert_eq!((&ra.quantity, ra.bin), (&rb.quantity, rb.bin));
        if kinetic.contains(&ra.quantity.as_str()) {
            assert!(
                (ra.value - rb.value).abs() <= 1e-9 * ra.value.abs().max(1.0),
                "{} bin {}: granflow {}, import {}",
                ra.quantity,
                ra.bin,
                ra.value,
                rb.value
            );
            compared += 1;
        }
        if lacking.contains(&ra.quantity.as_str()) {
            assert!(
                rb.value.is_nan(),
                "{} bin {}: {}",
                rb.quantity,
                rb.bin,
                rb.value
            );
        }
    }
    assert_eq!(compared, kinetic.len() * 7, "7 bins across W = 8");
}

#[test]
fn frames_of_another_channel_are_refused_with_the_reason() {
    let (p, _, frames) = run();
    assert!(matches!(
        records_from_frames(&p, &frames[..1]),
        Err(ImportError::TooFewFrames(1))
    ));
    let mut wider = frames.clone();
    wider[2].bounds[1][1] = 9.0;
    let e = records_from_frames(&p, &wider).unwrap_err();
    assert!(
        e.to_string()
            .contains("box y is 9 long, the job's width W is 8"),
        "{e}"
    );
    let mut backwards = frames.clone();
    backwards.swap(1, 2);
    assert!(matches!(
        records_from_frames(&p, &backwards),
        Err(ImportError::Order { .. })
    ));
    let mut fewer = frames.clone();
    fewer[3].ids.pop();
    fewer[3].states.pop();
    assert!(matches!(
        records_from_frames(&p, &fewer),
        Err(ImportError::Particles { .. })
    ));
    let mut odd = frames;
    odd[1].states[0].diameter = 0.95;
    assert!(matches!(
        records_from_frames(&p, &odd),
        Err(ImportError::Particles { .. })
    ));
}

/// `granflow lammps-import` refuses a dump that is not of the job's channel with exit code 2,
/// naming the dump, the frame and what differs.
#[test]
fn the_command_names_the_dump_and_what_does_not_fit() {
    use std::process::Command;
    let root = common::scratch("dem_import_refusals");
    let sweep = root.join("channel.ron");
    std::fs::write(
        &sweep,
        r#"(
    engine: "dem",
    fixed: (width_over_diameter: 8.0, span_over_diameter: 5.0, length_over_diameter: 10.0,
            volume_fraction: 0.55, normal_stiffness: 1e5),
    run: (steps: 1000.0, snapshot_interval: 500.0),
)"#,
    )
    .unwrap();
    // two frames of two particles in a box 12 wide instead of W = 8
    let frame = |step: u64| {
        format!(
            "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff pp\n\
             0 10\n0 12\n0 5\nITEM: ATOMS id diameter x y z vx vy vz omegax omegay omegaz\n\
             1 1.0 1 1 1 0 0 0 0 0 0\n2 1.1 3 3 3 0 0 0 0 0 0\n"
        )
    };
    let dump = root.join("dump.dem");
    std::fs::write(&dump, frame(0) + &frame(100)).unwrap();
    let run = |dump: &std::path::Path| {
        Command::new(common::BIN)
            .arg("lammps-import")
            .arg(&sweep)
            .args(["--job", "0", "--dump"])
            .arg(dump)
            .arg("--out")
            .arg(root.join("out"))
            .output()
            .unwrap()
    };
    let out = run(&dump);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("dump.dem: not a run of job")
            && stderr.contains("box y is 12 long, the job's width W is 8"),
        "{stderr}"
    );
    // a file that is not a dump: the line and what was expected
    std::fs::write(&dump, "ITEM: TIMESTEP\nten\n").unwrap();
    let out = run(&dump);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("not a readable LAMMPS dump") && stderr.contains("line 2"),
        "{stderr}"
    );
    assert!(!root.join("out").join("jobs.parquet").exists());
}

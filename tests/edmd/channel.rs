//! Oracle 4 (docs/oracles.md section 4; momentum and energy conservation): balances of steady channel flow.
//! - exact at every snapshot, to round-off: the x-impulse delivered to the walls equals
//!   N m g t - (P_x(t) - P_x(0)) (pair collisions conserve momentum), and the work done by
//!   gravity minus the energy dissipated equals the change of kinetic energy;
//! - in the steady state, time averaged: the x-momentum delivered to the walls per unit time is
//!   N m g, and the gravitational power N m g <u_x> equals the dissipation rate, each within
//!   three standard errors of the block-averaged estimate (and the standard error itself is
//!   small, so the check has teeth).

use granflow::engine::edmd::{EdmdEngine, EdmdParams};
use granflow::engine::{Engine, Particles, Snapshot, StopAt};

fn p(s: &Snapshot) -> &Particles {
    s.particles().expect("EDMD snapshots carry particles")
}

fn momentum_x(s: &Snapshot) -> f64 {
    p(s).velocities.iter().map(|v| v[0]).sum()
}

fn wall_impulse_x(s: &Snapshot) -> f64 {
    p(s).wall_momentum[0][0] + p(s).wall_momentum[1][0]
}

fn kinetic_energy(s: &Snapshot) -> f64 {
    p(s).translational_energy + p(s).rotational_energy
}

/// Mean and standard error of the mean of independent block values.
fn mean_and_standard_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn channel_flow_balances_momentum_and_energy() {
    // small channel L = W = H = 10 d, phi = 0.15 (N = 286), e = 0.8: steady after ~250 cpp
    let mut params = EdmdParams::channel(10.0, 10.0, 10.0, 0.15, 5);
    params.restitution = 0.8;
    let n = params.particles as f64;
    let g = params.gravity;
    let mut engine = EdmdEngine::new(params).unwrap();
    let start = engine.snapshot();
    let (p0, e0) = (momentum_x(&start), kinetic_energy(&start));

    let warm_up = 400.0;
    let blocks = 24;
    let block_cpp = 50.0;
    let mut previous: Option<Snapshot> = None;
    let (mut momentum_ratio, mut power_ratio) = (Vec::new(), Vec::new());
    for b in 0..=blocks {
        engine
            .advance(StopAt::CollisionsPerParticle(
                warm_up + b as f64 * block_cpp,
            ))
            .unwrap();
        let s = engine.snapshot();
        // exact identities, to round-off
        let momentum_defect = wall_impulse_x(&s) - (n * g * s.time() - (momentum_x(&s) - p0));
        let momentum_scale = n * g * s.time();
        assert!(
            momentum_defect.abs() <= 1e-9 * momentum_scale,
            "momentum defect {momentum_defect} of {momentum_scale}"
        );
        let energy_defect =
            p(&s).gravity_work - p(&s).energy_dissipated - (kinetic_energy(&s) - e0);
        assert!(
            energy_defect.abs() <= 1e-9 * p(&s).gravity_work,
            "energy defect {energy_defect} of {}",
            p(&s).gravity_work
        );
        if let Some(q) = &previous {
            let dt = s.time() - q.time();
            momentum_ratio.push((wall_impulse_x(&s) - wall_impulse_x(q)) / (n * g * dt));
            power_ratio.push(
                (p(&s).energy_dissipated - p(q).energy_dissipated)
                    / (p(&s).gravity_work - p(q).gravity_work),
            );
        }
        previous = Some(s);
    }
    for (name, ratios) in [
        ("wall momentum / (N m g)", &momentum_ratio),
        ("dissipation / gravity power", &power_ratio),
    ] {
        let (mean, se) = mean_and_standard_error(ratios);
        eprintln!(
            "{name}: {mean:.5} +- {se:.5} over {} blocks of {block_cpp} cpp",
            ratios.len()
        );
        assert!(
            se < 0.02,
            "{name}: standard error {se} too large for a meaningful check"
        );
        assert!(
            (mean - 1.0).abs() < 3.0 * se,
            "{name}: {mean} differs from 1 by more than 3 standard errors ({se})"
        );
    }
}

/// Dense channels (phi = 0.45-0.6, up to the placement's capacity) start and flow: the lattice
/// placement leaves room between spheres, so the run does not stall at t = 0 in collisions at
/// zero distance (the simple-cubic placement alone made rows of spheres touch from phi ~0.42
/// in a 10^3 channel); the exact momentum identity holds and no two spheres overlap.
#[test]
fn dense_channels_start_and_flow() {
    for phi in [0.45, 0.5, 0.6] {
        let mut params = EdmdParams::channel(10.0, 10.0, 10.0, phi, 3);
        params.restitution = 0.9;
        params.initial_temperature = 1.0;
        let n = params.particles;
        let mut engine =
            EdmdEngine::new(params.clone()).unwrap_or_else(|e| panic!("phi = {phi}: {e}"));
        let start = engine.snapshot();
        engine
            .advance(StopAt::CollisionsPerParticle(100.0))
            .unwrap_or_else(|e| panic!("phi = {phi}: {e}"));
        let s = engine.snapshot();
        // 100 collisions per particle at a collision rate of order 10-100 per unit time
        assert!(
            s.time() > 0.3,
            "phi = {phi}: only t = {} after 100 cpp",
            s.time()
        );
        let g = params.gravity;
        let defect =
            wall_impulse_x(&s) - (n as f64 * g * s.time() - (momentum_x(&s) - momentum_x(&start)));
        assert!(
            defect.abs() <= 1e-9 * n as f64 * g * s.time(),
            "phi = {phi}: defect {defect}"
        );
        let r = &p(&s).positions;
        let (length, height) = (params.geometry.length, params.geometry.height);
        let mut closest = f64::INFINITY;
        for a in 0..n {
            for b in a + 1..n {
                let mut d2 = 0.0;
                for (k, period) in [(0, Some(length)), (1, None), (2, Some(height))] {
                    let mut d = r[a][k] - r[b][k];
                    if let Some(l) = period {
                        d -= l * (d / l).round();
                    }
                    d2 += d * d;
                }
                closest = closest.min(d2.sqrt());
            }
        }
        assert!(
            closest > 1.0 - 1e-9,
            "phi = {phi}: spheres overlap ({closest} apart)"
        );
    }
}

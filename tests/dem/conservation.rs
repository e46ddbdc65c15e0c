//! Conservation without dissipation: with damping and friction off, energy is conserved to
//! the integrator's accuracy over many contacts, and the momentum along the walls exactly.

use crate::dem::support::{jittered, params};

/// A dense elastic gas (k_n = 1e5, xi_n = xi_t = 0, k_t = 0: no tangential force at all) in a
/// 6 x 5 x 6 channel between the (equally elastic) walls, no gravity. The energy
/// E = sum m v^2/2 + sum I w^2/2 + sum k_n delta^2/2 (pairs and walls) is the Hamiltonian of
/// the model; velocity Verlet conserves a nearby "shadow" energy for smooth forces, but the
/// linear contact force has a kink where a contact starts and ends, sampled by the steps up to
/// dt away from it: each contact event leaves an energy error of at most about
/// (w dt)^2 E_c of random sign, E_c ~ E / N the energy of one contact, and E oscillates by
/// O((w dt)^2) of the contact energy in between.
///
/// Bound: over the run's ~1e4 contact events (N = 100) the random walk reaches about
/// sqrt(1e4) (w dt)^2 E / N = (w dt)^2 E: the test requires |E - E0| / E0 < (w dt)^2 at
/// every sample (3.9e-3 at 50 steps per contact, 9.9e-4 at 100; measured 3.1e-4 and
/// 1.5e-4), and that halving dt shrinks the largest deviation.
///
/// (With k_t > 0 the model is not conservative even without damping and sliding: a contact
/// that ends with a stretched tangential spring drops its history, and its energy; a dense
/// gas with mu = 1e3 and k_t = 2/7 k_n loses 80 % of its energy in 2 time units. Hence
/// k_t = 0 here.)
///
/// Momentum: with no tangential force anywhere the walls push along y only, and pair forces
/// are exactly opposite (computed once per pair), so P_x and P_z change only by the round-off
/// of adding the kicks: |Delta P| <= 1e-12 sum m |v| over the run.
#[test]
fn energy_and_momentum_are_conserved_without_dissipation() {
    let mut worst = Vec::new();
    for n in [50.0, 100.0] {
        let mut p = params(1e5, 6.0, 5.0, 6.0);
        p.normal_damping = 0.0;
        p.tangential_damping_ratio = 0.0;
        p.stiffness_ratio = 0.0;
        let t_c = p
            .contact_types()
            .iter()
            .map(|t| t.contact_time)
            .fold(f64::INFINITY, f64::min);
        p.time_step = t_c / n;
        let states = jittered(&p, 1.15, 1.0, 3);
        let mut e = granflow::engine::dem::DemEngine::from_state(p.clone(), &states, &[]).unwrap();
        let energy = |e: &granflow::engine::dem::DemEngine| e.energies().iter().sum::<f64>();
        let scale: f64 = e
            .states()
            .iter()
            .map(|s| {
                granflow::engine::dem::params::sphere_mass(s.diameter)
                    * s.velocity.iter().map(|v| v.abs()).sum::<f64>()
            })
            .sum();
        let (e0, p0) = (energy(&e), e.momentum());
        let steps = (2.0 / p.time_step) as u64;
        let mut max_dev: f64 = 0.0;
        for k in 1..=100 {
            e.advance_to_step(k * steps / 100).unwrap();
            max_dev = max_dev.max((energy(&e) / e0 - 1.0).abs());
            let pm = e.momentum();
            assert!(
                (pm[0] - p0[0]).abs() <= 1e-12 * scale,
                "P_x {} -> {}",
                p0[0],
                pm[0]
            );
            assert!(
                (pm[2] - p0[2]).abs() <= 1e-12 * scale,
                "P_z {} -> {}",
                p0[2],
                pm[2]
            );
        }
        let c = e.counters();
        println!(
            "n = {n}: N = {}, {} pair-steps in contact over {} steps ({} wall), max |E/E0 - 1| = {max_dev:.3e}",
            e.particle_count(),
            c.contacts,
            c.steps,
            c.wall_contacts
        );
        assert!(c.contacts as f64 > 1e4 * n / 50.0, "many contacts");
        let w_dt = std::f64::consts::PI / n;
        assert!(max_dev < w_dt * w_dt, "energy drift {max_dev:e}");
        worst.push(max_dev);
    }
    assert!(worst[1] < worst[0], "{worst:?}");
}

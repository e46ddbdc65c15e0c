//! Physics oracles of single contacts: head-on collisions (e_n and t_c of every pair type and
//! of the wall), oblique collisions with friction (sticking and sliding), a sphere sliding
//! then rolling on a wall, and a sphere resting on a wall.

use crate::dem::support::{body, engine, mono, params};
use granflow::engine::dem::params::sphere_mass;
use granflow::engine::dem::{ContactType, DemParams, SizeMix, WallDamping};

/// A collision measured: rebound ratio and contact duration (start and end interpolated
/// linearly between the steps around the sign change of the overlap).
struct Measured {
    restitution: f64,
    duration: f64,
}

/// Two spheres (or one against the wall y = 0 when `db` is None) approaching head on at
/// relative speed 1 with `n` steps per analytic contact time; no gravity.
fn head_on(p: &DemParams, da: f64, db: Option<f64>, n: f64) -> (Measured, ContactType) {
    let kind = p
        .contact_types()
        .into_iter()
        .find(|t| t.diameter == da && t.other == db)
        .expect("a contact type of the mix");
    let p = DemParams {
        time_step: kind.contact_time / n,
        ..p.clone()
    };
    let dt = p.time_step;
    let (states, overlap): (
        Vec<_>,
        Box<dyn Fn(&[granflow::engine::dem::BodyState]) -> f64>,
    ) = match db {
        Some(db) => {
            let gap = 0.5 * (da + db) + 0.02;
            (
                vec![
                    body(da, [4.0, 4.0, 3.0], [0.5, 0.0, 0.0], [0.0; 3]),
                    body(db, [4.0 + gap, 4.0, 3.0], [-0.5, 0.0, 0.0], [0.0; 3]),
                ],
                Box::new(move |s| 0.5 * (da + db) - (s[1].position[0] - s[0].position[0])),
            )
        }
        None => (
            vec![
                body(da, [4.0, 0.5 * da + 0.02, 3.0], [0.0, -1.0, 0.0], [0.0; 3]),
                // a bystander far away (a state has at least two particles)
                body(da, [10.0, 4.0, 3.0], [0.0; 3], [0.0; 3]),
            ],
            Box::new(move |s| 0.5 * da - s[0].position[1]),
        ),
    };
    let approach = match db {
        Some(_) => 1.0,
        None => 1.0,
    };
    let mut e = engine(p, &states);
    let (mut start, mut end) = (f64::NAN, f64::NAN);
    let mut previous = overlap(&e.states());
    let mut step = 0u64;
    while end.is_nan() {
        step += 1;
        e.advance_to_step(step).unwrap();
        let now = overlap(&e.states());
        let t = step as f64 * dt;
        if previous <= 0.0 && now > 0.0 {
            start = t - dt * now / (now - previous);
        }
        if previous > 0.0 && now <= 0.0 {
            end = t - dt * now / (now - previous);
        }
        previous = now;
        assert!(step < 100_000, "no end of contact");
    }
    let s = e.states();
    let separation = match db {
        Some(_) => s[1].velocity[0] - s[0].velocity[0],
        None => s[0].velocity[1],
    };
    (
        Measured {
            restitution: separation / approach,
            duration: end - start,
        },
        kind,
    )
}

/// Head-on collisions: the rebound ratio is e_n = exp(-xi_n t_c / 2) and the contact lasts
/// t_c = pi / sqrt(k_n/m_eff - xi_n^2/4) for every pair type of the mix, for the mono pair and
/// for each size against the wall (m_eff = m).
///
/// The integrator's error: velocity Verlet with the dashpot evaluated at the half-step
/// velocity, and a contact that starts and ends between steps. The dashpot force jumps from 0
/// to m_eff xi_n v_n when the contact starts (and back when it ends), and the scheme applies
/// it from a step that is up to dt late (or early): an impulse error of up to
/// m_eff xi_n v_n dt at each end, so e_n is off by up to 2 xi_n dt (first order); the lag of
/// the half-step velocity in the dashpot renormalises m_eff by (1 - xi_n dt / 2), which moves
/// t_c by about xi_n dt / 4; Verlet's phase error is (omega_0 dt)^2 / 24. The tolerances are
/// these bounds: |e - e_n| <= 2 xi_n dt + (omega_0 dt)^2 and |t - t_c| / t_c <=
/// xi_n dt / 2 + (omega_0 dt)^2 (the interpolated ends add O(dt^2)). At 100 steps per
/// contact (xi_n dt = 0.004) that is 0.9 % and 0.3 % (measured: 0.05 % and 0.1 %); the test
/// also requires the contact time's error to shrink with dt (first order, not a bias).
#[test]
fn head_on_collisions_give_e_n_and_t_c_of_each_pair_type() {
    let poly = DemParams {
        size_mix: SizeMix::Debnath,
        ..params(1e6, 8.0, 6.0, 12.0)
    };
    let mut cases: Vec<(DemParams, f64, Option<f64>)> = vec![(mono(poly.clone()), 1.0, Some(1.0))];
    for t in poly.contact_types() {
        cases.push((poly.clone(), t.diameter, t.other));
    }
    assert_eq!(cases.len(), 1 + 6 + 3);
    for (p, da, db) in cases {
        let mut errors = Vec::new();
        for n in [50.0, 100.0, 200.0] {
            let (m, kind) = head_on(&p, da, db, n);
            let dt = kind.contact_time / n;
            let w0 = (p.normal_stiffness / kind.effective_mass).sqrt();
            let xi = kind.damping_rate();
            let e_err = (m.restitution - kind.restitution).abs();
            let t_err = (m.duration / kind.contact_time - 1.0).abs();
            let e_tol = 2.0 * xi * dt + (w0 * dt).powi(2);
            let t_tol = 0.5 * xi * dt + (w0 * dt).powi(2);
            println!(
                "{} n={n}: e = {:.6} (analytic {:.6}, err {:.2e}, tol {:.2e}), t = {:.6e} (analytic {:.6e}, rel err {:.2e}, tol {:.2e})",
                kind.name(),
                m.restitution,
                kind.restitution,
                e_err,
                e_tol,
                m.duration,
                kind.contact_time,
                t_err,
                t_tol
            );
            assert!(
                e_err <= e_tol,
                "{}: e error {e_err:e} > {e_tol:e}",
                kind.name()
            );
            assert!(
                t_err <= t_tol,
                "{}: t_c error {t_err:e} > {t_tol:e}",
                kind.name()
            );
            errors.push((e_err, t_err));
        }
        // the contact time converges (first order: halving dt at least roughly halves the
        // error; e_n's error also depends on where the steps fall at the contact's ends)
        assert!(
            errors[1].1 < 0.7 * errors[0].1 && errors[2].1 < 0.7 * errors[1].1,
            "{errors:?}"
        );
    }
}

/// The paper's wall (App. A: "the restitution and friction coefficients for particle-wall
/// collisions are the same as those for particle-particle collisions"): with `wall_damping:
/// pair_restitution` a sphere of each size of the mix hits a wall head on and rebounds with
/// the pair's e_n = 0.82, its contact lasting t_c = sqrt(m / k_n) sqrt(pi^2 + ln^2 e_n) (the
/// linear law's t_c at m_eff = m with the damping that gives e_n: m_eff delta'' + m_eff xi
/// delta' + k_n delta = 0, e_n = exp(-xi t_c / 2), t_c = pi / sqrt(k_n / m - xi^2 / 4)),
/// at the paper's k_n = 1e6. Tolerances as in the head-on test above (the integrator's
/// first-order error at 100 steps per contact). Under LAMMPS' convention (the pair's xi_n at
/// m_eff = m, `pair_rate`) the d_p sphere rebounds with 0.755 instead: the same measurement
/// must see that.
#[test]
fn each_size_rebounds_from_the_wall_with_the_pair_restitution() {
    let e_n: f64 = 0.82;
    let paper = DemParams {
        wall_damping: WallDamping::PairRestitution,
        ..params(1e6, 8.0, 6.0, 12.0)
    };
    let n = 100.0;
    for &(d, _) in SizeMix::Debnath.components() {
        let (m, kind) = head_on(&paper, d, None, n);
        let t_c = (sphere_mass(d) / paper.normal_stiffness).sqrt()
            * (std::f64::consts::PI.powi(2) + e_n.ln().powi(2)).sqrt();
        let dt = t_c / n;
        let xi = -2.0 * e_n.ln() / t_c;
        let w0 = (paper.normal_stiffness / sphere_mass(d)).sqrt();
        let e_tol = 2.0 * xi * dt + (w0 * dt).powi(2);
        let t_tol = 0.5 * xi * dt + (w0 * dt).powi(2);
        println!(
            "{d}-wall: e = {:.5} (paper {e_n}, tol {e_tol:.1e}), t = {:.5e} (analytic {t_c:.5e}, tol {t_tol:.1e})",
            m.restitution, m.duration
        );
        assert!(
            (m.restitution - e_n).abs() <= e_tol,
            "{d}-wall: e = {}",
            m.restitution
        );
        assert!(
            (m.duration / t_c - 1.0).abs() <= t_tol,
            "{d}-wall: t = {}",
            m.duration
        );
        // what the records carry
        assert!((kind.restitution - e_n).abs() < 1e-12, "{kind:?}");
        assert!((kind.contact_time / t_c - 1.0).abs() < 1e-12, "{kind:?}");
    }
    // LAMMPS' fix wall/gran with the pair's xi_n: the d_p sphere rebounds with 0.755
    let lammps = DemParams {
        wall_damping: WallDamping::PairRate,
        ..paper
    };
    let (m, _) = head_on(&lammps, 1.0, None, n);
    println!("1.0-wall, pair_rate: e = {:.5}", m.restitution);
    assert!((m.restitution - 0.755).abs() < 0.005, "{}", m.restitution);
}

/// The slip of the contact points of particles a and b (a - b) tangential to the initial
/// line of centres n = -e_x (fixed, so that the spheres' drift apart after the contact does
/// not turn the frame), and the normal relative velocity along n.
fn slip(s: &[granflow::engine::dem::BodyState]) -> ([f64; 3], f64) {
    let (a, b) = (&s[0], &s[1]);
    let n = [-1.0, 0.0, 0.0];
    let (ra, rb) = (0.5 * a.diameter, 0.5 * b.diameter);
    let rw = [
        ra * a.spin[0] + rb * b.spin[0],
        ra * a.spin[1] + rb * b.spin[1],
        ra * a.spin[2] + rb * b.spin[2],
    ];
    let cross = [
        rw[1] * n[2] - rw[2] * n[1],
        rw[2] * n[0] - rw[0] * n[2],
        rw[0] * n[1] - rw[1] * n[0],
    ];
    let mut vs = [0.0; 3];
    for k in 0..3 {
        vs[k] = a.velocity[k] - b.velocity[k] - cross[k];
    }
    let vn = vs[0] * n[0] + vs[1] * n[1] + vs[2] * n[2];
    (
        [vs[0] - vn * n[0], vs[1] - vn * n[1], vs[2] - vn * n[2]],
        vn,
    )
}

/// Two equal spheres meet with normal speed v_n = 1 (along x) and tangential slip g_t (along
/// z), no spin, no damping, k_t = 2/7 k_n and friction `mu`; returns (slip and normal
/// relative velocity before, after, the engine's final states).
fn oblique(
    mu: f64,
    g_t: f64,
) -> (
    ([f64; 3], f64),
    ([f64; 3], f64),
    Vec<granflow::engine::dem::BodyState>,
) {
    let kn = 1e8;
    let mut p = mono(params(kn, 8.0, 6.0, 12.0));
    p.normal_damping = 0.0;
    p.tangential_damping_ratio = 0.0;
    p.friction = mu;
    let t_c = p.contact_types()[0].contact_time;
    p.time_step = t_c / 200.0;
    let states = vec![
        body(1.0, [4.0, 4.0, 3.0], [0.5, 0.0, 0.5 * g_t], [0.0; 3]),
        body(
            1.0,
            [4.0 + 1.0 + 1e-5, 4.0, 3.0],
            [-0.5, 0.0, -0.5 * g_t],
            [0.0; 3],
        ),
    ];
    let before = slip(&states);
    let mut e = engine(p, &states);
    e.advance_to_step(1200).unwrap();
    let s = e.states();
    assert!(e.contacts().is_empty(), "the contact has ended");
    (before, slip(&s), s)
}

/// Sticking (Walton's regime of the linear model): with k_t = 2/7 k_n the tangential
/// oscillation of the contact points has the frequency of the normal one,
/// w_t^2 = k_t (1/m_a + 1/m_b + R_a^2/I_a + R_b^2/I_b) = (7/2) k_t / m_eff = k_n / m_eff, and the
/// ratio |F_t| / F_n = (k_t g_t / w) / (k_n v_n / w) = (2/7) g_t / v_n stays constant during
/// the contact. Without damping and with g_t / v_n < 7 mu / 2 the contact sticks throughout,
/// lasts half a tangential period, and the slip is reversed exactly: g_t' = -g_t.
/// Tolerance: the contact ends at a step, up to dt away from the half period, which leaves a
/// slip error of order (w dt)^2 g_t (2.5e-4 at 200 steps per contact), and the line of centres
/// turns by about g_t t_c / d = 1.6e-5 rad during the contact (k_n = 1e8 keeps t_c short):
/// |g_t' + g_t| <= 4 (w dt)^2 |g_t|.
#[test]
fn an_oblique_contact_that_sticks_reverses_the_slip() {
    let g_t = 0.1;
    let (before, after, s) = oblique(10.0, g_t);
    let w_dt = std::f64::consts::PI / 200.0;
    let reversal = (after.0[2] + before.0[2]).abs() / g_t;
    println!(
        "sticking: slip {:?} -> {:?}, |g' + g| / g = {reversal:.2e}",
        before.0, after.0
    );
    assert!(reversal <= 4.0 * w_dt * w_dt, "{reversal:e}");
    assert!(
        (after.1 + before.1).abs() < 4.0 * w_dt * w_dt,
        "elastic normal rebound"
    );
    // equal spheres spin alike
    assert_eq!(s[0].spin, s[1].spin);
}

/// Gross sliding: with g_t / v_n > 7 mu the contact slides throughout; the tangential force is
/// mu F_n at every step (F_n >= 0 without damping), along the unchanging slip direction, so
/// the tangential impulse is mu times the normal one, and the slip of the contact points
/// drops by (7/2) mu |Delta v_n| (1/m_a + 1/m_b for the translation, R_a^2/I_a + R_b^2/I_b for
/// the rotation: a torque of the wrong sign would make it 2 - 5 = -3 instead of 7): here
/// g_t' = g_t - 7 mu v_n. The discrete identity holds to round-off up to the turning of the
/// line of centres during the contact (theta ~ g_t t_c / d = 1.6e-4 rad at k_n = 1e8): the
/// normal impulse 2 m_eff v_n then has a component of about 2 theta v_n m_eff along the slip
/// (measured in the fixed initial frame), 1e-3 of the drop: the tolerance.
#[test]
fn an_oblique_contact_that_slides_loses_seven_halves_mu_of_the_normal_impulse() {
    let (mu, g_t) = (0.05, 1.0);
    let (before, after, s) = oblique(mu, g_t);
    let normal_change = after.1 - before.1;
    let drop = before.0[2] - after.0[2];
    println!(
        "sliding: slip {:?} -> {:?}, v_n {} -> {}, drop {drop} vs 3.5 mu dv_n {}",
        before.0,
        after.0,
        before.1,
        after.1,
        3.5 * mu * normal_change
    );
    assert!((drop - 3.5 * mu * normal_change).abs() <= 1e-3 * drop);
    assert!((drop - 7.0 * mu * (-before.1)).abs() <= 1e-3 * drop);
    assert!(after.0[2] > 0.0, "still sliding forwards");
    assert_eq!(s[0].spin, s[1].spin);
}

/// A sphere launched along a wall (gravity towards the wall, normal force m g) slides with
/// the friction force mu m g: v(t) = v0 - mu g t, spin growing at mu m g R / I, until the
/// slip v + R w_z vanishes at t* = 2 v0 / (7 mu g); then it rolls at 5/7 v0 (the angular
/// momentum about the contact point, m R v - I w_z, is conserved: the friction force acts at
/// the contact point; exactly so in the scheme, whose kicks of v and w use the same F_t).
/// Tolerances: during sliding the cap is mu k_n delta = mu m g to round-off, but the setup
/// force call has no history yet (LAMMPS: |s| = 0 gives F_t = 0), so the deceleration starts
/// half a step late: |v - (v0 - mu g t)| <= mu g dt. At the end, after the tangential spring
/// oscillation has been damped (xi_t), the residual slip is below 1e-9 and
/// |v - 5/7 v0| <= (2/7) |slip| + 1e-12.
#[test]
fn a_sphere_slides_then_rolls_on_a_wall() {
    for d in [0.9, 1.0, 1.1] {
        let mut p = params(1e6, 8.0, 6.0, 12.0);
        p.gravity = [0.0, -1.0, 0.0];
        p.wall_friction = 0.5;
        let (mu, g, v0) = (0.5, 1.0, 1.0);
        let m = granflow::engine::dem::params::sphere_mass(d);
        let r = 0.5 * d;
        let y = r - m * g / p.normal_stiffness;
        let states = vec![
            body(d, [2.0, y, 3.0], [v0, 0.0, 0.0], [0.0; 3]),
            body(d, [6.0, 4.0, 3.0], [0.0; 3], [0.0; 3]),
        ];
        let dt = p.time_step;
        let mut e = engine(p, &states);
        let t_star = 2.0 * v0 / (7.0 * mu * g);
        let half = (0.5 * t_star / dt).round() as u64;
        e.advance_to_step(half).unwrap();
        let s = &e.states()[0];
        let t = half as f64 * dt;
        let expected = v0 - mu * g * t;
        println!("d = {d}: v({t:.4}) = {} vs {expected}", s.velocity[0]);
        assert!((s.velocity[0] - expected).abs() <= mu * g * dt, "sliding");
        let slip = s.velocity[0] + r * s.spin[2];
        assert!(
            (slip - (v0 - 3.5 * mu * g * t)).abs() <= 3.5 * mu * g * dt,
            "slip {slip}"
        );
        e.advance_to_step(((t_star + 1.0) / dt) as u64).unwrap();
        let s = &e.states()[0];
        let slip = s.velocity[0] + r * s.spin[2];
        println!(
            "d = {d}: rolling at v = {} (5/7 v0 = {}), slip {slip:e}",
            s.velocity[0],
            5.0 / 7.0 * v0
        );
        assert!(slip.abs() < 1e-9);
        assert!((s.velocity[0] - 5.0 / 7.0 * v0).abs() <= 2.0 / 7.0 * slip.abs() + 1e-12);
    }
}

/// A sphere resting on a wall under gravity (towards the wall) has the overlap m g / k_n.
/// Released touching the wall at rest, it oscillates and is damped (amplitude
/// m g / k_n exp(-xi_n t / 2), e^-123 after one time unit); the fixed point of the scheme is
/// k_n delta = m g to round-off, and delta = R - y is known to ulp(y) / delta = 2e-10: the
/// tolerance is 1e-8 relative.
#[test]
fn a_sphere_at_rest_on_a_wall_has_the_overlap_m_g_over_k_n() {
    for d in [0.9, 1.0, 1.1] {
        for kn in [1e5, 1e6] {
            let mut p = params(kn, 8.0, 6.0, 12.0);
            p.gravity = [0.0, -1.0, 0.0];
            let states = vec![
                body(d, [2.0, 0.5 * d, 3.0], [0.0; 3], [0.0; 3]),
                body(d, [6.0, 0.5 * d, 3.0], [0.0; 3], [0.0; 3]),
            ];
            let dt = p.time_step;
            let mut e = engine(p, &states);
            e.advance_to_step((1.0 / dt) as u64).unwrap();
            let m = granflow::engine::dem::params::sphere_mass(d);
            let expected = m / kn;
            for s in e.states() {
                let overlap = 0.5 * d - s.position[1];
                assert!(
                    (overlap / expected - 1.0).abs() < 1e-8,
                    "d = {d}, k_n = {kn}: overlap {overlap:e} vs m g / k_n = {expected:e}"
                );
            }
        }
    }
}

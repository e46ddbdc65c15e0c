//! Oracle 3 (docs/oracles.md section 3; Huthmann & Zippelius, Phys. Rev. E 56, R6275 (1997); Haff,
//! J. Fluid Mech. 134, 401 (1983)): homogeneous cooling of rough and smooth inelastic spheres.
//! - R/T tends to the Huthmann-Zippelius value h + sqrt(1 + h^2), h = (A - C)/(2B), within 3 %
//!   for six (e, beta) pairs of the table, two with e = 1 and four inelastic rough ones;
//! - for nearly smooth spheres (beta <= 0), where that Maxwellian closure is off by up to 7 %,
//!   R/T agrees with a DSMC solution of the Boltzmann equation (no closure) within 2 %;
//!   the DSMC itself reproduces Huthmann-Zippelius within 3 % where the closure holds;
//! - smooth spheres follow Haff's law T = T0 / (1 + t/t0)^2, t0 = 6/((1 - e^2) omega(T0)),
//!   within 3 %.
//!
//! Dilute (phi = 0.01) boxes a few mean free paths wide, so the homogeneous state holds
//! (no clustering) over the times checked, as the theory assumes.

use granflow::engine::dsmc::homogeneous::HomogeneousGas;
use granflow::engine::edmd::collision::ContactLaw;
use granflow::engine::edmd::{EdmdEngine, EdmdParams};
use granflow::engine::{Engine, StopAt};

fn cooling_box(n: usize, phi: f64, e: f64, beta: f64, seed: u64) -> EdmdParams {
    let side = (n as f64 * std::f64::consts::PI / 6.0 / phi).cbrt();
    let mut p = EdmdParams::periodic_elastic(side, n, 1.0, seed);
    p.restitution = e;
    p.roughness = beta;
    p
}

/// R/T = h + sqrt(1 + h^2) with A = (1 - e^2)/4 + eta (1 - eta), B = eta^2 / K,
/// C = (eta / K)(1 - eta / K), eta = K (1 + beta) / (2 (1 + K)).
fn huthmann_zippelius_ratio(e: f64, beta: f64, k: f64) -> f64 {
    let eta = k * (1.0 + beta) / (2.0 * (1.0 + k));
    let a = (1.0 - e * e) / 4.0 + eta * (1.0 - eta);
    let b = eta * eta / k;
    let c = (eta / k) * (1.0 - eta / k);
    let h = (a - c) / (2.0 * b);
    h + (1.0 + h * h).sqrt()
}

#[test]
fn formula_reproduces_the_table_of_the_oracles() {
    for (e, beta, table) in [
        (1.0, -0.5, 0.1549),
        (1.0, 0.0, 0.4),
        (0.9, 0.8, 1.0274),
        (0.8, -0.5, 1.4471),
        (0.5, 0.5, 1.5702),
    ] {
        let r = huthmann_zippelius_ratio(e, beta, 0.4);
        assert!(
            (r - table).abs() < 6e-5,
            "e = {e}, beta = {beta}: {r} vs table {table}"
        );
    }
}

/// Mean of E_rot / E_trans (= R/T) over collisions per particle 40..80 of a dilute cooling box.
/// The ratio relaxes from its initial value 1 at a rate of only ~0.15-0.2 per collision per
/// particle, so the first 40 are discarded.
fn measured_ratio(e: f64, beta: f64, seed: u64) -> f64 {
    let mut engine = EdmdEngine::new(cooling_box(2000, 0.01, e, beta, seed)).unwrap();
    engine.advance(StopAt::CollisionsPerParticle(40.0)).unwrap();
    let mut ratios = Vec::new();
    for s in 1..=40 {
        engine
            .advance(StopAt::CollisionsPerParticle(40.0 + s as f64))
            .unwrap();
        let snap = engine.particles_now();
        ratios.push(snap.rotational_energy / snap.translational_energy);
    }
    ratios.iter().sum::<f64>() / ratios.len() as f64
}

/// The same protocol solved by DSMC (Boltzmann equation, molecular chaos, no Maxwellian
/// closure) for `n` spheres: mean R/T over collisions per particle 40..80.
fn boltzmann_ratio(e: f64, beta: f64, n: usize, seed: u64) -> f64 {
    let law = ContactLaw {
        restitution: e,
        roughness: beta,
        inertia_factor: 0.4,
    };
    let mut gas = HomogeneousGas::new(n, law, seed);
    gas.advance_to(40.0);
    gas.renormalise();
    let mut ratios = Vec::new();
    for s in 1..=40 {
        gas.advance_to(40.0 + s as f64);
        let (t, r) = gas.temperatures();
        ratios.push(r / t);
        gas.renormalise();
    }
    ratios.iter().sum::<f64>() / ratios.len() as f64
}

/// Rough enough spheres (beta >= 0.5), where the Maxwellian closure of the theory holds.
/// Nearly smooth spheres (beta <= 0) are checked against the Boltzmann equation instead
/// (below): there the closure misses the non-Gaussian translation-rotation correlations
/// (Vega Reyes, Santos & Kremer, PRE 89, 020202, 2014; Megias & Santos 2023) and DSMC, which
/// has no closure, finds R/T up to 7 % below it.
const ROUGH_CASES: [(f64, f64); 6] = [
    (1.0, 0.5),
    (1.0, 0.8),
    (0.9, 0.5),
    (0.9, 0.8),
    (0.8, 0.5),
    (0.5, 0.8),
];

#[test]
fn dsmc_reference_matches_huthmann_zippelius_where_the_maxwellian_closure_holds() {
    for (k, (e, beta)) in ROUGH_CASES.into_iter().enumerate() {
        let mean = boltzmann_ratio(e, beta, 20_000, 40 + k as u64);
        let expected = huthmann_zippelius_ratio(e, beta, 0.4);
        eprintln!("DSMC e = {e}, beta = {beta}: R/T = {mean:.4}, Huthmann-Zippelius {expected:.4}");
        assert!(
            (mean / expected - 1.0).abs() < 0.03,
            "DSMC e = {e}, beta = {beta}: R/T = {mean} vs {expected}"
        );
    }
}

/// Mean of `runs` independent runs (seeds `seed`, `seed + 1`, ...).
fn mean_of_runs(runs: u64, seed: u64, run: impl Fn(u64) -> f64) -> f64 {
    (seed..seed + runs).map(run).sum::<f64>() / runs as f64
}

#[test]
fn nearly_smooth_spheres_follow_the_boltzmann_equation() {
    // e = 1, beta = 0 is the table's R/T = 2/5 entry: DSMC of the Boltzmann equation finds
    // 0.385 (N = 20 000), 4 % below the Maxwellian closure. Both methods run the same N = 2000:
    // R/T carries a finite-N bias of about +1 % there (DSMC 0.389 at N = 2000; the engine at
    // N = 4000, phi = 0.002 gives 0.385 like DSMC at N = 20 000), which then cancels.
    // Tolerance 2 %: one engine run scatters by 0.85 % (8 seeds), one DSMC run by 1.1 %, so the
    // difference of a 4-run and a 8-run mean has a standard error of 0.6 %: 2 % is 3 sigma;
    // the closure's error here (4-7 % for beta = 0) is well outside it.
    for (k, (e, beta)) in [(1.0, 0.0), (1.0, -0.5), (0.9, 0.0), (0.8, 0.0)]
        .into_iter()
        .enumerate()
    {
        let seed = 100 * (k as u64 + 1);
        let engine = mean_of_runs(4, seed, |s| measured_ratio(e, beta, s));
        let boltzmann = mean_of_runs(8, seed + 50, |s| boltzmann_ratio(e, beta, 2000, s));
        let closure = huthmann_zippelius_ratio(e, beta, 0.4);
        eprintln!(
            "e = {e}, beta = {beta}: R/T = {engine:.4}, DSMC {boltzmann:.4}, \
             Huthmann-Zippelius (Maxwellian) {closure:.4}"
        );
        assert!(
            (engine / boltzmann - 1.0).abs() < 0.02,
            "e = {e}, beta = {beta}: R/T = {engine} vs DSMC {boltzmann}"
        );
    }
}

#[test]
fn rotational_to_translational_temperature_ratio_matches_huthmann_zippelius() {
    // T = m<c^2>/3, R = I<w^2>/3: with N particles, R/T = E_rot / E_trans.
    // Elastic-normal rough cases (e = 1) and inelastic rough cases.
    for (k, (e, beta)) in ROUGH_CASES.into_iter().enumerate() {
        let mean = measured_ratio(e, beta, 20 + k as u64);
        let expected = huthmann_zippelius_ratio(e, beta, 0.4);
        eprintln!("e = {e}, beta = {beta}: R/T = {mean:.4}, Huthmann-Zippelius {expected:.4}");
        assert!(
            (mean / expected - 1.0).abs() < 0.03,
            "e = {e}, beta = {beta}: R/T = {mean} vs {expected}"
        );
    }
}

#[test]
fn smooth_spheres_follow_haffs_law() {
    let (n, phi, e) = (8000, 0.01, 0.9);
    let mut engine = EdmdEngine::new(cooling_box(n, phi, e, -1.0, 31)).unwrap();
    let start = engine.particles_now();
    let t0_temp = 2.0 * start.translational_energy / (3.0 * n as f64);
    let g = (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
    let omega0 =
        4.0 * (phi / (std::f64::consts::PI / 6.0)) * g * (std::f64::consts::PI * t0_temp).sqrt();
    let t0 = 6.0 / ((1.0 - e * e) * omega0);
    let mut worst: f64 = 0.0;
    for k in 1..=8 {
        let t = 0.25 * k as f64 * t0; // down to T ~ T0 / 9
        engine.advance(StopAt::Time(t)).unwrap();
        let s = engine.particles_now();
        let temp = 2.0 * s.translational_energy / (3.0 * n as f64);
        let haff = t0_temp / (1.0 + t / t0).powi(2);
        worst = worst.max((temp / haff - 1.0).abs());
        assert!(
            (temp / haff - 1.0).abs() < 0.03,
            "t/t0 = {}: T = {temp}, Haff {haff}",
            t / t0
        );
    }
    eprintln!("Haff's law: largest relative deviation {worst:.4}");
}

//! Oracles of the thesis' statistics (docs/oracles.md section 2):
//! - elastic, perfectly rough hard spheres in a periodic box at phi = 0.1 and 0.3 (equilibrium
//!   with the spins taking part): every fluctuation component
//!   Gaussian (skewness 0 and kurtosis 3 within 4 batch-means errors, the VDF within 0.06 of
//!   exp(-x^2/2) for |x| <= 1.5; errors: batch means, at least those of independent samples),
//!   g(d+) within 2 % of Carnahan-Starling, g -> 1 at large r
//!   (within 1 %), velocity correlations 0 within 5 standard errors, Lambda = 1/3 within 4
//!   errors, the mean free path within 2 % of 1 / (sqrt 2 pi n d^2 g_CS(d)) (Carnahan-Starling
//!   is good to ~0.5 % here; a wrong chord or a lost path would be off by far more);
//! - homogeneous cooling of smooth inelastic spheres: a2 within 25 % of van Noije & Ernst's
//!   first Sonine approximation at e = 0.8 and 0.9;
//! - the estimators on hand-made particle sets with known answers: a simple cubic lattice
//!   (g(r) counts 6, 12, 8 neighbours with the exact shell normalisation), an ideal gas between
//!   walls (g = 1 in every slab, the wall slabs included), dimers with built-in velocity
//!   correlations, and particles with known angles Psi between C and Omega.

use granflow::analysis::statistics::{
    self, Statistics, StatisticsPlan, StatisticsSettings, WindowRecord,
};
use granflow::analysis::{AnalysisSettings, record_snapshot};
use granflow::engine::edmd::{EdmdEngine, EdmdParams};
use granflow::engine::{
    BoxGeometry, Content, Counters, Engine, Particles, Progress, Snapshot, StopAt,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// Carnahan-Starling contact value (1 - phi/2) / (1 - phi)^3.
fn carnahan_starling(phi: f64) -> f64 {
    (1.0 - phi / 2.0) / (1.0 - phi).powi(3)
}

/// Run `engine` through `snapshots` snapshots `every` time units apart after `warmup` time
/// units (time stops: no snapshot falls on a collision), recording statistics at each, and
/// analyse them all.
fn run_statistics(
    engine: &mut EdmdEngine,
    settings: StatisticsSettings,
    warmup: f64,
    every: f64,
    snapshots: u32,
) -> (Statistics, Vec<statistics::StatisticsRecord>) {
    let plan = StatisticsPlan::every_snapshot(settings);
    engine.advance(StopAt::Time(warmup)).unwrap();
    engine.record_free_paths(plan.settings.bins);
    let mut structure = Vec::new();
    let mut records = Vec::new();
    for k in 1..=snapshots {
        engine
            .advance(StopAt::Time(warmup + every * k as f64))
            .unwrap();
        let snap = engine.snapshot();
        let paths = engine.take_free_paths();
        structure.push(record_snapshot(&snap, &AnalysisSettings::default()));
        records.push(plan.record(k, &snap, paths));
    }
    let window: Vec<WindowRecord> = structure
        .iter()
        .zip(&records)
        .map(|(s, r)| WindowRecord {
            structure: s,
            statistics: r,
        })
        .collect();
    let all = (f64::NEG_INFINITY, f64::INFINITY);
    (statistics::analyse(&window, &plan, all, &[]), records)
}

fn periodic(n: usize, phi: f64, seed: u64) -> EdmdParams {
    let side = (n as f64 * std::f64::consts::PI / 6.0 / phi).cbrt();
    EdmdParams::periodic_elastic(side, n, 1.0, seed)
}

#[test]
fn elastic_hard_spheres_in_equilibrium_meet_kinetic_theory() {
    for (phi, seed) in [(0.1, 3), (0.3, 4)] {
        // perfectly rough (beta = 1) elastic spheres: energy is conserved and the spins take
        // part (smooth spheres keep their initial spins, a sample of 2000 values, for ever)
        let mut params = periodic(2000, phi, seed);
        params.roughness = 1.0;
        params.wall_roughness = 1.0;
        let mut engine = EdmdEngine::new(params).unwrap();
        let settings = StatisticsSettings {
            bins: 3,
            r_max: 4.0,
            vcf_dr: 0.5,
            ..StatisticsSettings::default()
        };
        // mean free time 1 / omega: 0.7 (phi = 0.1) and 0.11 (phi = 0.3) at kT = 1; snapshots a
        // few collision times apart
        let tau = 1.0
            / (4.0 * phi / (std::f64::consts::PI / 6.0)
                * carnahan_starling(phi)
                * std::f64::consts::PI.sqrt());
        let (s, _) = run_statistics(&mut engine, settings, 20.0 * tau, 3.0 * tau, 250);
        let where_ = format!("phi = {phi}");
        // VDFs: Gaussian
        // the error: the batch-means one, or where that is smaller (10 blocks estimate it to
        // ~25 %) the one of independent samples, sqrt(6/n) and sqrt(24/n) for a Gaussian
        for m in &s.vdf_moments {
            let n = m.samples as f64;
            let kurtosis_error = m.kurtosis_error.max((24.0 / n).sqrt());
            let skewness_error = m.skewness_error.max((6.0 / n).sqrt());
            eprintln!(
                "{where_} slab {} {}: kurtosis {:.4} +- {:.4}, skewness {:.4} +- {:.4}",
                m.slab, m.component, m.kurtosis, kurtosis_error, m.skewness, skewness_error
            );
            assert!(kurtosis_error < 0.05, "{where_}: {m:?}");
            assert!(
                (m.kurtosis - 3.0).abs() < 4.0 * kurtosis_error,
                "{where_}: kurtosis {m:?}"
            );
            assert!(
                m.skewness.abs() < 4.0 * skewness_error,
                "{where_}: skewness {m:?}"
            );
        }
        assert_eq!(s.vdf_moments.len(), 3 * 6);
        // the histograms: unit variance (x is scaled by the pooled sigma; 2 % allows for the
        // bins' width, dx^2/12 = 0.3 %, and noise), and within 0.08 of the Gaussian for
        // |x| <= 1.5 (P(0) is itself one noisy bin; 18 series x 15 points)
        for (slab, component) in s.vdf_moments.iter().map(|m| (m.slab, m.component.clone())) {
            let rows: Vec<_> = s
                .vdf
                .iter()
                .filter(|r| r.slab == slab && r.component == component)
                .collect();
            let dx = rows[1].x - rows[0].x;
            let variance: f64 = rows.iter().map(|r| r.x * r.x * r.density * dx).sum();
            assert!(
                (variance - 1.0).abs() < 0.02,
                "{where_}: slab {slab} {component}: <x^2> = {variance}"
            );
        }
        let worst = s
            .vdf
            .iter()
            .filter(|r| r.x.abs() <= 1.5)
            .map(|r| (r.p - (-0.5 * r.x * r.x).exp()).abs())
            .fold(0.0, f64::max);
        eprintln!("{where_}: VDF within {worst:.4} of the Gaussian for |x| <= 1.5");
        assert!(worst < 0.08, "{where_}: VDF off the Gaussian by {worst}");
        // g(d+) against Carnahan-Starling, g -> 1 far away
        let cs = carnahan_starling(phi);
        eprintln!(
            "{where_}: g(d+) = {:.4} (centre slab {:.4}), Carnahan-Starling {cs:.4}",
            s.summary.contact_value, s.summary.contact_value_centre
        );
        assert!(
            (s.summary.contact_value / cs - 1.0).abs() < 0.02,
            "{where_}: g(d+) = {} vs {cs}",
            s.summary.contact_value
        );
        let far: Vec<f64> = s
            .pair_correlation
            .iter()
            .filter(|r| r.slab.is_none() && r.r > 3.0)
            .map(|r| r.g)
            .collect();
        let far_mean = far.iter().sum::<f64>() / far.len() as f64;
        eprintln!("{where_}: g over 3 < r < 4: {far_mean:.4}");
        assert!(
            (far_mean - 1.0).abs() < 0.01,
            "{where_}: g far = {far_mean}"
        );
        assert!(
            s.pair_correlation
                .iter()
                .filter(|r| r.r < 0.98)
                .all(|r| r.pairs == 0),
            "{where_}: pairs closer than d"
        );
        // velocity correlations: zero within 5 standard errors (1/sqrt(pairs) for independent
        // velocities), less the slab mean's -1/(N_slab - 1) for pairs of one slab
        let slab_bias = 1.0 / (2000.0 / 3.0 - 1.0);
        let mut worst_z = 0.0f64;
        for r in &s.velocity_correlation {
            let se = 1.0 / (r.pairs as f64).sqrt();
            let z = (r.c.abs() - slab_bias).max(0.0) / se;
            worst_z = worst_z.max(z);
            assert!(z < 5.0, "{where_}: {r:?} is {z:.1} standard errors from 0");
        }
        eprintln!(
            "{where_}: {} velocity-correlation points, the largest {worst_z:.2} standard errors from 0",
            s.velocity_correlation.len()
        );
        // Lambda: 1/3
        for r in &s.orientation {
            eprintln!(
                "{where_}: Lambda slab {} = {:.4} +- {:.4}",
                r.slab, r.lambda, r.error
            );
            assert!(r.error > 0.0 && r.error < 0.01, "{where_}: {r:?}");
            assert!(
                (r.lambda - 1.0 / 3.0).abs() < 4.0 * r.error,
                "{where_}: {r:?}"
            );
        }
        // mean free path
        let n = phi / (std::f64::consts::PI / 6.0);
        let lambda = 1.0 / (std::f64::consts::SQRT_2 * std::f64::consts::PI * n * cs);
        eprintln!(
            "{where_}: mean free path {:.4} over {} paths, kinetic theory {lambda:.4}",
            s.summary.mean_free_path, s.summary.free_paths
        );
        assert!(s.summary.free_paths > 100_000);
        assert!(
            (s.summary.mean_free_path / lambda - 1.0).abs() < 0.02,
            "{where_}: lambda = {} vs {lambda}",
            s.summary.mean_free_path
        );
        assert_eq!(s.summary.wall_path_fraction, 0.0);
    }
}

/// A snapshot of hand-made particles (no gravity, K = 2/5).
fn snapshot_of(
    geometry: BoxGeometry,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    spins: Vec<[f64; 3]>,
) -> Snapshot {
    Snapshot {
        progress: Progress::default(),
        counters: Counters::default(),
        content: Content::Particles(Particles {
            geometry,
            inertia_factor: 0.4,
            gravity: 0.0,
            positions,
            velocities,
            angular_velocities: spins,
            diameters: Vec::new(),
            translational_energy: 0.0,
            rotational_energy: 0.0,
            wall_momentum: [[0.0; 3]; 2],
            energy_dissipated: 0.0,
            gravity_work: 0.0,
            suppressed_dissipation: 0.0,
        }),
    }
}

/// The statistics of hand-made snapshots, all in the window.
fn analyse_snapshots(snapshots: &[Snapshot], settings: StatisticsSettings) -> Statistics {
    let plan = StatisticsPlan::every_snapshot(settings);
    let structure: Vec<_> = snapshots
        .iter()
        .map(|s| record_snapshot(s, &AnalysisSettings::default()))
        .collect();
    let records: Vec<_> = snapshots
        .iter()
        .enumerate()
        .map(|(k, s)| plan.record(k as u32 + 1, s, None))
        .collect();
    let window: Vec<WindowRecord> = structure
        .iter()
        .zip(&records)
        .map(|(s, r)| WindowRecord {
            structure: s,
            statistics: r,
        })
        .collect();
    statistics::analyse(&window, &plan, (f64::NEG_INFINITY, f64::INFINITY), &[])
}

fn gaussian(rng: &mut Pcg64) -> f64 {
    // Box-Muller
    let (u, v): (f64, f64) = (rng.random(), rng.random());
    (-2.0 * (1.0 - u).ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

fn cube(side: f64, walls: bool) -> BoxGeometry {
    BoxGeometry {
        length: side,
        width: side,
        height: side,
        walls,
    }
}

/// Brute-force ordered pair counts per distance bin (minimum image along the periodic axes).
fn brute_counts(g: &BoxGeometry, r: &[[f64; 3]], r_max: f64, dr: f64) -> Vec<u64> {
    let ext = g.extents();
    let mut out = vec![0u64; (r_max / dr).ceil() as usize];
    for i in 0..r.len() {
        for j in 0..r.len() {
            if i == j {
                continue;
            }
            let mut d2 = 0.0;
            for a in 0..3 {
                let mut d = r[i][a] - r[j][a];
                if a != 1 || !g.walls {
                    d -= ext[a] * (d / ext[a]).round();
                }
                d2 += d * d;
            }
            if d2 < r_max * r_max {
                let last = out.len() - 1;
                out[((d2.sqrt() / dr) as usize).min(last)] += 1;
            }
        }
    }
    out
}

/// The pair counts of g(r): a simple cubic lattice has 6, 12 and 8 neighbours at a, a sqrt 2
/// and a sqrt 3 and none closer; random sets (periodic, between walls, boxes of one and of
/// several cells per axis) match a brute-force count pair for pair.
#[test]
fn pair_counts_match_a_lattice_and_brute_force() {
    let a = 1.11;
    let mut lattice = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            for k in 0..8 {
                lattice.push([i, j, k].map(|c| (c as f64 + 0.5) * a));
            }
        }
    }
    let n = lattice.len();
    let geometry = cube(8.0 * a, false);
    let snap = snapshot_of(geometry, lattice, vec![[0.0; 3]; n], Vec::new());
    let settings = StatisticsSettings {
        bins: 4,
        r_max: 2.1,
        ..StatisticsSettings::default()
    };
    let s = analyse_snapshots(std::slice::from_ref(&snap), settings);
    let overall: Vec<_> = s
        .pair_correlation
        .iter()
        .filter(|r| r.slab.is_none())
        .collect();
    let shells: Vec<(f64, u64)> = overall
        .iter()
        .filter(|r| r.pairs > 0)
        .map(|r| (r.r, r.pairs))
        .collect();
    let expect = [(a, 6), (a * 2f64.sqrt(), 12), (a * 3f64.sqrt(), 8)];
    assert_eq!(shells.len(), 3, "{shells:?}");
    for ((r, count), (want_r, per)) in shells.iter().zip(expect) {
        assert!(
            (r - want_r).abs() <= 0.01,
            "shell at {r}, expected {want_r}"
        );
        assert_eq!(*count, per * n as u64, "shell at {want_r}");
    }
    // each slab sees the same neighbours
    for slab in 0..4u32 {
        let pairs: u64 = s
            .pair_correlation
            .iter()
            .filter(|r| r.slab == Some(slab))
            .map(|r| r.pairs)
            .sum();
        assert_eq!(pairs, 26 * n as u64 / 4, "slab {slab}");
    }
    // random sets against brute force
    let mut rng = Pcg64::seed_from_u64(7);
    for (walls, r_max) in [(false, 2.1), (false, 4.4), (true, 2.1), (true, 4.4)] {
        let g = cube(9.0, walls);
        let r: Vec<[f64; 3]> = (0..700)
            .map(|_| {
                let y = if walls {
                    0.5 + 8.0 * rng.random::<f64>()
                } else {
                    9.0 * rng.random::<f64>()
                };
                [9.0 * rng.random::<f64>(), y, 9.0 * rng.random::<f64>()]
            })
            .collect();
        let dr = 0.05;
        let brute = brute_counts(&g, &r, r_max, dr);
        let snap = snapshot_of(g, r, vec![[0.0; 3]; 700], Vec::new());
        let s = analyse_snapshots(
            std::slice::from_ref(&snap),
            StatisticsSettings {
                bins: 3,
                r_max,
                dr,
                vcf_dr: dr,
                ..StatisticsSettings::default()
            },
        );
        let mut counted = vec![0u64; brute.len()];
        for row in s.pair_correlation.iter().filter(|r| r.slab.is_none()) {
            counted[(row.r / dr) as usize] = row.pairs;
        }
        assert_eq!(counted, brute, "walls {walls}, r_max {r_max}");
    }
}

/// An ideal gas (uniform centres, no exclusion) has g = 1 at every r in every slab: between
/// walls too, where a shell around a particle near a wall is cut by it (the normalisation
/// counts only its part inside; a plain 4 pi r^2 dr would give ~0.7 there).
#[test]
fn an_ideal_gas_has_g_one_in_every_slab() {
    let mut rng = Pcg64::seed_from_u64(11);
    for walls in [true, false] {
        let (l, w, h) = (12.0, 10.0, 12.0);
        let geometry = BoxGeometry {
            length: l,
            width: w,
            height: h,
            walls,
        };
        let snapshots: Vec<Snapshot> = (0..40)
            .map(|_| {
                let r: Vec<[f64; 3]> = (0..1500)
                    .map(|_| {
                        let y = if walls {
                            0.5 + (w - 1.0) * rng.random::<f64>()
                        } else {
                            w * rng.random::<f64>()
                        };
                        [l * rng.random::<f64>(), y, h * rng.random::<f64>()]
                    })
                    .collect();
                snapshot_of(geometry, r, vec![[0.0; 3]; 1500], Vec::new())
            })
            .collect();
        let s = analyse_snapshots(
            &snapshots,
            StatisticsSettings {
                bins: 5,
                r_max: 3.0,
                dr: 0.1,
                vcf_dr: 0.1,
                ..StatisticsSettings::default()
            },
        );
        for slab in [None, Some(0), Some(2), Some(4)] {
            let rows: Vec<_> = s
                .pair_correlation
                .iter()
                .filter(|r| r.slab == slab && r.r > 0.5)
                .collect();
            let (pairs, weighted): (u64, f64) = rows.iter().fold((0, 0.0), |(p, w), r| {
                (p + r.pairs, w + r.pairs as f64 / r.g)
            });
            let mean = pairs as f64 / weighted;
            eprintln!(
                "walls {walls}, slab {slab:?}: g over 0.5 < r < 3 = {mean:.4} ({pairs} pairs)"
            );
            assert!(
                (mean - 1.0).abs() < 4.0 / (pairs as f64).sqrt() + 0.003,
                "walls {walls}, slab {slab:?}: g = {mean}"
            );
            for r in rows {
                let sigma = (r.pairs as f64).sqrt().max(1.0) / (r.pairs as f64 / r.g);
                assert!(
                    (r.g - 1.0).abs() < 5.0 * sigma,
                    "walls {walls}, slab {slab:?}: {r:?}"
                );
            }
        }
    }
}

/// Dimers 1.5 d long, 6 d apart, with the second particle's velocity built from the first's:
/// c' = M c + noise (unit variances), M = [[0.6, 0.2, 0], [0, -0.3, 0], [0, 0, 0]]. Then
/// C_xx = 0.6, C_yy = -0.3, C_zz = 0, C_xy = (0.2 + 0)/2 = 0.1, C_xz = C_yz = 0 at r = 1.5 and
/// no pairs elsewhere (within 5 standard errors, 1/sqrt(pairs), and the slab mean's -1/(N-1)).
#[test]
fn velocity_correlations_of_dimers_are_the_built_in_ones() {
    let mut rng = Pcg64::seed_from_u64(5);
    let m = [[0.6, 0.2, 0.0], [0.0, -0.3, 0.0], [0.0, 0.0, 0.0]];
    let geometry = cube(48.0, false);
    let snapshots: Vec<Snapshot> = (0..25)
        .map(|_| {
            let (mut r, mut c) = (Vec::new(), Vec::new());
            for i in 0..8 {
                for j in 0..8 {
                    for k in 0..8 {
                        let centre = [i, j, k].map(|q| 6.0 * q as f64 + 3.0);
                        let u = {
                            let v = [gaussian(&mut rng), gaussian(&mut rng), gaussian(&mut rng)];
                            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                            v.map(|x| 0.75 * x / n)
                        };
                        r.push([0, 1, 2].map(|a| centre[a] - u[a]));
                        r.push([0, 1, 2].map(|a| centre[a] + u[a]));
                        let first = [gaussian(&mut rng), gaussian(&mut rng), gaussian(&mut rng)];
                        let second = [0, 1, 2].map(|a| {
                            let built: f64 = (0..3).map(|b| m[a][b] * first[b]).sum();
                            let rest = 1.0 - m[a].iter().map(|x| x * x).sum::<f64>();
                            built + rest.sqrt() * gaussian(&mut rng)
                        });
                        c.push(first);
                        c.push(second);
                    }
                }
            }
            snapshot_of(geometry, r, c, Vec::new())
        })
        .collect();
    let s = analyse_snapshots(
        &snapshots,
        StatisticsSettings {
            bins: 1,
            r_max: 3.0,
            ..StatisticsSettings::default()
        },
    );
    let expected = [
        ("xx", 0.6),
        ("yy", -0.3),
        ("zz", 0.0),
        ("xy", 0.1),
        ("xz", 0.0),
        ("yz", 0.0),
    ];
    assert_eq!(
        s.velocity_correlation.len(),
        6,
        "{:?}",
        s.velocity_correlation
    );
    for (pair, want) in expected {
        let row = s
            .velocity_correlation
            .iter()
            .find(|r| r.pair == pair)
            .unwrap();
        let se = 1.0 / (row.pairs as f64).sqrt();
        eprintln!(
            "C_{pair}({:.2}) = {:.4} (built in {want}, +- {se:.4})",
            row.r, row.c
        );
        assert!((row.r - 1.5).abs() < 0.11, "{row:?}");
        assert!((row.c - want).abs() < 5.0 * se + 0.002, "{row:?} vs {want}");
    }
}

/// Particles whose fluctuations C and Omega make known angles Psi (0, 30, 45, 60, 90 degrees),
/// each with a mirror (-c, -w) in its slab so that the slab means vanish: Lambda is the mean
/// cos^2 Psi of its slab, to round-off.
#[test]
fn lambda_of_known_angles() {
    let mut rng = Pcg64::seed_from_u64(9);
    let angles = [0.0, 30.0, 45.0, 60.0, 90.0].map(|d: f64| d.to_radians());
    let geometry = cube(20.0, true);
    let (mut r, mut c, mut w) = (Vec::new(), Vec::new(), Vec::new());
    let mut expected = [(0.0, 0usize); 2];
    for i in 0..400 {
        let slab = i % 2;
        let psi = angles[(i / 2 + slab) % angles.len()];
        // orthonormal e1, e2 from a random direction
        let v = [gaussian(&mut rng), gaussian(&mut rng), gaussian(&mut rng)];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let e1 = v.map(|x| x / n);
        let t = if e1[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let d = t[0] * e1[0] + t[1] * e1[1] + t[2] * e1[2];
        let e2 = {
            let u = [0, 1, 2].map(|a| t[a] - d * e1[a]);
            let m = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
            u.map(|x| x / m)
        };
        let speed = 0.5 + rng.random::<f64>();
        let spin = 0.5 + rng.random::<f64>();
        let cv = e1.map(|x| speed * x);
        let wv = [0, 1, 2].map(|a| spin * (psi.cos() * e1[a] + psi.sin() * e2[a]));
        let y = if slab == 0 { 3.0 } else { 15.0 };
        let x = 19.0 * rng.random::<f64>();
        for sign in [1.0, -1.0] {
            r.push([x + 0.5 * (sign + 1.0) * 0.5, y, 10.0]);
            c.push(cv.map(|q| sign * q));
            w.push(wv.map(|q| sign * q));
            expected[slab].0 += psi.cos().powi(2);
            expected[slab].1 += 1;
        }
    }
    let snap = snapshot_of(geometry, r, c, w);
    let s = analyse_snapshots(
        std::slice::from_ref(&snap),
        StatisticsSettings {
            bins: 2,
            r_max: 2.0,
            ..StatisticsSettings::default()
        },
    );
    assert_eq!(s.orientation.len(), 2);
    for row in &s.orientation {
        let (sum, count) = expected[row.slab as usize];
        let want = sum / count as f64;
        assert!(
            (row.lambda - want).abs() < 1e-9,
            "slab {}: Lambda {} vs {want}",
            row.slab,
            row.lambda
        );
    }
}

/// Known non-Gaussian distributions: C_x uniform on [-1, 1] (skewness 0, kurtosis 9/5, density
/// 1/(2 sqrt 3) over |x| < sqrt 3 in units of sigma) and C_y = E - 1 with E exponential
/// (skewness 2, kurtosis 9); C_z Gaussian. Within 4 batch-means errors (5 % for the density).
#[test]
fn moments_and_histograms_of_known_distributions() {
    let mut rng = Pcg64::seed_from_u64(13);
    let geometry = cube(30.0, false);
    let snapshots: Vec<Snapshot> = (0..20)
        .map(|_| {
            let n = 5000;
            let r: Vec<[f64; 3]> = (0..n)
                .map(|_| [0, 1, 2].map(|_| 30.0 * rng.random::<f64>()))
                .collect();
            let c: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    let u: f64 = rng.random();
                    let e = -(1.0 - rng.random::<f64>()).ln();
                    [2.0 * u - 1.0, e - 1.0, gaussian(&mut rng)]
                })
                .collect();
            snapshot_of(geometry, r, c, Vec::new())
        })
        .collect();
    let s = analyse_snapshots(
        &snapshots,
        StatisticsSettings {
            bins: 1,
            r_max: 1.0,
            ..StatisticsSettings::default()
        },
    );
    for (component, skew, kurt) in [("C_x", 0.0, 1.8), ("C_y", 2.0, 9.0), ("C_z", 0.0, 3.0)] {
        let m = s
            .vdf_moments
            .iter()
            .find(|m| m.component == component)
            .unwrap();
        eprintln!(
            "{component}: skewness {:.3} +- {:.3}, kurtosis {:.3} +- {:.3}",
            m.skewness, m.skewness_error, m.kurtosis, m.kurtosis_error
        );
        assert!((m.skewness - skew).abs() < 4.0 * m.skewness_error, "{m:?}");
        assert!((m.kurtosis - kurt).abs() < 4.0 * m.kurtosis_error, "{m:?}");
    }
    // the uniform's density, 1/(2 sqrt 3) = 0.2887 inside |x| < sqrt 3, and none outside
    let uniform = 1.0 / (2.0 * 3f64.sqrt());
    for r in s.vdf.iter().filter(|r| r.component == "C_x") {
        if r.x.abs() < 3f64.sqrt() - 0.15 {
            assert!((r.density / uniform - 1.0).abs() < 0.05, "{r:?}");
            assert!((r.p - 1.0).abs() < 0.08, "{r:?}");
        } else if r.x.abs() > 3f64.sqrt() + 0.15 {
            assert!(r.density < 1e-3, "{r:?}");
        }
    }
}

/// van Noije & Ernst (1998), first Sonine approximation for smooth inelastic hard spheres in
/// 3D: a2 = 16 (1 - e)(1 - 2 e^2) / (81 - 17 e + 30 e^2 (1 - e)).
fn a2_van_noije_ernst(e: f64) -> f64 {
    16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) / (81.0 - 17.0 * e + 30.0 * e * e * (1.0 - e))
}

/// Homogeneous cooling of smooth inelastic spheres (dilute: phi = 0.01, a box 5 mean free paths
/// wide, so the homogeneous state holds): the fourth cumulant a2 = kurtosis / 3 - 1 of a
/// velocity component, from each snapshot's power sums (the temperature falls: each snapshot
/// is standardised by its own variance), averaged over 500 snapshots one collision per
/// particle apart after 40 of relaxation, within 25 % of van Noije & Ernst (their first Sonine
/// approximation is good to ~10-20 % here), with a standard error below 12.5 % of a2, so that
/// the tolerance is at least two errors and a Gaussian (a2 = 0) fails by eight.
#[test]
fn homogeneous_cooling_has_the_sonine_a2() {
    for (e, seed) in [(0.8, 21), (0.9, 22)] {
        let mut p = periodic(4000, 0.01, seed);
        p.restitution = e;
        let mut engine = EdmdEngine::new(p).unwrap();
        let plan = StatisticsPlan::every_snapshot(StatisticsSettings {
            bins: 1,
            r_max: 1.0,
            ..StatisticsSettings::default()
        });
        engine.advance(StopAt::CollisionsPerParticle(40.0)).unwrap();
        let mut a2 = Vec::new();
        for k in 1..=500u32 {
            engine
                .advance(StopAt::CollisionsPerParticle(40.0 + k as f64))
                .unwrap();
            let snap = engine.snapshot();
            let record = plan.record(k, &snap, None);
            let v = &record.sample.as_ref().unwrap().vdf;
            let n: u64 = (0..3).map(|a| v.count[a]).sum();
            let m2 = (0..3).map(|a| v.s2[a]).sum::<f64>() / n as f64;
            let m4 = (0..3).map(|a| v.s4[a]).sum::<f64>() / n as f64;
            a2.push(m4 / (m2 * m2) / 3.0 - 1.0);
        }
        let refs: Vec<&f64> = a2.iter().collect();
        let mean = |s: &[&f64]| s.iter().map(|x| **x).sum::<f64>() / s.len() as f64;
        let measured = mean(&refs);
        let se = statistics::blocks::batch_error(&refs, mean);
        let theory = a2_van_noije_ernst(e);
        eprintln!("e = {e}: a2 = {measured:.5} +- {se:.5}, van Noije & Ernst {theory:.5}");
        assert!(
            se < 0.125 * theory.abs(),
            "e = {e}: error {se} too large to test"
        );
        assert!(
            (measured - theory).abs() < 0.25 * theory.abs(),
            "e = {e}: a2 = {measured} +- {se} vs {theory}"
        );
    }
}

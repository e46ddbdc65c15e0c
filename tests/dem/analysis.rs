//! The dense analysis against synthetic DEM records whose answers are known: a linear
//! velocity profile and its shear rate, a given temperature, the stress of a known set of
//! contacts in the paper's axes, the block errors of a known series, the profile of eq. 3.1
//! and its constant, the regime of an accelerating and of a stopped flow, and Q6 of the plug.

use granflow::analysis::dense::{DenseSettings, analyse, shear_layer};
use granflow::engine::dem::{
    BinSums, Bins, BondSums, DampingFrom, IntervalSums, Record, RunConstants, SizeMix,
};

/// W = 10 (bins 0, 1.5, 2.5, ..., 8.5, 10), L = 2, B = 2 (bin cross-section 4).
const W: f64 = 10.0;
const AREA: f64 = 4.0;
const MASS: f64 = 100.0;

fn constants(width: f64) -> RunConstants {
    RunConstants {
        width,
        span: 2.0,
        length: 2.0,
        particles: 100,
        volume_fraction: 0.5,
        total_mass: MASS,
        gravity: [1.0, 0.0, 0.0],
        time_step: 0.01,
        sample_every: 1,
        size_mix: SizeMix::default(),
        normal_stiffness: 1e5,
        tangential_stiffness: 2e5 / 7.0,
        normal_damping: 78.0,
        tangential_damping: 39.0,
        damping_from: DampingFrom::Restitution,
        friction: 0.5,
        wall_friction: 0.5,
        contact_types: Vec::new(),
        bin_edges: Bins::new(width).edges,
        bond_cutoff: 1.2,
    }
}

/// One sample of a bin of n particles of mass m moving at (u, 0, 0) with fluctuations of
/// temperature t (m <v'^2> = 2 t per translational direction: 6 t over 6 degrees of freedom
/// with no spin) at volume fraction phi.
fn bin(n: f64, m: f64, u: f64, t: f64, phi: f64, volume: f64) -> BinSums {
    let p = m * n * u;
    let mut b = BinSums {
        count: n,
        volume: phi * volume,
        mass: m * n,
        inertia: 0.1 * m * n,
        momentum: [p, 0.0, 0.0],
        ..Default::default()
    };
    // sum m v_a v_b = P_a P_b / M + sum m v'_a v'_b
    b.mean_momentum_flux[0] = p * p / (m * n);
    b.momentum_flux[0] = b.mean_momentum_flux[0] + 2.0 * n * t;
    b.momentum_flux[1] = 2.0 * n * t;
    b.momentum_flux[2] = 2.0 * n * t;
    b
}

/// A record of one sample, the bins from `f(centre, volume)`, the walls carrying
/// `balance` of the weight and the centre of mass at `u_cm`.
fn record(k: u64, width: f64, balance: f64, u_cm: f64, f: &dyn Fn(f64, f64) -> BinSums) -> Record {
    let c = constants(width);
    let edges = c.bin_edges.clone();
    let bins = edges
        .windows(2)
        .map(|e| f(0.5 * (e[0] + e[1]), (e[1] - e[0]) * AREA))
        .collect();
    let half = 0.5 * balance * MASS;
    Record {
        constants: c,
        sums: IntervalSums {
            start_step: 100 * k,
            end_step: 100 * (k + 1),
            duration: 1.0,
            samples: 1,
            bins,
            force_steps: 1,
            wall_force: [[half, -3.0, 0.0], [half, 3.0, 0.0]],
            com_velocity: [u_cm, 0.0, 0.0],
            ..Default::default()
        },
        bonds: Vec::new(),
    }
}

fn profile(a: &granflow::analysis::dense::DenseAnalysis, q: &str) -> Vec<(f64, f64, f64)> {
    a.profiles
        .iter()
        .filter(|r| r.quantity == q)
        .map(|r| (r.coordinate, r.value, r.error))
        .collect()
}

/// u_y = 2 + 0.3 x on the paper's bins (1.5 d_p at the walls): du_y/dx = 0.3 in every bin
/// (to round-off: the three-point and one-sided rules are exact for a line), T = 0.02 and
/// phi = 0.55 as given, and the bin volumes right (phi is a volume over S V).
#[test]
fn a_linear_profile_gives_its_shear_rate_temperature_and_volume_fraction() {
    let records: Vec<Record> = (0..10)
        .map(|k| {
            record(k, W, 1.0, 5.0, &|x, v| {
                bin(20.0, 0.5, 2.0 + 0.3 * x, 0.02, 0.55, v)
            })
        })
        .collect();
    let a = analyse(&records, &DenseSettings::default());
    let shear = profile(&a, "shear_rate");
    assert_eq!(shear.len(), 9);
    for (x, v, e) in &shear {
        assert!((v - 0.3).abs() < 1e-12, "x/W = {x}: {v}");
        assert!(*e < 1e-12, "identical blocks: error {e}");
    }
    for (_, v, _) in profile(&a, "temperature") {
        assert!((v - 0.02).abs() < 1e-14, "{v}");
    }
    for (_, v, _) in profile(&a, "volume_fraction") {
        assert!((v - 0.55).abs() < 1e-14, "{v}");
    }
    // the vorticity ratio: no spin here
    for (_, v, _) in profile(&a, "spin_over_vorticity") {
        assert_eq!(v, 0.0);
    }
    // coordinates are the bin centres over W
    let x: Vec<f64> = shear.iter().map(|s| s.0).collect();
    assert_eq!(x[0], 0.075);
    assert!((x[1] - 0.2).abs() < 1e-15 && (x[8] - 0.925).abs() < 1e-15);
}

/// A known set of contacts, summed as the engine sums them (a contact of force F on i,
/// r = x_i - x_j, adds F_a r_b / 2 to the bins of both): in one bin, a repulsive
/// wall-normal contact (F = (0, 2, 0), r = (0, 1, 0) in our axes: a compressed chain across
/// the channel) and a frictional one (F = (0.5, 1, 0), r = (0.2, 1, 0)). The paper's axes
/// swap x and y: sigma_xx (wall-normal) = (2 + 1) / V, compressive positive; sigma_xy (paper:
/// wall-normal force, flow-wise branch) = F_y r_x / V = 0.2 / V; sigma_yx = F_x r_y / V =
/// 0.5 / V; sigma_yy = 0.5 * 0.2 / V; mu = |sigma_xy / sigma_xx| = 0.2 / 3.
#[test]
fn the_stress_of_known_contacts_is_compressive_positive_in_the_papers_axes() {
    let contacts: [([f64; 3], [f64; 3]); 2] = [
        ([0.0, 2.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.5, 1.0, 0.0], [0.2, 1.0, 0.0]),
    ];
    let target = 4; // the central bin, [4.5, 5.5], volume 4
    let records: Vec<Record> = (0..10)
        .map(|k| {
            record(k, W, 1.0, 5.0, &|x, v| {
                let mut b = bin(10.0, 0.5, 1.0, 0.0, 0.5, v);
                if (x - 5.0).abs() < 0.1 {
                    for (f, r) in &contacts {
                        for (a, fa) in f.iter().enumerate() {
                            for (c, rc) in r.iter().enumerate() {
                                // both particles in this bin: twice F_a r_b / 2
                                b.contact_stress[3 * a + c] += 2.0 * 0.5 * fa * rc;
                            }
                        }
                    }
                }
                b
            })
        })
        .collect();
    let a = analyse(&records, &DenseSettings::default());
    let at = |q: &str| profile(&a, q)[target].1;
    let v = 4.0;
    assert!((at("stress_xx") - 3.0 / v).abs() < 1e-14);
    assert!((at("stress_xy") - 0.2 / v).abs() < 1e-14);
    assert!((at("stress_yx") - 0.5 / v).abs() < 1e-14);
    assert!((at("stress_yy") - 0.1 / v).abs() < 1e-14);
    assert_eq!(at("stress_zz"), 0.0);
    assert!((at("mu") - 0.2 / 3.0).abs() < 1e-14);
    // no contact elsewhere and no fluctuation: no stress
    assert_eq!(profile(&a, "stress_xx")[3].1, 0.0);
}

/// Block errors of a known series: with window_fraction 1 and 2 blocks of 2 records, u_y
/// = 1, 2, 3, 4 in records 0..3 (every bin) gives block means 1.5 and 3.5: the value 2.5,
/// the standard error std(1.5, 3.5) / sqrt(2) = 1.
#[test]
fn profile_errors_are_standard_errors_of_block_values() {
    let records: Vec<Record> = (0..4)
        .map(|k| {
            let u = 1.0 + k as f64;
            record(k, W, 1.0, u, &|_, v| bin(10.0, 0.5, u, 0.0, 0.5, v))
        })
        .collect();
    let s = DenseSettings {
        blocks: 2,
        window_fraction: 1.0,
        ..Default::default()
    };
    let a = analyse(&records, &s);
    for (_, v, e) in profile(&a, "velocity") {
        assert!(
            (v - 2.5).abs() < 1e-12 && (e - 1.0).abs() < 1e-12,
            "{v} +- {e}"
        );
    }
    assert!((a.dense_summary.com_velocity - 2.5).abs() < 1e-12);
    assert!((a.dense_summary.com_velocity_error - 1.0).abs() < 1e-12);
    assert_eq!(a.series.len(), 4);
    assert!(a.series.iter().all(|r| r.in_window));
}

/// The profile of eq. 3.1 with the constant 3 and delta_0.95 = 6 d_p across W = 40, mirrored
/// about the centre (x from the wall bin's centre): the analysis reads u_slip and u_max
/// (u_max / u_slip exact), delta_0.95 to 2 % (linear interpolation between bins 1 d_p apart
/// where the profile bends) and the constant to 3 % (it scales with the delta it is fitted
/// with).
#[test]
fn the_profile_of_eq_3_1_gives_its_constant_and_thickness() {
    let (us, um, delta) = (2.0, 2.8, 6.0);
    let w = 40.0;
    let u = move |x: f64| {
        let d = x.min(w - x) - 0.75;
        us + (um - us) * (1.0 - (-3.0 * d / delta).exp())
    };
    let records: Vec<Record> = (0..10)
        .map(|k| record(k, w, 1.0, 2.5, &|x, v| bin(10.0, 0.5, u(x), 0.0, 0.5, v)))
        .collect();
    let a = analyse(&records, &DenseSettings::default()).dense_summary;
    let centre = u(20.0);
    assert!((a.slip_velocity - us).abs() < 1e-12);
    assert!((a.max_velocity - centre).abs() < 1e-12);
    assert!((a.velocity_ratio - centre / us).abs() < 1e-12);
    assert!(
        (a.shear_layer_thickness / delta - 1.0).abs() < 0.02,
        "{a:?}"
    );
    assert!((a.profile_constant / 3.0 - 1.0).abs() < 0.03, "{a:?}");
    // on its own: an exact exponential on fine points gives 3 closely
    let x: Vec<f64> = (0..200).map(|k| k as f64 * 0.1).collect();
    let v: Vec<f64> = x.iter().map(|x| 1.0 - (-3.0 * x / 5.0).exp()).collect();
    let (d, c) = shear_layer(&x, &v);
    // (linear interpolation of delta between points 0.1 apart: 0.3 %)
    assert!(
        (d / 5.0 - 1.0).abs() < 3e-3 && (c / 3.0 - 1.0).abs() < 3e-3,
        "{d} {c}"
    );
}

/// Regimes from the momentum balance: walls carrying 80 % of the weight (the flow gains
/// 0.2 g) is `accelerating`; 100 % with u_cm = 1e-5 (below 1e-3 sqrt(g W)) is `jammed`;
/// 100 % at u_cm = 5 with a balance that scatters by 1 % between records is `steady`.
#[test]
fn the_balance_and_the_velocity_give_the_regime() {
    let run = |balance: &dyn Fn(u64) -> f64, u: f64| {
        let records: Vec<Record> = (0..20)
            .map(|k| record(k, W, balance(k), u, &|_, v| bin(10.0, 0.5, u, 0.0, 0.5, v)))
            .collect();
        analyse(&records, &DenseSettings::default()).dense_summary
    };
    let a = run(&|k| 0.8 + 0.01 * (k % 2) as f64, 5.0);
    assert_eq!(a.label, "accelerating", "{a:?}");
    let a = run(&|_| 1.0, 1e-5);
    assert_eq!(a.label, "jammed", "{a:?}");
    let a = run(&|k| 1.0 + 0.01 * (k % 3) as f64 - 0.01, 5.0);
    assert_eq!(a.label, "steady", "{a:?}");
    assert!((a.wall_force_balance - 1.0).abs() < 0.01);
    // the wall friction coefficient: flow-wise over normal force on both walls, beta M g / 6
    let expect = a.wall_force_balance * MASS / 6.0;
    assert!(
        (a.wall_friction_coefficient / expect - 1.0).abs() < 1e-12,
        "{a:?}"
    );
}

/// Bond sums of `copies` copies of a set of bond directions.
fn bonds_of(directions: &[[f64; 3]], copies: usize) -> BondSums {
    let mut s = BondSums::default();
    for _ in 0..copies {
        for &r in directions {
            s.add_bond(r);
        }
    }
    s
}

/// Q6 of the plug: a W = 10 channel whose three central bins are a dense, unsheared plug
/// (phi = 0.64) with the bonds of fcc, the rest loose with the bonds of simple cubic. The
/// plug's Q6 is fcc's 0.5745 (the sc bins outside do not enter), the profile gives each bin
/// its own; without a plug the dense zone is read, and a loose channel has no Q6.
#[test]
fn q6_is_read_in_the_plug_else_in_the_dense_zone() {
    let mut fcc = Vec::new();
    for a in [-1.0, 1.0] {
        for b in [-1.0, 1.0] {
            fcc.extend([[a, b, 0.0], [a, 0.0, b], [0.0, a, b]]);
        }
    }
    let sc = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let run = |phi: &dyn Fn(f64) -> f64, u: &dyn Fn(f64) -> f64| {
        let records: Vec<Record> = (0..10)
            .map(|k| {
                let mut r = record(k, W, 1.0, 5.0, &|x, v| {
                    bin(20.0, 0.5, u(x), 0.01, phi(x), v)
                });
                let edges = r.constants.bin_edges.clone();
                r.bonds = edges
                    .windows(2)
                    .map(|e| {
                        let x = 0.5 * (e[0] + e[1]);
                        let (mut b, q) = if (x - 5.0).abs() < 1.5 {
                            (bonds_of(&fcc, 7), 0.5)
                        } else {
                            (bonds_of(&sc, 5), 0.3)
                        };
                        b.particles = 10.0;
                        b.local_q6 = 10.0 * q;
                        b
                    })
                    .collect();
                r
            })
            .collect();
        analyse(&records, &DenseSettings::default())
    };
    let plug = |x: f64| if (x - 5.0).abs() < 1.5 { 0.64 } else { 0.55 };
    let a = run(&plug, &|_| 3.0);
    let s = &a.dense_summary;
    assert_eq!(s.q6_region, "plug", "{s:?}");
    assert_eq!(s.plug_start, 3.5);
    assert!((s.q6_plug - 0.574_524).abs() < 1e-5, "{s:?}");
    assert!(s.q6_plug_error < 1e-12, "identical blocks: {s:?}");
    // the local q6 sums given per bin: 0.5 per particle in the plug
    assert!((s.local_q6_plug - 0.5).abs() < 1e-12, "{s:?}");
    let q6 = profile(&a, "q6");
    assert_eq!(q6.len(), 9);
    assert!((q6[0].1 - 0.353_553).abs() < 1e-5, "{q6:?}");
    assert!((q6[4].1 - 0.574_524).abs() < 1e-5, "{q6:?}");
    let local = profile(&a, "local_q6");
    assert!((local[0].1 - 0.3).abs() < 1e-12 && (local[4].1 - 0.5).abs() < 1e-12);
    // dense (phi_ad <= phi < 0.63) everywhere and sheared: no plug, the dense zone is read
    // (the whole channel here: 3 fcc bins of 84 bonds, 6 sc bins of 15)
    let a = run(&|_| 0.60, &|x| 3.0 - 0.1 * (x - 5.0).abs());
    let s = &a.dense_summary;
    assert_eq!(s.q6_region, "dense", "{s:?}");
    assert!(s.plug_start.is_nan());
    let mut all = BondSums::default();
    for _ in 0..3 {
        all.add(&bonds_of(&fcc, 7));
    }
    for _ in 0..6 {
        all.add(&bonds_of(&sc, 5));
    }
    assert!((s.q6_plug - all.q6()).abs() < 1e-12, "{s:?}");
    assert!(
        (s.local_q6_plug - (3.0 * 0.5 + 6.0 * 0.3) / 9.0).abs() < 1e-12,
        "{s:?}"
    );
    // loose everywhere: no region, no value
    let a = run(&|_| 0.5, &|_| 3.0);
    let s = &a.dense_summary;
    assert_eq!(s.q6_region, "none");
    assert!(s.q6_plug.is_nan() && s.q6_plug_error.is_nan(), "{s:?}");
    assert!(s.local_q6_plug.is_nan());
}

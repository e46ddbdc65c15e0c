//! Shared helpers of the DEM tests: parameters and hand-built states.

use granflow::engine::dem::params::{damping_for_restitution, default_time_step};
use granflow::engine::dem::{BodyState, DemEngine, DemParams, SizeMix};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// The paper's law at stiffness k_n (e_n = 0.82 for the d_p pair, k_t = 2/7 k_n, xi_t = xi_n/2,
/// mu = 0.5) in a W x B x L channel; no gravity unless set.
pub fn params(kn: f64, width: f64, span: f64, length: f64) -> DemParams {
    DemParams {
        normal_stiffness: kn,
        normal_damping: damping_for_restitution(0.82, kn),
        time_step: default_time_step(kn),
        gravity: [0.0; 3],
        ..DemParams::channel(width, span, length, 0.3, 1)
    }
}

/// A particle at rest at `x` with velocity `v`.
pub fn body(d: f64, x: [f64; 3], v: [f64; 3], w: [f64; 3]) -> BodyState {
    BodyState::fresh(d, x, v, w)
}

/// About `n` particles of the mix on a jittered simple cubic lattice filling the channel,
/// with Gaussian velocities and spins of variance `temperature` (per unit mass).
pub fn jittered(p: &DemParams, spacing: f64, temperature: f64, seed: u64) -> Vec<BodyState> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let comps = p.size_mix.components();
    let d_max = p.max_diameter();
    let n = |len: f64| ((len / spacing).floor() as usize).max(1);
    let (nx, ny, nz) = (n(p.length), n(p.width - d_max * 0.2), n(p.span));
    let (sx, sy, sz) = (
        p.length / nx as f64,
        (p.width - d_max) / ny as f64,
        p.span / nz as f64,
    );
    let jitter = 0.5 * (spacing - d_max).max(0.0);
    let mut out = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                let mut u = || 2.0 * rng.random::<f64>() - 1.0;
                let x = [
                    (i as f64 + 0.5) * sx + jitter * u(),
                    0.5 * d_max + (j as f64 + 0.5) * sy + jitter * u(),
                    (k as f64 + 0.5) * sz + jitter * u(),
                ];
                let r: f64 = rng.random();
                let mut acc = 0.0;
                let d = comps
                    .iter()
                    .find(|c| {
                        acc += c.1;
                        r < acc
                    })
                    .map_or(comps[comps.len() - 1].0, |c| c.0);
                let s = temperature.sqrt();
                let mut g = || {
                    // Box-Muller
                    let (a, b): (f64, f64) = (rng.random(), rng.random());
                    s * (-2.0 * (1.0 - a).ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
                };
                let v = [g(), g(), g()];
                let w = [g(), g(), g()];
                out.push(body(d, x, v, w));
            }
        }
    }
    out
}

/// Bitwise equality of two states, with the first difference named.
pub fn assert_same_states(a: &[BodyState], b: &[BodyState], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: particle counts");
    for (t, (x, y)) in a.iter().zip(b).enumerate() {
        let fields = [
            ("position", x.position, y.position),
            ("velocity", x.velocity, y.velocity),
            ("spin", x.spin, y.spin),
            ("force", x.force, y.force),
            ("torque", x.torque, y.torque),
            ("wall_shear", x.wall_shear, y.wall_shear),
            ("floor_shear", x.floor_shear, y.floor_shear),
        ];
        for (name, u, v) in fields {
            for k in 0..3 {
                assert!(
                    u[k].to_bits() == v[k].to_bits(),
                    "{what}: particle {t} {name}[{k}]: {:e} vs {:e}",
                    u[k],
                    v[k]
                );
            }
        }
        assert_eq!(x.diameter.to_bits(), y.diameter.to_bits());
    }
}

/// Mono size mix.
pub fn mono(mut p: DemParams) -> DemParams {
    p.size_mix = SizeMix::Mono;
    p
}

/// The engine from a state, panicking with the reason.
pub fn engine(p: DemParams, states: &[BodyState]) -> DemEngine {
    DemEngine::from_state(p, states, &[]).unwrap()
}

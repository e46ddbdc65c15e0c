//! Sampling: bin sums across the channel (paper §2: bins of width d_p, 1.5 d_p next to each
//! wall; a particle belongs to the bin of its centre), accumulated every `sample_every` steps
//! at the full step, and the wall balances accumulated at every step. A snapshot hands out
//! the sums since the previous one; the analysis forms the paper's fields from them
//! (eqs. 2.1-2.5) with its own conventions for averages and errors.
//!
//! Conventions fixed here (dem.md A2 leaves them open):
//! - contact stress: a contact of force F on i (from j), r = x_i - x_j (minimum image), adds
//!   F_a r_b / 2 to the (a, b) component (row-major, a = force direction) of the bins of i
//!   and of j: compressive positive, the full non-symmetric tensor, summed over the
//!   contacts, not yet divided by a volume. A wall contact of force F with del from the
//!   wall point to the centre adds F_a del_b to that wall's `wall_stress` instead;
//! - dissipation: -F . v_s for each pair contact, v_s = v_i - v_j - (R_i w_i + R_j w_j) x n
//!   the relative velocity of the contact points at the full step, assigned to the bin of
//!   the midpoint of the centres (the elastic part integrates to ~0 over a contact); for a
//!   wall contact -F . v_s goes to that wall's `wall_dissipation`;
//! - wall forces are the particles' forces *on* the walls (minus the walls' forces on them):
//!   in a steady flow the x components of both walls add up to the weight M g.

use serde::{Deserialize, Serialize};

/// The bins across the channel: edges 0, 1.5, ..., W - 1.5, W; the interior (W - 3) is cut
/// into round(W - 3) equal bins (of width d_p for a whole W).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bins {
    /// W
    pub width: f64,
    /// the bin edges, from 0 to W
    pub edges: Vec<f64>,
    interior_width: f64,
}

/// Width of the bin next to each wall (paper §2).
pub const WALL_BIN: f64 = 1.5;

impl Bins {
    pub fn new(width: f64) -> Bins {
        let interior = ((width - 2.0 * WALL_BIN).round() as usize).max(1);
        let interior_width = (width - 2.0 * WALL_BIN) / interior as f64;
        let mut edges = vec![0.0];
        for k in 0..=interior {
            edges.push(WALL_BIN + k as f64 * interior_width);
        }
        *edges.last_mut().expect("edges") = width - WALL_BIN;
        edges.push(width);
        Bins {
            width,
            edges,
            interior_width,
        }
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.edges.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bin of a centre at y (clamped to the channel).
    #[inline]
    pub fn of(&self, y: f64) -> usize {
        let last = self.len() - 1;
        if y < WALL_BIN {
            0
        } else if y >= self.width - WALL_BIN {
            last
        } else {
            (1 + ((y - WALL_BIN) / self.interior_width) as usize).min(last - 1)
        }
    }
}

/// Indices of the symmetric products in [`BinSums`] (xx, yy, zz, xy, xz, yz).
pub const SYM: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// The sums of one bin over the samples of an interval.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BinSums {
    /// particle-samples: sum of 1
    pub count: f64,
    /// sum of particle volumes pi d^3 / 6
    pub volume: f64,
    /// sum m
    pub mass: f64,
    /// sum m v_a
    pub momentum: [f64; 3],
    /// sum m v_a v_b, in [`SYM`] order
    pub momentum_flux: [f64; 6],
    /// sum I, I = m d^2 / 10
    pub inertia: f64,
    /// sum I w_a
    pub spin_momentum: [f64; 3],
    /// sum I w_a w_b, in [`SYM`] order
    pub spin_flux: [f64; 6],
    /// sum over the samples of P_a P_b / M of the bin's instantaneous totals (P = sum m v,
    /// M = sum m), in [`SYM`] order: with `momentum_flux` it gives the fluctuations about
    /// the instantaneous bin mean (eqs. 2.3-2.4)
    #[serde(default)]
    pub mean_momentum_flux: [f64; 6],
    /// sum over the samples of S_a S_b / J of the bin's instantaneous totals (S = sum I w,
    /// J = sum I), in [`SYM`] order
    #[serde(default)]
    pub mean_spin_flux: [f64; 6],
    /// sum over the contacts of the bin's particles of F_a r_b / 2 (row-major 3 x 3)
    pub contact_stress: [f64; 9],
    /// sum of -F . v_s over the pair contacts whose midpoint is in the bin
    pub dissipation: f64,
    /// pair contacts whose midpoint is in the bin
    pub contacts: f64,
}

/// What an interval (from one snapshot to the next) sums.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct IntervalSums {
    /// first and last step of the interval (steps since the floor was removed)
    pub start_step: u64,
    pub end_step: u64,
    /// (end_step - start_step) dt
    pub duration: f64,
    /// samples (every `sample_every` steps) summed into the bins and per-sample sums
    pub samples: u64,
    /// the bins' sums
    pub bins: Vec<BinSums>,
    /// force evaluations summed in `wall_force`
    pub force_steps: u64,
    /// sum over the force evaluations of the interval's steps of the force on each wall
    /// (0: y = 0, 1: y = W)
    pub wall_force: [[f64; 3]; 2],
    /// impulse on each wall over the interval as velocity Verlet delivers it:
    /// sum over steps of (dt/2) (F_start + F_end)
    pub wall_impulse: [[f64; 3]; 2],
    /// work of gravity over the interval, sum over drifts of m g . dx
    pub gravity_work: f64,
    /// at the samples: sum of the force on each wall
    pub sampled_wall_force: [[f64; 3]; 2],
    /// at the samples: sum over wall contacts of F_a del_b (force on the particle, del from
    /// the wall point to its centre), per wall
    pub wall_stress: [[f64; 9]; 2],
    /// at the samples: sum over wall contacts of -F . v_s, per wall
    pub wall_dissipation: [f64; 2],
    /// at the samples: sum of the centre-of-mass velocity sum m v / M
    pub com_velocity: [f64; 3],
    /// at the samples: sum of the translational and rotational kinetic energies
    /// (sum m v^2 / 2, sum I w^2 / 2)
    pub kinetic_energy: [f64; 2],
    /// at the samples: sum of the touching pairs
    pub contacts: f64,
    /// total momentum sum m v at the start and at the end of the interval
    pub momentum: [[f64; 3]; 2],
}

impl IntervalSums {
    /// An empty interval starting at `step` with the state's total momentum.
    pub fn start(step: u64, bins: usize, momentum: [f64; 3]) -> Self {
        IntervalSums {
            start_step: step,
            end_step: step,
            bins: vec![BinSums::default(); bins],
            momentum: [momentum, momentum],
            ..Default::default()
        }
    }
}

/// Add the kinetic part of one sample of the full-step state to an interval: each
/// particle's count, volume pi d^3 / 6, mass m, inertia I = m d^2 / 10, momentum m v, spin
/// momentum I w and their products to the bin of its centre, the bins' instantaneous
/// (M, P, J, S) products, the centre-of-mass velocity sum m v / M and the kinetic energies
/// (sum m v^2 / 2, sum I w^2 / 2). Particles are given as columns in any fixed order (the
/// sums' rounding follows it). The contact, wall and sample counts are the caller's.
pub fn add_kinetic_sample(
    interval: &mut IntervalSums,
    bins: &Bins,
    mass: &[f64],
    radius: &[f64],
    x: &[[f64; 3]],
    v: &[[f64; 3]],
    w: &[[f64; 3]],
) {
    let iv = interval;
    let mut total_mass = 0.0;
    let mut momentum = [0.0; 3];
    let mut kinetic = [0.0; 2];
    // this sample's bin totals: (M, P, J, S) for the fluctuations about the instantaneous
    // bin means
    let mut now = vec![(0.0, [0.0; 3], 0.0, [0.0; 3]); iv.bins.len()];
    for i in 0..mass.len() {
        let (m, v, w) = (mass[i], v[i], w[i]);
        let d = 2.0 * radius[i];
        let inertia = 0.1 * m * d * d;
        let bin = bins.of(x[i][1]);
        let t = &mut now[bin];
        t.0 += m;
        t.2 += inertia;
        for k in 0..3 {
            t.1[k] += m * v[k];
            t.3[k] += inertia * w[k];
        }
        let s = &mut iv.bins[bin];
        s.count += 1.0;
        s.volume += std::f64::consts::PI / 6.0 * d * d * d;
        s.mass += m;
        s.inertia += inertia;
        for k in 0..3 {
            s.momentum[k] += m * v[k];
            s.spin_momentum[k] += inertia * w[k];
        }
        for (c, &(p, q)) in SYM.iter().enumerate() {
            s.momentum_flux[c] += m * v[p] * v[q];
            s.spin_flux[c] += inertia * w[p] * w[q];
        }
        total_mass += m;
        for k in 0..3 {
            momentum[k] += m * v[k];
        }
        kinetic[0] += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        kinetic[1] += 0.5 * inertia * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    for (s, (m, p, j, l)) in iv.bins.iter_mut().zip(&now) {
        if *m > 0.0 {
            for (c, &(a, q)) in SYM.iter().enumerate() {
                s.mean_momentum_flux[c] += p[a] * p[q] / m;
                s.mean_spin_flux[c] += l[a] * l[q] / j;
            }
        }
    }
    for (u, p) in iv.com_velocity.iter_mut().zip(momentum) {
        *u += p / total_mass;
    }
    iv.kinetic_energy[0] += kinetic[0];
    iv.kinetic_energy[1] += kinetic[1];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_follow_the_paper() {
        let b = Bins::new(10.0);
        assert_eq!(
            b.edges,
            vec![0.0, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 10.0]
        );
        assert_eq!(b.of(0.4), 0);
        assert_eq!(b.of(1.49), 0);
        assert_eq!(b.of(1.5), 1);
        assert_eq!(b.of(2.49), 1);
        assert_eq!(b.of(5.0), 4);
        assert_eq!(b.of(8.49), 7);
        assert_eq!(b.of(8.5), 8);
        assert_eq!(b.of(9.6), 8);
        assert_eq!(b.of(-0.1), 0);
        assert_eq!(b.of(10.1), 8);
        let b = Bins::new(100.0);
        assert_eq!(b.len(), 99);
        assert_eq!(b.edges[49], 49.5);
        let odd = Bins::new(10.4);
        assert_eq!(odd.len(), 9);
        assert!((odd.edges[8] - 8.9).abs() < 1e-12);
    }
}

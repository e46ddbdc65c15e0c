//! Sampling accumulators: the raw velocity moments of each layer cell and species summed over
//! the samples of an interval (the inner sums of thesis eq. 3.14), and the interval's
//! balances (wall tallies, work of the body force, collisional dissipation). From the raw
//! moments the analysis forms every field of eqs. 3.15-3.19 with the time-averaged cell
//! velocity, as the thesis does (3.2.2).

use super::walls::WallTally;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Number of raw moments per cell and species.
pub const MOMENTS: usize = 13;

/// Index of each raw moment in a cell's [`Moments`]: the count, sum v_a, sum v_a v_b,
/// sum v_a |v|^2 (a, b in x, y, z).
pub mod moment {
    pub const COUNT: usize = 0;
    pub const VX: usize = 1;
    pub const VY: usize = 2;
    pub const VZ: usize = 3;
    pub const XX: usize = 4;
    pub const YY: usize = 5;
    pub const ZZ: usize = 6;
    pub const XY: usize = 7;
    pub const XZ: usize = 8;
    pub const YZ: usize = 9;
    pub const QX: usize = 10;
    pub const QY: usize = 11;
    pub const QZ: usize = 12;
}

/// Raw moments of one cell and species, indexed by [`moment`].
pub type Moments = [f64; MOMENTS];

/// Add one simulator's velocity to a cell's moments.
#[inline(always)]
pub fn add_velocity(m: &mut Moments, v: &Vector3<f64>) {
    let speed2 = v.norm_squared();
    m[moment::COUNT] += 1.0;
    m[moment::VX] += v.x;
    m[moment::VY] += v.y;
    m[moment::VZ] += v.z;
    m[moment::XX] += v.x * v.x;
    m[moment::YY] += v.y * v.y;
    m[moment::ZZ] += v.z * v.z;
    m[moment::XY] += v.x * v.y;
    m[moment::XZ] += v.x * v.z;
    m[moment::YZ] += v.y * v.z;
    m[moment::QX] += v.x * speed2;
    m[moment::QY] += v.y * speed2;
    m[moment::QZ] += v.z * speed2;
}

/// The balances of an interval: what the walls received, the work of the body force and
/// what collisions dissipated. Their exact identity: work - heat to walls - dissipated = the
/// change of the kinetic energy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Balances {
    /// per wall (0: y = 0, 1: y = W)
    pub walls: [WallTally; 2],
    /// work of the body force, sum m a dx
    pub work: f64,
    /// kinetic energy lost in inelastic collisions
    pub dissipated: f64,
    /// accepted collisions
    pub collisions: u64,
}

impl Balances {
    /// Add another set of balances.
    pub fn add(&mut self, other: &Balances) {
        for w in 0..2 {
            self.walls[w].add(&other.walls[w]);
        }
        self.work += other.work;
        self.dissipated += other.dissipated;
        self.collisions += other.collisions;
    }
}

/// Everything sampled since the interval started: moments, balances, and the state's
/// kinetic energy and momentum at its ends (filled in when the interval is taken).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct IntervalSums {
    /// step at which the interval started and the step it was taken at
    pub start_step: u64,
    pub end_step: u64,
    /// simulated time covered, (end_step - start_step) dt
    pub duration: f64,
    /// samples summed into `moments`
    pub samples: u64,
    /// layer cells and species: `moments[cell * species + s]`
    pub cells: usize,
    pub species: usize,
    pub moments: Vec<Moments>,
    /// balances over the interval
    pub balances: Balances,
    /// total kinetic energy sum m |v|^2 / 2 and x-momentum sum m v_x at start and end
    pub kinetic_energy: [f64; 2],
    pub momentum_x: [f64; 2],
}

impl IntervalSums {
    /// An empty interval starting at `step` with the state's energy and momentum.
    pub fn start(step: u64, cells: usize, species: usize, energy: f64, momentum_x: f64) -> Self {
        IntervalSums {
            start_step: step,
            end_step: step,
            cells,
            species,
            moments: vec![[0.0; MOMENTS]; cells * species],
            kinetic_energy: [energy, energy],
            momentum_x: [momentum_x, momentum_x],
            ..Default::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_are_the_raw_sums() {
        let mut m = [0.0; MOMENTS];
        add_velocity(&mut m, &Vector3::new(1.0, 2.0, 3.0));
        add_velocity(&mut m, &Vector3::new(-1.0, 0.0, 1.0));
        assert_eq!(m[moment::COUNT], 2.0);
        assert_eq!(m[moment::VZ], 4.0);
        assert_eq!(m[moment::XY], 2.0);
        assert_eq!(m[moment::YZ], 6.0);
        assert_eq!(m[moment::QX], 14.0 - 2.0);
        assert_eq!(m[moment::QZ], 42.0 + 2.0);
    }
}

//! The lattice and the automaton's rules for one site, written in the seed's own notation:
//! the triangular lattice and its neighbours, the velocities v_k and their momenta, and the
//! collision rules (1)-(5) as a function of a site's 7-bit state. The reference uses these
//! directly; the bit-parallel kernel implements the same table with Boolean operations on
//! bit planes and is tested against [`collide`] on all 128 states.
//!
//! **Lattice.** Site (x, y): x = 0..L along the pipe (periodic; gravity points to +x), y =
//! 0..W across it (column y = 0 and y = W - 1 lie next to the walls). Columns are lattice
//! lines parallel to gravity and the walls, spaced sqrt(3)/2 apart; odd columns are shifted by
//! half a spacing along x, so site (x, y) sits at (x + (y mod 2) / 2, y sqrt(3) / 2).
//!
//! **States.** Bit 0 of a site's state is the rest particle, bit k (k = 1..6) the particle
//! with velocity v_k = (cos (k-1) 60deg, sin (k-1) 60deg), numbered counterclockwise with v1
//! along gravity: v1 = +x (down the pipe), v4 = -x, v2 and v3 point towards y = W - 1, v5 and
//! v6 towards y = 0.
//!
//! **Reading of the seed's rules.** The seed numbers the six bonds of a site and writes a rule
//! as (incoming) -> (outgoing). Read with every index as a velocity, rules (2) and (5) would
//! reverse the momentum of their particles (e.g. (i, i+2) has momentum v_{i+1}, the printed
//! outcomes (0, i-2) and (i+3, i-1) have -v_{i+1}), against the seed's "All collisions
//! conserve mass and momentum". Every printed index is consistent, and every rule conserves
//! momentum, if the incoming particles are named by the bond they arrive on (a particle
//! arriving on bond i moves with velocity v_{i+3} = -v_i) and the outgoing ones by the bond
//! they leave on (velocity v_j). That is the reading implemented here. In velocities:
//! - (1) head-on pair {k, k+3} (nothing else at the site) -> {k+1, k+4} (turned
//!   counterclockwise) or {k-1, k+2} (clockwise), 1/2 each;
//! - (2) pair {k, k+2} (nothing else) -> rest particle + v_{k+1} with probability p, else
//!   unchanged;
//! - (3) triple {k, k+2, k+4} (nothing else) -> rest particle + a head-on pair on one of the
//!   three axes, p/3 each, else unchanged (under the all-velocities reading the 1-p branch
//!   would rotate the triple as in FHP; this is the only difference between the readings);
//! - (4) head-on pair + rest particle -> three rest particles (two of them extra);
//! - (5) pair {k, k+2} + rest particle -> two rest particles (one extra) + v_{k+1}.
//!
//! A rule applies only to exactly the listed configuration (as in FHP's tables); every other
//! state is left unchanged by (1)-(5).
//!
//! The reading is also the one that reproduces the seed's results. Measured with it: the
//! Fig. 2 run (L = 220, W = 11, rho = 1, p = g = b = 0.5, 256K samples) gives a peak at
//! f = 590-604 (seed: 596), v = 0.396-0.406 (seed: 0.4) and alpha = 1.28 +- 0.06 over seeds
//! 1-5 (seed: 1.33), and the Fig. 1(a) run shows dense bands travelling at ~0.3 sites per
//! step. The all-velocity reading was tried and not kept: there the spectrum is flat below
//! f ~ 300 (no 1/f^alpha at all) and the space-time picture shows no bands.

use super::params::Thresholds;

/// Bit of the rest particle.
pub const REST: u8 = 1;
/// All seven states occupied.
pub const FULL: u8 = 0x7f;

/// Bit of the velocity v_k, k taken mod 6 in 1..=6 (so v_0 = v_6, v_7 = v_1).
pub const fn vel(k: i32) -> u8 {
    1 << ((k - 1).rem_euclid(6) + 1)
}

/// Momentum of v_k (k = 1..6) in integer units: x (along gravity) in halves of the lattice
/// spacing, y (across) in units of sqrt(3)/2. v1 = (2, 0), v2 = (1, 1), v3 = (-1, 1),
/// v4 = (-2, 0), v5 = (-1, -1), v6 = (1, -1); index 0 (rest) is (0, 0).
pub const MOMENTUM: [[i64; 2]; 7] = [[0, 0], [2, 0], [1, 1], [-1, 1], [-2, 0], [-1, -1], [1, -1]];

/// Number of particles in a site state.
pub fn mass(state: u8) -> u32 {
    (state & FULL).count_ones()
}

/// Momentum of a site state in the units of [`MOMENTUM`].
pub fn momentum(state: u8) -> [i64; 2] {
    let mut p = [0, 0];
    for (k, m) in MOMENTUM.iter().enumerate().skip(1) {
        if state & (1 << k) != 0 {
            p[0] += m[0];
            p[1] += m[1];
        }
    }
    p
}

/// The lattice: L sites along the pipe, W across.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Geometry {
    pub length: usize,
    pub width: usize,
}

impl Geometry {
    /// Number of sites L W.
    pub fn sites(&self) -> usize {
        self.length * self.width
    }

    /// Index of site (x, y) in site order: x runs fastest (along the pipe), then y.
    pub fn index(&self, x: usize, y: usize) -> usize {
        y * self.length + x
    }

    /// Site (x, y) of an index.
    pub fn site(&self, s: usize) -> (usize, usize) {
        (s % self.length, s / self.length)
    }

    /// The neighbour of (x, y) along v_k (k = 1..6), or None beyond a wall.
    pub fn neighbour(&self, x: usize, y: usize, k: i32) -> Option<(usize, usize)> {
        let l = self.length;
        let odd = y % 2;
        let (x2, dy): (usize, i64) = match k {
            1 => ((x + 1) % l, 0),
            4 => ((x + l - 1) % l, 0),
            2 => ((x + odd) % l, 1),
            6 => ((x + odd) % l, -1),
            3 => ((x + l - 1 + odd) % l, 1),
            5 => ((x + l - 1 + odd) % l, -1),
            _ => panic!("velocity index {k} is not in 1..=6"),
        };
        let y2 = y as i64 + dy;
        (0..self.width as i64)
            .contains(&y2)
            .then_some((x2, y2 as usize))
    }
}

/// Which of the rules (1)-(5) acted on a site.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// no rule matched, or (2)/(3) chose "unchanged" (probability 1 - p)
    None,
    /// (1) head-on pair turned
    HeadOn,
    /// (2) with dissipation: pair -> rest + moving
    DissipativePair,
    /// (3) with dissipation: triple -> rest + head-on pair
    ThreeBody,
    /// (4) head-on pair + rest -> three rest particles
    RestHeadOn,
    /// (5) pair + rest -> two rest particles + moving
    RestPair,
}

/// Outcome of the collision rules at one site.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Collision {
    /// the new state (at most one rest particle: bit 0)
    pub state: u8,
    /// extra rest particles that must hop away (0, 1 or 2)
    pub extras: u8,
    pub rule: Rule,
}

/// Bit of the particle arriving on bond i (seed notation): velocity v_{i+3}.
const fn incoming(i: i32) -> u8 {
    vel(i + 3)
}

/// Bit of the particle leaving on bond j: velocity v_j.
const fn outgoing(j: i32) -> u8 {
    vel(j)
}

/// Apply rules (1)-(5) to a site state with its collision uniform `u` (one u serves all rules:
/// at most one rule matches a state). Literal transcription of the seed with the bond reading
/// of the module docs; the thresholds choose the branches (see [`Thresholds`]).
pub fn collide(state: u8, u: u32, t: &Thresholds) -> Collision {
    let u = u64::from(u);
    let done = |state: u8, extras: u8, rule: Rule| Collision {
        state,
        extras,
        rule,
    };
    for i in 1..=6 {
        // (1) (i, i+3) -> (i+1, i-2) or (i-1, i+2), 1/2 each
        if state == incoming(i) | incoming(i + 3) {
            return if u < t.half {
                done(outgoing(i + 1) | outgoing(i - 2), 0, Rule::HeadOn)
            } else {
                done(outgoing(i - 1) | outgoing(i + 2), 0, Rule::HeadOn)
            };
        }
        // (2) (i, i+2) -> (0, i-2) with p, (i+3, i-1) with 1 - p
        if state == incoming(i) | incoming(i + 2) {
            return if u < t.dissipation {
                done(REST | outgoing(i - 2), 0, Rule::DissipativePair)
            } else {
                done(outgoing(i + 3) | outgoing(i - 1), 0, Rule::None)
            };
        }
        // (3) (i, i+2, i-2) -> (0, i, i+3), (0, i-1, i+2), (0, i+1, i-2) with p/3 each,
        // (i+3, i+1, i-1) with 1 - p. The three outcomes are told apart by the axis of their
        // head-on pair: u < t/3 -> the pair on v1/v4, u < 2t/3 -> v2/v5, else v3/v6.
        if state == incoming(i) | incoming(i + 2) | incoming(i - 2) {
            if u < t.dissipation {
                let axis = if u < t.third {
                    1
                } else if u < t.two_thirds {
                    2
                } else {
                    3
                };
                let outcomes = [
                    REST | outgoing(i) | outgoing(i + 3),
                    REST | outgoing(i - 1) | outgoing(i + 2),
                    REST | outgoing(i + 1) | outgoing(i - 2),
                ];
                let chosen = outcomes
                    .into_iter()
                    .find(|o| o & vel(axis) != 0)
                    .expect("the three outcomes cover the three axes");
                return done(chosen, 0, Rule::ThreeBody);
            }
            return done(
                outgoing(i + 3) | outgoing(i + 1) | outgoing(i - 1),
                0,
                Rule::None,
            );
        }
        // (4) (i, 0, i+3) -> (0, 0, 0): one rest particle stays, two are extra
        if state == incoming(i) | REST | incoming(i + 3) {
            return done(REST, 2, Rule::RestHeadOn);
        }
        // (5) (i, 0, i+2) -> (0, 0, i-2): one rest particle stays, one is extra
        if state == incoming(i) | REST | incoming(i + 2) {
            return done(REST | outgoing(i - 2), 1, Rule::RestPair);
        }
    }
    done(state, 0, Rule::None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_are_mutual() {
        let g = Geometry {
            length: 5,
            width: 4,
        };
        for y in 0..4 {
            for x in 0..5 {
                for k in 1..=6 {
                    if let Some((x2, y2)) = g.neighbour(x, y, k) {
                        let back = (k + 2) % 6 + 1;
                        assert_eq!(g.neighbour(x2, y2, back), Some((x, y)));
                    }
                }
            }
        }
    }
}

//! Homogeneous DSMC: N spheres without positions; collision pairs are drawn at random and
//! accepted with probability proportional to their relative speed |g|, and the contact
//! direction k is drawn with weight g . k over the approaching hemisphere: together this
//! samples the Boltzmann collision operator of hard spheres under molecular chaos. Time is counted in collisions per particle, so no density enters.
//!
//! The collision rule is the engine's own ([`pair_collision`], thesis eqs. 2.5-2.11), which
//! tests check from first principles; what this module adds is an independent way of
//! choosing who collides and how (no flights, no cells, no neighbour search). The contact
//! direction comes from the kernel the channel DSMC shares ([`contact_direction`]).

use super::kernel::contact_direction;
use crate::engine::edmd::collision::{ContactLaw, SphereVelocity, pair_collision};
use crate::engine::edmd::setup::gaussian3;
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// A spatially homogeneous gas of rough inelastic spheres (m = d = 1).
pub struct HomogeneousGas {
    /// c, translational velocities (zero mean)
    velocities: Vec<Vector3<f64>>,
    /// w, angular velocities
    spins: Vec<Vector3<f64>>,
    /// e, beta, K
    law: ContactLaw,
    rng: Pcg64,
    /// 2 max |c_i|, an upper bound of every relative speed |c_i - c_j| (the acceptance is
    /// exact, not capped)
    speed_bound: f64,
    /// collisions performed
    collisions: u64,
}

impl HomogeneousGas {
    /// `n` spheres with Maxwellian velocities at T = R = 1 (T = m <c^2>/3, R = I <w^2>/3).
    pub fn new(n: usize, law: ContactLaw, seed: u64) -> Self {
        assert!(n >= 2, "a gas needs at least two spheres");
        let mut rng = Pcg64::seed_from_u64(seed);
        let inertia = law.inertia_factor / 4.0; // I = K m d^2 / 4
        let velocities = (0..n).map(|_| gaussian3(&mut rng, 1.0).into()).collect();
        let spins = (0..n)
            .map(|_| gaussian3(&mut rng, (1.0 / inertia).sqrt()).into())
            .collect();
        let mut gas = HomogeneousGas {
            velocities,
            spins,
            law,
            rng,
            speed_bound: 0.0,
            collisions: 0,
        };
        gas.renormalise();
        gas
    }

    /// Collisions per particle so far, 2 collisions / N.
    pub fn collisions_per_particle(&self) -> f64 {
        2.0 * self.collisions as f64 / self.velocities.len() as f64
    }

    /// Translational and rotational temperatures (T, R) = (m <c^2>/3, I <w^2>/3) in the units
    /// of the last renormalisation (only their ratio and their change are meaningful).
    pub fn temperatures(&self) -> (f64, f64) {
        let n = self.velocities.len() as f64;
        let t = self
            .velocities
            .iter()
            .map(|c| c.norm_squared())
            .sum::<f64>()
            / (3.0 * n);
        let inertia = self.law.inertia_factor / 4.0;
        let r = inertia * self.spins.iter().map(|w| w.norm_squared()).sum::<f64>() / (3.0 * n);
        (t, r)
    }

    /// Collide until the clock reaches `collisions_per_particle`.
    pub fn advance_to(&mut self, collisions_per_particle: f64) {
        let n = self.velocities.len();
        let target = (collisions_per_particle * n as f64 / 2.0).ceil() as u64;
        while self.collisions < target {
            let i = self.rng.random_range(0..n);
            let j = (i + self.rng.random_range(1..n)) % n;
            // a pair collides at a rate proportional to its relative speed |g|
            let g = self.velocities[i] - self.velocities[j];
            let speed = g.norm();
            if self.rng.random::<f64>() * self.speed_bound >= speed {
                continue;
            }
            let k = contact_direction(&mut self.rng, &(g / speed));
            let out = pair_collision(
                &SphereVelocity {
                    linear: self.velocities[i],
                    angular: self.spins[i],
                },
                &SphereVelocity {
                    linear: self.velocities[j],
                    angular: self.spins[j],
                },
                &k,
                &self.law,
            );
            self.velocities[i] = out.first.linear;
            self.spins[i] = out.first.angular;
            self.velocities[j] = out.second.linear;
            self.spins[j] = out.second.angular;
            self.collisions += 1;
            let fastest = self.velocities[i].norm().max(self.velocities[j].norm());
            self.speed_bound = self.speed_bound.max(2.0 * fastest);
        }
    }

    /// Remove the round-off drift of the (conserved, zero) mean velocity and scale c and w
    /// alike so that T = 1: R/T is unchanged, and a cooling gas does not underflow.
    pub fn renormalise(&mut self) {
        let n = self.velocities.len() as f64;
        let mean = self.velocities.iter().sum::<Vector3<f64>>() / n;
        for c in &mut self.velocities {
            *c -= mean;
        }
        let scale = 1.0 / self.temperatures().0.sqrt();
        for c in &mut self.velocities {
            *c *= scale;
        }
        for w in &mut self.spins {
            *w *= scale;
        }
        self.speed_bound = 2.0 * self.velocities.iter().map(|c| c.norm()).fold(0.0, f64::max);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn elastic(beta: f64) -> ContactLaw {
        ContactLaw {
            restitution: 1.0,
            roughness: beta,
            inertia_factor: 0.4,
        }
    }

    /// Elastic perfectly rough spheres (e = beta = 1) conserve T + R; elastic smooth ones
    /// (beta = -1) conserve T and R separately.
    #[test]
    fn elastic_gases_keep_their_energy() {
        let mut rough = HomogeneousGas::new(1000, elastic(1.0), 7);
        let (t0, r0) = rough.temperatures();
        rough.advance_to(10.0);
        let (t, r) = rough.temperatures();
        assert!(
            ((t + r) / (t0 + r0) - 1.0).abs() < 1e-12,
            "{t} + {r} vs {t0} + {r0}"
        );
        assert!(
            (t / t0 - 1.0).abs() > 1e-6,
            "rough collisions exchange T and R"
        );

        let mut smooth = HomogeneousGas::new(1000, elastic(-1.0), 8);
        let (t0, r0) = smooth.temperatures();
        smooth.advance_to(10.0);
        let (t, r) = smooth.temperatures();
        assert!((t / t0 - 1.0).abs() < 1e-12 && (r / r0 - 1.0).abs() < 1e-12);
        assert!(smooth.collisions_per_particle() >= 10.0);
    }

    /// Renormalising sets T = 1 with zero mean velocity and keeps R/T.
    #[test]
    fn renormalising_keeps_the_ratio() {
        let law = ContactLaw {
            restitution: 0.8,
            roughness: 0.0,
            inertia_factor: 0.4,
        };
        let mut gas = HomogeneousGas::new(1000, law, 9);
        gas.advance_to(5.0);
        let (t, r) = gas.temperatures();
        gas.renormalise();
        let (t1, r1) = gas.temperatures();
        assert!((t1 - 1.0).abs() < 1e-12);
        assert!((r1 / t1 - r / t).abs() < 1e-12);
        let mean: Vector3<f64> = gas.velocities.iter().sum::<Vector3<f64>>() / 1000.0;
        assert!(mean.norm() < 1e-14);
    }
}

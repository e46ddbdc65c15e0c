//! Free flight across the channel under the body force, with exact wall hits within a step
//! (thesis eqs. 3.7-3.8 and 3.12-3.13), and the wall models of ch. 3-4: thermal (eqs.
//! 3.9-3.11), Maxwell (diffuse fraction alpha, else specular), rough (eqs. 4.1-4.3) and
//! adiabatic (eqs. 4.5-4.7). A wall hit is processed at its own time inside the step, so
//! a simulator may hit both walls in one step at large Kn; the force keeps acting after it
//! (the a t_post of eqs. 3.9 and 4.1).

use super::kernel::{normal_pair, open_unit};
use super::params::WallModel;
use nalgebra::Vector3;
use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

/// What one wall received from the gas since the start of a tally.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallTally {
    /// wall hits
    pub hits: u64,
    /// momentum delivered to the wall, sum m (v - v')
    pub momentum: [f64; 3],
    /// kinetic energy delivered to the wall (the heat it takes up), sum m (|v|^2 - |v'|^2) / 2
    pub energy: f64,
}

impl WallTally {
    /// Add another tally.
    pub fn add(&mut self, other: &WallTally) {
        self.hits += other.hits;
        for a in 0..3 {
            self.momentum[a] += other.momentum[a];
        }
        self.energy += other.energy;
    }
}

/// The wall rule of a run, with the temperatures it needs.
#[derive(Clone, Copy, Debug)]
pub struct Walls {
    pub model: WallModel,
    /// alpha, diffuse fraction (Maxwell)
    pub accommodation: f64,
    /// beta_w (rough)
    pub roughness: f64,
    /// T_w (thermal, Maxwell)
    pub temperature: f64,
}

impl Walls {
    /// The velocity with which a simulator of mass `mass` leaves wall `wall` (0: y = 0, the gas
    /// above; 1: y = W, the gas below) after arriving with `v`. `adjacent` is the temperature
    /// of the layer cell next to that wall (adiabatic walls).
    #[inline]
    pub fn reemit<R: Rng + ?Sized>(
        &self,
        wall: usize,
        v: Vector3<f64>,
        mass: f64,
        adjacent: f64,
        rng: &mut R,
    ) -> Vector3<f64> {
        let inward = if wall == 0 { 1.0 } else { -1.0 };
        match self.model {
            WallModel::Thermal => self.diffuse(inward, mass, rng),
            WallModel::Maxwell => {
                if rng.random::<f64>() < self.accommodation {
                    self.diffuse(inward, mass, rng)
                } else {
                    Vector3::new(v.x, -v.y, v.z)
                }
            }
            // eqs. 4.1-4.3
            WallModel::Rough => Vector3::new(-self.roughness * v.x, -v.y, -self.roughness * v.z),
            // eqs. 4.5-4.7
            WallModel::Adiabatic => {
                let sigma = (adjacent / mass).sqrt();
                let (gx, gz) = normal_pair(rng);
                Vector3::new(sigma * gx, -v.y, sigma * gz)
            }
            WallModel::Periodic => unreachable!("periodic runs have no walls"),
        }
    }

    /// Diffuse re-emission at T_w (eqs. 3.9-3.11): v_x, v_z = sqrt(k T_w / m) v_G and
    /// |v_y| = sqrt(2 k T_w / m) v_BG, v_BG = sqrt(-ln U) the Rayleigh deviate of the
    /// flux-weighted half-Maxwellian (density proportional to v_y exp(-m v_y^2 / (2 k T_w))).
    #[inline]
    fn diffuse<R: Rng + ?Sized>(&self, inward: f64, mass: f64, rng: &mut R) -> Vector3<f64> {
        let sigma = (self.temperature / mass).sqrt();
        let (gx, gz) = normal_pair(rng);
        let normal = sigma * (-2.0 * libm::log(open_unit(rng))).sqrt();
        Vector3::new(sigma * gx, inward * normal, sigma * gz)
    }
}

/// Fly a simulator at `y` with velocity `v` for `dt` under the acceleration `a` along x
/// between the walls y = 0 and y = 1 (eqs. 3.7-3.8); at each wall hit within the step
/// `hit(wall, v_in)` returns v_out (eqs. 3.12-3.13 with the remaining time as t_post).
/// Returns the displacement along x, so that the work of the body force is m a dx.
#[inline(always)]
pub fn fly(
    y: &mut f64,
    v: &mut Vector3<f64>,
    dt: f64,
    a: f64,
    mut hit: impl FnMut(usize, Vector3<f64>) -> Vector3<f64>,
) -> f64 {
    let end = *y + v.y * dt;
    if end > 0.0 && end < 1.0 {
        let dx = v.x * dt + 0.5 * a * dt * dt;
        *y = end;
        v.x += a * dt;
        return dx;
    }
    let mut left = dt;
    let mut dx = 0.0;
    loop {
        let end = *y + v.y * left;
        if end > 0.0 && end < 1.0 || v.y == 0.0 {
            dx += v.x * left + 0.5 * a * left * left;
            *y = end.clamp(0.0, 1.0);
            v.x += a * left;
            return dx;
        }
        let wall = usize::from(end >= 1.0);
        let t_pre = ((wall as f64 - *y) / v.y).clamp(0.0, left);
        dx += v.x * t_pre + 0.5 * a * t_pre * t_pre;
        v.x += a * t_pre;
        *y = wall as f64;
        left -= t_pre;
        *v = hit(wall, *v);
    }
}

/// Fly without walls: y periodic with period 1, no force.
#[inline(always)]
pub fn fly_periodic(y: &mut f64, v: &Vector3<f64>, dt: f64) {
    let end = (*y + v.y * dt).rem_euclid(1.0);
    *y = if end < 1.0 { end } else { 0.0 };
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_pcg::Pcg64Mcg;

    fn walls(model: WallModel) -> Walls {
        Walls {
            model,
            accommodation: 0.3,
            roughness: 0.4,
            temperature: 1.0,
        }
    }

    /// Diffuse re-emission has the moments of the flux-weighted half-Maxwellian at T_w/m:
    /// <v_x^2> = <v_z^2> = T/m, <v_y> = sqrt(pi T / (2 m)), <v_y^2> = 2 T/m, pointing inwards
    /// (10^5 draws; errors ~ 0.5 %).
    #[test]
    fn thermal_walls_emit_the_flux_weighted_half_maxwellian() {
        let mut rng = Pcg64Mcg::seed_from_u64(2);
        let w = walls(WallModel::Thermal);
        let mass = 2.5;
        let n = 100_000;
        for wall in [0, 1] {
            let (mut xx, mut zz, mut y1, mut yy) = (0.0, 0.0, 0.0, 0.0);
            for _ in 0..n {
                let v = w.reemit(wall, Vector3::new(1.0, 1.0, 1.0), mass, 0.0, &mut rng);
                let inward = if wall == 0 { v.y } else { -v.y };
                assert!(inward > 0.0);
                xx += v.x * v.x / n as f64;
                zz += v.z * v.z / n as f64;
                y1 += inward / n as f64;
                yy += v.y * v.y / n as f64;
            }
            let t = 1.0 / mass;
            assert!((xx / t - 1.0).abs() < 0.015 && (zz / t - 1.0).abs() < 0.015);
            assert!((y1 / (std::f64::consts::PI * t / 2.0).sqrt() - 1.0).abs() < 0.01);
            assert!((yy / (2.0 * t) - 1.0).abs() < 0.015, "{yy}");
        }
    }

    /// Rough walls follow eqs. 4.1-4.3 exactly; beta_w = -1 is specular and conserves energy;
    /// adiabatic walls reverse v_y and draw the tangential components at T_adjacent / m.
    #[test]
    fn athermal_walls_follow_their_rules() {
        let mut rng = Pcg64Mcg::seed_from_u64(4);
        let v = Vector3::new(0.7, -0.4, 0.2);
        let out = walls(WallModel::Rough).reemit(0, v, 1.0, 0.0, &mut rng);
        assert_eq!(out, Vector3::new(-0.4 * 0.7, 0.4, -0.4 * 0.2));
        let smooth = Walls {
            roughness: -1.0,
            ..walls(WallModel::Rough)
        };
        let out = smooth.reemit(0, v, 1.0, 0.0, &mut rng);
        assert_eq!(out.norm_squared(), v.norm_squared());
        let w = walls(WallModel::Adiabatic);
        let (mut xx, n) = (0.0, 100_000);
        for _ in 0..n {
            let out = w.reemit(1, -v, 2.0, 3.0, &mut rng);
            assert_eq!(out.y, -0.4);
            xx += 0.5 * (out.x * out.x + out.z * out.z) / n as f64;
        }
        assert!((xx / 1.5 - 1.0).abs() < 0.015, "{xx}");
    }

    /// A Maxwell wall is diffuse in a fraction alpha of the hits and specular otherwise.
    #[test]
    fn maxwell_walls_mix_diffuse_and_specular() {
        let mut rng = Pcg64Mcg::seed_from_u64(6);
        let w = walls(WallModel::Maxwell);
        let v = Vector3::new(0.25, 0.5, -0.125);
        let n = 100_000;
        let specular = (0..n)
            .filter(|_| w.reemit(1, v, 1.0, 0.0, &mut rng) == Vector3::new(0.25, -0.5, -0.125))
            .count();
        let fraction = specular as f64 / n as f64;
        assert!((fraction - 0.7).abs() < 0.006, "{fraction}");
    }

    /// Flight with hits: a simulator crossing both walls in one step ends where the exact
    /// piecewise motion puts it, and the x displacement and velocity include the force before
    /// and after each hit.
    #[test]
    fn flights_process_every_hit_at_its_time() {
        let (mut y, mut v) = (0.9, Vector3::new(1.0, 1.0, 0.0));
        let (dt, a) = (1.5, 0.2);
        let mut hits = Vec::new();
        let dx = fly(&mut y, &mut v, dt, a, |wall, vin| {
            hits.push((wall, vin.x));
            Vector3::new(vin.x, -vin.y, vin.z)
        });
        // hits the top at t = 0.1, the bottom at t = 1.1, ends at y = 0.4 moving up
        assert_eq!(hits.iter().map(|h| h.0).collect::<Vec<_>>(), vec![1, 0]);
        assert!((hits[0].1 - (1.0 + a * 0.1)).abs() < 1e-14);
        assert!((hits[1].1 - (1.0 + a * 1.1)).abs() < 1e-14);
        assert!((y - 0.4).abs() < 1e-14 && v.y == 1.0);
        assert!((v.x - (1.0 + a * dt)).abs() < 1e-14);
        assert!((dx - (dt + 0.5 * a * dt * dt)).abs() < 1e-14);
        // periodic flights wrap
        let mut y = 0.75;
        fly_periodic(&mut y, &Vector3::new(0.0, -2.0, 0.0), 0.5);
        assert!((y - 0.75).abs() < 1e-15);
    }
}

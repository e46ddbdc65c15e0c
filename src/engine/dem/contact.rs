//! The contact law (paper App. A, eqs. A1-A3, linear model a = 0) written as LAMMPS'
//! `pair_style gran/hooke/history` and `fix wall/gran hooke/history` compute it (version
//! 29 Sep 2021, Debian's `lmp`), in the same order of operations, so that a LAMMPS run from
//! the same state agrees to round-off: the pure rule, shared by the fast kernel and the
//! reference.
//!
//! For a pair i, j with del = x_i - x_j (minimum image), r = |del|, overlap
//! delta = R_i + R_j - r > 0 (a pair with r^2 >= (R_i + R_j)^2 does not touch), n = del / r:
//!
//! - v_r = v_i - v_j; v_n = (v_r . n) n; v_t = v_r - v_n;
//!   surface slip v_tr = v_t - (R_i w_i + R_j w_j) x n, the velocity of i's contact point
//!   relative to j's (LAMMPS: vtr = vt + del x wr with wr = (R_i w_i + R_j w_j) / r);
//! - normal force on i: F_n = (k_n delta - m_eff xi_n (v_r . n)) n, m_eff = m_i m_j / (m_i + m_j);
//!   a net attractive F_n at the end of a contact is not clipped (LAMMPS' default, no
//!   `limit_damping`);
//! - history (the shear displacement s, Silbert et al. 2001): s += v_tr dt, then rotated onto
//!   the tangent plane, s -= (s . n) n (both only in force calls that update it: not in
//!   LAMMPS' `setup`);
//! - F_t = -(k_t s + m_eff xi_t v_tr); Coulomb: if |F_t| > mu |F_n| (|F_n| with the dashpot),
//!   s = (mu |F_n| / |F_t|) (s + m_eff xi_t v_tr / k_t) - m_eff xi_t v_tr / k_t and F_t is
//!   scaled to mu |F_n| (when |s| = 0 before the rotation, F_t = 0); the sliding force is thus
//!   along -(k_t s + m_eff xi_t v_tr), as LAMMPS has it;
//! - force on i: F = F_n + F_t, on j: -F; torques: tau_i = -R_i n x F_t, tau_j = -R_j n x F_t
//!   (LAMMPS: torque -= radius * tor, tor = del x fs / r).
//!
//! A flat wall is a particle of infinite mass and no radius (`fix wall/gran`): del is the
//! vector from the nearest wall point to the centre, r = |del|, contact while r^2 <= R^2,
//! overlap R - r, m_eff = m_i, v_tr = v_t - R_i w_i x n, tau_i = -R_i n x F_t. The history is
//! dropped (zeroed) when a contact ends. Its law may differ by particle size ([`WallLaws`]:
//! LAMMPS then has one `fix wall/gran` per size group).
//!
//! With k_t = 0 the Coulomb rescale of LAMMPS divides by k_t; here the history is then zeroed
//! (it carries no force).
//!
//! Arithmetic differs from LAMMPS' in the last bits only, where that saves a division or a
//! square root: 1/r^2 = (1/r)^2, |s| and |F_t| compared through their squares, and
//! m_eff xi_t / k_t formed once.

use serde::{Deserialize, Serialize};

/// The coefficients of one contact law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactLaw {
    /// k_n, normal stiffness
    pub kn: f64,
    /// k_t, tangential stiffness
    pub kt: f64,
    /// xi_n, normal damping rate (LAMMPS gamma_n)
    pub gamma_n: f64,
    /// xi_t, tangential damping rate (LAMMPS gamma_t)
    pub gamma_t: f64,
    /// mu, Coulomb friction coefficient
    pub mu: f64,
    /// Delta t, the step of the history increment
    pub dt: f64,
}

/// Most particle sizes of a mix (the paper's: 3).
pub const MAX_SIZES: usize = 3;

/// The wall's law for each particle size (`fix wall/gran` applied per size group): the same
/// k_n, k_t and mu for all, a damping per size when the wall matches the pair's restitution
/// ([`super::params::WallDamping`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallLaws {
    radii: [f64; MAX_SIZES],
    laws: [ContactLaw; MAX_SIZES],
    len: usize,
}

impl WallLaws {
    /// The laws of particles of these radii (at most [`MAX_SIZES`]).
    pub fn new(sizes: &[(f64, ContactLaw)]) -> WallLaws {
        assert!(
            !sizes.is_empty() && sizes.len() <= MAX_SIZES,
            "{} sizes: a mix has 1 to {MAX_SIZES}",
            sizes.len()
        );
        let mut w = WallLaws {
            radii: [f64::NAN; MAX_SIZES],
            laws: [sizes[0].1; MAX_SIZES],
            len: sizes.len(),
        };
        for (k, &(r, law)) in sizes.iter().enumerate() {
            w.radii[k] = r;
            w.laws[k] = law;
        }
        w
    }

    /// The same law for every size.
    pub fn uniform(law: ContactLaw) -> WallLaws {
        WallLaws::new(&[(f64::NAN, law)])
    }

    /// The law of a particle of radius R (its size's; the last size's for a radius of none,
    /// which only [`WallLaws::uniform`] meets: particles are always of the mix).
    #[inline(always)]
    pub fn of(&self, radius: f64) -> &ContactLaw {
        let k = self.radii[..self.len]
            .iter()
            .position(|&r| r == radius)
            .unwrap_or(self.len - 1);
        &self.laws[k]
    }

    /// (R, law) of each size.
    pub fn sizes(&self) -> impl Iterator<Item = (f64, &ContactLaw)> {
        self.radii[..self.len].iter().copied().zip(&self.laws)
    }
}

/// What one contact gives: the force on i (j gets -force) and tor = n x F_t (LAMMPS' `tor`):
/// the torque on i is -R_i tor, on j -R_j tor.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForce {
    /// F, the force on i
    pub force: [f64; 3],
    /// n x F_t
    pub tor: [f64; 3],
}

/// A pair contact i-j. `del` = x_i - x_j (minimum image), `rsq` = |del|^2, which must be
/// below (R_i + R_j)^2; `update`: advance the history (every force call of a step; not in a
/// setup call).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn pair(
    law: &ContactLaw,
    del: [f64; 3],
    rsq: f64,
    (radi, radj): (f64, f64),
    (vi, vj): ([f64; 3], [f64; 3]),
    (wi, wj): ([f64; 3], [f64; 3]),
    (mi, mj): (f64, f64),
    shear: &mut [f64; 3],
    update: bool,
) -> ContactForce {
    let r = rsq.sqrt();
    let rinv = 1.0 / r;
    let rsqinv = rinv * rinv;
    // relative translational velocity v_r = v_i - v_j
    let vr = [vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]];
    // wr = (R_i w_i + R_j w_j) / r
    let wr = [
        (radi * wi[0] + radj * wj[0]) * rinv,
        (radi * wi[1] + radj * wj[1]) * rinv,
        (radi * wi[2] + radj * wj[2]) * rinv,
    ];
    let meff = mi * mj / (mi + mj);
    core(
        law,
        del,
        r,
        rinv,
        rsqinv,
        vr,
        wr,
        radi + radj,
        meff,
        shear,
        update,
    )
}

/// A wall contact: `del` from the nearest wall point to the centre, `rsq` = |del|^2 <= R^2,
/// the wall at rest, m_eff = m.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn wall(
    law: &ContactLaw,
    del: [f64; 3],
    rsq: f64,
    radius: f64,
    v: [f64; 3],
    w: [f64; 3],
    mass: f64,
    shear: &mut [f64; 3],
    update: bool,
) -> ContactForce {
    let r = rsq.sqrt();
    let rinv = 1.0 / r;
    let rsqinv = rinv * rinv;
    // v_r = v - v_wall, v_wall = 0
    let vr = [v[0] - 0.0, v[1] - 0.0, v[2] - 0.0];
    let wr = [
        radius * w[0] * rinv,
        radius * w[1] * rinv,
        radius * w[2] * rinv,
    ];
    core(
        law, del, r, rinv, rsqinv, vr, wr, radius, mass, shear, update,
    )
}

/// The shared part of both: normal spring-dashpot, history, Coulomb cap, torque arm.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn core(
    law: &ContactLaw,
    del: [f64; 3],
    r: f64,
    rinv: f64,
    rsqinv: f64,
    vr: [f64; 3],
    wr: [f64; 3],
    radsum: f64,
    meff: f64,
    shear: &mut [f64; 3],
    update: bool,
) -> ContactForce {
    let [delx, dely, delz] = del;
    // normal component v_n = (v_r . del) del / r^2, tangential v_t = v_r - v_n
    let vnnr = vr[0] * delx + vr[1] * dely + vr[2] * delz;
    let vn = [
        delx * vnnr * rsqinv,
        dely * vnnr * rsqinv,
        delz * vnnr * rsqinv,
    ];
    let vt = [vr[0] - vn[0], vr[1] - vn[1], vr[2] - vn[2]];
    // F_n = ccel del: ccel r = k_n delta - m_eff xi_n (v_r . n)
    let damp = meff * law.gamma_n * vnnr * rsqinv;
    let ccel = law.kn * (radsum - r) * rinv - damp;
    // surface slip v_tr = v_t + del x wr = v_t - (R_i w_i + R_j w_j) x n
    let vtr = [
        vt[0] - (delz * wr[1] - dely * wr[2]),
        vt[1] - (delx * wr[2] - delz * wr[0]),
        vt[2] - (dely * wr[0] - delx * wr[1]),
    ];
    // history: s += v_tr dt, then rotated onto the tangent plane
    let s = shear;
    if update {
        s[0] += vtr[0] * law.dt;
        s[1] += vtr[1] * law.dt;
        s[2] += vtr[2] * law.dt;
    }
    // |s| before the rotation (LAMMPS' shrmag), only ever compared with 0
    let shear2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
    let rsht = (s[0] * delx + s[1] * dely + s[2] * delz) * rsqinv;
    if update {
        s[0] -= rsht * delx;
        s[1] -= rsht * dely;
        s[2] -= rsht * delz;
    }
    // F_t = -(k_t s + m_eff xi_t v_tr)
    let mgt = meff * law.gamma_t;
    let mut fs = [
        -(law.kt * s[0] + mgt * vtr[0]),
        -(law.kt * s[1] + mgt * vtr[1]),
        -(law.kt * s[2] + mgt * vtr[2]),
    ];
    // Coulomb: |F_t| <= mu |F_n|, the history rescaled so that the spring gives the cap
    let fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
    let fnmax = law.mu * (ccel * r).abs();
    if fs2 > fnmax * fnmax {
        if shear2 != 0.0 {
            let ratio = fnmax / fs2.sqrt();
            if law.kt != 0.0 {
                let c = mgt / law.kt;
                for k in 0..3 {
                    s[k] = ratio * (s[k] + c * vtr[k]) - c * vtr[k];
                }
            } else {
                *s = [0.0; 3];
            }
            for f in &mut fs {
                *f *= ratio;
            }
        } else {
            fs = [0.0; 3];
        }
    }
    ContactForce {
        force: [
            delx * ccel + fs[0],
            dely * ccel + fs[1],
            delz * ccel + fs[2],
        ],
        tor: [
            rinv * (dely * fs[2] - delz * fs[1]),
            rinv * (delz * fs[0] - delx * fs[2]),
            rinv * (delx * fs[1] - dely * fs[0]),
        ],
    }
}

/// Elastic energy stored in a contact: k_n delta^2 / 2 + k_t |s|^2 / 2.
#[inline]
pub fn elastic_energy(law: &ContactLaw, overlap: f64, shear: &[f64; 3]) -> f64 {
    0.5 * law.kn * overlap * overlap
        + 0.5 * law.kt * (shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> ContactLaw {
        ContactLaw {
            kn: 1e5,
            kt: 2e5 / 7.0,
            gamma_n: 50.0,
            gamma_t: 25.0,
            mu: 0.5,
            dt: 1e-4,
        }
    }

    /// Swapping i and j gives exactly the opposite force, the same `tor` and the opposite
    /// history: what lets each pair be computed once (and the two orientations agree).
    #[test]
    fn a_pair_is_antisymmetric_bitwise() {
        let del = [0.61, -0.52, 0.3];
        let rsq = del.iter().map(|d| d * d).sum::<f64>();
        let (vi, vj) = ([0.3, -1.2, 0.7], [-0.4, 0.1, 0.25]);
        let (wi, wj) = ([3.0, -1.0, 2.0], [0.5, 4.0, -2.5]);
        let mut s1 = [1e-4, 2e-4, -1e-4];
        let mut s2 = [-1e-4, -2e-4, 1e-4];
        let l = law();
        for _ in 0..3 {
            let a = pair(
                &l,
                del,
                rsq,
                (0.45, 0.5),
                (vi, vj),
                (wi, wj),
                (0.38, 0.52),
                &mut s1,
                true,
            );
            let b = pair(
                &l,
                [-del[0], -del[1], -del[2]],
                rsq,
                (0.5, 0.45),
                (vj, vi),
                (wj, wi),
                (0.52, 0.38),
                &mut s2,
                true,
            );
            for k in 0..3 {
                assert_eq!(a.force[k].to_bits(), (-b.force[k]).to_bits());
                assert_eq!(a.tor[k].to_bits(), b.tor[k].to_bits());
                assert_eq!(s1[k].to_bits(), (-s2[k]).to_bits());
            }
        }
    }

    /// Signs: a sphere spinning against a wall below it slides, so the wall pushes it
    /// forward along its rolling direction and the torque brakes the spin.
    #[test]
    fn friction_opposes_the_surface_slip() {
        // wall at y = 0, sphere above: del = (0, y, 0); the contact point (at -R e_y) of a
        // sphere spinning with w = (0, 0, -10) moves with w x (-R e_y) = (-10 R, 0, 0)
        let l = law();
        let radius = 0.5;
        let y = 0.499;
        let mut s = [0.0; 3];
        let c = wall(
            &l,
            [0.0, y, 0.0],
            y * y,
            radius,
            [0.0; 3],
            [0.0, 0.0, -10.0],
            0.5,
            &mut s,
            true,
        );
        // contact point slides along -x, so friction on the sphere is along +x
        assert!(c.force[0] > 0.0, "{c:?}");
        // torque -R tor must oppose w_z < 0: positive z
        assert!(-radius * c.tor[2] > 0.0, "{c:?}");
        // the normal force pushes away from the wall
        assert!(c.force[1] > 0.0);
    }
}

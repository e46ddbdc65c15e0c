//! The pair contact law over a batch of pairs at once, one pair per lane: the same IEEE
//! operations in the same order as [`super::contact::pair`], so the same bits, laid out as
//! arrays (one per quantity) and written without branches (the Coulomb cap is a select), so
//! that the compiler runs eight pairs per AVX-512 instruction where the CPU has AVX-512F,
//! four per AVX2 instruction where it has AVX2 (both detected at run time) and two per SSE2
//! instruction elsewhere. Neither path contracts a multiply and
//! an add into one rounding (no FMA), and square roots and divisions are correctly rounded
//! in every lane: the result does not depend on the path taken.
//!
//! A lane's inputs are formed by the caller with the scalar rule's own first operations:
//! del = x_i - x_j (minimum image), r^2, v_r = v_i - v_j, the spin sum R_i w_i + R_j w_j
//! (LAMMPS' wr before its division by r), R_i, R_j, m_i, m_j and the history s; its outputs
//! are F (on i), tor = n x F_t and the advanced history. Lanes past the batch's length are
//! computed from whatever they hold and never read.

use super::contact::ContactLaw;

/// Pairs per batch.
pub const BATCH: usize = 128;

/// Lanes per vector of the widest path (AVX-512: eight f64); the law runs in whole vectors
/// (BATCH is a whole number of them).
const VECTOR: usize = 8;
const _: () = assert!(BATCH.is_multiple_of(VECTOR), "a batch is whole vectors");

/// One batch of pair contacts, a quantity per array, a pair per index (lane).
#[derive(Clone, Debug)]
pub struct ContactLanes {
    /// del = x_i - x_j (minimum image)
    pub del: [[f64; BATCH]; 3],
    /// r^2 = |del|^2
    pub rsq: [f64; BATCH],
    /// R_i, R_j
    pub radius: [[f64; BATCH]; 2],
    /// m_i, m_j
    pub mass: [[f64; BATCH]; 2],
    /// v_r = v_i - v_j
    pub vr: [[f64; BATCH]; 3],
    /// R_i w_i + R_j w_j
    pub spin: [[f64; BATCH]; 3],
    /// s, the history (advanced in place)
    pub shear: [[f64; BATCH]; 3],
    /// F on i (output)
    pub force: [[f64; BATCH]; 3],
    /// tor = n x F_t (output)
    pub tor: [[f64; BATCH]; 3],
}

impl Default for ContactLanes {
    fn default() -> Self {
        ContactLanes {
            del: [[1.0; BATCH]; 3],
            rsq: [3.0; BATCH],
            radius: [[0.5; BATCH]; 2],
            mass: [[1.0; BATCH]; 2],
            vr: [[0.0; BATCH]; 3],
            spin: [[0.0; BATCH]; 3],
            shear: [[0.0; BATCH]; 3],
            force: [[0.0; BATCH]; 3],
            tor: [[0.0; BATCH]; 3],
        }
    }
}

impl ContactLanes {
    /// The law in lanes 0 .. n (rounded up to a whole vector; n <= [`BATCH`]).
    /// `UPDATE`: advance the histories (see [`super::contact::pair`]).
    pub fn evaluate<const UPDATE: bool>(&mut self, law: &ContactLaw, n: usize) {
        let n = n.next_multiple_of(VECTOR).min(BATCH);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512F (checked just above)
            unsafe { self.evaluate_avx512::<UPDATE>(law, n) };
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above)
            unsafe { self.evaluate_avx2::<UPDATE>(law, n) };
            return;
        }
        self.evaluate_lanes::<UPDATE>(law, n);
    }

    /// The same loop compiled for AVX-512 (eight lanes per instruction).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn evaluate_avx512<const UPDATE: bool>(&mut self, law: &ContactLaw, n: usize) {
        self.evaluate_lanes::<UPDATE>(law, n);
    }

    /// The same loop compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn evaluate_avx2<const UPDATE: bool>(&mut self, law: &ContactLaw, n: usize) {
        self.evaluate_lanes::<UPDATE>(law, n);
    }

    /// The law of [`super::contact`] lane by lane (its doc has the equations), in lanes
    /// 0 .. n, n a multiple of [`VECTOR`].
    #[inline(always)]
    fn evaluate_lanes<const UPDATE: bool>(&mut self, law: &ContactLaw, n: usize) {
        let ContactLaw {
            kn,
            kt,
            gamma_n,
            gamma_t,
            mu,
            dt,
        } = *law;
        // n is a whole number of vectors of eight lanes (the caller rounds it up), said
        // here, and every array cut to the n lanes: the loop then has no bounds checks and no
        // lanes left over, so the compiler's vector loop runs all of it (without this, some
        // builds, e.g. with one codegen unit, left the last eight lanes of every batch to a
        // scalar remainder loop, and their pair kernel was 15-20 % slower:
        // docs/performance.md)
        assert!(
            n.is_multiple_of(VECTOR) && n <= BATCH,
            "whole vectors of lanes"
        );
        let [dx, dy, dz] = self.del.each_ref().map(|a| &a[..n]);
        let rsq = &self.rsq[..n];
        let [ri, rj] = self.radius.each_ref().map(|a| &a[..n]);
        let [mi, mj] = self.mass.each_ref().map(|a| &a[..n]);
        let [vrx, vry, vrz] = self.vr.each_ref().map(|a| &a[..n]);
        let [wsx, wsy, wsz] = self.spin.each_ref().map(|a| &a[..n]);
        let [sx, sy, sz] = self.shear.each_mut().map(|a| &mut a[..n]);
        let [fx, fy, fz] = self.force.each_mut().map(|a| &mut a[..n]);
        let [tx, ty, tz] = self.tor.each_mut().map(|a| &mut a[..n]);
        for l in 0..n {
            let (delx, dely, delz) = (dx[l], dy[l], dz[l]);
            let r = rsq[l].sqrt();
            let rinv = 1.0 / r;
            let rsqinv = rinv * rinv;
            let vr = [vrx[l], vry[l], vrz[l]];
            // wr = (R_i w_i + R_j w_j) / r
            let wr = [wsx[l] * rinv, wsy[l] * rinv, wsz[l] * rinv];
            let meff = mi[l] * mj[l] / (mi[l] + mj[l]);
            let radsum = ri[l] + rj[l];
            // v_n = (v_r . del) del / r^2, v_t = v_r - v_n
            let vnnr = vr[0] * delx + vr[1] * dely + vr[2] * delz;
            let vn = [
                delx * vnnr * rsqinv,
                dely * vnnr * rsqinv,
                delz * vnnr * rsqinv,
            ];
            let vt = [vr[0] - vn[0], vr[1] - vn[1], vr[2] - vn[2]];
            // F_n = ccel del
            let damp = meff * gamma_n * vnnr * rsqinv;
            let ccel = kn * (radsum - r) * rinv - damp;
            // v_tr = v_t + del x wr
            let vtr = [
                vt[0] - (delz * wr[1] - dely * wr[2]),
                vt[1] - (delx * wr[2] - delz * wr[0]),
                vt[2] - (dely * wr[0] - delx * wr[1]),
            ];
            let mut s = [sx[l], sy[l], sz[l]];
            if UPDATE {
                s[0] += vtr[0] * dt;
                s[1] += vtr[1] * dt;
                s[2] += vtr[2] * dt;
            }
            let shear2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
            let rsht = (s[0] * delx + s[1] * dely + s[2] * delz) * rsqinv;
            if UPDATE {
                s[0] -= rsht * delx;
                s[1] -= rsht * dely;
                s[2] -= rsht * delz;
            }
            // F_t = -(k_t s + m_eff xi_t v_tr)
            let mgt = meff * gamma_t;
            let fs = [
                -(kt * s[0] + mgt * vtr[0]),
                -(kt * s[1] + mgt * vtr[1]),
                -(kt * s[2] + mgt * vtr[2]),
            ];
            // Coulomb, as selects: sliding with a history rescales it and F_t by
            // mu |F_n| / |F_t| (the history to zero when k_t = 0); sliding without one
            // zeroes F_t
            let fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
            let fnmax = mu * (ccel * r).abs();
            let sliding = fs2 > fnmax * fnmax;
            let rescale = sliding & (shear2 != 0.0);
            let ratio = fnmax / fs2.sqrt();
            let c = mgt / kt;
            let mut f_t = [0.0; 3];
            for k in 0..3 {
                let rescaled = if kt != 0.0 {
                    ratio * (s[k] + c * vtr[k]) - c * vtr[k]
                } else {
                    0.0
                };
                s[k] = if rescale { rescaled } else { s[k] };
                let capped = if rescale { fs[k] * ratio } else { 0.0 };
                f_t[k] = if sliding { capped } else { fs[k] };
            }
            sx[l] = s[0];
            sy[l] = s[1];
            sz[l] = s[2];
            fx[l] = delx * ccel + f_t[0];
            fy[l] = dely * ccel + f_t[1];
            fz[l] = delz * ccel + f_t[2];
            tx[l] = rinv * (dely * f_t[2] - delz * f_t[1]);
            ty[l] = rinv * (delz * f_t[0] - delx * f_t[2]);
            tz[l] = rinv * (delx * f_t[1] - dely * f_t[0]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::contact;
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    fn law(kt: f64) -> ContactLaw {
        ContactLaw {
            kn: 1e5,
            kt,
            gamma_n: 50.0,
            gamma_t: 25.0,
            mu: 0.5,
            dt: 1e-4,
        }
    }

    /// Every lane gives the scalar rule's bits (force, tor, history), on both paths, with
    /// and without the history update, for sticking and sliding contacts, histories of zero
    /// and k_t = 0.
    #[test]
    fn lanes_are_the_scalar_rule_bit_for_bit() {
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        let (mut sliding, mut sticking) = (0, 0);
        for kt in [2e5 / 7.0, 0.0] {
            let law = law(kt);
            for round in 0..40 {
                let mut lanes = ContactLanes::default();
                let n = 1 + round % BATCH;
                let mut scalar = Vec::new();
                for l in 0..n {
                    let (ra, rb) = (
                        [0.45, 0.5, 0.55][rng.random_range(0..3usize)],
                        [0.45, 0.5, 0.55][rng.random_range(0..3usize)],
                    );
                    let dir: [f64; 3] = std::array::from_fn(|_| rng.random::<f64>() - 0.5);
                    let len = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
                    // overlaps from 1e-5 to 1e-2 of R_i + R_j: sticking and sliding
                    let overlap = 10f64.powf(-2.0 - 3.0 * rng.random::<f64>());
                    let r = (ra + rb) * (1.0 - overlap);
                    let del = dir.map(|d| d / len * r);
                    let rsq = del.iter().map(|d| d * d).sum::<f64>();
                    let scale = if l % 3 == 0 { 20.0 } else { 0.5 };
                    let v: [[f64; 3]; 4] = std::array::from_fn(|_| {
                        std::array::from_fn(|_| scale * (rng.random::<f64>() - 0.5))
                    });
                    let shear: [f64; 3] = if l % 4 == 1 {
                        [0.0; 3]
                    } else {
                        std::array::from_fn(|_| 1e-3 * (rng.random::<f64>() - 0.5))
                    };
                    let (ma, mb) = (contact_mass(ra), contact_mass(rb));
                    for k in 0..3 {
                        lanes.del[k][l] = del[k];
                        lanes.vr[k][l] = v[0][k] - v[1][k];
                        lanes.spin[k][l] = ra * v[2][k] + rb * v[3][k];
                        lanes.shear[k][l] = shear[k];
                    }
                    lanes.rsq[l] = rsq;
                    lanes.radius[0][l] = ra;
                    lanes.radius[1][l] = rb;
                    lanes.mass[0][l] = ma;
                    lanes.mass[1][l] = mb;
                    scalar.push((del, rsq, (ra, rb), v, (ma, mb), shear));
                }
                for update in [true, false] {
                    let mut a = lanes.clone();
                    let mut b = lanes.clone();
                    if update {
                        a.evaluate::<true>(&law, n);
                        b.evaluate_lanes::<true>(&law, n.next_multiple_of(VECTOR));
                    } else {
                        a.evaluate::<false>(&law, n);
                        b.evaluate_lanes::<false>(&law, n.next_multiple_of(VECTOR));
                    }
                    for (l, (del, rsq, rad, v, m, shear)) in scalar.iter().enumerate() {
                        let mut s = *shear;
                        let c = contact::pair(
                            &law,
                            *del,
                            *rsq,
                            *rad,
                            (v[0], v[1]),
                            (v[2], v[3]),
                            *m,
                            &mut s,
                            update,
                        );
                        // sliding: |F_t| = mu |F_n| (to round-off)
                        let n = del.map(|d| d / rsq.sqrt());
                        let f_n = c.force.iter().zip(n).map(|(f, n)| f * n).sum::<f64>();
                        let f_t = (0..3)
                            .map(|k| (c.force[k] - f_n * n[k]).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        if (f_t - law.mu * f_n.abs()).abs() < 1e-9 * f_n.abs() {
                            sliding += 1;
                        } else {
                            sticking += 1;
                        }
                        for lanes in [&a, &b] {
                            for k in 0..3 {
                                assert_eq!(lanes.force[k][l].to_bits(), c.force[k].to_bits());
                                assert_eq!(lanes.tor[k][l].to_bits(), c.tor[k].to_bits());
                                assert_eq!(lanes.shear[k][l].to_bits(), s[k].to_bits());
                            }
                        }
                    }
                }
            }
        }
        assert!(
            sliding > 200 && sticking > 200,
            "{sliding} sliding, {sticking} sticking"
        );
    }

    fn contact_mass(r: f64) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * r * r * r
    }
}

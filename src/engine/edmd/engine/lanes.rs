//! The contact test's first pass for two partners at once, one in each lane of an SSE2
//! register (part of every x86-64 CPU): the partners' records are gathered straight into the
//! lanes, so the arithmetic of [`EdmdEngine::approach`] and [`PairApproach::may_touch_within`]
//! runs once for both without the shuffles that three-component vectors cost. Each lane does
//! the same IEEE operations in the same order as the scalar pass, so both give the same bits
//! (tested against it, NaN and edge cases included); elsewhere the scalar pass is used.

use super::{EdmdEngine, Kinematics};
use crate::engine::edmd::images::Image;
use crate::engine::edmd::motion::PairApproach;

/// The first pass for two partners: each lane's contact equation, the partner's collision
/// counter, and whether it may touch within the horizon.
pub(super) struct TwoApproaches {
    pub pairs: [PairApproach; 2],
    pub collisions: [u32; 2],
    pub may_touch: [bool; 2],
}

impl EdmdEngine {
    /// The first pass for images `images` of partners `partners` of particle `i` (at `now`),
    /// within `horizon` after `now`: as [`EdmdEngine::approach`] followed by
    /// [`PairApproach::may_touch_within`] for each, bit for bit.
    #[inline(always)]
    pub(super) fn approach_two(
        &self,
        i: usize,
        partners: [u32; 2],
        images: [Image; 2],
        horizon: f64,
    ) -> TwoApproaches {
        debug_assert!(partners.iter().all(|&j| (j as usize) < self.kin.len()));
        // SAFETY: partners come from the neighbour lists, which hold only ids of this engine's
        // particles (see `approach`)
        let others = partners.map(|j| unsafe { self.kin.get_unchecked(j as usize) });
        let shifts = images.map(|image| self.image_shifts.of(image));
        let me = &self.kin[i];
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: SSE2 is part of the x86-64 baseline
            unsafe {
                sse2::approach_two(me, others, shifts, self.now, self.params.gravity, horizon)
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (others, shifts);
            let mut out = TwoApproaches {
                pairs: [PairApproach::default(); 2],
                collisions: [0; 2],
                may_touch: [false; 2],
            };
            for lane in 0..2 {
                let (pair, collisions) = self.approach(i, partners[lane], images[lane]);
                out.pairs[lane] = pair;
                out.collisions[lane] = collisions;
                out.may_touch[lane] = pair.may_touch_within(horizon);
            }
            out
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod sse2 {
    use super::{Kinematics, PairApproach, TwoApproaches};
    use std::arch::x86_64::*;

    /// Lane 0 from `a`, lane 1 from `b`.
    #[inline(always)]
    unsafe fn lanes(a: f64, b: f64) -> __m128d {
        unsafe { _mm_set_pd(b, a) }
    }

    #[inline(always)]
    unsafe fn splat(x: f64) -> __m128d {
        unsafe { _mm_set1_pd(x) }
    }

    /// See [`super::EdmdEngine::approach_two`]; `g` is gravity along x.
    #[inline(always)]
    pub(super) unsafe fn approach_two(
        me: &Kinematics,
        others: [&Kinematics; 2],
        shifts: [&[f64; 3]; 2],
        now: f64,
        g: f64,
        horizon: f64,
    ) -> TwoApproaches {
        let [a, b] = others;
        unsafe {
            // fly: r_j = p + c dt (+ g dt^2 / 2 along x), c_j,x = c_x + g dt
            let dt = _mm_sub_pd(splat(now), lanes(a.time, b.time));
            let half_g_dt = _mm_mul_pd(splat(0.5 * g), dt);
            let cx = lanes(a.velocity[0], b.velocity[0]);
            let cy = lanes(a.velocity[1], b.velocity[1]);
            let cz = lanes(a.velocity[2], b.velocity[2]);
            let rjx = _mm_add_pd(
                _mm_add_pd(lanes(a.position[0], b.position[0]), _mm_mul_pd(cx, dt)),
                _mm_mul_pd(half_g_dt, dt),
            );
            let rjy = _mm_add_pd(lanes(a.position[1], b.position[1]), _mm_mul_pd(cy, dt));
            let rjz = _mm_add_pd(lanes(a.position[2], b.position[2]), _mm_mul_pd(cz, dt));
            let cjx = _mm_add_pd(cx, _mm_mul_pd(splat(g), dt));
            // r = r_i - (r_j + shift), v = c_i - c_j
            let [sa, sb] = shifts;
            let rx = _mm_sub_pd(splat(me.position[0]), _mm_add_pd(rjx, lanes(sa[0], sb[0])));
            let ry = _mm_sub_pd(splat(me.position[1]), _mm_add_pd(rjy, lanes(sa[1], sb[1])));
            let rz = _mm_sub_pd(splat(me.position[2]), _mm_add_pd(rjz, lanes(sa[2], sb[2])));
            let vx = _mm_sub_pd(splat(me.velocity[0]), cjx);
            let vy = _mm_sub_pd(splat(me.velocity[1]), cy);
            let vz = _mm_sub_pd(splat(me.velocity[2]), cz);
            // b = r.v, gap = |r|^2 - 1, v2 = |v|^2, summed left to right as the scalar pass
            let dot = |p: [__m128d; 3], q: [__m128d; 3]| {
                _mm_add_pd(
                    _mm_add_pd(_mm_mul_pd(p[0], q[0]), _mm_mul_pd(p[1], q[1])),
                    _mm_mul_pd(p[2], q[2]),
                )
            };
            let r = [rx, ry, rz];
            let v = [vx, vy, vz];
            let bv = dot(r, v);
            let gap = _mm_sub_pd(dot(r, r), splat(1.0));
            let v2 = dot(v, v);
            // may_touch_within: !(b >= 0) & !(b^2 - v2 gap < 0) & !(gap > -2 b horizon)
            let zero = _mm_setzero_pd();
            let disc = _mm_sub_pd(_mm_mul_pd(bv, bv), _mm_mul_pd(v2, gap));
            let approaching = _mm_cmpnge_pd(bv, zero);
            let meets = _mm_cmpnlt_pd(disc, zero);
            let soon = _mm_cmpngt_pd(gap, _mm_mul_pd(_mm_mul_pd(splat(-2.0), bv), splat(horizon)));
            let mask = _mm_movemask_pd(_mm_and_pd(_mm_and_pd(approaching, meets), soon));
            let mut bs = [0.0; 2];
            let mut gaps = [0.0; 2];
            let mut v2s = [0.0; 2];
            _mm_storeu_pd(bs.as_mut_ptr(), bv);
            _mm_storeu_pd(gaps.as_mut_ptr(), gap);
            _mm_storeu_pd(v2s.as_mut_ptr(), v2);
            TwoApproaches {
                pairs: [0, 1].map(|l| PairApproach::from_parts(bs[l], gaps[l], v2s[l])),
                collisions: [a.collisions, b.collisions],
                may_touch: [mask & 1 != 0, mask & 2 != 0],
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::engine::edmd::engine::{EdmdEngine, Kinematics};
    use crate::engine::edmd::images::Image;
    use crate::engine::edmd::{EdmdParams, NeighbourSearch};
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    /// Random states (with gravity, in a box with walls so that images shift along x and z),
    /// with partners at other local times, pairs that overlap, touch, recede, NaN and infinite
    /// coordinates: the two-lane pass gives the scalar pass's coefficients bit for bit and the
    /// same decisions, for horizons from 0 to infinity.
    #[test]
    fn two_lane_first_pass_is_the_scalar_pass_bit_for_bit() {
        let params = EdmdParams::channel(12.0, 10.0, 11.0, 0.2, 1);
        let mut engine =
            EdmdEngine::with_search(params, NeighbourSearch::Lists { skin: 0.5 }).expect("channel");
        let mut rng = Pcg64::seed_from_u64(5);
        let n = engine.kin.len();
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let draw = |rng: &mut Pcg64, scale: f64| -> f64 {
            if rng.random::<f64>() < 0.02 {
                specials[rng.random_range(0..specials.len())]
            } else {
                scale * (2.0 * rng.random::<f64>() - 1.0)
            }
        };
        let mut compared = 0;
        for round in 0..20_000 {
            engine.now = 3.0 + rng.random::<f64>();
            let i = rng.random_range(0..n);
            let partners = [rng.random_range(0..n) as u32, rng.random_range(0..n) as u32];
            for &id in [i as u32].iter().chain(&partners) {
                let k = &mut engine.kin[id as usize];
                // some pairs close together (near contact), some far apart
                let spread = if round % 3 == 0 { 1.2 } else { 6.0 };
                *k = Kinematics {
                    position: std::array::from_fn(|_| 5.0 + draw(&mut rng, spread)),
                    velocity: std::array::from_fn(|_| draw(&mut rng, 3.0)),
                    time: engine.now - rng.random::<f64>().powi(3),
                    collisions: rng.random_range(0..1000),
                    cell: k.cell,
                };
            }
            let images = [0, 1].map(|_| Image::from_index(rng.random_range(0..Image::COUNT)));
            let horizon = [0.0, 1e-3, 0.1, 1.0, f64::INFINITY][round % 5];
            let two = engine.approach_two(i, partners, images, horizon);
            for lane in 0..2 {
                let (pair, collisions) = engine.approach(i, partners[lane], images[lane]);
                let (want, got) = (pair.parts(), two.pairs[lane].parts());
                for (w, g) in want.iter().zip(&got) {
                    assert!(
                        w.to_bits() == g.to_bits(),
                        "round {round} lane {lane}: {want:?} vs {got:?}"
                    );
                }
                assert_eq!(collisions, two.collisions[lane]);
                assert_eq!(
                    pair.may_touch_within(horizon),
                    two.may_touch[lane],
                    "round {round} lane {lane}: {want:?}, horizon {horizon}"
                );
                compared += 1;
            }
        }
        assert_eq!(compared, 40_000);
    }
}

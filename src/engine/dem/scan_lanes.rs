//! The candidate scan of the pair kernel: which pairs of a block of listed pairs touch now
//! (r^2 < (R_a + R_b)^2) or touched at their last evaluation, collected with their
//! separation into the lanes of [`ContactLanes`] in pair order, without a branch on the
//! contact test (most listed pairs do not touch, and which do is unpredictable).
//!
//! Each pair's del = min_image(x_a - x_b) and r^2 = (del_x^2 + del_y^2) + del_z^2 are formed
//! exactly as [`Domain::min_image`] and the scalar law form them, and written to the next
//! free lane, which only a candidate keeps: the count moves on by the contact test, not by a
//! branch. Compiled for AVX2 where the CPU has it. (Eight pairs at a time with AVX-512
//! gathers and compress was measured slower on this machine's Zen 4: docs/performance.md.)

use super::contact_lanes::{BATCH, ContactLanes};
use super::domain::Domain;
use super::simd::with_avx2;

/// Pairs per block of the scan: a block's candidates fill at most one batch of lanes.
pub const SCAN_BLOCK: usize = BATCH;

/// A block's candidates, lane by lane (the lanes' own arrays hold their separations).
#[derive(Clone, Debug)]
pub struct Candidates {
    /// the candidate's place in its block
    pub place: [u32; BATCH],
    /// its particles (working indices)
    pub a: [u32; BATCH],
    pub b: [u32; BATCH],
}

impl Default for Candidates {
    fn default() -> Self {
        Candidates {
            place: [0; BATCH],
            a: [0; BATCH],
            b: [0; BATCH],
        }
    }
}

/// Scan a block of at most [`SCAN_BLOCK`] listed pairs, `touch` their touching flags: the
/// candidates' places and particles into `out`, their del, r^2, R_a and R_b into the lanes'
/// first lanes. Returns the number of candidates.
pub fn scan(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    pairs: &[[u32; 2]],
    touch: &[bool],
    out: &mut Candidates,
    lanes: &mut ContactLanes,
) -> usize {
    assert!(pairs.len() <= SCAN_BLOCK && touch.len() == pairs.len());
    with_avx2(
        #[inline(always)]
        || scan_scalar(domain, x, radius, pairs, touch, out, lanes),
    )
}

/// The scan itself (see the module's doc).
#[inline(always)]
pub fn scan_scalar(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    pairs: &[[u32; 2]],
    touch: &[bool],
    out: &mut Candidates,
    lanes: &mut ContactLanes,
) -> usize {
    let mut n = 0;
    for (place, (&[a, b], &touched)) in pairs.iter().zip(touch).enumerate() {
        let (i, j) = (a as usize, b as usize);
        let del = domain.min_image([x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]]);
        let rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
        let (ra, rb) = (radius[i], radius[j]);
        let radsum = ra + rb;
        for k in 0..3 {
            lanes.del[k][n] = del[k];
        }
        lanes.rsq[n] = rsq;
        lanes.radius[0][n] = ra;
        lanes.radius[1][n] = rb;
        out.place[n] = place as u32;
        out.a[n] = a;
        out.b[n] = b;
        n += ((rsq < radsum * radsum) | touched) as usize;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    /// The candidates are exactly the pairs in contact or flagged touching, in pair order,
    /// each with its own separation (the minimum image across the periodic boundaries, none
    /// along a non-periodic x), for blocks of every length up to SCAN_BLOCK.
    #[test]
    fn the_candidates_are_the_touching_pairs_in_order() {
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let (mut kept, mut across) = (0, 0);
        for (round, periodic_x) in (0..60).zip([true, false].into_iter().cycle()) {
            let domain = Domain::new(6.0, 5.0, 4.0, periodic_x);
            let n = 300;
            let x: Vec<[f64; 3]> = (0..n)
                .map(|_| std::array::from_fn(|k| rng.random::<f64>() * domain.extent[k]))
                .collect();
            let radius: Vec<f64> = (0..n)
                .map(|_| [0.45, 0.5, 0.55][rng.random_range(0..3usize)])
                .collect();
            let len = 1 + round * 7 % SCAN_BLOCK;
            // mostly pairs near each other (many in contact, some across a boundary)
            let pairs: Vec<[u32; 2]> = (0..len)
                .map(|_| {
                    let a = rng.random_range(0..n);
                    let far = rng.random::<f64>() < 0.2;
                    let near = |b: usize| {
                        let d = domain.min_image(std::array::from_fn(|k| x[a][k] - x[b][k]));
                        b != a && (far || d.iter().map(|d| d * d).sum::<f64>() < 1.5)
                    };
                    let b = (0..20 * n)
                        .map(|_| rng.random_range(0..n))
                        .find(|&b| near(b))
                        .unwrap_or((a + 1) % n);
                    [a as u32, b as u32]
                })
                .collect();
            let touch: Vec<bool> = (0..len).map(|_| rng.random::<f64>() < 0.3).collect();
            let (mut found, mut lanes) = (Candidates::default(), ContactLanes::default());
            let count = scan(&domain, &x, &radius, &pairs, &touch, &mut found, &mut lanes);
            let mut l = 0;
            for (place, (&[a, b], &t)) in pairs.iter().zip(&touch).enumerate() {
                let (a, b) = (a as usize, b as usize);
                let raw: [f64; 3] = std::array::from_fn(|k| x[a][k] - x[b][k]);
                let del = domain.min_image(raw);
                across += (del != raw) as usize;
                let rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
                let radsum = radius[a] + radius[b];
                if !(rsq < radsum * radsum || t) {
                    continue;
                }
                assert_eq!(found.place[l] as usize, place, "round {round}");
                assert_eq!((found.a[l] as usize, found.b[l] as usize), (a, b));
                for k in 0..3 {
                    assert_eq!(lanes.del[k][l].to_bits(), del[k].to_bits());
                }
                assert_eq!(lanes.rsq[l].to_bits(), rsq.to_bits());
                assert_eq!(
                    (lanes.radius[0][l], lanes.radius[1][l]),
                    (radius[a], radius[b])
                );
                l += 1;
            }
            assert_eq!(count, l, "round {round}");
            kept += count;
        }
        assert!(
            kept > 500 && across > 20,
            "{kept} candidates, {across} across a boundary"
        );
    }
}

//! The candidate scan of the pair kernel: which pairs of a block of listed pairs touch now
//! (r^2 < (R_a + R_b)^2) or touched at their last evaluation, collected with their
//! separation into the lanes of [`ContactLanes`] in pair order, without a branch on the
//! contact test (most listed pairs do not touch, and which do is unpredictable).
//!
//! Two loops. The test: each pair's del = min_image(x_a - x_b) and r^2 =
//! (del_x^2 + del_y^2) + del_z^2, formed exactly as [`Domain::min_image`] and the scalar law form them; only the
//! candidates' places are kept (a place is written to the next free entry, which only a
//! candidate keeps: the count moves on by the test, not by a branch). Where the CPU has AVX2
//! the test takes four pairs at a time: their positions loaded as rows, subtracted, turned
//! into columns, and the places of the candidates among the four written with a table
//! ([`COMPRESS`]). Then, for the candidates alone (a quarter of the listed pairs), del and r^2
//! are formed again, with the same operations, into the lanes. (Eight pairs at a time with
//! AVX-512 gathers and compress was measured slower on this machine's Zen 4, and so was
//! keeping the vector loop's separations in the lanes instead of forming them again:
//! docs/performance.md.)

use super::contact_lanes::{BATCH, ContactLanes};
use super::domain::Domain;

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

/// A block of listed pairs, as the scan reads them.
#[derive(Clone, Copy, Debug)]
pub struct Listed<'a> {
    /// (owner, other), working indices
    pub pairs: &'a [[u32; 2]],
    /// whether each touched at its last evaluation
    pub touch: &'a [bool],
}

/// Scan a block of at most [`SCAN_BLOCK`] listed pairs: the candidates' places and particles
/// into `out`, their del, r^2, R_a and R_b into the lanes' first lanes. Returns the number
/// of candidates. Four pairs at a time in AVX2 vectors where the CPU has AVX2, else
/// [`scan_scalar`]; the same candidates and bits either way.
pub fn scan(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    listed: Listed,
    out: &mut Candidates,
    lanes: &mut ContactLanes,
) -> usize {
    let n = candidates(domain, x, radius, listed, &mut out.place);
    separations(domain, x, radius, listed.pairs, n, out, lanes);
    n
}

/// The candidates' places in the block, in order; returns their number.
pub fn candidates(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    listed: Listed,
    place: &mut [u32; BATCH],
) -> usize {
    let Listed { pairs, touch } = listed;
    assert!(pairs.len() <= SCAN_BLOCK && touch.len() == pairs.len());
    let (mut done, mut n) = (0, 0);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above)
        (done, n) = unsafe { candidates_avx2(domain, x, radius, listed, place) };
    }
    candidates_scalar(domain, x, radius, listed, done, n, place)
}

/// The scan pair by pair (the reference the vector scan is tested against).
pub fn scan_scalar(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    listed: Listed,
    out: &mut Candidates,
    lanes: &mut ContactLanes,
) -> usize {
    assert!(listed.pairs.len() <= SCAN_BLOCK);
    let n = candidates_scalar(domain, x, radius, listed, 0, 0, &mut out.place);
    separations(domain, x, radius, listed.pairs, n, out, lanes);
    n
}

/// The candidate test of pairs `from ..`, after `n` candidates found: each pair's place is
/// written to the next free entry, which only a candidate keeps (the count moves on by the
/// test, not by a branch). Returns the number of candidates.
fn candidates_scalar(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    listed: Listed,
    from: usize,
    mut n: usize,
    place: &mut [u32; BATCH],
) -> usize {
    let Listed { pairs, touch } = listed;
    for p in from..pairs.len() {
        let (i, j) = (pairs[p][0] as usize, pairs[p][1] as usize);
        let del = domain.min_image([x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]]);
        let rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
        let radsum = radius[i] + radius[j];
        place[n] = p as u32;
        n += ((rsq < radsum * radsum) | touch[p]) as usize;
    }
    n
}

/// The candidates' particles, del, r^2 and radii (del and r^2 formed again, with the same
/// operations as the test).
fn separations(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    pairs: &[[u32; 2]],
    n: usize,
    out: &mut Candidates,
    lanes: &mut ContactLanes,
) {
    for l in 0..n {
        let [a, b] = pairs[out.place[l] as usize];
        let (i, j) = (a as usize, b as usize);
        let del = domain.min_image([x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]]);
        for k in 0..3 {
            lanes.del[k][l] = del[k];
        }
        lanes.rsq[l] = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
        lanes.radius[0][l] = radius[i];
        lanes.radius[1][l] = radius[j];
        out.a[l] = a;
        out.b[l] = b;
    }
}

/// For each subset of four pairs (bit k: the group's pair k is a candidate), the places of
/// its members in order.
const COMPRESS: [[u32; 4]; 16] = {
    let mut t = [[0u32; 4]; 16];
    let mut m = 0;
    while m < 16 {
        let (mut k, mut n) = (0, 0);
        while k < 4 {
            if m & (1 << k) != 0 {
                t[m][n] = k as u32;
                n += 1;
            }
            k += 1;
        }
        m += 1;
    }
    t
};

/// The candidate test four pairs at a time: returns (pairs done, candidates found).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn candidates_avx2(
    domain: &Domain,
    x: &[[f64; 3]],
    radius: &[f64],
    listed: Listed,
    place: &mut [u32; BATCH],
) -> (usize, usize) {
    use std::arch::x86_64::*;
    let Listed { pairs, touch } = listed;
    let groups = pairs.len() / 4;
    let half = domain.half_periods();
    let ext = domain.extent;
    let (hx, hz) = (_mm256_set1_pd(half[0]), _mm256_set1_pd(half[2]));
    let (nhx, nhz) = (_mm256_set1_pd(-half[0]), _mm256_set1_pd(-half[2]));
    let (lx, lz) = (_mm256_set1_pd(ext[0]), _mm256_set1_pd(ext[2]));
    let three = _mm256_set_epi64x(0, -1, -1, -1);
    let mut n = 0usize;
    for g in 0..groups {
        let p = 4 * g;
        let pos = |i: u32| {
            let i = i as usize;
            assert!(i < x.len());
            // SAFETY: in bounds; the masked lane is not read
            unsafe { _mm256_maskload_pd(x.as_ptr().add(i) as *const f64, three) }
        };
        let d: [__m256d; 4] =
            std::array::from_fn(|k| _mm256_sub_pd(pos(pairs[p + k][0]), pos(pairs[p + k][1])));
        let t0 = _mm256_unpacklo_pd(d[0], d[1]);
        let t1 = _mm256_unpackhi_pd(d[0], d[1]);
        let t2 = _mm256_unpacklo_pd(d[2], d[3]);
        let t3 = _mm256_unpackhi_pd(d[2], d[3]);
        let mut dx = _mm256_permute2f128_pd::<0x20>(t0, t2);
        let dy = _mm256_permute2f128_pd::<0x20>(t1, t3);
        let mut dz = _mm256_permute2f128_pd::<0x31>(t0, t2);
        // the minimum image, as Domain::min_image
        let image = |d: __m256d, h, nh, l| {
            let up = _mm256_blendv_pd(d, _mm256_add_pd(d, l), _mm256_cmp_pd::<_CMP_LT_OQ>(d, nh));
            _mm256_blendv_pd(up, _mm256_sub_pd(d, l), _mm256_cmp_pd::<_CMP_GT_OQ>(d, h))
        };
        dx = image(dx, hx, nhx, lx);
        dz = image(dz, hz, nhz, lz);
        let rsq = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
            _mm256_mul_pd(dz, dz),
        );
        let r = |k: usize| radius[pairs[p + k][0] as usize] + radius[pairs[p + k][1] as usize];
        let radsum = _mm256_set_pd(r(3), r(2), r(1), r(0));
        let near = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(
            rsq,
            _mm256_mul_pd(radsum, radsum),
        ));
        let t = &touch[p..p + 4];
        let m = near as usize
            | (t[0] as usize)
            | (t[1] as usize) << 1
            | (t[2] as usize) << 2
            | (t[3] as usize) << 3;
        assert!(n + 4 <= BATCH);
        // SAFETY: the tables' rows are 16 and 32 bytes; n + 4 <= BATCH (just checked)
        unsafe {
            let at = _mm_add_epi32(
                _mm_loadu_si128(COMPRESS[m].as_ptr() as *const __m128i),
                _mm_set1_epi32(p as i32),
            );
            _mm_storeu_si128(place.as_mut_ptr().add(n) as *mut __m128i, at);
        }
        n += m.count_ones() as usize;
    }
    (4 * groups, n)
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
            let listed = Listed {
                pairs: &pairs,
                touch: &touch,
            };
            let count = scan(&domain, &x, &radius, listed, &mut found, &mut lanes);
            // the vector scan (where this CPU has it) and the pair-by-pair one agree
            let (mut plain, mut plain_lanes) = (Candidates::default(), ContactLanes::default());
            let plain_count =
                scan_scalar(&domain, &x, &radius, listed, &mut plain, &mut plain_lanes);
            assert_eq!(count, plain_count, "round {round}");
            assert_eq!(found.place[..count], plain.place[..count]);
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

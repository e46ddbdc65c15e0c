//! The counter-based random stream of the lattice gas: every random decision is a pure
//! function of (seed, step, purpose, site), so runs are bitwise reproducible, a checkpoint
//! needs no generator state, and the bit-parallel kernel and the one-site reference draw the
//! same decisions in whatever order they need them.
//!
//! **Generator.** SplitMix64 (Steele, Lea & Flood, OOPSLA 2014; the finaliser is Stafford's
//! "variant 13"): word i of a stream with key k is `mix64(k + (i + 1) * GAMMA)`, exactly the
//! i-th output of a SplitMix64 generator started at state k, so each stream is a SplitMix64
//! sequence (which passes BigCrush) that can be read at any position in O(1). The key of a
//! (step, purpose) stream is `mix64(mix64(seed ^ SEED_SALT) ^ mix64(step * PURPOSES + purpose))`
//! (bijective in (step, purpose) for a fixed seed). Chosen over a crate because the kernel
//! needs random access (one word per 64 sites, skipped where no site needs a decision) at a
//! cost of a few cycles; ChaCha-style block ciphers would cost a block per access. Two streams
//! of one run share words only if their keys fall within a stream's length of each other on
//! the SplitMix64 orbit: about (streams)^2 x (words per stream) / 2^64, below 0.03 for the
//! seed's longest run (2.6 M steps of 220 x 11 sites).
//!
//! **Uniforms of a site.** A decision "with probability q" at site (x, y) is `u < t(q)`, where
//! t(q) = round(q 2^32) ([`threshold`]) and u is a 32-bit uniform integer whose binary digit j
//! (j = 0 the most significant) is bit (x mod 64) of word `(y * nw + x / 64) * 32 + j` of the
//! (step, purpose) stream, nw = ceil(L / 64) being the words per column. The kernel compares
//! 64 sites at once digit by digit from the most significant one and stops as soon as every
//! site that needs the decision is decided ([`less_than`]), so it draws only a few words per
//! 64 sites; the reference assembles u whole ([`site_uniform`]). Probabilities are therefore
//! realised as multiples of 2^-32 ([`effective_probability`]).

/// Number of binary digits of a site uniform u.
pub const DIGITS: u32 = 32;
/// 2^32: the threshold of probability 1 (every u is below it).
pub const ONE: u64 = 1 << DIGITS;

const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;
const SEED_SALT: u64 = 0x6c61_7474_6963_6567; // "latticeg"

/// What a random word decides; part of the stream key, so purposes never share words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// initial occupation of moving state v_k (k = 1..6), at step 0
    Init(u8),
    /// collision rules (1)-(3): head-on chirality, dissipation and the triple's axis
    Collide,
    /// rule (6): a rest particle starts moving along gravity
    GravityRest,
    /// rule (6): a particle v3 next to a rest particle is kicked to v2
    GravityKick3,
    /// rule (6): a particle v5 next to a rest particle is kicked to v6
    GravityKick5,
    /// rule (7) at the wall next to column y = 0 (bounce back or specular)
    WallLow,
    /// rule (7) at the wall next to column y = W - 1
    WallHigh,
    /// the random walk of the extra rest particles of rules (4)-(5)
    Hop,
}

impl Purpose {
    /// Number of distinct purposes.
    pub const COUNT: u64 = 13;

    fn index(self) -> u64 {
        match self {
            Purpose::Init(k) => {
                assert!(
                    (1..=6).contains(&k),
                    "initial-state purpose of a moving state"
                );
                u64::from(k) - 1
            }
            Purpose::Collide => 6,
            Purpose::GravityRest => 7,
            Purpose::GravityKick3 => 8,
            Purpose::GravityKick5 => 9,
            Purpose::WallLow => 10,
            Purpose::WallHigh => 11,
            Purpose::Hop => 12,
        }
    }
}

/// The SplitMix64 output function (Stafford's variant 13 of the MurmurHash3 finaliser).
#[inline(always)]
pub fn mix64(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The random words of one (seed, step, purpose).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stream {
    key: u64,
}

impl Stream {
    /// The stream of `purpose` at time step `step` of the run with `seed`.
    pub fn new(seed: u64, step: u64, purpose: Purpose) -> Self {
        let local = step
            .wrapping_mul(Purpose::COUNT)
            .wrapping_add(purpose.index());
        Stream {
            key: mix64(mix64(seed ^ SEED_SALT) ^ mix64(local)),
        }
    }

    /// Word `index` of the stream.
    #[inline(always)]
    pub fn word(&self, index: u64) -> u64 {
        mix64(
            self.key
                .wrapping_add(index.wrapping_add(1).wrapping_mul(GAMMA)),
        )
    }
}

/// t(q) = round(q 2^32), clamped to [0, 2^32]: a decision with probability q is `u < t(q)`.
pub fn threshold(q: f64) -> u64 {
    if q.is_nan() || q <= 0.0 {
        0
    } else if q >= 1.0 {
        ONE
    } else {
        ((q * ONE as f64).round() as u64).min(ONE)
    }
}

/// The probability a threshold realises, t / 2^32.
pub fn effective_probability(q: f64) -> f64 {
    threshold(q) as f64 / ONE as f64
}

/// Index of the first digit word of the 64 sites of word `w` in column `y` (nw words per
/// column): the digits of those sites are words `base .. base + 32` of a stream.
#[inline(always)]
pub fn digit_base(y: usize, w: usize, nw: usize) -> u64 {
    ((y * nw + w) as u64) * u64::from(DIGITS)
}

/// The 32-bit uniform u of site (x, y) in `stream` (nw words per column): digit j is bit
/// x mod 64 of word `digit_base(y, x / 64, nw) + j`. The one-site form used by the reference.
pub fn site_uniform(stream: &Stream, nw: usize, x: usize, y: usize) -> u32 {
    let base = digit_base(y, x / 64, nw);
    let bit = x % 64;
    let mut u = 0u32;
    for j in 0..u64::from(DIGITS) {
        u = (u << 1) | ((stream.word(base + j) >> bit) & 1) as u32;
    }
    u
}

/// The digit words of the 64 sites of one word for one stream, drawn lazily (most significant
/// first) and kept, so that several thresholds compared against the same uniforms share them.
pub struct Digits<'a> {
    stream: &'a Stream,
    base: u64,
    words: [u64; DIGITS as usize],
    have: usize,
}

impl<'a> Digits<'a> {
    /// The digits of the sites of word `w` of column `y` (nw words per column).
    #[inline(always)]
    pub fn new(stream: &'a Stream, y: usize, w: usize, nw: usize) -> Self {
        Digits {
            stream,
            base: digit_base(y, w, nw),
            words: [0; DIGITS as usize],
            have: 0,
        }
    }

    /// Digit word j (bit i: digit j of the uniform of the word's site i).
    #[inline(always)]
    pub fn get(&mut self, j: usize) -> u64 {
        while self.have <= j {
            self.words[self.have] = self.stream.word(self.base + self.have as u64);
            self.have += 1;
        }
        self.words[j]
    }
}

/// Bit-sliced `u < t` for the sites in `need` (bits outside `need` are 0 in the result).
///
/// Digits are compared from the most significant one: a site is decided at the first digit
/// where its u differs from t (below if u has 0 where t has 1); sites still equal after t's
/// last 1-digit have u >= t. The loop stops when no needed site is undecided, so on average
/// it draws about log2(popcount(need)) + 2 digit words, not 32.
#[inline(always)]
pub fn less_than(digits: &mut Digits, t: u64, need: u64) -> u64 {
    if need == 0 || t == 0 {
        return 0;
    }
    if t >= ONE {
        return need;
    }
    let last = (DIGITS - 1 - t.trailing_zeros()) as usize;
    let mut below = 0u64;
    let mut open = need; // sites whose digits so far equal t's
    for j in 0..=last {
        let d = digits.get(j);
        if (t >> (DIGITS as usize - 1 - j)) & 1 == 1 {
            below |= open & !d; // digit 0 where t has 1: u < t
            open &= d;
        } else {
            open &= !d; // digit 1 where t has 0: u > t
        }
        if open == 0 {
            break;
        }
    }
    below
}

/// Longest random walk of an extra rest particle (rules (4)-(5)) before the fallback: the
/// particle then goes to the first site without a rest particle after the walk's last site in
/// site order. The walk is bounded so that a step can never loop forever; it needs this many
/// hops only when rest particles fill nearly all sites around it.
pub const MAX_HOPS: u64 = 1024;

/// Index in the (step, [`Purpose::Hop`]) stream of the word that chooses hop `hop` of extra
/// rest particle `extra` (0 or 1) created at site `site` (site order).
pub fn hop_word_index(site: usize, extra: u8, hop: u64) -> u64 {
    (site as u64 * 2 + u64::from(extra)) * MAX_HOPS + hop
}

/// Uniform choice among `n` options from a random word (multiply-shift, Lemire 2019).
#[inline(always)]
pub fn choose(word: u64, n: usize) -> usize {
    ((u128::from(word) * n as u128) >> 64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_sliced_comparison_equals_the_integer_one() {
        let nw = 3;
        for (i, q) in [0.0, 0.1, 0.5, 1.0 / 3.0, 0.75, 0.999, 1.0]
            .iter()
            .enumerate()
        {
            let t = threshold(*q);
            let stream = Stream::new(7, i as u64, Purpose::Collide);
            for y in 0..2 {
                for w in 0..nw {
                    for need in [u64::MAX, 0x0f0f_0000_ffff_0001, 1 << 63] {
                        let mut d = Digits::new(&stream, y, w, nw);
                        let m = less_than(&mut d, t, need);
                        for b in 0..64 {
                            let u = site_uniform(&stream, nw, w * 64 + b, y);
                            let want = (need >> b) & 1 == 1 && u64::from(u) < t;
                            assert_eq!((m >> b) & 1 == 1, want, "q {q} site {b}");
                        }
                    }
                }
            }
        }
    }
}

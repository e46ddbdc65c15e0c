//! The bit-parallel kernel ("multi-spin coding", as in the lattice-gas codes since
//! Frisch, Hasslacher & Pomeau): each column of the pipe (a lattice line parallel to gravity)
//! is a bit string of its L sites, one bit plane per state (rest, v1..v6), 64 sites per
//! machine word. Collisions and gravity are Boolean formulas evaluated on 64 sites at once;
//! propagation along the column is a shift by one bit with periodic wrap-around at L;
//! propagation to a neighbouring column is a copy or a shift, depending on the column's
//! parity (odd columns are offset by half a spacing). Random decisions are bit masks built
//! from the counter-based stream ([`rng::less_than`]), so the kernel draws exactly the
//! decisions of the one-site reference. The hops of the extra rest particles of rules (4)-(5)
//! are sequential by definition and run as scalar code on the bit planes.

use super::params::{LgaParams, Thresholds};
use super::rng::{self, Digits, Purpose, Stream, less_than};
use super::rules::{Geometry, MOMENTUM};
use super::state::{Counters, PAYLOAD_VERSION, Payload};

/// Planes of a site word: 0 rest, k = 1..6 velocity v_k, 7 unused (pads the 7 planes of 64
/// sites to one 64-byte cache line).
pub const PLANES: usize = 8;
/// The states of 64 consecutive sites of a column: `word[k]` bit i is state k of site i.
pub type SiteWord = [u64; PLANES];

/// Sum and carry of three bit planes (a full adder on each bit position).
#[inline(always)]
fn full_add(a: u64, b: u64, c: u64) -> (u64, u64) {
    let ab = a ^ b;
    (ab ^ c, (a & b) | (c & ab))
}

/// A site word after the collision rules (1)-(5), with the masks of what happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Collided {
    /// the new states (rest plane: at most one rest particle per site)
    pub state: SiteWord,
    /// sites of rule (5): one extra rest particle to place
    pub one_extra: u64,
    /// sites of rule (4): two extra rest particles to place
    pub two_extras: u64,
    /// sites of rule (1)
    pub head_on: u64,
    /// sites of rule (2), dissipative branch
    pub dissipative_pairs: u64,
    /// sites of rule (3), dissipative branch
    pub three_body: u64,
}

/// Rules (1)-(5) on 64 sites: the Boolean form of [`rules::collide`] (tested against it on
/// all 128 states). `digits` are the collision uniforms of these sites.
#[inline(always)]
pub fn collide_word(s: &SiteWord, digits: &mut Digits, th: &Thresholds) -> Collided {
    let r = s[0];
    // n[k] is the plane of v_{k+1}; index arithmetic below is mod 6
    let n = [s[1], s[2], s[3], s[4], s[5], s[6]];
    // number of moving particles per site as a 3-bit binary number (ones, twos, fours):
    // two full adders over v1..v3 and v4..v6, then the sum of the two 2-bit results
    let (sum_a, carry_a) = full_add(n[0], n[1], n[2]);
    let (sum_b, carry_b) = full_add(n[3], n[4], n[5]);
    let ones = sum_a ^ sum_b;
    let (twos, fours) = full_add(carry_a, carry_b, sum_a & sum_b);
    let exactly_two = !ones & twos & !fours;
    let exactly_three = ones & twos & !fours;

    // the configurations of the rules (the rest plane decides between (1)/(4), (2)/(5))
    let head_on: [u64; 3] = std::array::from_fn(|a| exactly_two & n[a] & n[a + 3]);
    let pair: [u64; 6] = std::array::from_fn(|k| exactly_two & n[k] & n[(k + 2) % 6]);
    let triple = [
        exactly_three & n[0] & n[2] & n[4], // v1, v3, v5
        exactly_three & n[1] & n[3] & n[5], // v2, v4, v6
    ];
    let any_head_on = head_on[0] | head_on[1] | head_on[2];
    let any_pair = pair.iter().fold(0, |acc, &m| acc | m);
    let any_triple = triple[0] | triple[1];

    // random decisions, drawn only for the sites whose rule has a random branch; one uniform
    // per site serves them all (a site matches one rule at most)
    let turning = any_head_on & !r;
    let ccw = less_than(digits, th.half, turning);
    let dissipate = less_than(digits, th.dissipation, (any_pair | any_triple) & !r);
    let triple_d = any_triple & dissipate;
    let below_third = less_than(digits, th.third, triple_d);
    let below_two_thirds = less_than(digits, th.two_thirds, triple_d);
    // the axis of the triple's new head-on pair: v1/v4, v2/v5, v3/v6
    let axis = [
        below_third,
        below_two_thirds & !below_third,
        triple_d & !below_two_thirds,
    ];

    // which bits change, as XOR masks (the configurations are disjoint)
    let mut flip = [0u64; 6];
    for a in 0..3 {
        // (1) and (4) take the pair {a, a+3} away
        flip[a] ^= head_on[a];
        flip[a + 3] ^= head_on[a];
        // (1) puts it back turned: {a+1, a+4} (ccw) or {a-1, a+2} (cw)
        let cc = head_on[a] & ccw;
        let cw = head_on[a] & !r & !ccw;
        flip[a + 1] ^= cc;
        flip[(a + 4) % 6] ^= cc;
        flip[(a + 5) % 6] ^= cw;
        flip[a + 2] ^= cw;
    }
    for (k, &p) in pair.iter().enumerate() {
        // (5) always, (2) with probability p: {k, k+2} -> v_{k+1} (plus rest particles)
        let act = p & (r | dissipate);
        flip[k] ^= act;
        flip[(k + 2) % 6] ^= act;
        flip[(k + 1) % 6] ^= act;
    }
    for (k, f) in flip.iter_mut().enumerate() {
        // (3): a member of the triple leaves unless it lies on the chosen axis; a velocity
        // of the other parity arrives if it lies on the chosen axis
        let own = triple[k % 2] & triple_d;
        let other = triple[1 - k % 2] & triple_d;
        *f ^= (own & !axis[k % 3]) | (other & axis[k % 3]);
    }
    let mut state = *s;
    state[0] = r | (any_pair & dissipate) | triple_d;
    for k in 0..6 {
        state[k + 1] = n[k] ^ flip[k];
    }
    Collided {
        state,
        one_extra: any_pair & r,
        two_extras: any_head_on & r,
        head_on: turning,
        dissipative_pairs: any_pair & dissipate,
        three_body: triple_d,
    }
}

/// The fast lattice gas.
#[derive(Clone, Debug)]
pub struct LgaEngine {
    params: LgaParams,
    thresholds: Thresholds,
    geometry: Geometry,
    /// words per column, ceil(L / 64)
    nw: usize,
    /// valid bits of a column's last word (the padding bits are always 0)
    last_mask: u64,
    /// the state, word `y * nw + w` holding sites x = 64 w .. 64 w + 63 of column y
    cur: Vec<SiteWord>,
    /// the state after collisions (and hops, gravity) within a step
    tmp: Vec<SiteWord>,
    /// (word, rule-(5) sites, rule-(4) sites) of the current step, in site order
    extras: Vec<(usize, u64, u64)>,
    step: u64,
    counters: Counters,
    wall_impulse: [i64; 2],
}

impl LgaEngine {
    /// The initial state: each moving state of each site occupied with probability rho / 6.
    pub fn new(params: LgaParams) -> Result<Self, String> {
        params.validate()?;
        let mut e = Self::empty(params);
        for k in 1..=6u8 {
            let stream = Stream::new(e.params.seed, 0, Purpose::Init(k));
            for c in 0..e.cur.len() {
                let (y, w) = (c / e.nw, c % e.nw);
                let mut digits = Digits::new(&stream, y, w, e.nw);
                e.cur[c][usize::from(k)] =
                    less_than(&mut digits, e.thresholds.occupation, e.valid(w));
            }
        }
        Ok(e)
    }

    /// A run at step 0 from a given occupation (7-bit states in site order).
    pub fn with_occupation(params: LgaParams, occupation: &[u8]) -> Result<Self, String> {
        params.validate()?;
        Self::from_payload_struct(Payload {
            version: PAYLOAD_VERSION,
            params,
            step: 0,
            counters: Counters::default(),
            wall_impulse: [0, 0],
            occupation: occupation.to_vec(),
        })
    }

    /// Restore a state written by [`LgaEngine::to_payload`] (or the reference's).
    pub fn from_payload(bytes: &[u8]) -> Result<Self, String> {
        Self::from_payload_struct(Payload::from_bytes(bytes)?)
    }

    fn from_payload_struct(p: Payload) -> Result<Self, String> {
        let p = Payload::from_bytes(&p.to_bytes())?; // the same checks as a file
        let mut e = Self::empty(p.params);
        e.step = p.step;
        e.counters = p.counters;
        e.wall_impulse = p.wall_impulse;
        for (s, &o) in p.occupation.iter().enumerate() {
            let (x, y) = e.geometry.site(s);
            let c = y * e.nw + x / 64;
            for k in 0..7 {
                e.cur[c][k] |= u64::from((o >> k) & 1) << (x % 64);
            }
        }
        Ok(e)
    }

    fn empty(params: LgaParams) -> Self {
        let geometry = Geometry {
            length: params.length,
            width: params.width,
        };
        let nw = params.length.div_ceil(64);
        let rem = params.length % 64;
        LgaEngine {
            thresholds: params.thresholds(),
            nw,
            last_mask: if rem == 0 { !0 } else { (1u64 << rem) - 1 },
            cur: vec![[0; PLANES]; nw * params.width],
            tmp: vec![[0; PLANES]; nw * params.width],
            extras: Vec::new(),
            step: 0,
            counters: Counters::default(),
            wall_impulse: [0, 0],
            geometry,
            params,
        }
    }

    /// Valid-site mask of word `w` of a column.
    fn valid(&self, w: usize) -> u64 {
        if w + 1 == self.nw { self.last_mask } else { !0 }
    }

    pub fn params(&self) -> &LgaParams {
        &self.params
    }

    /// Time steps done.
    pub fn step(&self) -> u64 {
        self.step
    }

    /// Run up to `step` time steps (nothing if already there).
    pub fn advance_to(&mut self, step: u64) {
        while self.step < step {
            self.update();
        }
    }

    /// Number of particles N (conserved exactly).
    pub fn particle_count(&self) -> u64 {
        self.cur
            .iter()
            .map(|w| {
                w[..7]
                    .iter()
                    .map(|p| u64::from(p.count_ones()))
                    .sum::<u64>()
            })
            .sum()
    }

    /// Total momentum: x (along gravity) in halves of the lattice spacing, y in units of
    /// sqrt(3)/2 (see [`rules::MOMENTUM`]).
    pub fn momentum(&self) -> [i64; 2] {
        let mut p = [0i64; 2];
        for w in &self.cur {
            for k in 1..7 {
                let c = i64::from(w[k].count_ones());
                p[0] += c * MOMENTUM[k][0];
                p[1] += c * MOMENTUM[k][1];
            }
        }
        p
    }

    /// Momentum given to the particles by the walls since step 0 (units as [`Self::momentum`]).
    /// With the gravity events, it closes the momentum balance exactly:
    /// P(t) - P(0) = wall impulse + (2 (gravity starts + kicks), 0).
    pub fn wall_impulse(&self) -> [i64; 2] {
        self.wall_impulse
    }

    /// 7-bit state of every site (bit 0 rest, bit k velocity v_k) in site order: index
    /// y L + x, x along the pipe running fastest.
    pub fn occupation(&self) -> Vec<u8> {
        let mut out = vec![0u8; self.geometry.sites()];
        for (s, o) in out.iter_mut().enumerate() {
            let (x, y) = self.geometry.site(s);
            let word = &self.cur[y * self.nw + x / 64];
            for (k, plane) in word.iter().take(7).enumerate() {
                *o |= (((plane >> (x % 64)) & 1) as u8) << k;
            }
        }
        out
    }

    /// Particles in bins of `bin_length` consecutive x (all W sites of each), bin i covering
    /// x = i b .. (i + 1) b - 1; the last bin is shorter when b does not divide L.
    pub fn bin_counts(&self, bin_length: usize) -> Vec<u32> {
        assert!(bin_length > 0, "bin length must be at least 1");
        let l = self.geometry.length;
        let mut bins = vec![0u32; l.div_ceil(bin_length)];
        for y in 0..self.geometry.width {
            for w in 0..self.nw {
                let word = &self.cur[y * self.nw + w];
                let (lo, hi) = (w * 64, (w * 64 + 64).min(l));
                let mut x = lo;
                while x < hi {
                    // the part of this word inside bin x / b
                    let bin = x / bin_length;
                    let end = ((bin + 1) * bin_length).min(hi);
                    let width = end - x;
                    let mask = if width == 64 {
                        !0
                    } else {
                        ((1u64 << width) - 1) << (x - lo)
                    };
                    bins[bin] += word[..7]
                        .iter()
                        .map(|p| (p & mask).count_ones())
                        .sum::<u32>();
                    x = end;
                }
            }
        }
        bins
    }

    /// Bytes held by the engine's state (both word buffers and the extras list).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.cur.as_slice())
            + std::mem::size_of_val(self.tmp.as_slice())
            + self.extras.capacity() * std::mem::size_of::<(usize, u64, u64)>()
    }

    /// The event counters as named values, in the order of [`Counters`]' fields.
    pub fn counters(&self) -> Vec<(&'static str, u64)> {
        self.counters.named()
    }

    /// The event counters.
    pub fn counts(&self) -> Counters {
        self.counters
    }

    /// The full state (parameters, step, counters, wall impulse, occupation) as postcard.
    pub fn to_payload(&self) -> Vec<u8> {
        Payload {
            version: PAYLOAD_VERSION,
            params: self.params.clone(),
            step: self.step,
            counters: self.counters,
            wall_impulse: self.wall_impulse,
            occupation: self.occupation(),
        }
        .to_bytes()
    }

    /// One time step: collisions (1)-(5), hops of the extra rest particles, gravity (6),
    /// walls (7) and propagation.
    fn update(&mut self) {
        self.collide();
        self.place_extras();
        self.gravity();
        self.propagate();
        self.step += 1;
    }

    /// Rules (1)-(5) on every word, cur -> tmp; the words with extra rest particles are
    /// listed in `extras`.
    fn collide(&mut self) {
        let stream = Stream::new(self.params.seed, self.step, Purpose::Collide);
        let th = self.thresholds;
        let nw = self.nw;
        let c = &mut self.counters;
        self.extras.clear();
        for (i, (src, dst)) in self.cur.iter().zip(self.tmp.iter_mut()).enumerate() {
            let mut digits = Digits::new(&stream, i / nw, i % nw, nw);
            let out = collide_word(src, &mut digits, &th);
            *dst = out.state;
            if out.one_extra | out.two_extras != 0 {
                self.extras.push((i, out.one_extra, out.two_extras));
                c.rest_pairs += u64::from(out.one_extra.count_ones());
                c.rest_head_on += u64::from(out.two_extras.count_ones());
            }
            if out.head_on | out.dissipative_pairs | out.three_body != 0 {
                c.head_on += u64::from(out.head_on.count_ones());
                c.dissipative_pairs += u64::from(out.dissipative_pairs.count_ones());
                c.three_body += u64::from(out.three_body.count_ones());
            }
        }
    }

    /// The rest bit of site (x, y) in `tmp`.
    fn has_rest(&self, x: usize, y: usize) -> bool {
        (self.tmp[y * self.nw + x / 64][0] >> (x % 64)) & 1 == 1
    }

    fn set_rest(&mut self, x: usize, y: usize) {
        self.tmp[y * self.nw + x / 64][0] |= 1 << (x % 64);
    }

    /// The extra rest particles of rules (4)-(5) hop to random neighbours until they find a
    /// site without a rest particle, site by site in site order (see the module docs of
    /// `lga` for the order, the bound and the fallback).
    fn place_extras(&mut self) {
        if self.extras.is_empty() {
            return;
        }
        let g = self.geometry;
        let n = g.sites();
        let nw = self.nw;
        let mut free: u64 = (0..self.tmp.len())
            .map(|c| u64::from((!self.tmp[c][0] & self.valid(c % nw)).count_ones()))
            .sum();
        let hop = Stream::new(self.params.seed, self.step, Purpose::Hop);
        let extras = std::mem::take(&mut self.extras);
        for &(c, one, two) in &extras {
            let (y, w) = (c / nw, c % nw);
            let mut bits = one | two;
            while bits != 0 {
                let b = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let count: u8 = if (two >> b) & 1 == 1 { 2 } else { 1 };
                let x = w * 64 + b;
                if free < u64::from(count) {
                    // not enough room: the rule is not applied, the site keeps its state
                    for k in 0..7 {
                        let m = 1u64 << b;
                        self.tmp[c][k] = (self.tmp[c][k] & !m) | (self.cur[c][k] & m);
                    }
                    self.counters.blocked_rest_collisions += 1;
                    if count == 2 {
                        self.counters.rest_head_on -= 1;
                    } else {
                        self.counters.rest_pairs -= 1;
                    }
                    continue;
                }
                let s = g.index(x, y);
                for e in 0..count {
                    let (mut px, mut py) = (x, y);
                    let mut placed = false;
                    for h in 0..rng::MAX_HOPS {
                        let mut around = [(0usize, 0usize); 6];
                        let mut m = 0;
                        for k in 1..=6 {
                            if let Some(q) = g.neighbour(px, py, k) {
                                around[m] = q;
                                m += 1;
                            }
                        }
                        (px, py) = around[rng::choose(hop.word(rng::hop_word_index(s, e, h)), m)];
                        self.counters.rest_hops += 1;
                        if !self.has_rest(px, py) {
                            placed = true;
                            break;
                        }
                    }
                    if !placed {
                        self.counters.hop_fallbacks += 1;
                        let from = g.index(px, py);
                        let q = (1..=n)
                            .map(|d| (from + d) % n)
                            .find(|&q| {
                                let (qx, qy) = g.site(q);
                                !self.has_rest(qx, qy)
                            })
                            .expect("a site without a rest particle is left");
                        (px, py) = g.site(q);
                    }
                    self.set_rest(px, py);
                    free -= 1;
                }
            }
        }
        self.extras = extras;
    }

    /// Rule (6) on every word of tmp: with probability g a rest particle moves to v1 (if v1
    /// is empty), and next to a rest particle v3 -> v2 and v5 -> v6 (if the target is empty);
    /// the three decisions are independent and read the state before the rule.
    fn gravity(&mut self) {
        let (seed, t, nw) = (self.params.seed, self.step, self.nw);
        let th = self.thresholds.gravity;
        if th == 0 {
            return;
        }
        let start = Stream::new(seed, t, Purpose::GravityRest);
        let kick3 = Stream::new(seed, t, Purpose::GravityKick3);
        let kick5 = Stream::new(seed, t, Purpose::GravityKick5);
        for (i, s) in self.tmp.iter_mut().enumerate() {
            let r = s[0];
            if r == 0 {
                continue;
            }
            let (y, w) = (i / nw, i % nw);
            let starts = less_than(&mut Digits::new(&start, y, w, nw), th, r & !s[1]);
            let k3 = less_than(&mut Digits::new(&kick3, y, w, nw), th, r & s[3] & !s[2]);
            let k5 = less_than(&mut Digits::new(&kick5, y, w, nw), th, r & s[5] & !s[6]);
            s[0] ^= starts;
            s[1] |= starts;
            s[3] ^= k3;
            s[2] |= k3;
            s[5] ^= k5;
            s[6] |= k5;
            self.counters.gravity_starts += u64::from(starts.count_ones());
            self.counters.gravity_kicks += u64::from(k3.count_ones() + k5.count_ones());
        }
    }

    /// Propagation tmp -> cur, with rule (7) at the walls: a particle at column 0 moving
    /// towards the wall (v5, v6) stays at its site and turns into v2 / v3 (bounced back,
    /// probability b) or v3 / v2 (mirrored); likewise v2, v3 at column W - 1 turn into v5 / v6
    /// or v6 / v5. One decision per wall site serves both of its particles.
    fn propagate(&mut self) {
        let (nw, wd) = (self.nw, self.geometry.width);
        let last_bit = (self.geometry.length - 1) % 64;
        let last_mask = self.last_mask;
        let th = self.thresholds.bounce_back;
        let low = Stream::new(self.params.seed, self.step, Purpose::WallLow);
        let high = Stream::new(self.params.seed, self.step, Purpose::WallHigh);
        let tmp = &self.tmp;
        // plane k of column y shifted by one site towards +x (periodic) / towards -x
        let up = |y: usize, k: usize, w: usize| -> u64 {
            let col = &tmp[y * nw..(y + 1) * nw];
            let carry = if w == 0 {
                (col[nw - 1][k] >> last_bit) & 1
            } else {
                col[w - 1][k] >> 63
            };
            (col[w][k] << 1) | carry
        };
        let down = |y: usize, k: usize, w: usize| -> u64 {
            let col = &tmp[y * nw..(y + 1) * nw];
            let carry = if w + 1 == nw {
                (col[0][k] & 1) << last_bit
            } else {
                col[w + 1][k] << 63
            };
            (col[w][k] >> 1) | carry
        };
        // plane k of column y unshifted
        let same = |y: usize, k: usize, w: usize| tmp[y * nw + w][k];
        for y in 0..wd {
            let even = |y: usize| y.is_multiple_of(2);
            for w in 0..nw {
                let here = &tmp[y * nw + w];
                let mut out = [0u64; PLANES];
                out[0] = here[0];
                out[1] = up(y, 1, w);
                out[4] = down(y, 4, w);
                // v2 (and v3) arrive from column y - 1: x' = x (x - 1) from an even column,
                // x' = x + 1 (x) from an odd one
                if y > 0 {
                    out[2] = if even(y - 1) {
                        same(y - 1, 2, w)
                    } else {
                        up(y - 1, 2, w)
                    };
                    out[3] = if even(y - 1) {
                        down(y - 1, 3, w)
                    } else {
                        same(y - 1, 3, w)
                    };
                } else {
                    let hit = here[5] | here[6];
                    let back = less_than(&mut Digits::new(&low, y, w, nw), th, hit);
                    out[2] = (back & here[5]) | (!back & here[6]);
                    out[3] = (back & here[6]) | (!back & here[5]);
                    self.counters.wall_collisions +=
                        u64::from(here[5].count_ones() + here[6].count_ones());
                    self.counters.wall_bounce_backs +=
                        u64::from((back & here[5]).count_ones() + (back & here[6]).count_ones());
                    // bounced v5 -> v2: (+2, +2), v6 -> v3: (-2, +2); mirrored: (0, +2)
                    self.wall_impulse[0] += 2
                        * (i64::from((back & here[5]).count_ones())
                            - i64::from((back & here[6]).count_ones()));
                    self.wall_impulse[1] +=
                        2 * i64::from(here[5].count_ones() + here[6].count_ones());
                }
                // v5 (and v6) arrive from column y + 1
                if y + 1 < wd {
                    out[5] = if even(y + 1) {
                        down(y + 1, 5, w)
                    } else {
                        same(y + 1, 5, w)
                    };
                    out[6] = if even(y + 1) {
                        same(y + 1, 6, w)
                    } else {
                        up(y + 1, 6, w)
                    };
                } else {
                    let hit = here[2] | here[3];
                    let back = less_than(&mut Digits::new(&high, y, w, nw), th, hit);
                    out[5] = (back & here[2]) | (!back & here[3]);
                    out[6] = (back & here[3]) | (!back & here[2]);
                    self.counters.wall_collisions +=
                        u64::from(here[2].count_ones() + here[3].count_ones());
                    self.counters.wall_bounce_backs +=
                        u64::from((back & here[2]).count_ones() + (back & here[3]).count_ones());
                    // bounced v2 -> v5: (-2, -2), v3 -> v6: (+2, -2); mirrored: (0, -2)
                    self.wall_impulse[0] += 2
                        * (i64::from((back & here[3]).count_ones())
                            - i64::from((back & here[2]).count_ones()));
                    self.wall_impulse[1] -=
                        2 * i64::from(here[2].count_ones() + here[3].count_ones());
                }
                if w + 1 == nw {
                    for p in out.iter_mut() {
                        *p &= last_mask;
                    }
                }
                self.cur[y * nw + w] = out;
            }
        }
    }
}

//! The one-site-at-a-time reference implementation: a byte per site, the rules of
//! [`super::rules`] applied site by site, the random decisions read as whole 32-bit uniforms
//! ([`rng::site_uniform`]). Slow and plain; the bit-parallel kernel must give the same states
//! and counters step by step.

use super::params::{LgaParams, Thresholds};
use super::rng::{self, Purpose, Stream};
use super::rules::{self, Geometry, MOMENTUM, REST, Rule, collide, mass, vel};
use super::state::{Counters, PAYLOAD_VERSION, Payload};

/// The reference lattice gas.
#[derive(Clone, Debug)]
pub struct LgaReference {
    params: LgaParams,
    thresholds: Thresholds,
    geometry: Geometry,
    /// words per column of the kernel's layout (the random stream is defined on it)
    nw: usize,
    step: u64,
    sites: Vec<u8>,
    counters: Counters,
    wall_impulse: [i64; 2],
}

impl LgaReference {
    /// The initial state: each moving state of each site occupied with probability rho / 6.
    pub fn new(params: LgaParams) -> Result<Self, String> {
        params.validate()?;
        let mut r = Self::empty(params);
        let th = r.thresholds;
        for k in 1..=6u8 {
            let stream = Stream::new(r.params.seed, 0, Purpose::Init(k));
            for s in 0..r.sites.len() {
                let (x, y) = r.geometry.site(s);
                if u64::from(rng::site_uniform(&stream, r.nw, x, y)) < th.occupation {
                    r.sites[s] |= 1 << k;
                }
            }
        }
        Ok(r)
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

    /// Restore from a payload written by either implementation.
    pub fn from_payload(bytes: &[u8]) -> Result<Self, String> {
        Self::from_payload_struct(Payload::from_bytes(bytes)?)
    }

    fn from_payload_struct(p: Payload) -> Result<Self, String> {
        let p = Payload::from_bytes(&p.to_bytes())?; // the same checks as a file
        let mut r = Self::empty(p.params);
        r.step = p.step;
        r.counters = p.counters;
        r.wall_impulse = p.wall_impulse;
        r.sites = p.occupation;
        Ok(r)
    }

    fn empty(params: LgaParams) -> Self {
        let geometry = Geometry {
            length: params.length,
            width: params.width,
        };
        LgaReference {
            thresholds: params.thresholds(),
            nw: params.length.div_ceil(64),
            step: 0,
            sites: vec![0; geometry.sites()],
            counters: Counters::default(),
            wall_impulse: [0, 0],
            geometry,
            params,
        }
    }

    pub fn params(&self) -> &LgaParams {
        &self.params
    }

    /// Time steps done.
    pub fn step(&self) -> u64 {
        self.step
    }

    /// 7-bit state of every site in site order.
    pub fn occupation(&self) -> Vec<u8> {
        self.sites.clone()
    }

    /// The event counters.
    pub fn counts(&self) -> Counters {
        self.counters
    }

    /// Momentum given to the particles by the walls so far.
    pub fn wall_impulse(&self) -> [i64; 2] {
        self.wall_impulse
    }

    pub fn particle_count(&self) -> u64 {
        self.sites.iter().map(|&s| u64::from(mass(s))).sum()
    }

    /// The full state (the same payload as the kernel's).
    pub fn to_payload(&self) -> Vec<u8> {
        Payload {
            version: PAYLOAD_VERSION,
            params: self.params.clone(),
            step: self.step,
            counters: self.counters,
            wall_impulse: self.wall_impulse,
            occupation: self.sites.clone(),
        }
        .to_bytes()
    }

    /// Run up to `step` time steps (nothing if already there).
    pub fn advance_to(&mut self, step: u64) {
        while self.step < step {
            self.update();
        }
    }

    /// One time step: collisions (1)-(5), hops of the extra rest particles, gravity (6),
    /// walls (7) and propagation.
    fn update(&mut self) {
        let g = self.geometry;
        let n = g.sites();
        let th = self.thresholds;
        let (seed, t, nw) = (self.params.seed, self.step, self.nw);
        let uniform = |purpose: Purpose, x: usize, y: usize| {
            u64::from(rng::site_uniform(&Stream::new(seed, t, purpose), nw, x, y))
        };

        // collisions, every site on its own
        let pre = std::mem::take(&mut self.sites);
        let mut post = vec![0u8; n];
        let mut extras = vec![0u8; n];
        let mut rule_at = vec![Rule::None; n];
        for s in 0..n {
            let (x, y) = g.site(s);
            let state = pre[s];
            let random = state & REST == 0 && matches!(mass(state), 2 | 3);
            let u = if random {
                uniform(Purpose::Collide, x, y) as u32
            } else {
                0
            };
            let c = collide(state, u, &th);
            post[s] = c.state;
            extras[s] = c.extras;
            rule_at[s] = c.rule;
            let counter = match c.rule {
                Rule::None => None,
                Rule::HeadOn => Some(&mut self.counters.head_on),
                Rule::DissipativePair => Some(&mut self.counters.dissipative_pairs),
                Rule::ThreeBody => Some(&mut self.counters.three_body),
                Rule::RestHeadOn => Some(&mut self.counters.rest_head_on),
                Rule::RestPair => Some(&mut self.counters.rest_pairs),
            };
            if let Some(c) = counter {
                *c += 1;
            }
        }

        // extra rest particles hop, site by site in site order
        let hop = Stream::new(seed, t, Purpose::Hop);
        let mut free = post.iter().filter(|&&s| s & REST == 0).count();
        for s in 0..n {
            if extras[s] == 0 {
                continue;
            }
            if free < usize::from(extras[s]) {
                post[s] = pre[s];
                self.counters.blocked_rest_collisions += 1;
                match rule_at[s] {
                    Rule::RestHeadOn => self.counters.rest_head_on -= 1,
                    _ => self.counters.rest_pairs -= 1,
                }
                continue;
            }
            for e in 0..extras[s] {
                let mut pos = s;
                let mut placed = false;
                for h in 0..rng::MAX_HOPS {
                    let (x, y) = g.site(pos);
                    let around: Vec<usize> = (1..=6)
                        .filter_map(|k| g.neighbour(x, y, k))
                        .map(|(x2, y2)| g.index(x2, y2))
                        .collect();
                    pos = around[rng::choose(hop.word(rng::hop_word_index(s, e, h)), around.len())];
                    self.counters.rest_hops += 1;
                    if post[pos] & REST == 0 {
                        placed = true;
                        break;
                    }
                }
                if !placed {
                    self.counters.hop_fallbacks += 1;
                    pos = (1..=n)
                        .map(|d| (pos + d) % n)
                        .find(|&q| post[q] & REST == 0)
                        .expect("a site without a rest particle is left");
                }
                post[pos] |= REST;
                free -= 1;
            }
        }

        // gravity: rest -> v1, and v3 -> v2, v5 -> v6 next to a rest particle (probability g)
        for (s, state) in post.iter_mut().enumerate() {
            if *state & REST == 0 {
                continue;
            }
            let (x, y) = g.site(s);
            let before = *state;
            if before & vel(1) == 0 && uniform(Purpose::GravityRest, x, y) < th.gravity {
                *state = (*state & !REST) | vel(1);
                self.counters.gravity_starts += 1;
            }
            if before & vel(3) != 0
                && before & vel(2) == 0
                && uniform(Purpose::GravityKick3, x, y) < th.gravity
            {
                *state = (*state & !vel(3)) | vel(2);
                self.counters.gravity_kicks += 1;
            }
            if before & vel(5) != 0
                && before & vel(6) == 0
                && uniform(Purpose::GravityKick5, x, y) < th.gravity
            {
                *state = (*state & !vel(5)) | vel(6);
                self.counters.gravity_kicks += 1;
            }
        }

        // propagation; a particle that would cross a wall is reflected in place: bounced back
        // with probability b, else mirrored (one decision per wall site)
        let mut next = vec![0u8; n];
        for (s, &state) in post.iter().enumerate() {
            let (x, y) = g.site(s);
            next[s] |= state & REST;
            for k in 1..=6 {
                if state & vel(k) == 0 {
                    continue;
                }
                match g.neighbour(x, y, k) {
                    Some((x2, y2)) => next[g.index(x2, y2)] |= vel(k),
                    None => {
                        let (purpose, back, mirror) = match k {
                            2 => (Purpose::WallHigh, 5, 6),
                            3 => (Purpose::WallHigh, 6, 5),
                            5 => (Purpose::WallLow, 2, 3),
                            6 => (Purpose::WallLow, 3, 2),
                            _ => unreachable!("v1 and v4 never leave the pipe"),
                        };
                        let bounce = uniform(purpose, x, y) < th.bounce_back;
                        let k2 = if bounce { back } else { mirror };
                        debug_assert_eq!(next[s] & vel(k2), 0, "no particle arrives there");
                        next[s] |= vel(k2);
                        self.counters.wall_collisions += 1;
                        self.counters.wall_bounce_backs += u64::from(bounce);
                        let (after, before) = (MOMENTUM[k2 as usize], MOMENTUM[k as usize]);
                        self.wall_impulse[0] += after[0] - before[0];
                        self.wall_impulse[1] += after[1] - before[1];
                    }
                }
            }
        }
        self.sites = next;
        self.step += 1;
    }

    /// Total momentum in the units of [`rules::MOMENTUM`].
    pub fn momentum(&self) -> [i64; 2] {
        self.sites.iter().fold([0, 0], |acc, &s| {
            let p = rules::momentum(s);
            [acc[0] + p[0], acc[1] + p[1]]
        })
    }
}

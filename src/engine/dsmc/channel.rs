//! The DSMC channel engine (thesis ch. 2-3, 5.2): smooth inelastic hard spheres of one or two
//! species driven by a body force along x between two walls normal to y, with layer cells
//! across y and Bird's no-time-counter collisions.
//!
//! One step (thesis 2.3.2):
//! 1. *move*: every simulator flies for dt under the force, walls processed at their hit
//!    times ([`walls::fly`]), and gets the key (cell, species) of its new position;
//! 2. *sort*: a counting sort by key makes each cell's simulators of each species one
//!    contiguous run (cell-major, species-minor), so moves, collisions and sampling stream
//!    through memory;
//! 3. *collide*: in each cell and for each species pair (s, t), Bird's NTC selects
//!    M = N_s (N_s - 1)/2 F_N sigma_st g_max dt / V_c (s = t) or N_s N_t F_N sigma_st g_max dt
//!    / V_c (s != t) candidate pairs (rounded at random, so its mean is exact), in a mixture
//!    taken in random order across the species pairs (a fixed order biases the species against
//!    each other by O(dt)); a candidate collides with probability |g| / g_max along a contact
//!    direction weighted by g . k, which samples the thesis' rule (eqs. 2.19-2.25, 5.4-5.5)
//!    with four times fewer rejections ([`kernel::contact_direction`]). g_max is an exact
//!    bound computed afresh in every cell and step, g_max = r_s + r_t with r_s = max |v_i - c|
//!    over the species-s simulators and c the cell's mean velocity
//!    (|v_i - v_j| <= |v_i - c| + |v_j - c|), instead of the thesis' bound updated when
//!    exceeded (see [`DsmcCounters::bound_exceedances`] for why);
//! 4. *sample*: every `sample_every` steps the raw moments of each (cell, species) are added
//!    to the interval's sums ([`sampling`]).
//!
//! Randomness comes from one PCG-64 (MCG) stream whose 128-bit state is part of the payload,
//! so that the same seed gives bitwise the same run, and a run resumed from a payload
//! continues bitwise as if it had never stopped.

use super::kernel::{contact_direction, normal_pair, smooth_collision};
use super::params::{DsmcParams, WallModel};
use super::sampling::{Balances, IntervalSums, add_velocity};
use super::walls::{Walls, fly, fly_periodic};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// One simulated particle: velocity and position across the channel (x and z are periodic and
/// not stored, thesis 3.2.1). Its species is that of the sorted run it sits in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Simulator {
    /// v, velocity
    pub v: [f64; 3],
    /// y in [0, W]
    pub y: f64,
}

/// Event counts since the start of the run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DsmcCounters {
    pub steps: u64,
    /// simulator flights (one per simulator and step)
    pub moves: u64,
    /// NTC candidate pairs
    pub candidates: u64,
    /// accepted collisions
    pub collisions: u64,
    pub wall_hits: u64,
    /// candidates with |g| above their cell's g_max, which collisions earlier in the same cell
    /// and step can cause (they collide with probability 1 instead of |g| / g_max_true, and
    /// raise g_max for the rest of the cell). The exact per-step bound replaces the thesis'
    /// g_max that starts at 3 most probable speeds and grows when exceeded (3.2.2): that bound
    /// is exceeded by 3 % of the pairs at T_w, each such candidate is under-collided until
    /// g_max has crept up (it kept Q 2 % low for the first ~40 000 steps at Kn = 0.89), and it
    /// never comes down in a cooled cluster, where almost every candidate is then rejected
    /// (measured: both effects, the second stalling a granular run at Kn = 0.01, e = 0.7).
    pub bound_exceedances: u64,
    /// sampling steps
    pub samples: u64,
}

/// Resolution checks of a run: a priori from the parameters, measured from the run so far
/// (cell occupancies and collisions counted at every step; NaN before the first step).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DsmcChecks {
    pub cells: usize,
    pub particles: usize,
    /// cell width / lambda with the a priori lambda = Kn W (thesis: <= 1/3)
    pub cell_width_over_mean_free_path: f64,
    /// dt / tau_c with the a priori tau_c at T_w (the `time_step` parameter)
    pub time_step_over_collision_time: f64,
    /// largest cell width / local lambda, lambda_c = 1 / (sqrt 2 n_c pi d_1^2) with n_c the
    /// cell's mean real density over the run
    pub max_cell_width_over_local_mean_free_path: f64,
    /// largest dt x local collision rate per particle (2 collisions / occupancy of a cell)
    pub max_time_step_over_local_collision_time: f64,
    /// dt x mean collision rate per particle of the whole gas
    pub time_step_over_mean_collision_time: f64,
    /// NTC candidates per accepted collision (g_max / <|g|> on average)
    pub candidates_per_collision: f64,
    /// mean occupancy of the emptiest cell
    pub min_mean_particles_per_cell: f64,
}

/// Everything that evolves, as the payload stores it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct State {
    params: DsmcParams,
    step: u64,
    /// PCG-64 MCG state
    rng: u128,
    /// simulators sorted by (cell, species)
    particles: Vec<Simulator>,
    /// start of each (cell, species) run in `particles`, plus the total
    segments: Vec<u32>,
    /// temperature of the layer cell next to each wall (adiabatic walls)
    adjacent: [f64; 2],
    counters: DsmcCounters,
    /// balances since step 0
    totals: Balances,
    /// the running sampling interval
    interval: IntervalSums,
    /// per cell: summed occupancy over steps, collisions
    cell_stats: Vec<[u64; 2]>,
}

/// A species pair that collides in the cells.
#[derive(Clone, Copy, Debug)]
struct Pair {
    s: usize,
    t: usize,
    restitution: f64,
    /// candidates per (pair of simulators) per unit g_max: F_N sigma_st dt / V_c
    rate: f64,
}

/// The NTC candidates of one species pair in one cell and step: how many are left, and the
/// bound g_max on |g| (raised when a candidate exceeds it).
#[derive(Clone, Copy, Debug, Default)]
struct PairPlan {
    candidates: u64,
    bound: f64,
}

/// Constants of a run derived from its parameters (not stored).
#[derive(Clone, Debug)]
struct Derived {
    cells: usize,
    species: usize,
    dt: f64,
    acceleration: f64,
    masses: [f64; 2],
    counts: [usize; 2],
    pairs: Vec<Pair>,
    walls: Walls,
}

impl Derived {
    fn of(p: &DsmcParams) -> Derived {
        let cells = p.cell_count();
        let species = p.species();
        let counts = p.species_counts();
        let total = (counts[0] + counts[1]) as f64;
        let dt = p.dt();
        let d = p.diameters();
        let mut pairs = Vec::new();
        for s in 0..species {
            for t in s..species {
                let dst = 0.5 * (d[s] + d[t]);
                // F_N / V_c = n W / (N dy) = n cells / N, and n sigma_st = n pi d_1^2 (d_st/d_1)^2
                let rate = p.collision_density() * dst * dst * dt * cells as f64 / total;
                pairs.push(Pair {
                    s,
                    t,
                    restitution: p.pair_restitution(s, t),
                    rate,
                });
            }
        }
        Derived {
            cells,
            species,
            dt,
            acceleration: p.acceleration(),
            masses: p.masses(),
            counts,
            pairs,
            walls: Walls {
                model: p.wall_model,
                accommodation: p.accommodation,
                roughness: p.wall_roughness,
                temperature: 1.0,
            },
        }
    }
}

/// Reused buffers of the step (not stored).
#[derive(Clone, Debug, Default)]
struct Scratch {
    keys: Vec<u32>,
    counts: Vec<u32>,
    sorted: Vec<Simulator>,
}

/// What a snapshot of the channel carries: the run's constants and the sampling interval
/// since the previous snapshot (what the rarefied analysis records).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Kn
    pub knudsen_number: f64,
    /// a-hat
    pub forcing: f64,
    pub wall_model: WallModel,
    /// [m_1, m_2]
    pub masses: [f64; 2],
    /// simulators of each species
    pub counts: [u64; 2],
    /// moments and balances of the interval
    pub sums: IntervalSums,
}

impl crate::engine::EngineSample for Sample {}

/// The DSMC channel engine.
#[derive(Clone, Debug)]
pub struct DsmcEngine {
    state: State,
    derived: Derived,
    scratch: Scratch,
}

impl DsmcEngine {
    /// Set up a run: simulators uniform across the channel, Maxwellian velocities at T_w
    /// (species s with variance k T_w / m_s per component), species 1 first.
    pub fn new(params: DsmcParams) -> Result<Self, String> {
        params.validate()?;
        let derived = Derived::of(&params);
        let mut rng = Pcg64Mcg::seed_from_u64(params.seed);
        let mut particles = Vec::with_capacity(derived.counts[0] + derived.counts[1]);
        let mut keys = Vec::with_capacity(particles.capacity());
        for s in 0..derived.species {
            let sigma = (1.0 / derived.masses[s]).sqrt();
            for _ in 0..derived.counts[s] {
                let y = rng.random::<f64>();
                let (a, b) = normal_pair(&mut rng);
                let (c, _) = normal_pair(&mut rng);
                particles.push(Simulator {
                    v: [sigma * a, sigma * b, sigma * c],
                    y,
                });
                let cell = cell_of(y, derived.cells);
                keys.push((cell * derived.species + s) as u32);
            }
        }
        let segments_len = derived.cells * derived.species + 1;
        let state = State {
            step: 0,
            rng: 0,
            particles,
            segments: vec![0; segments_len],
            adjacent: [1.0; 2],
            counters: DsmcCounters::default(),
            totals: Balances::default(),
            interval: IntervalSums::default(),
            cell_stats: vec![[0; 2]; derived.cells],
            params,
        };
        let mut engine = DsmcEngine {
            state,
            derived,
            scratch: Scratch::default(),
        };
        engine.scratch.keys = keys;
        engine.sort();
        engine.state.rng = rng.state();
        engine.state.interval = engine.fresh_interval();
        if engine.state.params.wall_model == WallModel::Adiabatic {
            engine.update_adjacent();
        }
        Ok(engine)
    }

    pub fn params(&self) -> &DsmcParams {
        &self.state.params
    }

    /// Steps done.
    pub fn steps(&self) -> u64 {
        self.state.step
    }

    /// Simulated time, steps x dt.
    pub fn time(&self) -> f64 {
        self.state.step as f64 * self.derived.dt
    }

    /// Delta t.
    pub fn dt(&self) -> f64 {
        self.derived.dt
    }

    /// Layer cells across the channel.
    pub fn cells(&self) -> usize {
        self.derived.cells
    }

    /// Simulators of each species.
    pub fn species_counts(&self) -> [usize; 2] {
        self.derived.counts
    }

    /// Run until `step` steps are done (nothing if already there). Deterministic: the same
    /// parameters reach the same state bitwise, however the run is split into calls.
    pub fn advance_to_step(&mut self, step: u64) {
        while self.state.step < step {
            self.step();
        }
    }

    /// Counters by name: steps, moves, candidates, collisions, wall hits, g_max bound
    /// exceedances, samples.
    pub fn counters(&self) -> Vec<(&'static str, u64)> {
        let c = &self.state.counters;
        vec![
            ("moves", c.moves),
            ("candidates", c.candidates),
            ("collisions", c.collisions),
            ("wall_hits", c.wall_hits),
            ("bound_exceedances", c.bound_exceedances),
            ("samples", c.samples),
        ]
    }

    /// The counters as a struct.
    pub fn counter_values(&self) -> DsmcCounters {
        self.state.counters
    }

    /// Cell-width and time-step checks, a priori and measured over the run so far.
    pub fn checks(&self) -> DsmcChecks {
        let d = &self.derived;
        let p = &self.state.params;
        let n = (d.counts[0] + d.counts[1]) as f64;
        let steps = self.state.counters.steps as f64;
        let mut max_width = f64::NAN;
        let mut max_rate = f64::NAN;
        let mut min_occupancy = f64::NAN;
        if steps > 0.0 {
            for &[occupancy, collisions] in &self.state.cell_stats {
                let mean = occupancy as f64 / steps;
                // width / lambda_c = (W / cells) / (lambda N / (cells n_c)) = n_c / (N lambda)
                max_width = max_width.max(mean / (n * p.mean_free_path()));
                if occupancy > 0 {
                    max_rate = max_rate.max(2.0 * collisions as f64 / occupancy as f64);
                }
                min_occupancy = min_occupancy.min(mean);
            }
        }
        let c = &self.state.counters;
        DsmcChecks {
            cells: d.cells,
            particles: n as usize,
            cell_width_over_mean_free_path: 1.0 / (d.cells as f64 * p.mean_free_path()),
            time_step_over_collision_time: p.time_step,
            max_cell_width_over_local_mean_free_path: max_width,
            max_time_step_over_local_collision_time: max_rate,
            time_step_over_mean_collision_time: 2.0 * c.collisions as f64 / (n * steps),
            candidates_per_collision: c.candidates as f64 / c.collisions as f64,
            min_mean_particles_per_cell: min_occupancy,
        }
    }

    /// Balances since step 0.
    pub fn totals(&self) -> &Balances {
        &self.state.totals
    }

    /// The running sampling interval (read-only).
    pub fn interval(&self) -> &IntervalSums {
        &self.state.interval
    }

    /// Read and reset the sampling interval: returns the sums since the last call (or the
    /// start) with the kinetic energy and x-momentum at both ends, and starts a new interval.
    pub fn take_interval(&mut self) -> IntervalSums {
        let fresh = self.fresh_interval();
        let mut done = std::mem::replace(&mut self.state.interval, fresh);
        done.end_step = self.state.step;
        done.duration = (done.end_step - done.start_step) as f64 * self.derived.dt;
        done.kinetic_energy[1] = self.state.interval.kinetic_energy[0];
        done.momentum_x[1] = self.state.interval.momentum_x[0];
        done
    }

    /// Read and reset the sampling interval as a [`Sample`] with the run's constants.
    pub fn take_sample(&mut self) -> Sample {
        let counts = self.species_counts();
        Sample {
            knudsen_number: self.params().knudsen_number,
            forcing: self.params().forcing,
            wall_model: self.params().wall_model,
            masses: self.params().masses(),
            counts: [counts[0] as u64, counts[1] as u64],
            sums: self.take_interval(),
        }
    }

    /// Total kinetic energy sum m |v|^2 / 2 and x-momentum sum m v_x.
    pub fn energy_and_momentum(&self) -> (f64, f64) {
        let (mut energy, mut momentum) = (0.0, 0.0);
        self.for_each_simulator(|s, _, v| {
            let m = self.derived.masses[s];
            energy += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            momentum += m * v[0];
        });
        (energy, momentum)
    }

    /// Visit every simulator as (species, y, v), in storage order.
    pub fn for_each_simulator(&self, mut f: impl FnMut(usize, f64, [f64; 3])) {
        let st = &self.state;
        for (seg, w) in st.segments.windows(2).enumerate() {
            let s = seg % self.derived.species;
            for p in &st.particles[w[0] as usize..w[1] as usize] {
                f(s, p.y, p.v);
            }
        }
    }

    /// The engine state as postcard bytes (the caller adds its envelope).
    pub fn to_payload(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.state).expect("DSMC state serialises")
    }

    /// Restore an engine from [`to_payload`](Self::to_payload) bytes; it continues bitwise
    /// as the engine that wrote them would have.
    pub fn from_payload(bytes: &[u8]) -> Result<Self, String> {
        let state: State = postcard::from_bytes(bytes)
            .map_err(|e| format!("DSMC payload does not decode: {e}"))?;
        state.params.validate()?;
        let derived = Derived::of(&state.params);
        let n = derived.counts[0] + derived.counts[1];
        let k = derived.cells * derived.species;
        let consistent = state.particles.len() == n
            && state.segments.len() == k + 1
            && state.segments[0] == 0
            && state.segments[k] as usize == n
            && state.segments.windows(2).all(|w| w[0] <= w[1])
            && state.cell_stats.len() == derived.cells
            && state.interval.moments.len() == k
            && state.particles.iter().all(|p| (0.0..=1.0).contains(&p.y));
        if !consistent {
            return Err(format!(
                "DSMC payload is inconsistent with its parameters ({} simulators, {} cells, \
                 {} species expected)",
                n, derived.cells, derived.species
            ));
        }
        Ok(DsmcEngine {
            state,
            derived,
            scratch: Scratch::default(),
        })
    }

    fn fresh_interval(&self) -> IntervalSums {
        let (energy, momentum) = self.energy_and_momentum();
        IntervalSums::start(
            self.state.step,
            self.derived.cells,
            self.derived.species,
            energy,
            momentum,
        )
    }

    /// One DSMC step: move, sort, collide, (adiabatic walls: wall-cell temperatures), sample.
    fn step(&mut self) {
        let mut rng = Pcg64Mcg::new(self.state.rng);
        self.flights(&mut rng);
        self.sort();
        self.collisions(&mut rng);
        if self.state.params.wall_model == WallModel::Adiabatic {
            self.update_adjacent();
        }
        self.state.rng = rng.state();
        self.state.step += 1;
        self.state.counters.steps += 1;
        if self
            .state
            .step
            .is_multiple_of(self.state.params.sample_every)
        {
            self.sample();
        }
    }

    /// Move every simulator for dt and key it by its new (cell, species).
    fn flights(&mut self, rng: &mut Pcg64Mcg) {
        let d = &self.derived;
        let st = &mut self.state;
        let sc = &mut self.scratch;
        let n = st.particles.len();
        sc.keys.resize(n, 0);
        let (dt, a, cells, species) = (d.dt, d.acceleration, d.cells, d.species);
        let walls = d.walls;
        let adjacent = st.adjacent;
        let mut tally = Balances::default();
        for seg in 0..cells * species {
            let s = seg % species;
            let mass = d.masses[s];
            let (lo, hi) = (st.segments[seg] as usize, st.segments[seg + 1] as usize);
            let mut dx = 0.0;
            for (p, key) in st.particles[lo..hi].iter_mut().zip(&mut sc.keys[lo..hi]) {
                let mut v = Vector3::from(p.v);
                if walls.model == WallModel::Periodic {
                    fly_periodic(&mut p.y, &v, dt);
                } else {
                    dx += fly(&mut p.y, &mut v, dt, a, |wall, incoming| {
                        let outgoing = walls.reemit(wall, incoming, mass, adjacent[wall], rng);
                        let w = &mut tally.walls[wall];
                        w.hits += 1;
                        for c in 0..3 {
                            w.momentum[c] += mass * (incoming[c] - outgoing[c]);
                        }
                        w.energy +=
                            0.5 * mass * (incoming.norm_squared() - outgoing.norm_squared());
                        outgoing
                    });
                    p.v = v.into();
                }
                *key = (cell_of(p.y, cells) * species + s) as u32;
            }
            tally.work += mass * a * dx;
        }
        st.counters.moves += n as u64;
        st.counters.wall_hits += tally.walls[0].hits + tally.walls[1].hits;
        st.totals.add(&tally);
        st.interval.balances.add(&tally);
    }

    /// Counting sort of the simulators by key into contiguous (cell, species) runs.
    fn sort(&mut self) {
        let st = &mut self.state;
        let sc = &mut self.scratch;
        let k = st.segments.len() - 1;
        sc.counts.clear();
        sc.counts.resize(k, 0);
        for &key in &sc.keys {
            sc.counts[key as usize] += 1;
        }
        let mut offset = 0u32;
        for (start, count) in st.segments.iter_mut().zip(sc.counts.iter_mut()) {
            *start = offset;
            offset += *count;
            *count = *start; // becomes the write cursor of its run
        }
        st.segments[k] = offset;
        sc.sorted.resize(st.particles.len(), Simulator::default());
        for (p, &key) in st.particles.iter().zip(&sc.keys) {
            let cursor = &mut sc.counts[key as usize];
            sc.sorted[*cursor as usize] = *p;
            *cursor += 1;
        }
        std::mem::swap(&mut st.particles, &mut sc.sorted);
    }

    /// NTC collisions in every cell and species pair.
    fn collisions(&mut self, rng: &mut Pcg64Mcg) {
        let d = &self.derived;
        let st = &mut self.state;
        let species = d.species;
        let (mut candidates, mut collisions, mut exceeded) = (0u64, 0u64, 0u64);
        let mut dissipated = 0.0;
        for c in 0..d.cells {
            let run = |s: usize| {
                (
                    st.segments[c * species + s] as usize,
                    st.segments[c * species + s + 1] as usize,
                )
            };
            let (cell_start, cell_end) = (run(0).0, run(species - 1).1);
            let before = collisions;
            if cell_end - cell_start >= 2 {
                // r_s = max |v_i - c| about the cell's mean velocity c
                let cell = &st.particles[cell_start..cell_end];
                let centre = cell
                    .iter()
                    .map(|p| Vector3::from(p.v))
                    .sum::<Vector3<f64>>()
                    / cell.len() as f64;
                let mut radius = [0.0f64; 2];
                for (s, r) in radius.iter_mut().enumerate().take(species) {
                    let (lo, hi) = run(s);
                    let widest = st.particles[lo..hi]
                        .iter()
                        .map(|p| (Vector3::from(p.v) - centre).norm_squared())
                        .fold(0.0, f64::max);
                    *r = widest.sqrt();
                }
                // candidates of each species pair: M = pair count x rate x bound, rounded at
                // random (in pair order, before any collision)
                let mut plans = [PairPlan::default(); 3];
                let mut left = 0u64;
                for (plan, pair) in plans.iter_mut().zip(&d.pairs) {
                    let ((lo_s, hi_s), (lo_t, hi_t)) = (run(pair.s), run(pair.t));
                    let (ns, nt) = (hi_s - lo_s, hi_t - lo_t);
                    let pair_count = if pair.s == pair.t {
                        (ns * ns.saturating_sub(1) / 2) as f64
                    } else {
                        (ns * nt) as f64
                    };
                    let bound = radius[pair.s] + radius[pair.t];
                    if pair_count == 0.0 || bound == 0.0 {
                        continue;
                    }
                    let expected = pair_count * pair.rate * bound;
                    plan.candidates = (expected + rng.random::<f64>()) as u64;
                    plan.bound = bound;
                    left += plan.candidates;
                }
                candidates += left;
                // one species pair: its candidates in turn; a mixture: the candidates of all
                // pairs in random order (each next one of pair p with probability
                // remaining_p / remaining), so that no species pair always collides first in
                // a step: a fixed order (1-1, then 1-2, then 2-2) made two identical species
                // differ by O(dt), T_2 / T_1 = 0.990 at dt = 0.4 tau_c and 0.998 at 0.1
                let mixture = d.pairs.len() > 1;
                while left > 0 {
                    let p = if mixture {
                        let mut r = rng.random_range(0..left);
                        let mut p = 0;
                        while r >= plans[p].candidates {
                            r -= plans[p].candidates;
                            p += 1;
                        }
                        p
                    } else {
                        0
                    };
                    plans[p].candidates -= 1;
                    left -= 1;
                    let pair = &d.pairs[p];
                    let ((lo_s, hi_s), (lo_t, hi_t)) = (run(pair.s), run(pair.t));
                    let (ns, nt) = (hi_s - lo_s, hi_t - lo_t);
                    let i = lo_s + rng.random_range(0..ns as u32) as usize;
                    let j = if pair.s == pair.t {
                        let r = rng.random_range(0..(ns - 1) as u32) as usize;
                        lo_s + (i - lo_s + 1 + r) % ns
                    } else {
                        lo_t + rng.random_range(0..nt as u32) as usize
                    };
                    let mut vi = Vector3::from(st.particles[i].v);
                    let mut vj = Vector3::from(st.particles[j].v);
                    let g = vi - vj;
                    let speed = g.norm();
                    let bound = &mut plans[p].bound;
                    if speed > *bound {
                        *bound = speed;
                        exceeded += 1;
                    }
                    if rng.random::<f64>() * *bound < speed {
                        let k = contact_direction(rng, &(g / speed));
                        let masses = (d.masses[pair.s], d.masses[pair.t]);
                        dissipated +=
                            smooth_collision(&mut vi, &mut vj, &k, pair.restitution, masses);
                        st.particles[i].v = vi.into();
                        st.particles[j].v = vj.into();
                        collisions += 1;
                    }
                }
            }
            let stats = &mut st.cell_stats[c];
            stats[0] += (cell_end - cell_start) as u64;
            stats[1] += collisions - before;
        }
        let cn = &mut st.counters;
        cn.candidates += candidates;
        cn.collisions += collisions;
        cn.bound_exceedances += exceeded;
        for b in [&mut st.totals, &mut st.interval.balances] {
            b.collisions += collisions;
            b.dissipated += dissipated;
        }
    }

    /// Temperature of the two wall cells, T = sum m |v - u|^2 / (3 (N_c - 1)) with u the cell's
    /// mass-weighted mean velocity (all species); a cell with fewer than two simulators keeps
    /// its previous value.
    fn update_adjacent(&mut self) {
        let species = self.derived.species;
        for (wall, cell) in [(0, 0), (1, self.derived.cells - 1)] {
            let (mut mass, mut momentum, mut energy, mut count) = (0.0, Vector3::zeros(), 0.0, 0);
            for s in 0..species {
                let m = self.derived.masses[s];
                let lo = self.state.segments[cell * species + s] as usize;
                let hi = self.state.segments[cell * species + s + 1] as usize;
                for p in &self.state.particles[lo..hi] {
                    let v = Vector3::from(p.v);
                    mass += m;
                    momentum += m * v;
                    energy += m * v.norm_squared();
                    count += 1;
                }
            }
            if count >= 2 {
                let u = momentum / mass;
                let thermal = energy - mass * u.norm_squared();
                self.state.adjacent[wall] = thermal / (3.0 * (count - 1) as f64);
            }
        }
    }

    /// Add the moments of every (cell, species) run to the interval.
    fn sample(&mut self) {
        let st = &mut self.state;
        for (seg, w) in st.segments.windows(2).enumerate() {
            let acc = &mut st.interval.moments[seg];
            for p in &st.particles[w[0] as usize..w[1] as usize] {
                add_velocity(acc, &Vector3::from(p.v));
            }
        }
        st.interval.samples += 1;
        st.counters.samples += 1;
    }
}

/// Layer cell of position y in [0, 1].
#[inline(always)]
fn cell_of(y: f64, cells: usize) -> usize {
    ((y * cells as f64) as usize).min(cells - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mixture() -> DsmcParams {
        DsmcParams {
            knudsen_number: 0.2,
            restitution: 0.8,
            species2_fraction: 0.3,
            mass_ratio: 2.0,
            restitution_12: 0.9,
            cells: 17,
            seed: 4,
            ..DsmcParams::default()
        }
    }

    /// After every step each sorted run holds exactly the simulators of its cell, and the
    /// species counts are kept.
    #[test]
    fn sorted_runs_hold_their_cell_and_species() {
        let mut engine = DsmcEngine::new(mixture()).unwrap();
        for step in 1..=20 {
            engine.advance_to_step(step);
            let st = &engine.state;
            let (cells, species) = (engine.derived.cells, engine.derived.species);
            let mut counts = [0; 2];
            for (seg, w) in st.segments.windows(2).enumerate() {
                for p in &st.particles[w[0] as usize..w[1] as usize] {
                    assert_eq!(cell_of(p.y, cells), seg / species);
                    assert!((0.0..=1.0).contains(&p.y));
                }
                counts[seg % species] += (w[1] - w[0]) as usize;
            }
            assert_eq!(counts, engine.derived.counts);
        }
    }

    /// Without walls and force the collisions conserve momentum to round-off and dissipate
    /// exactly the kinetic energy they report.
    #[test]
    fn periodic_collisions_conserve_momentum_and_account_for_energy() {
        let params = DsmcParams {
            wall_model: WallModel::Periodic,
            forcing: 0.0,
            ..mixture()
        };
        let mut engine = DsmcEngine::new(params).unwrap();
        let (e0, _) = engine.energy_and_momentum();
        let momentum = |engine: &DsmcEngine| {
            let mut p = Vector3::zeros();
            engine.for_each_simulator(|s, _, v| p += engine.derived.masses[s] * Vector3::from(v));
            p
        };
        let p0 = momentum(&engine);
        engine.advance_to_step(200);
        let (e1, _) = engine.energy_and_momentum();
        assert!(
            (momentum(&engine) - p0).norm() < 1e-10,
            "{:?}",
            momentum(&engine) - p0
        );
        assert!(engine.counter_values().collisions > 1000);
        let lost = engine.totals().dissipated;
        assert!(lost > 0.01 * e0);
        assert!((e0 - e1 - lost).abs() < 1e-10 * e0, "{e0} - {e1} vs {lost}");
    }

    /// take_interval reads and resets: consecutive intervals tile the run, and the samples
    /// of an interval are its steps / sample_every.
    #[test]
    fn intervals_tile_the_run() {
        let params = DsmcParams {
            sample_every: 4,
            ..mixture()
        };
        let mut engine = DsmcEngine::new(params).unwrap();
        engine.advance_to_step(10);
        let a = engine.take_interval();
        engine.advance_to_step(30);
        let b = engine.take_interval();
        assert_eq!((a.start_step, a.end_step, a.samples), (0, 10, 2));
        assert_eq!((b.start_step, b.end_step, b.samples), (10, 30, 5));
        assert_eq!(a.kinetic_energy[1], b.kinetic_energy[0]);
        assert!((b.duration - 20.0 * engine.dt()).abs() < 1e-15);
        let samples: f64 = b.moments.iter().map(|m| m[0]).sum();
        assert_eq!(samples, 5.0 * engine.state.particles.len() as f64);
    }
}

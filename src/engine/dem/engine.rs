//! The DEM channel engine: state, the step loop (preparation, then flow), sampling,
//! snapshots, and the canonical checkpoint payload.
//!
//! A step: the initial half step (or it was fused into the previous pass), a list rebuild
//! if a pair's separation may have changed by the skin since the last one, the pair forces, the particle
//! pass (gather, walls, floor, gravity, final half step; fused with the next initial half
//! step when nothing needs the full-step state in between), the wall balances, and every
//! `sample_every` steps a sample. Between calls the state is always at a full step with the
//! forces of that step, which is what a checkpoint holds (in tag order, with the touching
//! pairs' histories by tags): the payload depends on the physical state only, never on the
//! working order, the list or the thread count, and a restored engine continues bitwise.

use super::bodies::{Bodies, BodyState};
use super::bond_order::{self, BondSums};
use super::contact::{self, ContactLaw};
use super::domain::Domain;
use super::forces::{self, Boundaries, Pass, Tally};
use super::neighbours::{KeptContact, NeighbourList};
use super::params::{ContactType, DampingFrom, DemParams, SizeMix, WallDamping};
use super::prepare::{self, Preparation, SETTLE_CHECK_EVERY};
use super::sampling::{self, Bins, IntervalSums};
use crate::engine::{BoxGeometry, Particles};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::time::Instant;

/// Where a run is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Phase {
    /// raining onto the temporary floor
    Preparing(Preparation),
    /// the floor removed, x periodic
    Flowing,
}

/// Counts since the start (preparation included unless said).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DemCounters {
    /// flow steps (after the floor was removed)
    pub steps: u64,
    /// preparation steps
    pub prep_steps: u64,
    /// pair-steps in contact
    pub contacts: u64,
    /// particle-steps touching a wall or the floor
    pub wall_contacts: u64,
    /// neighbour-list rebuilds
    pub rebuilds: u64,
    /// particle-steps (N per step, preparation included): the measure of work
    pub particle_steps: u64,
    /// samples taken
    pub samples: u64,
}

/// Cumulative balances of the flow (since the floor was removed).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Totals {
    /// impulse of the particles on each wall (velocity-Verlet consistent)
    pub wall_impulse: [[f64; 3]; 2],
    /// work of gravity
    pub gravity_work: f64,
    /// kinetic + elastic energy when the flow started
    pub initial_energy: f64,
}

/// The constants of a run that every record carries.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunConstants {
    /// W, B, L
    pub width: f64,
    pub span: f64,
    pub length: f64,
    /// N
    pub particles: u64,
    /// sum of the particle volumes / (L W B): the actual phi-bar
    pub volume_fraction: f64,
    /// M, total mass
    pub total_mass: f64,
    /// g
    pub gravity: [f64; 3],
    /// Delta t
    pub time_step: f64,
    pub sample_every: u64,
    pub size_mix: SizeMix,
    /// k_n, k_t, xi_n, xi_t
    pub normal_stiffness: f64,
    pub tangential_stiffness: f64,
    pub normal_damping: f64,
    pub tangential_damping: f64,
    /// how xi_n was fixed
    pub damping_from: DampingFrom,
    /// mu_p, mu_w
    pub friction: f64,
    pub wall_friction: f64,
    /// e_n and t_c of every pair type and of each size against the wall
    pub contact_types: Vec<ContactType>,
    /// the bins' edges across the channel
    pub bin_edges: Vec<f64>,
    /// two particles are bonded (for Q6) when their centres are closer than this times the
    /// mean of their diameters ([`bond_order::BOND_CUTOFF`])
    pub bond_cutoff: f64,
}

/// What a snapshot's analysis keeps: the run's constants, the interval's sums, and the
/// bond-orientational sums of the state at the snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    pub constants: RunConstants,
    pub sums: IntervalSums,
    /// per bin, the bonds with their midpoint in it and their sums of Y_6m, of the particles
    /// at the snapshot ([`bond_order`]: one evaluation per snapshot, not per sample)
    pub bonds: Vec<BondSums>,
}

impl RunConstants {
    /// The constants of a run of `params` with these particles (radii R, masses m, any
    /// order) and bins.
    pub fn of(params: &DemParams, radius: &[f64], mass: &[f64], bins: &Bins) -> RunConstants {
        let p = params;
        let volume: f64 = radius.iter().map(|r| 4.0 / 3.0 * PI * r * r * r).sum();
        RunConstants {
            width: p.width,
            span: p.span,
            length: p.length,
            particles: radius.len() as u64,
            volume_fraction: volume / (p.length * p.width * p.span),
            total_mass: mass.iter().sum(),
            gravity: p.gravity,
            time_step: p.time_step,
            sample_every: p.sample_every,
            size_mix: p.size_mix,
            normal_stiffness: p.normal_stiffness,
            tangential_stiffness: p.tangential_stiffness(),
            normal_damping: p.normal_damping,
            tangential_damping: p.tangential_damping(),
            damping_from: p.damping_from,
            friction: p.friction,
            wall_friction: p.wall_friction,
            contact_types: p.contact_types(),
            bin_edges: bins.edges.clone(),
            bond_cutoff: bond_order::BOND_CUTOFF,
        }
    }
}

/// A snapshot of the DEM engine: the record and the particles (tag order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub record: Record,
    pub particles: Particles,
}

impl crate::engine::EngineSample for Sample {
    fn particles(&self) -> Option<&Particles> {
        Some(&self.particles)
    }
    fn particles_mut(&mut self) -> Option<&mut Particles> {
        Some(&mut self.particles)
    }
}

/// Version of the checkpoint payload: 1, the postcard bytes of [`Payload`] (the wall damping
/// was then always the pair's, [`WallDamping::PairRate`]); 2, those bytes followed by the
/// wall damping's (it is not in [`DemParams`]' serialised form, so that version 1 decodes).
pub const PAYLOAD_VERSION: u32 = 2;

/// The checkpoint payload: the physical state in canonical form.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Payload {
    params: DemParams,
    phase: Phase,
    step: u64,
    counters: DemCounters,
    bodies: Vec<BodyState>,
    contacts: Vec<KeptContact>,
    interval: IntervalSums,
    totals: Totals,
    last_wall_force: [[f64; 3]; 2],
}

/// The DEM channel engine.
#[derive(Clone, Debug)]
pub struct DemEngine {
    params: DemParams,
    phase: Phase,
    domain: Domain,
    bodies: Bodies,
    list: NeighbourList,
    bins: Bins,
    step: u64,
    counters: DemCounters,
    interval: IntervalSums,
    totals: Totals,
    /// force on each wall at the last force evaluation
    last_wall_force: [[f64; 3]; 2],
    /// scratch of the parallel passes
    tallies: Vec<Tally>,
    /// wall-clock seconds spent per stage (not part of the state)
    timings: StageTimes,
}

/// Wall-clock seconds spent in each stage of the steps since the engine was built or
/// restored (for benchmarks; not part of the state, never in a checkpoint).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// pair forces
    pub pairs: f64,
    /// gather, walls, gravity, kicks and drifts
    pub particles: f64,
    /// neighbour-list rebuilds
    pub rebuilds: f64,
    /// samples of the bin sums
    pub samples: f64,
}

impl DemEngine {
    /// A prepared run: particles rained onto the floor and settled, the floor removed.
    pub fn new(params: DemParams) -> Result<Self, String> {
        let mut engine = Self::unprepared(params)?;
        engine.prepare(u64::MAX)?;
        Ok(engine)
    }

    /// A run whose particles are still on their lattice above the floor.
    pub fn unprepared(params: DemParams) -> Result<Self, String> {
        params
            .validate()
            .map_err(|p| format!("{}: {}", p.key, p.message))?;
        let (states, preparation) = prepare::lattice(&params)?;
        let mut engine = Self::assemble(params, Phase::Preparing(preparation), &states, &[]);
        engine.setup_forces();
        Ok(engine)
    }

    /// A flowing run from a given state (x periodic, no floor), e.g. the state of another
    /// code. The forces are computed as LAMMPS' `setup` does (histories not advanced); the
    /// given forces and torques are ignored. `contacts`: histories of touching pairs by tags
    /// (owner tag first), empty for a fresh state.
    pub fn from_state(
        params: DemParams,
        states: &[BodyState],
        contacts: &[KeptContact],
    ) -> Result<Self, String> {
        params
            .validate_box_and_law()
            .map_err(|p| format!("{}: {}", p.key, p.message))?;
        if states.len() < 2
            || states
                .iter()
                .any(|s| !params.size_mix.has_diameter(s.diameter))
        {
            return Err(format!(
                "a state needs at least 2 particles, each of a diameter of the size mix {:?}",
                params.size_mix.components()
            ));
        }
        let domain = Domain::new(params.length, params.width, params.span, true);
        let mut states = states.to_vec();
        for s in &mut states {
            domain.wrap(&mut s.position);
            s.position_at_build = s.position;
        }
        let mut engine = Self::assemble(params, Phase::Flowing, &states, contacts);
        engine.setup_forces();
        engine.start_flow();
        Ok(engine)
    }

    fn assemble(
        params: DemParams,
        phase: Phase,
        states: &[BodyState],
        contacts: &[KeptContact],
    ) -> Self {
        let domain = Domain::new(
            params.length,
            params.width,
            params.span,
            phase == Phase::Flowing,
        );
        let mut bodies = Bodies::from_states(states, params.time_step);
        let mut list = NeighbourList::default();
        let reach = params.max_diameter() + params.skin;
        list.build(&mut bodies, &domain, reach, params.skin, contacts);
        let bins = Bins::new(params.width);
        DemEngine {
            interval: IntervalSums::start(0, bins.len(), [0.0; 3]),
            params,
            phase,
            domain,
            bodies,
            list,
            bins,
            step: 0,
            counters: DemCounters::default(),
            totals: Totals::default(),
            last_wall_force: [[0.0; 3]; 2],
            tallies: Vec::new(),
            timings: StageTimes::default(),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &DemParams {
        &self.params
    }

    /// The phase.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// N
    pub fn particle_count(&self) -> usize {
        self.bodies.len()
    }

    /// Flow steps done.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// Delta t
    pub fn dt(&self) -> f64 {
        self.params.time_step
    }

    /// Simulated flow time, steps x dt.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.params.time_step
    }

    pub fn counters(&self) -> DemCounters {
        self.counters
    }

    /// Wall-clock seconds per stage since the engine was built or restored.
    pub fn stage_times(&self) -> StageTimes {
        self.timings
    }

    /// Cumulative balances since the flow started.
    pub fn totals(&self) -> Totals {
        self.totals
    }

    /// The running interval's sums (read-only).
    pub fn interval(&self) -> &IntervalSums {
        &self.interval
    }

    /// e_n and t_c of every pair type and of each size against a wall.
    pub fn contact_types(&self) -> Vec<ContactType> {
        self.params.contact_types()
    }

    /// The particles in canonical (tag) order.
    pub fn states(&self) -> Vec<BodyState> {
        self.bodies.states()
    }

    /// The touching pairs' histories by tags, sorted.
    pub fn contacts(&self) -> Vec<KeptContact> {
        self.list.touching(&self.bodies)
    }

    /// The box.
    pub fn domain(&self) -> Domain {
        self.domain
    }

    /// Pairs in the neighbour list.
    pub fn listed_pairs(&self) -> usize {
        self.list.pairs.len()
    }

    fn reach(&self) -> f64 {
        self.params.max_diameter() + self.params.skin
    }

    /// The laws in force: the preparation compacts with `settle_friction`, then freezes with
    /// the run's friction.
    pub fn laws(&self) -> (ContactLaw, Boundaries) {
        let (pair_law, wall_laws, floor) = match &self.phase {
            Phase::Preparing(p) if !p.freezing => {
                let mu = self.params.settle_friction;
                (
                    self.params.law(mu),
                    self.params.wall_laws_with(mu),
                    Some(p.floor),
                )
            }
            Phase::Preparing(p) => (
                self.params.pair_law(),
                self.params.wall_laws(),
                Some(p.floor),
            ),
            Phase::Flowing => (self.params.pair_law(), self.params.wall_laws(), None),
        };
        (
            pair_law,
            Boundaries {
                width: self.params.width,
                wall_laws,
                floor,
                floor_laws: wall_laws,
                gravity: self.params.gravity,
            },
        )
    }

    /// Forces of the current state without advancing any history (LAMMPS' setup).
    fn setup_forces(&mut self) {
        let (law, bounds) = self.laws();
        forces::pair_forces(&law, &self.domain, &self.bodies, &mut self.list, false);
        let tally = forces::particle_pass(
            &law,
            &bounds,
            &self.domain,
            &mut self.bodies,
            &self.list,
            Pass::Setup,
            false,
            &mut self.tallies,
        );
        self.last_wall_force = tally.on_walls;
    }

    /// Reset clocks and balances for the flow at the current state.
    fn start_flow(&mut self) {
        self.step = 0;
        self.totals = Totals {
            initial_energy: {
                let e = self.energies();
                e[0] + e[1] + e[2]
            },
            ..Totals::default()
        };
        self.interval = IntervalSums::start(0, self.bins.len(), self.momentum());
    }

    /// Run the preparation for at most `max_steps` more steps; Ok(true) once the floor is
    /// removed (immediately when the run is already flowing).
    pub fn prepare(&mut self, max_steps: u64) -> Result<bool, String> {
        let mut left = max_steps;
        while let Phase::Preparing(p) = &self.phase {
            if left == 0 {
                return Ok(false);
            }
            if p.steps >= p.max_steps {
                return Err(format!(
                    "the packing did not settle within {} steps ({:.1} time units): kinetic \
                     energy per particle {:.3e} > {:.3e} (lower the stiffness or raise the \
                     damping)",
                    p.max_steps,
                    p.max_steps as f64 * self.params.time_step,
                    p.last_energy,
                    p.threshold
                ));
            }
            let to_check = SETTLE_CHECK_EVERY - p.steps % SETTLE_CHECK_EVERY;
            let n = to_check.min(left);
            self.run_steps(n);
            left -= n;
            let check_now = matches!(
                &self.phase,
                Phase::Preparing(p) if p.steps.is_multiple_of(SETTLE_CHECK_EVERY)
            );
            if check_now {
                let e = self.energies();
                let per_particle = (e[0] + e[1]) / self.bodies.len() as f64;
                let Phase::Preparing(p) = &mut self.phase else {
                    unreachable!("checked above")
                };
                p.last_energy = per_particle;
                if !p.freezing {
                    p.freezing =
                        per_particle < p.compact_threshold || p.steps >= p.compact_max_steps;
                } else if per_particle < p.threshold {
                    self.remove_floor()?;
                }
            }
        }
        Ok(true)
    }

    /// End of the preparation: check that the packing fits in L, remove the floor, make x
    /// periodic, recompute the forces (without the floor, with the run's friction) and start
    /// the flow's clocks.
    fn remove_floor(&mut self) -> Result<(), String> {
        let b = &self.bodies;
        let top = (0..b.len())
            .map(|i| b.x[i][0] - b.radius[i])
            .fold(f64::INFINITY, f64::min);
        let bottom = (0..b.len())
            .map(|i| b.x[i][0] + b.radius[i])
            .fold(f64::NEG_INFINITY, f64::max);
        let height = bottom - top;
        if height > self.params.length {
            return Err(format!(
                "volume_fraction: the settled packing is {height:.3} d_p tall, more than L = {} \
                 (its volume fraction {:.4} is below phi-bar = {}): lower volume_fraction or \
                 settle_friction",
                self.params.length,
                self.params.volume_fraction * self.params.length / height,
                self.params.volume_fraction
            ));
        }
        self.phase = Phase::Flowing;
        self.domain = Domain::new(
            self.params.length,
            self.params.width,
            self.params.span,
            true,
        );
        for x in &mut self.bodies.x {
            self.domain.wrap(x);
        }
        for s in &mut self.bodies.floor_shear {
            *s = [0.0; 3];
        }
        let reach = self.reach();
        self.list
            .rebuild(&mut self.bodies, &self.domain, reach, self.params.skin);
        self.setup_forces();
        self.start_flow();
        Ok(())
    }

    /// Run the flow until `step` flow steps are done (a preparation still going is finished
    /// first). Deterministic: the same parameters reach the same bits, however the run is
    /// split into calls and on any number of threads.
    pub fn advance_to_step(&mut self, step: u64) -> Result<(), String> {
        self.prepare(u64::MAX)?;
        if step > self.step {
            self.run_steps(step - self.step);
        }
        Ok(())
    }

    /// `n` steps of the current phase (a preparation is not ended here).
    fn run_steps(&mut self, n: u64) {
        if n == 0 {
            return;
        }
        let (law, bounds) = self.laws();
        let dt = self.params.time_step;
        let skin2 = self.params.skin * self.params.skin;
        let np = self.bodies.len() as u64;
        let reach = self.reach();
        let mut drifted = forces::kick_drift(
            &self.domain,
            &bounds,
            dt,
            &mut self.bodies,
            &mut self.tallies,
        );
        for left in (0..n).rev() {
            self.add_gravity_work(drifted.gravity_power * dt);
            // rebuild before a pair's separation can have changed by the skin since the last
            // build (a common motion of all particles does not count)
            if drifted.separation_change2() > skin2 {
                let clock = Instant::now();
                self.list
                    .rebuild(&mut self.bodies, &self.domain, reach, self.params.skin);
                self.counters.rebuilds += 1;
                self.timings.rebuilds += clock.elapsed().as_secs_f64();
            }
            let clock = Instant::now();
            let contacts =
                forces::pair_forces(&law, &self.domain, &self.bodies, &mut self.list, true);
            self.timings.pairs += clock.elapsed().as_secs_f64();
            let (flowing, sample) = match &self.phase {
                Phase::Flowing => (
                    true,
                    (self.step + 1).is_multiple_of(self.params.sample_every),
                ),
                Phase::Preparing(_) => (false, false),
            };
            let fuse = left > 0 && !sample;
            let pass = if fuse {
                Pass::FinalAndNext
            } else {
                Pass::Final
            };
            let clock = Instant::now();
            let tally = forces::particle_pass(
                &law,
                &bounds,
                &self.domain,
                &mut self.bodies,
                &self.list,
                pass,
                sample,
                &mut self.tallies,
            );
            self.timings.particles += clock.elapsed().as_secs_f64();
            self.counters.contacts += contacts;
            self.counters.wall_contacts += tally.wall_contacts;
            self.counters.particle_steps += np;
            if flowing {
                self.step += 1;
                self.counters.steps += 1;
                let iv = &mut self.interval;
                for w in 0..2 {
                    for k in 0..3 {
                        let f = tally.on_walls[w][k];
                        iv.wall_force[w][k] += f;
                        let j = 0.5 * dt * (self.last_wall_force[w][k] + f);
                        iv.wall_impulse[w][k] += j;
                        self.totals.wall_impulse[w][k] += j;
                    }
                }
                iv.force_steps += 1;
            } else if let Phase::Preparing(p) = &mut self.phase {
                p.steps += 1;
                self.counters.prep_steps += 1;
            }
            self.last_wall_force = tally.on_walls;
            if sample {
                let clock = Instant::now();
                self.sample(&bounds);
                self.timings.samples += clock.elapsed().as_secs_f64();
            }
            if left == 0 {
                break;
            }
            drifted = if fuse {
                tally
            } else {
                forces::kick_drift(
                    &self.domain,
                    &bounds,
                    dt,
                    &mut self.bodies,
                    &mut self.tallies,
                )
            };
        }
    }

    fn add_gravity_work(&mut self, work: f64) {
        if self.phase == Phase::Flowing {
            self.interval.gravity_work += work;
            self.totals.gravity_work += work;
        }
    }

    /// Add one sample of the full-step state to the interval.
    fn sample(&mut self, bounds: &Boundaries) {
        let b = &self.bodies;
        let iv = &mut self.interval;
        sampling::add_kinetic_sample(iv, &self.bins, &b.mass, &b.radius, &b.x, &b.v, &b.w);
        for i in 0..b.len() {
            // the wall contact of this step
            let wf = b.wall_force[i];
            if wf != [0.0; 3] {
                let (r, v, w) = (b.radius[i], b.v[i], b.w[i]);
                let (wall, del, _) = forces::nearer_wall(b.x[i][1], r, bounds.width);
                for (a, fa) in wf.iter().enumerate() {
                    iv.sampled_wall_force[wall][a] -= fa;
                    for (c, dc) in del.iter().enumerate() {
                        iv.wall_stress[wall][3 * a + c] += fa * dc;
                    }
                }
                let n = [0.0, del[1].signum(), 0.0];
                let vs = sub(v, cross(scale(w, r), n));
                iv.wall_dissipation[wall] -= dot(wf, vs);
            }
        }
        let mut touching = 0.0;
        for (p, &touch) in self.list.touch.iter().enumerate() {
            if !touch {
                continue;
            }
            touching += 1.0;
            let [a, c] = self.list.pairs[p];
            let (a, c) = (a as usize, c as usize);
            let r = self.domain.min_image(sub(b.x[a], b.x[c]));
            let f = self.list.pair_out(p).force;
            let (ba, bc) = (self.bins.of(b.x[a][1]), self.bins.of(b.x[c][1]));
            for (k, fk) in f.iter().enumerate() {
                for (l, rl) in r.iter().enumerate() {
                    let s = 0.5 * fk * rl;
                    iv.bins[ba].contact_stress[3 * k + l] += s;
                    iv.bins[bc].contact_stress[3 * k + l] += s;
                }
            }
            // relative velocity of the contact points: v_a - v_c - (R_a w_a + R_c w_c) x n
            let len = dot(r, r).sqrt();
            let n = scale(r, 1.0 / len);
            let rw = add(scale(b.w[a], b.radius[a]), scale(b.w[c], b.radius[c]));
            let vs = sub(sub(b.v[a], b.v[c]), cross(rw, n));
            let mid = self.bins.of(b.x[c][1] + 0.5 * r[1]);
            iv.bins[mid].dissipation -= dot(f, vs);
            iv.bins[mid].contacts += 1.0;
        }
        iv.contacts += touching;
        iv.samples += 1;
        self.counters.samples += 1;
    }

    /// Total momentum sum m v.
    pub fn momentum(&self) -> [f64; 3] {
        let b = &self.bodies;
        let mut p = [0.0; 3];
        for (m, v) in b.mass.iter().zip(&b.v) {
            for (pk, vk) in p.iter_mut().zip(v) {
                *pk += m * vk;
            }
        }
        p
    }

    /// [translational kinetic, rotational kinetic, elastic] energy: sum m v^2/2, sum I w^2/2,
    /// and k_n delta^2/2 + k_t |s|^2/2 over the touching pairs, walls and floor.
    pub fn energies(&self) -> [f64; 3] {
        let b = &self.bodies;
        let (law, bounds) = self.laws();
        let mut e = [0.0; 3];
        for i in 0..b.len() {
            let (m, r) = (b.mass[i], b.radius[i]);
            e[0] += 0.5 * m * dot(b.v[i], b.v[i]);
            e[1] += 0.5 * (0.4 * m * r * r) * dot(b.w[i], b.w[i]);
            let (_, del, touching) = forces::nearer_wall(b.x[i][1], r, bounds.width);
            if touching {
                e[2] += contact::elastic_energy(
                    bounds.wall_laws.of(r),
                    r - del[1].abs(),
                    &b.wall_shear[i],
                );
            }
            if let Some(floor) = bounds.floor {
                let dx = floor - b.x[i][0];
                if dx * dx <= r * r {
                    e[2] += contact::elastic_energy(
                        bounds.floor_laws.of(r),
                        r - dx.abs(),
                        &b.floor_shear[i],
                    );
                }
            }
        }
        for (p, &touch) in self.list.touch.iter().enumerate() {
            if touch {
                let [a, c] = self.list.pairs[p];
                let (a, c) = (a as usize, c as usize);
                let r = self.domain.min_image(sub(b.x[a], b.x[c]));
                let overlap = b.radius[a] + b.radius[c] - dot(r, r).sqrt();
                e[2] += contact::elastic_energy(&law, overlap.max(0.0), &self.list.shear[p]);
            }
        }
        e
    }

    /// The run's constants.
    pub fn constants(&self) -> RunConstants {
        RunConstants::of(
            &self.params,
            &self.bodies.radius,
            &self.bodies.mass,
            &self.bins,
        )
    }

    /// Read and reset the interval: its sums since the last call (or the start of the flow)
    /// with the run's constants and the particles now, and start a new interval.
    pub fn take_sample(&mut self) -> Sample {
        let momentum = self.momentum();
        let fresh = IntervalSums::start(self.step, self.bins.len(), momentum);
        let mut sums = std::mem::replace(&mut self.interval, fresh);
        sums.end_step = self.step;
        sums.duration = (sums.end_step - sums.start_step) as f64 * self.params.time_step;
        sums.momentum[1] = momentum;
        Sample {
            record: Record {
                constants: self.constants(),
                sums,
                bonds: self.bond_sums(),
            },
            particles: self.particles(),
        }
    }

    /// The bond-orientational sums per bin of the particles now (tag order: a function of
    /// the positions alone).
    pub fn bond_sums(&self) -> Vec<BondSums> {
        let b = &self.bodies;
        bond_order::bond_sums(
            &self.domain,
            &self.bins,
            &b.by_tag(&b.x),
            &b.by_tag(&b.radius),
        )
    }

    /// The particles now, in tag order.
    pub fn particles(&self) -> Particles {
        let b = &self.bodies;
        let e = self.energies();
        let p = &self.params;
        Particles {
            geometry: BoxGeometry {
                length: p.length,
                width: p.width,
                height: p.span,
                walls: true,
            },
            inertia_factor: 0.4,
            gravity: p.gravity[0],
            positions: b.by_tag(&b.x),
            velocities: b.by_tag(&b.v),
            angular_velocities: b.by_tag(&b.w),
            diameters: b.by_tag(&b.radius).iter().map(|r| 2.0 * r).collect(),
            translational_energy: e[0],
            rotational_energy: e[1],
            wall_momentum: self.totals.wall_impulse,
            energy_dissipated: self.totals.gravity_work
                - (e[0] + e[1] + e[2] - self.totals.initial_energy),
            gravity_work: self.totals.gravity_work,
            suppressed_dissipation: 0.0,
        }
    }

    /// The state as postcard bytes of version [`PAYLOAD_VERSION`] (the caller seals them).
    pub fn to_payload(&self) -> Vec<u8> {
        let payload = Payload {
            params: self.params.clone(),
            phase: self.phase.clone(),
            step: self.step,
            counters: self.counters,
            bodies: self.bodies.states(),
            contacts: self.contacts(),
            interval: self.interval.clone(),
            totals: self.totals,
            last_wall_force: self.last_wall_force,
        };
        let mut bytes = postcard::to_stdvec(&payload).expect("DEM state serialises");
        bytes.extend(postcard::to_stdvec(&self.params.wall_damping).expect("a choice serialises"));
        bytes
    }

    /// An engine from [`to_payload`](Self::to_payload) bytes; it continues bitwise as the one
    /// that wrote them.
    pub fn from_payload(bytes: &[u8]) -> Result<Self, String> {
        Self::from_payload_of_version(PAYLOAD_VERSION, bytes)
    }

    /// An engine from payload bytes of a version (1 or [`PAYLOAD_VERSION`]).
    pub fn from_payload_of_version(version: u32, bytes: &[u8]) -> Result<Self, String> {
        let undecodable = |e: postcard::Error| format!("DEM payload does not decode: {e}");
        let (mut p, rest): (Payload, &[u8]) =
            postcard::take_from_bytes(bytes).map_err(undecodable)?;
        let (wall_damping, rest) = match version {
            1 => (WallDamping::PairRate, rest),
            2 => postcard::take_from_bytes(rest).map_err(undecodable)?,
            v => {
                return Err(format!(
                    "DEM payload version {v}, this granflow reads versions 1 to {PAYLOAD_VERSION}"
                ));
            }
        };
        if !rest.is_empty() {
            return Err(format!(
                "DEM payload of version {version} has {} bytes after its end",
                rest.len()
            ));
        }
        p.params.wall_damping = wall_damping;
        p.params
            .validate_box_and_law()
            .map_err(|e| format!("DEM payload: {}: {}", e.key, e.message))?;
        let n = p.bodies.len();
        let bins = Bins::new(p.params.width).len();
        if n < 2
            || p.interval.bins.len() != bins
            || p.contacts.iter().any(|c| c.0 >= c.1 || c.1 as usize >= n)
        {
            return Err(format!(
                "DEM payload is inconsistent ({n} particles, {} bins of {bins}, contacts by tags \
                 below N)",
                p.interval.bins.len()
            ));
        }
        let mut engine = Self::assemble(p.params, p.phase, &p.bodies, &p.contacts);
        engine.step = p.step;
        engine.counters = p.counters;
        engine.interval = p.interval;
        engine.totals = p.totals;
        engine.last_wall_force = p.last_wall_force;
        Ok(engine)
    }
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

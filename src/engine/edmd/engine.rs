//! The event-driven engine: one scheduled event per particle (validated by collision
//! counters), a calendar queue, cell lists, and per-particle local times (delayed update,
//! Lubachevsky 1991): a particle's state is only brought forward when one of its own events
//! is processed.

use super::EdmdParams;
use super::cells::{AxisCells, CellGrid, Neighbourhood};
use super::checkpoint::{self, EngineState};
use super::collision::{self, ContactLaw, SphereVelocity};
use super::motion::{fly, linear_exit_time_within, pair_contact_time_within, parabolic_exit_time};
use super::neighbours::{Image, Neighbour, NeighbourLists};
use super::queue::{CalendarQueue, EventQueue};
use super::search::{PartnerBatch, prefetch};
use super::setup;
use crate::engine::{Counters, Engine, EngineError, Progress, Snapshot, StopAt};
use nalgebra::Vector3;

mod list_search;
pub use list_search::NeighbourSearch;

/// Cell side is at least d times this factor (> 1 so that round-off at cell faces never hides
/// a partner).
const CELL_MARGIN: f64 = 1.0 + 1e-9;

/// The engine rebuilds its cells, events and calendar every this many events per particle
/// (at event counts that are multiples of it: deterministic points of the run), so that the
/// grid follows the mean flow and the calendar follows the event rate.
const REBUILD_EVENTS_PER_PARTICLE: u64 = 50;

/// Kinematic state of one particle at its own local time: the data read when other particles
/// look for collision partners, packed into one 64-byte cache line.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(64))]
pub(crate) struct Kinematics {
    /// r, centre at `time`
    pub position: [f64; 3],
    /// c, velocity at `time`
    pub velocity: [f64; 3],
    /// local time of this state
    pub time: f64,
    /// number of velocity changes (collisions) since the last rebuild; validates events
    pub collisions: u32,
}

/// What a particle's scheduled event is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EventKind {
    /// nothing can happen (at rest without gravity)
    None,
    /// collision with `partner`, valid while the partner's collision counter still equals
    /// `partner_collisions`
    Pair {
        partner: u32,
        partner_collisions: u32,
    },
    /// leaves its cell along `axis` through the upper (true) or lower face
    Cross { axis: u8, upper: bool },
    /// hits the wall at y = W (true) or y = 0
    Wall { upper: bool },
    /// may have moved skin/2 from its neighbour list's centre: renews the list (list search)
    Renew,
}

/// The earliest pair collision found by a particle's last full neighbour search (kept while
/// the particle only crosses cells, so that a crossing needs to search only the new cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PairCandidate {
    /// absolute time of the contact (infinite: none)
    pub time: f64,
    /// partner, or NO_PARTNER
    pub partner: u32,
    /// partner's collision counter when the candidate was found
    pub partner_collisions: u32,
}

const NO_PARTNER: u32 = u32::MAX;

impl PairCandidate {
    const NONE: PairCandidate = PairCandidate {
        time: f64::INFINITY,
        partner: NO_PARTNER,
        partner_collisions: 0,
    };
}

/// What a particle will do next and the best pair found by its last full neighbour search.
#[derive(Clone, Copy, Debug)]
struct Plan {
    /// the scheduled event
    event: EventKind,
    /// earliest pair collision of the last full neighbour search (kept while the particle
    /// only crosses cells)
    candidate: PairCandidate,
}

impl Plan {
    const NONE: Plan = Plan {
        event: EventKind::None,
        candidate: PairCandidate::NONE,
    };
}

/// A physical event as processed (for tests that compare engines event by event).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhysicalEvent {
    Pair {
        time: f64,
        first: u32,
        second: u32,
    },
    Wall {
        time: f64,
        particle: u32,
        upper: bool,
    },
}

/// Event-driven engine for rough inelastic hard spheres.
pub struct EdmdEngine {
    params: EdmdParams,
    /// particle-particle contact law (e, beta, K)
    pair_law: ContactLaw,
    /// particle-wall contact law (e_w, beta_w, K)
    wall_law: ContactLaw,
    /// current simulated time (time of the last event, or of the last stop)
    now: f64,
    kin: Vec<Kinematics>,
    /// particle id of each storage slot (slots are re-sorted by cell at every rebuild)
    ids: Vec<u32>,
    /// w, angular velocities (constant between collisions)
    angular: Vec<[f64; 3]>,
    /// time of each particle's last collision (pair or wall), for the TC model
    last_collision: Vec<f64>,
    /// scheduled event and pair candidate of each particle (one record: one cache miss)
    plan: Vec<Plan>,
    queue: CalendarQueue,
    /// how partners are found: cell lists, or neighbour lists (then the cells hold anchors)
    search: NeighbourSearch,
    /// symmetric neighbour lists (list search only)
    lists: NeighbourLists,
    /// centre of each particle's neighbour list, in the grid frame (list search only)
    anchors: Vec<[f64; 3]>,
    /// neighbours found by a list renewal (reused: no allocation per event)
    scratch: Vec<Neighbour>,
    /// shift vector of each periodic image (box lengths along the periodic axes)
    image_shifts: [[f64; 3]; Image::COUNT],
    cells: CellGrid,
    /// U, velocity along x of the cell grid: the grid drifts with the mean flow so that the
    /// fast flow of a channel does not turn into a stream of cell crossings. A particle's
    /// grid-frame coordinate is xi = x - U (t - t_grid).
    grid_drift: f64,
    /// t_grid, time at which the drifting grid frame coincides with the box frame
    grid_epoch: f64,
    /// event count of the next periodic rebuild
    next_rebuild: u64,
    counters: Counters,
    /// cumulative impulse delivered to the wall at y = 0 and at y = W
    wall_momentum: [[f64; 3]; 2],
    /// cumulative kinetic energy dissipated in collisions
    dissipated: f64,
    /// cumulative work of gravity, m g sum of x-displacements
    gravity_work: f64,
    /// true directly after a snapshot: the state is synchronised and a checkpoint is valid
    synchronised: bool,
    /// physical events, when recording is switched on (tests)
    log: Option<Vec<PhysicalEvent>>,
}

impl EdmdEngine {
    /// A fresh run: place spheres, draw velocities, schedule all events. The neighbour search
    /// is chosen from the parameters ([`NeighbourSearch::automatic`]).
    pub fn new(params: EdmdParams) -> Result<Self, EngineError> {
        let search = NeighbourSearch::automatic(&params);
        Self::with_search(params, search)
    }

    /// A fresh run with the given neighbour search (for tests and benchmarks).
    pub fn with_search(params: EdmdParams, search: NeighbourSearch) -> Result<Self, EngineError> {
        params.validate()?;
        search.validate()?;
        let start = setup::initial_state(&params)?;
        let n = params.particles;
        let state = EngineState {
            params,
            now: 0.0,
            positions: start.positions,
            velocities: start.velocities,
            angular_velocities: start.angular_velocities,
            last_collision: vec![f64::NEG_INFINITY; n],
            counters: Counters::default(),
            wall_momentum: [[0.0; 3]; 2],
            dissipated: 0.0,
            gravity_work: 0.0,
        };
        Ok(Self::from_state(state, search))
    }

    /// Rebuild an engine from checkpoint bytes (see [`checkpoint`]).
    pub fn restore(bytes: &[u8]) -> Result<Self, EngineError> {
        let state = checkpoint::decode(bytes)?;
        state.params.validate()?;
        let search = NeighbourSearch::automatic(&state.params);
        Ok(Self::from_state(state, search))
    }

    /// As [`EdmdEngine::restore`], with the given neighbour search (for tests).
    pub fn restore_with_search(bytes: &[u8], search: NeighbourSearch) -> Result<Self, EngineError> {
        let state = checkpoint::decode(bytes)?;
        state.params.validate()?;
        search.validate()?;
        Ok(Self::from_state(state, search))
    }

    fn from_state(state: EngineState, search: NeighbourSearch) -> Self {
        let p = &state.params;
        let g = p.geometry;
        let n = p.particles;
        let side = CELL_MARGIN * search.reach();
        let axes = [
            AxisCells::new(0.0, g.length, g.length, true, side),
            if g.walls {
                AxisCells::new(
                    collision::RADIUS,
                    g.width - 2.0 * collision::RADIUS,
                    g.width,
                    false,
                    side,
                )
            } else {
                AxisCells::new(0.0, g.width, g.width, true, side)
            },
            AxisCells::new(0.0, g.height, g.height, true, side),
        ];
        let ext = g.extents();
        let periodic = [true, !g.walls, true];
        let image_shifts = std::array::from_fn(|index| {
            let k = Image::from_index(index).offsets();
            std::array::from_fn(|a| {
                if periodic[a] {
                    k[a] as f64 * ext[a]
                } else {
                    0.0
                }
            })
        });
        let kin = (0..n)
            .map(|i| Kinematics {
                position: state.positions[i],
                velocity: state.velocities[i],
                time: state.now,
                collisions: 0,
            })
            .collect();
        let mut engine = EdmdEngine {
            pair_law: ContactLaw {
                restitution: p.restitution,
                roughness: p.roughness,
                inertia_factor: p.inertia_factor,
            },
            wall_law: ContactLaw {
                restitution: p.wall_restitution,
                roughness: p.wall_roughness,
                inertia_factor: p.inertia_factor,
            },
            now: state.now,
            kin,
            ids: (0..n as u32).collect(),
            angular: state.angular_velocities,
            last_collision: state.last_collision,
            plan: vec![Plan::NONE; n],
            queue: CalendarQueue::new(n, 1, 1.0, state.now),
            search,
            lists: NeighbourLists::new(match search {
                NeighbourSearch::Cells => 0,
                NeighbourSearch::Lists { .. } => n,
            }),
            anchors: Vec::new(),
            scratch: Vec::new(),
            image_shifts,
            cells: CellGrid::new(axes, n),
            grid_drift: 0.0,
            grid_epoch: state.now,
            next_rebuild: 0,
            counters: state.counters,
            wall_momentum: state.wall_momentum,
            dissipated: state.dissipated,
            gravity_work: state.gravity_work,
            synchronised: true,
            log: None,
            params: state.params,
        };
        engine.rebuild();
        engine
    }

    /// Record every physical event from now on (for tests; costs memory).
    pub fn record_events(&mut self) {
        self.log = Some(Vec::new());
    }

    /// The physical events recorded so far.
    pub fn recorded_events(&self) -> &[PhysicalEvent] {
        self.log.as_deref().unwrap_or(&[])
    }

    /// The parameters of this run.
    pub fn params(&self) -> &EdmdParams {
        &self.params
    }

    /// Bytes of memory per particle held by the engine's data structures.
    pub fn bytes_per_particle(&self) -> f64 {
        let n = self.kin.len().max(1);
        let per = std::mem::size_of::<Kinematics>()
            + std::mem::size_of::<[f64; 3]>()
            + std::mem::size_of::<f64>()
            + std::mem::size_of::<Plan>()
            + std::mem::size_of::<u32>()
            + self.queue.bytes_per_particle();
        let lists = self.lists.bytes() + std::mem::size_of_val(self.anchors.as_slice());
        (per * n + self.cells.bytes() + lists) as f64 / n as f64
    }

    /// Bring every particle to the current time, wrap positions into the box, set the grid
    /// drift to the mean flow, re-sort the cells and re-predict all events from scratch.
    /// Deterministic in the state alone, so a run restored from a checkpoint continues exactly
    /// like the run that wrote it.
    fn rebuild(&mut self) {
        let n = self.kin.len();
        let ext = self.params.geometry.extents();
        for i in 0..n {
            self.advance_particle(i, self.now);
            self.kin[i].collisions = 0;
            for a in 0..3 {
                if a == 1 && self.params.geometry.walls {
                    continue;
                }
                let x = &mut self.kin[i].position[a];
                if !(0.0..ext[a]).contains(x) {
                    *x = x.rem_euclid(ext[a]);
                    if *x >= ext[a] {
                        *x = 0.0; // -tiny rounds to L
                    }
                }
            }
        }
        // store particles in cell order (ties by particle id, so the order depends on the
        // state alone): the partners a search reads then sit close together in memory
        let axes = self.cells.axes;
        self.cells = CellGrid::new(axes, n);
        let cell_of: Vec<usize> = (0..n)
            .map(|s| self.cells.index(self.cells.locate(self.kin[s].position)))
            .collect();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_unstable_by_key(|&s| (cell_of[s], self.ids[s]));
        self.kin = order.iter().map(|&s| self.kin[s]).collect();
        self.angular = order.iter().map(|&s| self.angular[s]).collect();
        self.last_collision = order.iter().map(|&s| self.last_collision[s]).collect();
        self.ids = order.iter().map(|&s| self.ids[s]).collect();
        // inserted last to first, so that each cell lists its particles in storage order
        for (slot, &s) in order.iter().enumerate().rev() {
            self.cells.insert(slot as u32, cell_of[s]);
        }
        if self.uses_lists() {
            self.build_all_lists();
        }
        // the grid drifts with the mean flow along gravity (U = <c_x>); none without gravity
        self.grid_epoch = self.now;
        self.grid_drift = if self.params.gravity > 0.0 {
            self.kin.iter().map(|k| k.velocity[0]).sum::<f64>() / n as f64
        } else {
            0.0
        };
        let period = REBUILD_EVENTS_PER_PARTICLE * n as u64;
        self.next_rebuild = (self.counters.events / period + 1) * period;
        // predict every particle's next event, then size the calendar from their spread:
        // about four events per bucket near `now`, a year of buckets spanning ~4 mean times
        let times: Vec<f64> = (0..n).map(|i| self.predict(i)).collect();
        let finite: Vec<f64> = times
            .iter()
            .filter(|t| t.is_finite())
            .map(|t| t - self.now)
            .collect();
        let mean = if finite.is_empty() {
            1.0
        } else {
            finite.iter().sum::<f64>() / finite.len() as f64
        };
        let width = (4.0 * mean / n as f64).max(1e-12);
        self.queue = CalendarQueue::new(n, n.max(16), width, self.now);
        for (i, &t) in times.iter().enumerate() {
            if t.is_finite() {
                self.queue.schedule(i as u32, t);
            }
        }
    }

    /// Free flight of particle `i` from its local time to `t` (gravity g along +x).
    #[inline(always)]
    fn advance_particle(&mut self, i: usize, t: f64) {
        let k = &mut self.kin[i];
        let dt = t - k.time;
        if dt != 0.0 {
            let g = self.params.gravity;
            let (r, c) = fly(k.position, k.velocity, g, dt);
            self.gravity_work += g * (r[0] - k.position[0]);
            k.position = r;
            k.velocity = c;
            k.time = t;
        }
    }

    /// Earliest event of particle `i` (whose state is at `now`) after a full search: leaving its
    /// cell, hitting a wall, or colliding with a sphere in its own or an adjacent cell. Stores
    /// the earliest pair collision as the particle's candidate (whatever its time) and the
    /// earliest event as its event; returns the event time (infinite when nothing can happen).
    fn predict(&mut self, i: usize) -> f64 {
        if self.uses_lists() {
            return self.predict_from_list(i);
        }
        let around = self.cells.around(self.cells.cell_of(i as u32));
        self.plan[i].candidate = self.scan_cells(i, &around, f64::INFINITY);
        self.choose_event(i)
    }

    /// Event of particle `i` right after it crossed into a new cell along `axis`: its velocity
    /// is unchanged, so the pair candidate of its last full search still holds if the partner
    /// has not collided since; only the layer of cells that just became adjacent is searched.
    fn predict_after_crossing(&mut self, i: usize, axis: usize, upper: bool) -> f64 {
        let candidate = self.plan[i].candidate;
        let still_valid = match candidate.partner {
            NO_PARTNER => true,
            j => self.kin[j as usize].collisions == candidate.partner_collisions,
        };
        if !still_valid {
            return self.predict(i);
        }
        let entered = self
            .cells
            .entered(self.cells.cell_of(i as u32), axis, upper);
        let found = self.scan_cells(i, &entered, candidate.time);
        if found.time < candidate.time {
            self.plan[i].candidate = found;
        }
        self.choose_event(i)
    }

    /// The earlier of particle `i`'s cell exit (or wall hit) and its pair candidate: stored as
    /// its event, time returned.
    fn choose_event(&mut self, i: usize) -> f64 {
        let (exit_time, exit_kind) = self.exit_event(i);
        let candidate = self.plan[i].candidate;
        let pair = EventKind::Pair {
            partner: candidate.partner,
            partner_collisions: candidate.partner_collisions,
        };
        // a collision or a crossing is a coin flip: chosen by selects, not a branch
        let collides = (candidate.time <= exit_time) & (candidate.partner != NO_PARTNER);
        self.plan[i].event = if collides { pair } else { exit_kind };
        if collides { candidate.time } else { exit_time }
    }

    /// When and how particle `i` (at `now`) leaves its cell; the outer faces of the edge cells
    /// along a wall axis are the walls. Along x the faces move with the drifting grid.
    fn exit_event(&self, i: usize) -> (f64, EventKind) {
        let me = &self.kin[i];
        let g = self.params.gravity;
        let coords = self.cells.coords(self.cells.cell_of(i as u32));
        let axes = &self.cells.axes;
        // the earliest face, chosen by selects (which one it is is random): first axis on ties
        let (mut best, mut axis, mut upper) = (f64::INFINITY, 0, false);
        for a in 0..3 {
            let (lo, hi) = axes[a].faces(coords[a]);
            let (dt, up) = if a == 0 && g > 0.0 {
                // in the drifting grid frame: xi = x - U (t - t_grid), velocity c_x - U
                parabolic_exit_time(
                    me.position[0] - self.grid_drift * (self.now - self.grid_epoch),
                    me.velocity[0] - self.grid_drift,
                    g,
                    lo,
                    hi,
                )
            } else {
                linear_exit_time_within(me.position[a], me.velocity[a], lo, hi)
            };
            let earlier = dt < best;
            best = if earlier { dt } else { best };
            axis = if earlier { a } else { axis };
            upper = if earlier { up } else { upper };
        }
        if best == f64::INFINITY {
            return (f64::INFINITY, EventKind::None);
        }
        let at_wall = !axes[axis].periodic
            && if upper {
                coords[axis] + 1 == axes[axis].count
            } else {
                coords[axis] == 0
            };
        let kind = if at_wall {
            EventKind::Wall { upper }
        } else {
            EventKind::Cross {
                axis: axis as u8,
                upper,
            }
        };
        (self.now + best, kind)
    }

    /// Earliest collision of particle `i` (at `now`) before `horizon` with a sphere in the
    /// cells of `hood`.
    ///
    /// Memory latency is what limits this search, so it runs in three passes whose loads do
    /// not wait on each other: prefetch the cells' heads; read them and prefetch each first
    /// member's record and link; walk the lists, collecting partners in batches (prefetching
    /// later members' records) and testing each full batch.
    fn scan_cells(&self, i: usize, hood: &Neighbourhood, horizon: f64) -> PairCandidate {
        let mut best = PairCandidate::NONE;
        let mut best_dt = horizon - self.now;
        let mut batch = PartnerBatch::new();
        self.cells.walk(
            hood,
            |first| prefetch(&self.kin[first as usize]),
            |j, image| {
                if j as usize == i {
                    return;
                }
                prefetch(&self.kin[j as usize]);
                if batch.push(j, image) {
                    self.earliest_among(i, batch.partners(), &mut best, &mut best_dt);
                    batch.clear();
                }
            },
        );
        self.earliest_among(i, batch.partners(), &mut best, &mut best_dt);
        best
    }

    /// Update `best` (contact before `now + best_dt`) with the given partners of particle `i`,
    /// each in its periodic image.
    #[inline(always)]
    fn earliest_among(
        &self,
        i: usize,
        partners: impl Iterator<Item = (u32, Image)>,
        best: &mut PairCandidate,
        best_dt: &mut f64,
    ) {
        let me = &self.kin[i];
        let g = self.params.gravity;
        for (j, image) in partners {
            let other = &self.kin[j as usize];
            let shift = &self.image_shifts[image.index()];
            // partner brought to `now` on the fly (its stored state is not touched)
            let (rj, cj) = fly(other.position, other.velocity, g, self.now - other.time);
            let r = [
                me.position[0] - (rj[0] + shift[0]),
                me.position[1] - (rj[1] + shift[1]),
                me.position[2] - (rj[2] + shift[2]),
            ];
            let v = [
                me.velocity[0] - cj[0],
                me.velocity[1] - cj[1],
                me.velocity[2] - cj[2],
            ];
            let dt = pair_contact_time_within(r, v, *best_dt);
            if dt < *best_dt {
                *best_dt = dt;
                *best = PairCandidate {
                    time: self.now + dt,
                    partner: j,
                    partner_collisions: other.collisions,
                };
            }
        }
    }

    /// True with neighbour-list search (else cells).
    #[inline(always)]
    fn uses_lists(&self) -> bool {
        matches!(self.search, NeighbourSearch::Lists { .. })
    }

    /// Predict and schedule the next event of particle `i`.
    #[inline]
    fn reschedule(&mut self, i: usize) {
        let t = self.predict(i);
        self.schedule(i, t);
    }

    #[inline]
    fn schedule(&mut self, i: usize, t: f64) {
        if t.is_finite() {
            self.queue.schedule(i as u32, t);
        } else {
            self.queue.cancel(i as u32);
        }
    }

    /// Process the earliest event. Returns false when no event is left.
    fn step(&mut self) -> bool {
        let Some((t, id)) = self.queue.pop() else {
            return false;
        };
        let i = id as usize;
        // the following event is most likely the queue's next one: start loading its records
        // now, so that they are in cache when it is processed
        if let Some((_, next)) = self.queue.peek() {
            let next = next as usize;
            prefetch(&self.kin[next]);
            prefetch(&self.plan[next]);
            prefetch(&self.angular[next]);
            if self.uses_lists() {
                prefetch(self.lists.head(next));
            }
        }
        self.now = t;
        self.counters.events += 1;
        if self.counters.events == self.next_rebuild {
            // the popped event is re-predicted by the rebuild, together with all others
            self.rebuild();
            return true;
        }
        self.synchronised = false;
        self.advance_particle(i, t);
        match self.plan[i].event {
            EventKind::Pair {
                partner,
                partner_collisions,
            } => {
                let j = partner as usize;
                if self.kin[j].collisions == partner_collisions {
                    self.advance_particle(j, t);
                    self.collide_pair(i, j);
                    self.reschedule(i);
                    self.reschedule(j);
                } else {
                    self.reschedule(i);
                }
            }
            EventKind::Cross { axis, upper } => {
                self.cross_cell(i, axis as usize, upper);
                let t = self.predict_after_crossing(i, axis as usize, upper);
                self.schedule(i, t);
            }
            EventKind::Wall { upper } => {
                self.collide_wall(i, upper);
                self.reschedule(i);
            }
            EventKind::Renew => {
                self.renew_list(i);
                self.reschedule(i);
            }
            EventKind::None => unreachable!("a particle without event was scheduled"),
        }
        self.prefetch_partner_of_next_event();
        true
    }

    /// The next event's own records were prefetched when this step began; by now its plan (and
    /// neighbour list) has arrived, so what they name can be loaded too: the partner of a
    /// collision (its counter and velocities are read at once, its list next) and the
    /// neighbours that the particle's next prediction will test.
    #[inline(always)]
    fn prefetch_partner_of_next_event(&mut self) {
        if let Some((_, next)) = self.queue.peek() {
            let next = next as usize;
            if let EventKind::Pair { partner, .. } = self.plan[next].event {
                let j = partner as usize;
                prefetch(&self.kin[j]);
                prefetch(&self.angular[j]);
                if self.uses_lists() {
                    prefetch(self.lists.head(j));
                }
            }
            if self.uses_lists() {
                for entry in self.lists.of(next) {
                    prefetch(&self.kin[entry.slot() as usize]);
                }
            }
        }
    }

    /// Move particle `i` into the next cell along `axis`, wrapping across the periodic seam.
    fn cross_cell(&mut self, i: usize, axis: usize, upper: bool) {
        self.counters.cell_crossings += 1;
        let cell = self.cells.cell_of(i as u32);
        let mut coords = self.cells.coords(cell);
        let ax = self.cells.axes[axis];
        let (next, shift) = ax
            .neighbour(coords[axis], if upper { 1 } else { -1 })
            .expect("crossing stays in the box");
        // a wrapped neighbour carries the shift that brings it next to the old cell; the
        // particle itself moves the opposite way
        self.kin[i].position[axis] -= shift;
        coords[axis] = next;
        let flat = self.cells.index(coords);
        self.cells.relocate(i as u32, flat);
    }

    /// Minimum-image separation r_i - r_j of two particles at the same time.
    fn separation(&self, i: usize, j: usize) -> Vector3<f64> {
        let g = &self.params.geometry;
        let ext = g.extents();
        let mut r = [0.0; 3];
        for a in 0..3 {
            let mut d = self.kin[i].position[a] - self.kin[j].position[a];
            if a != 1 || !g.walls {
                if d > 0.5 * ext[a] {
                    d -= ext[a];
                } else if d < -0.5 * ext[a] {
                    d += ext[a];
                }
            }
            r[a] = d;
        }
        Vector3::from(r)
    }

    /// Pair collision of i and j (both at `now`), with the TC model.
    fn collide_pair(&mut self, i: usize, j: usize) {
        let t = self.now;
        let r = self.separation(i, j);
        let k = -r / r.norm(); // unit vector from i to j
        let tc = self.params.tc;
        let tc_elastic =
            tc > 0.0 && (t - self.last_collision[i] < tc || t - self.last_collision[j] < tc);
        let law = if tc_elastic {
            self.counters.tc_elastic_collisions += 1;
            ContactLaw {
                restitution: 1.0,
                ..self.pair_law
            }
        } else {
            self.pair_law
        };
        let first = SphereVelocity {
            linear: self.kin[i].velocity.into(),
            angular: self.angular[i].into(),
        };
        let second = SphereVelocity {
            linear: self.kin[j].velocity.into(),
            angular: self.angular[j].into(),
        };
        let out = collision::pair_collision(&first, &second, &k, &law);
        self.kin[i].velocity = out.first.linear.into();
        self.kin[j].velocity = out.second.linear.into();
        self.angular[i] = out.first.angular.into();
        self.angular[j] = out.second.angular.into();
        self.kin[i].collisions += 1;
        self.kin[j].collisions += 1;
        self.last_collision[i] = t;
        self.last_collision[j] = t;
        self.dissipated += out.dissipated;
        self.counters.pair_collisions += 1;
        if let Some(log) = &mut self.log {
            let (a, b) = (self.ids[i], self.ids[j]);
            log.push(PhysicalEvent::Pair {
                time: t,
                first: a.min(b),
                second: a.max(b),
            });
        }
    }

    /// Collision of particle i with the wall at y = W (upper) or y = 0.
    fn collide_wall(&mut self, i: usize, upper: bool) {
        let w = self.params.geometry.width;
        // at contact the centre is a from the wall; round-off never lets it sink in
        let y = &mut self.kin[i].position[1];
        *y = if upper {
            y.min(w - collision::RADIUS)
        } else {
            y.max(collision::RADIUS)
        };
        let k = Vector3::new(0.0, if upper { 1.0 } else { -1.0 }, 0.0);
        let sphere = SphereVelocity {
            linear: self.kin[i].velocity.into(),
            angular: self.angular[i].into(),
        };
        let out = collision::wall_collision(&sphere, &k, &self.wall_law);
        self.kin[i].velocity = out.sphere.linear.into();
        self.angular[i] = out.sphere.angular.into();
        self.kin[i].collisions += 1;
        self.last_collision[i] = self.now;
        let side = &mut self.wall_momentum[upper as usize];
        for a in 0..3 {
            side[a] += out.impulse[a];
        }
        self.dissipated += out.dissipated;
        self.counters.wall_collisions += 1;
        if let Some(log) = &mut self.log {
            log.push(PhysicalEvent::Wall {
                time: self.now,
                particle: self.ids[i],
                upper,
            });
        }
    }

    /// Stall check: a window of 100 events per particle that covers less simulated time than
    /// the TC time t_c (or 1e-9 without the TC model) means inelastic collapse.
    fn stall_check(&self, window_start_time: f64) -> Result<(), EngineError> {
        let span = self.now - window_start_time;
        let floor = if self.params.tc > 0.0 {
            self.params.tc
        } else {
            1e-9
        };
        if span < floor {
            return Err(EngineError::Stalled(format!(
                "{} events ({} per particle) advanced simulated time by only {span:.3e} at t = {:.6} \
                 (collisions per particle {:.1}): inelastic collapse. The TC model time is tc = {:e}; \
                 increase tc (e.g. to {:e}) or raise the restitution",
                self.stall_window(),
                self.stall_window() / self.kin.len() as u64,
                self.now,
                self.collisions_per_particle(),
                self.params.tc,
                if self.params.tc > 0.0 {
                    self.params.tc * 10.0
                } else {
                    1e-4
                },
            )));
        }
        Ok(())
    }

    fn stall_window(&self) -> u64 {
        100 * self.kin.len() as u64
    }

    fn collisions_per_particle(&self) -> f64 {
        2.0 * self.counters.pair_collisions as f64 / self.kin.len() as f64
    }

    /// Per-slot data rearranged by particle id (the order of snapshots and checkpoints).
    fn by_id<T: Copy + Default>(&self, per_slot: &[T]) -> Vec<T> {
        let mut out = vec![T::default(); per_slot.len()];
        for (slot, &id) in self.ids.iter().enumerate() {
            out[id as usize] = per_slot[slot];
        }
        out
    }

    /// Current state as plain data (particles at their local times brought to `now`).
    fn state(&self) -> EngineState {
        let g = self.params.gravity;
        let (positions, velocities) = self
            .by_id(&self.kin)
            .into_iter()
            .map(|k| fly(k.position, k.velocity, g, self.now - k.time))
            .unzip();
        EngineState {
            params: self.params.clone(),
            now: self.now,
            positions,
            velocities,
            angular_velocities: self.by_id(&self.angular),
            last_collision: self.by_id(&self.last_collision),
            counters: self.counters,
            wall_momentum: self.wall_momentum,
            dissipated: self.dissipated,
            gravity_work: self.gravity_work,
        }
    }
}

impl Engine for EdmdEngine {
    fn particle_count(&self) -> usize {
        self.kin.len()
    }

    fn progress(&self) -> Progress {
        Progress {
            time: self.now,
            collisions_per_particle: self.collisions_per_particle(),
            events: self.counters.events,
        }
    }

    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        let window = self.stall_window();
        let mut window_end = self.counters.events + window;
        let mut window_start_time = self.now;
        match stop {
            StopAt::CollisionsPerParticle(target) => {
                let target_pairs = (target * self.kin.len() as f64 / 2.0).ceil() as u64;
                while self.counters.pair_collisions < target_pairs {
                    if !self.step() {
                        break;
                    }
                    if self.counters.events >= window_end {
                        self.stall_check(window_start_time)?;
                        window_end += window;
                        window_start_time = self.now;
                    }
                }
            }
            StopAt::Time(t_stop) => {
                while let Some((t, _)) = self.queue.peek() {
                    if t > t_stop {
                        break;
                    }
                    self.step();
                    if self.counters.events >= window_end {
                        self.stall_check(window_start_time)?;
                        window_end += window;
                        window_start_time = self.now;
                    }
                }
                if t_stop > self.now {
                    self.now = t_stop;
                    self.synchronised = false;
                }
            }
        }
        Ok(())
    }

    fn snapshot(&mut self) -> Snapshot {
        self.rebuild();
        self.synchronised = true;
        let k_over_4 = self.params.inertia_factor / 4.0; // I = K m d^2 / 4
        let translational_energy = self
            .kin
            .iter()
            .map(|k| 0.5 * dot(k.velocity, k.velocity))
            .sum();
        let rotational_energy = self
            .angular
            .iter()
            .map(|w| 0.5 * k_over_4 * dot(*w, *w))
            .sum();
        let kinematics = self.by_id(&self.kin);
        Snapshot {
            time: self.now,
            collisions_per_particle: self.collisions_per_particle(),
            geometry: self.params.geometry,
            inertia_factor: self.params.inertia_factor,
            gravity: self.params.gravity,
            positions: kinematics.iter().map(|k| k.position).collect(),
            velocities: kinematics.iter().map(|k| k.velocity).collect(),
            angular_velocities: self.by_id(&self.angular),
            counters: self.counters,
            translational_energy,
            rotational_energy,
            wall_momentum: self.wall_momentum,
            energy_dissipated: self.dissipated,
            gravity_work: self.gravity_work,
        }
    }

    fn checkpoint(&self) -> Vec<u8> {
        assert!(
            self.synchronised,
            "a checkpoint is only taken directly after a snapshot"
        );
        checkpoint::encode(&self.state())
    }
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

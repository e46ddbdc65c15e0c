//! The event-driven engine: one scheduled event per particle (validated by collision
//! counters), a tournament tree of events, cell lists, and per-particle local times (delayed
//! update, Lubachevsky 1991): a particle's state is only brought forward when one of its own
//! events is processed.

use super::EdmdParams;
use super::cells::{AxisCells, CellGrid, Neighbourhood};
use super::checkpoint::{self, EdmdCounters, EngineState};
use super::collision::{self, ContactLaw, SphereVelocity};
use super::huge::HugeArray;
use super::images::ImageShifts;
use super::motion::{fly, linear_exit_time_within, parabolic_exit_time};
use super::neighbours::{Image, Neighbour, NeighbourLists};
use super::queue::{EngineQueue, EventQueue};
use super::search_policy::SearchPolicy;
use super::setup;
use crate::engine::prefetch::prefetch_at;
use crate::engine::{
    Content, Engine, EngineDef, EngineError, Particles, Progress, Snapshot, StopAt,
};
use nalgebra::Vector3;

mod boundary;
mod cell_search;
mod collide;
mod event_loop;
mod lanes;
mod list_search;
mod rebuild;
mod stall;

pub use list_search::NeighbourSearch;

/// Cell side is at least d times this factor (> 1 so that round-off at cell faces never hides
/// a partner).
const CELL_MARGIN: f64 = 1.0 + 1e-9;

/// The engine rebuilds its cells and events every this many events per particle (at event
/// counts that are multiples of it: deterministic points of the run), so that the grid follows
/// the mean flow.
const REBUILD_EVENTS_PER_PARTICLE: u64 = 50;

/// Up to this many bytes of particle records, a list search does not prefetch the records of
/// the partners it will test: they stay in the second-level cache (512 KiB on this project's
/// machines), where the prefetch instructions cost more than they hide (N = 4000, phi = 0.40:
/// 6 % faster without them, median of 9 interleaved rounds); larger systems prefetch.
const RECORDS_IN_CACHE: usize = 512 * 1024;

/// Kinematic state of one particle at its own local time: the data read when other particles
/// look for collision partners, and the particle's cell, packed into one 64-byte cache line.
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
    /// flat index of the cell whose list holds the particle (cell search: the cell of its
    /// centre in the grid frame; list search: of its list's centre)
    pub cell: u32,
}

/// What only a particle's own events read and write, packed into one 64-byte cache line: a
/// collision touches the two particles' [`Kinematics`] and `Own` lines and nothing else of
/// theirs.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Own {
    /// w, angular velocity (constant between collisions)
    angular: [f64; 3],
    /// time of the last collision (pair or wall), for the TC model
    last_collision: f64,
    /// scheduled event and pair candidate
    plan: Plan,
}

// each record is one cache line
const _: () = assert!(std::mem::size_of::<Kinematics>() == 64);
const _: () = assert!(std::mem::size_of::<Own>() == 64);

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
    kin: HugeArray<Kinematics>,
    /// particle id of each storage slot (slots are re-sorted by cell at every rebuild)
    ids: HugeArray<u32>,
    /// spin, last collision and plan of each particle
    own: HugeArray<Own>,
    queue: EngineQueue,
    /// how partners are found (cell lists, or neighbour lists: then the cells hold anchors)
    /// and whether rebuilds re-choose it
    policy: SearchPolicy,
    /// symmetric neighbour lists (list search only)
    lists: NeighbourLists,
    /// centre of each particle's neighbour list, in the grid frame (list search only)
    anchors: HugeArray<[f64; 3]>,
    /// neighbours found by a list renewal (reused: no allocation per event)
    scratch: Vec<Neighbour>,
    /// shift vector of each periodic image (box lengths along the periodic axes)
    image_shifts: ImageShifts,
    cells: CellGrid,
    /// U, velocity along x of the cell grid: the grid drifts with the mean flow so that the
    /// fast flow of a channel does not turn into a stream of cell crossings. A particle's
    /// grid-frame coordinate is xi = x - U (t - t_grid).
    grid_drift: f64,
    /// t_grid, time at which the drifting grid frame coincides with the box frame
    grid_epoch: f64,
    /// event count of the next periodic rebuild
    next_rebuild: u64,
    counters: EdmdCounters,
    /// cumulative impulse delivered to the wall at y = 0 and at y = W
    wall_momentum: [[f64; 3]; 2],
    /// cumulative kinetic energy dissipated in collisions
    dissipated: f64,
    /// cumulative energy the TC model kept from being dissipated: (1 - e^2) g_n^2 / 4 of
    /// every collision it made elastic (what constant e would have dissipated in addition)
    suppressed_dissipation: f64,
    /// start of the current stall-check window: (event count, simulated time); windows run
    /// across snapshots and checkpoints, so frequent snapshots cannot hide a collapse
    stall_window: (u64, f64),
    /// cumulative work of gravity, m g sum of x-displacements
    gravity_work: f64,
    /// true directly after a snapshot: the state is synchronised and a checkpoint is valid
    synchronised: bool,
    /// physical events, when recording is switched on (tests)
    log: Option<Vec<PhysicalEvent>>,
    /// free paths ended since they were last taken, when statistics are on
    free_paths: Option<Box<crate::engine::FreePathTally>>,
}

impl EdmdEngine {
    /// A fresh run: place spheres, draw velocities, schedule all events. The neighbour search
    /// starts as [`NeighbourSearch::automatic`] chooses from the parameters and is re-chosen at
    /// rebuilds from the run's own bookkeeping ([`SearchPolicy`]).
    pub fn new(params: EdmdParams) -> Result<Self, EngineError> {
        let start = NeighbourSearch::automatic(&params);
        Self::with_policy(
            params,
            SearchPolicy::adaptive(start, &EdmdCounters::default()),
        )
    }

    /// A fresh run with the given neighbour search throughout (for tests and benchmarks).
    pub fn with_search(params: EdmdParams, search: NeighbourSearch) -> Result<Self, EngineError> {
        Self::with_policy(params, SearchPolicy::fixed(search))
    }

    /// A fresh run whose neighbour search follows `policy`.
    pub fn with_policy(params: EdmdParams, policy: SearchPolicy) -> Result<Self, EngineError> {
        params.validate()?;
        policy.search.validate()?;
        let start = setup::initial_state(&params)?;
        Ok(Self::from_initial(params, policy, start))
    }

    /// A run of `params` from the given initial state at t = 0 (no collision yet), its search
    /// following `policy` (parameters and policy already validated).
    pub(in crate::engine::edmd) fn from_initial(
        params: EdmdParams,
        policy: SearchPolicy,
        start: setup::InitialState,
    ) -> Self {
        let n = params.particles;
        let state = EngineState {
            params,
            now: 0.0,
            positions: start.positions,
            velocities: start.velocities,
            angular_velocities: start.angular_velocities,
            last_collision: vec![f64::NEG_INFINITY; n],
            counters: EdmdCounters::default(),
            wall_momentum: [[0.0; 3]; 2],
            dissipated: 0.0,
            gravity_work: 0.0,
            suppressed_dissipation: 0.0,
            stall_window: (0, 0.0),
            search: policy,
        };
        Self::from_state(state)
    }

    /// Rebuild an engine from checkpoint bytes (see [`checkpoint`]).
    pub fn restore(bytes: &[u8]) -> Result<Self, EngineError> {
        let state = checkpoint::decode(bytes)?;
        state.params.validate()?;
        state.search.search.validate()?;
        Ok(Self::from_state(state))
    }

    /// Rebuild an engine from a checkpoint payload already taken out of its envelope.
    pub fn restore_payload(version: u32, payload: &[u8]) -> Result<Self, EngineError> {
        let state = checkpoint::decode_payload(version, payload)?;
        state.params.validate()?;
        state.search.search.validate()?;
        Ok(Self::from_state(state))
    }

    /// The event counters so far.
    pub fn counters(&self) -> EdmdCounters {
        self.counters
    }

    /// The neighbour search in use.
    pub fn search(&self) -> NeighbourSearch {
        self.policy.search
    }

    /// As [`EdmdEngine::restore`], with the given neighbour search throughout (for tests).
    pub fn restore_with_search(bytes: &[u8], search: NeighbourSearch) -> Result<Self, EngineError> {
        let mut state = checkpoint::decode(bytes)?;
        state.params.validate()?;
        search.validate()?;
        state.search = SearchPolicy::fixed(search);
        Ok(Self::from_state(state))
    }

    fn from_state(state: EngineState) -> Self {
        let p = &state.params;
        let g = p.geometry;
        let n = p.particles;
        let search = state.search.search;
        let axes = grid_axes(&g, search);
        let ext = g.extents();
        let periodic = [true, !g.walls, true];
        let image_shifts = ImageShifts::new(ext, periodic);
        let kin = HugeArray::from_fn(n, |i| Kinematics {
            position: state.positions[i],
            velocity: state.velocities[i],
            time: state.now,
            collisions: 0,
            cell: 0,
        });
        let own = HugeArray::from_fn(n, |i| Own {
            angular: state.angular_velocities[i],
            last_collision: state.last_collision[i],
            plan: Plan::NONE,
        });
        // the state's copies of the particles are freed before the rebuild's own buffers are
        // taken (at 3e5 spheres they were a fifth of the job's peak memory)
        let EngineState {
            params,
            now,
            counters,
            wall_momentum,
            dissipated,
            gravity_work,
            suppressed_dissipation,
            stall_window,
            search: policy,
            ..
        } = state;
        let p = &params;
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
            now,
            kin,
            ids: HugeArray::from_fn(n, |i| i as u32),
            own,
            queue: EngineQueue::new(n, 1, 1.0, now),
            policy,
            lists: lists_for(search, n),
            anchors: HugeArray::default(),
            scratch: Vec::new(),
            image_shifts,
            cells: CellGrid::new(axes, n),
            grid_drift: 0.0,
            grid_epoch: now,
            next_rebuild: 0,
            counters,
            wall_momentum,
            dissipated,
            suppressed_dissipation,
            stall_window,
            gravity_work,
            synchronised: true,
            log: None,
            free_paths: None,
            params,
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
            + std::mem::size_of::<Own>()
            + std::mem::size_of::<u32>()
            + self.queue.bytes_per_particle();
        let lists = self.lists.bytes() + std::mem::size_of_val(&self.anchors[..]);
        (per * n + self.cells.bytes() + lists) as f64 / n as f64
    }
    fn collisions_per_particle(&self) -> f64 {
        2.0 * self.counters.pair_collisions as f64 / self.kin.len() as f64
    }

    /// `of(slot)` for every slot, arranged by particle id (the order of snapshots and
    /// checkpoints).
    fn by_id<T: Copy + Default>(&self, of: impl Fn(usize) -> T) -> Vec<T> {
        let mut out = vec![T::default(); self.ids.len()];
        for (slot, &id) in self.ids.iter().enumerate() {
            out[id as usize] = of(slot);
        }
        out
    }
}

/// The cell grid of a box for a neighbour search: cells of side at least d (cell search) or
/// at least d + skin (list search, whose cells hold the lists' centres); along a wall axis the
/// cells span the centres' range [d/2, W - d/2].
fn grid_axes(g: &crate::engine::BoxGeometry, search: NeighbourSearch) -> [AxisCells; 3] {
    let side = CELL_MARGIN * search.reach();
    [
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
    ]
}

/// Neighbour lists for `n` particles with list search, none with cell search.
fn lists_for(search: NeighbourSearch, n: usize) -> NeighbourLists {
    NeighbourLists::new(match search {
        NeighbourSearch::Cells => 0,
        NeighbourSearch::Lists { .. } => n,
    })
}

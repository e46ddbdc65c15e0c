//! The engine's neighbour-list search (used at high density): each particle's collision
//! partners are read from its list instead of 27 cells, cell crossings disappear, and a
//! particle renews its list when it has moved skin/2 from the list's centre (its anchor).
//! The cell grid then holds the anchors, in cells of side >= d + skin.

use super::super::motion::{ball_exit_time, ball_exit_time_bound, linear_exit_time};
use super::super::neighbours::Neighbour;
use super::super::search::{KeptNeighbours, KeptPairs};
use super::{EdmdEngine, EventKind, NO_PARTNER, PairCandidate, collision};
use crate::engine::edmd::EdmdParams;
use crate::engine::prefetch::prefetch_at;

/// How the engine finds collision partners. Both give the same dynamics; they differ in speed
/// (and in round-off, so a run is bitwise reproducible only with the same choices, which a run
/// makes from its parameters at the start, [`NeighbourSearch::automatic`], and from its own
/// counters at rebuilds, [`crate::engine::edmd::SearchPolicy`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum NeighbourSearch {
    /// cell lists, cells of side >= d: the partners are in the 27 cells around a particle
    Cells,
    /// neighbour lists of bounding spheres: partners are the particles whose list centres are
    /// closer than d + `skin`; a list is renewed when its particle has moved `skin`/2
    Lists {
        /// skin, in d (0 < skin <= 1)
        skin: f64,
    },
}

impl NeighbourSearch {
    /// At and above this volume fraction the engine uses neighbour lists.
    pub const LISTS_FROM_VOLUME_FRACTION: f64 = 0.3;
    /// Default skin of the neighbour lists, in d.
    pub const DEFAULT_SKIN: f64 = 0.5;

    /// Cell lists at low density, neighbour lists at high density: the search a run starts
    /// with (from the parameters only, so runs stay reproducible).
    pub fn automatic(params: &EdmdParams) -> Self {
        if params.volume_fraction() >= Self::LISTS_FROM_VOLUME_FRACTION {
            NeighbourSearch::Lists {
                skin: Self::DEFAULT_SKIN,
            }
        } else {
            NeighbourSearch::Cells
        }
    }

    /// Smallest cell side, in d: the reach of a search.
    pub(super) fn reach(self) -> f64 {
        match self {
            NeighbourSearch::Cells => 1.0,
            NeighbourSearch::Lists { skin } => 1.0 + skin,
        }
    }

    pub(super) fn validate(self) -> Result<(), crate::engine::EngineError> {
        match self {
            NeighbourSearch::Lists { skin } if !(skin > 0.0 && skin <= 1.0) => {
                Err(crate::engine::EngineError::InvalidParams(format!(
                    "neighbour-list skin = {skin} is out of range: allowed (0, 1] particle diameters"
                )))
            }
            _ => Ok(()),
        }
    }
}

impl EdmdEngine {
    fn skin(&self) -> f64 {
        match self.policy.search {
            NeighbourSearch::Lists { skin } => skin,
            NeighbourSearch::Cells => unreachable!("list search without lists"),
        }
    }

    /// Anchor every particle where it is now and build all lists (part of a rebuild: the
    /// cells already hold the particles at their current positions, which are in the box).
    pub(super) fn build_all_lists(&mut self) {
        self.lists.clear();
        self.anchors = self.kin.iter().map(|k| k.position).collect();
        let mut found = std::mem::take(&mut self.scratch);
        for i in 0..self.kin.len() {
            self.overlapping::<true>(i, &mut found);
            for entry in &found {
                self.lists.link(i as u32, entry.slot(), entry.image());
            }
        }
        self.scratch = found;
    }

    /// The particles whose anchors are within d + skin of particle `i`'s (in any periodic
    /// image), into `found`; with `HIGHER_ONLY`, only those in higher slots (a compile-time
    /// choice: a renewal's test per member is then one comparison).
    fn overlapping<const HIGHER_ONLY: bool>(&self, i: usize, found: &mut Vec<Neighbour>) {
        found.clear();
        let reach = 1.0 + self.skin();
        let coords = self.cells.coords(self.kin[i].cell as usize);
        let around = self.cells.around_coords(coords);
        let a = self.anchors[i];
        // cells whose nearest point is out of reach are skipped (a corner cell about half the
        // time): with a margin far above round-off, so that no anchor they hold could pass the
        // test below
        let slabs = self.cells.slab_distances(coords, a);
        let cell_reach = reach + 1e-6;
        let mut kept = KeptNeighbours::new();
        self.cells.walk_within(
            &around,
            &slabs,
            cell_reach * cell_reach,
            |first| prefetch_at(&self.anchors, first as usize),
            |j, image| {
                debug_assert!((j as usize) < self.anchors.len());
                // SAFETY: cell members are ids of this engine's particles (see `approach`)
                let b = unsafe { *self.anchors.get_unchecked(j as usize) };
                let shift = *self.image_shifts.of(image);
                let d = [
                    a[0] - (b[0] + shift[0]),
                    a[1] - (b[1] + shift[1]),
                    a[2] - (b[2] + shift[2]),
                ];
                // whether an anchor is within reach is a coin flip: kept without a branch
                let near = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach;
                let wanted = (j as usize != i) & (!HIGHER_ONLY | (j as usize > i));
                if kept.push_if(near & wanted, Neighbour::new(j, image)) {
                    found.extend_from_slice(kept.as_slice());
                    kept.clear();
                }
            },
        );
        found.extend_from_slice(kept.as_slice());
    }

    /// Renew particle `i`'s list (it is at `now`): anchor it where it is (wrapped into the box
    /// of the grid frame) and list the particles now within reach, editing only the lists of
    /// those that left or joined.
    #[inline(never)]
    pub(super) fn renew_list(&mut self, i: usize) {
        let offset = self.grid_drift * (self.now - self.grid_epoch);
        let ext = self.params.geometry.extents();
        let walls = self.params.geometry.walls;
        let position = &mut self.kin[i].position;
        for (axis, shift) in [(0, offset), (1, 0.0), (2, 0.0)] {
            if axis == 1 && walls {
                continue;
            }
            let xi = position[axis] - shift;
            if !(0.0..ext[axis]).contains(&xi) {
                position[axis] -= (xi / ext[axis]).floor() * ext[axis];
            }
        }
        self.anchors[i] = [position[0] - offset, position[1], position[2]];
        let cell = self.cells.index(self.cells.locate(self.anchors[i]));
        self.cells
            .relocate(i as u32, self.kin[i].cell as usize, cell);
        self.kin[i].cell = cell as u32;
        let mut found = std::mem::take(&mut self.scratch);
        self.overlapping::<false>(i, &mut found);
        self.lists.replace(i as u32, &found);
        self.scratch = found;
    }

    /// Earliest event of particle `i` (at `now`) with list search: a collision with a
    /// neighbour, a wall, or the renewal of its list. Stored as its event; time returned.
    pub(super) fn predict_from_list(&mut self, i: usize) -> f64 {
        let (exit_time, exit_kind) = self.list_exit_event(i);
        let mut best = PairCandidate::NONE;
        let mut best_dt = exit_time - self.now;
        let list = self.lists.entries(i);
        if self.prefetches_partners() {
            for entry in list {
                prefetch_at(&self.kin, entry.slot() as usize);
            }
        }
        // the first pass two partners at a time (see `lanes`), in list order
        let mut kept = KeptPairs::new();
        self.first_pass_in_lanes(i, list, &mut kept, &mut best, &mut best_dt);
        self.earliest_kept(&kept, &mut best, &mut best_dt);
        let (time, kind) = if best.partner != NO_PARTNER {
            (
                best.time,
                EventKind::Pair {
                    partner: best.partner,
                    partner_collisions: best.partner_collisions,
                },
            )
        } else {
            (exit_time, exit_kind)
        };
        self.own[i].plan.event = kind;
        time
    }

    /// The earlier of particle `i`'s wall hit and the renewal of its list: the moment it may
    /// have moved skin/2 from its anchor (in the grid frame, drifting with U; exact without
    /// gravity, a safe lower bound with it).
    fn list_exit_event(&self, i: usize) -> (f64, EventKind) {
        let me = &self.kin[i];
        let g = self.params.gravity;
        let a = self.anchors[i];
        let u = self.grid_drift;
        let d = [
            me.position[0] - u * (self.now - self.grid_epoch) - a[0],
            me.position[1] - a[1],
            me.position[2] - a[2],
        ];
        let v = [me.velocity[0] - u, me.velocity[1], me.velocity[2]];
        let radius = 0.5 * self.skin();
        let mut best = if g > 0.0 {
            ball_exit_time_bound(d, v, g, radius)
        } else {
            ball_exit_time(d, v, radius).unwrap_or(f64::INFINITY)
        };
        let mut kind = EventKind::Renew;
        if self.params.geometry.walls {
            let w = self.params.geometry.width;
            let lowest = collision::RADIUS;
            if let Some((dt, upper)) =
                linear_exit_time(me.position[1], me.velocity[1], lowest, w - lowest)
                && dt < best
            {
                best = dt;
                kind = EventKind::Wall { upper };
            }
        }
        if best.is_infinite() {
            kind = EventKind::None;
        }
        (self.now + best, kind)
    }
}

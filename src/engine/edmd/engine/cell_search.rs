//! Event prediction with cell lists: when a particle leaves its cell or hits a wall, and the
//! earliest pair contact among the spheres of its own and adjacent cells.

use super::*;
use crate::engine::edmd::motion::PairApproach;
use crate::engine::edmd::neighbours::Neighbour;
use crate::engine::edmd::search::{KeptNeighbours, KeptPairs};

impl EdmdEngine {
    /// Earliest event of particle `i` (whose state is at `now`) after a full search: leaving its
    /// cell, hitting a wall, or colliding with a sphere in its own or an adjacent cell. Stores
    /// the earliest pair collision as the particle's candidate (whatever its time) and the
    /// earliest event as its event; returns the event time (infinite when nothing can happen).
    pub(super) fn predict(&mut self, i: usize) -> f64 {
        if self.uses_lists() {
            return self.predict_from_list(i);
        }
        let coords = self.cells.coords(self.kin[i].cell as usize);
        let around = self.cells.around_coords(coords);
        self.own[i].plan.candidate = self.scan_cells(i, &around, f64::INFINITY);
        self.choose_event(i, coords)
    }

    /// Event of particle `i` right after it crossed into the cell at `coords` along `axis`: its
    /// velocity is unchanged, so the pair candidate of its last full search still holds if the
    /// partner has not collided since; only the layer of cells that just became adjacent is
    /// searched.
    pub(super) fn predict_after_crossing(
        &mut self,
        i: usize,
        coords: [usize; 3],
        axis: usize,
        upper: bool,
    ) -> f64 {
        let candidate = self.own[i].plan.candidate;
        let still_valid = match candidate.partner {
            NO_PARTNER => true,
            j => self.kin[j as usize].collisions == candidate.partner_collisions,
        };
        if !still_valid {
            return self.predict(i);
        }
        let entered = self.cells.entered_at(coords, axis, upper);
        let found = self.scan_cells(i, &entered, candidate.time);
        if found.time < candidate.time {
            self.own[i].plan.candidate = found;
        }
        self.choose_event(i, coords)
    }

    /// The earlier of particle `i`'s exit from its cell (at `coords`) or wall hit and its pair
    /// candidate: stored as its event, time returned.
    pub(super) fn choose_event(&mut self, i: usize, coords: [usize; 3]) -> f64 {
        let (exit_time, exit_kind) = self.exit_event(i, coords);
        let candidate = self.own[i].plan.candidate;
        let pair = EventKind::Pair {
            partner: candidate.partner,
            partner_collisions: candidate.partner_collisions,
        };
        // a collision or a crossing is a coin flip: chosen by selects, not a branch
        let collides = (candidate.time <= exit_time) & (candidate.partner != NO_PARTNER);
        self.own[i].plan.event = if collides { pair } else { exit_kind };
        if collides { candidate.time } else { exit_time }
    }

    /// When and how particle `i` (at `now`) leaves its cell (at `coords`); the outer faces of
    /// the edge cells along a wall axis are the walls. Along x the faces move with the
    /// drifting grid.
    pub(super) fn exit_event(&self, i: usize, coords: [usize; 3]) -> (f64, EventKind) {
        let me = &self.kin[i];
        let g = self.params.gravity;
        let axes = &self.cells.axes;
        // the earliest face, chosen by selects (which one it is is random): first axis on ties
        let (mut best, mut axis, mut upper) = (f64::INFINITY, 0, false);
        for a in 0..3 {
            let (lo, hi) = self.cells.faces(a, coords[a]);
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
    /// The walk reads the cells' heads, prefetches each first member's record and link, then
    /// walks the lists, gathering the members; they get the first, square-root-free pass of
    /// the contact test two at a time (see [`Self::consider`]) and are kept when they may
    /// touch; the kept ones get the second pass when the buffer is full and at the end.
    pub(super) fn scan_cells(&self, i: usize, hood: &Neighbourhood, horizon: f64) -> PairCandidate {
        let mut best = PairCandidate::NONE;
        let mut best_dt = horizon - self.now;
        let mut kept = KeptPairs::new();
        // the members met (all but `i` itself), gathered so that the first pass can take them
        // two at a time, as a list search does
        let mut met = KeptNeighbours::new();
        self.cells.walk(
            hood,
            |first| prefetch_at(&self.kin, first as usize),
            |j, image| {
                if met.push_if(j as usize != i, Neighbour::new(j, image)) {
                    self.first_pass_in_lanes(i, met.as_slice(), &mut kept, &mut best, &mut best_dt);
                    met.clear();
                }
            },
        );
        self.first_pass_in_lanes(i, met.as_slice(), &mut kept, &mut best, &mut best_dt);
        self.earliest_kept(&kept, &mut best, &mut best_dt);
        best
    }

    /// The first pass over `partners` of particle `i`, two at a time (see `lanes`) and the
    /// odd one alone, in their order: the pairs that may touch before `now + best_dt` are
    /// added to `kept` (a full buffer gets the second pass at once; the caller gives the rest
    /// theirs).
    #[inline(always)]
    pub(super) fn first_pass_in_lanes(
        &self,
        i: usize,
        partners: &[Neighbour],
        kept: &mut KeptPairs,
        best: &mut PairCandidate,
        best_dt: &mut f64,
    ) {
        let mut pairs = partners.chunks_exact(2);
        for two in &mut pairs {
            let ids = [two[0].slot(), two[1].slot()];
            let found = self.approach_two(i, ids, [two[0].image(), two[1].image()], *best_dt);
            for lane in 0..2 {
                let entry = (found.pairs[lane], ids[lane], found.collisions[lane]);
                if kept.push_if(found.may_touch[lane], entry) {
                    self.earliest_kept(kept, best, best_dt);
                    kept.clear();
                }
            }
        }
        for last in pairs.remainder() {
            self.consider(i, last.slot(), last.image(), kept, best, best_dt);
        }
    }

    /// The first pass for image `image` of particle `j` as a partner of particle `i`: kept
    /// when it may touch before `now + best_dt`; a full buffer gets the second pass at once.
    ///
    /// The contact test has two passes: the first computes b = r.v, the gap |r|^2 - d^2 and
    /// |v|^2 of every pair and keeps, without a branch, those that approach (b < 0) soon enough
    /// (gap <= -2 b t_max) for the horizon when the pair is met; the second
    /// ([`Self::earliest_kept`]) takes the square root only for those, when the buffer is full
    /// and at the end. A later horizon is never longer, so the second pass (the whole test of
    /// `pair_contact_time_within` on the kept pairs, in their order) decides exactly as
    /// testing every pair would, bit for bit.
    #[inline(always)]
    fn consider(
        &self,
        i: usize,
        j: u32,
        image: Image,
        kept: &mut KeptPairs,
        best: &mut PairCandidate,
        best_dt: &mut f64,
    ) {
        let (pair, collisions) = self.approach(i, j, image);
        if kept.push_if(pair.may_touch_within(*best_dt), (pair, j, collisions)) {
            self.earliest_kept(kept, best, best_dt);
            kept.clear();
        }
    }

    /// The contact equation of particle `i` (at `now`) with image `image` of particle `j`
    /// (brought to `now` on the fly; its stored state is not touched), and `j`'s collision
    /// counter.
    #[inline(always)]
    pub(super) fn approach(&self, i: usize, j: u32, image: Image) -> (PairApproach, u32) {
        let me = &self.kin[i];
        debug_assert!((j as usize) < self.kin.len());
        // SAFETY: partners come from the cell and neighbour lists, which hold only ids of
        // this engine's particles (both index per-particle arrays with every id they take in)
        let other = unsafe { self.kin.get_unchecked(j as usize) };
        let shift = self.image_shifts.of(image);
        let (rj, cj) = fly(
            other.position,
            other.velocity,
            self.params.gravity,
            self.now - other.time,
        );
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
        (PairApproach::new(r, v), other.collisions)
    }

    /// The second pass: the kept pairs' contact times, in their order, against `best`.
    #[inline(always)]
    pub(super) fn earliest_kept(
        &self,
        kept: &KeptPairs,
        best: &mut PairCandidate,
        best_dt: &mut f64,
    ) {
        for &(pair, partner, partner_collisions) in kept.as_slice() {
            let dt = pair.contact_time_within(*best_dt);
            if dt < *best_dt {
                *best_dt = dt;
                *best = PairCandidate {
                    time: self.now + dt,
                    partner,
                    partner_collisions,
                };
            }
        }
    }

    /// Whether a list search prefetches its partners' records: only when the records do not
    /// fit in the second-level cache (see [`RECORDS_IN_CACHE`]).
    #[inline(always)]
    pub(super) fn prefetches_partners(&self) -> bool {
        self.kin.len() * std::mem::size_of::<Kinematics>() > RECORDS_IN_CACHE
    }

    /// True with neighbour-list search (else cells).
    #[inline(always)]
    pub(super) fn uses_lists(&self) -> bool {
        matches!(self.policy.search, NeighbourSearch::Lists { .. })
    }
}

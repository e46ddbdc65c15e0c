//! The event loop: scheduling, taking the earliest event from the queue, dispatching it, and
//! prefetching what the next event will read.

use super::*;

impl EdmdEngine {
    /// Predict and schedule the next event of particle `i`.
    #[inline]
    pub(super) fn reschedule(&mut self, i: usize) {
        let t = self.predict(i);
        self.schedule(i, t);
    }

    #[inline]
    pub(super) fn schedule(&mut self, i: usize, t: f64) {
        if t.is_finite() {
            self.queue.schedule(i as u32, t);
        } else {
            self.queue.cancel(i as u32);
        }
    }

    /// Process the earliest event. Returns false when no event is left.
    ///
    /// Every event ends by scheduling (or cancelling) the particle's next one, which replaces
    /// it in the queue (see [`EngineQueue::take_next`]).
    pub(super) fn step(&mut self) -> bool {
        let Some((t, id)) = self.queue.take_next() else {
            return false;
        };
        let i = id as usize;
        // the following event is most likely the queue's next one: where the queue knows it
        // already (the calendar of a large system, whose records do not stay in cache), start
        // loading its records now, so that they are in cache when it is processed
        if let Some((_, next)) = self.queue.following() {
            self.prefetch_own_records(next as usize);
        }
        self.now = t;
        self.counters.events += 1;
        if self.counters.events == self.next_rebuild {
            // the event is re-predicted by the rebuild, together with all others
            self.rebuild();
            return true;
        }
        self.synchronised = false;
        self.advance_particle(i, t);
        match self.own[i].plan.event {
            EventKind::Pair {
                partner,
                partner_collisions,
            } => {
                let j = partner as usize;
                if self.kin[j].collisions == partner_collisions {
                    // the partner's list arrived during the last step: its neighbours load
                    // while the collision is worked out (the particle's own were asked for
                    // then)
                    self.prefetch_listed(j);
                    self.advance_particle(j, t);
                    self.collide_pair(i, j);
                    self.reschedule(i);
                    self.reschedule(j);
                } else {
                    self.reschedule(i);
                }
            }
            EventKind::Cross { axis, upper } => {
                let coords = self.cross_cell(i, axis as usize, upper);
                let t = self.predict_after_crossing(i, coords, axis as usize, upper);
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

    /// Start loading particle `next`'s records: its [`Kinematics`] and [`Own`] lines and (list
    /// search) its list and the list's centre.
    #[inline(always)]
    fn prefetch_own_records(&self, next: usize) {
        prefetch_at(&self.kin, next);
        prefetch_at(&self.own, next);
        if self.uses_lists() {
            self.lists.prefetch(next);
            prefetch_at(&self.anchors, next);
        }
    }

    /// Start loading the records of the neighbours in particle `i`'s list (whose list is in
    /// cache), when they do not all fit in a second-level cache.
    #[inline(always)]
    fn prefetch_listed(&self, i: usize) {
        if self.uses_lists() && self.prefetches_partners() {
            for entry in self.lists.of(i) {
                prefetch_at(&self.kin, entry.slot() as usize);
            }
        }
    }

    /// Start loading what the next event will read: its own records (unless the step began
    /// with them, [`EngineQueue::following`]) and, once its plan has arrived, what the plan
    /// names: the partner of a collision (its counter and velocities are read at once, its
    /// list next) and the neighbours that the particle's next prediction will test.
    #[inline(always)]
    pub(super) fn prefetch_partner_of_next_event(&mut self) {
        if let Some((_, next)) = self.queue.peek() {
            let next = next as usize;
            if matches!(self.queue, EngineQueue::Tree(_)) {
                self.prefetch_own_records(next);
            }
            if let EventKind::Pair { partner, .. } = self.own[next].plan.event {
                let j = partner as usize;
                prefetch_at(&self.kin, j);
                prefetch_at(&self.own, j);
                if self.uses_lists() {
                    self.lists.prefetch(j);
                    prefetch_at(&self.anchors, j);
                }
            }
            self.prefetch_listed(next);
        }
    }
}

//! Rebuilds (wrap, re-sort cells, re-predict every event) and the free flight that brings a
//! particle to a given time.

use super::*;
use crate::engine::edmd::huge::permute;

impl EdmdEngine {
    /// Bring every particle to the current time, wrap positions into the box, set the grid
    /// drift to the mean flow, re-sort the cells and re-predict all events from scratch.
    /// Deterministic in the state alone, so a run restored from a checkpoint continues exactly
    /// like the run that wrote it.
    pub(super) fn rebuild(&mut self) {
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
        // re-choose the neighbour search from the bookkeeping since the last choice (counters
        // only: a restored run chooses as the uninterrupted one did)
        let policy = self.policy.next(&self.counters, n);
        if policy.search != self.policy.search {
            self.lists = lists_for(policy.search, n);
            self.anchors = HugeArray::default();
        }
        self.policy = policy;
        // store particles in cell order (ties by particle id, so the order depends on the
        // state alone): the partners a search reads then sit close together in memory
        let axes = grid_axes(&self.params.geometry, policy.search);
        self.cells = CellGrid::new(axes, n);
        // sorted as keys (cell << 32 | id), then each array rearranged in place
        let mut keys: Vec<u64> = (0..n)
            .map(|s| {
                let cell = self.cells.index(self.cells.locate(self.kin[s].position));
                (cell as u64) << 32 | self.ids[s] as u64
            })
            .collect();
        keys.sort_unstable();
        let mut slot_of_id = vec![0u32; n];
        for (s, &id) in self.ids.iter().enumerate() {
            slot_of_id[id as usize] = s as u32;
        }
        let from: Vec<u32> = keys
            .iter()
            .map(|&k| slot_of_id[k as u32 as usize])
            .collect();
        drop(slot_of_id);
        permute(&mut self.kin, &from);
        permute(&mut self.own, &from);
        drop(from);
        // inserted last to first, so that each cell lists its particles in storage order
        for (slot, &key) in keys.iter().enumerate().rev() {
            self.ids[slot] = key as u32;
            self.kin[slot].cell = (key >> 32) as u32;
            self.cells.insert(slot as u32, (key >> 32) as usize);
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
        // predict every particle's next event, then size the calendar (if the queue is one)
        // from their spread: about four events per bucket near `now`, a year of buckets
        // spanning ~4 mean times
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
        self.queue = EngineQueue::new(n, n.max(16), width, self.now);
        for (i, &t) in times.iter().enumerate() {
            if t.is_finite() {
                self.queue.schedule(i as u32, t);
            }
        }
    }

    /// Free flight of particle `i` from its local time to `t` (gravity g along +x).
    #[inline(always)]
    pub(super) fn advance_particle(&mut self, i: usize, t: f64) {
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
}

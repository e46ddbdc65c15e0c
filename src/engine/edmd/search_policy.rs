//! Which neighbour search a run uses, re-chosen at rebuilds from what the run measures: the
//! bookkeeping events (cell crossings, or list renewals, plus invalidated predictions) per
//! pair collision. Cells are cheap while particles fly far between collisions; neighbour
//! lists are cheap once particles are caged (dense plugs and slugs of a channel, whose global
//! volume fraction says nothing about it). The choice depends on counters alone, which
//! checkpoints keep, so a resumed run chooses as the uninterrupted one did; it changes the
//! round-off of a run, not its physics.

use super::NeighbourSearch;
use super::checkpoint::EdmdCounters;
use serde::{Deserialize, Serialize};

/// Below this many bookkeeping events per pair collision with cells, lists are cheaper.
/// Measured (docs/performance.md): channels at W/d = 15-50 where lists were 1.2-2.7x faster
/// ran 0.18-0.57 with cells, those where cells were 1.3-1.9x faster 0.85-1.33; a periodic box
/// at phi = 0.30, where both are even, runs about 0.6.
pub const LISTS_BELOW: f64 = 0.6;
/// Above this many bookkeeping events per pair collision with lists, cells are cheaper (lists
/// count about 2.3 times as many: a renewal comes every skin/2 = d/4 of travel, a crossing
/// every cell side ~ d along each axis). Measured: 0.18-1.21 where lists won, 2.17-3.36 where
/// cells won. The gap between the two limits keeps a run near the break-even from switching
/// back and forth.
pub const CELLS_ABOVE: f64 = 2.0;
/// A choice waits for at least this many pair collisions per particle since the last one.
pub const MIN_COLLISIONS_PER_PARTICLE: f64 = 2.0;

/// The search in use and how it is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchPolicy {
    /// the search in use
    pub search: NeighbourSearch,
    /// re-chosen at rebuilds (false: fixed, as tests and forced benchmarks ask)
    pub adaptive: bool,
    /// (pair collisions, bookkeeping events) when the search was last chosen
    pub mark: (u64, u64),
}

impl SearchPolicy {
    /// A fixed search.
    pub fn fixed(search: NeighbourSearch) -> Self {
        SearchPolicy {
            search,
            adaptive: false,
            mark: (0, 0),
        }
    }

    /// Start with `search` and re-choose from the counters after `counters`.
    pub fn adaptive(search: NeighbourSearch, counters: &EdmdCounters) -> Self {
        SearchPolicy {
            search,
            adaptive: true,
            mark: (counters.pair_collisions, bookkeeping(counters)),
        }
    }

    /// The choice at a rebuild with `counters`, for `particles` particles: unchanged when
    /// fixed or when too few collisions happened since the last choice (the mark then stays),
    /// else from the bookkeeping events per pair collision since then (and a new mark).
    pub fn next(self, counters: &EdmdCounters, particles: usize) -> Self {
        let collisions = counters.pair_collisions - self.mark.0;
        if !self.adaptive
            || (collisions as f64) < MIN_COLLISIONS_PER_PARTICLE * particles as f64 / 2.0
        {
            return self;
        }
        let per_collision = (bookkeeping(counters) - self.mark.1) as f64 / collisions as f64;
        let search = match self.search {
            NeighbourSearch::Cells if per_collision < LISTS_BELOW => NeighbourSearch::Lists {
                skin: NeighbourSearch::DEFAULT_SKIN,
            },
            NeighbourSearch::Lists { .. } if per_collision > CELLS_ABOVE => NeighbourSearch::Cells,
            same => same,
        };
        SearchPolicy::adaptive(search, counters)
    }
}

/// Events that are neither pair nor wall collisions: cell crossings, list renewals,
/// invalidated predictions and rebuilds.
fn bookkeeping(counters: &EdmdCounters) -> u64 {
    counters.events - counters.pair_collisions - counters.wall_collisions
}

#[cfg(test)]
mod tests {
    use super::*;

    const LISTS: NeighbourSearch = NeighbourSearch::Lists {
        skin: NeighbourSearch::DEFAULT_SKIN,
    };

    /// Counters after `pairs` pair collisions and `book` bookkeeping events (no walls).
    fn counters(pairs: u64, book: u64) -> EdmdCounters {
        EdmdCounters {
            pair_collisions: pairs,
            events: pairs + book,
            ..Default::default()
        }
    }

    #[test]
    fn cells_give_way_to_lists_only_below_the_limit() {
        let start = SearchPolicy::adaptive(NeighbourSearch::Cells, &counters(0, 0));
        // 1000 particles, 2000 collisions since the mark: enough to choose
        assert_eq!(start.next(&counters(2000, 1000), 1000).search, LISTS);
        assert_eq!(
            start.next(&counters(2000, 1300), 1000).search,
            NeighbourSearch::Cells
        );
        // too few collisions: nothing changes, the mark stays
        let early = start.next(&counters(900, 0), 1000);
        assert_eq!(early, start);
    }

    #[test]
    fn lists_give_way_to_cells_only_above_the_limit() {
        let start = SearchPolicy::adaptive(LISTS, &counters(5000, 7000));
        assert_eq!(
            start.next(&counters(7000, 12000), 1000).search,
            NeighbourSearch::Cells
        );
        // 1.5 per collision: in the band between the limits, lists stay
        let stay = start.next(&counters(7000, 10000), 1000);
        assert_eq!(stay.search, LISTS);
        assert_eq!(stay.mark, (7000, 10000), "a choice sets a new mark");
    }

    #[test]
    fn a_fixed_search_never_changes() {
        let fixed = SearchPolicy::fixed(NeighbourSearch::Cells);
        assert_eq!(fixed.next(&counters(1_000_000, 0), 10), fixed);
    }
}

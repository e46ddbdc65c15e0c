//! The fast data structures against their simple reference versions.
//! - the calendar queue pops exactly like the B-tree reference queue on random event streams;
//! - the fast engine (cells or neighbour lists, calendar queue, delayed updates) processes the
//!   same physical events as the slow all-pairs reference engine on small systems.

use granflow::engine::edmd::queue::{CalendarQueue, EventQueue, ReferenceQueue};
use granflow::engine::edmd::reference::ReferenceEngine;
use granflow::engine::edmd::{EdmdEngine, EdmdParams, NeighbourSearch, PhysicalEvent};
use granflow::engine::{BoxGeometry, Engine, StopAt};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

#[test]
fn calendar_queue_pops_like_reference_queue() {
    for (seed, buckets, width) in [
        (1u64, 16usize, 0.01),
        (2, 1, 1.0),
        (3, 1000, 1e-4),
        (4, 7, 10.0),
    ] {
        let n = 500u32;
        let mut rng = Pcg64::seed_from_u64(seed);
        let mut fast = CalendarQueue::new(n as usize, buckets, width, 0.0);
        let mut slow = ReferenceQueue::new(n as usize);
        let mut now = 0.0f64;
        for step in 0..200_000 {
            let op = rng.random_range(0..10);
            if op < 5 {
                // schedule in the future, sometimes far, sometimes exactly at `now` (ties)
                let id = rng.random_range(0..n);
                let t = match rng.random_range(0..4) {
                    0 => now,
                    1 => now + rng.random::<f64>() * 1000.0,
                    _ => now + rng.random::<f64>(),
                };
                fast.schedule(id, t);
                slow.schedule(id, t);
            } else if op < 6 {
                let id = rng.random_range(0..n);
                fast.cancel(id);
                slow.cancel(id);
            } else if op < 7 {
                assert_eq!(fast.peek(), slow.peek(), "peek differs at step {step}");
            } else {
                let (a, b) = (fast.pop(), slow.pop());
                assert_eq!(a, b, "pop differs at step {step} (seed {seed})");
                if let Some((t, _)) = a {
                    assert!(t >= now, "time went backwards");
                    now = t;
                }
            }
            assert_eq!(fast.len(), slow.len());
        }
        while let Some(b) = slow.pop() {
            assert_eq!(fast.pop(), Some(b));
        }
        assert!(fast.pop().is_none());
    }
}

fn small_system(walls: bool, gravity: f64, seed: u64) -> EdmdParams {
    EdmdParams {
        geometry: BoxGeometry {
            length: 7.0,
            width: 5.0,
            height: 4.0,
            walls,
        },
        particles: 30,
        gravity,
        restitution: 0.8,
        roughness: 0.3,
        wall_restitution: 0.9,
        wall_roughness: 0.5,
        inertia_factor: 0.4,
        tc: 0.0,
        initial_temperature: 1.0,
        placement: Default::default(),
        seed,
    }
}

/// Compare the first `count` physical events: same partners in the same order, times equal
/// to 1e-9 relative. Round-off differs between the engines (delayed vs. global updates), and
/// hard-sphere dynamics amplify it by about e per collision per particle, so `count` is kept
/// to a few collisions per particle, where 1e-16 cannot have grown to 1e-9.
const TIME_TOL: f64 = 1e-9;

/// Both searches: cells, and neighbour lists with a wide skin (few renewals, lists spanning
/// several periodic images of the small box) and a narrow one (many renewals).
const SEARCHES: [NeighbourSearch; 3] = [
    NeighbourSearch::Cells,
    NeighbourSearch::Lists { skin: 0.5 },
    NeighbourSearch::Lists { skin: 0.05 },
];

fn compare(params: EdmdParams, count: usize) {
    for search in SEARCHES {
        let slow = ReferenceEngine::new(params.clone()).unwrap();
        let fast = EdmdEngine::with_search(params.clone(), search).unwrap();
        compare_engines(fast, slow, count);
    }
}

fn compare_engines(mut fast: EdmdEngine, mut slow: ReferenceEngine, count: usize) {
    slow.run_events(count);
    fast.record_events();
    let mut t_end = fast.progress().time;
    while fast.recorded_events().len() < count {
        t_end += 0.05;
        fast.advance(StopAt::Time(t_end)).unwrap();
    }
    for (k, (a, b)) in fast.recorded_events().iter().zip(&slow.events).enumerate() {
        let ok = match (a, b) {
            (
                PhysicalEvent::Pair {
                    time: t1,
                    first: a1,
                    second: b1,
                },
                PhysicalEvent::Pair {
                    time: t2,
                    first: a2,
                    second: b2,
                },
            ) => a1 == a2 && b1 == b2 && (t1 - t2).abs() <= TIME_TOL * t2.max(1.0),
            (
                PhysicalEvent::Wall {
                    time: t1,
                    particle: p1,
                    upper: u1,
                },
                PhysicalEvent::Wall {
                    time: t2,
                    particle: p2,
                    upper: u2,
                },
            ) => p1 == p2 && u1 == u2 && (t1 - t2).abs() <= TIME_TOL * t2.max(1.0),
            _ => false,
        };
        assert!(ok, "event {k} differs: fast {a:?}, reference {b:?}");
    }
}

#[test]
fn fast_engine_matches_all_pairs_engine_in_periodic_box() {
    for seed in 1..=10 {
        compare(small_system(false, 0.0, seed), 100);
    }
}

#[test]
fn fast_engine_matches_all_pairs_engine_in_channel_with_gravity() {
    for seed in 1..=10 {
        compare(small_system(true, 1.0, seed), 100);
    }
}

/// In a developed flow the fast engine's cell grid drifts with the mean flow U (xi = x - U t);
/// the all-pairs engine has no cells, so agreement checks the drifting grid (crossings of
/// moving faces, the periodic seam in the moving frame) as well.
#[test]
fn fast_engine_matches_all_pairs_engine_in_developed_flow_with_drifting_grid() {
    for seed in 1..=10 {
        let params = small_system(true, 1.0, seed);
        let mut warm = EdmdEngine::new(params.clone()).unwrap();
        warm.advance(StopAt::CollisionsPerParticle(40.0)).unwrap();
        let snapshot = warm.snapshot();
        let particles = snapshot.particles().unwrap();
        let mean_flow =
            particles.velocities.iter().map(|v| v[0]).sum::<f64>() / particles.len() as f64;
        assert!(
            mean_flow > 1.0,
            "seed {seed}: the flow has not developed (U = {mean_flow})"
        );
        for search in SEARCHES {
            let fast = EdmdEngine::restore_with_search(&warm.checkpoint(), search).unwrap();
            let slow = ReferenceEngine::from_snapshot(params.clone(), &snapshot);
            compare_engines(fast, slow, 100);
        }
    }
}

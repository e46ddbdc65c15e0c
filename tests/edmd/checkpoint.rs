//! Checkpoint/restore. A channel run at e = 0.7 stopped at a checkpoint and
//! resumed ends bitwise identical to the uninterrupted run; truncated, corrupt and foreign
//! checkpoints are rejected with a reason.

use granflow::engine::edmd::{EdmdEngine, EdmdParams, NeighbourSearch, Placement, SearchPolicy};
use granflow::engine::{self, EngineError, Snapshot, StopAt};

fn channel() -> EdmdParams {
    // the thesis channel at L/W = 1, W/d = H/d = 10 (N = 286), e = 0.7, beta = 0.1
    EdmdParams::channel(10.0, 10.0, 10.0, 0.15, 42)
}

fn run(engine: &mut dyn engine::Engine, from: usize, to: usize) -> Snapshot {
    let mut last = None;
    for k in from + 1..=to {
        engine
            .advance(StopAt::CollisionsPerParticle(20.0 * k as f64))
            .unwrap();
        last = Some(engine.snapshot());
    }
    last.unwrap()
}

fn assert_bitwise_equal(sa: &Snapshot, sb: &Snapshot) {
    assert_eq!(sa.time().to_bits(), sb.time().to_bits(), "time");
    assert_eq!(sa.counters, sb.counters, "counters");
    let (a, b) = (sa.particles().unwrap(), sb.particles().unwrap());
    let bits = |v: &Vec<[f64; 3]>| {
        v.iter()
            .flat_map(|x| x.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert!(bits(&a.positions) == bits(&b.positions), "positions differ");
    assert!(
        bits(&a.velocities) == bits(&b.velocities),
        "velocities differ"
    );
    assert!(
        bits(&a.angular_velocities) == bits(&b.angular_velocities),
        "angular velocities differ"
    );
    assert_eq!(a.energy_dissipated.to_bits(), b.energy_dissipated.to_bits());
    assert_eq!(a.gravity_work.to_bits(), b.gravity_work.to_bits());
    assert_eq!(a.wall_momentum, b.wall_momentum);
}

fn resume_equals_uninterrupted(params: EdmdParams) {
    let mut straight = EdmdEngine::new(params.clone()).unwrap();
    let reference = run(&mut straight, 0, 10);

    let mut first = EdmdEngine::new(params.clone()).unwrap();
    run(&mut first, 0, 4);
    let bytes = engine::Engine::checkpoint(&first);
    drop(first);
    let mut resumed = granflow::registry::restore(&bytes).unwrap();
    let end = run(resumed.as_mut(), 4, 10);
    assert!(end.counters.get("pair_collisions") > 0 && end.time() > 0.0);
    assert_bitwise_equal(&reference, &end);

    // and a second, identical run is bitwise identical too (no hidden state such as addresses)
    let mut again = EdmdEngine::new(params).unwrap();
    assert_bitwise_equal(&reference, &run(&mut again, 0, 10));
}

#[test]
fn resumed_run_is_bitwise_identical_to_uninterrupted_run() {
    resume_equals_uninterrupted(channel());
}

/// The same with neighbour lists (a dense channel, phi = 0.35): the lists, anchors and
/// renewal events are rebuilt from the state at the checkpoint exactly as the uninterrupted
/// run rebuilds them at the same snapshot.
#[test]
fn resumed_run_with_neighbour_lists_is_bitwise_identical() {
    let dense = EdmdParams::channel(10.0, 10.0, 10.0, 0.35, 42);
    assert!(matches!(
        NeighbourSearch::automatic(&dense),
        NeighbourSearch::Lists { .. }
    ));
    resume_equals_uninterrupted(dense);
}

/// The same from the thermalised start (a random packing run 200 collisions per particle
/// elastic and without gravity; src/engine/edmd/start.rs) in a dense channel, phi = 0.5: the
/// start is the run's state at t = 0, so a checkpoint after it carries everything.
#[test]
fn resumed_run_from_a_thermalised_start_is_bitwise_identical() {
    let mut dense = EdmdParams::channel(10.0, 10.0, 10.0, 0.5, 42);
    dense.restitution = 0.9;
    dense.roughness = 0.9;
    dense.placement = Placement::Thermalised {
        collisions_per_particle: 200,
    };
    resume_equals_uninterrupted(dense);
}

/// A run whose neighbour search is re-chosen during the run: a dense channel (phi = 0.45)
/// started with cell search switches to neighbour lists at a snapshot, from its own
/// bookkeeping. Resumed from a checkpoint taken before the switch and from one taken after
/// it, it ends bitwise identical to the uninterrupted run.
#[test]
fn resumed_run_that_switches_its_search_is_bitwise_identical() {
    let dense = EdmdParams::channel(10.0, 10.0, 10.0, 0.45, 7);
    let start = || {
        let policy = SearchPolicy::adaptive(NeighbourSearch::Cells, &Default::default());
        EdmdEngine::with_policy(dense.clone(), policy).unwrap()
    };
    let mut straight = start();
    assert_eq!(straight.search(), NeighbourSearch::Cells);
    let switch = (1..=20)
        .find(|&k| {
            run(&mut straight, k - 1, k);
            matches!(straight.search(), NeighbourSearch::Lists { .. })
        })
        .expect("a dense channel should move to neighbour lists within 400 cpp");
    let end = switch + 5;
    let reference = run(&mut straight, switch, end);

    let mut before = start();
    if switch > 1 {
        run(&mut before, 0, switch - 1);
    } else {
        engine::Engine::snapshot(&mut before);
    }
    assert_eq!(
        before.search(),
        NeighbourSearch::Cells,
        "checkpoint before the switch"
    );
    let bytes = engine::Engine::checkpoint(&before);
    let mut resumed = granflow::registry::restore(&bytes).unwrap();
    assert_bitwise_equal(&reference, &run(resumed.as_mut(), switch - 1, end));

    let mut after = start();
    run(&mut after, 0, switch + 2);
    assert!(
        matches!(after.search(), NeighbourSearch::Lists { .. }),
        "checkpoint after it"
    );
    let bytes = engine::Engine::checkpoint(&after);
    let mut resumed = granflow::registry::restore(&bytes).unwrap();
    assert_bitwise_equal(&reference, &run(resumed.as_mut(), switch + 2, end));
}

#[test]
fn damaged_checkpoints_are_rejected() {
    let mut e = EdmdEngine::new(channel()).unwrap();
    run(&mut e, 0, 1);
    let bytes = engine::Engine::checkpoint(&e);
    assert!(granflow::registry::restore(&bytes).is_ok());

    let reason = |b: &[u8]| match granflow::registry::restore(b) {
        Err(EngineError::Checkpoint(why)) => why,
        Err(other) => panic!("wrong error kind: {other}"),
        Ok(_) => panic!("a damaged checkpoint was accepted"),
    };
    assert!(reason(&bytes[..bytes.len() - 1]).contains("truncated"));
    assert!(reason(&bytes[..10]).contains("truncated"));
    let mut flipped = bytes.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 0x40;
    assert!(reason(&flipped).contains("checksum"));
    let mut foreign = bytes.clone();
    foreign[0] = b'X';
    assert!(reason(&foreign).contains("magic"));
    let mut future = bytes.clone();
    future[16] = 99;
    assert!(reason(&future).contains("version"));
}

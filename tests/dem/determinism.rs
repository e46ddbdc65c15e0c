//! The engine against its reference, bit for bit; and the determinism rules: the same bits on
//! any number of threads, with any skin, and after a checkpoint and restore.

use crate::dem::support::{assert_same_states, jittered, params};
use granflow::engine::dem::reference::Reference;
use granflow::engine::dem::{DemEngine, DemParams, KeptContact, Phase};
use granflow::engine::{Engine, StopAt};
use std::collections::BTreeSet;

fn same_contacts(a: &[KeptContact], b: &[KeptContact], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: touching pairs");
    for (x, y) in a.iter().zip(b) {
        assert_eq!((x.0, x.1), (y.0, y.1), "{what}: pair");
        for k in 0..3 {
            assert_eq!(
                x.2[k].to_bits(),
                y.2[k].to_bits(),
                "{what}: history of {:?}",
                (x.0, x.1)
            );
        }
    }
}

/// Run the engine beside the reference for `total` steps in calls of the given sizes (so
/// that fused and unfused steps both occur), comparing the whole state after each call.
/// Returns (rebuilds, contacts that started, contacts that ended).
fn beside_reference(e: &mut DemEngine, total: u64, what: &str) -> (u64, usize, usize) {
    let (law, bounds) = e.laws();
    let mut r = Reference::new(law, bounds, e.domain(), e.states(), &e.contacts());
    let rebuilds = e.counters().rebuilds;
    let (mut started, mut ended) = (0, 0);
    let mut before: BTreeSet<(u32, u32)> = e.contacts().iter().map(|c| (c.0, c.1)).collect();
    let mut done = 0;
    let mut call = 0;
    while done < total {
        let k = [1, 7, 3, 13][call % 4].min(total - done);
        call += 1;
        match e.phase() {
            Phase::Preparing(_) => {
                assert!(
                    !e.prepare(k).unwrap(),
                    "{what}: settled during the comparison"
                );
            }
            Phase::Flowing => e.advance_to_step(e.steps() + k).unwrap(),
        }
        for _ in 0..k {
            r.step();
        }
        done += k;
        let at = format!("{what}, step {done}");
        assert_same_states(&e.states(), &r.bodies, &at);
        same_contacts(&e.contacts(), &r.contact_list(), &at);
        let now: BTreeSet<(u32, u32)> = e.contacts().iter().map(|c| (c.0, c.1)).collect();
        started += now.difference(&before).count();
        ended += before.difference(&now).count();
        before = now;
    }
    (e.counters().rebuilds - rebuilds, started, ended)
}

fn small_channel() -> DemParams {
    let mut p = params(1e4, 6.0, 4.0, 6.0);
    p.volume_fraction = 0.45;
    p.gravity = [1.0, 0.0, 0.0];
    p.settle_friction = 0.3;
    p.skin = 0.02;
    p
}

/// The fast engine (cell list, neighbour list with a skin, rebuilds that reorder the
/// particles, histories carried by tags, row gather, parallel blocks, fused half steps) is
/// the all-pairs reference step by step, to the last bit: in the preparation (raining onto
/// the floor with friction) and in the flow (walls, gravity, friction, three sizes), over
/// enough steps that the list is rebuilt many times and contacts start and end. Bitwise,
/// because both apply the same contact rule and sum each particle's forces in the same order
/// (partners by tag, wall, floor, gravity): any other difference is a bug. With the paper's
/// walls, whose damping differs by size (both look each particle's law up by its radius).
#[test]
fn the_engine_is_the_reference_bit_for_bit() {
    let p = DemParams {
        wall_damping: granflow::engine::dem::WallDamping::PairRestitution,
        ..small_channel()
    };
    let mut e = DemEngine::unprepared(p).unwrap();
    assert!(e.particle_count() > 100);
    let (rebuilds, started, ended) = beside_reference(&mut e, 1500, "preparation");
    println!("preparation: {rebuilds} rebuilds, {started} contacts started, {ended} ended");
    assert!(rebuilds >= 5 && started > 100 && ended > 20);
    assert!(e.prepare(u64::MAX).unwrap());
    let (rebuilds, started, ended) = beside_reference(&mut e, 2000, "flow");
    println!("flow: {rebuilds} rebuilds, {started} contacts started, {ended} ended");
    assert!(rebuilds >= 5 && started > 20 && ended > 20);
}

/// A channel large enough for several parallel blocks of particles (256) and pairs (2048).
fn threaded_channel() -> (DemParams, Vec<granflow::engine::dem::BodyState>) {
    let mut p = params(1e5, 16.0, 10.0, 20.0);
    p.gravity = [1.0, 0.0, 0.0];
    let states = jittered(&p, 1.105, 0.3, 11);
    assert!(states.len() > 3 * 256, "{}", states.len());
    (p, states)
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// The number of threads does not change a single bit: the checkpoint bytes after a flow and
/// after part of a preparation are the same on one thread and on two (and on three for the
/// flow: more threads than cores, so tasks are stolen at other places).
#[test]
fn threads_do_not_change_a_bit() {
    let (p, states) = threaded_channel();
    let run = |threads: usize| {
        pool(threads).install(|| {
            let mut e = DemEngine::from_state(p.clone(), &states, &[]).unwrap();
            e.advance_to_step(400).unwrap();
            assert!(e.listed_pairs() > 2048, "{}", e.listed_pairs());
            (e.checkpoint(), bits(&e.bond_sums()))
        })
    };
    let one = run(1);
    assert_eq!(one, run(2), "flow, two threads");
    assert_eq!(one, run(3), "flow, three threads");
    let mut q = params(1e5, 16.0, 10.0, 20.0);
    q.gravity = [1.0, 0.0, 0.0];
    q.volume_fraction = 0.5;
    let prep = |threads: usize| {
        pool(threads).install(|| {
            let mut e = DemEngine::unprepared(q.clone()).unwrap();
            assert!(e.particle_count() > 1536);
            assert!(!e.prepare(600).unwrap());
            e.checkpoint()
        })
    };
    assert_eq!(prep(1), prep(2), "preparation");
}

/// The skin and the list's rebuild times change nothing: two skins, the same states and
/// histories.
#[test]
fn the_skin_changes_nothing() {
    let (p, states) = threaded_channel();
    let run = |skin: f64| {
        let mut q = p.clone();
        q.skin = skin;
        let mut e = DemEngine::from_state(q, &states, &[]).unwrap();
        e.advance_to_step(300).unwrap();
        (e.states(), e.contacts(), e.counters().rebuilds)
    };
    let (a, ca, ra) = run(0.03);
    let (b, cb, rb) = run(0.4);
    assert!(ra > rb, "{ra} vs {rb} rebuilds");
    assert_same_states(&a, &b, "skin 0.03 vs 0.4");
    same_contacts(&ca, &cb, "skin 0.03 vs 0.4");
}

/// Checkpoint at step k, restore, continue: the same bytes as the uninterrupted run, at the
/// job's synchronisation points (snapshot, then checkpoint), in the flow and in the middle of
/// a preparation.
#[test]
fn checkpoint_restore_continue_is_bitwise_the_uninterrupted_run() {
    let (p, states) = threaded_channel();
    let mut a: Box<dyn Engine> = Box::new(DemEngine::from_state(p, &states, &[]).unwrap());
    let time = |k: f64| StopAt::Time(k * 0.01);
    a.advance(time(3.0)).unwrap();
    a.snapshot();
    let bytes = a.checkpoint();
    let mut b = granflow::registry::restore(&bytes).unwrap();
    assert_eq!(
        b.checkpoint(),
        bytes,
        "a restored engine writes what it read"
    );
    for k in [5.0, 9.0] {
        a.advance(time(k)).unwrap();
        b.advance(time(k)).unwrap();
        let (sa, sb) = (a.snapshot(), b.snapshot());
        assert_eq!(sa.progress, sb.progress);
        assert_eq!(sa.counters, sb.counters);
        let (da, db) = (
            sa.sample::<granflow::engine::dem::Sample>().unwrap(),
            sb.sample::<granflow::engine::dem::Sample>().unwrap(),
        );
        assert_eq!(da.record.constants, db.record.constants);
        let (ia, ib) = (&da.record.sums, &db.record.sums);
        assert_eq!(ia.bins, ib.bins, "bins at {k}");
        assert_eq!(
            format!("{:?}", IntervalSumsNoBins(ia)),
            format!("{:?}", IntervalSumsNoBins(ib)),
            "sums at {k}"
        );
        assert_eq!(da.particles, db.particles, "particles at {k}");
        // the bond-order sums, taken in tag order: the restored engine's working order (its
        // list was built at the restore) does not enter
        assert_eq!(
            bits(&da.record.bonds),
            bits(&db.record.bonds),
            "bonds at {k}"
        );
        assert!(da.record.bonds.iter().map(|s| s.bonds).sum::<f64>() > 1000.0);
        assert_eq!(sa.content, sb.content, "snapshot at {k}");
        assert_eq!(a.checkpoint(), b.checkpoint(), "checkpoint at {k}");
    }
    // in the middle of a preparation
    let mut q = small_channel();
    q.skin = 0.1;
    let mut a = DemEngine::unprepared(q).unwrap();
    a.prepare(700).unwrap();
    let mut b = DemEngine::from_payload(&a.to_payload()).unwrap();
    a.prepare(1300).unwrap();
    b.prepare(1300).unwrap();
    assert_eq!(a.to_payload(), b.to_payload(), "preparation");
}

/// A checkpoint payload of version 1 (written before `wall_damping` existed: the state
/// alone) restores with the walls those runs had, the pair's damping, and continues as the
/// run it came from; version 2 carries the wall damping after the state.
#[test]
fn a_payload_of_version_1_restores_with_the_pairs_wall_damping() {
    use granflow::engine::dem::WallDamping;
    let p = DemParams {
        skin: 0.1,
        ..small_channel()
    };
    for wall in [WallDamping::PairRate, WallDamping::PairRestitution] {
        let mut a = DemEngine::unprepared(DemParams {
            wall_damping: wall,
            ..p.clone()
        })
        .unwrap();
        a.prepare(700).unwrap();
        let v2 = a.to_payload();
        // version 1 is version 2 without its last byte, the wall damping's variant index
        let v1 = &v2[..v2.len() - 1];
        let b = DemEngine::from_payload_of_version(2, &v2).unwrap();
        assert_eq!(b.params().wall_damping, wall);
        let c = DemEngine::from_payload_of_version(1, v1).unwrap();
        assert_eq!(c.params().wall_damping, WallDamping::PairRate);
        assert!(DemEngine::from_payload_of_version(1, &v2).is_err());
        assert!(DemEngine::from_payload_of_version(3, &v2).is_err());
        if wall == WallDamping::PairRate {
            let mut c = c;
            a.prepare(1300).unwrap();
            c.prepare(1300).unwrap();
            assert_eq!(a.to_payload(), c.to_payload());
        }
    }
}

/// The bits of bond-order sums.
fn bits(sums: &[granflow::engine::dem::BondSums]) -> Vec<u64> {
    sums.iter()
        .flat_map(|s| {
            [s.bonds, s.particles, s.local_q6]
                .into_iter()
                .chain(s.harmonics)
                .map(f64::to_bits)
        })
        .collect()
}

struct IntervalSumsNoBins<'a>(&'a granflow::engine::dem::IntervalSums);

impl std::fmt::Debug for IntervalSumsNoBins<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.0;
        write!(
            f,
            "{} {} {} {} {:?} {:?} {} {:?} {:?} {:?} {:?} {:?} {} {:?}",
            s.start_step,
            s.end_step,
            s.samples,
            s.force_steps,
            s.wall_force,
            s.wall_impulse,
            s.gravity_work,
            s.sampled_wall_force,
            s.wall_stress,
            s.wall_dissipation,
            s.com_velocity,
            s.kinetic_energy,
            s.contacts,
            s.momentum
        )
    }
}

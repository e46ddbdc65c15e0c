//! The lattice-gas engine (Peng & Herrmann 1994): exact conservation laws, the bit-parallel
//! kernel against the one-site reference, checkpoints, and the seed's physics oracles.

use granflow::engine::lga::kernel::{SiteWord, collide_word};
use granflow::engine::lga::rng::{self, Digits, Purpose, Stream};
use granflow::engine::lga::rules::{self, Rule, collide};
use granflow::engine::lga::{LgaEngine, LgaParams, LgaReference};

fn params(
    length: usize,
    width: usize,
    density: f64,
    p: f64,
    g: f64,
    b: f64,
    seed: u64,
) -> LgaParams {
    LgaParams {
        length,
        width,
        density,
        dissipation: p,
        gravity: g,
        bounce_back: b,
        seed,
    }
}

/// Rules (1)-(5) on all 128 site states and every branch: mass (with the extra rest
/// particles) and momentum are conserved exactly, and each branch occurs. Exact integers,
/// no tolerance.
#[test]
fn collision_rules_conserve_mass_and_momentum_on_all_states() {
    let th = params(8, 2, 1.0, 0.5, 0.5, 0.5, 1).thresholds();
    let mut seen = std::collections::BTreeSet::new();
    for state in 0..128u8 {
        // u on a grid fine enough to hit every branch (the thresholds are multiples of ~2^32/6)
        for i in 0..64u64 {
            let u = ((i << 32) / 64 + 12345) as u32;
            let c = collide(state, u, &th);
            assert_eq!(
                rules::mass(c.state) + u32::from(c.extras),
                rules::mass(state),
                "mass of state {state:07b}, u {u}"
            );
            assert_eq!(
                rules::momentum(c.state),
                rules::momentum(state),
                "momentum of {state:07b}"
            );
            assert!(c.state & rules::REST != 0 || c.extras == 0);
            if c.state != state {
                seen.insert((state, c.state));
            }
        }
    }
    // (1): 3 pairs x 2 turns; (2): 6 pairs x 1; (3): 2 triples x 3 axes; (4): 3; (5): 6
    assert_eq!(seen.len(), 6 + 6 + 6 + 3 + 6, "distinct changes {seen:?}");
}

/// The Boolean kernel of rules (1)-(5) equals the site table on all 128 states, for many
/// random streams (so every random branch of every state occurs), including extras.
#[test]
fn bit_parallel_collisions_equal_the_site_table() {
    let nw = 2;
    for (q, p) in [(0, 0.5), (1, 0.1), (2, 1.0), (3, 0.0)] {
        let th = params(128, 1, 1.0, p, 0.5, 0.5, 1).thresholds();
        for step in 0..200u64 {
            let stream = Stream::new(99 + q, step, Purpose::Collide);
            for w in 0..nw {
                let mut word: SiteWord = [0; 8];
                for b in 0..64 {
                    let state = (w * 64 + b) as u8;
                    for (k, plane) in word.iter_mut().take(7).enumerate() {
                        *plane |= u64::from((state >> k) & 1) << b;
                    }
                }
                let out = collide_word(&word, &mut Digits::new(&stream, 0, w, nw), &th);
                for b in 0..64 {
                    let state = (w * 64 + b) as u8;
                    let u = rng::site_uniform(&stream, nw, w * 64 + b, 0);
                    let want = collide(state, u, &th);
                    let got: u8 = (0..7).map(|k| (((out.state[k] >> b) & 1) as u8) << k).sum();
                    let extras = ((out.one_extra >> b) & 1) + 2 * ((out.two_extras >> b) & 1);
                    assert_eq!(got, want.state, "state {state:07b} p {p} step {step}");
                    assert_eq!(extras as u8, want.extras, "extras of {state:07b}");
                    let bit = |m: u64| (m >> b) & 1 == 1;
                    assert_eq!(bit(out.head_on), want.rule == Rule::HeadOn);
                    assert_eq!(
                        bit(out.dissipative_pairs),
                        want.rule == Rule::DissipativePair
                    );
                    assert_eq!(bit(out.three_body), want.rule == Rule::ThreeBody);
                }
            }
        }
    }
}

fn assert_same(kernel: &LgaEngine, reference: &LgaReference, what: &str) {
    assert_eq!(kernel.step(), reference.step());
    assert_eq!(
        kernel.occupation(),
        reference.occupation(),
        "{what}: states at step {}",
        kernel.step()
    );
    assert_eq!(
        kernel.counts(),
        reference.counts(),
        "{what}: counters at step {}",
        kernel.step()
    );
    assert_eq!(
        kernel.wall_impulse(),
        reference.wall_impulse(),
        "{what}: wall impulse"
    );
}

/// Kernel == reference step by step (states, counters, wall impulse) over several parameter
/// sets: sizes below, at and above one word per column, odd and even W, W = 1, dilute and
/// dense, smooth and rough walls, with and without gravity and dissipation.
#[test]
fn kernel_equals_reference_step_by_step() {
    let cases = [
        params(220, 11, 1.0, 0.5, 0.5, 0.5, 1),
        params(64, 4, 1.0, 0.1, 0.5, 0.5, 2),
        params(130, 5, 2.5, 0.9, 0.3, 1.0, 3),
        params(37, 3, 5.5, 0.5, 0.5, 0.0, 4),
        params(70, 2, 0.3, 1.0, 1.0, 0.5, 5),
        params(5, 1, 3.0, 0.5, 0.5, 0.5, 6),
        params(1, 3, 4.0, 0.7, 0.2, 0.3, 7),
        params(128, 6, 1.2, 0.0, 0.5, 0.5, 8),
    ];
    for p in cases {
        let what = format!("{p:?}");
        let mut k = LgaEngine::new(p.clone()).unwrap();
        let mut r = LgaReference::new(p).unwrap();
        assert_same(&k, &r, &what);
        for t in 1..=300 {
            k.advance_to(t);
            r.advance_to(t);
            assert_same(&k, &r, &what);
        }
    }
}

#[test]
#[ignore]
fn scratch_explore() {
    let args: Vec<f64> = std::env::var("LGA_ARGS")
        .unwrap_or("220 11 1.0 0.5 0.5 0.5 1 100000".into())
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    let p = params(
        args[0] as usize,
        args[1] as usize,
        args[2],
        args[3],
        args[4],
        args[5],
        args[6] as u64,
    );
    let steps = args[7] as u64;
    let mut k = LgaEngine::new(p.clone()).unwrap();
    if args.get(9).is_some() {
        let mut r = LgaReference::new(p.clone()).unwrap();
        for t in 1..=300 {
            k.advance_to(t);
            r.advance_to(t);
            assert_eq!(k.occupation(), r.occupation(), "step {t}");
        }
        println!("kernel == reference (300 steps)");
    }
    let settings = granflow::analysis::lattice::LatticeSettings::default();
    let mut recs = Vec::new();
    let every = 10;
    let mut t = 0;
    while t < steps {
        t += every;
        k.advance_to(t);
        recs.push(granflow::analysis::lattice::record(&k, &settings));
    }
    let an = granflow::analysis::lattice::analyse(&recs, &settings);
    println!("{:#?}", an.summary);
    if let Ok(path) = std::env::var("LGA_PNG") {
        granflow::analysis::lattice::plot_spacetime(&an, std::path::Path::new(&path)).unwrap();
    }
    if let Ok(path) = std::env::var("LGA_SPEC") {
        let mut txt = String::new();
        for f in &an.spectrum {
            txt.push_str(&format!("{} {} {}\n", f.frequency, f.power, f.fitted as u8));
        }
        std::fs::write(path, txt).unwrap();
    }

    let n0 = k.particle_count();
    let t0 = std::time::Instant::now();
    k.advance_to(steps);
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "sites/s {:.3e}  N {} -> {}  momentum {:?} counters {:?}",
        (p.length * p.width) as f64 * steps as f64 / dt,
        n0,
        k.particle_count(),
        k.momentum(),
        k.counters()
    );
}

//! Adding an engine, proved on a toy: an ideal gas of free-flying spheres in a periodic box,
//! declared here as docs/architecture.md's "Adding an engine" says (an `Engine`, an `EngineDef`,
//! a registry `Entry` pairing it with an analysis), goes through the path a job takes: resolve
//! the parameters, build, advance, snapshot, record, checkpoint, restore through its
//! declaration, analyse. Oracle: without collisions every sphere keeps its speed |c| = v0, so
//! the translational energy per particle is v0^2 / 2 at every snapshot (exact up to rounding),
//! and every centre stays in the box (the records count N of them).

use granflow::analysis::{Analysis, AnalysisKind};
use granflow::engine::declare::{
    BuiltEngine, InId, ParamDefault, ParamKind, check_payload_version,
};
use granflow::engine::{
    BoxGeometry, Clock, Content, Counters, Engine, EngineDef, EngineError, ParamDef, ParamValue,
    Particles, Progress, Snapshot, StopAt, Values, envelope,
};
use granflow::registry::{self, Entry};
use serde::{Deserialize, Serialize};

/// The box edge, in particle diameters.
const EDGE: f64 = 10.0;

/// The toy's declaration: two parameters, one clock, no counters.
static TOY: EngineDef = EngineDef {
    name: "toy",
    title: "free-flying spheres in a periodic box (a test's engine)",
    version: 1,
    params: &[
        ParamDef {
            name: "particles",
            symbol: "N",
            unit: "1",
            kind: ParamKind::Integer,
            default: ParamDefault::Required,
            allowed: "a whole number from 1 to 1000",
            check: |v| (1.0..=1000.0).contains(&v),
            doc: "number of spheres",
            in_id: InId::Always,
        },
        ParamDef {
            name: "speed",
            symbol: "v0",
            unit: "sqrt(g d)",
            kind: ParamKind::Real,
            default: ParamDefault::Number(1.0),
            allowed: "> 0",
            check: |v| v > 0.0,
            doc: "the speed of every sphere",
            in_id: InId::Always,
        },
    ],
    alternatives: &[],
    clocks: &[Clock::Time],
    resolve: |_| Ok(()),
    build,
    restore,
    size_name: "N",
    size: |v| v["particles"].as_f64().unwrap_or(0.0),
    work: |v, _, t| v["particles"].as_f64().unwrap_or(0.0) * t,
    work_unit: "particle moves",
    work_rate: |_| 1e8,
    memory: |v| 100.0 * v["particles"].as_f64().unwrap_or(0.0),
    counters: &[],
    ratios: &[],
    example: &[("particles", "8")],
    example_run: (Clock::Time, 10.0, 1.0),
};

/// The one line a registry would hold for it (registry::ENGINES is a static list; the test
/// pairs the toy the same way).
static TOY_ENTRY: Entry = Entry {
    engine: &TOY,
    analysis: AnalysisKind::Structure,
};

/// The toy's state (also its checkpoint payload).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Toy {
    time: f64,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
}

fn build(values: &Values, seed: u64) -> BuiltEngine {
    let n = values["particles"].as_f64().unwrap() as usize;
    let speed = values["speed"].as_f64().unwrap();
    // spheres on a line through the box, each moving along one axis, direction by seed
    let positions = (0..n)
        .map(|i| {
            let s = (i as f64 + 0.5) / n as f64 * EDGE;
            [s, (s * 3.0) % EDGE, (s * 7.0) % EDGE]
        })
        .collect();
    let velocities = (0..n)
        .map(|i| {
            let mut c = [0.0; 3];
            let sign = if (seed >> (i % 64)) & 1 == 1 {
                -1.0
            } else {
                1.0
            };
            c[i % 3] = sign * speed;
            c
        })
        .collect();
    Ok(Box::new(Toy {
        time: 0.0,
        positions,
        velocities,
    }))
}

fn restore(version: u32, payload: &[u8]) -> BuiltEngine {
    check_payload_version("toy", version, 1)?;
    let toy: Toy = serde_json::from_slice(payload)
        .map_err(|e| EngineError::Checkpoint(format!("toy payload: {e}")))?;
    Ok(Box::new(toy))
}

impl Engine for Toy {
    fn def(&self) -> &'static EngineDef {
        &TOY
    }
    fn particle_count(&self) -> usize {
        self.positions.len()
    }
    fn progress(&self) -> Progress {
        Progress {
            time: self.time,
            ..Progress::default()
        }
    }
    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        let StopAt::Time(t) = stop else {
            return Err(TOY.clock_error(stop.clock()));
        };
        let dt = t - self.time;
        for (r, c) in self.positions.iter_mut().zip(&self.velocities) {
            for d in 0..3 {
                r[d] = (r[d] + c[d] * dt).rem_euclid(EDGE);
            }
        }
        self.time = t;
        Ok(())
    }
    fn snapshot(&mut self) -> Snapshot {
        let energy = self
            .velocities
            .iter()
            .map(|c| 0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]))
            .sum();
        Snapshot {
            progress: self.progress(),
            counters: Counters::default(),
            content: Content::Particles(Particles {
                geometry: BoxGeometry {
                    length: EDGE,
                    width: EDGE,
                    height: EDGE,
                    walls: false,
                },
                inertia_factor: 0.4,
                gravity: 0.0,
                positions: self.positions.clone(),
                velocities: self.velocities.clone(),
                angular_velocities: Vec::new(),
                diameters: Vec::new(),
                translational_energy: energy,
                rotational_energy: 0.0,
                wall_momentum: [[0.0; 3]; 2],
                energy_dissipated: 0.0,
                gravity_work: 0.0,
                suppressed_dissipation: 0.0,
            }),
        }
    }
    fn checkpoint(&self) -> Vec<u8> {
        envelope::seal(TOY.name, 1, &serde_json::to_vec(self).unwrap())
    }
}

#[test]
fn a_toy_engine_goes_through_the_path_of_a_job() {
    let given: Values = [("particles".to_string(), ParamValue::Number(27.0))].into();
    let values = TOY.resolve_values(&given).expect("valid parameters");
    assert_eq!(
        values["speed"],
        ParamValue::Number(1.0),
        "the default filled in"
    );
    let bad: Values = [("particles".to_string(), ParamValue::Number(0.0))].into();
    let problem = TOY.resolve_values(&bad).unwrap_err();
    assert_eq!(problem.key, "particles");
    assert!(
        problem
            .message
            .contains("allowed a whole number from 1 to 1000")
    );

    let mut engine = (TOY.build)(&values, 0b1011).expect("builds");
    let analyser = TOY_ENTRY
        .analysis
        .analyser(&serde_json::Value::Null)
        .unwrap();
    let mut records = vec![analyser.record_with(&engine.snapshot(), 0, None).unwrap()];
    for k in 1..=12 {
        engine.advance(StopAt::Time(0.7 * k as f64)).unwrap();
        let snapshot = engine.snapshot();
        records.push(analyser.record_with(&snapshot, k, None).unwrap());
    }
    assert!(matches!(
        engine.advance(StopAt::Steps(20)),
        Err(EngineError::Clock { engine: "toy", .. })
    ));

    // the checkpoint restores through the toy's declaration, to the same trajectory
    let sealed_bytes = engine.checkpoint();
    let sealed = envelope::open(&sealed_bytes).unwrap();
    assert_eq!(sealed.engine, "toy");
    let mut resumed = (TOY.restore)(sealed.version, sealed.payload).unwrap();
    engine.advance(StopAt::Time(10.0)).unwrap();
    resumed.advance(StopAt::Time(10.0)).unwrap();
    assert_eq!(engine.snapshot(), resumed.snapshot());
    // and only through it: the registry, the one list of engines, does not know the toy
    let unknown = registry::restore(&sealed_bytes)
        .err()
        .expect("not registered");
    assert!(
        unknown
            .to_string()
            .contains("written by the engine \"toy\", which this granflow does not have"),
        "{unknown}"
    );

    for (k, r) in records.iter().enumerate() {
        let s = r.structure().expect("a structure record");
        assert!((s.time - 0.7 * k as f64).abs() < 1e-12);
        assert!((s.translational_energy - 0.5).abs() < 1e-14, "v0^2/2");
        assert_eq!(s.particles, 27);
    }
    let Analysis::Structure(a) = analyser.analyse(&records).unwrap() else {
        panic!("the structure analysis gives a structure result");
    };
    assert_eq!(a.energy.len(), records.len());
    assert!(
        a.energy
            .iter()
            .all(|e| (e.translational - 0.5).abs() < 1e-14)
    );
}

/// The engine layer imports nothing above itself: no module under src/engine names the
/// analyses, the registry, sweeps, reports, Slurm or the command line (the registry pairs
/// engines with analyses from above).
#[test]
fn the_engine_layer_imports_nothing_above_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/engine");
    let above = [
        "analysis",
        "registry",
        "sweep",
        "report",
        "slurm",
        "cli",
        "job_figures",
    ];
    let mut found = Vec::new();
    let mut dirs = vec![root];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for (i, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("");
                for layer in above {
                    if code.contains(&format!("crate::{layer}")) {
                        found.push(format!("{}:{}: {}", path.display(), i + 1, line.trim()));
                    }
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "imports from above the engine layer:\n{}",
        found.join("\n")
    );
}

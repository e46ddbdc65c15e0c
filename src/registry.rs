//! The registry: the one list of the engines granflow has, each paired with the analysis its
//! snapshots feed. It stands above the engines ([`crate::engine`], which import nothing above
//! themselves) and the analyses ([`crate::analysis`]), and below everything that runs jobs.
//! Adding an engine means writing it with its declaration ([`EngineDef`], next to its code) and
//! adding one [`Entry`] here; sweep files, ids, tables, `sim`, `plan` and the parameter tables
//! of docs/parameters.md follow from the declaration.
//!
//! From a name to a job's first snapshot and its record:
//! ```
//! use granflow::engine::Values;
//! use granflow::registry;
//!
//! let lga = registry::find("lga").expect("the lattice gas is registered");
//! let mut values = Values::new();
//! for (key, text) in lga.example {
//!     values.insert(key.to_string(), lga.param(key).unwrap().parse_text(text).unwrap());
//! }
//! let values = lga.resolve_values(&values).expect("the example parameters are valid");
//! let mut engine = (lga.build)(&values, 1).expect("the engine builds");
//! let snapshot = engine.snapshot();
//! assert_eq!(snapshot.progress.steps, 0);
//! let analyser = registry::analysis_of(lga).analyser(&serde_json::Value::Null).unwrap();
//! let record = analyser.record(&snapshot).expect("the lattice analysis reads a lattice");
//! assert_eq!(record.time(), 0.0);
//! ```

use crate::analysis::AnalysisKind;
use crate::engine::{Engine, EngineDef, EngineError, envelope};

/// An engine and the analysis its snapshots feed.
#[derive(Debug)]
pub struct Entry {
    pub engine: &'static EngineDef,
    pub analysis: AnalysisKind,
}

/// Every engine, in the order `granflow engines` lists them.
pub static ENGINES: &[Entry] = &[
    Entry {
        engine: &crate::engine::edmd::DECLARATION,
        analysis: AnalysisKind::Structure,
    },
    Entry {
        engine: &crate::engine::lga::DECLARATION,
        analysis: AnalysisKind::Lattice,
    },
    Entry {
        engine: &crate::engine::dsmc::DECLARATION,
        analysis: AnalysisKind::Rarefied,
    },
    Entry {
        engine: &crate::engine::dem::DECLARATION,
        analysis: AnalysisKind::Dense,
    },
];

/// The engines' declarations, in registry order.
pub fn engines() -> impl Iterator<Item = &'static EngineDef> {
    ENGINES.iter().map(|e| e.engine)
}

/// The engine of this name.
pub fn find(name: &str) -> Option<&'static EngineDef> {
    engines().find(|e| e.name == name)
}

/// The analysis the snapshots of a registered engine feed.
///
/// # Panics
/// When the engine is not in [`ENGINES`] (every declaration a job or sweep names comes from
/// [`find`]).
pub fn analysis_of(engine: &EngineDef) -> AnalysisKind {
    ENGINES
        .iter()
        .find(|e| e.engine.name == engine.name)
        .map(|e| e.analysis)
        .unwrap_or_else(|| panic!("the {} engine is not in the registry", engine.name))
}

/// The engine names, quoted and comma separated (for error messages).
pub fn names() -> String {
    engines()
        .map(|e| format!("\"{}\"", e.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The engines (other than `except`) that have a parameter of this name.
pub fn engines_with_param(name: &str, except: &str) -> Vec<&'static str> {
    engines()
        .filter(|e| e.name != except && e.param(name).is_some())
        .map(|e| e.name)
        .collect()
}

/// The names of the engines whose analysis is of this kind, comma separated.
pub fn engines_analysed_by(accepts: impl Fn(AnalysisKind) -> bool) -> String {
    ENGINES
        .iter()
        .filter(|e| accepts(e.analysis))
        .map(|e| e.engine.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// `the "edmd" engine`, `the "edmd" and "dsmc" engines`, `the "a", "b" and "c" engines`.
pub fn engines_phrase(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
    match quoted.as_slice() {
        [] => "no engine".into(),
        [one] => format!("the {one} engine"),
        [init @ .., last] => format!("the {} and {last} engines", init.join(", ")),
    }
}

/// Rebuild an engine from checkpoint bytes written by [`Engine::checkpoint`]: the envelope
/// names the engine, whose declaration restores it.
pub fn restore(bytes: &[u8]) -> Result<Box<dyn Engine>, EngineError> {
    let sealed = envelope::open(bytes)?;
    let def = find(&sealed.engine).ok_or_else(|| {
        EngineError::Checkpoint(format!(
            "written by the engine \"{}\", which this granflow does not have (engines: {})",
            sealed.engine,
            names()
        ))
    })?;
    (def.restore)(sealed.version, sealed.payload)
}

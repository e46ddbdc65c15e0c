//! The registry: the one list of the engines granflow has. Adding an engine means writing its
//! declaration ([`super::EngineDef`], next to its code) and adding it here; sweep files, ids,
//! tables, `sim`, `plan` and the parameter tables of docs/parameters.md follow from the declaration.

use super::EngineDef;

/// Every engine, in the order `granflow engines` lists them.
pub static ENGINES: &[&EngineDef] = &[
    &super::edmd::DECLARATION,
    &super::lga::DECLARATION,
    &super::dsmc::DECLARATION,
    &super::dem::DECLARATION,
];

/// The engine of this name.
pub fn find(name: &str) -> Option<&'static EngineDef> {
    ENGINES.iter().copied().find(|e| e.name == name)
}

/// The engine names, quoted and comma separated (for error messages).
pub fn names() -> String {
    ENGINES
        .iter()
        .map(|e| format!("\"{}\"", e.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The engines (other than `except`) that have a parameter of this name.
pub fn engines_with_param(name: &str, except: &str) -> Vec<&'static str> {
    ENGINES
        .iter()
        .filter(|e| e.name != except && e.param(name).is_some())
        .map(|e| e.name)
        .collect()
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

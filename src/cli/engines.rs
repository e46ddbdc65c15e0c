//! `granflow engines`: the registry's engines with their parameters, clocks and counters;
//! `--markdown` prints the parameter tables of docs/parameters.md (generated, so the document
//! cannot drift from the declarations: a test compares them).

use super::out::{out, outln};
use crate::registry;
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow engines              # every engine: its parameters (symbol, unit, default,
                                # allowed values, meaning), clocks and counters
  granflow engines --markdown   # the parameter tables of docs/parameters.md")]
pub struct EnginesArgs {
    /// print the parameter tables as markdown (the ones docs/parameters.md shows)
    #[arg(long)]
    pub markdown: bool,
}

/// The parameter tables of docs/parameters.md: one heading line and table per engine.
pub fn markdown() -> String {
    let mut out = String::new();
    for e in registry::engines() {
        out.push_str(&format!(
            "`engine: \"{}\"`: {}. Run length: {}.\n\n",
            e.name,
            e.title,
            e.clocks
                .iter()
                .map(|c| format!("`{}`", c.key()))
                .collect::<Vec<_>>()
                .join(" or ")
        ));
        out.push_str(&e.markdown_table());
        out.push('\n');
    }
    out
}

/// A parameter's default as the tables show it: a number, a name, "required" or "derived".
pub fn default_text(default: &crate::engine::declare::ParamDefault) -> String {
    use crate::engine::declare::ParamDefault;
    match default {
        ParamDefault::Required => "required".to_string(),
        ParamDefault::Derived => "derived".to_string(),
        ParamDefault::Number(v) => format!("{v}"),
        ParamDefault::Text(s) => format!("\"{s}\""),
    }
}

pub fn run(args: EnginesArgs) -> anyhow::Result<()> {
    if args.markdown {
        out!("{}", markdown());
        return Ok(());
    }
    for e in registry::engines() {
        outln!("{}: {}", e.name, e.title);
        outln!("  run length: {}", e.clock_names());
        outln!(
            "  {:<22} {:<7} {:<9} {:<10} allowed",
            "key",
            "symbol",
            "unit",
            "default"
        );
        for d in e.params {
            outln!(
                "  {:<22} {:<7} {:<9} {:<10} {}",
                d.name,
                d.symbol,
                d.unit,
                default_text(&d.default),
                d.allowed
            );
            outln!("  {:<22} {}", "", d.doc);
        }
        outln!(
            "  counters: {}",
            e.counters
                .iter()
                .map(|c| c.name)
                .collect::<Vec<_>>()
                .join(", ")
        );
        outln!("  analysis: {:?}", registry::analysis_of(e));
    }
    Ok(())
}

//! Engine parameters as command-line flags, generated from the registry: every declared
//! parameter of every engine is a flag `--<name with - for _>` (help heading "Engine
//! parameters"), so a new engine's parameters appear in `granflow sim --help` without code here.

use crate::registry;
use clap::{Arg, ArgMatches, Args, Command, FromArgMatches};

/// The engine-parameter flags given on the command line: (parameter name, text), in the order
/// of the registry's declarations.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamFlags(pub Vec<(&'static str, String)>);

/// Each parameter name once (engines may share a name), with the engines that declare it.
fn flag_params() -> Vec<(&'static crate::engine::ParamDef, Vec<&'static str>)> {
    let mut out: Vec<(&'static crate::engine::ParamDef, Vec<&'static str>)> = Vec::new();
    for engine in registry::engines() {
        for def in engine.params {
            match out.iter_mut().find(|(d, _)| d.name == def.name) {
                Some((_, engines)) => engines.push(engine.name),
                None => out.push((def, vec![engine.name])),
            }
        }
    }
    out
}

impl FromArgMatches for ParamFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut out = Vec::new();
        for (def, _) in flag_params() {
            if let Some(v) = matches.get_one::<String>(def.name) {
                out.push((def.name, v.clone()));
            }
        }
        Ok(ParamFlags(out))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for ParamFlags {
    fn augment_args(cmd: Command) -> Command {
        let mut cmd = cmd.next_help_heading("Engine parameters");
        for (def, engines) in flag_params() {
            cmd = cmd.arg(
                Arg::new(def.name)
                    .long(def.name.replace('_', "-"))
                    .value_name(def.symbol)
                    .help(format!(
                        "{}: {} [{}; {}]",
                        def.symbol,
                        def.doc,
                        engines.join(", "),
                        def.allowed
                    )),
            );
        }
        cmd.next_help_heading(None::<&str>)
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

//! The `granflow` command: parse arguments, dispatch, print errors with their cause chain.

use std::process::ExitCode;

fn main() -> ExitCode {
    granflow::cli::main()
}

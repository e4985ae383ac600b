//! `higraph-lsp`: the HiGraph language server and command-line checker.
//!
//! `main` only dispatches; the subcommands live in [`cli`].

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::run()
}

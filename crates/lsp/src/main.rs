//! `higraph-lsp`: the HiGraph language server and command-line checker.
//!
//! `main` only dispatches; the subcommands live in [`cli`], the language server in
//! [`server`].

mod cli;
mod server;
mod workspace;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::run()
}

//! `higraph-lsp`: the HiGraph language server and command-line checker.
//!
//! `main` only dispatches; the subcommands live in [`cli`], the language server in
//! [`server`].

mod build;
mod cli;
mod server;
mod testing;
mod workspace;

use std::process::ExitCode;

/// Stack size of the threads that analyse: the command line's and the server's. The parser's
/// nesting limit (`higraph_syntax::NESTING_LIMIT`) bounds every recursive walk of the analysis
/// to a small fraction of the default 2 MiB (8 MiB for the main thread); the generous size is
/// a second line of defence, and only address space until it is touched.
pub(crate) const ANALYSIS_STACK_SIZE: usize = 64 << 20;

fn main() -> ExitCode {
    // The command runs on a thread of its own for the stack size; if that thread cannot be
    // started, it runs here.
    match std::thread::Builder::new()
        .name("higraph-lsp".into())
        .stack_size(ANALYSIS_STACK_SIZE)
        .spawn(cli::run)
    {
        Ok(thread) => thread
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
        Err(_) => cli::run(),
    }
}

//! End-to-end tests of the `higraph-lsp` command line: the real binary, run as a user would
//! run it, on files written to temporary folders (`tooling.md` §1, §2; `diagnostics.md` §4).

#[path = "cli/support.rs"]
mod support;

#[path = "cli/check.rs"]
mod check;
#[path = "cli/explain.rs"]
mod explain;
#[path = "cli/fmt.rs"]
mod fmt;
#[path = "cli/parse.rs"]
mod parse;
#[path = "cli/paths.rs"]
mod paths;
#[path = "cli/render.rs"]
mod render;
#[path = "cli/sarif.rs"]
mod sarif;
#[path = "cli/terminal.rs"]
mod terminal;

//! End-to-end tests of the language server (`tooling.md` §4): the real `higraph-lsp` binary
//! driven over stdio by a small JSON-RPC client, as an editor drives it.

#[path = "lsp/client.rs"]
mod client;

#[path = "lsp/action_resolve.rs"]
mod action_resolve;
#[path = "lsp/build.rs"]
mod build;
#[path = "lsp/calls.rs"]
mod calls;
#[path = "lsp/diagnostics.rs"]
mod diagnostics;
#[path = "lsp/features.rs"]
mod features;
#[path = "lsp/format_tokens.rs"]
mod format_tokens;
#[path = "lsp/lenses.rs"]
mod lenses;
#[path = "lsp/lifecycle.rs"]
mod lifecycle;
#[path = "lsp/links.rs"]
mod links;
#[path = "lsp/pull.rs"]
mod pull;
#[path = "lsp/robustness.rs"]
mod robustness;
#[path = "lsp/signature_help.rs"]
mod signature_help;
#[path = "lsp/testing.rs"]
mod testing;

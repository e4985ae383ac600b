//! Hardening tests of the real binary (issue 10): the file system cases — FIFOs, devices,
//! links out of the workspace, link loops, dangling links, folders named like sources,
//! oversized files, `fmt` and `render -o` writes — each run with a timeout so that a hang
//! fails the test instead of blocking CI; and a seeded random language-server session that
//! ends by comparing the published diagnostics with `check --format json` on the same texts.

#[allow(dead_code)]
#[path = "lsp/client.rs"]
mod client;

#[cfg(unix)]
#[path = "robustness/files.rs"]
mod files;
#[path = "robustness/session.rs"]
mod session;

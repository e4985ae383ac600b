//! Semantic analysis of HiGraph workspaces, independent of any editor protocol.
//!
//! The crate owns everything the command line and the language server have in common: the
//! salsa database ([`db`]) from file texts to diagnostics, the rules of `diagnostics.md`
//! ([`rules`]), the diagnostic model ([`Diagnostic`], [`Severity`], [`Code`]), the
//! configuration ([`config`]), and the conversion between byte offsets and line/column
//! positions ([`LineIndex`]).
//!
//! It knows nothing of LSP types and does no file I/O: callers read files and hand their
//! contents to an [`AnalysisHost`].

pub mod address;
pub mod build;
mod check;
pub mod closest;
pub mod config;
pub mod db;
pub mod diag;
mod diagnostic;
mod file_contents;
#[doc(hidden)]
pub mod fixture_workspace;
pub mod format;
mod host;
pub mod ide;
pub mod iec;
pub mod index;
pub mod lang;
mod line_index;
pub mod lower;
pub mod model;
pub mod registry;
pub mod render;
mod resolve;
pub mod rules;
pub mod sdf;
pub mod suppress;

pub use diagnostic::{
    Code, Diagnostic, DiagnosticTag, FileId, Fix, PendingRename, RelatedInfo, Severity, TextEdit,
};
pub use file_contents::FileContents;
pub use host::{Analysis, AnalysisHost, Cancellable, OutputFile, WorkspaceData};
pub use line_index::{LineColumn, LineIndex, Position, PositionEncoding};

pub use higraph_syntax::{TextRange, TextSize};

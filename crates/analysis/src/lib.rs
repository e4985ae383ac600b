//! Semantic analysis of HiGraph workspaces, independent of any editor protocol.
//!
//! This crate owns everything the command line and the language server have in common:
//! the diagnostic model ([`Diagnostic`], [`Severity`], [`Code`]), the conversion between byte
//! offsets and line/column positions in every encoding an editor may ask for ([`LineIndex`]),
//! and the computation of each file's diagnostics ([`file_diagnostics`]).
//!
//! It knows nothing of LSP types and does no file I/O: callers read files and hand their
//! contents in as [`FileContents`]. Today the diagnostics are the syntax errors of each file;
//! the salsa database (files → parse → item tree → semantic model → diagnostics) will replace
//! [`file_diagnostics`] with a workspace-wide computation producing the same model per file.

mod check;
mod diagnostic;
mod file_contents;
mod line_index;

pub use check::file_diagnostics;
pub use diagnostic::{
    Code, Diagnostic, DiagnosticTag, FileId, Fix, RelatedInfo, Severity, TextEdit,
};
pub use file_contents::FileContents;
pub use line_index::{LineColumn, LineIndex, Position, PositionEncoding};

pub use higraph_syntax::{TextRange, TextSize};

//! Editor features, one module per feature, each an `impl Analysis` block with its tests at
//! the bottom. Positions are byte offsets into a file's text; the language server converts
//! them to and from the client's encoding. Every method runs on a snapshot and returns
//! [`Cancellable`](crate::Cancellable): `Err` when an edit arrived meanwhile.
//!
//! | module            | feature |
//! |-------------------|---------|
//! | `defs`            | what a position refers to; all references of a definition |
//! | `goto_definition` | go to definition |
//! | `references`      | find all references (go-to-usage) |
//! | `highlights`      | document highlights with read/write kind |
//! | `rename`          | prepare rename and workspace-wide rename |
//! | `hover`           | hover text |
//! | `completion`      | context-aware completion |
//! | `signature_help`  | formals of an instance's graph, a CALL's block interface, a qualifier |
//! | `inlay_hints`     | state names after `trans a->b`, formal types after actuals |
//! | `symbols`         | document symbols (hierarchical) and workspace symbols |
//! | `semantic_tokens` | semantic highlighting |
//! | `folding`         | folding ranges and selection ranges |
//! | `code_actions`    | quick fixes from diagnostics; formatting edits |
//! | `range_format`    | range formatting: the canonical layout of the items a range touches |
//! | `document_links`  | symbol-table paths in `higraph.toml`, codes in `higraph-allow` comments |
//! | `call_hierarchy`  | group → instances → graphs, and message flow between instances |
//! | `code_lens`       | counts above graphs, groups, states and symbols (resolved lazily) |

use higraph_syntax::{TextRange, TextSize};

mod call_hierarchy;
mod code_actions;
mod code_lens;
mod completion;
pub mod defs;
mod document_links;
#[cfg(test)]
pub(crate) mod fixture;
mod folding;
mod goto_definition;
mod highlights;
mod hover;
mod inlay_hints;
pub(crate) mod range_format;
mod references;
pub(crate) mod relayout;
pub(crate) mod rename;
mod semantic_tokens;
mod signature_help;
mod symbols;

pub use call_hierarchy::{Call, CallItem};
pub use code_actions::CodeAction;
pub use code_lens::{CodeLens, LensKind, ResolvedLens};
pub use completion::{CompletionItem, CompletionKind};
pub use document_links::{DocumentLink, LinkTarget};
pub use folding::{Fold, FoldKind};
pub use highlights::HighlightKind;
pub use hover::Hover;
pub use inlay_hints::{InlayHint, InlayKind};
pub use semantic_tokens::{SemanticToken, TOKEN_KINDS, TOKEN_MODIFIERS, TokenKind, TokenModifier};
pub use signature_help::{SignatureHelp, SignatureKind, SignatureParameter};
pub use symbols::DocumentSymbol;

/// A position in a workspace file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct FilePosition {
    /// Workspace-relative path.
    pub path: String,
    pub offset: TextSize,
}

/// A range in a workspace file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct FileRange {
    pub path: String,
    pub range: TextRange,
}

/// One replacement in a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Edit {
    pub range: TextRange,
    pub new_text: String,
}

/// Edits to several files, applied together.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SourceChange {
    /// Per file (workspace-relative path), non-overlapping edits sorted by range.
    pub files: Vec<(String, Vec<Edit>)>,
}

impl SourceChange {
    /// Adds an edit, keeping files and edits sorted.
    pub fn insert(&mut self, path: &str, edit: Edit) {
        let index = match self.files.binary_search_by(|(p, _)| p.as_str().cmp(path)) {
            Ok(i) => i,
            Err(i) => {
                self.files.insert(i, (path.to_owned(), Vec::new()));
                i
            }
        };
        let edits = &mut self.files[index].1;
        // After any edit at the same offset: insertions keep their order.
        let at = edits.partition_point(|e| e.range.start() <= edit.range.start());
        if !edits.contains(&edit) {
            edits.insert(at, edit);
        }
    }
}

/// What kind of thing a symbol or target is (for icons and document symbols).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SymbolKind {
    Graph,
    Group,
    Chart,
    Symbol,
    BlockInterface,
    Variable,
    Message,
    PredefinedVariable,
    State,
    Transition,
    Instance,
    Sequencer,
    Step,
    ChartTransition,
    Section,
    /// A `test` item.
    Test,
}

/// Something to navigate to.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NavigationTarget {
    pub path: String,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The name (what to select).
    pub focus_range: TextRange,
    pub name: String,
    pub kind: SymbolKind,
}

//! Lossless, resilient syntax for the HiGraph language.
//!
//! `parse(text)` never fails: it returns a rowan tree whose text is exactly the input, plus the
//! syntax diagnostics (HG0xxx) of `diagnostics.md` §3.0. Typed accessors over the tree live in
//! [`ast`]. This crate knows nothing of salsa, workspaces or the LSP.

pub mod ast;
mod error;
mod kind;
pub mod lexer;
pub mod literal;
mod parser;
mod reparse;
mod validation;

use std::fmt::Write;

pub use error::{ErrorCode, Fix, Related, SyntaxError, TextEdit};
pub use kind::{HiGraphLanguage, SyntaxElement, SyntaxKind, SyntaxNode, SyntaxToken};
pub use parser::NESTING_LIMIT;
pub use reparse::Edit;
pub use rowan::{self, GreenNode, TextRange, TextSize, WalkEvent};

/// The result of parsing one file: the green tree and the syntax diagnostics.
#[derive(Debug, Clone)]
pub struct Parse {
    green: GreenNode,
    errors: Vec<SyntaxError>,
}

impl PartialEq for Parse {
    fn eq(&self, other: &Parse) -> bool {
        green_eq(&self.green, &other.green) && self.errors == other.errors
    }
}

impl Eq for Parse {}

/// Structural equality of two green trees that skips shared subtrees: after an incremental
/// reparse only the edited path is new, so comparing two versions of a tree costs the width
/// of that path, not the size of the tree (rowan's own `==` walks everything).
pub fn green_eq(a: &rowan::GreenNodeData, b: &rowan::GreenNodeData) -> bool {
    if std::ptr::eq(a, b) {
        return true;
    }
    if a.kind() != b.kind()
        || a.text_len() != b.text_len()
        || a.children().len() != b.children().len()
    {
        return false;
    }
    a.children().zip(b.children()).all(|pair| match pair {
        (rowan::NodeOrToken::Node(x), rowan::NodeOrToken::Node(y)) => green_eq(x, y),
        (rowan::NodeOrToken::Token(x), rowan::NodeOrToken::Token(y)) => x == y,
        _ => false,
    })
}

impl Parse {
    /// The root of the syntax tree (a `SOURCE_FILE` node).
    pub fn syntax_node(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.green.clone())
    }

    /// The typed root.
    pub fn tree(&self) -> ast::SourceFile {
        ast::SourceFile {
            syntax: self.syntax_node(),
        }
    }

    /// The green tree (cheap to clone, `Send + Sync`).
    pub fn green(&self) -> &GreenNode {
        &self.green
    }

    /// The syntax diagnostics, sorted by position.
    pub fn errors(&self) -> &[SyntaxError] {
        &self.errors
    }

    /// The tree in rowan's debug format, one node or token per line, tokens as
    /// `KIND@start..end "text"` — the format of `higraph-lsp parse` and the parser tests.
    pub fn debug_tree(&self) -> String {
        debug_tree(&self.syntax_node())
    }
}

/// At most this many syntax errors of one file are listed; the rest are summarised by one
/// HG0013 at the first of them. A file with more has lost its structure (a binary file, a
/// megabyte of `>`), and listing every error, each with its quick fix, would make the output
/// grow far beyond the problem.
pub const MAX_SYNTAX_ERRORS: usize = 100;

impl Parse {
    fn new(green: GreenNode, mut errors: Vec<SyntaxError>) -> Parse {
        errors.sort_by_key(|e| (e.range.start(), e.range.end(), e.code));
        if errors.len() > MAX_SYNTAX_ERRORS {
            let unlisted = errors.len() - MAX_SYNTAX_ERRORS;
            let first = errors[MAX_SYNTAX_ERRORS].range;
            errors.truncate(MAX_SYNTAX_ERRORS);
            let message = if unlisted == 1 {
                "1 more syntax error in this file is not listed".to_owned()
            } else {
                format!("{unlisted} more syntax errors in this file are not listed")
            };
            errors.push(SyntaxError::new(ErrorCode::HG0013, first, message));
        }
        Parse { green, errors }
    }

    /// Were some syntax errors summarised by HG0013 ([`MAX_SYNTAX_ERRORS`])?
    pub fn errors_summarised(&self) -> bool {
        self.errors
            .last()
            .is_some_and(|e| e.code == ErrorCode::HG0013)
    }
}

/// Parses one file. Never fails, never panics; the tree's text equals `text`.
pub fn parse(text: &str) -> Parse {
    let (green, errors) = parser::parse(text);
    Parse::new(green, errors)
}

/// Prints a subtree: nodes as `KIND@start..end`, tokens as `KIND@start..end "text"`, indented by
/// depth.
pub fn debug_tree(node: &SyntaxNode) -> String {
    let mut out = String::new();
    let mut depth = 0usize;
    for event in node.preorder_with_tokens() {
        match event {
            WalkEvent::Enter(element) => {
                let _ = write!(out, "{:indent$}", "", indent = depth * 2);
                match element {
                    rowan::NodeOrToken::Node(n) => {
                        let _ = writeln!(out, "{:?}@{:?}", n.kind(), n.text_range());
                    }
                    rowan::NodeOrToken::Token(t) => {
                        let _ = writeln!(out, "{:?}@{:?} {:?}", t.kind(), t.text_range(), t.text());
                    }
                }
                depth += 1;
            }
            WalkEvent::Leave(_) => depth -= 1,
        }
    }
    out
}

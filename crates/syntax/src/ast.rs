//! Typed accessors over the syntax tree, in the style of rust-analyzer's `ast` module.
use crate::SyntaxNode;

/// The root of a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SourceFile {
    pub(crate) syntax: SyntaxNode,
}

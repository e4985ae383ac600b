//! Text edits shared by the quick fixes of graphs and of declarations: removing a construct
//! with the white space in front of it, and inserting a new member on its own line.

use higraph_syntax::{SyntaxKind, SyntaxNode, TextRange};

/// The range that removes `node` together with the white space directly before it.
pub(super) fn removal_range(node: &SyntaxNode) -> TextRange {
    let range = node.text_range();
    let before = node
        .first_token()
        .and_then(|t| t.prev_token())
        .filter(|t| t.kind() == SyntaxKind::WHITESPACE);
    match before {
        Some(ws) => TextRange::new(ws.text_range().start(), range.end()),
        None => range,
    }
}

/// The indentation of the line `node` starts on (`"  "` if it cannot be told).
pub(super) fn indentation(node: &SyntaxNode) -> String {
    node.first_token()
        .and_then(|t| t.prev_token())
        .filter(|t| t.kind() == SyntaxKind::WHITESPACE)
        .and_then(|t| {
            t.text()
                .rsplit_once('\n')
                .map(|(_, indent)| indent.to_owned())
        })
        .unwrap_or_else(|| "  ".to_owned())
}

/// An insertion of `member` on a new line after `node`, indented like `node`.
pub(super) fn insert_member_after(node: &SyntaxNode, member: &str) -> (TextRange, String) {
    let at = TextRange::empty(node.text_range().end());
    (at, format!("\n{}{member}", indentation(node)))
}

/// The range of an item without its closing `;` (`wait T#2S` of `wait T#2S;`), like a
/// statement's range (§2.3).
pub(super) fn without_semi(node: &SyntaxNode) -> TextRange {
    let mut tokens = node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia());
    let Some(first) = tokens.next() else {
        return node.text_range();
    };
    let last = tokens
        .filter(|t| t.kind() != SyntaxKind::SEMI)
        .last()
        .unwrap_or_else(|| first.clone());
    TextRange::new(first.text_range().start(), last.text_range().end())
}

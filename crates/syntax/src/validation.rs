//! Checks over the finished tree that need no parser state: constants (HG0006, HG0007).
//!
//! Typed and character constants are checked wherever they stand (the lexer made them one
//! token); plain numbers only where they are constants (LITERAL nodes), since a state number or
//! a byte address is not a constant.

use crate::{SyntaxError, SyntaxKind::*, SyntaxNode, literal::check_literal, rowan::NodeOrToken};

pub(crate) fn validate(root: &SyntaxNode, errors: &mut Vec<SyntaxError>) {
    for element in root.descendants_with_tokens() {
        let (text, range) = match &element {
            NodeOrToken::Token(token) => match token.kind() {
                TYPED_CONST => (token.text().to_owned(), token.text_range()),
                // An unclosed constant already has HG0005.
                CHAR if is_closed_char(token.text()) => {
                    (token.text().to_owned(), token.text_range())
                }
                _ => continue,
            },
            NodeOrToken::Node(node) if node.kind() == LITERAL => {
                let is_number = node
                    .children_with_tokens()
                    .filter_map(|e| e.into_token())
                    .any(|t| t.kind() == NUMBER);
                if !is_number {
                    continue;
                }
                (node.text().to_string(), node.text_range())
            }
            NodeOrToken::Node(_) => continue,
        };
        if let Err(error) = check_literal(&text) {
            errors.push(SyntaxError::new(
                error.code.error_code(),
                range,
                error.message,
            ));
        }
    }
}

fn is_closed_char(text: &str) -> bool {
    crate::lexer::is_closed_char(text)
}

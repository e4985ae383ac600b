//! Placeholder: every token directly under SOURCE_FILE. Replaced by the real parser.
use rowan::{GreenNode, GreenNodeBuilder, TextSize};

use crate::{SyntaxError, SyntaxKind, lexer};

pub(crate) fn parse(text: &str) -> (GreenNode, Vec<SyntaxError>) {
    let mut builder = GreenNodeBuilder::new();
    let mut errors = Vec::new();
    builder.start_node(SyntaxKind::SOURCE_FILE.into());
    let mut offset = TextSize::from(0);
    for token in lexer::tokenize(text) {
        lexer::token_errors(token, offset, &mut errors);
        builder.token(token.kind.into(), token.text);
        offset += TextSize::of(token.text);
    }
    builder.finish_node();
    (builder.finish(), errors)
}

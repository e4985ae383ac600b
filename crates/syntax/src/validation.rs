//! Checks of constants (HG0006, HG0007), called by the parser as it builds the tree.
//!
//! Typed and character constants are checked wherever they stand (the lexer made them one
//! token); plain numbers only where they are constants (LITERAL nodes), since a state number or
//! a byte address is not a constant.

use rowan::TextRange;

use crate::{SyntaxError, SyntaxKind, lexer::is_closed_char, literal::check_literal};

/// Checks a `TYPED_CONST` or `CHAR` token. An unclosed character constant already has HG0005.
pub(crate) fn check_constant_token(
    kind: SyntaxKind,
    text: &str,
    range: TextRange,
    errors: &mut Vec<SyntaxError>,
) {
    if kind == SyntaxKind::CHAR && !is_closed_char(text) {
        return;
    }
    push(text, range, errors);
}

/// Checks a constant of more than one token: a number with a joined `-`, or a pointer with a
/// space after its area (`P#M 100.0`).
pub(crate) fn check_number(text: &str, range: TextRange, errors: &mut Vec<SyntaxError>) {
    push(text, range, errors);
}

fn push(text: &str, range: TextRange, errors: &mut Vec<SyntaxError>) {
    if let Err(error) = check_literal(text) {
        errors.push(SyntaxError::new(
            error.code.error_code(),
            range,
            error.message,
        ));
    }
}

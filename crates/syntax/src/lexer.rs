//! The context-free lexer: text → tokens (kind + text), plus the diagnostics that belong to
//! single tokens (HG0004, HG0005, HG0009).
//!
//! Every byte of the input lands in exactly one token; characters that cannot begin a token are
//! gathered into one `LEX_ERROR` token per run.

use logos::Logos;
use rowan::{TextRange, TextSize};

use crate::{SyntaxError, SyntaxKind, error::ErrorCode};

/// One lexed token: its kind and its text (a slice of the input).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token<'a> {
    pub kind: SyntaxKind,
    pub text: &'a str,
}

/// Splits `text` into tokens. The concatenation of the tokens' texts is `text`.
pub fn tokenize(text: &str) -> Vec<Token<'_>> {
    // Tokens average more than three bytes; a little slack saves most reallocations.
    let mut tokens = Vec::with_capacity(text.len() / 3 + 16);
    tokens.extend(Tokens::new(text));
    tokens
}

/// The tokens of a text, in order (what [`tokenize`] collects). The parser runs the same
/// rules in its own loop (`Parser::new`).
pub(crate) struct Tokens<'a> {
    lexer: logos::Lexer<'a, SyntaxKind>,
    /// Offset of the lexer's input in the text (after a byte-order mark).
    base: usize,
    text: &'a str,
    /// A token to return before lexing on: the byte-order mark, or the token that ended a run
    /// of unlexable characters.
    pending: Option<Token<'a>>,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(text: &'a str) -> Tokens<'a> {
        // A leading byte-order mark is trivia.
        let bom = if text.starts_with('\u{FEFF}') {
            '\u{FEFF}'.len_utf8()
        } else {
            0
        };
        Tokens {
            lexer: SyntaxKind::lexer(&text[bom..]),
            base: bom,
            text,
            pending: (bom > 0).then(|| Token {
                kind: SyntaxKind::WHITESPACE,
                text: &text[..bom],
            }),
        }
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = Token<'a>;

    #[inline]
    fn next(&mut self) -> Option<Token<'a>> {
        if let Some(token) = self.pending.take() {
            return Some(token);
        }
        // One token per run of unlexable characters: the run ends at the next lexable token.
        let mut error_start = None;
        loop {
            match self.lexer.next() {
                Some(Ok(kind)) => {
                    let token = Token {
                        kind,
                        text: self.lexer.slice(),
                    };
                    let Some(start) = error_start else {
                        return Some(token);
                    };
                    self.pending = Some(token);
                    let end = self.base + self.lexer.span().start;
                    return Some(self.error_token(start, end));
                }
                Some(Err(())) => {
                    error_start.get_or_insert(self.base + self.lexer.span().start);
                }
                None => {
                    let end = self.text.len();
                    return error_start.map(|start| self.error_token(start, end));
                }
            }
        }
    }
}

impl<'a> Tokens<'a> {
    fn error_token(&self, start: usize, end: usize) -> Token<'a> {
        Token {
            kind: SyntaxKind::LEX_ERROR,
            text: &self.text[start..end],
        }
    }
}

/// Diagnostics that a single token carries on its own: unclosed strings and character
/// constants, unexpected characters and non-ASCII letters in identifiers.
pub(crate) fn token_errors(token: Token<'_>, offset: TextSize, errors: &mut Vec<SyntaxError>) {
    let range = TextRange::at(offset, TextSize::of(token.text));
    match token.kind {
        SyntaxKind::STRING if !is_closed(token.text, '"') => {
            errors.push(
                SyntaxError::new(
                    ErrorCode::HG0004,
                    range,
                    "string is not closed before the end of the line",
                )
                .with_fix(
                    "Insert '\"' at the end of the line",
                    TextRange::empty(range.end()),
                    "\"",
                ),
            );
        }
        SyntaxKind::CHAR if !is_closed_char(token.text) => {
            errors.push(
                SyntaxError::new(
                    ErrorCode::HG0005,
                    range,
                    "character constant is not closed before the end of the line",
                )
                .with_fix(
                    "Insert \"'\" at the end of the line",
                    TextRange::empty(range.end()),
                    "'",
                ),
            );
        }
        SyntaxKind::LEX_ERROR => {
            let c = token.text.chars().next().unwrap_or('\u{FFFD}');
            errors.push(SyntaxError::new(
                ErrorCode::HG0009,
                range,
                format!("unexpected character '{c}' (U+{:04X})", c as u32),
            ));
        }
        SyntaxKind::IDENT | SyntaxKind::TYPED_CONST if !token.text.is_ascii() => {
            non_ascii_runs(token.text, offset, errors)
        }
        _ => {}
    }
}

fn is_closed(text: &str, quote: char) -> bool {
    text.len() >= 2 && text.ends_with(quote)
}

/// `'...'` is closed when, after the opening quote, the quotes pair up to an odd count at the
/// end (`''` inside stands for one quote).
pub(crate) fn is_closed_char(text: &str) -> bool {
    let body = &text[1..];
    let mut chars = body.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\'' {
            if chars.peek() == Some(&'\'') {
                chars.next();
            } else {
                return chars.peek().is_none();
            }
        }
    }
    false
}

/// HG0009 for every run of non-ASCII letters inside an identifier; umlauts get a fix.
fn non_ascii_runs(text: &str, offset: TextSize, errors: &mut Vec<SyntaxError>) {
    let mut iter = text.char_indices().peekable();
    while let Some((start, c)) = iter.next() {
        if c.is_ascii() {
            continue;
        }
        let mut end = start + c.len_utf8();
        while let Some(&(i, next)) = iter.peek() {
            if next.is_ascii() {
                break;
            }
            end = i + next.len_utf8();
            iter.next();
        }
        let run = &text[start..end];
        let range = TextRange::new(
            offset + TextSize::from(start as u32),
            offset + TextSize::from(end as u32),
        );
        let ascii: Option<String> = run.chars().map(umlaut_replacement).collect();
        let error = match ascii {
            Some(ascii) => SyntaxError::new(
                ErrorCode::HG0009,
                range,
                format!("identifiers use ASCII letters only; write '{ascii}' for '{run}'"),
            )
            .with_fix(format!("Replace '{run}' with '{ascii}'"), range, ascii),
            None => SyntaxError::new(
                ErrorCode::HG0009,
                range,
                format!("unexpected character '{c}' (U+{:04X})", c as u32),
            ),
        };
        errors.push(error);
    }
}

fn umlaut_replacement(c: char) -> Option<&'static str> {
    Some(match c {
        'ä' => "ae",
        'ö' => "oe",
        'ü' => "ue",
        'ß' => "ss",
        'Ä' => "Ae",
        'Ö' => "Oe",
        'Ü' => "Ue",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use SyntaxKind::*;

    fn kinds(text: &str) -> Vec<(SyntaxKind, &str)> {
        tokenize(text)
            .into_iter()
            .map(|t| (t.kind, t.text))
            .collect()
    }

    #[test]
    fn typed_constants_are_one_token() {
        for c in [
            "B#16#FF",
            "DW#16#00A2_1234",
            "2#0101_0000",
            "L#-5",
            "B#(1, 14,100,120)",
            "S5T#1H_1M_0S",
            "T#2.5H",
            "D#1994-3-15",
            "TOD#1:10:3.3",
            "DT#1994-3-15-1:10:3.3",
            "P#M50.0",
            "16#FF",
        ] {
            assert_eq!(kinds(c), vec![(TYPED_CONST, c)], "{c}");
        }
    }

    #[test]
    fn addresses_split_into_words_numbers_and_dots() {
        assert_eq!(
            kinds("DB10.DBX 5.1"),
            vec![
                (IDENT, "DB10"),
                (DOT, "."),
                (IDENT, "DBX"),
                (WHITESPACE, " "),
                (NUMBER, "5.1")
            ]
        );
        assert_eq!(
            kinds("E1.0"),
            vec![(IDENT, "E1"), (DOT, "."), (NUMBER, "0")]
        );
    }

    #[test]
    fn error_runs_are_merged() {
        assert_eq!(
            kinds("a$@b"),
            vec![(IDENT, "a"), (LEX_ERROR, "$@"), (IDENT, "b")]
        );
    }

    #[test]
    fn strings_and_chars_end_at_the_line() {
        assert_eq!(
            kinds("\"ab\ncd"),
            vec![(STRING, "\"ab"), (WHITESPACE, "\n"), (IDENT, "cd")]
        );
        assert_eq!(kinds("'it''s'"), vec![(CHAR, "'it''s'")]);
        assert!(is_closed_char("'it''s'"));
        assert!(!is_closed_char("'it''s"));
        assert!(is_closed_char("''"));
        assert!(!is_closed_char("'''"));
    }

    #[test]
    fn bom_is_trivia() {
        assert_eq!(
            kinds("\u{FEFF}graph"),
            vec![(WHITESPACE, "\u{FEFF}"), (IDENT, "graph")]
        );
    }
}

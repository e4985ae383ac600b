//! The hand-written resilient recursive-descent parser.
//!
//! The parser sees only *significant* tokens (not white space, comments or unlexable
//! characters); those are attached to the tree as it goes, so the tree stays lossless. Keywords
//! are contextual: the grammar functions check an identifier's text and *remap* it to a `*_KW`
//! kind where it acts as a keyword. Punctuation that forms one unit (`:=`, `->`, labels, STL
//! comparisons) is grouped into a node; the tokens themselves stay as lexed.
//!
//! Errors never stop the parse. Every recovery reports exactly one HG0001 or HG0002 (cascade
//! rule C1 of `diagnostics.md`), and every `<` that is closed by recovery or by the end of the
//! file reports HG0003.

mod chart;
pub(crate) mod fragment;
mod graph;
mod group;
mod items;
mod stl;

use rowan::{Checkpoint, GreenNode, GreenNodeBuilder, TextRange, TextSize};

use crate::{
    SyntaxError, SyntaxKind,
    SyntaxKind::*,
    error::ErrorCode,
    lexer::{self, Token},
    validation,
};

pub(crate) fn parse(text: &str) -> (GreenNode, Vec<SyntaxError>) {
    let mut p = Parser::new(text);
    items::source_file(&mut p);
    p.finish()
}

/// Marker for "end of input" in lookahead.
const EOF: SyntaxKind = SyntaxKind::__LAST_TOKEN;

/// Which enclosing construct may claim a member keyword (language.md §1.4): a member keyword
/// at statement start closes every inner body up to the construct that accepts it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scope {
    /// Inside a graph: `state N`, `trans N|any|return`, `activate`, `permanent <`, sections.
    Graph,
    /// Inside a group: `instance NAME :`, `option NAME`.
    Group,
    /// Inside a sequencer: `step X`, `trans X`, `parallel <`, `alt <`, `branch <`, `jump X`,
    /// `loop X`, `sequencer X`.
    Sequencer,
    /// Inside a chart but not in a sequencer (chart variable sections).
    Chart,
}

pub(crate) struct Parser<'t> {
    tokens: Vec<Token<'t>>,
    offsets: Vec<TextSize>,
    /// Indices into `tokens` of the significant tokens.
    significant: Vec<usize>,
    /// For each significant token: is there a line break between it and the previous one?
    newline_before: Vec<bool>,
    /// For each significant token: does it follow the previous significant token with
    /// nothing at all in between?
    joined: Vec<bool>,
    /// Position in `significant`.
    pos: usize,
    /// Tokens in `tokens` before this index are already in the tree.
    emitted: usize,
    /// End of the last significant token added to the tree.
    last_end: TextSize,
    text_len: TextSize,
    builder: GreenNodeBuilder<'static>,
    errors: Vec<SyntaxError>,
}

impl<'t> Parser<'t> {
    fn new(text: &'t str) -> Parser<'t> {
        let tokens = lexer::tokenize(text);
        let mut offsets = Vec::with_capacity(tokens.len());
        let mut errors = Vec::new();
        let mut offset = TextSize::from(0);
        let mut significant = Vec::new();
        let mut newline_before = Vec::new();
        let mut joined = Vec::new();
        let mut saw_newline = false;
        let mut adjacent = false;
        for (i, token) in tokens.iter().enumerate() {
            offsets.push(offset);
            // Only a few kinds can carry an error of their own; skip the call for the rest.
            if matches!(token.kind, STRING | CHAR | LEX_ERROR)
                || (matches!(token.kind, IDENT | TYPED_CONST) && !token.text.is_ascii())
            {
                lexer::token_errors(*token, offset, &mut errors);
            }
            offset += TextSize::of(token.text);
            match token.kind {
                WHITESPACE | COMMENT | LEX_ERROR => {
                    if token.text.contains(['\n', '\r']) {
                        saw_newline = true;
                    }
                    adjacent = false;
                }
                _ => {
                    significant.push(i);
                    newline_before.push(saw_newline);
                    joined.push(adjacent);
                    saw_newline = false;
                    adjacent = true;
                }
            }
        }
        Parser {
            tokens,
            offsets,
            significant,
            newline_before,
            joined,
            pos: 0,
            emitted: 0,
            last_end: TextSize::from(0),
            text_len: offset,
            builder: GreenNodeBuilder::new(),
            errors,
        }
    }

    fn finish(self) -> (GreenNode, Vec<SyntaxError>) {
        (self.builder.finish(), self.errors)
    }

    // ------------------------------------------------------------------ lookahead

    /// Kind of the `n`th significant token from the current position (`EOF` past the end).
    pub(crate) fn nth(&self, n: usize) -> SyntaxKind {
        self.significant
            .get(self.pos + n)
            .map_or(EOF, |&i| self.tokens[i].kind)
    }

    pub(crate) fn current(&self) -> SyntaxKind {
        self.nth(0)
    }

    pub(crate) fn nth_text(&self, n: usize) -> &'t str {
        self.significant
            .get(self.pos + n)
            .map_or("", |&i| self.tokens[i].text)
    }

    pub(crate) fn at(&self, kind: SyntaxKind) -> bool {
        self.current() == kind
    }

    pub(crate) fn at_eof(&self) -> bool {
        self.pos >= self.significant.len()
    }

    /// Is the `n`th token an identifier spelled `word` (ASCII case-insensitively)?
    pub(crate) fn nth_is_word(&self, n: usize, word: &str) -> bool {
        self.nth(n) == IDENT && self.nth_text(n).eq_ignore_ascii_case(word)
    }

    pub(crate) fn at_word(&self, word: &str) -> bool {
        self.nth_is_word(0, word)
    }

    /// Does the `n`th token follow the `n-1`th with nothing between them?
    pub(crate) fn nth_joined(&self, n: usize) -> bool {
        self.joined.get(self.pos + n).copied().unwrap_or(false)
    }

    /// Is there a line break before the `n`th token? (End of file counts as a new line.)
    pub(crate) fn nth_on_new_line(&self, n: usize) -> bool {
        self.newline_before
            .get(self.pos + n)
            .copied()
            .unwrap_or(true)
    }

    /// Range of the `n`th significant token, or the empty range at the end of the input.
    pub(crate) fn nth_range(&self, n: usize) -> TextRange {
        match self.significant.get(self.pos + n) {
            Some(&i) => TextRange::at(self.offsets[i], TextSize::of(self.tokens[i].text)),
            None => TextRange::empty(self.text_len),
        }
    }

    /// End of the last significant token in the tree ("where the parser stopped").
    pub(crate) fn last_end(&self) -> TextSize {
        self.last_end
    }

    /// Describes the current token for messages: `'text'` or `end of file`.
    pub(crate) fn found(&self) -> String {
        if self.at_eof() {
            "end of file".to_owned()
        } else {
            format!("'{}'", self.nth_text(0))
        }
    }

    // ------------------------------------------------------------------ tree building

    /// Adds the pending trivia (and unlexable characters) before the current token.
    fn flush_trivia(&mut self) {
        let upto = self
            .significant
            .get(self.pos)
            .copied()
            .unwrap_or(self.tokens.len());
        while self.emitted < upto {
            let token = self.tokens[self.emitted];
            self.builder.token(token.kind.into(), token.text);
            self.emitted += 1;
        }
    }

    /// Starts the root node; leading trivia belongs to it.
    pub(crate) fn start_root(&mut self) {
        self.builder.start_node(SOURCE_FILE.into());
    }

    pub(crate) fn start(&mut self, kind: SyntaxKind) {
        self.flush_trivia();
        self.builder.start_node(kind.into());
    }

    pub(crate) fn finish_node(&mut self) {
        self.builder.finish_node();
    }

    pub(crate) fn checkpoint(&mut self) -> Checkpoint {
        self.flush_trivia();
        self.builder.checkpoint()
    }

    pub(crate) fn start_at(&mut self, checkpoint: Checkpoint, kind: SyntaxKind) {
        self.builder.start_node_at(checkpoint, kind.into());
    }

    /// Adds the current token to the tree.
    pub(crate) fn bump(&mut self) {
        let kind = self.current();
        self.bump_as(kind);
    }

    /// Adds the current token to the tree with another kind (keywords).
    pub(crate) fn bump_as(&mut self, kind: SyntaxKind) {
        if self.at_eof() {
            return;
        }
        self.flush_trivia();
        let i = self.significant[self.pos];
        let token = self.tokens[i];
        if matches!(token.kind, TYPED_CONST | CHAR) {
            // Typed and character constants are checked wherever they stand (HG0006/HG0007).
            let range = TextRange::at(self.offsets[i], TextSize::of(token.text));
            validation::check_constant_token(token.kind, token.text, range, &mut self.errors);
        }
        self.builder.token(kind.into(), token.text);
        self.emitted = i + 1;
        self.last_end = self.offsets[i] + TextSize::of(token.text);
        self.pos += 1;
    }

    /// Adds the current identifier as the keyword of its spelling.
    pub(crate) fn bump_keyword(&mut self) {
        let kind = SyntaxKind::from_keyword(self.nth_text(0)).unwrap_or(IDENT);
        self.bump_as(kind);
    }

    /// Wraps `n` tokens in a node.
    pub(crate) fn bump_node(&mut self, kind: SyntaxKind, n: usize) {
        self.start(kind);
        for _ in 0..n {
            self.bump();
        }
        self.finish_node();
    }

    /// Adds all remaining tokens to the tree.
    pub(crate) fn flush_rest(&mut self) {
        while !self.at_eof() {
            self.bump();
        }
        self.flush_trivia();
    }

    // ------------------------------------------------------------------ errors

    /// Number of diagnostics so far (lets a caller see whether a sub-parser recovered).
    pub(crate) fn error_count(&self) -> usize {
        self.errors.len()
    }

    pub(crate) fn push_error(&mut self, error: SyntaxError) {
        self.errors.push(error);
    }

    /// HG0001 at the current token: `expected {expected}, found {found}`.
    pub(crate) fn error_expected(&mut self, expected: &str) {
        let range = self.nth_range(0);
        let message = format!("expected {expected}, found {}", self.found());
        self.errors
            .push(SyntaxError::new(ErrorCode::HG0001, range, message));
    }

    /// HG0002: the element is complete but its `;` is missing.
    pub(crate) fn error_missing_semi(&mut self, element: &str) {
        let at = TextRange::empty(self.last_end);
        self.errors.push(
            SyntaxError::new(
                ErrorCode::HG0002,
                at,
                format!("missing ';' after {element}"),
            )
            .with_fix("Insert ';'", at, ";"),
        );
    }

    /// HG0003 for the `<` at `open`.
    pub(crate) fn error_unclosed(&mut self, open: TextRange, construct: &str) {
        let stop = TextRange::empty(self.last_end);
        self.errors.push(
            SyntaxError::new(
                ErrorCode::HG0003,
                open,
                format!("'<' of {construct} is never closed"),
            )
            .with_related(stop, "the parser stopped here")
            .with_fix("Insert '>'", stop, ">"),
        );
    }

    /// HG0001 at the current token, then skips to a recovery point: past the next `;`, or up
    /// to the next `>`, an item keyword that starts a statement or line, or the end of file.
    pub(crate) fn error_and_recover(&mut self, expected: &str) {
        self.error_expected(expected);
        self.recover();
    }

    /// Skips tokens into an ERROR node (see [`Parser::error_and_recover`]); reports nothing.
    pub(crate) fn recover(&mut self) {
        self.start(ERROR);
        let mut first = true;
        while !self.at_eof() {
            match self.current() {
                SEMI => {
                    self.bump();
                    break;
                }
                R_ANGLE => break,
                _ if !first && self.at_line_start_recovery_point() => break,
                _ => self.bump(),
            }
            first = false;
        }
        self.finish_node();
    }

    /// During recovery, an item or member keyword that starts a line is taken as the start of
    /// the next statement (a `;` was evidently lost before it).
    fn at_line_start_recovery_point(&self) -> bool {
        self.nth_on_new_line(0)
            && (self.at_item_start()
                || [Scope::Graph, Scope::Group, Scope::Sequencer, Scope::Chart]
                    .iter()
                    .any(|&s| self.at_member_start(s)))
    }

    /// Like `recover`, but for an item or member header: also stops before a `<`, so the
    /// caller can still parse the body. Returns whether it stopped at `<`.
    pub(crate) fn recover_header(&mut self) -> bool {
        if self.at(L_ANGLE) {
            return true;
        }
        self.start(ERROR);
        let mut first = true;
        let mut at_body = false;
        while !self.at_eof() {
            match self.current() {
                SEMI => {
                    self.bump();
                    break;
                }
                L_ANGLE => {
                    at_body = true;
                    break;
                }
                R_ANGLE => break,
                _ if !first && self.at_line_start_recovery_point() => break,
                _ => self.bump(),
            }
            first = false;
        }
        self.finish_node();
        at_body
    }

    /// Ends an element that must be followed by `;` (diagnostics.md HG0002 / HG0001):
    /// consumes the `;`; or reports HG0002 when the next token is `>`, the end of file, a block
    /// label, on a later line, or can begin a new element (`can_begin`); or reports HG0001 and
    /// recovers.
    pub(crate) fn expect_semi(&mut self, element: &str, can_begin: fn(&Parser<'_>) -> bool) {
        if self.at(SEMI) {
            self.bump();
        } else if self.at_eof()
            || self.at(R_ANGLE)
            || self.nth_on_new_line(0)
            || stl::at_label(self)
            || can_begin(self)
        {
            self.error_missing_semi(element);
        } else {
            self.error_and_recover("';'");
        }
    }

    /// Expects the `<` of a body; returns its range (for HG0003) or `None` after an error.
    pub(crate) fn expect_open(&mut self, what: &str) -> Option<TextRange> {
        if self.at(L_ANGLE) {
            let range = self.nth_range(0);
            self.bump();
            return Some(range);
        }
        self.error_expected(&format!("'<' to open {what}"));
        if self.recover_header() {
            let range = self.nth_range(0);
            self.bump();
            Some(range)
        } else {
            None
        }
    }

    // ------------------------------------------------------------------ shared predicates

    /// An item keyword that, at statement start, closes every open block (language.md §1.4).
    pub(crate) fn at_item_start(&self) -> bool {
        if self.current() != IDENT {
            return false;
        }
        let word = self.nth_text(0);
        let next = self.nth(1);
        let is = |w: &str| word.eq_ignore_ascii_case(w);
        if is("graph") || is("group") || is("chart") || is("block") {
            matches!(next, IDENT | STRING)
        } else if is("symbols") {
            next == L_ANGLE
        } else if is("mnemonic") {
            self.nth_is_word(1, "simatic") || self.nth_is_word(1, "international")
        } else {
            false
        }
    }

    /// A member keyword of `scope` at statement start (language.md §1.4).
    pub(crate) fn at_member_start(&self, scope: Scope) -> bool {
        if self.current() != IDENT {
            return false;
        }
        let next = self.nth(1);
        let is = |w: &str| self.at_word(w);
        match scope {
            Scope::Graph => {
                (is("state") && next == NUMBER)
                    || (is("trans")
                        && (next == NUMBER
                            || self.nth_is_word(1, "any")
                            || self.nth_is_word(1, "return")))
                    || is("activate")
                    || ((is("permanent") || is("in") || is("out") || is("in_out") || is("stat"))
                        && next == L_ANGLE)
            }
            Scope::Group => {
                (is("instance") && next == IDENT && self.nth(2) == COLON && self.nth(3) != EQ)
                    || (is("option") && next == IDENT && matches!(self.nth(2), SEMI | NUMBER))
            }
            Scope::Sequencer => {
                let named = matches!(next, IDENT | NUMBER);
                ((is("step") || is("trans") || is("jump") || is("loop") || is("sequencer"))
                    && named)
                    || ((is("parallel") || is("alt") || is("branch")) && next == L_ANGLE)
            }
            Scope::Chart => {
                (is("sequencer") && matches!(next, IDENT | NUMBER))
                    || ((is("in") || is("out") || is("in_out") || is("stat")) && next == L_ANGLE)
            }
        }
    }

    /// Common loop control for `< ... >` bodies: returns `true` when the body ends here —
    /// after consuming its `>`, or (reporting HG0003) at the end of the file, an item keyword
    /// or a member keyword of an enclosing scope.
    pub(crate) fn body_ends(&mut self, open: TextRange, construct: &str, scopes: &[Scope]) -> bool {
        if self.at(R_ANGLE) {
            self.bump();
            return true;
        }
        if self.at_eof() || self.at_item_start() || scopes.iter().any(|&s| self.at_member_start(s))
        {
            self.error_unclosed(open, construct);
            return true;
        }
        false
    }

    /// Parses a declared name (NAME node) if the current token is an identifier.
    pub(crate) fn name(&mut self) -> bool {
        if self.at(IDENT) {
            self.bump_node(NAME, 1);
            true
        } else {
            false
        }
    }

    /// An optional display-name or comment string.
    pub(crate) fn opt_comment_string(&mut self) {
        if self.at(STRING) {
            self.bump_node(COMMENT_STRING, 1);
        }
    }

    /// `:=` written as two adjacent tokens.
    pub(crate) fn at_assign(&self) -> bool {
        self.at(COLON) && self.nth(1) == EQ && self.nth_joined(1)
    }

    /// A `:` that is not the start of `:=`.
    pub(crate) fn at_colon(&self) -> bool {
        self.at(COLON) && !self.at_assign()
    }

    /// `->` written as two adjacent tokens.
    pub(crate) fn at_arrow(&self) -> bool {
        self.at(MINUS) && self.nth(1) == R_ANGLE && self.nth_joined(1)
    }
}

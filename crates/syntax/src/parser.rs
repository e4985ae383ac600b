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

mod builder;
mod chart;
pub(crate) mod fragment;
mod graph;
mod group;
mod items;
mod stl;
mod test;

use std::fmt;

use logos::Logos;
use rowan::{GreenNode, TextRange, TextSize};

use builder::{Checkpoint, TreeBuilder};

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

/// A description for a diagnostic message that is formatted only if the message is made:
/// the parser names every construct and element it enters, but almost all of them parse
/// without a message. `lazy(|f| write!(f, "state {number}"))`.
pub(crate) struct Lazy<F>(F);

pub(crate) fn lazy<F: Fn(&mut fmt::Formatter<'_>) -> fmt::Result>(f: F) -> Lazy<F> {
    Lazy(f)
}

impl<F: Fn(&mut fmt::Formatter<'_>) -> fmt::Result> fmt::Display for Lazy<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        (self.0)(f)
    }
}

/// A text offset. Texts are below 4 GiB (rowan's limit), so the offset fits.
fn text_size(offset: usize) -> TextSize {
    TextSize::new(offset as u32)
}

/// How deep expressions and sequencer elements may nest (HG0012). Each pair of parentheses,
/// each `not`, each operator (`and`, `or`, `xor`, a comparison) over the operands below it and
/// each `parallel`/`alt` (with its `branch`) is one level; the levels of an expression inside
/// nested branches add to those of the branches. No hand-written or generated program comes
/// near it, and it bounds the depth of every tree the parser builds (at most four tree levels
/// per level, plus the fixed levels of items and members: about 1 050). Every recursive walk
/// over the syntax tree — in this crate, the analysis, its editor features, the formatter and
/// the renderer, and the binary — relies on that bound instead of a limit of its own.
pub const NESTING_LIMIT: u32 = 256;

/// Marker for "end of input" in lookahead.
const EOF: SyntaxKind = SyntaxKind::__LAST_TOKEN;

/// What the lexing loop of [`Parser::new`] needs to know about a token beyond its kind,
/// worked out once per distinct token (kind and text) rather than once per occurrence.
#[derive(Debug, Clone, Copy)]
struct TokenInfo {
    /// The keyword an identifier is spelled like; `IDENT` if none, and for other tokens.
    keyword: SyntaxKind,
    /// The token's [`stl::word`] flags.
    flags: u16,
    /// White space with a line break.
    line_break: bool,
    /// Can the token carry a diagnostic of its own ([`lexer::token_errors`])? Strings,
    /// character constants and identifiers or typed constants with non-ASCII characters.
    check: bool,
}

impl TokenInfo {
    fn new(kind: SyntaxKind, text: &str) -> TokenInfo {
        TokenInfo {
            keyword: if kind == IDENT {
                SyntaxKind::from_keyword(text).unwrap_or(IDENT)
            } else {
                IDENT
            },
            flags: stl::word_flags(kind, text),
            line_break: kind == WHITESPACE && text.bytes().any(|b| b == b'\n' || b == b'\r'),
            check: matches!(kind, STRING | CHAR)
                || (matches!(kind, IDENT | TYPED_CONST) && !text.is_ascii()),
        }
    }
}

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

/// A significant token, with what the grammar asks about it precomputed.
///
/// Kept to 32 bytes: its offset in the text follows from where `text` points
/// ([`Parser::offset`]).
#[derive(Debug, Clone, Copy)]
struct Significant<'t> {
    text: &'t str,
    /// Number of trivia tokens before this token: the trivia up to here precedes it.
    trivia_end: u32,
    /// The token's number in the tree builder (as lexed, not as a keyword).
    id: u32,
    kind: SyntaxKind,
    /// For an identifier spelled like a keyword (ASCII case-insensitively), that keyword;
    /// `IDENT` for every other token.
    keyword: SyntaxKind,
    /// What the STL grammar asks about the token's text ([`stl::word_flags`]).
    flags: u16,
    /// Is there a line break between this token and the previous significant one?
    newline_before: bool,
    /// Does this token follow the previous significant token with nothing at all in between?
    joined: bool,
}

pub(crate) struct Parser<'t> {
    /// The significant tokens, in order.
    significant: Vec<Significant<'t>>,
    /// White space, comments and unlexable characters, in order, as token numbers of the
    /// tree builder.
    trivia: Vec<u32>,
    /// Position in `significant`.
    pos: usize,
    /// Trivia tokens before this index are already in the tree.
    trivia_emitted: usize,
    /// End of the last significant token added to the tree.
    last_end: TextSize,
    text_len: TextSize,
    /// Where the text begins after a leading byte-order mark (0 without one).
    text_start: TextSize,
    /// Address of the text: a token's offset is its text's address minus this.
    base: usize,
    /// The whole text.
    source: &'t str,
    builder: TreeBuilder<'t>,
    errors: Vec<SyntaxError>,
    /// Number of HG0001 and HG0002 reported so far ([`Parser::recoveries`]).
    recoveries: usize,
    /// Nesting levels open here ([`NESTING_LIMIT`]).
    depth: u32,
    /// Inside the body of a `test`: expression paths are test paths (`TEST_PATH`).
    pub(crate) in_test: bool,
}

impl<'t> Parser<'t> {
    fn new(text: &'t str) -> Parser<'t> {
        // Capacity for a significant token per four bytes and a trivia token per five: more
        // than typical files need (reallocating these large vectors costs more than unused
        // capacity, which is never touched).
        let mut significant = Vec::with_capacity(text.len() / 4 + 16);
        let mut trivia = Vec::with_capacity(text.len() / 5 + 16);
        let mut builder = TreeBuilder::new();
        // Per distinct token (by number): the keyword it is spelled like and its word flags,
        // worked out once per distinct text rather than once per occurrence.
        let mut info: Vec<TokenInfo> = Vec::new();
        let mut errors = Vec::new();
        let mut saw_newline = false;
        let mut adjacent = false;
        // The lexer runs here directly rather than through `lexer::Tokens`: this loop is the
        // hottest of the parser. The same rules apply: a leading byte-order mark is white
        // space, and a run of unlexable characters is one LEX_ERROR token. Every token is
        // interned in the tree builder right away, so the grammar adds tokens by number.
        let bom = if text.starts_with('\u{FEFF}') {
            '\u{FEFF}'.len_utf8()
        } else {
            0
        };
        if bom > 0 {
            trivia.push(builder.intern_token(WHITESPACE, &text[..bom]));
            info.push(TokenInfo::new(WHITESPACE, &text[..bom]));
        }
        // The LEX_ERROR run being lexed (start, end), while it can grow.
        let mut error_run: Option<(usize, usize)> = None;
        let mut lexer = SyntaxKind::lexer(&text[bom..]);
        while let Some(result) = lexer.next() {
            let span = lexer.span();
            let start = bom + span.start;
            let Ok(kind) = result else {
                let run = error_run.get_or_insert((start, start));
                run.1 = bom + span.end;
                adjacent = false;
                continue;
            };
            if let Some((run_start, run_end)) = error_run.take() {
                let run = &text[run_start..run_end];
                let id = builder.intern_token(LEX_ERROR, run);
                if id as usize == info.len() {
                    info.push(TokenInfo::new(LEX_ERROR, run));
                }
                trivia.push(id);
                let token = Token {
                    kind: LEX_ERROR,
                    text: run,
                };
                lexer::token_errors(token, text_size(run_start), &mut errors);
            }
            let token_text = lexer.slice();
            let id = builder.intern_token(kind, token_text);
            if id as usize == info.len() {
                info.push(TokenInfo::new(kind, token_text));
            }
            let TokenInfo {
                keyword,
                flags,
                line_break,
                check,
            } = info[id as usize];
            // Only a few tokens can carry an error of their own; skip the call for the rest.
            if check {
                let token = Token {
                    kind,
                    text: token_text,
                };
                lexer::token_errors(token, text_size(start), &mut errors);
            }
            match kind {
                WHITESPACE | COMMENT => {
                    // Comments end before the line break.
                    saw_newline |= line_break;
                    adjacent = false;
                    trivia.push(id);
                }
                _ => {
                    significant.push(Significant {
                        text: token_text,
                        trivia_end: trivia.len() as u32,
                        id,
                        kind,
                        keyword,
                        flags,
                        newline_before: saw_newline,
                        joined: adjacent,
                    });
                    saw_newline = false;
                    adjacent = true;
                }
            }
        }
        if let Some((run_start, run_end)) = error_run {
            let run = &text[run_start..run_end];
            trivia.push(builder.intern_token(LEX_ERROR, run));
            let token = Token {
                kind: LEX_ERROR,
                text: run,
            };
            lexer::token_errors(token, text_size(run_start), &mut errors);
        }
        let offset = text_size(text.len());
        Parser {
            significant,
            trivia,
            pos: 0,
            trivia_emitted: 0,
            last_end: TextSize::from(0),
            text_len: offset,
            text_start: text_size(bom),
            base: text.as_ptr() as usize,
            source: text,
            builder,
            errors,
            recoveries: 0,
            depth: 0,
            in_test: false,
        }
    }

    fn finish(self) -> (GreenNode, Vec<SyntaxError>) {
        (self.builder.finish(), self.errors)
    }

    /// The top of the file: offset 0, or the end of a leading byte-order mark.
    pub(crate) fn text_start(&self) -> TextSize {
        self.text_start
    }

    /// Does the text begin with a significant token (no leading trivia)?
    pub(crate) fn starts_with_significant(&self) -> bool {
        self.significant.first().is_some_and(|s| s.trivia_end == 0)
    }

    /// Is every token, trivia included, in the tree?
    pub(crate) fn all_emitted(&self) -> bool {
        self.at_eof() && self.trivia_emitted == self.trivia.len()
    }

    // ------------------------------------------------------------------ lookahead

    #[inline]
    fn nth_token(&self, n: usize) -> Option<&Significant<'t>> {
        self.significant.get(self.pos + n)
    }

    /// Kind of the `n`th significant token from the current position (`EOF` past the end).
    #[inline]
    pub(crate) fn nth(&self, n: usize) -> SyntaxKind {
        self.nth_token(n).map_or(EOF, |t| t.kind)
    }

    #[inline]
    pub(crate) fn current(&self) -> SyntaxKind {
        self.nth(0)
    }

    #[inline]
    pub(crate) fn nth_text(&self, n: usize) -> &'t str {
        self.nth_token(n).map_or("", |t| t.text)
    }

    #[inline]
    pub(crate) fn at(&self, kind: SyntaxKind) -> bool {
        self.current() == kind
    }

    #[inline]
    pub(crate) fn at_eof(&self) -> bool {
        self.pos >= self.significant.len()
    }

    /// Is the `n`th token an identifier spelled `word` (ASCII case-insensitively)? For
    /// keywords, [`Parser::nth_is_kw`] is cheaper.
    pub(crate) fn nth_is_word(&self, n: usize, word: &str) -> bool {
        self.nth_token(n)
            .is_some_and(|t| t.kind == IDENT && t.text.eq_ignore_ascii_case(word))
    }

    pub(crate) fn at_word(&self, word: &str) -> bool {
        self.nth_is_word(0, word)
    }

    /// Is the `n`th token an identifier spelled like the keyword `kw` (`STATE_KW` for
    /// `state`, `State`, ...)?
    #[inline]
    pub(crate) fn nth_is_kw(&self, n: usize, kw: SyntaxKind) -> bool {
        self.nth_token(n).is_some_and(|t| t.keyword == kw)
    }

    /// The keyword the `n`th token is spelled like; `IDENT` if none (and for other tokens).
    #[inline]
    pub(crate) fn nth_keyword(&self, n: usize) -> SyntaxKind {
        self.nth_token(n).map_or(IDENT, |t| t.keyword)
    }

    #[inline]
    pub(crate) fn at_kw(&self, kw: SyntaxKind) -> bool {
        self.nth_is_kw(0, kw)
    }

    /// Does the `n`th token have one of the word flags `flags` ([`stl::word_flags`])?
    #[inline]
    pub(crate) fn nth_has(&self, n: usize, flags: u16) -> bool {
        self.nth_token(n).is_some_and(|t| t.flags & flags != 0)
    }

    /// Does the `n`th token follow the `n-1`th with nothing between them?
    #[inline]
    pub(crate) fn nth_joined(&self, n: usize) -> bool {
        self.nth_token(n).is_some_and(|t| t.joined)
    }

    /// Is there a line break before the `n`th token? (End of file counts as a new line.)
    #[inline]
    pub(crate) fn nth_on_new_line(&self, n: usize) -> bool {
        self.nth_token(n).is_none_or(|t| t.newline_before)
    }

    /// Offset of `token` in the text.
    #[inline]
    fn offset(&self, token: &Significant<'t>) -> TextSize {
        text_size(token.text.as_ptr() as usize - self.base)
    }

    /// Range of the `n`th significant token, or the empty range at the end of the input.
    pub(crate) fn nth_range(&self, n: usize) -> TextRange {
        match self.nth_token(n) {
            Some(t) => TextRange::at(self.offset(t), TextSize::of(t.text)),
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
    #[inline]
    fn flush_trivia(&mut self) {
        let upto = self
            .significant
            .get(self.pos)
            .map_or(self.trivia.len(), |t| t.trivia_end as usize);
        if self.trivia_emitted < upto {
            self.builder
                .push_tokens(&self.trivia[self.trivia_emitted..upto]);
            self.trivia_emitted = upto;
        }
    }

    /// Starts the root node; leading trivia belongs to it.
    pub(crate) fn start_root(&mut self) {
        self.builder.start_node(SOURCE_FILE);
    }

    #[inline]
    pub(crate) fn start(&mut self, kind: SyntaxKind) {
        self.flush_trivia();
        self.builder.start_node(kind);
    }

    #[inline]
    pub(crate) fn finish_node(&mut self) {
        self.builder.finish_node();
    }

    pub(crate) fn checkpoint(&mut self) -> Checkpoint {
        self.flush_trivia();
        self.builder.checkpoint()
    }

    pub(crate) fn start_at(&mut self, checkpoint: Checkpoint, kind: SyntaxKind) {
        self.builder.start_node_at(checkpoint, kind);
    }

    /// Adds the current token to the tree.
    #[inline]
    pub(crate) fn bump(&mut self) {
        let kind = self.current();
        self.bump_as(kind);
    }

    /// Adds the current token to the tree with another kind (keywords).
    #[inline]
    pub(crate) fn bump_as(&mut self, kind: SyntaxKind) {
        let Some(&token) = self.significant.get(self.pos) else {
            return;
        };
        self.flush_trivia();
        let id = if kind == token.kind {
            token.id
        } else {
            self.builder.intern_token(kind, token.text)
        };
        self.builder.push_token(id);
        self.advance(token);
    }

    /// Moves past `token`, the current token, once it is in the tree.
    #[inline]
    fn advance(&mut self, token: Significant<'t>) {
        if matches!(token.kind, TYPED_CONST | CHAR) && token.flags & stl::word::VALID_CONSTANT == 0
        {
            // Typed and character constants are checked wherever they stand (HG0006/HG0007).
            let range = TextRange::at(self.offset(&token), TextSize::of(token.text));
            validation::check_constant_token(token.kind, token.text, range, &mut self.errors);
        }
        self.advance_unchecked(token);
    }

    #[inline]
    fn advance_unchecked(&mut self, token: Significant<'t>) {
        self.last_end = self.offset(&token) + TextSize::of(token.text);
        self.pos += 1;
    }

    /// Wraps the `n` current tokens in a node without checking a constant among them: the
    /// caller checks the constant they form together (`P#M 100.0`).
    pub(crate) fn bump_node_unchecked(&mut self, kind: SyntaxKind, n: usize) {
        self.start(kind);
        for _ in 0..n {
            let Some(&token) = self.significant.get(self.pos) else {
                break;
            };
            self.flush_trivia();
            self.builder.push_token(token.id);
            self.advance_unchecked(token);
        }
        self.finish_node();
    }

    /// The text from the start of the `first`th token to the end of the `last`th one.
    pub(crate) fn text_between(&self, first: usize, last: usize) -> &'t str {
        let start = usize::from(self.nth_range(first).start());
        let end = usize::from(self.nth_range(last).end());
        self.source.get(start..end).unwrap_or("")
    }

    /// Adds the current identifier as the keyword of its spelling.
    pub(crate) fn bump_keyword(&mut self) {
        let kind = self.nth_token(0).map_or(IDENT, |t| t.keyword);
        self.bump_as(kind);
    }

    /// Wraps `n` tokens in a node.
    pub(crate) fn bump_node(&mut self, kind: SyntaxKind, n: usize) {
        // Most nodes of one token (`NAME_REF`, `OPCODE`, ...) were made before: add that node.
        if n == 1
            && let Some(&token) = self.significant.get(self.pos)
        {
            self.flush_trivia();
            if self.builder.push_wrapped(kind, token.id) {
                self.advance(token);
                return;
            }
        }
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

    /// Number of HG0001 and HG0002 reported so far: a caller compares it before and after a
    /// sub-parser to see whether the sub-parser recovered from a syntax error (cascade rule C1:
    /// then the caller reports nothing more). Other diagnostics do not count: a malformed or
    /// out-of-range constant (HG0006/HG0007) leaves the construct complete.
    pub(crate) fn recoveries(&self) -> usize {
        self.recoveries
    }

    pub(crate) fn push_error(&mut self, error: SyntaxError) {
        self.errors.push(error);
    }

    // ------------------------------------------------------------------ nesting

    /// Can `levels` more levels open here without passing [`NESTING_LIMIT`]?
    pub(crate) fn fits(&self, levels: u32) -> bool {
        self.depth.saturating_add(levels) <= NESTING_LIMIT
    }

    /// Runs `f` one nesting level deeper.
    pub(crate) fn nested<T>(&mut self, f: impl FnOnce(&mut Parser<'t>) -> T) -> T {
        self.depth += 1;
        let result = f(self);
        self.depth -= 1;
        result
    }

    /// HG0012 at the current token, the one that would nest too deep.
    pub(crate) fn error_too_deep(&mut self) {
        let range = self.nth_range(0);
        self.errors.push(SyntaxError::new(
            ErrorCode::HG0012,
            range,
            format!("nesting is deeper than {NESTING_LIMIT} levels"),
        ));
    }

    /// Adds the tokens from the current `open` token to the `close` that balances it, flat,
    /// to the tree (the caller wraps them in an ERROR node). Stops early at the end of the
    /// file, at an item keyword that starts a line and, for parentheses, before a `;`.
    pub(crate) fn skip_balanced(&mut self, open: SyntaxKind, close: SyntaxKind) {
        let mut open_count = 0usize;
        while !self.at_eof() {
            let kind = self.current();
            if kind == open {
                open_count += 1;
            } else if kind == close {
                open_count = open_count.saturating_sub(1);
                if open_count == 0 {
                    self.bump();
                    break;
                }
            } else if (kind == SEMI && open == L_PAREN)
                || (self.nth_on_new_line(0) && self.at_item_start())
            {
                break;
            }
            self.bump();
        }
    }

    /// HG0001 at the current token: `expected {expected}, found {found}`.
    pub(crate) fn error_expected(&mut self, expected: &str) {
        let range = self.nth_range(0);
        let message = format!("expected {expected}, found {}", self.found());
        self.recoveries += 1;
        self.errors
            .push(SyntaxError::new(ErrorCode::HG0001, range, message));
    }

    /// HG0001 at the current token, with a related location: `expected {expected}, found
    /// {found}`, and `related_message` at `related` (the `IF` an `END_IF` would close).
    pub(crate) fn error_expected_related(
        &mut self,
        expected: &str,
        related: TextRange,
        related_message: &str,
    ) {
        let range = self.nth_range(0);
        let message = format!("expected {expected}, found {}", self.found());
        self.recoveries += 1;
        self.errors.push(
            SyntaxError::new(ErrorCode::HG0001, range, message)
                .with_related(related, related_message),
        );
    }

    /// HG0002: the element is complete but its `;` is missing.
    pub(crate) fn error_missing_semi(&mut self, element: &dyn fmt::Display) {
        let at = TextRange::empty(self.last_end);
        self.recoveries += 1;
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
    pub(crate) fn error_unclosed(&mut self, open: TextRange, construct: &dyn fmt::Display) {
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
                R_ANGLE if self.r_angle_closes() => break,
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
                R_ANGLE if self.r_angle_closes() => break,
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
    pub(crate) fn expect_semi(
        &mut self,
        element: &dyn fmt::Display,
        can_begin: fn(&Parser<'_>) -> bool,
    ) {
        if self.at(SEMI) {
            self.bump();
        } else if self.at_eof()
            || self.r_angle_closes()
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
    pub(crate) fn expect_open(&mut self, what: &dyn fmt::Display) -> Option<TextRange> {
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
        self.nth_item_start(0)
    }

    /// Does an item begin at the `n`th token: an item keyword followed by what can continue
    /// that item (language.md §1.4)? Otherwise the keyword is a name.
    fn nth_item_start(&self, n: usize) -> bool {
        let Some(token) = self.nth_token(n) else {
            return false;
        };
        match token.keyword {
            GRAPH_KW | GROUP_KW | CHART_KW | BLOCK_KW => {
                self.nth_is_name(n + 1) || self.nth(n + 1) == STRING
            }
            TEST_KW => self.nth_is_name(n + 1),
            SYMBOLS_KW => self.nth_opens_body(n + 1),
            MNEMONIC_KW => {
                self.nth_is_kw(n + 1, SIMATIC_KW) || self.nth_is_kw(n + 1, INTERNATIONAL_KW)
            }
            _ => false,
        }
    }

    /// A member keyword of `scope` at statement start (language.md §1.4).
    pub(crate) fn at_member_start(&self, scope: Scope) -> bool {
        self.nth_member_start(0, scope)
    }

    /// Does a member of `scope` begin at the `n`th token (language.md §1.4)? Only a keyword
    /// followed by what begins that member counts; otherwise the keyword is a name (§7).
    fn nth_member_start(&self, n: usize, scope: Scope) -> bool {
        let Some(token) = self.nth_token(n) else {
            return false;
        };
        let named = || self.nth_is_name(n + 1) || self.nth(n + 1) == NUMBER;
        match (scope, token.keyword) {
            (Scope::Graph, STATE_KW) => self.nth_starts_number(n + 1),
            (Scope::Graph, TRANS_KW) => {
                self.nth_starts_number(n + 1)
                    || self.nth_is_kw(n + 1, ANY_KW)
                    || self.nth_is_kw(n + 1, RETURN_KW)
            }
            (Scope::Graph, ACTIVATE_KW) => self.nth_is_name(n + 1),
            // No STL statement begins with a name and `<`: here `<` always opens the body.
            (Scope::Graph, PERMANENT_KW | IN_KW | OUT_KW | IN_OUT_KW | STAT_KW) => {
                self.nth(n + 1) == L_ANGLE
            }
            (Scope::Group, INSTANCE_KW) => {
                self.nth(n + 1) == IDENT
                    && self.nth(n + 2) == COLON
                    && !(self.nth(n + 3) == EQ && self.nth_joined(n + 3))
            }
            (Scope::Group, OPTION_KW) => {
                self.nth(n + 1) == IDENT
                    && (self.nth(n + 2) == SEMI || self.nth_starts_number(n + 2))
            }
            (Scope::Sequencer, STEP_KW | TRANS_KW | JUMP_KW | LOOP_KW | SEQUENCER_KW) => named(),
            (Scope::Sequencer, PARALLEL_KW | ALT_KW | BRANCH_KW) => self.nth_opens_body(n + 1),
            (Scope::Chart, SEQUENCER_KW) => named(),
            (Scope::Chart, ACTION_KW) => self.nth_is_name(n + 1),
            (Scope::Chart, IN_KW | OUT_KW | IN_OUT_KW | STAT_KW) => self.nth_opens_body(n + 1),
            _ => false,
        }
    }

    /// Is the `n`th token an identifier that can be a name: any identifier but the operators
    /// `and`, `or`, `xor`, `not` (reserved words, language.md §7) and the IEC words that
    /// follow an operand (`THEN`, `OF`, `MOD`, docs/iec.md §2)? After a keyword, such a word
    /// makes the keyword a name in an expression (`step and x`, `IF step THEN`).
    fn nth_is_name(&self, n: usize) -> bool {
        self.nth_token(n).is_some_and(|t| {
            t.kind == IDENT
                && !matches!(
                    t.keyword,
                    AND_KW | OR_KW | XOR_KW | NOT_KW | THEN_KW | OF_KW | MOD_KW
                )
        })
    }

    /// Can an operand of a chart expression begin at the `n`th token (language.md §6)?
    pub(crate) fn nth_starts_operand(&self, n: usize) -> bool {
        match self.nth(n) {
            IDENT | STRING | NUMBER | TYPED_CONST | CHAR | L_PAREN => true,
            // `-5`, and unary minus: `-x`, `-(a + b)`, `- 5`.
            MINUS => {
                matches!(
                    self.nth(n + 1),
                    NUMBER | IDENT | TYPED_CONST | STRING | L_PAREN
                ) && !self.nth_on_new_line(n + 1)
            }
            _ => false,
        }
    }

    /// Does the `<` at the `n`th token open a body after a keyword (`in <`, `parallel <`,
    /// `symbols <`), rather than compare a variable named like the keyword in a chart
    /// expression (`in < 5`, `in <> x`, `in <= x`)? A body begins with `>`, a declaration or
    /// symbol `NAME :`, a block label, `branch <` or a sequencer element; a comparison with
    /// an operand. (Looks at most four tokens ahead; no recursion.)
    fn nth_opens_body(&self, n: usize) -> bool {
        if self.nth(n) != L_ANGLE {
            return false;
        }
        let next = n + 1;
        let joined = self.nth_joined(next);
        match self.nth(next) {
            EQ if joined => false,
            // `<>`: an empty body, unless an operand follows on the line (`in <> 5`).
            R_ANGLE if joined => {
                self.nth_on_new_line(next + 1) || !self.nth_starts_operand(next + 1)
            }
            IDENT | STRING if self.nth(next + 1) == COLON => true,
            IDENT
                if self.nth(next + 1) == MINUS
                    && self.nth(next + 2) == COLON
                    && self.nth_has(next, stl::word::LETTER_C) =>
            {
                true
            }
            IDENT => match self.nth_token(next).map_or(IDENT, |t| t.keyword) {
                BRANCH_KW | PARALLEL_KW | ALT_KW => self.nth(next + 1) == L_ANGLE,
                STEP_KW | TRANS_KW | JUMP_KW | LOOP_KW | SEQUENCER_KW => {
                    self.nth_is_name(next + 1) || self.nth(next + 1) == NUMBER
                }
                _ => false,
            },
            _ => !self.nth_starts_operand(next),
        }
    }

    /// Does the `>` at the current position close the block (language.md §1.3)? At statement
    /// start it does (the callers see to the STL comparisons). Inside a statement, a `>` that
    /// is part of a joined token (`->`, `=>`, `<>`, `>=`, `>I`) does not, nor does a `>` that
    /// an operand follows on its line (a comparison) — unless that operand is the keyword of
    /// an item or member that begins there (`> trans 1->2 <`).
    pub(crate) fn r_angle_closes(&self) -> bool {
        let Some(token) = self.nth_token(0) else {
            return false;
        };
        if token.kind != R_ANGLE {
            return false;
        }
        let after_joined = token.joined
            && self.pos > 0
            && matches!(self.significant[self.pos - 1].kind, MINUS | EQ | L_ANGLE);
        let before_joined =
            self.nth_joined(1) && (self.nth(1) == EQ || self.nth_has(1, stl::word::CMP_TYPE));
        if after_joined || before_joined {
            return false;
        }
        if self.nth_on_new_line(1) || !self.nth_starts_operand(1) {
            return true;
        }
        self.nth_item_start(1)
            || [Scope::Graph, Scope::Group, Scope::Sequencer, Scope::Chart]
                .iter()
                .any(|&s| self.nth_member_start(1, s))
    }

    /// Common loop control for `< ... >` bodies: returns `true` when the body ends here —
    /// after consuming its `>`, or (reporting HG0003) at the end of the file, an item keyword
    /// or a member keyword of an enclosing scope.
    pub(crate) fn body_ends(
        &mut self,
        open: TextRange,
        construct: &dyn fmt::Display,
        scopes: &[Scope],
    ) -> bool {
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

    /// `:=` written as two adjacent tokens at the `n`th token.
    pub(crate) fn nth_is_assign(&self, n: usize) -> bool {
        self.nth(n) == COLON && self.nth(n + 1) == EQ && self.nth_joined(n + 1)
    }

    /// A `:` that is not the start of `:=`.
    pub(crate) fn at_colon(&self) -> bool {
        self.at(COLON) && !self.at_assign()
    }

    /// Number of tokens of a number that may be negative at the current position: 1 for a
    /// number, 2 for `-` and a number written together (`-1`; language.md §1.1), 0 if none
    /// starts here. With `integer`, only whole numbers count: an `INT` of the grammar
    /// (language.md §1.5). Both tokens stay as lexed, children of the node that holds the
    /// number (`ast::Terminal`).
    pub(crate) fn signed_number_len(&self, integer: bool) -> usize {
        let is_number = |n: usize| {
            if integer {
                self.nth_has(n, stl::word::INTEGER)
            } else {
                self.nth(n) == NUMBER
            }
        };
        if is_number(0) {
            1
        } else if self.at(MINUS) && self.nth_joined(1) && is_number(1) {
            2
        } else {
            0
        }
    }

    /// Does a number, or `-` and a number written together, start at the `n`th token?
    fn nth_starts_number(&self, n: usize) -> bool {
        self.nth(n) == NUMBER
            || (self.nth(n) == MINUS && self.nth(n + 1) == NUMBER && self.nth_joined(n + 1))
    }

    /// `->` written as two adjacent tokens.
    pub(crate) fn at_arrow(&self) -> bool {
        self.at(MINUS) && self.nth(1) == R_ANGLE && self.nth_joined(1)
    }
}

#[cfg(test)]
mod tests {
    use crate::{SyntaxKind::*, lexer::tokenize, parse};

    /// The parser lexes on its own (see `Parser::new`); its tokens must be `tokenize`'s.
    #[test]
    fn parser_tokens_are_the_lexer_tokens() {
        assert_eq!(std::mem::size_of::<super::Significant<'_>>(), 32);
        for text in [
            "",
            "\u{FEFF}",
            "\u{FEFF}graph G < >",
            "$",
            "$@",
            "graph $@ G <\n$>",
            "a$@b",
            "\"open\n'x''",
            "@@ // note\n@ §§",
            "graph Gärtner < state 1 < U Ä; > >€",
            "  \r\n\t",
        ] {
            let leaves: Vec<_> = parse(text)
                .syntax_node()
                .descendants_with_tokens()
                .filter_map(|e| e.into_token())
                .map(|t| (t.kind(), t.text().to_owned()))
                .collect();
            let tokens = tokenize(text);
            assert_eq!(leaves.len(), tokens.len(), "{text:?}");
            for ((kind, leaf), token) in leaves.iter().zip(&tokens) {
                assert_eq!(leaf, token.text, "{text:?}");
                assert!(
                    *kind == token.kind || (token.kind == IDENT && kind.is_keyword()),
                    "{text:?}: {kind:?} for {:?}",
                    token.kind
                );
            }
        }
    }
}

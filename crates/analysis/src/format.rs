//! The canonical layout of `tooling.md` §2a: `higraph-lsp fmt` and LSP formatting.
//!
//! [`format`] rebuilds a file from its syntax tree. The layout rules:
//!
//! * two spaces of indentation per open `<`; one member per line (declaration, state,
//!   transition, instance, actual, symbol, option, step, condition, statement, …);
//! * blank lines between members are kept, at most one; blank lines right after a `<` and
//!   right before a `>` are dropped;
//! * comments stay where they are: a comment at the end of a line stays at the end of the line
//!   of the token before it (after one space), a comment on its own line stays on its own line
//!   (indented like the member after it). A comment inside a construct that would otherwise go
//!   on one line makes it multi-line; a comment inside a statement continues the statement on
//!   the next line, indented once more;
//! * keywords in lower case, also the values of `mode` and `switching` (in the grammar's
//!   spelling: `auto`, `T_or_B`); STL operations, block labels, action qualifiers, address
//!   areas and the known type names in upper case; everything else (identifiers, strings,
//!   constants, option names) exactly as written. Mnemonics are not translated (that is the
//!   HG4007 quick fix);
//! * a state, transition or `permanent` body holding at most one block with at most one
//!   statement stays on the header's line: `state 4 "Auf" < C: = Auf; >`, also with `wait` and
//!   `supervise` items, which are not blocks (`< C: = #Ab; supervise T#10S; >`); otherwise each
//!   label goes on its own line with its statements below it, indented once more, and `wait`
//!   and `supervise` items go on their own lines at the labels' level;
//! * a variable section stays on one line when it fits in [`MAX_WIDTH`] columns;
//! * next to a `// higraph-allow:` comment (before the construct, or at the end of its last
//!   line), a body keeps the input's choice between one line and several, because the comment
//!   suppresses diagnostics on its own line and the next one only;
//! * transition headers are `trans A->B prio N [auto] [manual] [waits] [fault] ["name"]`, with
//!   the implicit priority (diagnostics.md §2.6, [`implicit_priorities`]) written out; state
//!   headers are `state N ["name"] [fault] [message]` (attributes keep their order);
//! * `:=` of the actuals of an instance and `:` of the symbols of a table are aligned (over
//!   the whole block);
//! * one space around `:=` and `:`, none around `->`, none before `;` and `,`, one after `,`;
//!   one space between an operation and its operand, except after `+` and `)` where an operand
//!   that touched the operation keeps touching it (`+AR1`, `)MCR` are operations of their
//!   own); the spacing inside addresses, constants and indirect operands is kept (`E 1.0` and
//!   `E1.0` differ: the second is a name in a chart), only runs of blanks become one space;
//! * charts (decisions where the spec is silent): a step, transition, jump, loop, `start`,
//!   `pre`, `post`, `init`, `run` or `term` body holding at most one entry (condition,
//!   statement, step item) stays on one line, like state bodies; sequencers, `parallel`,
//!   `alt`, `branch`, graphs, groups, instances, symbol tables and block interfaces are always
//!   one member per line; an empty body is written `< >`;
//! * tests: one statement per line (`runtime.md` §5.1), also for a short test; keywords
//!   (`restart cold`) in lower case, paths, command names and messages as written.
//!
//! Line endings: the output uses the line ending of the input's first line break (CR LF or
//! LF; a file without line breaks, or with a lone CR first, gets LF), so Windows files stay
//! Windows files. A leading byte-order mark is kept. The output ends with one line break.
//!
//! The formatter refuses a file with syntax errors ([`FormatError::Syntax`]), and a tree more
//! than 2000 levels deep ([`FormatError::Internal`]; the parser's nesting limit keeps files
//! without syntax errors far below that): its walks recurse once per level. It checks its
//! own result: the output must parse without errors and have the same significant tokens, with
//! the same parent nodes, as the input (modulo the case changes above, the order of header
//! clauses and the priorities written out); otherwise it returns [`FormatError::Internal`]
//! and the caller keeps the input. So formatting never loses a token or changes the meaning.

use std::collections::HashMap;
use std::fmt;

use higraph_syntax::{
    SyntaxElement, SyntaxError, SyntaxKind,
    SyntaxKind::*,
    SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
    parse,
    rowan::NodeOrToken,
};

/// A variable section stays on one line if that line is at most this many columns wide.
pub const MAX_WIDTH: usize = 100;

/// One level of indentation.
const INDENT: &str = "  ";

/// Why a file was not formatted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FormatError {
    /// The file has syntax errors (HG0xxx); it is left as it is.
    Syntax(Vec<SyntaxError>),
    /// The formatter's result failed its own check (a bug); the file is left as it is.
    Internal(String),
    /// [`format_with`]'s caller no longer wants the result.
    Cancelled,
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormatError::Syntax(errors) => match errors.len() {
                1 => f.write_str("the file has a syntax error"),
                n => write!(f, "the file has {n} syntax errors"),
            },
            FormatError::Internal(reason) => write!(f, "internal formatter error: {reason}"),
            FormatError::Cancelled => f.write_str("formatting was cancelled"),
        }
    }
}

impl std::error::Error for FormatError {}

/// Formats a whole file in the canonical layout. Idempotent: formatting the result again
/// gives the same text.
pub fn format(text: &str) -> Result<String, FormatError> {
    format_with(text, &|| false)
}

/// [`format`], asking `is_cancelled` between members and phases: once it answers `true` the
/// work stops and the result is [`FormatError::Cancelled`] (a language server whose request
/// was cancelled must not keep computing it).
pub fn format_with(text: &str, is_cancelled: &dyn Fn() -> bool) -> Result<String, FormatError> {
    let stop = || {
        if is_cancelled() {
            Err(FormatError::Cancelled)
        } else {
            Ok(())
        }
    };
    let parsed = parse(text);
    stop()?;
    if !parsed.errors().is_empty() {
        return Err(FormatError::Syntax(parsed.errors().to_vec()));
    }
    let root = parsed.syntax_node();
    // The layout walks the tree recursively. The parser's nesting limit keeps trees of
    // files without syntax errors far shallower; this bound holds whatever that limit is.
    if tree_depth(&root) > MAX_DEPTH {
        return Err(FormatError::Internal(format!(
            "the file nests constructs more than {MAX_DEPTH} levels deep"
        )));
    }
    let tokens = TokenTable::new(&root);
    let prios = file_priorities(&root);
    stop()?;
    let mut formatter = Formatter {
        tokens: &tokens,
        prios: &prios,
        em: Emitter::new(&tokens),
        is_cancelled,
        cancelled: false,
    };
    formatter.source_file(&root);
    if formatter.cancelled {
        return Err(FormatError::Cancelled);
    }
    let body = formatter.em.finish()?;
    stop()?;

    let mut out = String::with_capacity(body.len() + 16);
    if text.starts_with('\u{FEFF}') {
        out.push('\u{FEFF}');
    }
    if uses_crlf(text) {
        out.push_str(&body.replace('\n', "\r\n"));
    } else {
        out.push_str(&body);
    }
    verify(&root, &prios, &out)?;
    Ok(out)
}

/// The canonical layout of the top-level items (graphs, groups, charts, symbol tables, tests,
/// options, …) that `range` touches, for range formatting: each such item's range in `text`
/// with its text in [`format_with`]'s output of the whole file, when the two differ. So the
/// result is exactly the full formatting restricted to those items (the file's mnemonic set,
/// line endings and implicit priorities are those of the whole file), and the text between
/// items is left alone. An item is touched when it overlaps a non-empty `range`, or contains
/// an empty one (a cursor) at its start, end or inside. Refused like [`format_with`]: a file
/// with syntax errors is [`FormatError::Syntax`].
pub fn format_items_with(
    text: &str,
    range: TextRange,
    is_cancelled: &dyn Fn() -> bool,
) -> Result<Vec<(TextRange, String)>, FormatError> {
    let formatted = format_with(text, is_cancelled)?;
    let items = |text: &str| -> Vec<TextRange> {
        parse(text)
            .syntax_node()
            .children()
            .map(|item| item.text_range())
            .collect()
    };
    let (old, new) = (items(text), items(&formatted));
    if old.len() != new.len() {
        return Err(FormatError::Internal(format!(
            "the formatted file has {} top-level items, the file {}",
            new.len(),
            old.len()
        )));
    }
    let touched = |item: TextRange| {
        if range.is_empty() {
            item.contains_inclusive(range.start())
        } else {
            range.start() < item.end() && item.start() < range.end()
        }
    };
    let mut out = Vec::new();
    for (old, new) in old.into_iter().zip(new).filter(|(old, _)| touched(*old)) {
        let before = text.get(std::ops::Range::<usize>::from(old));
        let after = formatted.get(std::ops::Range::<usize>::from(new));
        match (before, after) {
            (Some(before), Some(after)) if before == after => {}
            (Some(_), Some(after)) => out.push((old, after.to_owned())),
            _ => {
                return Err(FormatError::Internal(
                    "an item is not on character boundaries".into(),
                ));
            }
        }
    }
    Ok(out)
}

/// The deepest syntax tree the formatter lays out (its walks recurse once per level).
const MAX_DEPTH: usize = 2000;

/// The number of node levels of a tree, without recursion.
fn tree_depth(root: &SyntaxNode) -> usize {
    use higraph_syntax::rowan::WalkEvent;
    let mut depth = 0usize;
    let mut deepest = 0;
    for event in root.preorder() {
        match event {
            WalkEvent::Enter(_) => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            WalkEvent::Leave(_) => depth = depth.saturating_sub(1),
        }
    }
    deepest
}

/// Does the input's first line break use CR LF?
fn uses_crlf(text: &str) -> bool {
    text.find(['\r', '\n'])
        .is_some_and(|at| text[at..].starts_with("\r\n"))
}

/// The self-check of [`format`]: the output parses cleanly and carries the same significant
/// tokens as the input.
fn verify(
    root: &SyntaxNode,
    prios: &HashMap<TextSize, u64>,
    output: &str,
) -> Result<(), FormatError> {
    let reparsed = parse(output);
    if let Some(error) = reparsed.errors().first() {
        return Err(FormatError::Internal(format!(
            "the formatted text does not parse: {}",
            error.message
        )));
    }
    let new_root = reparsed.syntax_node();
    let new_prios = file_priorities(&new_root);
    let before = significant_stream(root, prios);
    let after = significant_stream(&new_root, &new_prios);
    if before != after {
        let at = before
            .iter()
            .zip(&after)
            .position(|(a, b)| a != b)
            .unwrap_or(before.len().min(after.len()));
        return Err(FormatError::Internal(format!(
            "the formatted text differs in its tokens at token {at}: {:?} became {:?}",
            before.get(at),
            after.get(at)
        )));
    }
    Ok(())
}

// ------------------------------------------------------------------------------------------
// Implicit priorities (diagnostics.md §2.6)

/// The computed priority of every transition of `graph` that has no `prio`, in the order of
/// `graph.transitions()`: `Some(p)` for a transition without `prio` that belongs to a
/// priority range, `None` for a transition with an explicit `prio` and for one that belongs
/// to no range (its source is `return` or a state that does not exist).
///
/// The priorities are the graph rules' own (`rules::graph::effective_priorities`, §2.6), so
/// what the formatter writes out is what the rules computed.
pub fn implicit_priorities(graph: &ast::Graph) -> Vec<Option<u64>> {
    graph
        .transitions()
        .zip(crate::rules::graph::effective_priorities(graph))
        .map(|(trans, priority)| priority.filter(|_| trans.prio().is_none()))
        .collect()
}

/// The highest priority the formatter writes out: larger implicit priorities are an error
/// (HG2303) that an explicit number would report differently, so they stay implicit.
const MAX_WRITTEN_PRIORITY: u64 = 65535;

/// The implicit priorities of every graph of a file, by the start offset of the transition.
fn file_priorities(root: &SyntaxNode) -> HashMap<TextSize, u64> {
    let mut prios = HashMap::new();
    for graph in root.descendants().filter_map(ast::Graph::cast) {
        for (trans, prio) in graph.transitions().zip(implicit_priorities(&graph)) {
            if let Some(prio) = prio.filter(|&p| p <= MAX_WRITTEN_PRIORITY) {
                prios.insert(trans.syntax().text_range().start(), prio);
            }
        }
    }
    prios
}

// ------------------------------------------------------------------------------------------
// Tokens and the trivia between them

/// A comment in the trivia before a token.
#[derive(Debug, Clone)]
struct GapComment {
    text: String,
    /// Line breaks between the previous token or comment and this comment.
    newlines_before: usize,
}

/// The trivia before one significant token (or before the end of the file).
#[derive(Debug, Clone, Default)]
struct Gap {
    comments: Vec<GapComment>,
    /// Line breaks between the last comment (or the previous token) and the token.
    newlines_before_token: usize,
    /// No trivia at all: the token touches the previous one.
    touching: bool,
}

/// The significant tokens of a file in text order, with the trivia before each.
struct TokenTable {
    /// Token start offset → index.
    index: HashMap<TextSize, usize>,
    /// `gaps[i]` is the trivia before token `i`; the last entry is the trivia before the end
    /// of the file.
    gaps: Vec<Gap>,
    /// `comments_upto[i]`: how many comments lie in `gaps[..i]`.
    comments_upto: Vec<usize>,
    /// `breaks_upto[i]`: how many of `gaps[..i]` hold a line break or a comment.
    breaks_upto: Vec<usize>,
    /// The start offset of every significant token, in text order (so ascending).
    starts: Vec<TextSize>,
}

impl TokenTable {
    fn new(root: &SyntaxNode) -> TokenTable {
        let mut index = HashMap::new();
        let mut starts = Vec::new();
        let mut gaps = Vec::new();
        let mut gap = Gap {
            touching: true,
            ..Gap::default()
        };
        let mut newlines = 0usize;
        for element in root.descendants_with_tokens() {
            let NodeOrToken::Token(token) = element else {
                continue;
            };
            match token.kind() {
                WHITESPACE => {
                    newlines += count_line_breaks(token.text());
                    gap.touching = false;
                }
                COMMENT => {
                    gap.comments.push(GapComment {
                        text: token.text().trim_end().to_owned(),
                        newlines_before: newlines,
                    });
                    newlines = 0;
                    gap.touching = false;
                }
                _ => {
                    gap.newlines_before_token = newlines;
                    index.insert(token.text_range().start(), gaps.len());
                    starts.push(token.text_range().start());
                    gaps.push(std::mem::take(&mut gap));
                    gap.touching = true;
                    newlines = 0;
                }
            }
        }
        gap.newlines_before_token = newlines;
        gaps.push(gap);
        let mut comments_upto = Vec::with_capacity(gaps.len() + 1);
        let mut count = 0;
        for gap in &gaps {
            comments_upto.push(count);
            count += gap.comments.len();
        }
        comments_upto.push(count);
        let mut breaks_upto = Vec::with_capacity(gaps.len() + 1);
        let mut count = 0;
        for gap in &gaps {
            breaks_upto.push(count);
            count += usize::from(gap.newlines_before_token > 0 || !gap.comments.is_empty());
        }
        breaks_upto.push(count);
        TokenTable {
            index,
            gaps,
            comments_upto,
            breaks_upto,
            starts,
        }
    }

    /// The indices of the first and the last significant token within `range` (`None` if it
    /// holds none). A binary search, so asking it of every node of a deep tree stays cheap.
    fn span(&self, range: TextRange) -> Option<(usize, usize)> {
        let first = self.starts.partition_point(|&start| start < range.start());
        let end = self.starts.partition_point(|&start| start < range.end());
        (first < end).then(|| (first, end - 1))
    }

    fn index_of(&self, token: &SyntaxToken) -> Option<usize> {
        self.index.get(&token.text_range().start()).copied()
    }

    /// Are there comments before any of the tokens `from..=to`?
    fn comments_in(&self, from: usize, to: usize) -> bool {
        if from > to {
            return false;
        }
        let count = |i: usize| self.comments_upto.get(i).copied().unwrap_or(0);
        count(to + 1) > count(from)
    }

    /// Are there line breaks before any of the tokens `from..=to`?
    fn line_breaks_in(&self, from: usize, to: usize) -> bool {
        if from > to {
            return false;
        }
        let count = |i: usize| {
            let last = self.breaks_upto.len().saturating_sub(1);
            self.breaks_upto.get(i.min(last)).copied().unwrap_or(0)
        };
        count(to + 1) > count(from)
    }

    /// Is there a `// higraph-allow:` comment right before token `first` (on its line or the
    /// line before), or at the end of the line of token `last`?
    fn allow_comment_around(&self, first: usize, last: usize) -> bool {
        let is_allow = |comment: &GapComment| comment.text.contains("higraph-allow");
        let before = self
            .gaps
            .get(first)
            .is_some_and(|gap| gap.comments.iter().any(is_allow));
        let after = self.gaps.get(last + 1).is_some_and(|gap| {
            gap.comments
                .first()
                .is_some_and(|c| c.newlines_before == 0 && is_allow(c))
        });
        before || after
    }

    /// Does token `i` touch the token before it?
    fn touching(&self, i: usize) -> bool {
        self.gaps.get(i).is_some_and(|gap| gap.touching)
    }

    /// The number of significant tokens.
    fn len(&self) -> usize {
        self.gaps.len().saturating_sub(1)
    }
}

/// LF, CR LF and a lone CR each count as one line break.
fn count_line_breaks(text: &str) -> usize {
    let bytes = text.as_bytes();
    let mut count = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')) {
            count += 1;
        }
    }
    count
}

/// The significant tokens of a node, in text order.
fn significant_tokens(node: &SyntaxNode) -> impl Iterator<Item = SyntaxToken> + use<> {
    node.descendants_with_tokens()
        .filter_map(|element| element.into_token())
        .filter(|token| !token.kind().is_trivia())
}

// ------------------------------------------------------------------------------------------
// Pieces: formatted tokens with the separator before them

/// What goes between a piece and the one before it on the same line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Sep {
    /// Nothing: the pieces touch.
    Join,
    /// One space.
    Space,
    /// This many spaces (alignment).
    Pad(usize),
}

impl Sep {
    fn width(self) -> usize {
        match self {
            Sep::Join => 0,
            Sep::Space => 1,
            Sep::Pad(n) => n,
        }
    }
}

/// One output token.
#[derive(Debug, Clone)]
struct Piece {
    /// The input token it comes from; `None` for text the formatter adds (a priority).
    token: Option<usize>,
    /// Where that token starts in the input.
    start: Option<TextSize>,
    text: String,
    kind: SyntaxKind,
    /// The kind of the token's parent node.
    parent: SyntaxKind,
    sep: Sep,
}

/// Where the first piece of a unit goes.
#[derive(Debug, Clone, Copy)]
enum Place {
    /// On the current line, after this separator.
    Inline(Sep),
    /// On a new line.
    Line {
        indent: usize,
        /// Indentation of comments on their own lines before the piece.
        comment_indent: usize,
        /// Keep one blank line if the input had one here.
        blank: bool,
    },
}

impl Place {
    /// A member on its own line.
    fn member(indent: usize) -> Place {
        Place::Line {
            indent,
            comment_indent: indent,
            blank: true,
        }
    }

    /// The `>` that closes a multi-line body whose members are at `indent + 1`.
    fn close(indent: usize) -> Place {
        Place::Line {
            indent,
            comment_indent: indent + 1,
            blank: false,
        }
    }
}

fn width(pieces: &[Piece]) -> usize {
    pieces
        .iter()
        .enumerate()
        .map(|(i, piece)| {
            let sep = if i == 0 { 0 } else { piece.sep.width() };
            sep + piece.text.chars().count()
        })
        .sum()
}

// ------------------------------------------------------------------------------------------
// The emitter: pieces and comments → lines

struct Emitter<'t> {
    tokens: &'t TokenTable,
    out: String,
    /// How often each input token was written (must end as exactly once each).
    used: Vec<u8>,
    /// Nothing written on the current line yet.
    at_line_start: bool,
    /// A comment ends the current line: the next piece must start a new one.
    need_newline: bool,
    /// The last thing written was a `<` (no blank line may follow).
    after_open: bool,
    /// Indentation of the current unit; continuation lines get one more.
    unit_indent: usize,
}

impl<'t> Emitter<'t> {
    fn new(tokens: &'t TokenTable) -> Emitter<'t> {
        Emitter {
            tokens,
            out: String::new(),
            used: vec![0; tokens.len()],
            at_line_start: true,
            need_newline: false,
            after_open: true,
            unit_indent: 0,
        }
    }

    fn newline(&mut self) {
        let trimmed = self.out.trim_end_matches([' ', '\t']).len();
        self.out.truncate(trimmed);
        self.out.push('\n');
        self.at_line_start = true;
        self.need_newline = false;
    }

    fn blank_line(&mut self) {
        if !self.out.is_empty() && !self.out.ends_with("\n\n") {
            self.out.push('\n');
        }
    }

    fn indent(&mut self, level: usize) {
        for _ in 0..level {
            self.out.push_str(INDENT);
        }
    }

    /// Writes the comments of gap `gap`: the first one at the end of the current line if it
    /// was there in the input, the others on their own lines at `indent`.
    fn comments(&mut self, gap: usize, indent: usize) {
        let tokens = self.tokens;
        let Some(gap) = tokens.gaps.get(gap) else {
            return;
        };
        for (k, comment) in gap.comments.iter().enumerate() {
            if k == 0 && comment.newlines_before == 0 && !self.at_line_start {
                self.out.push(' ');
            } else {
                if !self.at_line_start {
                    self.newline();
                }
                if comment.newlines_before >= 2 && !self.after_open {
                    self.blank_line();
                }
                self.indent(indent);
            }
            self.out.push_str(&comment.text);
            self.at_line_start = false;
            self.need_newline = true;
            self.after_open = false;
        }
    }

    /// Writes one piece at `place`.
    fn piece(&mut self, place: Place, piece: &Piece) {
        let comment_indent = match place {
            Place::Line { comment_indent, .. } => comment_indent,
            Place::Inline(_) => self.unit_indent + 1,
        };
        if let Some(i) = piece.token {
            if let Some(count) = self.used.get_mut(i) {
                *count = count.saturating_add(1);
            }
            self.comments(i, comment_indent);
        }
        match place {
            Place::Line { indent, blank, .. } => {
                if !self.at_line_start {
                    self.newline();
                }
                let newlines = piece
                    .token
                    .and_then(|i| self.tokens.gaps.get(i))
                    .map_or(0, |gap| gap.newlines_before_token);
                if blank && newlines >= 2 && !self.after_open {
                    self.blank_line();
                }
                self.indent(indent);
                self.unit_indent = indent;
            }
            Place::Inline(sep) => {
                if self.need_newline || self.at_line_start {
                    if !self.at_line_start {
                        self.newline();
                    }
                    self.indent(self.unit_indent + 1);
                } else {
                    for _ in 0..sep.width() {
                        self.out.push(' ');
                    }
                }
            }
        }
        self.out.push_str(&piece.text);
        self.at_line_start = false;
        self.need_newline = false;
        self.after_open = piece.kind == L_ANGLE;
    }

    /// Writes a unit: its first piece at `place`, the others after their separators.
    fn pieces(&mut self, place: Place, pieces: &[Piece]) {
        for (i, piece) in pieces.iter().enumerate() {
            let place = if i == 0 {
                place
            } else {
                Place::Inline(piece.sep)
            };
            self.piece(place, piece);
        }
    }

    /// Writes the comments at the end of the file and returns the text (LF line ends).
    fn finish(mut self) -> Result<String, FormatError> {
        let eof = self.tokens.len();
        self.comments(eof, 0);
        if !self.at_line_start {
            self.newline();
        }
        while self.out.ends_with("\n\n") {
            self.out.pop();
        }
        if let Some(i) = self.used.iter().position(|&count| count != 1) {
            let what = if self.used[i] == 0 {
                "left out"
            } else {
                "written twice"
            };
            return Err(FormatError::Internal(format!("token {i} was {what}")));
        }
        Ok(self.out)
    }
}

// ------------------------------------------------------------------------------------------
// The formatter: syntax tree → pieces and lines

/// Kinds whose tokens always touch each other.
const JOINED: &[SyntaxKind] = &[
    OPCODE,
    TYPE_REF,
    ARROW,
    ASSIGN_OP,
    LABEL,
    JUMP_LABEL,
    COMPARE_OP,
    VAR_REF,
    STATUS_OPERAND,
    CASE_LABEL,
    OUTPUT_OP,
];

/// Kinds whose tokens keep the spacing of the input (touching or one space), because the
/// spacing is part of what they mean (`E 1.0` vs `E1.0`, `-5`).
const PRESERVED: &[SyntaxKind] = &[ADDRESS, LITERAL, INDIRECT, PATH, TEST_PATH, MESSAGE_TARGET];

/// An identifier inside an address that is an area of either mnemonic set (Appendix A.2),
/// optionally followed by digits (`E`, `MW`, `DB10`, `DBX5`, `E1`).
fn is_area_word(word: &str) -> bool {
    let letters = word.trim_end_matches(|c: char| c.is_ascii_digit());
    crate::address::is_area_spelling(letters)
}

/// Is this a `DBn . DBX…` message target that would read as a data-block address if its
/// tokens touched? Such a target keeps its spacing.
fn looks_like_db_address(node: &SyntaxNode) -> bool {
    let words: Vec<String> = significant_tokens(node)
        .filter(|t| t.kind() == IDENT)
        .map(|t| t.text().to_ascii_uppercase())
        .collect();
    match words.as_slice() {
        [first, second] => {
            let db = first
                .strip_prefix("DB")
                .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
            let access = ["DBX", "DBB", "DBW", "DBD"].iter().any(|a| {
                second
                    .strip_prefix(a)
                    .is_some_and(|n| n.bytes().all(|b| b.is_ascii_digit()))
            });
            db && access
        }
        _ => false,
    }
}

/// The value of a chart property (`mode auto;`, `switching T_or_B;`) in the spelling of the
/// grammar, if it is one of the values the grammar lists for that property.
fn chart_prop_value(token: &SyntaxToken) -> Option<&'static str> {
    let prop = token.parent()?.parent()?;
    if token.parent()?.kind() != NAME_REF || prop.kind() != CHART_PROP {
        return None;
    }
    let values: &[&'static str] = match significant_tokens(&prop).next()?.kind() {
        MODE_KW => &["auto", "manual"],
        SWITCHING_KW => &["T", "B", "T_or_B", "T_and_B", "step"],
        PROFILE_KW => &["iec", "pcs7"],
        _ => return None,
    };
    values
        .iter()
        .copied()
        .find(|value| value.eq_ignore_ascii_case(token.text()))
}

/// The keywords of the IEC statements and `MOD`, written in upper case as IEC 61131-3 writes
/// them (docs/iec.md §5).
fn is_iec_keyword(kind: SyntaxKind) -> bool {
    matches!(
        kind,
        IF_KW | THEN_KW | ELSIF_KW | ELSE_KW | END_IF_KW | CASE_KW | OF_KW | END_CASE_KW | MOD_KW
    )
}

/// A structured statement, always laid out on several lines.
fn is_structured(kind: SyntaxKind) -> bool {
    matches!(kind, IF_STMT | CASE_STMT)
}

/// The text a token is written with.
fn token_text(token: &SyntaxToken) -> String {
    let text = token.text();
    let kind = token.kind();
    if is_iec_keyword(kind) {
        return text.to_ascii_uppercase();
    }
    if kind.is_keyword() {
        return text.to_ascii_lowercase();
    }
    if let Some(value) = chart_prop_value(token) {
        return value.to_owned();
    }
    let parent = token.parent().map(|p| p.kind());
    match parent {
        Some(OPCODE | LABEL | QUALIFIER) => text.to_ascii_uppercase(),
        Some(TYPE_REF) if kind == IDENT => {
            if crate::lang::Type::from_name(text, true).is_some() {
                text.to_ascii_uppercase()
            } else {
                text.to_owned()
            }
        }
        Some(ADDRESS) if kind == IDENT && is_area_word(text) => text.to_ascii_uppercase(),
        Some(NAME_REF) if kind == IDENT && crate::resolve::is_one_word_address_operand(token) => {
            text.to_ascii_uppercase()
        }
        _ => text.to_owned(),
    }
}

/// The separator between two pieces that belong to different nodes. `next_token` is the
/// token of `next` (`None` for added text).
fn boundary_sep(prev: Option<&Piece>, next: &Piece, next_token: Option<&SyntaxToken>) -> Sep {
    let Some(prev) = prev else {
        return Sep::Space;
    };
    if next.kind == SEMI {
        // A `;` touches what it ends (`U x;`, `A : BOOL;`), but an empty statement stands
        // apart (`< ; >`, `E: ;`, `M001: ;`).
        let ends_construct = match (next_token.and_then(|t| t.parent()), prev.start) {
            (Some(parent), Some(start)) => parent.text_range().contains(start),
            _ => false,
        };
        return if ends_construct && prev.parent != JUMP_LABEL {
            Sep::Join
        } else {
            Sep::Space
        };
    }
    let in_parens = |parent: SyntaxKind| matches!(parent, PARAM_LIST | PAREN_EXPR | FB_CALL);
    // `Timer(`, `1, 2..3:`, unary minus `-x` (but `- 5` is no negative number `-5`).
    let unary_minus = prev.kind == MINUS && prev.parent == PREFIX_EXPR && next.kind != NUMBER;
    if (next.kind == L_PAREN && next.parent == FB_CALL)
        || (next.kind == COLON && next.parent == CASE_ARM)
        || unary_minus
    {
        return Sep::Join;
    }
    if next.kind == COMMA
        || (prev.kind == L_PAREN && in_parens(prev.parent))
        || (next.kind == R_PAREN && in_parens(next.parent))
        || prev.parent == ARROW
        || next.parent == ARROW
    {
        Sep::Join
    } else {
        Sep::Space
    }
}

/// Rank of a transition attribute in the canonical header order.
fn attribute_rank(node: &SyntaxNode) -> usize {
    let keyword = significant_tokens(node).next().map(|t| t.kind());
    match keyword {
        Some(AUTO_KW) => 0,
        Some(MANUAL_KW) => 1,
        Some(WAITS_KW) => 2,
        _ => 3,
    }
}

/// The children of a node that has a `< … >` body, split at the body.
struct Split {
    /// Header elements (nodes and significant tokens) before the `<`.
    header: Vec<SyntaxElement>,
    open: Option<SyntaxToken>,
    members: Vec<SyntaxNode>,
    close: Option<SyntaxToken>,
}

fn split(node: &SyntaxNode) -> Split {
    let body = node.children().find(|child| child.kind() == BODY);
    let mut header = Vec::new();
    let mut open = None;
    let mut members = Vec::new();
    let mut close = None;
    let mut visit = |element: SyntaxElement, open: &mut Option<SyntaxToken>| match element {
        NodeOrToken::Token(token) if token.kind().is_trivia() => {}
        NodeOrToken::Token(token) if token.kind() == L_ANGLE && open.is_none() => {
            *open = Some(token);
        }
        NodeOrToken::Token(token) if token.kind() == R_ANGLE && open.is_some() => {
            close = Some(token);
        }
        element if open.is_none() => header.push(element),
        NodeOrToken::Node(member) => members.push(member),
        NodeOrToken::Token(_) => {}
    };
    for element in node.children_with_tokens() {
        match (&element, &body) {
            (NodeOrToken::Node(child), Some(body)) if child == body => {
                for inner in body.children_with_tokens() {
                    visit(inner, &mut open);
                }
            }
            _ => visit(element, &mut open),
        }
    }
    Split {
        header,
        open,
        members,
        close,
    }
}

struct Formatter<'t> {
    tokens: &'t TokenTable,
    prios: &'t HashMap<TextSize, u64>,
    em: Emitter<'t>,
    /// Asked before each member is laid out.
    is_cancelled: &'t dyn Fn() -> bool,
    /// Set once `is_cancelled` said so: every later member is skipped.
    cancelled: bool,
}

impl Formatter<'_> {
    // ---------------------------------------------------------------- pieces

    fn piece(&self, token: &SyntaxToken) -> Piece {
        Piece {
            token: self.tokens.index_of(token),
            start: Some(token.text_range().start()),
            text: token_text(token),
            kind: token.kind(),
            parent: token.parent().map_or(SOURCE_FILE, |p| p.kind()),
            sep: Sep::Space,
        }
    }

    /// Appends a token with the separator that the boundary rules give.
    fn push_token(&self, token: &SyntaxToken, out: &mut Vec<Piece>) {
        if token.kind().is_trivia() {
            return;
        }
        let mut piece = self.piece(token);
        piece.sep = self.boundary(out.last(), &piece, token);
        out.push(piece);
    }

    /// The separator before `piece` (of `token`) after `prev` from another node: the rules of
    /// [`boundary_sep`], except that an operand touching a `+` or `)` opcode keeps touching it:
    /// `+AR1` and `)MCR` are STEP 7 operations of their own (HG4003), while `+ AR1` adds a
    /// constant and `) MCR` closes a bracket; and a number touching a `-` keeps touching it.
    fn boundary(&self, prev: Option<&Piece>, piece: &Piece, token: &SyntaxToken) -> Sep {
        let after_punctuation =
            prev.is_some_and(|p| p.parent == OPCODE && matches!(p.kind, PLUS | R_PAREN));
        // A negative number (`state -1`, `prio -1`, `-1->0`) stays one: `- 1` is no number.
        // (Not the binary `-` of `a - 5`.)
        let negative =
            token.kind() == NUMBER && prev.is_some_and(|p| p.kind == MINUS && p.parent != BIN_EXPR);
        let touching = piece.token.is_some_and(|i| self.tokens.touching(i));
        if (after_punctuation || negative) && touching && token.kind() != SEMI {
            Sep::Join
        } else {
            boundary_sep(prev, piece, Some(token))
        }
    }

    /// Appends the whole element on one line.
    fn collect(&self, element: SyntaxElement, out: &mut Vec<Piece>) {
        match element {
            NodeOrToken::Token(token) => self.push_token(&token, out),
            NodeOrToken::Node(node) => self.collect_node(&node, out),
        }
    }

    fn collect_node(&self, node: &SyntaxNode, out: &mut Vec<Piece>) {
        let kind = node.kind();
        let joined = JOINED.contains(&kind);
        let preserved = PRESERVED.contains(&kind);
        if joined || preserved {
            let keep_spacing = preserved && (kind != MESSAGE_TARGET || looks_like_db_address(node));
            let mut first = true;
            for token in significant_tokens(node) {
                let mut piece = self.piece(&token);
                piece.sep = if first {
                    self.boundary(out.last(), &piece, &token)
                } else if keep_spacing {
                    match piece.token {
                        Some(i) if !self.tokens.touching(i) => Sep::Space,
                        _ => Sep::Join,
                    }
                } else {
                    Sep::Join
                };
                first = false;
                out.push(piece);
            }
            return;
        }
        match kind {
            STATE | TRANS => {
                self.header_pieces(node, out);
                let split = split(node);
                self.inline_body(&split, out);
            }
            _ => {
                for child in node.children_with_tokens() {
                    self.collect(child, out);
                }
            }
        }
    }

    /// The whole node on one line.
    fn inline(&self, node: &SyntaxNode) -> Vec<Piece> {
        let mut out = Vec::new();
        self.collect_node(node, &mut out);
        out
    }

    /// `< members >` on one line.
    fn inline_body(&self, split: &Split, out: &mut Vec<Piece>) {
        if let Some(open) = &split.open {
            self.push_token(open, out);
        }
        for member in &split.members {
            self.collect_node(member, out);
        }
        if let Some(close) = &split.close {
            self.push_token(close, out);
        }
    }

    /// Comments between the first and the last token of the elements (in text order).
    fn comments_within(&self, elements: &[SyntaxElement]) -> bool {
        let (Some(first), Some(last)) = (elements.first(), elements.last()) else {
            return false;
        };
        let range = TextRange::new(first.text_range().start(), last.text_range().end());
        match self.tokens.span(range) {
            Some((first, last)) => self.tokens.comments_in(first + 1, last),
            None => false,
        }
    }

    /// The header of a node (everything before its `<`). State and transition headers are put
    /// in canonical order, and a transition's implicit priority is written out.
    fn header_pieces(&self, node: &SyntaxNode, out: &mut Vec<Piece>) {
        let split = split(node);
        let header = &split.header;
        let reorder = !self.comments_within(header);
        match node.kind() {
            TRANS => {
                let is_clause = |e: &SyntaxElement| {
                    e.as_node().is_some_and(|n| {
                        matches!(n.kind(), PRIO_CLAUSE | ATTRIBUTE | COMMENT_STRING)
                    })
                };
                let fixed: Vec<&SyntaxElement> = header.iter().filter(|e| !is_clause(e)).collect();
                let clauses: Vec<SyntaxNode> = header
                    .iter()
                    .filter(|e| is_clause(e))
                    .filter_map(|e| e.as_node().cloned())
                    .collect();
                for element in &fixed {
                    self.collect((*element).clone(), out);
                }
                let has_prio = clauses.iter().any(|c| c.kind() == PRIO_CLAUSE);
                if !has_prio && let Some(&prio) = self.prios.get(&node.text_range().start()) {
                    out.push(Piece {
                        token: None,
                        start: None,
                        text: "prio".to_owned(),
                        kind: PRIO_KW,
                        parent: PRIO_CLAUSE,
                        sep: Sep::Space,
                    });
                    out.push(Piece {
                        token: None,
                        start: None,
                        text: prio.to_string(),
                        kind: NUMBER,
                        parent: PRIO_CLAUSE,
                        sep: Sep::Space,
                    });
                }
                if reorder {
                    let of = |kind| clauses.iter().filter(move |c| c.kind() == kind);
                    for clause in of(PRIO_CLAUSE) {
                        self.collect_node(clause, out);
                    }
                    let mut attributes: Vec<&SyntaxNode> = of(ATTRIBUTE).collect();
                    attributes.sort_by_key(|a| attribute_rank(a));
                    for clause in attributes {
                        self.collect_node(clause, out);
                    }
                    for clause in of(COMMENT_STRING) {
                        self.collect_node(clause, out);
                    }
                } else {
                    for clause in &clauses {
                        self.collect_node(clause, out);
                    }
                }
            }
            STATE if reorder => {
                let is_kind =
                    |e: &SyntaxElement, kind| e.as_node().is_some_and(|n| n.kind() == kind);
                for element in header
                    .iter()
                    .filter(|e| !is_kind(e, COMMENT_STRING) && !is_kind(e, ATTRIBUTE))
                {
                    self.collect(element.clone(), out);
                }
                for element in header.iter().filter(|e| is_kind(e, COMMENT_STRING)) {
                    self.collect(element.clone(), out);
                }
                for element in header.iter().filter(|e| is_kind(e, ATTRIBUTE)) {
                    self.collect(element.clone(), out);
                }
            }
            _ => {
                for element in header {
                    self.collect(element.clone(), out);
                }
            }
        }
    }

    // ---------------------------------------------------------------- layout decisions

    /// Can this node be written on one line?
    fn fits_on_one_line(&self, node: &SyntaxNode, indent: usize) -> bool {
        let split = split(node);
        let mut body_elements: Vec<SyntaxElement> = Vec::new();
        if let Some(open) = &split.open {
            body_elements.push(NodeOrToken::Token(open.clone()));
        }
        body_elements.extend(split.members.iter().cloned().map(NodeOrToken::Node));
        if let Some(close) = &split.close {
            body_elements.push(NodeOrToken::Token(close.clone()));
        }
        if split.open.is_none() {
            // No body: a simple member.
            return true;
        }
        if self.comments_within(&body_elements) {
            return false;
        }
        // A `// higraph-allow:` comment covers its own line and the next one, so next to one
        // the input's choice between one line and several is kept: joining or splitting lines
        // would change which diagnostics it suppresses.
        if let Some((first, last)) = self.tokens.span(node.text_range())
            && self.tokens.allow_comment_around(first, last)
        {
            return !self.tokens.line_breaks_in(first + 1, last);
        }
        let members = &split.members;
        if members.is_empty() {
            return true;
        }
        match node.kind() {
            STATE | TRANS | PERMANENT => {
                // At most one block with at most one statement; `wait` and `supervise` items
                // are not blocks (`state 2 "Ab" < C: = #Ab; supervise T#10S; >`).
                let blocks: Vec<&SyntaxNode> =
                    members.iter().filter(|m| m.kind() == BLOCK).collect();
                blocks.len() <= 1
                    && blocks
                        .iter()
                        .all(|block| block.children().filter(|c| c.kind() == STL_STMT).count() <= 1)
            }
            START_PART | PRE_PART | POST_PART | STEP_PHASE | CHART_TRANS | JUMP | LOOP
            | CHART_ACTION => members.len() == 1 && !is_structured(members[0].kind()),
            STEP => members.len() == 1 && members.iter().all(|m| self.fits_on_one_line(m, indent)),
            VAR_SECTION => INDENT.len() * indent + width(&self.inline(node)) <= MAX_WIDTH,
            _ => false,
        }
    }

    // ---------------------------------------------------------------- layout

    fn source_file(&mut self, root: &SyntaxNode) {
        for item in root.children() {
            self.layout(&item, Place::member(0), 0);
        }
    }

    /// Writes a member at `place`; `indent` is its own indentation level (its body's members
    /// go one level deeper).
    fn layout(&mut self, node: &SyntaxNode, place: Place, indent: usize) {
        if self.cancelled || (self.is_cancelled)() {
            self.cancelled = true;
            return;
        }
        if is_structured(node.kind()) {
            self.structured(node, place, indent);
            return;
        }
        if self.fits_on_one_line(node, indent) {
            let pieces = self.inline(node);
            self.em.pieces(place, &pieces);
            return;
        }
        let split = split(node);
        let mut header = Vec::new();
        if matches!(node.kind(), STATE | TRANS) {
            self.header_pieces(node, &mut header);
        } else {
            for element in &split.header {
                self.collect(element.clone(), &mut header);
            }
        }
        if let Some(open) = &split.open {
            self.push_token(open, &mut header);
        }
        self.em.pieces(place, &header);
        let inner = indent + 1;
        match node.kind() {
            STATE | TRANS | PERMANENT => {
                for member in &split.members {
                    self.instruction_item(member, inner);
                }
            }
            SYMBOLS => self.aligned(&split.members, inner, SYMBOL, |p| {
                p.kind == COLON && p.parent == SYMBOL
            }),
            INSTANCE => self.aligned(&split.members, inner, ACTUAL, |p| {
                p.kind == COLON && p.parent == ASSIGN_OP
            }),
            _ => {
                for member in &split.members {
                    self.layout(member, Place::member(inner), inner);
                }
            }
        }
        if let Some(close) = &split.close {
            let piece = self.piece(close);
            self.em.piece(Place::close(indent), &piece);
        }
    }

    /// An `IF` or `CASE` statement (or one of its clauses or arms) at `place`, its own lines at
    /// `indent`: the keywords and conditions on lines of their own (`IF c THEN`, `ELSIF c
    /// THEN`, `ELSE`, `END_IF;`, `CASE e OF`, `1, 2..3:`, `END_CASE;`), the statements one
    /// level deeper; the arms and the `ELSE` of a `CASE` one level deeper than `CASE`.
    fn structured(&mut self, node: &SyntaxNode, place: Place, indent: usize) {
        let mut line: Vec<Piece> = Vec::new();
        let mut line_place = place;
        let clause_indent = if node.kind() == CASE_STMT {
            indent + 1
        } else {
            indent
        };
        for child in node.children_with_tokens() {
            match child {
                NodeOrToken::Token(token) if token.kind().is_trivia() => {}
                NodeOrToken::Node(child)
                    if ast::Stmt::can_cast(child.kind())
                        || matches!(child.kind(), ELSIF_CLAUSE | ELSE_CLAUSE | CASE_ARM) =>
                {
                    if !line.is_empty() {
                        self.em.pieces(line_place, &line);
                        line.clear();
                    }
                    if ast::Stmt::can_cast(child.kind()) {
                        self.layout(&child, Place::member(indent + 1), indent + 1);
                    } else {
                        self.structured(&child, Place::member(clause_indent), clause_indent);
                    }
                    line_place = Place::member(indent);
                }
                other => self.collect(other, &mut line),
            }
        }
        if !line.is_empty() {
            self.em.pieces(line_place, &line);
        }
    }

    /// A block, `wait` or `supervise` item of a multi-line instruction body.
    fn instruction_item(&mut self, node: &SyntaxNode, indent: usize) {
        if node.kind() != BLOCK {
            let pieces = self.inline(node);
            self.em.pieces(Place::member(indent), &pieces);
            return;
        }
        let mut statement_indent = indent;
        for child in node.children() {
            let pieces = self.inline(&child);
            if child.kind() == LABEL {
                statement_indent = indent + 1;
                self.em.pieces(Place::member(indent), &pieces);
            } else {
                self.em.pieces(Place::member(statement_indent), &pieces);
            }
        }
    }

    /// Members of a symbol table or instance, with the separator before the first piece that
    /// `is_anchor` matches padded so that those pieces line up.
    fn aligned(
        &mut self,
        members: &[SyntaxNode],
        indent: usize,
        kind: SyntaxKind,
        is_anchor: impl Fn(&Piece) -> bool,
    ) {
        let lines: Vec<Vec<Piece>> = members.iter().map(|m| self.inline(m)).collect();
        let before_anchor = |pieces: &[Piece]| -> Option<usize> {
            let at = pieces.iter().position(&is_anchor)?;
            Some(width(&pieces[..at]))
        };
        let column = members
            .iter()
            .zip(&lines)
            .filter(|(m, _)| m.kind() == kind)
            .filter_map(|(_, pieces)| before_anchor(pieces))
            .max()
            .unwrap_or(0);
        for (member, mut pieces) in members.iter().zip(lines) {
            if member.kind() == kind
                && let (Some(at), Some(w)) =
                    (pieces.iter().position(&is_anchor), before_anchor(&pieces))
                && at > 0
            {
                pieces[at].sep = Sep::Pad(column.saturating_sub(w) + 1);
            }
            self.em.pieces(Place::member(indent), &pieces);
        }
    }
}

// ------------------------------------------------------------------------------------------
// The token check

/// The significant tokens of a file as `(parent kind, kind, text)` lines, with the case
/// differences the formatter may introduce folded, state and transition headers in canonical
/// clause order and implicit priorities written out: two files with equal streams mean the
/// same.
fn significant_stream(root: &SyntaxNode, prios: &HashMap<TextSize, u64>) -> Vec<String> {
    let mut out = Vec::new();
    stream_node(root, prios, &mut out);
    out
}

fn stream_token(token: &SyntaxToken, out: &mut Vec<String>) {
    if token.kind().is_trivia() {
        return;
    }
    let parent = token.parent().map_or(SOURCE_FILE, |p| p.kind());
    let folded = token.kind().is_keyword()
        || matches!(parent, OPCODE | LABEL | QUALIFIER | TYPE_REF | ADDRESS)
        || chart_prop_value(token).is_some()
        || (token.kind() == IDENT && crate::resolve::is_one_word_address_operand(token));
    let text = if folded {
        token.text().to_ascii_lowercase()
    } else {
        token.text().to_owned()
    };
    out.push(format!("{parent:?} {:?} {text}", token.kind()));
}

fn stream_node(node: &SyntaxNode, prios: &HashMap<TextSize, u64>, out: &mut Vec<String>) {
    if !matches!(node.kind(), STATE | TRANS) {
        for child in node.children_with_tokens() {
            match child {
                NodeOrToken::Token(token) => stream_token(&token, out),
                NodeOrToken::Node(child) => stream_node(&child, prios, out),
            }
        }
        return;
    }
    let mut clauses: Vec<(usize, SyntaxNode)> = Vec::new();
    let mut has_prio = false;
    let mut rest: Vec<SyntaxElement> = Vec::new();
    for child in node.children_with_tokens() {
        match &child {
            NodeOrToken::Node(n)
                if matches!(n.kind(), PRIO_CLAUSE | ATTRIBUTE | COMMENT_STRING) =>
            {
                let rank = match n.kind() {
                    PRIO_CLAUSE => {
                        has_prio = true;
                        0
                    }
                    ATTRIBUTE if node.kind() == TRANS => 1 + attribute_rank(n),
                    ATTRIBUTE => 10,
                    _ if node.kind() == TRANS => 10,
                    _ => 5,
                };
                clauses.push((rank, n.clone()));
            }
            _ => rest.push(child),
        }
    }
    clauses.sort_by_key(|(rank, _)| *rank);
    let mut header_done = false;
    for child in rest {
        if !header_done && child.as_node().is_some_and(|n| n.kind() == BODY) {
            if !has_prio && let Some(prio) = prios.get(&node.text_range().start()) {
                out.push(format!("{PRIO_CLAUSE:?} {PRIO_KW:?} prio"));
                out.push(format!("{PRIO_CLAUSE:?} {NUMBER:?} {prio}"));
            }
            for (_, clause) in &clauses {
                stream_node(clause, prios, out);
            }
            header_done = true;
        }
        match child {
            NodeOrToken::Token(token) => stream_token(&token, out),
            NodeOrToken::Node(child) => stream_node(&child, prios, out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn priorities(text: &str) -> Vec<Option<u64>> {
        let parsed = parse(text);
        assert!(parsed.errors().is_empty(), "{:?}", parsed.errors());
        let graph = parsed
            .syntax_node()
            .descendants()
            .find_map(ast::Graph::cast)
            .expect("a graph");
        implicit_priorities(&graph)
    }

    #[test]
    fn implicit_priorities_follow_text_order_and_skip_explicit_ones() {
        let text = "graph G <
  state 0 < >
  state 1 < >
  trans 0->1 < >
  trans 0->1 prio 2 < >
  trans 0->1 < >
  trans 0->return < >
  trans 1->0 prio 5 < >
  trans 1->0 < >
  trans any->0 prio 1 < >
  trans any->1 < >
  trans 7->0 < >
  trans return->0 < >
>
";
        assert_eq!(
            priorities(text),
            vec![
                Some(1),
                None,
                Some(3),
                Some(4),
                None,
                Some(6),
                None,
                Some(2),
                None,
                None
            ]
        );
    }

    #[test]
    fn implicit_priority_skips_every_explicit_priority_of_the_range() {
        let text = "graph G <
  state 0 < >
  trans 0->0 prio 1 < >
  trans 0->0 < >
  trans 0->0 prio 3 < >
  trans 0->0 prio 2 < >
>
";
        // The second transition: greater than 1, and 2 and 3 are used explicitly.
        assert_eq!(priorities(text), vec![None, Some(4), None, None]);
    }

    #[test]
    fn state_numbers_compare_numerically() {
        let text = "graph G < state 007 < > trans 7->7 < > >";
        assert_eq!(priorities(text), vec![Some(1)]);
    }

    #[test]
    fn line_breaks() {
        assert_eq!(count_line_breaks("\r\n\n\r \r"), 4);
        assert!(uses_crlf("a\r\nb\n"));
        assert!(!uses_crlf("a\nb\r\n"));
        assert!(!uses_crlf("ab"));
    }

    #[test]
    fn syntax_errors_are_refused() {
        assert!(matches!(
            format("graph G < state 0 < U x >"),
            Err(FormatError::Syntax(_))
        ));
    }

    #[test]
    fn empty_input() {
        assert_eq!(format("").as_deref(), Ok(""));
        assert_eq!(format("  \n\n").as_deref(), Ok(""));
        assert_eq!(format("// c  \n\n\n// d").as_deref(), Ok("// c\n\n// d\n"));
    }
}

//! Folding ranges and selection ranges (`tooling.md` §4 "foldingRange, selectionRange").
//!
//! * A fold is every `< >` block that spans several lines — from its `<` through its `>`
//!   (through the block's last token when the `>` is missing) — and every run of at least two
//!   line comments on consecutive lines, each alone on its line.
//! * A selection range chain starts at the token under the offset (a word rather than the
//!   punctuation next to it; nothing for white space), then, for a comment in a run of line
//!   comments, the run (as folded), and goes out through the enclosing nodes to the whole
//!   file. Node ranges are trimmed to their first and last non-blank
//!   token, and a range equal to the previous one is left out.

use higraph_syntax::{
    SyntaxKind::{self, *},
    SyntaxNode, SyntaxToken, TextRange, TextSize,
    rowan::{NodeOrToken, TokenAtOffset},
};

use crate::{Analysis, Cancellable, db};

/// What a fold holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FoldKind {
    /// A `< >` block.
    Region,
    /// A run of line comments.
    Comment,
}

/// A foldable range.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Fold {
    /// From the `<` through the `>` (a block), or from the first comment's `//` through the
    /// end of the last comment (a comment run).
    pub range: TextRange,
    pub kind: FoldKind,
}

impl Analysis {
    /// The folds of a `.higraph` file in text order (by start; an enclosing block comes before
    /// the blocks inside it). An unknown path has none.
    pub fn folding_ranges(&self, path: &str) -> Cancellable<Vec<Fold>> {
        let Some(file) = self.file(path) else {
            return Ok(Vec::new());
        };
        self.with_db(|db, _| {
            let root = db::parse(db, file).syntax_node();
            let mut folds = block_folds(&root);
            folds.extend(comment_folds(&root));
            folds.sort_by_key(|f| (f.range.start(), std::cmp::Reverse(f.range.end())));
            folds
        })
    }

    /// For each offset, the ranges an "expand selection" steps through: from the innermost
    /// token or node at the offset outwards to the whole file, each strictly containing the
    /// previous one. An offset outside the file, or a file not in the workspace, gets an
    /// empty chain.
    pub fn selection_ranges(
        &self,
        path: &str,
        offsets: &[TextSize],
    ) -> Cancellable<Vec<Vec<TextRange>>> {
        let Some(file) = self.file(path) else {
            return Ok(vec![Vec::new(); offsets.len()]);
        };
        self.with_db(|db, _| {
            let root = db::parse(db, file).syntax_node();
            offsets
                .iter()
                .map(|&offset| selection_chain(&root, offset))
                .collect()
        })
    }
}

// ------------------------------------------------------------------------------ folding

/// Every `<`-opened block spanning several lines. Linear in the size of the tree: each node
/// looks only at its own children, and the line breaks are found once for the file.
fn block_folds(root: &SyntaxNode) -> Vec<Fold> {
    let breaks = LineBreaks::of(root);
    let mut folds = Vec::new();
    for node in root.descendants() {
        // `<` and `>` in chart expressions are operators.
        if matches!(node.kind(), BIN_EXPR | COMPARE_OP) {
            continue;
        }
        let tokens: Vec<SyntaxToken> = node
            .children_with_tokens()
            .filter_map(NodeOrToken::into_token)
            .collect();
        let Some(open) = tokens.iter().find(|t| t.kind() == L_ANGLE) else {
            continue;
        };
        let end = match tokens.iter().rev().find(|t| t.kind() == R_ANGLE) {
            Some(close) if close.text_range().start() > open.text_range().start() => {
                close.text_range().end()
            }
            // Unclosed (HG0003): up to the block's last token.
            _ => last_significant_end(&node).unwrap_or(open.text_range().end()),
        };
        let range = TextRange::new(open.text_range().start(), end);
        if breaks.inside(range) {
            folds.push(Fold {
                range,
                kind: FoldKind::Region,
            });
        }
    }
    folds
}

/// The end of the last token of `node` that is not white space or a comment: walks back from
/// the node's last token over trivia only.
fn last_significant_end(node: &SyntaxNode) -> Option<TextSize> {
    let start = node.text_range().start();
    let mut token = node.last_token();
    while let Some(t) = token {
        if t.text_range().start() < start {
            return None;
        }
        if !t.kind().is_trivia() {
            return Some(t.text_range().end());
        }
        token = t.prev_token();
    }
    None
}

/// The white-space tokens of a file that hold a line break, in text order.
struct LineBreaks(Vec<TextRange>);

impl LineBreaks {
    fn of(root: &SyntaxNode) -> LineBreaks {
        LineBreaks(
            root.descendants_with_tokens()
                .filter_map(NodeOrToken::into_token)
                .filter(|t| t.kind() == WHITESPACE && t.text().contains(['\n', '\r']))
                .map(|t| t.text_range())
                .collect(),
        )
    }

    /// Does `range` contain one of them? (Tokens do not overlap, so the first one that starts
    /// in `range` ends first.)
    fn inside(&self, range: TextRange) -> bool {
        let first = self.0.partition_point(|r| r.start() < range.start());
        self.0.get(first).is_some_and(|r| r.end() <= range.end())
    }
}

/// Runs of at least two comments on consecutive lines, each alone on its line.
fn comment_folds(root: &SyntaxNode) -> Vec<Fold> {
    let mut folds = Vec::new();
    let mut run: Option<(TextRange, usize)> = None;
    // Line breaks since the last comment of the run, and whether anything else came between.
    let mut breaks = 0usize;
    let mut interrupted = false;
    // Whether the current line has only had white space so far.
    let mut line_is_blank = true;
    let finish = |run: &mut Option<(TextRange, usize)>, folds: &mut Vec<Fold>| {
        if let Some((range, count)) = run.take()
            && count >= 2
        {
            folds.push(Fold {
                range,
                kind: FoldKind::Comment,
            });
        }
    };
    for token in root
        .descendants_with_tokens()
        .filter_map(NodeOrToken::into_token)
    {
        match token.kind() {
            WHITESPACE => {
                let n = line_breaks(token.text());
                if n > 0 {
                    breaks += n;
                    line_is_blank = true;
                }
            }
            COMMENT if line_is_blank => {
                let range = token.text_range();
                run = match run.take() {
                    Some((start, count)) if breaks == 1 && !interrupted => {
                        Some((start.cover(range), count + 1))
                    }
                    previous => {
                        let mut previous = previous;
                        finish(&mut previous, &mut folds);
                        Some((range, 1))
                    }
                };
                breaks = 0;
                interrupted = false;
                line_is_blank = false;
            }
            _ => {
                interrupted = true;
                line_is_blank = false;
            }
        }
    }
    finish(&mut run, &mut folds);
    folds
}

/// The number of line breaks (LF, CR LF or a lone CR) in `text`.
fn line_breaks(text: &str) -> usize {
    let bytes = text.as_bytes();
    bytes
        .iter()
        .enumerate()
        .filter(|&(i, &b)| b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')))
        .count()
}

// ------------------------------------------------------------------------------ selection

/// The chain of ranges around `offset`, innermost first.
fn selection_chain(root: &SyntaxNode, offset: TextSize) -> Vec<TextRange> {
    if offset > root.text_range().end() {
        return Vec::new();
    }
    let mut chain: Vec<TextRange> = Vec::new();
    let mut push = |range: Option<TextRange>| {
        if let Some(range) = range
            && chain.last().is_none_or(|last| *last != range)
        {
            chain.push(range);
        }
    };
    let token = pick_token(root.token_at_offset(offset));
    let parent = match &token {
        Some(token) => {
            if token.kind() != WHITESPACE {
                push(Some(token.text_range()));
            }
            if token.kind() == COMMENT
                && let Some(parent) = token.parent()
            {
                // A comment in a run of line comments: the whole run (the fold of the run).
                push(
                    comment_folds(&parent)
                        .into_iter()
                        .map(|fold| fold.range)
                        .find(|run| run.contains_range(token.text_range())),
                );
            }
            token.parent()
        }
        None => Some(root.clone()),
    };
    for node in parent.into_iter().flat_map(|p| p.ancestors()) {
        // A node's range without surrounding white space, if it still holds the offset.
        push(trimmed_range(&node).filter(|r| r.contains_inclusive(offset)));
    }
    // Last, the whole file.
    push(Some(root.text_range()));
    chain
}

/// Of the tokens touching an offset, the one a selection should start from: a word over
/// punctuation, anything over white space.
fn pick_token(tokens: TokenAtOffset<SyntaxToken>) -> Option<SyntaxToken> {
    match tokens {
        TokenAtOffset::None => None,
        TokenAtOffset::Single(token) => Some(token),
        TokenAtOffset::Between(left, right) => {
            let rank = |t: &SyntaxToken| match t.kind() {
                WHITESPACE => 0,
                k if is_word(k) => 2,
                _ => 1,
            };
            // Equal ranks go to the right: the cursor is in front of it.
            if rank(&left) > rank(&right) {
                Some(left)
            } else {
                Some(right)
            }
        }
    }
}

fn is_word(kind: SyntaxKind) -> bool {
    kind.is_keyword() || matches!(kind, IDENT | NUMBER | TYPED_CONST | STRING | CHAR | COMMENT)
}

/// A node's range without leading and trailing white space; `None` for a node of white
/// space only.
fn trimmed_range(node: &SyntaxNode) -> Option<TextRange> {
    // From each end inwards over white space only: the cost does not grow with the node
    // (the chain asks this of every ancestor, up to the whole file).
    let range = node.text_range();
    let mut first = node.first_token();
    while let Some(t) = first.take_if(|t| t.kind() == WHITESPACE) {
        first = t
            .next_token()
            .filter(|n| n.text_range().end() <= range.end());
    }
    let first = first?;
    let mut last = node.last_token();
    while let Some(t) = last.take_if(|t| t.kind() == WHITESPACE) {
        last = t
            .prev_token()
            .filter(|p| p.text_range().start() >= range.start());
    }
    let end = last.map_or(first.text_range().end(), |t| t.text_range().end());
    Some(TextRange::new(first.text_range().start(), end))
}

#[cfg(test)]
mod tests {
    use std::fmt::Write;

    use higraph_syntax::{TextRange, TextSize};

    use crate::ide::fixture;

    /// Each fold as its kind and its first and last line (0-based).
    fn folds(text: &str) -> String {
        let f = fixture::load(text);
        let path = f.position.path.clone();
        let text = f.text(&path);
        let line = |offset: TextSize| text[..usize::from(offset)].matches('\n').count();
        let mut out = String::new();
        for fold in f.host.analysis().folding_ranges(&path).unwrap_or_default() {
            let _ = writeln!(
                out,
                "{:?} {}..{} {:?}",
                fold.kind,
                line(fold.range.start()),
                line(fold.range.end()),
                f.slice(&path, fold.range).lines().next().unwrap_or("")
            );
        }
        out
    }

    /// The selection chain at the cursor, one range a line.
    fn selections(text: &str) -> String {
        let f = fixture::load(text);
        let path = f.position.path.clone();
        let chains = f
            .host
            .analysis()
            .selection_ranges(&path, &[f.position.offset])
            .unwrap_or_default();
        let mut out = String::new();
        for range in chains.into_iter().flatten() {
            let _ = writeln!(out, "{:?}", f.slice(&path, range));
        }
        out
    }

    #[test]
    fn blocks_over_several_lines_fold() {
        insta::assert_snapshot!(folds(
            r#"// Valve graph.
// Two lines of comments.
graph G <
  in < a : BOOL; >
  stat <
    s : INT;
  >
  state 0 < C: U a; >
  state 1 <
    // one comment is no run
    C: U a;
  >
  trans 0->1 < U a; > // trailing
  // not alone: the line above has code
>
chart C <
  sequencer S <
    step A < >
    trans T < x < 5; y <> 2; >
  >
>
"#
        ), @r#"
        Comment 0..1 "// Valve graph."
        Region 2..14 "<"
        Region 4..6 "<"
        Region 8..11 "<"
        Region 15..20 "<"
        Region 16..19 "<"
        "#);
    }

    /// A test body folds; comparison operators inside its expressions do not.
    #[test]
    fn tests_fold() {
        insta::assert_snapshot!(folds(
            "test T \"d\" <\n  run G;\n  expect x < 5 and y <> 2 and z > 3 and\n    w >= 4;\n  until (a\n    or b) within T#1S;\n>\n"
        ), @r#"Region 0..6 "<""#);
    }

    #[test]
    fn comment_runs_need_consecutive_lines() {
        insta::assert_snapshot!(folds(
            "// a\n// b\n\n// c\n// d\r\n// e\n  // f\ngraph G < > // g\n// h\n"
        ), @r#"
        Comment 0..1 "// a"
        Comment 3..6 "// c"
        "#);
    }

    #[test]
    fn an_unclosed_block_folds_to_its_last_token() {
        insta::assert_snapshot!(folds("graph G <\n  state 0 <\n    C: U a;\n"), @r#"
        Region 0..2 "<"
        Region 1..2 "<"
        "#);
    }

    #[test]
    fn selection_grows_from_the_word_to_the_file() {
        insta::assert_snapshot!(selections(
            "graph G <\n  state 0 < C: U Ob$0en; = Auf; >\n>\n"
        ), @r#"
        "Oben"
        "U Oben;"
        "C: U Oben; = Auf;"
        "< C: U Oben; = Auf; >"
        "state 0 < C: U Oben; = Auf; >"
        "<\n  state 0 < C: U Oben; = Auf; >\n>"
        "graph G <\n  state 0 < C: U Oben; = Auf; >\n>"
        "graph G <\n  state 0 < C: U Oben; = Auf; >\n>\n"
        "#);
    }

    #[test]
    fn selection_prefers_the_word_next_to_punctuation() {
        insta::assert_snapshot!(selections("graph G < state 0 < C: U Oben$0; > >"), @r#"
        "Oben"
        "U Oben;"
        "C: U Oben;"
        "< C: U Oben; >"
        "state 0 < C: U Oben; >"
        "< state 0 < C: U Oben; > >"
        "graph G < state 0 < C: U Oben; > >"
        "#);
    }

    #[test]
    fn selection_in_white_space_starts_at_the_enclosing_node() {
        insta::assert_snapshot!(selections("graph G <\n  $0\n  state 0 < >\n>\n"), @r#"
        "<\n  \n  state 0 < >\n>"
        "graph G <\n  \n  state 0 < >\n>"
        "graph G <\n  \n  state 0 < >\n>\n"
        "#);
    }

    #[test]
    fn selection_of_a_comment_in_a_run_takes_the_run_next() {
        insta::assert_snapshot!(selections("// one\n// t$0wo\n// three\ngraph G < >\n"), @r#"
        "// two"
        "// one\n// two\n// three"
        "// one\n// two\n// three\ngraph G < >"
        "// one\n// two\n// three\ngraph G < >\n"
        "#);
        // A comment alone is not a run.
        insta::assert_snapshot!(selections("graph G <\n  // al$0one\n  state 0 < >\n>\n"), @r#"
        "// alone"
        "<\n  // alone\n  state 0 < >\n>"
        "graph G <\n  // alone\n  state 0 < >\n>"
        "graph G <\n  // alone\n  state 0 < >\n>\n"
        "#);
    }

    #[test]
    fn selection_answers_every_offset() {
        let f = fixture::load("graph G < >\n");
        let analysis = f.host.analysis();
        let far = TextSize::from(1000);
        let chains = analysis
            .selection_ranges("main.higraph", &[TextSize::from(0), far])
            .unwrap_or_default();
        assert_eq!(chains.len(), 2);
        assert_eq!(chains[0].first(), Some(&TextRange::new(0.into(), 5.into())));
        assert!(chains[1].is_empty());
        let unknown = analysis
            .selection_ranges("nope.higraph", &[TextSize::from(0)])
            .unwrap_or_default();
        assert_eq!(unknown, vec![Vec::new()]);
    }
}

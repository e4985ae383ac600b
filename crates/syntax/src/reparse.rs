//! Incremental reparsing: after an edit inside one member of a graph (a `state`, `trans` or
//! `permanent` block), only that member is parsed again and spliced into the old tree; every
//! other node keeps its green node (the same allocation), so the analysis above can tell by
//! pointer which parts of the file are unchanged.
//!
//! The member is reparsed on its own only when that provably gives what a full parse would:
//!
//! * the edit lies inside the member, and white space separates the member from its
//!   neighbours (so no token can grow across its boundaries);
//! * the new text parses as exactly one member of the same kind that ends with its own `>` and
//!   has no unclosed `<` (HG0003) — a member that is not closed would swallow the members
//!   after it in a full parse;
//! * no token that can begin an operand follows the member on its line (whether a `>` inside
//!   a statement closes the block depends on the token after it, language.md §1.3);
//! * no diagnostic outside the member points into it, and none was left out of the old
//!   parse's list (HG0013).
//!
//! Otherwise [`Parse::reparse`] parses the whole file. `tests/reparse.rs` checks on random
//! edits that both ways give the same tree and the same diagnostics.

use rowan::{NodeOrToken, TextRange, TextSize};

use crate::{Parse, SyntaxError, SyntaxKind, SyntaxKind::*, SyntaxNode, parser};

/// One replacement: `delete` (a range of the old text) is replaced by `insert`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edit {
    pub delete: TextRange,
    pub insert: String,
}

impl Edit {
    /// Applies the edit to `text` (the text the edit's range refers to). `None` if the range
    /// is not inside `text` or not on character boundaries.
    pub fn apply(&self, text: &str) -> Option<String> {
        let start = usize::from(self.delete.start());
        let end = usize::from(self.delete.end());
        if end > text.len() || !text.is_char_boundary(start) || !text.is_char_boundary(end) {
            return None;
        }
        let mut out = String::with_capacity(text.len() - (end - start) + self.insert.len());
        out.push_str(&text[..start]);
        out.push_str(&self.insert);
        out.push_str(&text[end..]);
        Some(out)
    }
}

impl Parse {
    /// The parse of `new_text`, which must be this parse's text with `edit` applied: the
    /// edited member is reparsed alone where that is exact, else the whole text.
    pub fn reparse(&self, edit: &Edit, new_text: &str) -> Parse {
        self.reparse_member(edit, new_text)
            .unwrap_or_else(|| crate::parse(new_text))
    }

    /// The incremental path of [`Parse::reparse`]: `None` where it does not apply.
    pub fn reparse_member(&self, edit: &Edit, new_text: &str) -> Option<Parse> {
        if self.errors_summarised() {
            // The errors left out are not here to be kept: only a full parse knows them.
            return None;
        }
        let root = self.syntax_node();
        let old_len = root.text_range().end();
        if edit.delete.end() > old_len
            || u64::from(u32::from(old_len)) - u64::from(u32::from(edit.delete.len()))
                + edit.insert.len() as u64
                != new_text.len() as u64
        {
            return None;
        }
        let member = enclosing_member(&root, edit.delete)?;
        let range = member.text_range();
        if !separated_by_white_space(&member)
            || !follows_a_closed_member(&member)
            || followed_on_its_line_by_an_operand(&member)
        {
            return None;
        }
        let member_text = member.text().to_string();
        let relative = Edit {
            delete: edit.delete - range.start(),
            insert: edit.insert.clone(),
        };
        let new_member_text = relative.apply(&member_text)?;
        let (green, member_errors) = parser::fragment::graph_member(&new_member_text)?;
        if green.kind() != member.green().kind()
            || member_errors
                .iter()
                .any(|e| e.code == crate::ErrorCode::HG0003)
            || !ends_with_r_angle(&green)
        {
            return None;
        }
        let delta = i64::from(u32::from(TextSize::of(new_member_text.as_str())))
            - i64::from(u32::from(range.len()));
        let mut errors = Vec::with_capacity(self.errors().len() + member_errors.len());
        for error in self.errors() {
            if is_inside(error.range, range) {
                continue; // the member's own; replaced by `member_errors`
            }
            errors.push(shift_error(error, range, delta)?);
        }
        errors.extend(member_errors.into_iter().map(|e| e.shifted(range.start())));
        let new_root = member.replace_with(green);
        let parse = Parse::new(new_root, errors);
        debug_assert_eq!(parse.syntax_node().text().len(), TextSize::of(new_text));
        Some(parse)
    }
}

/// Does an error at `error` belong to the member at `member`? Empty ranges on the member's
/// boundaries belong to the neighbours (a member's own empty ranges, such as a missing `;`,
/// lie before its closing `>`).
fn is_inside(error: TextRange, member: TextRange) -> bool {
    member.contains_range(error)
        && (!error.is_empty() || (error.start() > member.start() && error.start() < member.end()))
}

/// The innermost graph member (`state`, `trans`, `permanent`) whose range contains `range`.
fn enclosing_member(root: &SyntaxNode, range: TextRange) -> Option<SyntaxNode> {
    let start = match root.covering_element(range) {
        NodeOrToken::Node(node) => node,
        NodeOrToken::Token(token) => token.parent()?,
    };
    start.ancestors().find(|node| {
        is_reparsable(node.kind())
            && node.parent().is_some_and(|body| {
                body.kind() == BODY && body.parent().is_some_and(|g| g.kind() == GRAPH)
            })
    })
}

fn is_reparsable(kind: SyntaxKind) -> bool {
    matches!(kind, STATE | TRANS | PERMANENT)
}

/// Is the member between two white-space tokens?
fn separated_by_white_space(member: &SyntaxNode) -> bool {
    let white = |t: Option<crate::SyntaxToken>| t.is_some_and(|t| t.kind() == WHITESPACE);
    let first = member.first_token();
    let last = member.last_token();
    white(first.and_then(|t| t.prev_token())) && white(last.and_then(|t| t.next_token()))
}

/// Was the member before `member` closed by its own `>` (at statement start) or `;`? If it was
/// closed by recovery at `member`'s keyword, or by a `>` that would not close it before an
/// operand, a change of `member`'s first tokens changes where it ends.
fn follows_a_closed_member(member: &SyntaxNode) -> bool {
    let Some(prev) = member
        .siblings_with_tokens(rowan::Direction::Prev)
        .skip(1)
        .find(|e| !e.kind().is_trivia())
    else {
        return false;
    };
    let last_child = |node: &SyntaxNode| node.last_child_or_token().map(|e| e.kind());
    match prev {
        NodeOrToken::Token(token) => token.kind() == L_ANGLE,
        NodeOrToken::Node(node) => match node.kind() {
            STATE | TRANS | PERMANENT => node
                .children()
                .filter(|c| c.kind() == BODY)
                .last()
                .is_some_and(|body| {
                    last_child(&body) == Some(R_ANGLE) && closes_at_statement_start(&body)
                }),
            VAR_SECTION => last_child(&node) == Some(R_ANGLE),
            ACTIVATE => last_child(&node) == Some(SEMI),
            _ => false,
        },
    }
}

/// Does a token that can begin an operand follow the member on its last line? Then whether a
/// `>` that ends the member inside a statement closes it depends on that token (language.md
/// §1.3, `Parser::r_angle_closes`), which the member parsed alone does not see.
fn followed_on_its_line_by_an_operand(member: &SyntaxNode) -> bool {
    let mut token = member.last_token().and_then(|t| t.next_token());
    while let Some(t) = token {
        match t.kind() {
            WHITESPACE if t.text().contains(['\n', '\r']) => return false,
            WHITESPACE | COMMENT | LEX_ERROR => token = t.next_token(),
            IDENT | STRING | NUMBER | TYPED_CONST | CHAR | L_PAREN | MINUS => return true,
            kind => return kind.is_keyword(),
        }
    }
    false
}

/// Does the `>` that ends `body` stand at the start of a statement (after `<`, `;` or a
/// label)? Such a `>` closes the block whatever follows it; one inside a statement (a missing
/// `;`) closes it only if the token after it cannot begin an operand (language.md §1.3).
fn closes_at_statement_start(body: &SyntaxNode) -> bool {
    let before = body
        .last_token()
        .and_then(|t| t.prev_token())
        .and_then(|t| {
            std::iter::successors(Some(t), |t| t.prev_token()).find(|t| !t.kind().is_trivia())
        });
    before.is_some_and(|t| matches!(t.kind(), L_ANGLE | SEMI | COLON))
}

fn ends_with_r_angle(green: &rowan::GreenNode) -> bool {
    let root = SyntaxNode::new_root(green.clone());
    root.last_token().is_some_and(|t| t.kind() == R_ANGLE)
}

/// An error outside the member, moved by the member's change of length; `None` if any of its
/// positions lies strictly inside the member (it depends on the member's text).
fn shift_error(error: &SyntaxError, member: TextRange, delta: i64) -> Option<SyntaxError> {
    let shift = |r: TextRange| -> Option<TextRange> {
        if r.end() <= member.start() {
            Some(r)
        } else if r.start() >= member.end() {
            let move_by = |p: TextSize| TextSize::from((i64::from(u32::from(p)) + delta) as u32);
            Some(TextRange::new(move_by(r.start()), move_by(r.end())))
        } else {
            None
        }
    };
    error.try_map_ranges(shift)
}

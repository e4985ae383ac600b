//! What the graph rules need to know of one member of a graph, read once from the member's
//! own syntax tree and cached per chunk of members ([`crate::db::chunk_facts`]).
//!
//! Ranges are relative to the member's start, so the facts of a member stay equal when
//! other members change or move; [`super::model::GraphModel`] adds each member's offset.
//! The rules that compare members (numbering, priorities, reachability, operating modes) run
//! on these facts alone, so a keystroke in one transition costs one fact extraction, not a
//! walk over the whole graph.

use higraph_syntax::{SyntaxKind, SyntaxNode, TextRange, ast, ast::AstNode};

use super::edit;
use crate::lang::{self, Mnemonic};

/// The facts of one graph member.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MemberFacts {
    State(StateFacts),
    Trans(TransFacts),
    /// `permanent`: only the `wait`/`supervise` items that do not belong there (HG3007).
    Permanent {
        misplaced: Vec<BodyItemFact>,
    },
    /// Variable sections, `activate`, errors: read from the syntax tree where needed.
    Other,
}

/// A `state`. Only states whose number parsed are part of the model; the others count
/// for their attributes (HG2106).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateFacts {
    /// The number as written, if it parsed (the ranges are empty otherwise).
    pub number: Option<String>,
    /// The state the number names ([`number_key`]); empty if there is no number.
    pub key: String,
    /// The display name (`state 1 "Oben"`), for completion.
    pub display_name: Option<String>,
    pub number_range: TextRange,
    /// `state` through the number.
    pub header: TextRange,
    pub attributes: Vec<AttrFact>,
    /// The `wait` items, in text order.
    pub waits: Vec<BodyItemFact>,
    /// The `supervise` items, in text order.
    pub supervisions: Vec<BodyItemFact>,
}

/// An attribute of a header (`fault`, `auto`, `waits`, ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AttrFact {
    /// The keyword in lower case.
    pub word: String,
    pub range: TextRange,
    /// The attribute with the white space before it (for "remove" fixes).
    pub removal: TextRange,
}

/// A `wait` or `supervise` item.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BodyItemFact {
    /// `wait` or `supervise`.
    pub keyword: &'static str,
    /// The item without its `;`.
    pub range: TextRange,
    /// The item with the white space before it.
    pub removal: TextRange,
}

/// What an endpoint names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum EndFact {
    /// A state number as written, and the state it names ([`number_key`]).
    State {
        text: String,
        key: String,
    },
    Any,
    Return,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EndpointFact {
    pub end: EndFact,
    pub range: TextRange,
}

impl EndpointFact {
    /// As shown in labels: the number as written, `any` or `return`.
    pub fn text(&self) -> &str {
        match &self.end {
            EndFact::State { text, .. } => text,
            EndFact::Any => "any",
            EndFact::Return => "return",
        }
    }
}

/// A `prio` clause.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PrioFact {
    pub range: TextRange,
    /// The number as written, if there is one.
    pub value: Option<String>,
}

/// A `trans` of a graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TransFacts {
    pub source: Option<EndpointFact>,
    pub target: Option<EndpointFact>,
    /// `trans` through the target endpoint; `None` if the header did not parse.
    pub header: Option<TextRange>,
    pub prio: Option<PrioFact>,
    pub attributes: Vec<AttrFact>,
    /// Is the condition part empty (§2.6)?
    pub empty_condition: bool,
    /// Does the condition query `INIT_SD` (a startup transition if the source is `any` and
    /// the graph declares no variable of that name)?
    pub queries_init_sd: bool,
    /// `wait`/`supervise` items in the body, which belong only in states (HG3007).
    pub misplaced: Vec<BodyItemFact>,
}

impl MemberFacts {
    /// Reads the facts of a member from its own tree (`member` is the root).
    pub fn of(member: &SyntaxNode) -> MemberFacts {
        match member.kind() {
            SyntaxKind::STATE => ast::State::cast(member.clone())
                .map_or(MemberFacts::Other, |s| MemberFacts::State(state(&s))),
            SyntaxKind::TRANS => ast::Trans::cast(member.clone())
                .map_or(MemberFacts::Other, |t| MemberFacts::Trans(trans(&t))),
            SyntaxKind::PERMANENT => MemberFacts::Permanent {
                misplaced: ast::Permanent::cast(member.clone())
                    .and_then(|p| p.body())
                    .map(|b| body_items(&b))
                    .unwrap_or_default(),
            },
            _ => MemberFacts::Other,
        }
    }
}

/// The state a number names: the integer it denotes, without leading zeros (`007` and `7` name
/// the same state, C3). A negative number (an `INT` may be negative, language.md §1.5) keeps
/// its `-` and names no valid state (HG2102); `-0` is `0`.
pub(crate) fn number_key(text: &str) -> String {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(digits) => (true, digits),
        None => (false, text),
    };
    let digits = digits.trim_start_matches('0');
    match (digits.is_empty(), negative) {
        (true, _) => "0".to_owned(),
        (false, true) => format!("-{digits}"),
        (false, false) => digits.to_owned(),
    }
}

fn state(node: &ast::State) -> StateFacts {
    let number = node.number().zip(node.syntax().first_token());
    let items = node.body().map(|b| body_items(&b)).unwrap_or_default();
    let (waits, supervisions) = items.into_iter().partition(|i| i.keyword == "wait");
    let empty = TextRange::default();
    StateFacts {
        number: number.as_ref().map(|(n, _)| n.text().to_owned()),
        key: number
            .as_ref()
            .map(|(n, _)| number_key(n.text()))
            .unwrap_or_default(),
        display_name: node.comment().map(|c| c.value()),
        number_range: number.as_ref().map_or(empty, |(n, _)| n.text_range()),
        header: number.as_ref().map_or(empty, |(n, keyword)| {
            TextRange::new(keyword.text_range().start(), n.text_range().end())
        }),
        attributes: attributes(node.attributes()),
        waits,
        supervisions,
    }
}

fn trans(node: &ast::Trans) -> TransFacts {
    let source = node.source().and_then(|e| endpoint(&e));
    let target = node.target().and_then(|e| endpoint(&e));
    let header = match (node.syntax().first_token(), &target) {
        (Some(keyword), Some(target)) => Some(TextRange::new(
            keyword.text_range().start(),
            target.range.end(),
        )),
        _ => None,
    };
    let prio = node.prio().map(|p| PrioFact {
        range: p.syntax().text_range(),
        value: p.value().map(|v| v.text().to_owned()),
    });
    TransFacts {
        empty_condition: !condition_statements(node).any(|s| s.opcode().is_some()),
        queries_init_sd: source.as_ref().is_some_and(|s| s.end == EndFact::Any)
            && condition_statements(node).any(|s| queries_init_sd(&s)),
        misplaced: node.body().map(|b| body_items(&b)).unwrap_or_default(),
        source,
        target,
        header,
        prio,
        attributes: attributes(node.attributes()),
    }
}

fn endpoint(node: &ast::Endpoint) -> Option<EndpointFact> {
    let token = node.token()?;
    let end = match node.kind()? {
        ast::EndpointKind::Any => EndFact::Any,
        ast::EndpointKind::Return => EndFact::Return,
        ast::EndpointKind::State => EndFact::State {
            text: token.text().to_owned(),
            key: number_key(token.text()),
        },
    };
    Some(EndpointFact {
        end,
        range: node.syntax().text_range(),
    })
}

/// Attributes with their lower-case keywords.
fn attributes(attrs: impl Iterator<Item = ast::Attribute>) -> Vec<AttrFact> {
    attrs
        .filter_map(|a| {
            Some(AttrFact {
                word: a.keyword()?.text().to_ascii_lowercase(),
                range: a.syntax().text_range(),
                removal: edit::removal_range(a.syntax()),
            })
        })
        .collect()
}

/// The `wait` and `supervise` items of a body.
fn body_items(body: &ast::Body) -> Vec<BodyItemFact> {
    body.body_items()
        .filter_map(|item| {
            let (keyword, node) = match &item {
                ast::BodyItem::Wait(w) => ("wait", w.syntax()),
                ast::BodyItem::Supervise(s) => ("supervise", s.syntax()),
                ast::BodyItem::Block(_) => return None,
            };
            Some(BodyItemFact {
                keyword,
                range: edit::without_semi(node),
                removal: edit::removal_range(node),
            })
        })
        .collect()
}

/// The condition part of a transition (§2.6): the statements before the first label and every
/// `?:` block.
pub(crate) fn condition_statements(trans: &ast::Trans) -> impl Iterator<Item = ast::StlStmt> {
    trans
        .body()
        .into_iter()
        .flat_map(|b| b.blocks())
        .filter(|b| b.label().is_none_or(|l| l.name() == "?"))
        .flat_map(|b| b.statements())
}

/// Does a statement have an operand `INIT_SD` or `#INIT_SD`? Statements that are not
/// analysed (jump labels, operations of neither mnemonic set: C4) do not count.
fn queries_init_sd(stmt: &ast::StlStmt) -> bool {
    if stmt.jump_label().is_some() {
        return false;
    }
    let Some(opcode) = stmt.opcode() else {
        return false;
    };
    let op = opcode.text();
    if !lang::is_subset_op(&op, Mnemonic::Simatic)
        && !lang::is_subset_op(&op, Mnemonic::International)
    {
        return false;
    }
    let params = stmt
        .call_args()
        .into_iter()
        .flat_map(|a| a.params())
        .filter_map(|p| p.value());
    stmt.operand().into_iter().chain(params).any(|operand| {
        let name = match operand {
            ast::Operand::NameRef(n) => n.token(),
            ast::Operand::VarRef(v) => v.name(),
            _ => None,
        };
        name.is_some_and(|t| {
            t.kind() == SyntaxKind::IDENT && t.text().eq_ignore_ascii_case("INIT_SD")
        })
    })
}

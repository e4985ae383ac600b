//! A position-free rendering of a file's semantic model: what each item declares and does,
//! with spelling of keywords, operations, areas and types normalised, white space ignored and
//! implicit transition priorities computed. Two texts with equal models mean the same, which
//! is what `fmt` (and, except for the renamed name, rename) must preserve.

use std::fmt::Write;

use higraph_syntax::{SyntaxKind, SyntaxNode, SyntaxToken, ast, ast::AstNode};

use crate::{Analysis, Cancellable, db, format};

impl Analysis {
    /// The semantic model of a `.higraph` file, one fact per line.
    pub fn semantic_model(&self, path: &str) -> Cancellable<String> {
        let Some(file) = self.file(path) else {
            return Ok(String::new());
        };
        self.with_db(|db, _| model_of(&db::parse(db, file).syntax_node()))
    }
}

/// The model of a parsed file.
pub fn model_of(root: &SyntaxNode) -> String {
    let mut out = String::new();
    let Some(file) = ast::SourceFile::cast(root.clone()) else {
        return out;
    };
    for item in file.items() {
        match item {
            ast::Item::Mnemonic(m) => {
                let set = m
                    .set()
                    .map(|t| t.text().to_ascii_lowercase())
                    .unwrap_or_default();
                let _ = writeln!(out, "mnemonic {set}");
            }
            ast::Item::Graph(graph) => graph_model(&graph, &mut out),
            ast::Item::Group(group) => generic("group", group.syntax(), &mut out),
            ast::Item::Chart(chart) => generic("chart", chart.syntax(), &mut out),
            ast::Item::Symbols(table) => {
                for symbol in table.symbols() {
                    let _ = writeln!(out, "symbol {}", normalised(symbol.syntax()));
                }
            }
            ast::Item::BlockInterface(block) => generic("block", block.syntax(), &mut out),
            ast::Item::Test(test) => test_model(&test, &mut out),
        }
    }
    out
}

/// Graphs: declarations, states with their blocks, transitions with effective priorities.
fn graph_model(graph: &ast::Graph, out: &mut String) {
    let name = graph.name().map(|n| n.text()).unwrap_or_default();
    let _ = writeln!(out, "graph {name} {}", comment(graph.comment()));
    for member in graph.members() {
        match member {
            ast::GraphMember::VarSection(section) => {
                let kw = section
                    .keyword()
                    .map(|k| k.text().to_ascii_lowercase())
                    .unwrap_or_default();
                for decl in section.decls() {
                    let _ = writeln!(out, "  var {kw} {}", normalised(decl.syntax()));
                }
            }
            ast::GraphMember::Activate(a) => {
                let _ = writeln!(out, "  {}", normalised(a.syntax()));
            }
            ast::GraphMember::Permanent(p) => {
                let _ = writeln!(out, "  permanent");
                body_model(p.body(), out);
            }
            ast::GraphMember::State(state) => {
                let number = state
                    .number()
                    .map(|t| t.text().to_owned())
                    .unwrap_or_default();
                let mut attrs: Vec<String> = state
                    .attributes()
                    .map(|a| a.syntax().text().to_string().to_ascii_lowercase())
                    .collect();
                attrs.sort();
                let _ = writeln!(
                    out,
                    "  state {number} {} {attrs:?}",
                    comment(state.comment())
                );
                body_model(state.body(), out);
            }
            ast::GraphMember::Trans(_) => {}
        }
    }
    let priorities = format::implicit_priorities(graph);
    for (trans, implicit) in graph.transitions().zip(priorities) {
        // The effective priority: as written, else the computed one (diagnostics.md §2.6).
        let explicit = trans
            .prio()
            .and_then(|p| p.value())
            .and_then(|v| v.text().parse::<u64>().ok());
        let prio = explicit.or(implicit);
        let endpoint = |e: Option<ast::Endpoint>| {
            e.and_then(|e| e.token())
                .map(|t| t.text().to_ascii_lowercase())
                .unwrap_or_default()
        };
        let mut attrs: Vec<String> = trans
            .attributes()
            .map(|a| a.syntax().text().to_string().to_ascii_lowercase())
            .collect();
        attrs.sort();
        let _ = writeln!(
            out,
            "  trans {}->{} prio {prio:?} {attrs:?} {}",
            endpoint(trans.source()),
            endpoint(trans.target()),
            comment(trans.comment())
        );
        body_model(trans.body(), out);
    }
}

fn body_model(body: Option<ast::Body>, out: &mut String) {
    let Some(body) = body else { return };
    for item in body.body_items() {
        match item {
            ast::BodyItem::Block(block) => {
                let label = block
                    .label()
                    .map(|l| l.name())
                    .unwrap_or_else(|| "-".to_owned());
                let _ = writeln!(out, "    block {label}");
                for stmt in block.statements() {
                    let _ = writeln!(out, "      {}", normalised(stmt.syntax()));
                }
            }
            ast::BodyItem::Wait(w) => {
                let _ = writeln!(out, "    {}", normalised(w.syntax()));
            }
            ast::BodyItem::Supervise(s) => {
                let _ = writeln!(out, "    {}", normalised(s.syntax()));
            }
        }
    }
}

/// Groups, charts and block interfaces: their significant tokens, normalised, one line per
/// statement-like node. Statements inside `IF` and `CASE` are indented by their nesting, so
/// that where a structured statement ends is part of the model.
fn generic(kind: &str, node: &SyntaxNode, out: &mut String) {
    let _ = writeln!(out, "{kind}");
    for child in node.descendants() {
        let depth = child
            .ancestors()
            .skip(1)
            .take_while(|a| a != node)
            .filter(|a| {
                matches!(
                    a.kind(),
                    SyntaxKind::IF_STMT
                        | SyntaxKind::ELSIF_CLAUSE
                        | SyntaxKind::ELSE_CLAUSE
                        | SyntaxKind::CASE_STMT
                        | SyntaxKind::CASE_ARM
                )
            })
            .count();
        let indent = "  ".repeat(depth + 1);
        if matches!(
            child.kind(),
            SyntaxKind::OPTION
                | SyntaxKind::ACTUAL
                | SyntaxKind::VAR_DECL
                | SyntaxKind::CHART_PROP
                | SyntaxKind::CONDITION
                | SyntaxKind::ASSIGNMENT
                | SyntaxKind::QUALIFIER_ACTION
                | SyntaxKind::STEP_TIME
                | SyntaxKind::CONFIRM
                | SyntaxKind::FB_CALL
        ) {
            let _ = writeln!(out, "{indent}{}", normalised(&child));
        } else if matches!(
            child.kind(),
            SyntaxKind::INSTANCE
                | SyntaxKind::SEQUENCER
                | SyntaxKind::STEP
                | SyntaxKind::CHART_TRANS
                | SyntaxKind::JUMP
                | SyntaxKind::LOOP
                | SyntaxKind::PARALLEL
                | SyntaxKind::ALT
                | SyntaxKind::BRANCH
                | SyntaxKind::STEP_PHASE
                | SyntaxKind::START_PART
                | SyntaxKind::PRE_PART
                | SyntaxKind::POST_PART
                | SyntaxKind::CHART_ACTION
        ) {
            let _ = writeln!(out, "{indent}{:?} {}", child.kind(), header(&child));
        } else if matches!(
            child.kind(),
            SyntaxKind::IF_STMT
                | SyntaxKind::ELSIF_CLAUSE
                | SyntaxKind::ELSE_CLAUSE
                | SyntaxKind::CASE_STMT
                | SyntaxKind::CASE_ARM
        ) {
            let _ = writeln!(
                out,
                "{indent}{:?} {}",
                child.kind(),
                structured_header(&child)
            );
        }
    }
    let _ = writeln!(out, "  header {}", header(node));
}

/// What an `IF`/`ELSIF` condition, a `CASE` selector or an arm's labels say: the tokens of
/// the node's own expression and labels, normalised.
fn structured_header(node: &SyntaxNode) -> String {
    let parts: Vec<String> = node
        .children()
        .filter(|c| ast::Expr::can_cast(c.kind()) || c.kind() == SyntaxKind::CASE_LABEL)
        .map(|c| normalised(&c))
        .collect();
    parts.join(" , ")
}

/// Tests: the header, then each statement in order (their order is their meaning).
fn test_model(test: &ast::Test, out: &mut String) {
    let name = test.name().map(|n| n.text()).unwrap_or_default();
    let _ = writeln!(out, "test {name} {}", comment(test.comment()));
    for stmt in test.statements() {
        let _ = writeln!(out, "  {}", normalised(stmt.syntax()));
    }
}

/// The significant tokens of a node before its body.
fn header(node: &SyntaxNode) -> String {
    let tokens: Vec<String> = node
        .children_with_tokens()
        .take_while(|e| e.kind() != SyntaxKind::BODY)
        .flat_map(|e| match e {
            higraph_syntax::rowan::NodeOrToken::Node(n) => n
                .descendants_with_tokens()
                .filter_map(|e| e.into_token())
                .collect::<Vec<_>>(),
            higraph_syntax::rowan::NodeOrToken::Token(t) => vec![t],
        })
        .filter(significant)
        .map(|t| token_text(&t))
        .collect();
    tokens.join(" ")
}

fn comment(comment: Option<ast::CommentString>) -> String {
    comment
        .map(|c| format!("{:?}", c.value()))
        .unwrap_or_default()
}

fn significant(token: &SyntaxToken) -> bool {
    !token.kind().is_trivia()
}

/// Keywords lower case; operations, areas and types upper case (as `fmt` writes them), names
/// as written.
fn token_text(token: &SyntaxToken) -> String {
    let in_kind = |kind| token.parent().is_some_and(|p| p.kind() == kind);
    let in_prop = token
        .parent_ancestors()
        .any(|p| p.kind() == SyntaxKind::CHART_PROP);
    if token.kind().is_keyword() || in_prop {
        // Chart property values (`mode auto`, `switching T_or_B`) are case-insensitive words.
        token.text().to_ascii_lowercase()
    } else if in_kind(SyntaxKind::OPCODE)
        || in_kind(SyntaxKind::ADDRESS)
        || crate::resolve::is_one_word_address_operand(token)
        || in_kind(SyntaxKind::TYPE_REF)
        || in_kind(SyntaxKind::LABEL)
        || in_kind(SyntaxKind::QUALIFIER)
    {
        token.text().to_ascii_uppercase()
    } else {
        token.text().to_owned()
    }
}

/// The significant tokens of a node, normalised, joined by single spaces.
fn normalised(node: &SyntaxNode) -> String {
    let tokens: Vec<String> = node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(significant)
        .map(|t| token_text(&t))
        .collect();
    tokens.join(" ")
}

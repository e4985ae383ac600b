//! Hover text (markdown): for a variable its section, type, message kind, initial value and
//! comment; for a predefined variable its meaning; for an STL operation its description and
//! operand types (in the file's mnemonic set); for an address its area, size, type and the
//! symbol naming it; for a symbol its address, type and comment; for a state its number, name,
//! attributes and transitions; for an instance its graph; for graphs, groups, charts and their
//! parts a summary; and for a code in a `// higraph-allow:` comment the rule's documentation
//! (`docs/rules/HGnnnn.md`, embedded at build time).

use higraph_runtime::program::StepMember;
use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
};

use super::{
    FilePosition,
    defs::{self, Definition, ItemId, UseTarget},
};
use crate::lower::{PathTarget, SegmentDef};
use crate::{
    Analysis, Cancellable,
    address::{self, Address, Size},
    db::{self, File, ItemKind, Workspace},
    index::SymbolSource,
    lang::{self, Mnemonic, OpClass},
    registry,
    resolve::GraphScope,
};

/// A hover: the range it is about and its markdown text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hover {
    pub range: TextRange,
    pub markdown: String,
}

impl Analysis {
    /// The hover text for the position, if there is something to say about it.
    pub fn hover(&self, pos: &FilePosition) -> Cancellable<Option<Hover>> {
        self.with_db(|db, ws| {
            let file = self.file(&pos.path)?;
            hover(db, ws, file, pos.offset)
        })
    }
}

fn hover(db: &dyn salsa::Database, ws: Workspace, file: File, offset: TextSize) -> Option<Hover> {
    let root = db::parse(db, file).syntax_node();
    let token = defs::token_at(&root, offset)?;
    if token.kind() == SyntaxKind::COMMENT {
        return allow_code(&token, offset);
    }
    let mnemonic = db::file_mnemonic(db, ws, file);
    if let Some(opcode) = token.parent_ancestors().find_map(ast::Opcode::cast) {
        return Some(Hover {
            range: opcode.syntax().text_range(),
            markdown: operation(&opcode.text(), mnemonic)?,
        });
    }
    if let Some(hover) = test_path(db, ws, file, offset) {
        return Some(hover);
    }
    if let Some(hover) = iec(&token) {
        return Some(hover);
    }
    for name_use in defs::uses_at(db, ws, file, offset) {
        if let UseTarget::Address(address) = &name_use.target {
            return Some(Hover {
                range: name_use.range,
                markdown: address_text(db, ws, address, mnemonic),
            });
        }
    }
    if let Some(at) = defs::definition_at(db, ws, file, offset) {
        return Some(Hover {
            range: at.range,
            markdown: definition(db, ws, &at.definition)?,
        });
    }
    let node = token.parent_ancestors().find_map(ast::Address::cast)?;
    let address = crate::index::read_address(&node.compact_text(), mnemonic)?;
    Some(Hover {
        range: node.syntax().text_range(),
        markdown: address_text(db, ws, &address, mnemonic),
    })
}

/// IEC charts (`docs/iec.md`): a standard function block type name, a member of an instance
/// (`Uhr.Q`, a formal of a call), `X`/`T` of a step.
fn iec(token: &SyntaxToken) -> Option<Hover> {
    use crate::iec::{Direction, FbType};
    let chart = token.parent_ancestors().find_map(ast::Chart::cast)?;
    let parent = token.parent()?;
    let instance_type = |name: &str| {
        chart
            .var_sections()
            .flat_map(|s| s.decls())
            .find(|d| {
                d.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
            })
            .and_then(|d| d.ty())
            .and_then(|t| t.name())
            .and_then(|t| FbType::from_name(t.text()))
    };
    let member_text = |fb: FbType, instance: &str, member: &str| {
        let member = fb.member(member)?;
        let direction = match member.direction {
            Direction::Input => "input",
            Direction::Output => "output",
        };
        Some(format!(
            "{}\n\n{direction} of `{instance}` ({}) · {}",
            code(&format!("{}.{} : {}", instance, member.name, member.ty)),
            fb.name(),
            member.doc
        ))
    };
    let range = token.text_range();
    match parent.kind() {
        SyntaxKind::TYPE_REF => {
            let fb = FbType::from_name(token.text())?;
            Some(Hover {
                range,
                markdown: fb_text(fb),
            })
        }
        SyntaxKind::NAME_REF => {
            let holder = parent.parent()?;
            let first = holder
                .children()
                .find(|n| n.kind() == SyntaxKind::NAME_REF)?;
            match holder.kind() {
                // `Inst.M` / `Step.X` on the second segment.
                SyntaxKind::PATH if first != parent => {
                    let path = ast::Path::cast(holder)?;
                    let segments: Vec<ast::NameRef> = path.segments().collect();
                    let [head, _] = segments.as_slice() else {
                        return None;
                    };
                    let head = head.text();
                    if let Some(fb) = instance_type(&head) {
                        return Some(Hover {
                            range,
                            markdown: member_text(fb, &head, token.text())?,
                        });
                    }
                    let is_step = chart.profile() == ast::Profile::Iec
                        && chart
                            .syntax()
                            .descendants()
                            .filter_map(ast::Step::cast)
                            .any(|s| {
                                s.name()
                                    .is_some_and(|n| n.text().eq_ignore_ascii_case(&head))
                            });
                    let markdown = match token.text().to_ascii_uppercase().as_str() {
                        "X" if is_step => format!(
                            "{}\n\nTRUE while step `{head}` is active",
                            code(&format!("{head}.X : BOOL"))
                        ),
                        "T" if is_step => format!(
                            "{}\n\nhow long step `{head}` has been active (0 while it is not)",
                            code(&format!("{head}.T : TIME"))
                        ),
                        _ => return None,
                    };
                    Some(Hover { range, markdown })
                }
                // A formal of a call: `IN := ...`, `Q => ...`.
                SyntaxKind::FB_ARG => {
                    let call = holder.parent().and_then(ast::FbCall::cast)?;
                    let instance = call.callee()?.text();
                    let fb = instance_type(&instance)?;
                    Some(Hover {
                        range,
                        markdown: member_text(fb, &instance, token.text())?,
                    })
                }
                _ => None,
            }
        }
        _ => None,
    }
}

/// A standard function block: its signature and what it does.
fn fb_text(fb: crate::iec::FbType) -> String {
    format!(
        "{}\n\nstandard function block (IEC 61131-3) · {}",
        code(&fb.signature()),
        fb.doc()
    )
}

/// A segment of a test path: what it names (as the declaration's own hover), and on the last
/// segment the path's type and whether a test can `set` it; members (`state`, `previous`,
/// `.X`/`.T`/`.error`, `calls`, block formals) are described. Addresses are left to the
/// address hover.
fn test_path(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<Hover> {
    let (path, _, res) = crate::lower::test_path_resolution_at(db, ws, file, offset)?;
    let (index, (range, segment)) = res
        .segments
        .iter()
        .enumerate()
        .find(|(_, (r, _))| r.contains_inclusive(offset))?;
    let text = path
        .syntax()
        .text()
        .to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let ty = res
        .ty
        .map_or_else(|| "the type of its value".to_owned(), |t| t.to_string());
    let access = match &res.settable {
        Ok(()) => "test path · can be `set`".to_owned(),
        Err(why) => format!("test path · read-only: {why}"),
    };
    let footer = format!("{}\n\n{access}", code(&format!("{text} : {ty}")));
    match segment {
        SegmentDef::Address => None,
        SegmentDef::Member => {
            let names = path.segment_texts();
            let before = index
                .checked_sub(1)
                .and_then(|i| names.get(i))
                .map_or("", |(n, _)| n.as_str());
            let what = match &res.target {
                PathTarget::InstState {
                    previous: false, ..
                } => {
                    format!("the current state of instance `{before}` (its `CurrentState`)")
                }
                PathTarget::InstState { previous: true, .. } => {
                    format!("the state instance `{before}` left at its last state change")
                }
                PathTarget::ChartState { .. } => {
                    format!("the operating state of chart `{before}`; `command` changes it")
                }
                PathTarget::Step { member, .. } => match member {
                    StepMember::Active => format!("step `{before}` is active"),
                    StepMember::Time => format!("how long step `{before}` has been active"),
                    StepMember::Error => {
                        format!("step `{before}` is active longer than its supervision time")
                    }
                },
                PathTarget::Calls { name, .. } => format!("how often block `{name}` was called"),
                PathTarget::Stub { name, param, .. } => {
                    let written = names.get(index).map_or(param.as_str(), |(n, _)| n.as_str());
                    format!("formal `{written}` of block `{name}`: the value its stub returns")
                }
                PathTarget::External(_) => {
                    "an external reference of a chart the test runs".to_owned()
                }
                _ => return None,
            };
            Some(Hover {
                range: *range,
                markdown: format!("{footer}\n\n{what}"),
            })
        }
        _ => {
            let at = defs::definition_at(db, ws, file, offset)?;
            let mut markdown = definition(db, ws, &at.definition)?;
            if index + 1 == res.segments.len() {
                markdown.push_str("\n\n---\n\n");
                markdown.push_str(&footer);
            }
            Some(Hover {
                range: at.range,
                markdown,
            })
        }
    }
}

/// A fenced code block of HiGraph text.
fn code(text: &str) -> String {
    format!("```higraph\n{text}\n```")
}

/// A node's text with white space and comments collapsed to single spaces.
fn collapsed(node: &SyntaxNode) -> String {
    let mut out = String::new();
    let mut space = false;
    for token in node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
    {
        if token.kind().is_trivia() {
            space = true;
            continue;
        }
        if space && !out.is_empty() {
            out.push(' ');
        }
        space = false;
        out.push_str(token.text());
    }
    out
}

/// The text of a node from its start up to (not including) its `<`, collapsed: the header of
/// a graph, state, instance, step, block interface, ...
fn header(node: &SyntaxNode) -> String {
    let mut out = String::new();
    let mut space = false;
    for element in node.children_with_tokens() {
        if matches!(
            element.kind(),
            SyntaxKind::BODY | SyntaxKind::L_ANGLE | SyntaxKind::VAR_SECTION
        ) {
            break;
        }
        let text = match &element {
            higraph_syntax::rowan::NodeOrToken::Node(n) => collapsed(n),
            higraph_syntax::rowan::NodeOrToken::Token(t) if t.kind().is_trivia() => {
                space = true;
                continue;
            }
            higraph_syntax::rowan::NodeOrToken::Token(t) => t.text().to_owned(),
        };
        if space && !out.is_empty() {
            out.push(' ');
        }
        space = false;
        out.push_str(&text);
    }
    out
}

// ------------------------------------------------------------------------------ definitions

fn definition(db: &dyn salsa::Database, ws: Workspace, definition: &Definition) -> Option<String> {
    if let Definition::Predefined { graph, name } = definition {
        return Some(predefined(db, *graph, name));
    }
    if let Definition::Symbol(position) = definition {
        return symbol(db, ws, *position);
    }
    let (_, node, _) = defs::declaration_node(db, ws, definition)?;
    let comment = node
        .children()
        .find_map(ast::CommentString::cast)
        .map(|c| c.value())
        .filter(|c| !c.is_empty());
    let mut parts: Vec<String> = Vec::new();
    match definition {
        Definition::Variable { owner, .. } => {
            let decl = ast::VarDecl::cast(node.clone())?;
            parts.push(code(&declaration_text(&decl)));
            parts.push(variable_summary(db, *owner, &decl));
            if let Some(fb) = decl
                .ty()
                .and_then(|t| t.name())
                .and_then(|t| crate::iec::FbType::from_name(t.text()))
            {
                parts.push(fb_text(fb));
            }
            if let Some(comment) = decl.comment().map(|c| c.value()).filter(|c| !c.is_empty()) {
                parts.push(comment);
            }
            return Some(parts.join("\n\n"));
        }
        Definition::Graph(_) => {
            parts.push(code(&header(&node)));
            let graph = ast::Graph::cast(node.clone())?;
            let vars = graph.var_sections().flat_map(|s| s.decls()).count();
            let states = graph.states().count();
            let transitions = graph.transitions().count();
            parts.push(format!(
                "graph · {} · {} · {}",
                plural(vars, "variable"),
                plural(states, "state"),
                plural(transitions, "transition")
            ));
        }
        Definition::Group(_) => {
            parts.push(code(&header(&node)));
            let group = ast::Group::cast(node.clone())?;
            parts.push(format!(
                "graph group · {}",
                plural(group.instances().count(), "instance")
            ));
        }
        Definition::Chart(_) => {
            parts.push(code(&header(&node)));
            let chart = ast::Chart::cast(node.clone())?;
            let kind = if chart.is_type() {
                "chart type"
            } else {
                "chart"
            };
            parts.push(format!(
                "{kind} · {}",
                plural(chart.sequencers().count(), "sequencer")
            ));
        }
        Definition::BlockInterface(_) => {
            parts.push(code(&header(&node)));
            let interface = ast::BlockInterface::cast(node.clone())?;
            let params: Vec<String> = interface
                .var_sections()
                .flat_map(|section| {
                    let keyword = section
                        .keyword()
                        .map(|k| k.text().to_ascii_lowercase())
                        .unwrap_or_default();
                    section
                        .decls()
                        .map(move |d| {
                            format!(
                                "`{keyword}` {}",
                                collapsed(d.syntax()).trim_end_matches(';').trim_end()
                            )
                        })
                        .collect::<Vec<_>>()
                })
                .collect();
            parts.push("interface of an external block".to_owned());
            if !params.is_empty() {
                parts.push(params.join("  \n"));
            }
        }
        Definition::Instance { group, .. } => {
            parts.push(code(&header(&node)));
            let graph = ast::Instance::cast(node.clone())
                .and_then(|i| i.graph())
                .map(|g| g.text())
                .unwrap_or_default();
            let position = ast::Group::cast(db::item_root(db, defs::item_loc(db, *group))?)?
                .instances()
                .position(|i| i.syntax().text_range() == node.text_range())
                .map_or(0, |p| p + 1);
            parts.push(format!(
                "instance of graph `{graph}` · number {position} in the run order of group `{}`",
                item_name(db, *group)
            ));
        }
        Definition::State { graph, number } => {
            parts.push(code(&header(&node)));
            parts.push(state_summary(db, *graph, *number, &node));
        }
        Definition::Sequencer { chart, .. } => {
            parts.push(code(&header(&node)));
            parts.push(format!("sequencer of chart `{}`", item_name(db, *chart)));
        }
        Definition::Step { sequencer, .. } => {
            parts.push(code(&header(&node)));
            parts.push(format!("step of sequencer `{sequencer}`"));
        }
        Definition::ChartTransition { sequencer, .. } => {
            parts.push(code(&header(&node)));
            let kind = match node.kind() {
                SyntaxKind::JUMP => "jump",
                SyntaxKind::LOOP => "loop",
                _ => "transition",
            };
            parts.push(format!("{kind} of sequencer `{sequencer}`"));
        }
        Definition::Action { chart, .. } => {
            parts.push(code(&header(&node)));
            let statements =
                ast::ChartAction::cast(node.clone()).map_or(0, |a| a.statements().count());
            parts.push(format!(
                "action of chart `{}` · {} · runs while a qualifier of an active step holds it",
                item_name(db, *chart),
                plural(statements, "statement")
            ));
        }
        Definition::Predefined { .. } | Definition::Symbol(_) => {}
    }
    if let Some(comment) = comment
        && !matches!(
            definition,
            Definition::Graph(_) | Definition::State { .. } | Definition::Group(_)
        )
    {
        parts.push(comment);
    }
    Some(parts.join("\n\n"))
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The declared name of an item.
fn item_name(db: &dyn salsa::Database, item: ItemId) -> String {
    db::file_summary(db, item.file)
        .items
        .get(item.index as usize)
        .and_then(|s| s.name.clone())
        .unwrap_or_default()
}

/// `Name : TYPE [msg in] [:= value]`: a variable declaration without its comment.
fn declaration_text(decl: &ast::VarDecl) -> String {
    let mut text = decl.name().map(|n| n.text()).unwrap_or_default();
    if let Some(ty) = decl.ty() {
        text.push_str(" : ");
        text.push_str(&collapsed(ty.syntax()));
    }
    if let Some(msg) = decl.msg_kind() {
        text.push(' ');
        text.push_str(&collapsed(msg.syntax()));
    }
    if let Some(initial) = decl.initial_value() {
        text.push(' ');
        text.push_str(&collapsed(initial.syntax()));
    }
    text
}

/// `` `in_out` variable of graph `Ventil` · formal parameter · incoming message ``.
fn variable_summary(db: &dyn salsa::Database, owner: ItemId, decl: &ast::VarDecl) -> String {
    let section = decl
        .syntax()
        .parent()
        .and_then(ast::VarSection::cast)
        .and_then(|s| s.keyword())
        .map(|k| k.text().to_ascii_lowercase())
        .unwrap_or_default();
    let owner_text = match defs::item_kind(db, owner) {
        Some(ItemKind::Graph) => format!("graph `{}`", item_name(db, owner)),
        Some(ItemKind::Chart) => format!("chart `{}`", item_name(db, owner)),
        _ => "a block interface".to_owned(),
    };
    let mut text = format!("`{section}` variable of {owner_text}");
    let is_graph = defs::item_kind(db, owner) == Some(ItemKind::Graph);
    if is_graph && section != "stat" {
        text.push_str(" · formal parameter");
    }
    if let Some(msg) = decl.msg_kind() {
        text.push_str(if msg.is_incoming() {
            " · incoming message"
        } else {
            " · outgoing message"
        });
    }
    text
}

fn predefined(db: &dyn salsa::Database, graph: ItemId, name: &str) -> String {
    let Some(p) = lang::predefined(name) else {
        return String::new();
    };
    let access = if p.writable {
        "the graph may write it"
    } else {
        "read-only: the graph runtime sets it"
    };
    let active = if p.active_by_default {
        "always active".to_owned()
    } else {
        let activated = db::item_root(db, defs::item_loc(db, graph))
            .and_then(ast::Graph::cast)
            .is_some_and(|g| GraphScope::new(&g).is_active(p));
        if activated {
            "activated by this graph".to_owned()
        } else {
            format!("inactive until `activate {};`", p.name)
        }
    };
    format!(
        "{}\n\npredefined `{}` variable of every graph · {access} · {active}\n\n{}",
        code(&format!("{} : {}", p.name, p.ty)),
        p.section.as_str(),
        p.meaning
    )
}

fn symbol(db: &dyn salsa::Database, ws: Workspace, position: usize) -> Option<String> {
    let symbol = db::global_index(db, ws).symbols.get(position)?;
    let name = if symbol.quoted {
        format!("\"{}\"", symbol.name)
    } else {
        symbol.name.clone()
    };
    let ty = match (&symbol.type_text, symbol.ty) {
        (Some(written), _) => format!(" {written}"),
        (None, Some(ty)) => format!(" {ty}"),
        (None, None) => String::new(),
    };
    let source = match symbol.source {
        SymbolSource::Declared => format!("declared in `{}`", symbol.name_loc.file.path(db)),
        SymbolSource::Imported(_) => format!("imported from `{}`", symbol.name_loc.file.path(db)),
    };
    let mut parts = vec![
        code(&format!("{name} : {}{ty}", symbol.address_text.trim())),
        format!("global symbol · {source}"),
    ];
    if let Some(comment) = symbol.comment.as_ref().filter(|c| !c.is_empty()) {
        parts.push(comment.clone());
    }
    Some(parts.join("\n\n"))
}

/// Number, name, attributes and the transitions in and out of a state.
fn state_summary(
    db: &dyn salsa::Database,
    graph: ItemId,
    number: u32,
    node: &SyntaxNode,
) -> String {
    let mut text = format!("state {number} of graph `{}`", item_name(db, graph));
    if let Some(state) = ast::State::cast(node.clone()) {
        if let Some(name) = state.comment().map(|c| c.value()) {
            text.push_str(&format!(" · name \"{name}\""));
        }
        let attributes: Vec<String> = state
            .attributes()
            .filter_map(|a| a.keyword())
            .map(|k| k.text().to_ascii_lowercase())
            .collect();
        if !attributes.is_empty() {
            text.push_str(&format!(" · {}", attributes.join(", ")));
        }
    }
    let Some(graph) = db::item_root(db, defs::item_loc(db, graph)).and_then(ast::Graph::cast)
    else {
        return text;
    };
    let is_this = |e: Option<ast::Endpoint>| {
        e.and_then(|e| e.token())
            .and_then(|t| t.text().parse::<u32>().ok())
            == Some(number)
    };
    let mut incoming = Vec::new();
    let mut outgoing = Vec::new();
    for trans in graph.transitions() {
        let label = transition_label(&trans);
        if is_this(trans.target()) {
            incoming.push(label.clone());
        }
        if is_this(trans.source()) {
            outgoing.push(label);
        }
    }
    let list = |labels: &[String]| {
        if labels.is_empty() {
            "none".to_owned()
        } else {
            labels.join(", ")
        }
    };
    text.push_str(&format!(
        "\n\nincoming: {}  \noutgoing: {}",
        list(&incoming),
        list(&outgoing)
    ));
    text
}

/// `` `0->1` prio 1 auto ``: the transition's endpoints, explicit priority and attributes.
fn transition_label(trans: &ast::Trans) -> String {
    let endpoint = |e: Option<ast::Endpoint>| {
        e.and_then(|e| e.token())
            .map_or_else(|| "?".to_owned(), |t| t.text().to_ascii_lowercase())
    };
    let mut label = format!(
        "`{}->{}`",
        endpoint(trans.source()),
        endpoint(trans.target())
    );
    if let Some(prio) = trans.prio().and_then(|p| p.value()) {
        label.push_str(&format!(" prio {}", prio.text()));
    }
    for attribute in trans.attributes().filter_map(|a| a.keyword()) {
        label.push(' ');
        label.push_str(&attribute.text().to_ascii_lowercase());
    }
    label
}

// ------------------------------------------------------------------------------ addresses

/// Area, size, type and the symbol naming an address.
fn address_text(
    db: &dyn salsa::Database,
    ws: Workspace,
    address: &Address,
    mnemonic: Mnemonic,
) -> String {
    let shown = address.display(mnemonic);
    let area_word = shown
        .split(' ')
        .next()
        .map(|w| w.rsplit('.').next().unwrap_or(w))
        .unwrap_or_default();
    let mut meaning = address::area_meaning(area_word, mnemonic)
        .map(|(_, m)| m.to_owned())
        .unwrap_or_else(|| "address".to_owned());
    if address.size == Size::Bit && !meaning.contains("bit") {
        meaning.push_str(" bit");
    }
    let mut parts = vec![code(&shown), format!("{meaning} · {}", address.ty())];
    if let Some(symbol) = db::global_index(db, ws).symbol_for_address(address) {
        let comment = symbol
            .comment
            .as_ref()
            .filter(|c| !c.is_empty())
            .map_or(String::new(), |c| format!(": {c}"));
        parts.push(format!("symbol `{}`{comment}", symbol.name));
    }
    parts.join("\n\n")
}

// ------------------------------------------------------------------------------ operations

/// One operation of the HiGraph STL subset: SIMATIC name, what it does, what operand it takes
/// (Appendix B).
struct Operation {
    simatic: &'static str,
    description: &'static str,
    operand: &'static str,
}

const fn op(simatic: &'static str, description: &'static str, operand: &'static str) -> Operation {
    Operation {
        simatic,
        description,
        operand,
    }
}

const BIT_OPERAND: &str = "a BOOL, TIMER or COUNTER operand; no constant";
const NO_OPERAND: &str = "none";
const COMPARE: &str = "none (compares ACCU 2 with ACCU 1; the result is the RLO)";
const ACCUS: &str = "none (works on ACCU 1 and ACCU 2)";
const ACCU1: &str = "none (works on ACCU 1)";

/// The operations of the HiGraph STL subset (`facts-stl.md` §2.1), by SIMATIC name.
const OPERATIONS: &[Operation] = &[
    op(
        "U",
        "AND: combines the operand's signal state with the RLO",
        BIT_OPERAND,
    ),
    op(
        "UN",
        "AND NOT: combines the negated signal state with the RLO",
        BIT_OPERAND,
    ),
    op(
        "O",
        "OR: combines the operand's signal state with the RLO; without an operand, the OR of AND groups",
        "optional: a BOOL, TIMER or COUNTER operand",
    ),
    op("ON", "OR NOT", BIT_OPERAND),
    op("X", "exclusive OR", BIT_OPERAND),
    op("XN", "exclusive OR NOT", BIT_OPERAND),
    op(
        "U(",
        "AND with a nested expression: saves the RLO on the nesting stack (at most 7 entries)",
        NO_OPERAND,
    ),
    op("UN(", "AND NOT with a nested expression", NO_OPERAND),
    op("O(", "OR with a nested expression", NO_OPERAND),
    op("ON(", "OR NOT with a nested expression", NO_OPERAND),
    op("X(", "exclusive OR with a nested expression", NO_OPERAND),
    op(
        "XN(",
        "exclusive OR NOT with a nested expression",
        NO_OPERAND,
    ),
    op(
        ")",
        "closes a nested expression and combines it with the saved RLO",
        NO_OPERAND,
    ),
    op(
        "=",
        "assign: writes the RLO to the operand",
        "a BOOL operand; no constant",
    ),
    op(
        "S",
        "set: sets the operand to 1 when the RLO is 1 (a counter: loads the preset from ACCU 1)",
        "a BOOL or COUNTER operand; no constant",
    ),
    op(
        "R",
        "reset: sets the operand to 0 when the RLO is 1 (a timer or counter: resets it)",
        "a BOOL, TIMER or COUNTER operand; no constant",
    ),
    op("SET", "sets the RLO to 1", NO_OPERAND),
    op("CLR", "sets the RLO to 0", NO_OPERAND),
    op("NOT", "negates the RLO", NO_OPERAND),
    op(
        "FP",
        "positive edge: the RLO becomes 1 on a rising edge; the operand keeps the previous RLO",
        "a BOOL operand (edge memory); no constant",
    ),
    op(
        "FN",
        "negative edge: the RLO becomes 1 on a falling edge; the operand keeps the previous RLO",
        "a BOOL operand (edge memory); no constant",
    ),
    op(
        "UW",
        "AND word (16 bits): ACCU 1 with ACCU 2 or a constant",
        "optional: a constant accepted for WORD",
    ),
    op(
        "OW",
        "OR word (16 bits)",
        "optional: a constant accepted for WORD",
    ),
    op(
        "XOW",
        "exclusive OR word (16 bits)",
        "optional: a constant accepted for WORD",
    ),
    op(
        "UD",
        "AND double word (32 bits): ACCU 1 with ACCU 2 or a constant",
        "optional: a constant accepted for DWORD",
    ),
    op(
        "OD",
        "OR double word (32 bits)",
        "optional: a constant accepted for DWORD",
    ),
    op(
        "XOD",
        "exclusive OR double word (32 bits)",
        "optional: a constant accepted for DWORD",
    ),
    op(
        "SI",
        "start the timer as a pulse (the time value comes from ACCU 1)",
        "a TIMER operand",
    ),
    op(
        "SV",
        "start the timer as an extended pulse",
        "a TIMER operand",
    ),
    op("SE", "start the timer as an on-delay", "a TIMER operand"),
    op(
        "SS",
        "start the timer as a retentive on-delay",
        "a TIMER operand",
    ),
    op("SA", "start the timer as an off-delay", "a TIMER operand"),
    op(
        "FR",
        "enable a timer or counter (restart on the next rising edge)",
        "a TIMER or COUNTER operand",
    ),
    op(
        "L",
        "load the operand into ACCU 1 (ACCU 1 moves to ACCU 2); a timer or counter loads its value as an integer",
        "a constant, or a BYTE, WORD, DWORD, INT, DINT, REAL, S5TIME, TIME, DATE, TOD, CHAR, TIMER or COUNTER operand; not a peripheral output",
    ),
    op(
        "LC",
        "load the value of a timer or counter into ACCU 1 as BCD",
        "a TIMER or COUNTER operand",
    ),
    op("ZV", "count up", "a COUNTER operand"),
    op("ZR", "count down", "a COUNTER operand"),
    op(
        "T",
        "transfer ACCU 1 to the operand",
        "a BYTE, WORD, DWORD, INT, DINT, REAL, S5TIME, TIME, DATE, TOD or CHAR operand; not a constant, not a peripheral input",
    ),
    op("TAR", "swap the address registers AR1 and AR2", NO_OPERAND),
    op("TAR1", "transfer AR1 to ACCU 1", NO_OPERAND),
    op("TAR2", "transfer AR2 to ACCU 1", NO_OPERAND),
    op(
        "CALL",
        "call a block: an FC or SFC, or an FB or SFB with its instance DB, with parameters",
        "a block (`FC 10`, a symbol), `, DB n` for an FB, and `( formal := actual, ... )`",
    ),
    op(
        "CC",
        "conditional call: calls the block when the RLO is 1",
        "an FC or SFC; no instance DB, no parameters",
    ),
    op("==I", "compare integers (16 bits): equal", COMPARE),
    op("<>I", "compare integers (16 bits): not equal", COMPARE),
    op(">I", "compare integers (16 bits): greater", COMPARE),
    op("<I", "compare integers (16 bits): less", COMPARE),
    op(
        ">=I",
        "compare integers (16 bits): greater or equal",
        COMPARE,
    ),
    op("<=I", "compare integers (16 bits): less or equal", COMPARE),
    op("==D", "compare double integers (32 bits): equal", COMPARE),
    op(
        "<>D",
        "compare double integers (32 bits): not equal",
        COMPARE,
    ),
    op(">D", "compare double integers (32 bits): greater", COMPARE),
    op("<D", "compare double integers (32 bits): less", COMPARE),
    op(
        ">=D",
        "compare double integers (32 bits): greater or equal",
        COMPARE,
    ),
    op(
        "<=D",
        "compare double integers (32 bits): less or equal",
        COMPARE,
    ),
    op("==R", "compare reals: equal", COMPARE),
    op("<>R", "compare reals: not equal", COMPARE),
    op(">R", "compare reals: greater", COMPARE),
    op("<R", "compare reals: less", COMPARE),
    op(">=R", "compare reals: greater or equal", COMPARE),
    op("<=R", "compare reals: less or equal", COMPARE),
    op("+I", "add integers (16 bits): ACCU 2 + ACCU 1", ACCUS),
    op("-I", "subtract integers (16 bits): ACCU 2 − ACCU 1", ACCUS),
    op("*I", "multiply integers (16 bits)", ACCUS),
    op("/I", "divide integers (16 bits): ACCU 2 / ACCU 1", ACCUS),
    op("+D", "add double integers (32 bits)", ACCUS),
    op("-D", "subtract double integers (32 bits)", ACCUS),
    op("*D", "multiply double integers (32 bits)", ACCUS),
    op("/D", "divide double integers (32 bits)", ACCUS),
    op("MOD", "remainder of the double-integer division", ACCUS),
    op(
        "+",
        "add a constant to ACCU 1",
        "an integer from −32768 to 32767, or an `L#` constant",
    ),
    op("+R", "add reals", ACCUS),
    op("-R", "subtract reals", ACCUS),
    op("*R", "multiply reals", ACCUS),
    op("/R", "divide reals", ACCUS),
    op("ABS", "absolute value of a real", ACCU1),
    op("SQR", "square of a real", ACCU1),
    op("SQRT", "square root of a real", ACCU1),
    op("EXP", "exponential of a real", ACCU1),
    op("LN", "natural logarithm of a real", ACCU1),
    op("SIN", "sine of a real (radians)", ACCU1),
    op("COS", "cosine of a real (radians)", ACCU1),
    op("TAN", "tangent of a real (radians)", ACCU1),
    op("ASIN", "arc sine of a real", ACCU1),
    op("ACOS", "arc cosine of a real", ACCU1),
    op("ATAN", "arc tangent of a real", ACCU1),
    op("SLW", "shift word left", "optional: a shift count 0 to 15"),
    op("SRW", "shift word right", "optional: a shift count 0 to 15"),
    op(
        "SSI",
        "shift integer right with sign",
        "optional: a shift count 0 to 15",
    ),
    op(
        "SLD",
        "shift double word left",
        "optional: a shift count 0 to 32",
    ),
    op(
        "SRD",
        "shift double word right",
        "optional: a shift count 0 to 32",
    ),
    op(
        "SSD",
        "shift double integer right with sign",
        "optional: a shift count 0 to 32",
    ),
    op(
        "RLD",
        "rotate double word left",
        "optional: a shift count 0 to 32",
    ),
    op(
        "RRD",
        "rotate double word right",
        "optional: a shift count 0 to 32",
    ),
    op("RLDA", "rotate ACCU 1 left via CC 1", ACCU1),
    op("RRDA", "rotate ACCU 1 right via CC 1", ACCU1),
    op(
        "INC",
        "increment the low byte of ACCU 1",
        "an integer from 0 to 255",
    ),
    op(
        "DEC",
        "decrement the low byte of ACCU 1",
        "an integer from 0 to 255",
    ),
    op("TAK", "swap ACCU 1 and ACCU 2", NO_OPERAND),
    op(
        "PUSH",
        "push: ACCU 1 to ACCU 2 (and on through the accumulators)",
        NO_OPERAND,
    ),
    op(
        "POP",
        "pop: ACCU 2 to ACCU 1 (and on through the accumulators)",
        NO_OPERAND,
    ),
    op("TAD", "reverse the byte order of ACCU 1 (32 bits)", ACCU1),
    op(
        "TAW",
        "reverse the byte order of the low word of ACCU 1",
        ACCU1,
    ),
    op("BTI", "convert BCD to integer (16 bits)", ACCU1),
    op("BTD", "convert BCD to double integer", ACCU1),
    op("ITB", "convert integer (16 bits) to BCD", ACCU1),
    op("DTB", "convert double integer to BCD", ACCU1),
    op("ITD", "convert integer (16 bits) to double integer", ACCU1),
    op("DTR", "convert double integer to real", ACCU1),
    op("INVI", "ones' complement of an integer (16 bits)", ACCU1),
    op("INVD", "ones' complement of a double integer", ACCU1),
    op("NEGI", "two's complement of an integer (16 bits)", ACCU1),
    op("NEGD", "two's complement of a double integer", ACCU1),
    op("NEGR", "negate a real", ACCU1),
    op("RND", "round a real to a double integer", ACCU1),
    op("RND+", "round a real up to a double integer", ACCU1),
    op("RND-", "round a real down to a double integer", ACCU1),
    op("TRUNC", "truncate a real to a double integer", ACCU1),
];

/// The hover text of an operation as written in a file of `mnemonic`.
fn operation(written: &str, mnemonic: Mnemonic) -> Option<String> {
    let (simatic, note) = match lang::classify_op(written, mnemonic) {
        OpClass::Subset(simatic) => (simatic, None),
        OpClass::OtherSet {
            simatic,
            translated,
        } => {
            let note = format!(
                "`{written}` is the {} spelling; this file uses {} mnemonics: write `{translated}` (HG4007)",
                mnemonic.other().display(),
                mnemonic.display()
            );
            (simatic, Some(note))
        }
        OpClass::Outside(_) => {
            return Some(format!(
                "{}\n\nnot part of the HiGraph STL subset (HG4003)",
                code(written)
            ));
        }
        OpClass::Unknown => return None,
    };
    let entry = OPERATIONS.iter().find(|o| o.simatic == simatic)?;
    let in_file = lang::op_in_set(&simatic, mnemonic);
    let other = lang::op_in_set(&simatic, mnemonic.other());
    let spelling = if other == in_file {
        String::new()
    } else {
        format!(" ({} `{other}`)", mnemonic.other().display())
    };
    let mut text = format!(
        "{}\n\n{}{spelling}\n\noperand: {}",
        code(&in_file),
        entry.description,
        entry.operand
    );
    if let Some(note) = note {
        text.push_str("\n\n");
        text.push_str(&note);
    }
    Some(text)
}

// ------------------------------------------------------------------------------ allow codes

/// The code under the cursor in a `// higraph-allow: LIST` comment, with its documentation.
fn allow_code(token: &SyntaxToken, offset: TextSize) -> Option<Hover> {
    let text = token.text();
    let body = text.trim_start_matches('/').trim_start();
    let list = body.strip_prefix("higraph-allow:")?;
    let mut at = text.len() - list.len();
    for part in list.split(',') {
        let lead = part.len() - part.trim_start().len();
        let trimmed = part.trim();
        let start = token.text_range().start() + TextSize::from((at + lead) as u32);
        let range = TextRange::at(start, TextSize::from(trimmed.len() as u32));
        at += part.len() + 1;
        if !trimmed.is_empty() && range.contains_inclusive(offset) {
            return Some(Hover {
                range,
                markdown: rule_text(trimmed)?,
            });
        }
    }
    None
}

/// The documentation of a code (`HG1210`), or the list of rules of a pattern (`HG12xx`).
fn rule_text(code: &str) -> Option<String> {
    let upper = code.to_ascii_uppercase();
    if let Some(doc) = registry::rule_doc(&upper) {
        return Some(doc.to_owned());
    }
    if let Some(rule) = registry::rule_of(&upper) {
        return Some(format!(
            "**{}** ({})\n\n{}",
            rule.code,
            rule.default_severity.as_str(),
            rule.template
        ));
    }
    let prefix = upper.trim_end_matches('X');
    if prefix.len() < 3 || prefix.len() == upper.len() {
        return None;
    }
    let rules: Vec<String> = registry::RULES
        .iter()
        .filter(|r| r.code.as_str().starts_with(prefix))
        .map(|r| {
            format!(
                "* `{}` ({}): {}",
                r.code,
                r.default_severity.as_str(),
                r.template
            )
        })
        .collect();
    if rules.is_empty() {
        return None;
    }
    Some(format!(
        "**{upper}**: {}\n\n{}",
        plural(rules.len(), "rule"),
        rules.join("\n")
    ))
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    fn check(text: &str) -> String {
        let f = fixture::load(text);
        match f.host.analysis().hover(&f.position) {
            Ok(Some(hover)) => format!(
                "[{}]\n{}",
                f.slice(&f.position.path, hover.range),
                hover.markdown
            ),
            Ok(None) => "no hover".to_owned(),
            Err(_) => "cancelled".to_owned(),
        }
    }

    const GRAPH: &str = r#"//- a.higraph
graph Ventil "valve" <
  in < Oben : BOOL "drill at top"; Zeit : TIME := T#5S; >
  in_out < IM_Ab : BOOL msg in; >
  activate CurrentState;
  state 0 "Init" < C: U Oben; = E 1.0; L CurrentState; T MW 10; >
  state 1 "Oben" fault message < C: U IM_Ab; = Start; supervise Zeit; >
  trans any->0 prio 1 < U INIT_SD; >
  trans 0->1 prio 1 auto < U Oben; >
  trans 1->0 prio 2 < U IM_Ab; >
>
// higraph-allow: HG1210, HG21xx
symbols < Start : A 4.1 BOOL "lamp"; >
//- b.higraph
mnemonic international;
graph G < state 0 < C: A I 1.0; U I 1.1; > trans any->0 < A INIT_SD; > >
group Anlage fc FC 1 db DB 1 < instance V1 : Ventil "first" < Oben := Start; > >
"#;

    fn at(needle: &str) -> String {
        check(&GRAPH.replacen(needle, &format!("$0{needle}"), 1))
    }

    const TESTED: &str = r#"//- plant.higraph
graph Ventil <
  in < Oben : BOOL "drill at top"; >
  out < Auf : BOOL; >
  state 0 < C: U Oben; = Auf; >
  trans any->0 < U INIT_SD; >
>
group Anlage fc FC 1 db DB 1 <
  instance V1 : Ventil < Oben := Start; >
>
chart Mischer <
  in < Freigabe : BOOL; >
  sequencer RUN <
    start < Freigabe; >
    step Heizen < >
    trans T1 < Freigabe; >
  >
>
symbols < Start : E 0.0 BOOL; Dosieren : FC 10; >
block Dosieren < out < Menge : INT; > >
//- tests.higraph
test T1 <
  run Anlage, Mischer;
  set V1.Oben := TRUE;
  expect V1.state = 0 and V1.previous = 0 and V1.ManualMode;
  expect Mischer.RUN.Heizen.T > T#0S and Mischer.Heizen.error and Mischer.state = Ready;
  expect Dosieren.calls = 0 and Dosieren.Menge = 0 and MW 10 = 0;
>
"#;

    fn in_test(needle: &str) -> String {
        let marker = "//- tests.higraph\n";
        let start = TESTED.find(marker).map_or(0, |i| i + marker.len());
        let at = TESTED[start..].find(needle).map_or(start, |i| start + i);
        check(&format!("{}$0{}", &TESTED[..at], &TESTED[at..]))
    }

    #[test]
    fn test_path_segments() {
        insta::assert_snapshot!(in_test("Oben :="), @"
        [Oben]
        ```higraph
        Oben : BOOL
        ```

        `in` variable of graph `Ventil` · formal parameter

        drill at top

        ---

        ```higraph
        V1.Oben : BOOL
        ```

        test path · can be `set`
        ");
        insta::assert_snapshot!(in_test("V1.Oben"), @"
        [V1]
        ```higraph
        instance V1 : Ventil
        ```

        instance of graph `Ventil` · number 1 in the run order of group `Anlage`
        ");
        insta::assert_snapshot!(in_test("state = 0"), @"
        [state]
        ```higraph
        V1.state : WORD
        ```

        test path · read-only: V1.state is kept by the instance

        the current state of instance `V1` (its `CurrentState`)
        ");
        insta::assert_snapshot!(in_test("previous"), @"
        [previous]
        ```higraph
        V1.previous : WORD
        ```

        test path · read-only: V1.previous is kept by the instance

        the state instance `V1` left at its last state change
        ");
        insta::assert_snapshot!(in_test("ManualMode"), @"
        [ManualMode]
        ```higraph
        ManualMode : BOOL
        ```

        predefined `in` variable of every graph · the graph may write it · always active

        manual operating mode: transitions marked 'manual' fire only while it is 1

        ---

        ```higraph
        V1.ManualMode : BOOL
        ```

        test path · can be `set`
        ");
        insta::assert_snapshot!(in_test("T > T#0S"), @"
        [T]
        ```higraph
        Mischer.RUN.Heizen.T : TIME
        ```

        test path · read-only: Mischer.RUN.Heizen.T is kept by the chart

        how long step `Heizen` has been active
        ");
        insta::assert_snapshot!(in_test("error"), @"
        [error]
        ```higraph
        Mischer.Heizen.error : BOOL
        ```

        test path · read-only: Mischer.Heizen.error is kept by the chart

        step `Heizen` is active longer than its supervision time
        ");
        insta::assert_snapshot!(in_test("state = Ready"), @"
        [state]
        ```higraph
        Mischer.state : operating state
        ```

        test path · read-only: Mischer.state changes by commands

        the operating state of chart `Mischer`; `command` changes it
        ");
        insta::assert_snapshot!(in_test("Heizen.T"), @"
        [Heizen]
        ```higraph
        step Heizen
        ```

        step of sequencer `RUN`
        ");
        insta::assert_snapshot!(in_test("calls"), @"
        [calls]
        ```higraph
        Dosieren.calls : DINT
        ```

        test path · read-only: Dosieren.calls counts the calls

        how often block `Dosieren` was called
        ");
        insta::assert_snapshot!(in_test("Menge"), @"
        [Menge]
        ```higraph
        Dosieren.Menge : INT
        ```

        test path · can be `set`

        formal `Menge` of block `Dosieren`: the value its stub returns
        ");
        insta::assert_snapshot!(in_test("MW 10"), @"
        [MW 10]
        ```higraph
        MW 10
        ```

        memory word · WORD
        ");
    }

    #[test]
    fn variables() {
        insta::assert_snapshot!(at("Oben; = E"), @"
        [Oben]
        ```higraph
        Oben : BOOL
        ```

        `in` variable of graph `Ventil` · formal parameter

        drill at top
        ");
        insta::assert_snapshot!(at("Zeit : TIME"), @"
        [Zeit]
        ```higraph
        Zeit : TIME := T#5S
        ```

        `in` variable of graph `Ventil` · formal parameter
        ");
        insta::assert_snapshot!(at("IM_Ab; >"), @"
        [IM_Ab]
        ```higraph
        IM_Ab : BOOL msg in
        ```

        `in_out` variable of graph `Ventil` · formal parameter · incoming message
        ");
    }

    #[test]
    fn predefined_variables() {
        insta::assert_snapshot!(at("CurrentState; T"), @"
        [CurrentState]
        ```higraph
        CurrentState : WORD
        ```

        predefined `stat` variable of every graph · read-only: the graph runtime sets it · activated by this graph

        number of the active state
        ");
        insta::assert_snapshot!(at("INIT_SD; > >"), @"
        [INIT_SD]
        ```higraph
        INIT_SD : BOOL
        ```

        predefined `stat` variable of every graph · the graph may write it · always active

        startup: set by the group FC on restart; the startup any-transition queries it
        ");
    }

    #[test]
    fn operations_in_both_mnemonics() {
        insta::assert_snapshot!(at("U Oben"), @"
        [U]
        ```higraph
        U
        ```

        AND: combines the operand's signal state with the RLO (international `A`)

        operand: a BOOL, TIMER or COUNTER operand; no constant
        ");
        insta::assert_snapshot!(at("A I 1.0"), @"
        [A]
        ```higraph
        A
        ```

        AND: combines the operand's signal state with the RLO (SIMATIC `U`)

        operand: a BOOL, TIMER or COUNTER operand; no constant
        ");
        insta::assert_snapshot!(at("U I 1.1"), @"
        [U]
        ```higraph
        A
        ```

        AND: combines the operand's signal state with the RLO (SIMATIC `U`)

        operand: a BOOL, TIMER or COUNTER operand; no constant

        `U` is the SIMATIC spelling; this file uses international mnemonics: write `A` (HG4007)
        ");
    }

    #[test]
    fn addresses_and_symbols() {
        insta::assert_snapshot!(at("E 1.0"), @"
        [E 1.0]
        ```higraph
        E 1.0
        ```

        input bit · BOOL
        ");
        insta::assert_snapshot!(at("MW 10"), @"
        [MW 10]
        ```higraph
        MW 10
        ```

        memory word · WORD
        ");
        insta::assert_snapshot!(at("A 4.1"), @"
        [A 4.1]
        ```higraph
        A 4.1
        ```

        output bit · BOOL

        symbol `Start`: lamp
        ");
        insta::assert_snapshot!(at("Start; supervise"), @"
        [Start]
        ```higraph
        Start : A 4.1 BOOL
        ```

        global symbol · declared in `a.higraph`

        lamp
        ");
    }

    #[test]
    fn states_instances_and_items() {
        insta::assert_snapshot!(at("1 \"Oben\""), @r#"
        [1]
        ```higraph
        state 1 "Oben" fault message
        ```

        state 1 of graph `Ventil` · name "Oben" · fault, message

        incoming: `0->1` prio 1 auto  
        outgoing: `1->0` prio 2
        "#);
        insta::assert_snapshot!(at("V1 :"), @r#"
        [V1]
        ```higraph
        instance V1 : Ventil "first"
        ```

        instance of graph `Ventil` · number 1 in the run order of group `Anlage`

        first
        "#);
        insta::assert_snapshot!(at("Ventil \"valve\""), @r#"
        [Ventil]
        ```higraph
        graph Ventil "valve"
        ```

        graph · 3 variables · 2 states · 3 transitions
        "#);
        insta::assert_snapshot!(at("Anlage"), @"
        [Anlage]
        ```higraph
        group Anlage fc FC 1 db DB 1
        ```

        graph group · 1 instance
        ");
    }

    #[test]
    fn charts_and_block_interfaces() {
        let text = r#"
chart Mischer "batch mixer" <
  sequencer RUN < start < TRUE; > step START "fill" < > trans T1 < TRUE; > step ENDE < >
    loop L1 -> START < TRUE; > >
>
block FC 10 "Dosieren" < in < Menge : INT; > out < Fertig : BOOL; > >
graph G < state 0 < C: CALL FC 10 (Menge := MW 2, Fertig := M 0.0); > trans any->0 < U INIT_SD; > >
"#;
        let at = |needle: &str| check(&text.replacen(needle, &format!("$0{needle}"), 1));
        insta::assert_snapshot!(
            [at("Mischer"), at("RUN"), at("START <"), at("L1"), at("FC 10 (")].join("\n---\n"),
            @r#"
        [Mischer]
        ```higraph
        chart Mischer "batch mixer"
        ```

        chart · 1 sequencer

        batch mixer
        ---
        [RUN]
        ```higraph
        sequencer RUN
        ```

        sequencer of chart `Mischer`
        ---
        [START]
        ```higraph
        step START "fill"
        ```

        step of sequencer `RUN`

        fill
        ---
        [L1]
        ```higraph
        loop L1 -> START
        ```

        loop of sequencer `RUN`
        ---
        [FC 10]
        ```higraph
        block FC 10 "Dosieren"
        ```

        interface of an external block

        `in` Menge : INT  
        `out` Fertig : BOOL

        Dosieren
        "#
        );
    }

    #[test]
    fn codes_in_allow_comments() {
        let doc = at("HG1210,");
        assert!(
            doc.starts_with("[HG1210]\n# HG1210: unused variable"),
            "{doc}"
        );
        insta::assert_snapshot!(at("HG21xx"), @"
        [HG21xx]
        **HG21XX**: 6 rules

        * `HG2101` (error): state number {n} is already used in graph {graph}
        * `HG2102` (error): state number {n} is outside 0..65535
        * `HG2103` (error): state {n} does not exist in graph {graph}
        * `HG2104` (error): 'any' can only be the source of a transition
        * `HG2105` (hint): states of {graph} are not numbered 0 to {n-1} without gaps (missing: {list})
        * `HG2106` (warning): attribute '{attr}' is given twice
        ");
    }

    #[test]
    fn nothing_on_punctuation_and_comments() {
        assert_eq!(at("< Oben"), "no hover");
    }

    #[test]
    fn iec_function_blocks_members_steps_and_actions() {
        let chart = "chart Ampel <
  profile iec;
  stat < Uhr : TON; Teile : INT; >
  action Zaehlen < Teile := Teile + 1; >
  sequencer Haupt <
    step Rot < P1 Zaehlen; run < Uhr(IN := Rot.X, PT := T#5S); > >
    trans Weiter < Uhr.Q; >
    step Gruen < >
  >
>
";
        let at = |needle: &str, with: &str| {
            let text = chart.replacen(needle, with, 1);
            let f = fixture::load(&text);
            f.host
                .analysis()
                .hover(&f.position)
                .expect("not cancelled")
                .map(|h| h.markdown)
                .unwrap_or_default()
        };
        let member = at("Uhr.Q", "Uhr.$0Q");
        assert!(
            member.contains("Uhr.Q : BOOL") && member.contains("output of `Uhr` (TON)"),
            "{member}"
        );
        let formal = at("PT :=", "$0PT :=");
        assert!(
            formal.contains("Uhr.PT : TIME") && formal.contains("input"),
            "{formal}"
        );
        let ty = at(": TON", ": $0TON");
        assert!(
            ty.contains("TON(IN : BOOL, PT : TIME) => (Q : BOOL, ET : TIME)"),
            "{ty}"
        );
        let instance = at("Uhr(", "$0Uhr(");
        assert!(
            instance.contains("`stat` variable of chart `Ampel`") && instance.contains("on-delay"),
            "{instance}"
        );
        let flag = at("Rot.X", "Rot.$0X");
        assert!(flag.contains("Rot.X : BOOL"), "{flag}");
        let action = at("P1 Zaehlen", "P1 $0Zaehlen");
        assert!(
            action.contains("action of chart `Ampel` · 1 statement"),
            "{action}"
        );
    }
}

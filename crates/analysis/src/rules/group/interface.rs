//! What a group needs to know about an instantiated graph: its formal parameters (`diagnostics.md`
//! §3.5), whether it has `auto`/`manual` transitions and whether it writes `ManualMode` or
//! `AutomaticMode` itself (HG3104).
//!
//! [`graph_interface`] is a salsa query over the graph's own syntax tree. Its result holds no
//! positions, so an edit inside a state or transition body leaves it equal and the groups that
//! instantiate the graph are not checked again.

use higraph_syntax::{
    SyntaxKind, SyntaxNode,
    ast::{self, AstNode, EndpointKind},
};

use crate::{
    db::{self, ItemLoc},
    index,
    lang::{self, Section, Type},
    rules::decls,
};

/// The direction of a message variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum MsgDir {
    /// `msg in`.
    Incoming,
    /// `msg out`.
    Outgoing,
}

/// One declared variable of a graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct InterfaceVar {
    /// The name as declared.
    pub name: String,
    pub section: Section,
    /// The declared type; `None` if it is missing or unknown (C2).
    pub ty: Option<Type>,
    /// `msg in` / `msg out` as written (in any section).
    pub msg: Option<MsgDir>,
}

impl InterfaceVar {
    /// The direction if it is a message formal (an `in_out` variable marked `msg`).
    pub fn message(&self) -> Option<MsgDir> {
        self.msg.filter(|_| self.section == Section::InOut)
    }
}

/// The two operating-mode inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    Manual,
    Automatic,
}

impl Mode {
    /// The predefined variable of the mode.
    pub fn variable(self) -> &'static str {
        match self {
            Mode::Manual => "ManualMode",
            Mode::Automatic => "AutomaticMode",
        }
    }

    /// The transition attribute that depends on the mode.
    pub fn attribute(self) -> &'static str {
        match self {
            Mode::Manual => "manual",
            Mode::Automatic => "auto",
        }
    }

    fn of_name(name: &str) -> Option<Mode> {
        if name.eq_ignore_ascii_case("ManualMode") {
            Some(Mode::Manual)
        } else if name.eq_ignore_ascii_case("AutomaticMode") {
            Some(Mode::Automatic)
        } else {
            None
        }
    }
}

/// A CALL target as written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum CalleeRef {
    /// An `ADDRESS` node, white space removed.
    Address(String),
    /// A name or a quoted name (without the quotes).
    Name(String),
}

/// A CALL actual that names a mode variable: a write unless the callee's interface is known
/// and the formal is an `in` parameter (Appendix E).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ModeCallArg {
    pub mode: Mode,
    pub callee: CalleeRef,
    /// The formal parameter of the callee, as written.
    pub formal: String,
}

/// The interface of a graph as seen from a group.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct GraphInterface {
    /// The graph's name as declared.
    pub name: String,
    /// The declared variables in declaration order; a later duplicate is left out (C3).
    pub vars: Vec<InterfaceVar>,
    /// A transition that is not a startup transition has `auto`.
    pub has_auto: bool,
    /// A transition that is not a startup transition has `manual`.
    pub has_manual: bool,
    /// The graph writes `ManualMode` (`= S R T FP FN`).
    pub writes_manual: bool,
    /// The graph writes `AutomaticMode`.
    pub writes_automatic: bool,
    /// CALL actuals that name a mode variable.
    pub mode_call_args: Vec<ModeCallArg>,
}

/// The predefined formal parameters of every graph (§3.5).
pub(crate) const PREDEFINED_FORMALS: [&str; 3] = ["ManualMode", "AutomaticMode", "UsrMsgQuit"];

impl GraphInterface {
    /// The declared variable of that name (case-insensitive).
    pub fn var(&self, name: &str) -> Option<&InterfaceVar> {
        self.vars.iter().find(|v| v.name.eq_ignore_ascii_case(name))
    }

    /// The formal parameters in declaration order: user formals, then the predefined inputs.
    pub fn formal_names(&self) -> impl Iterator<Item = &str> {
        self.vars
            .iter()
            .filter(|v| v.section.is_formal())
            .map(|v| v.name.as_str())
            .chain(
                PREDEFINED_FORMALS
                    .into_iter()
                    .filter(|p| self.var(p).is_none()),
            )
    }

    /// Does the graph write the mode variable itself (CALL actuals not included)?
    pub fn writes(&self, mode: Mode) -> bool {
        match mode {
            Mode::Manual => self.writes_manual,
            Mode::Automatic => self.writes_automatic,
        }
    }

    /// Does the graph have a non-startup transition marked with the mode's attribute?
    pub fn has_mode_transitions(&self, mode: Mode) -> bool {
        match mode {
            Mode::Manual => self.has_manual,
            Mode::Automatic => self.has_auto,
        }
    }
}

/// The interface of the graph at `item` (empty if the item is not a graph).
#[salsa::tracked(returns(ref))]
pub(crate) fn graph_interface<'db>(
    db: &'db dyn salsa::Database,
    item: ItemLoc<'db>,
) -> GraphInterface {
    let Some(graph) = db::item_root(db, item).and_then(ast::Graph::cast) else {
        return GraphInterface::default();
    };
    let mut interface = GraphInterface {
        name: graph.name().map(|n| n.text()).unwrap_or_default(),
        ..GraphInterface::default()
    };
    collect_vars(&graph, &mut interface);
    // The operating-mode facts of the members, chunk by chunk (see `db::chunk_modes`): an
    // edit in one member does not walk the whole graph again.
    let mut modes = ModeFacts::default();
    for &chunk in &db::graph_layout(db, item).chunks {
        modes.merge(db::chunk_modes(db, chunk));
    }
    interface.has_auto = modes.has_auto;
    interface.has_manual = modes.has_manual;
    interface.writes_manual = modes.writes_manual;
    interface.writes_automatic = modes.writes_automatic;
    interface.mode_call_args = modes.mode_call_args;
    interface
}

/// What the graph interface needs of the members of a graph: the operating-mode attributes
/// of transitions, writes of the mode variables and CALL actuals naming them.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ModeFacts {
    has_auto: bool,
    has_manual: bool,
    writes_manual: bool,
    writes_automatic: bool,
    mode_call_args: Vec<ModeCallArg>,
}

impl ModeFacts {
    /// The facts of one member (`member` is its root).
    pub(crate) fn of(member: &SyntaxNode) -> ModeFacts {
        let mut interface = GraphInterface::default();
        if let Some(trans) = ast::Trans::cast(member.clone()) {
            mode_transition(&trans, &mut interface);
        }
        collect_mode_writes(member, &mut interface);
        ModeFacts {
            has_auto: interface.has_auto,
            has_manual: interface.has_manual,
            writes_manual: interface.writes_manual,
            writes_automatic: interface.writes_automatic,
            mode_call_args: interface.mode_call_args,
        }
    }

    /// Adds the facts of further members (in text order).
    pub(crate) fn merge(&mut self, other: &ModeFacts) {
        self.has_auto |= other.has_auto;
        self.has_manual |= other.has_manual;
        self.writes_manual |= other.writes_manual;
        self.writes_automatic |= other.writes_automatic;
        self.mode_call_args
            .extend(other.mode_call_args.iter().cloned());
    }
}

fn collect_vars(graph: &ast::Graph, interface: &mut GraphInterface) {
    for (kind, decl) in decls::declarations(graph.var_sections()) {
        let Some(name) = decl.name().map(|n| n.text()).filter(|n| !n.is_empty()) else {
            continue;
        };
        if interface.var(&name).is_some() {
            continue;
        }
        let msg = decl.msg_kind().map(|m| {
            if m.is_incoming() {
                MsgDir::Incoming
            } else {
                MsgDir::Outgoing
            }
        });
        interface.vars.push(InterfaceVar {
            name,
            section: kind,
            ty: decl.ty().and_then(|t| index::declared_type(&t)),
            msg,
        });
    }
}

/// The name an operand refers to by name (`Name`, `#Name`).
fn operand_name(operand: &ast::Operand) -> Option<String> {
    match operand {
        ast::Operand::NameRef(n) => Some(n.text()),
        ast::Operand::VarRef(v) => v.name().map(|t| t.text().to_owned()),
        _ => None,
    }
}

/// Every operand of a statement: its operand and the values of its CALL parameters.
fn statement_operands(stmt: &ast::StlStmt) -> impl Iterator<Item = ast::Operand> + use<> {
    let params = stmt
        .call_args()
        .into_iter()
        .flat_map(|args| args.params())
        .filter_map(|p| p.value());
    stmt.operand().into_iter().chain(params)
}

/// Is `trans` a startup transition (§2.6): an any-transition whose condition part has an
/// operand naming `INIT_SD`?
fn is_startup(trans: &ast::Trans) -> bool {
    if trans.source().and_then(|s| s.kind()) != Some(EndpointKind::Any) {
        return false;
    }
    let Some(body) = trans.body() else {
        return false;
    };
    body.blocks()
        .filter(|b| b.label().is_none_or(|l| l.name() == "?"))
        .flat_map(|b| b.statements())
        .flat_map(|s| statement_operands(&s))
        .any(|o| operand_name(&o).is_some_and(|n| n.eq_ignore_ascii_case("INIT_SD")))
}

fn mode_transition(trans: &ast::Trans, interface: &mut GraphInterface) {
    let attributes: Vec<String> = trans
        .attributes()
        .filter_map(|a| a.keyword())
        .map(|k| k.text().to_ascii_lowercase())
        .collect();
    if attributes.is_empty() || is_startup(trans) {
        return;
    }
    interface.has_auto |= attributes.iter().any(|a| a == "auto");
    interface.has_manual |= attributes.iter().any(|a| a == "manual");
}

/// Operations that write their operand (Appendix E; the edge operations read and write).
const WRITING_OPS: [&str; 6] = ["=", "S", "R", "T", "FP", "FN"];

fn collect_mode_writes(member: &SyntaxNode, interface: &mut GraphInterface) {
    let statements = member
        .descendants()
        .filter(|n| n.kind() == SyntaxKind::STL_STMT)
        .filter_map(ast::StlStmt::cast);
    for stmt in statements {
        let Some(op) = stmt.opcode().map(|o| o.text()) else {
            continue;
        };
        if WRITING_OPS.contains(&op.as_str()) {
            let mode = stmt
                .operand()
                .and_then(|o| operand_name(&o))
                .and_then(|n| Mode::of_name(&n));
            match mode {
                Some(Mode::Manual) => interface.writes_manual = true,
                Some(Mode::Automatic) => interface.writes_automatic = true,
                None => {}
            }
        } else if op == "CALL" {
            collect_call_args(&stmt, interface);
        }
    }
}

fn collect_call_args(stmt: &ast::StlStmt, interface: &mut GraphInterface) {
    let Some(args) = stmt.call_args() else {
        return;
    };
    let Some(callee) = args.blocks().next().and_then(|b| callee_ref(&b)) else {
        return;
    };
    for param in args.params() {
        let mode = param
            .value()
            .and_then(|v| operand_name(&v))
            .and_then(|n| Mode::of_name(&n));
        let (Some(mode), Some(formal)) = (mode, param.formal()) else {
            continue;
        };
        interface.mode_call_args.push(ModeCallArg {
            mode,
            callee: callee.clone(),
            formal: formal.text(),
        });
    }
}

fn callee_ref(block: &ast::BlockRef) -> Option<CalleeRef> {
    if let Some(address) = block.address() {
        return Some(CalleeRef::Address(address.compact_text()));
    }
    if let Some(name) = block.name_ref() {
        return Some(CalleeRef::Name(name.text()));
    }
    block.symbol_ref().map(|s| CalleeRef::Name(s.name()))
}

/// Is `name` a predefined variable of the `stat` section (not a formal)?
pub(crate) fn is_predefined_stat(name: &str) -> bool {
    lang::predefined(name).is_some_and(|p| p.section == Section::Stat)
}

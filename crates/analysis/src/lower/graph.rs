//! Graphs → [`higraph_runtime::program::Graph`]: the variable table (predefined variables
//! first), states with their blocks and times, transitions by effective priority with their
//! condition blocks split as `runtime.md` §2.4 says, the startup transition and the initial
//! state. Operands are resolved by the analysis' own resolver ([`crate::resolve`]).

use std::collections::HashMap;

use higraph_runtime::program::{
    Block, Call, Graph, Instr, OpCode, Operand, Origin, Predef, State, Target, TimeValue, Trans,
    VarIdx, VarInfo,
};
use higraph_runtime::value::{Const, Ty, Value};
use higraph_syntax::{TextRange, ast, ast::AstNode};

use super::build::Lowerer;
use super::values;
use crate::db::{self, ItemLoc};
use crate::lang::{self, Mnemonic, OpClass, Type};
use crate::resolve::{self, GraphScope, Role, Target as RTarget, Usage};
use crate::rules::{Ctx, graph::GraphModel};

/// What the test paths need of a lowered graph: its variables by name.
#[derive(Debug, Clone, Default)]
pub(crate) struct GraphMeta {
    /// Upper-case name → variable index (declared and predefined).
    pub vars: HashMap<String, VarIdx>,
    /// Declared variables: (name range in the item, section), by `VarIdx - 18`.
    pub declared: Vec<(TextRange, lang::Section)>,
}

/// The variable index of a predefined variable, by name.
pub(crate) fn predef_index(name: &str) -> Option<VarIdx> {
    Predef::ALL
        .iter()
        .find(|p| p.name().eq_ignore_ascii_case(name))
        .map(|p| p.var())
}

const PREDEFS: VarIdx = Predef::ALL.len() as VarIdx;

/// The SIMATIC opcode of an operation (its SIMATIC name, upper case).
fn opcode(op: &str, constant_operand: Option<&Const>) -> Option<OpCode> {
    match (OpCode::from_simatic(op)?, constant_operand) {
        (OpCode::AddInt, Some(Const::LongInt(_))) => Some(OpCode::AddDint),
        (code, _) => Some(code),
    }
}

/// The type an operation implies for an unresolved name (as the STL rules use it).
fn implied(op: &str) -> Option<Type> {
    match op {
        "U" | "UN" | "X" | "XN" | "ON" | "O" | "=" | "FP" | "FN" | "S" | "R" => Some(Type::Bool),
        "SI" | "SV" | "SE" | "SS" | "SA" => Some(Type::Timer),
        "ZV" | "ZR" => Some(Type::Counter),
        _ => None,
    }
}

/// The opcode as written, without white space.
fn written_opcode(opcode: &ast::Opcode) -> String {
    opcode
        .syntax()
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| t.text().to_owned())
        .collect()
}

/// Lowers one graph (with its own resolution context).
pub(crate) struct GraphLowering<'l, 'a> {
    pub lw: &'l mut Lowerer<'a>,
    pub ctx: Ctx<'a>,
    pub scope: GraphScope,
    pub item: ItemLoc<'a>,
    pub mnemonic: Mnemonic,
    /// The operand being resolved, for the names side table (`names.rs`).
    pub slot: Option<super::names::Slot>,
    /// The `wait` (false) or `supervise` (true) value of a state being resolved.
    pub time_slot: Option<(u16, bool)>,
}

impl GraphLowering<'_, '_> {
    /// The origin of an item-relative range.
    fn origin(&mut self, range: TextRange) -> Origin {
        let (file, index) = (self.item.file(self.lw.db), self.item.index(self.lw.db));
        self.lw.origin(file, index, range)
    }

    /// Resolves an operand of this graph.
    pub fn operand(&mut self, operand: &ast::Operand, op: &str) -> (Operand, Option<Const>) {
        let usage = Usage {
            role: Role::Operand,
            implied: implied(op),
        };
        let resolved = resolve::resolve_operand(&mut self.ctx, &mut self.scope, operand, usage);
        self.ctx.out.diags.clear();
        if let Some(slot) = self.slot.take() {
            match &resolved.target {
                Some(RTarget::Symbol(s)) => {
                    self.lw.names.operand_symbols.insert(slot, s.name.clone());
                }
                Some(RTarget::Constant(_)) => {
                    let text: String = operand
                        .syntax()
                        .text()
                        .to_string()
                        .chars()
                        .filter(|c| !c.is_whitespace())
                        .collect();
                    self.lw.names.literals.insert(slot, text);
                }
                _ => {}
            }
        }
        match resolved.target {
            Some(RTarget::Var(i)) => (Operand::Var(PREDEFS + i as VarIdx), None),
            Some(RTarget::Predefined(p)) => (
                predef_index(p.name).map_or(Operand::None, Operand::Var),
                None,
            ),
            Some(RTarget::Symbol(s)) => (
                s.address
                    .as_ref()
                    .and_then(values::place)
                    .map_or(Operand::None, Operand::Place),
                None,
            ),
            Some(RTarget::Address(a)) => (
                values::place(&a).map_or(Operand::None, Operand::Place),
                None,
            ),
            Some(RTarget::Constant(lit)) => match values::constant(&lit) {
                Some(c) => (c.imm(), Some(c)),
                None => (Operand::None, None),
            },
            None => (Operand::None, None),
        }
    }

    /// A time value (`wait`, `supervise`).
    fn time_value(&mut self, operand: &ast::Operand) -> Option<TimeValue> {
        if let ast::Operand::Literal(lit) = operand {
            let lit = higraph_syntax::literal::check_literal(&lit.text()).ok()?;
            return match lit.value {
                higraph_syntax::literal::LiteralValue::Duration { millis } => {
                    Some(TimeValue::Const(millis))
                }
                _ => None,
            };
        }
        let usage = Usage {
            role: Role::TimeValue,
            implied: None,
        };
        let resolved = resolve::resolve_operand(&mut self.ctx, &mut self.scope, operand, usage);
        self.ctx.out.diags.clear();
        if let (Some(RTarget::Symbol(s)), Some((number, supervise))) =
            (&resolved.target, self.time_slot.take())
        {
            let graph = self.lw.program.graphs.len() as u32;
            self.lw
                .names
                .time_symbols
                .insert((graph, number, supervise), s.name.clone());
        }
        let operand = match resolved.target? {
            RTarget::Var(i) => Operand::Var(PREDEFS + i as VarIdx),
            RTarget::Predefined(p) => Operand::Var(predef_index(p.name)?),
            RTarget::Symbol(s) => Operand::Place(values::place(s.address.as_ref()?)?),
            RTarget::Address(a) => Operand::Place(values::place(&a)?),
            RTarget::Constant(_) => return None,
        };
        Some(TimeValue::Operand(operand))
    }

    /// One instruction block.
    fn block(&mut self, block: &ast::Block) -> Block {
        let mut code = Vec::new();
        for stmt in block.statements() {
            if stmt.jump_label().is_some() {
                continue;
            }
            let Some(opcode_node) = stmt.opcode() else {
                continue;
            };
            let written = written_opcode(&opcode_node);
            let op = match lang::classify_op(&written, self.mnemonic) {
                OpClass::Subset(op) | OpClass::OtherSet { simatic: op, .. } => op,
                OpClass::Outside(_) | OpClass::Unknown => continue,
            };
            let range = crate::rules::stl::statement_range(&stmt)
                .unwrap_or_else(|| opcode_node.syntax().text_range());
            let origin = self.origin(range);
            let (operand, constant) = if op == "CALL" || op == "CC" {
                (self.call(&stmt, origin), None)
            } else {
                match stmt.operand() {
                    Some(operand) => {
                        self.slot = Some((origin, 0));
                        self.operand(&operand, &op)
                    }
                    None => (Operand::None, None),
                }
            };
            let Some(opcode) = opcode(&op, constant.as_ref()) else {
                continue;
            };
            let opcode = match (opcode, &operand) {
                (OpCode::O, Operand::None) => OpCode::OrNone,
                (opcode, _) => opcode,
            };
            code.push(Instr {
                op: opcode,
                operand,
                origin,
            });
        }
        Block { code }
    }

    /// The operand of `CALL`/`CC`: the block and its parameters.
    fn call(&mut self, stmt: &ast::StlStmt, origin: Origin) -> Operand {
        let Some(args) = stmt.call_args() else {
            return Operand::None;
        };
        let Some(target) = args.blocks().next() else {
            return Operand::None;
        };
        let Some(block) = self.lw.block_of_ref(&target, self.mnemonic) else {
            return Operand::None;
        };
        if let Some(idb) = args.blocks().nth(1) {
            let text = if let Some(address) = idb.address() {
                address.compact_text()
            } else if let Some(name) = idb.name_ref() {
                name.text()
            } else if let Some(symbol) = idb.symbol_ref() {
                symbol.name()
            } else {
                String::new()
            };
            self.lw.names.call_dbs.insert(origin, text);
        }
        let mut params = Vec::new();
        for param in args.params() {
            let Some(formal) = param.formal() else {
                continue;
            };
            let actual = match param.value() {
                Some(value) => {
                    self.slot = Some((origin, params.len() as u32 + 1));
                    self.operand(&value, "CALL").0
                }
                None => Operand::None,
            };
            params.push((formal.text(), actual));
        }
        Operand::Call(Box::new(Call { block, params }))
    }

    /// The blocks of a body, by label.
    fn labelled_blocks(&mut self, body: &ast::Body) -> Vec<(Option<String>, Block)> {
        body.body_items()
            .filter_map(|item| match item {
                ast::BodyItem::Block(block) => {
                    let label = block.label().map(|l| l.name());
                    Some((label, self.block(&block)))
                }
                _ => None,
            })
            .collect()
    }

    /// The whole graph.
    pub fn graph(&mut self, graph: &ast::Graph) -> (Graph, GraphMeta) {
        let db = self.lw.db;
        let mut meta = GraphMeta::default();
        let mut vars: Vec<VarInfo> = Predef::ALL
            .iter()
            .map(|p| VarInfo {
                name: p.name().to_owned(),
                ty: p.ty(),
                msg_in: None,
                init: (*p == Predef::StateChange).then_some(Value::Bool(true)),
            })
            .collect();
        for p in Predef::ALL {
            meta.vars.insert(crate::index::key(p.name()), p.var());
        }
        // Declarations: the scope's first declaration of each name, with msg kind and initial
        // value from its node.
        let mut decl_nodes: HashMap<String, ast::VarDecl> = HashMap::new();
        for (_, decl) in crate::rules::decls::declarations(graph.var_sections()) {
            if let Some(name) = decl.name() {
                decl_nodes
                    .entry(crate::index::key(&name.text()))
                    .or_insert(decl);
            }
        }
        for (i, var) in self.scope.vars.iter().enumerate() {
            let ty = var.ty.and_then(values::ty).unwrap_or(Ty::Bool);
            let decl = decl_nodes.get(&crate::index::key(&var.name));
            let msg_in = decl.and_then(|d| d.msg_kind()).map(|m| m.is_incoming());
            let init = decl
                .and_then(|d| d.initial_value())
                .and_then(|v| v.literal())
                .and_then(|l| higraph_syntax::literal::check_literal(&l.text()).ok())
                .and_then(|l| values::value_in(&l, ty));
            let idx = PREDEFS + i as VarIdx;
            meta.vars.insert(crate::index::key(&var.name), idx);
            meta.declared.push((var.name_range, var.section));
            vars.push(VarInfo {
                name: var.name.clone(),
                ty,
                msg_in,
                init,
            });
        }

        let mut out = Graph {
            name: graph.name().map(|n| n.text()).unwrap_or_default(),
            vars,
            states: Vec::new(),
            any: Vec::new(),
            startup: None,
            initial: None,
            permanent_pre: Vec::new(),
            permanent_post: Vec::new(),
        };

        // States (the first of each number, C3).
        let mut seen = std::collections::HashSet::new();
        let mut state_index: HashMap<u16, usize> = HashMap::new();
        let mut trans_nodes = Vec::new();
        for member in graph.members() {
            match member {
                ast::GraphMember::State(state) => {
                    let Some(number) = state.number().and_then(|n| {
                        crate::rules::graph::number_key(n.text())
                            .parse::<u16>()
                            .ok()
                    }) else {
                        continue;
                    };
                    if !seen.insert(number) {
                        continue;
                    }
                    let lowered = self.state(&state, number);
                    state_index.insert(number, out.states.len());
                    out.states.push(lowered);
                }
                ast::GraphMember::Trans(trans) => trans_nodes.push(trans),
                ast::GraphMember::Permanent(permanent) => {
                    if let Some(body) = permanent.body() {
                        for (label, block) in self.labelled_blocks(&body) {
                            match label.as_deref() {
                                Some("C-") => out.permanent_pre.push(block),
                                Some("C") => out.permanent_post.push(block),
                                _ => {}
                            }
                        }
                    }
                }
                _ => {}
            }
        }

        // Transitions with their effective priorities and startup flags from the graph model.
        let header = db::graph_header(db, self.item);
        let facts = db::graph_facts(db, self.item);
        let model = GraphModel::new(
            String::new(),
            facts.members(),
            header.as_ref().is_some_and(|h| h.declares_init_sd),
            crate::rules::graph::VirtualLayout::Virtual,
        );
        let mut any: Vec<(Trans, bool)> = Vec::new();
        let mut startup_target = None;
        for (node, entry) in trans_nodes.iter().zip(&model.transitions) {
            let Some(prio) = entry.priority.and_then(|p| u32::try_from(p).ok()) else {
                continue;
            };
            let from = match entry.source_end() {
                Some(crate::rules::graph::model::End::Any) => None,
                Some(crate::rules::graph::model::End::State(key)) => match key.parse::<u16>() {
                    Ok(n) if state_index.contains_key(&n) => Some(n),
                    _ => continue,
                },
                _ => continue,
            };
            let to = match entry.target_end() {
                Some(crate::rules::graph::model::End::Return) => Target::Return,
                Some(crate::rules::graph::model::End::State(key)) => match key.parse::<u16>() {
                    Ok(n) if state_index.contains_key(&n) => Target::State(n),
                    _ => continue,
                },
                _ => continue,
            };
            let trans = self.transition(node, from, to, prio);
            match from {
                None => {
                    if entry.startup
                        && startup_target.is_none()
                        && let Target::State(n) = to
                    {
                        startup_target = Some(n);
                    }
                    any.push((trans, entry.startup));
                }
                Some(n) => {
                    if let Some(&s) = state_index.get(&n) {
                        out.states[s].transitions.push(trans);
                    }
                }
            }
        }
        any.sort_by_key(|(t, _)| t.prio);
        out.startup = any.iter().position(|(_, startup)| *startup);
        out.initial = out.startup.and_then(|i| match any[i].0.to {
            Target::State(n) => Some(n),
            Target::Return => None,
        });
        out.any = any.into_iter().map(|(t, _)| t).collect();
        for state in &mut out.states {
            state.transitions.sort_by_key(|t| t.prio);
        }
        (out, meta)
    }

    fn state(&mut self, state: &ast::State, number: u16) -> State {
        let reports = state.attributes().any(|a| {
            a.keyword().is_some_and(|k| {
                matches!(k.text().to_ascii_lowercase().as_str(), "fault" | "message")
            })
        });
        let mut out = State {
            number,
            name: state.comment().map(|c| c.value()),
            reports,
            entry: Vec::new(),
            pre: Vec::new(),
            cyclic: Vec::new(),
            exit: Vec::new(),
            wait: None,
            supervise: None,
            transitions: Vec::new(),
        };
        let Some(body) = state.body() else {
            return out;
        };
        for item in body.body_items() {
            match item {
                ast::BodyItem::Block(block) => {
                    let label = block.label().map(|l| l.name());
                    let lowered = self.block(&block);
                    match label.as_deref() {
                        Some("E") => out.entry.push(lowered),
                        Some("C-") => out.pre.push(lowered),
                        Some("C") => out.cyclic.push(lowered),
                        Some("X") => out.exit.push(lowered),
                        _ => {}
                    }
                }
                ast::BodyItem::Wait(wait) => {
                    if out.wait.is_none() {
                        self.time_slot = Some((number, false));
                        out.wait = wait.value().and_then(|v| self.time_value(&v));
                    }
                }
                ast::BodyItem::Supervise(supervise) => {
                    if out.supervise.is_none() {
                        self.time_slot = Some((number, true));
                        out.supervise = supervise.value().and_then(|v| self.time_value(&v));
                    }
                }
            }
        }
        out
    }

    fn transition(
        &mut self,
        trans: &ast::Trans,
        from: Option<u16>,
        to: Target,
        prio: u32,
    ) -> Trans {
        let has = |word: &str| {
            trans.attributes().any(|a| {
                a.keyword()
                    .is_some_and(|k| k.text().eq_ignore_ascii_case(word))
            })
        };
        let range = trans
            .source()
            .map(|s| s.syntax().text_range())
            .zip(trans.target().map(|t| t.syntax().text_range()))
            .map_or_else(|| trans.syntax().text_range(), |(a, b)| a.cover(b));
        let origin = self.origin(range);
        let mut out = Trans {
            from,
            to,
            prio,
            auto: has("auto"),
            manual: has("manual"),
            waits: has("waits"),
            conditions: Vec::new(),
            actions: Vec::new(),
            origin,
        };
        if let Some(body) = trans.body() {
            for (label, block) in self.labelled_blocks(&body) {
                match label.as_deref() {
                    // An empty unlabelled run is no block.
                    None if block.code.is_empty() => {}
                    None | Some("?") => out.conditions.push(block),
                    Some("!") => out.actions.push(block),
                    _ => {}
                }
            }
        }
        out
    }
}

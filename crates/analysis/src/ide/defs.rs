//! What a name refers to ([`definition_at`]) and every place that refers to it
//! ([`references`]), the core of go to definition, find references, highlights, rename and
//! hover.
//!
//! [`item_uses`] is a salsa query per item: every name reference of the item — STL operands,
//! time values, CALL targets and parameters, `activate` lists, transition endpoints,
//! `instance X : Graph`, both sides of actual parameters, `Inst.Msg`, `fc`/`db` names, chart
//! operands and jump/loop targets — resolved by the rules' own resolution
//! ([`crate::resolve`] in graphs, the actual-value resolution of groups, the chart operand
//! resolution), with its access kind (Appendix E) and a range relative to the item. A `test`
//! item's uses are its `run` and `command` entries and every segment of its test paths that
//! names a declaration of another item (`UseTarget::Def`), found by the test path resolver
//! (`lower/paths.rs`), so references, rename and hover reach into tests. Like the
//! rules' results it is position-independent, so an edit in one item leaves the uses of the
//! others cached, and a workspace-wide search only filters cached vectors.

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode, EndpointKind},
    rowan::TokenAtOffset,
};

use crate::{
    address::Address,
    db::{self, File, ItemKind, ItemLoc, Workspace},
    index::{self, GlobalIndex, SymbolSource},
    lang::{self, Section},
    resolve::{self, GraphScope, Role, Target, Usage},
    rules::{
        Ctx,
        chart::{
            ChartInfo, Scope,
            operands::{self, Unresolved},
        },
        group::{
            actuals::{self, Value},
            interface::{MsgDir, PREDEFINED_FORMALS, graph_interface},
        },
        stl::{self, Access},
    },
};

use super::SymbolKind;
use crate::lower::SegmentDef;

// ------------------------------------------------------------------------------ public model

/// A top-level item: its file and its position among the file's items.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ItemId {
    /// The file that holds the item.
    pub file: File,
    /// The item's position among the file's items (as in [`ItemLoc`]).
    pub index: u32,
}

impl ItemId {
    fn loc<'db>(self, db: &'db dyn salsa::Database) -> ItemLoc<'db> {
        ItemLoc::new(db, self.file, self.index)
    }
}

/// The salsa handle of an item.
pub(crate) fn item_loc<'db>(db: &'db dyn salsa::Database, item: ItemId) -> ItemLoc<'db> {
    item.loc(db)
}

/// Something a name can be declared as.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Definition {
    Graph(ItemId),
    Group(ItemId),
    Chart(ItemId),
    /// A `block` interface item.
    BlockInterface(ItemId),
    /// A global symbol (declared or imported): its position in [`GlobalIndex::symbols`].
    Symbol(usize),
    /// A variable of a graph, chart or block interface, by its declared name.
    Variable {
        owner: ItemId,
        name: String,
    },
    /// A predefined variable of a graph.
    Predefined {
        graph: ItemId,
        name: &'static str,
    },
    /// An instance of a group, by its declared name.
    Instance {
        group: ItemId,
        name: String,
    },
    /// A state of a graph, by number.
    State {
        graph: ItemId,
        number: u32,
    },
    Sequencer {
        chart: ItemId,
        name: String,
    },
    /// A step of a sequencer.
    Step {
        chart: ItemId,
        sequencer: String,
        name: String,
    },
    /// A chart transition, jump or loop.
    ChartTransition {
        chart: ItemId,
        sequencer: String,
        name: String,
    },
    /// An `action` of an IEC chart (`docs/iec.md` §6).
    Action {
        chart: ItemId,
        name: String,
    },
}

/// How a reference uses its definition (Appendix E access kinds, plus the declaration and
/// uses that are no access at all).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReferenceKind {
    /// The declaration itself.
    Declaration,
    Read,
    Write,
    /// Read and written (`FP`, timer and counter starts, `in_out` actuals).
    ReadWrite,
    /// A CALL actual whose callee's interface is unknown.
    Unknown,
    /// A use by name that is no access: a transition endpoint, `instance X : G`, a formal in
    /// an actual, an `Inst.` prefix, a jump target, an `activate` entry, a CALL target.
    Name,
}

impl ReferenceKind {
    fn of_access(access: Access) -> ReferenceKind {
        match access {
            Access::Read => ReferenceKind::Read,
            Access::Write => ReferenceKind::Write,
            Access::ReadWrite => ReferenceKind::ReadWrite,
            Access::Unknown => ReferenceKind::Unknown,
        }
    }
}

/// One reference to a definition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Reference {
    pub file: File,
    /// The name only: without `#`, and without the quotes of a quoted symbol.
    pub range: TextRange,
    pub kind: ReferenceKind,
    /// Written as a quoted string (`"Name"`).
    pub quoted: bool,
}

/// Where a definition is declared.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Declaration {
    pub file: File,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The name (without the quotes of a quoted symbol).
    pub focus_range: TextRange,
    /// The name as declared.
    pub name: String,
    pub kind: SymbolKind,
    /// The name is a quoted string.
    pub quoted: bool,
}

/// The name under a position and what it refers to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NameAt {
    pub definition: Definition,
    /// The name under the position (absolute; without `#` or quotes).
    pub range: TextRange,
}

// ------------------------------------------------------------------------------ uses per item

/// What a use inside an item refers to. Names are the declared spellings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum UseTarget {
    /// A variable declared in this graph or chart.
    Var(String),
    /// A predefined variable of this graph.
    Predefined(&'static str),
    /// A global symbol (position in [`GlobalIndex::symbols`]).
    Symbol(usize),
    /// `instance X : G`: the graph.
    Graph(ItemId),
    /// The formal side of an actual, or the message of `Inst.Msg`: a variable of a graph.
    Formal { graph: ItemId, name: String },
    /// A predefined formal (`ManualMode := ...`).
    PredefinedFormal { graph: ItemId, name: &'static str },
    /// An instance of this group (`Inst.` of a message target).
    Instance(String),
    /// A state of this graph (a transition endpoint).
    State(u32),
    /// A step of this chart (a jump or loop target, `Step.X`/`Step.T` in an IEC chart).
    Step { sequencer: String, name: String },
    /// An action of this chart (a qualifier's operand).
    Action(String),
    /// The interface of a CALL's callee.
    BlockInterface(ItemId),
    /// A formal parameter of a CALL whose callee's interface is declared.
    InterfaceParam { interface: ItemId, name: String },
    /// An absolute address (for hover; no definition).
    Address(Address),
    /// A name of a test (a path segment, a `run` or `command` entry): a definition of
    /// another item, found by the test path resolver (`lower/paths.rs`).
    Def(Definition),
}

/// One use of a name inside an item.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct NameUse {
    /// The name (without `#` or quotes; an address: the whole operand), relative to the item.
    pub range: TextRange,
    pub target: UseTarget,
    pub kind: ReferenceKind,
    /// Written as a quoted string.
    pub quoted: bool,
}

/// Every use of a name in one item, in text order of the walk.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct ItemUses {
    pub uses: Vec<NameUse>,
}

/// The uses of names in one item (ranges relative to the item).
#[salsa::tracked(returns(ref))]
pub(crate) fn item_uses<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> ItemUses {
    let Some(root) = db::item_root(db, item) else {
        return ItemUses::default();
    };
    let mut walker = Walker {
        ctx: Ctx::for_item(db, ws, item),
        uses: Vec::new(),
    };
    match ast::Item::cast(root) {
        Some(ast::Item::Graph(graph)) => walker.graph(&graph),
        Some(ast::Item::Group(group)) => walker.group(&group),
        Some(ast::Item::Chart(chart)) => walker.chart(&chart),
        Some(ast::Item::BlockInterface(interface)) => {
            if let Some(block) = interface.block() {
                walker.block_ref(&block);
            }
        }
        Some(ast::Item::Test(test)) => walker.uses = test_uses(db, ws, item.file(db), &test),
        Some(ast::Item::Symbols(_) | ast::Item::Mnemonic(_)) | None => {}
    }
    ItemUses { uses: walker.uses }
}

// ------------------------------------------------------------------------------ tests

/// The uses of a `test` item: its `run` entries, the chart of each `command`, and every
/// segment of its test paths that names a declaration, resolved by the test path resolver
/// (`lower/paths.rs`, the one the lowering and HG91xx use). A `set` target is written, the
/// last segment of another path read, the leading segments (group, instance, chart,
/// sequencer) are named.
fn test_uses(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    test: &ast::Test,
) -> Vec<NameUse> {
    let index = db::global_index(db, ws);
    let mut uses = Vec::new();
    let entry = |name: ast::NameRef, uses: &mut Vec<NameUse>| {
        let Some(item) = index.item(&name.text()) else {
            return;
        };
        let id = ItemId {
            file: item.file,
            index: item.item,
        };
        let definition = match item.kind {
            ItemKind::Group => Definition::Group(id),
            ItemKind::Chart => Definition::Chart(id),
            _ => return,
        };
        uses.push(NameUse {
            range: name.syntax().text_range(),
            target: UseTarget::Def(definition),
            kind: ReferenceKind::Name,
            quoted: false,
        });
    };
    for stmt in test.statements() {
        match stmt {
            ast::TestStmt::Run(run) => run.entries().for_each(|e| entry(e, &mut uses)),
            ast::TestStmt::Command(command) => {
                if let Some(chart) = command.chart() {
                    entry(chart, &mut uses);
                }
            }
            _ => {}
        }
    }
    let paths = crate::lower::test_item_paths(db, ws, file, test);
    // The workspace's files by path, built once: segments name their declarations by path.
    let files: std::collections::HashMap<&str, File> = if paths.is_empty() {
        std::collections::HashMap::new()
    } else {
        ws.files(db)
            .iter()
            .map(|f| (f.path(db).as_str(), *f))
            .collect()
    };
    for (path, segments) in paths {
        let written = path
            .syntax()
            .parent()
            .and_then(ast::TestSet::cast)
            .and_then(|set| set.target())
            .is_some_and(|target| target.syntax() == path.syntax());
        let last = segments.len().saturating_sub(1);
        let mut previous: Option<Definition> = None;
        for (i, (range, segment)) in segments.iter().enumerate() {
            let definition = segment_definition(db, ws, &files, segment, previous.as_ref());
            let kind = match (i == last, written) {
                (false, _) => ReferenceKind::Name,
                (true, true) => ReferenceKind::Write,
                (true, false) => ReferenceKind::Read,
            };
            if let Some(definition) = &definition {
                // A quoted first segment: the name without its quotes.
                let text = path
                    .syntax()
                    .text()
                    .slice(*range - path.syntax().text_range().start())
                    .to_string();
                let quoted = text.len() >= 2 && text.starts_with('"') && text.ends_with('"');
                let range = if quoted {
                    TextRange::new(
                        range.start() + TextSize::from(1),
                        range.end() - TextSize::from(1),
                    )
                } else {
                    *range
                };
                uses.push(NameUse {
                    range,
                    target: UseTarget::Def(definition.clone()),
                    kind,
                    quoted,
                });
            }
            previous = definition;
        }
    }
    uses.sort_by_key(|u| u.range.start());
    uses
}

/// The definition a test path segment names (`previous`: what the segment before names, for
/// a predefined variable of an instance's graph). Members (`state`, `.T`, block formals) and
/// addresses name none.
fn segment_definition(
    db: &dyn salsa::Database,
    ws: Workspace,
    files: &std::collections::HashMap<&str, File>,
    segment: &SegmentDef,
    previous: Option<&Definition>,
) -> Option<Definition> {
    let index = db::global_index(db, ws);
    match segment {
        SegmentDef::Symbol { name } | SegmentDef::Block { name } => {
            index.symbol_position(name).map(Definition::Symbol)
        }
        SegmentDef::Predefined { name } => {
            let Some(Definition::Instance {
                group,
                name: instance,
            }) = previous
            else {
                return None;
            };
            let root = db::item_root(db, group.loc(db)).and_then(ast::Group::cast)?;
            let node = root.instances().find(|i| {
                i.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(instance))
            })?;
            let graph = index.graph(&node.graph()?.text())?;
            Some(Definition::Predefined {
                graph: ItemId {
                    file: graph.file,
                    index: graph.item,
                },
                name,
            })
        }
        SegmentDef::Group { file, range }
        | SegmentDef::Instance { file, range }
        | SegmentDef::GraphVariable { file, range }
        | SegmentDef::Chart { file, range }
        | SegmentDef::ChartVariable { file, range }
        | SegmentDef::Sequencer { file, range }
        | SegmentDef::Step { file, range } => {
            // The declaration's name: what a cursor on it refers to.
            let file = *files.get(file.as_str())?;
            let offsets = db::item_offsets(db, file);
            let at = offsets.partition_point(|start| *start <= range.start());
            let item = ItemId {
                file,
                index: u32::try_from(at.checked_sub(1)?).ok()?,
            };
            let start = item_start(db, item);
            let root = db::item_root(db, item.loc(db))?;
            let token = root
                .token_at_offset(range.start().checked_sub(start)?)
                .right_biased()?;
            declared_at(db, ws, item, &token).map(|n| n.definition)
        }
        SegmentDef::Address | SegmentDef::Member => None,
    }
}

/// Walks one item, resolving names with a throw-away rule context (the diagnostics the
/// resolution reports are dropped).
struct Walker<'a> {
    ctx: Ctx<'a>,
    uses: Vec<NameUse>,
}

impl<'a> Walker<'a> {
    fn push(&mut self, range: TextRange, target: UseTarget, kind: ReferenceKind, quoted: bool) {
        self.uses.push(NameUse {
            range,
            target,
            kind,
            quoted,
        });
    }

    // -------------------------------------------------------------------------- graphs

    fn graph(&mut self, graph: &ast::Graph) {
        let mut scope = GraphScope::new(graph);
        for member in graph.members() {
            match member {
                ast::GraphMember::Activate(activate) => {
                    for name in activate.names() {
                        if let (Some(token), Some(p)) =
                            (name.token(), lang::predefined(&name.text()))
                        {
                            let target = UseTarget::Predefined(p.name);
                            self.push(token.text_range(), target, ReferenceKind::Name, false);
                        }
                    }
                }
                ast::GraphMember::State(state) => {
                    if let Some(body) = state.body() {
                        self.graph_body(&mut scope, &body);
                    }
                }
                ast::GraphMember::Trans(trans) => {
                    for endpoint in [trans.source(), trans.target()].into_iter().flatten() {
                        self.endpoint(&endpoint);
                    }
                    if let Some(body) = trans.body() {
                        self.graph_body(&mut scope, &body);
                    }
                }
                ast::GraphMember::Permanent(permanent) => {
                    if let Some(body) = permanent.body() {
                        self.graph_body(&mut scope, &body);
                    }
                }
                ast::GraphMember::VarSection(_) => {}
            }
        }
    }

    fn endpoint(&mut self, endpoint: &ast::Endpoint) {
        if endpoint.kind() != Some(EndpointKind::State) {
            return;
        }
        let Some(token) = endpoint.token() else {
            return;
        };
        if let Ok(number) = token.text().parse::<u32>() {
            let target = UseTarget::State(number);
            self.push(token.text_range(), target, ReferenceKind::Name, false);
        }
    }

    fn graph_body(&mut self, scope: &mut GraphScope, body: &ast::Body) {
        for item in body.body_items() {
            match item {
                ast::BodyItem::Block(block) => {
                    for stmt in block.statements() {
                        self.statement(scope, &stmt);
                        self.ctx.out.diags.clear();
                    }
                }
                ast::BodyItem::Wait(wait) => {
                    if let Some(value) = wait.value() {
                        self.time_value(scope, &value);
                    }
                }
                ast::BodyItem::Supervise(supervise) => {
                    if let Some(value) = supervise.value() {
                        self.time_value(scope, &value);
                    }
                }
            }
        }
    }

    fn time_value(&mut self, scope: &mut GraphScope, value: &ast::Operand) {
        let usage = Usage {
            role: Role::TimeValue,
            implied: None,
        };
        self.graph_operand(scope, value, usage, |_| ReferenceKind::Read);
        self.ctx.out.diags.clear();
    }

    fn statement(&mut self, scope: &mut GraphScope, stmt: &ast::StlStmt) {
        let Some(opcode) = stmt.opcode() else {
            return;
        };
        // Operations outside the subset and unknown ones are not analysed (C4), so their
        // operands are no uses either.
        let op = match lang::classify_op(&opcode.text(), self.ctx.mnemonic) {
            lang::OpClass::Subset(op) => op,
            lang::OpClass::OtherSet { simatic, .. } => simatic,
            lang::OpClass::Outside(_) | lang::OpClass::Unknown => return,
        };
        if op == "CALL" || op == "CC" {
            self.call(scope, stmt);
            return;
        }
        if let Some(operand) = stmt.operand() {
            let usage = Usage {
                role: Role::Operand,
                implied: None,
            };
            self.graph_operand(scope, &operand, usage, |ty| {
                ReferenceKind::of_access(stl::operand_access(&op, ty))
            });
        }
    }

    /// Resolves a graph operand (§2.4) and records what it names.
    fn graph_operand(
        &mut self,
        scope: &mut GraphScope,
        operand: &ast::Operand,
        usage: Usage,
        kind: impl FnOnce(Option<lang::Type>) -> ReferenceKind,
    ) {
        let resolved = resolve::resolve_operand(&mut self.ctx, scope, operand, usage);
        let kind = kind(resolved.ty);
        let target = match resolved.target {
            Some(Target::Var(var)) => match scope.vars.get(var) {
                Some(var) => UseTarget::Var(var.name.clone()),
                None => return,
            },
            Some(Target::Predefined(p)) => UseTarget::Predefined(p.name),
            Some(Target::Symbol(symbol)) => match self.ctx.index.symbol_position(&symbol.name) {
                Some(position) => UseTarget::Symbol(position),
                None => return,
            },
            Some(Target::Address(address)) => {
                self.push(resolved.range, UseTarget::Address(address), kind, false);
                return;
            }
            Some(Target::Constant(_)) | None => return,
        };
        if let Some((range, quoted)) = reference_range(operand) {
            self.push(range, target, kind, quoted);
        }
    }

    /// `CALL` / `CC`: the callee (a symbol, and its interface if declared), the instance DB
    /// and the parameters.
    fn call(&mut self, scope: &mut GraphScope, stmt: &ast::StlStmt) {
        let Some(args) = stmt.call_args() else {
            return;
        };
        let mut blocks = args.blocks();
        let interface = blocks.next().and_then(|callee| {
            let target = self.block_ref(&callee);
            let interface = self.interface_of(&target)?;
            let range = target
                .symbol
                .map_or(callee.syntax().text_range(), |(_, r, _)| r);
            let use_target = UseTarget::BlockInterface(interface);
            self.push(range, use_target, ReferenceKind::Name, false);
            Some(interface)
        });
        for instance_db in blocks {
            self.block_ref(&instance_db);
        }
        let formals = interface
            .map(|i| interface_vars(self.ctx.db, i))
            .unwrap_or_default();
        for param in args.params() {
            let formal = param.formal().and_then(|f| {
                let token = f.token()?;
                let formal = formals
                    .iter()
                    .find(|(name, _)| name.eq_ignore_ascii_case(token.text()))?;
                Some((token, formal.clone()))
            });
            let access = match (&interface, &formal) {
                (Some(interface), Some((token, (name, section)))) => {
                    let target = UseTarget::InterfaceParam {
                        interface: *interface,
                        name: name.clone(),
                    };
                    self.push(token.text_range(), target, ReferenceKind::Name, false);
                    match section {
                        Section::In => ReferenceKind::Read,
                        Section::Out => ReferenceKind::Write,
                        Section::InOut | Section::Stat => ReferenceKind::ReadWrite,
                    }
                }
                _ => ReferenceKind::Unknown,
            };
            if let Some(value) = param.value() {
                let usage = Usage {
                    role: Role::Operand,
                    implied: None,
                };
                self.graph_operand(scope, &value, usage, |_| access);
            }
        }
    }

    /// A block reference (CALL target, instance DB, `fc`/`db` name, `block` item): records
    /// the symbol it names and returns what it denotes.
    fn block_ref(&mut self, block: &ast::BlockRef) -> BlockTarget {
        let index = self.ctx.index;
        let mnemonic = self.ctx.mnemonic;
        let mut target = BlockTarget::default();
        if let Some(address) = block.address() {
            target.address = index::read_address(&address.compact_text(), mnemonic);
            return target;
        }
        let (name, range, quoted) = if let Some(name_ref) = block.name_ref() {
            let Some(token) = name_ref.token() else {
                return target;
            };
            if let Some(read) = resolve::address_without_space(token.text(), mnemonic) {
                target.address = read.address.ok();
                return target;
            }
            (token.text().to_owned(), token.text_range(), false)
        } else if let Some(symbol_ref) = block.symbol_ref() {
            let Some(token) = symbol_ref.token() else {
                return target;
            };
            (symbol_ref.name(), resolve::string_inner_range(&token), true)
        } else {
            return target;
        };
        target.name = Some(name.clone());
        if let Some(position) = index.symbol_position(&name) {
            target.address = index.symbols[position].address.clone();
            target.symbol = Some((position, range, quoted));
            self.push(
                range,
                UseTarget::Symbol(position),
                ReferenceKind::Name,
                quoted,
            );
        }
        target
    }

    /// The declared interface of a callee (the first `block` item naming it), matched like the
    /// CALL rules do: by block address, else by symbol name.
    fn interface_of(&self, callee: &BlockTarget) -> Option<ItemId> {
        let index = self.ctx.index;
        let entry = index.block_interfaces.iter().find(|entry| {
            let (address, name) = interface_target(index, self.ctx.mnemonic, &entry.reference);
            match (&callee.address, address) {
                (Some(a), Some(b)) => *a == b,
                _ => {
                    matches!((&callee.name, name), (Some(a), Some(b)) if a.eq_ignore_ascii_case(&b))
                }
            }
        })?;
        Some(ItemId {
            file: entry.file,
            index: entry.item,
        })
    }

    // -------------------------------------------------------------------------- groups

    fn group(&mut self, group: &ast::Group) {
        for clause in [group.fc(), group.db()].into_iter().flatten() {
            self.block_ref(&clause);
        }
        let db = self.ctx.db;
        let index = self.ctx.index;
        // The graph of each instance name (the first instance of a name counts, C3).
        let mut instances: Vec<(String, Option<ItemId>)> = Vec::new();
        for instance in group.instances() {
            let Some(name) = instance.name().map(|n| n.text()) else {
                continue;
            };
            if instances.iter().any(|(n, _)| n.eq_ignore_ascii_case(&name)) {
                continue;
            }
            let graph = instance
                .graph()
                .and_then(|g| index.graph(&g.text()))
                .map(|g| ItemId {
                    file: g.file,
                    index: g.item,
                });
            instances.push((name, graph));
        }
        for instance in group.instances() {
            let graph_ref = instance.graph();
            let graph = graph_ref
                .as_ref()
                .and_then(|g| index.graph(&g.text()))
                .map(|g| ItemId {
                    file: g.file,
                    index: g.item,
                });
            if let (Some(graph), Some(token)) = (graph, graph_ref.and_then(|g| g.token())) {
                self.push(
                    token.text_range(),
                    UseTarget::Graph(graph),
                    ReferenceKind::Name,
                    false,
                );
            }
            for actual in instance.actuals() {
                let value_kind = match (graph, actual.formal().and_then(|f| f.token())) {
                    (Some(graph), Some(token)) => self.formal(db, graph, &token),
                    _ => ReferenceKind::Unknown,
                };
                if let Some(value) = actual.value() {
                    self.actual_value(&instances, &value, value_kind);
                }
                self.ctx.out.diags.clear();
            }
        }
    }

    /// The formal side of an actual: records the variable and returns the access of the value.
    fn formal(
        &mut self,
        db: &dyn salsa::Database,
        graph: ItemId,
        token: &SyntaxToken,
    ) -> ReferenceKind {
        let interface = graph_interface(db, graph.loc(db));
        let range = token.text_range();
        if let Some(var) = interface.var(token.text()) {
            let target = UseTarget::Formal {
                graph,
                name: var.name.clone(),
            };
            self.push(range, target, ReferenceKind::Name, false);
            return match (var.message(), var.section) {
                (Some(MsgDir::Incoming), _) | (None, Section::In) => ReferenceKind::Read,
                (Some(MsgDir::Outgoing), _) | (None, Section::Out) => ReferenceKind::Write,
                (None, Section::InOut) => ReferenceKind::ReadWrite,
                (None, Section::Stat) => ReferenceKind::Unknown,
            };
        }
        let predefined = PREDEFINED_FORMALS
            .iter()
            .find(|p| p.eq_ignore_ascii_case(token.text()))
            .and_then(|p| lang::predefined(p));
        match predefined {
            Some(p) => {
                let target = UseTarget::PredefinedFormal {
                    graph,
                    name: p.name,
                };
                self.push(range, target, ReferenceKind::Name, false);
                ReferenceKind::Read
            }
            None => ReferenceKind::Unknown,
        }
    }

    /// The value side of an actual: a message target, a symbol or an address.
    fn actual_value(
        &mut self,
        instances: &[(String, Option<ItemId>)],
        value: &ast::Operand,
        kind: ReferenceKind,
    ) {
        if let ast::Operand::MessageTarget(target) = value {
            self.message_target(instances, target);
            return;
        }
        match actuals::resolve(&mut self.ctx, value) {
            Value::Symbol(symbol) => {
                let position = self.ctx.index.symbol_position(&symbol.name);
                if let (Some(position), Some((range, quoted))) = (position, reference_range(value))
                {
                    self.push(range, UseTarget::Symbol(position), kind, quoted);
                }
            }
            Value::Address(address) => {
                let range = value.syntax().text_range();
                self.push(range, UseTarget::Address(address), kind, false);
            }
            Value::Constant(_) | Value::Message | Value::Unknown => {}
        }
    }

    /// `Inst.Msg`: the instance, and the incoming message of its graph (which the sender
    /// writes).
    fn message_target(
        &mut self,
        instances: &[(String, Option<ItemId>)],
        target: &ast::MessageTarget,
    ) {
        let Some(inst_token) = target.instance().and_then(|i| i.token()) else {
            return;
        };
        let Some((name, graph)) = instances
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(inst_token.text()))
        else {
            return;
        };
        let use_target = UseTarget::Instance(name.clone());
        self.push(
            inst_token.text_range(),
            use_target,
            ReferenceKind::Name,
            false,
        );
        let (Some(graph), Some(msg_token)) = (graph, target.message().and_then(|m| m.token()))
        else {
            return;
        };
        let db = self.ctx.db;
        let interface = graph_interface(db, graph.loc(db));
        let range = msg_token.text_range();
        if let Some(var) = interface.var(msg_token.text()) {
            let use_target = UseTarget::Formal {
                graph: *graph,
                name: var.name.clone(),
            };
            self.push(range, use_target, ReferenceKind::Write, false);
        } else if let Some(p) = lang::predefined(msg_token.text()) {
            let use_target = UseTarget::PredefinedFormal {
                graph: *graph,
                name: p.name,
            };
            self.push(range, use_target, ReferenceKind::Write, false);
        }
    }

    // -------------------------------------------------------------------------- charts

    fn chart(&mut self, chart: &ast::Chart) {
        let info = ChartInfo {
            name: chart.name().map(|n| n.text()).unwrap_or_default(),
            is_type: chart.is_type(),
            chart: chart.clone(),
        };
        let vars = crate::rules::chart::decls::declare(&mut self.ctx, &info);
        let mut scope = Scope::new(info, vars);
        for path in chart.syntax().descendants().filter_map(ast::Path::cast) {
            self.chart_path(&mut scope, &path);
            self.ctx.out.diags.clear();
        }
        // The block named by a function block call is a use of its instance.
        for call in chart.syntax().descendants().filter_map(ast::FbCall::cast) {
            let Some(token) = call.callee().and_then(|c| c.token()) else {
                continue;
            };
            if let Some(var) = scope.var(token.text()).and_then(|i| scope.vars.get(i)) {
                let target = UseTarget::Var(var.name.clone());
                self.push(token.text_range(), target, ReferenceKind::ReadWrite, false);
            }
        }
        for sequencer in chart.sequencers() {
            self.jump_targets(&sequencer);
        }
    }

    /// `Step.X` / `Step.T` (IEC charts): the step; the sequencer holding a step of that name.
    fn step_flag(&mut self, chart: &ast::Chart, path: &ast::Path) {
        let Some(token) = path.segments().next().and_then(|s| s.token()) else {
            return;
        };
        for sequencer in chart.sequencers() {
            let Some(sequencer_name) = sequencer.name().map(|n| n.text()) else {
                continue;
            };
            if let Some(step) = step_names(&sequencer)
                .into_iter()
                .find(|s| s.eq_ignore_ascii_case(token.text()))
            {
                let target = UseTarget::Step {
                    sequencer: sequencer_name,
                    name: step,
                };
                self.push(token.text_range(), target, ReferenceKind::Read, false);
                return;
            }
        }
    }

    fn chart_path(&mut self, scope: &mut Scope, path: &ast::Path) {
        let target = operands::resolve(&mut self.ctx, scope, path, Unresolved::Operand, false);
        let kind = if is_written_path(path) {
            ReferenceKind::Write
        } else {
            ReferenceKind::Read
        };
        let (target, quoted) = match target {
            operands::Target::Var(i)
            | operands::Target::Iec(operands::IecTarget::FbMember { var: i, .. }) => {
                match scope.vars.get(i) {
                    Some(var) => (UseTarget::Var(var.name.clone()), false),
                    None => return,
                }
            }
            operands::Target::Iec(operands::IecTarget::StepFlag { .. }) => {
                let chart = scope.chart.chart.clone();
                self.step_flag(&chart, path);
                return;
            }
            operands::Target::Unresolved if is_qualifier_operand(path) => {
                let Some(token) = path.segments().next().and_then(|s| s.token()) else {
                    return;
                };
                if let Some(action) = scope
                    .action(token.text())
                    .and_then(|i| scope.actions.get(i))
                {
                    let target = UseTarget::Action(action.name.clone());
                    self.push(token.text_range(), target, ReferenceKind::Name, false);
                }
                return;
            }
            operands::Target::Symbol { name, .. } => match self.ctx.index.symbol_position(&name) {
                Some(position) => (UseTarget::Symbol(position), path.symbol().is_some()),
                None => return,
            },
            operands::Target::Address(Some(address)) => {
                let range = path.syntax().text_range();
                self.push(range, UseTarget::Address(address), kind, false);
                return;
            }
            _ => return,
        };
        let range = if let Some(symbol) = path.symbol() {
            symbol.token().map(|t| resolve::string_inner_range(&t))
        } else {
            path.segments()
                .next()
                .and_then(|s| s.token())
                .map(|t| t.text_range())
        };
        if let Some(range) = range {
            self.push(range, target, kind, quoted);
        }
    }

    /// Jump and loop targets: steps of the same sequencer (at any nesting level).
    fn jump_targets(&mut self, sequencer: &ast::Sequencer) {
        let Some(sequencer_name) = sequencer.name().map(|n| n.text()) else {
            return;
        };
        let steps = step_names(sequencer);
        for node in sequencer.syntax().descendants() {
            let target = match node.kind() {
                SyntaxKind::JUMP => ast::Jump::cast(node).and_then(|j| j.target()),
                SyntaxKind::LOOP => ast::Loop::cast(node).and_then(|l| l.target()),
                _ => None,
            };
            let Some(token) = target.and_then(|t| t.token()) else {
                continue;
            };
            if let Some(step) = steps.iter().find(|s| s.eq_ignore_ascii_case(token.text())) {
                let use_target = UseTarget::Step {
                    sequencer: sequencer_name.clone(),
                    name: step.clone(),
                };
                self.push(token.text_range(), use_target, ReferenceKind::Name, false);
            }
        }
    }
}

/// What a block reference denotes.
#[derive(Debug, Default)]
struct BlockTarget {
    /// The block address (absolute, or the symbol's).
    address: Option<Address>,
    /// The name as written (symbolic references).
    name: Option<String>,
    /// The symbol: its position, the reference's range and whether it is quoted.
    symbol: Option<(usize, TextRange, bool)>,
}

/// What a `block` item's reference names: a block address and/or a symbol name (as the CALL
/// rules read it).
pub(crate) fn interface_target(
    index: &GlobalIndex,
    mnemonic: lang::Mnemonic,
    reference: &str,
) -> (Option<Address>, Option<String>) {
    let trimmed = reference.trim();
    if trimmed.starts_with('"') {
        let name = ast::unquote(trimmed).to_owned();
        let address = index.symbol(&name).and_then(|s| s.address.clone());
        return (address, Some(name));
    }
    if let Some(address) =
        index::read_address(trimmed, mnemonic).filter(|a| a.block_kind().is_some())
    {
        return (Some(address), None);
    }
    let address = index.symbol(trimmed).and_then(|s| s.address.clone());
    (address, Some(trimmed.to_owned()))
}

/// The parameters (`in`, `out`, `in_out`) of a `block` interface: declared name and section.
fn interface_vars(db: &dyn salsa::Database, interface: ItemId) -> Vec<(String, Section)> {
    let Some(node) = db::item_root(db, interface.loc(db)).and_then(ast::BlockInterface::cast)
    else {
        return Vec::new();
    };
    let mut vars: Vec<(String, Section)> = Vec::new();
    for section in node.var_sections() {
        let Some(kind) = section
            .keyword()
            .and_then(|k| Section::from_keyword(k.text()))
        else {
            continue;
        };
        if kind == Section::Stat {
            continue;
        }
        for decl in section.decls() {
            let Some(name) = decl.name().map(|n| n.text()) else {
                continue;
            };
            if !vars.iter().any(|(n, _)| n.eq_ignore_ascii_case(&name)) {
                vars.push((name, kind));
            }
        }
    }
    vars
}

/// The range of the name an operand refers to by name (`Name`, `#Name` without `#`,
/// `"Name"` without quotes), and whether it is quoted.
fn reference_range(operand: &ast::Operand) -> Option<(TextRange, bool)> {
    match operand {
        ast::Operand::VarRef(var) => var.name().map(|t| (t.text_range(), false)),
        ast::Operand::NameRef(name) => name.token().map(|t| (t.text_range(), false)),
        ast::Operand::SymbolRef(symbol) => symbol
            .token()
            .map(|t| (resolve::string_inner_range(&t), true)),
        _ => None,
    }
}

/// Is the path the operand of a qualifier action?
fn is_qualifier_operand(path: &ast::Path) -> bool {
    path.syntax()
        .parent()
        .is_some_and(|p| p.kind() == SyntaxKind::QUALIFIER_ACTION)
}

/// Is a chart path written: an assignment target, the operand of a qualifier action, or the
/// target of a call's output (`Q => Path`)?
fn is_written_path(path: &ast::Path) -> bool {
    let Some(parent) = path.syntax().parent() else {
        return false;
    };
    if let Some(arg) = ast::FbArg::cast(parent.clone()) {
        return arg.is_output();
    }
    let first_path = parent.children().find(|n| n.kind() == SyntaxKind::PATH);
    matches!(
        parent.kind(),
        SyntaxKind::ASSIGNMENT | SyntaxKind::QUALIFIER_ACTION
    ) && first_path.as_ref() == Some(path.syntax())
}

/// The step names of a sequencer at every nesting level, first of each name.
fn step_names(sequencer: &ast::Sequencer) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for step in sequencer.syntax().descendants().filter_map(ast::Step::cast) {
        if let Some(name) = step.name().map(|n| n.text())
            && !names.iter().any(|n| n.eq_ignore_ascii_case(&name))
        {
            names.push(name);
        }
    }
    names
}

// ------------------------------------------------------------------------------ positions

/// The token at `offset`, preferring a name, number or string over punctuation.
pub(crate) fn token_at(root: &SyntaxNode, offset: TextSize) -> Option<SyntaxToken> {
    if offset > root.text_range().end() {
        return None;
    }
    let rank = |t: &SyntaxToken| match t.kind() {
        SyntaxKind::IDENT | SyntaxKind::NUMBER | SyntaxKind::STRING => 0,
        k if k.is_trivia() => 2,
        _ => 1,
    };
    match root.token_at_offset(offset) {
        TokenAtOffset::None => None,
        TokenAtOffset::Single(t) => Some(t),
        TokenAtOffset::Between(left, right) => {
            if rank(&right) <= rank(&left) {
                Some(right)
            } else {
                Some(left)
            }
        }
    }
}

/// The item whose node holds `token`, with the item's start offset.
pub(crate) fn item_of(
    db: &dyn salsa::Database,
    file: File,
    token: &SyntaxToken,
) -> Option<(ItemId, TextSize)> {
    let node = token.parent_ancestors().find(|n| {
        n.parent()
            .is_some_and(|p| p.kind() == SyntaxKind::SOURCE_FILE)
    })?;
    ast::Item::cast(node.clone())?;
    let start = node.text_range().start();
    let offsets = db::item_offsets(db, file);
    let index = offsets.binary_search(&start).ok()?;
    Some((
        ItemId {
            file,
            index: u32::try_from(index).ok()?,
        },
        start,
    ))
}

/// The start of an item in its file.
pub(crate) fn item_start(db: &dyn salsa::Database, item: ItemId) -> TextSize {
    db::item_offsets(db, item.file)
        .get(item.index as usize)
        .copied()
        .unwrap_or_default()
}

/// The uses at `offset` of `file` (several when a CALL target names a symbol and its
/// interface), with absolute ranges.
pub(crate) fn uses_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Vec<NameUse> {
    let root = db::parse(db, file).syntax_node();
    let Some(token) = token_at(&root, offset) else {
        return Vec::new();
    };
    let Some((item, start)) = item_of(db, file, &token) else {
        return Vec::new();
    };
    let Some(relative) = offset.checked_sub(start) else {
        return Vec::new();
    };
    item_uses(db, ws, item.loc(db))
        .uses
        .iter()
        .filter(|u| u.range.contains_inclusive(relative) || on_quote(u, relative))
        .map(|u| NameUse {
            range: u.range + start,
            ..u.clone()
        })
        .collect()
}

/// Is `offset` on one of the quotes around a quoted use?
fn on_quote(name_use: &NameUse, offset: TextSize) -> bool {
    let one = TextSize::from(1);
    name_use.quoted
        && name_use.range.start() >= one
        && TextRange::new(name_use.range.start() - one, name_use.range.end() + one).contains(offset)
}

/// What the name at `offset` of `file` refers to: a use resolves to its declaration, a
/// declared name to itself.
pub fn definition_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<NameAt> {
    definitions_at(db, ws, file, offset).into_iter().next()
}

/// Like [`definition_at`], but every definition the name refers to: a symbolic CALL target
/// names both the symbol and, if the workspace declares it, the block's interface.
pub fn definitions_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Vec<NameAt> {
    let root = db::parse(db, file).syntax_node();
    let Some(token) = token_at(&root, offset) else {
        return Vec::new();
    };
    let Some((item, _)) = item_of(db, file, &token) else {
        return Vec::new();
    };
    let found: Vec<NameAt> = uses_at(db, ws, file, offset)
        .iter()
        .filter_map(|u| {
            Some(NameAt {
                definition: definition_of(db, item, &u.target)?,
                range: u.range,
            })
        })
        .collect();
    if !found.is_empty() {
        return found;
    }
    declared_at(db, ws, item, &token).into_iter().collect()
}

/// The definition a use inside `item` refers to.
fn definition_of(db: &dyn salsa::Database, item: ItemId, target: &UseTarget) -> Option<Definition> {
    Some(match target {
        UseTarget::Var(name) => Definition::Variable {
            owner: item,
            name: name.clone(),
        },
        UseTarget::Predefined(name) => Definition::Predefined { graph: item, name },
        UseTarget::Symbol(position) => Definition::Symbol(*position),
        UseTarget::Graph(graph) => Definition::Graph(*graph),
        UseTarget::Formal { graph, name } => Definition::Variable {
            owner: *graph,
            name: name.clone(),
        },
        UseTarget::PredefinedFormal { graph, name } => Definition::Predefined {
            graph: *graph,
            name,
        },
        UseTarget::Instance(name) => Definition::Instance {
            group: item,
            name: name.clone(),
        },
        UseTarget::State(number) => {
            // An endpoint naming no state has nothing to go to.
            state_node(db, item, *number)?;
            Definition::State {
                graph: item,
                number: *number,
            }
        }
        UseTarget::Action(name) => Definition::Action {
            chart: item,
            name: name.clone(),
        },
        UseTarget::Step { sequencer, name } => Definition::Step {
            chart: item,
            sequencer: sequencer.clone(),
            name: name.clone(),
        },
        UseTarget::BlockInterface(interface) => Definition::BlockInterface(*interface),
        UseTarget::InterfaceParam { interface, name } => Definition::Variable {
            owner: *interface,
            name: name.clone(),
        },
        UseTarget::Def(definition) => definition.clone(),
        UseTarget::Address(_) => return None,
    })
}

/// The definition declared by the name at `offset` of `file` (a declaration's name or a
/// state's number), without looking at uses: no item's use index is computed, so this stays
/// cheap right after an edit of a large graph (the code lenses ask it).
pub(crate) fn declaration_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<NameAt> {
    let root = db::parse(db, file).syntax_node();
    let token = token_at(&root, offset)?;
    let (item, _) = item_of(db, file, &token)?;
    declared_at(db, ws, item, &token)
}

/// The definition whose declared name is `token` (a NAME of a declaration or a state
/// number).
fn declared_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    item: ItemId,
    token: &SyntaxToken,
) -> Option<NameAt> {
    let start = item_start(db, item);
    let parent = token.parent()?;
    if token.kind() == SyntaxKind::NUMBER && parent.kind() == SyntaxKind::STATE {
        let number = token.text().parse::<u32>().ok()?;
        return Some(NameAt {
            definition: Definition::State {
                graph: item,
                number,
            },
            range: token.text_range(),
        });
    }
    if parent.kind() != SyntaxKind::NAME {
        return None;
    }
    let owner = parent.parent()?;
    let name = ast::unquote(token.text()).to_owned();
    let range = if token.kind() == SyntaxKind::STRING {
        resolve::string_inner_range(token)
    } else {
        token.text_range()
    };
    let definition = match owner.kind() {
        SyntaxKind::GRAPH => Definition::Graph(item),
        SyntaxKind::GROUP => Definition::Group(item),
        SyntaxKind::CHART => Definition::Chart(item),
        SyntaxKind::VAR_DECL => Definition::Variable { owner: item, name },
        SyntaxKind::INSTANCE => Definition::Instance { group: item, name },
        SyntaxKind::SYMBOL => {
            let relative = token.text_range() - start;
            let position = db::global_index(db, ws).symbols.iter().position(|s| {
                s.source == SymbolSource::Declared
                    && s.name_loc.file == item.file
                    && s.name_loc.item == Some(item.index)
                    && s.name_loc.range == relative
            })?;
            Definition::Symbol(position)
        }
        SyntaxKind::SEQUENCER => Definition::Sequencer { chart: item, name },
        SyntaxKind::CHART_ACTION => Definition::Action { chart: item, name },
        SyntaxKind::STEP | SyntaxKind::CHART_TRANS | SyntaxKind::JUMP | SyntaxKind::LOOP => {
            let sequencer = owner
                .ancestors()
                .find_map(ast::Sequencer::cast)
                .and_then(|s| s.name())
                .map(|n| n.text())?;
            if owner.kind() == SyntaxKind::STEP {
                Definition::Step {
                    chart: item,
                    sequencer,
                    name,
                }
            } else {
                Definition::ChartTransition {
                    chart: item,
                    sequencer,
                    name,
                }
            }
        }
        _ => return None,
    };
    Some(NameAt { definition, range })
}

// ------------------------------------------------------------------------------ declarations

/// The items of the workspace of the given kinds, in workspace order.
pub(crate) fn items_of_kind(
    db: &dyn salsa::Database,
    ws: Workspace,
    kinds: &[ItemKind],
) -> Vec<ItemId> {
    let mut items = Vec::new();
    for &file in ws.files(db) {
        for (i, summary) in db::file_summary(db, file).items.iter().enumerate() {
            if kinds.contains(&summary.kind) {
                items.push(ItemId {
                    file,
                    index: i as u32,
                });
            }
        }
    }
    items
}

/// The state node of `graph` with that number (the first).
fn state_node(db: &dyn salsa::Database, graph: ItemId, number: u32) -> Option<ast::State> {
    let graph = db::item_root(db, graph.loc(db)).and_then(ast::Graph::cast)?;
    graph.states().find(|s| {
        s.number()
            .and_then(|t| t.text().parse::<u32>().ok())
            .is_some_and(|n| n == number)
    })
}

/// The sequencer of a chart item with that name (the first).
fn sequencer_node(db: &dyn salsa::Database, chart: ItemId, name: &str) -> Option<ast::Sequencer> {
    let chart = db::item_root(db, chart.loc(db)).and_then(ast::Chart::cast)?;
    chart.sequencers().find(|s| {
        s.name()
            .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
    })
}

/// The first variable declaration of that name in a graph, chart or block interface item.
pub(crate) fn var_decl(
    db: &dyn salsa::Database,
    owner: ItemId,
    name: &str,
) -> Option<ast::VarDecl> {
    let root = db::item_root(db, owner.loc(db))?;
    let sections: Vec<ast::VarSection> = match ast::Item::cast(root)? {
        ast::Item::Graph(g) => g.var_sections().collect(),
        ast::Item::Chart(c) => c.var_sections().collect(),
        ast::Item::BlockInterface(b) => b.var_sections().collect(),
        _ => return None,
    };
    sections.iter().flat_map(|s| s.decls()).find(|d| {
        d.name()
            .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
    })
}

/// The node that declares a definition, rooted at its item (item-relative ranges), with its
/// name token. `None` for predefined variables and imported symbols.
pub(crate) fn declaration_node(
    db: &dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
) -> Option<(ItemId, SyntaxNode, SyntaxToken)> {
    let name_token = |node: &SyntaxNode| {
        node.children()
            .find(|n| n.kind() == SyntaxKind::NAME)
            .and_then(ast::Name::cast)
            .and_then(|n| n.token())
    };
    let (item, node) = match definition {
        Definition::Graph(item)
        | Definition::Group(item)
        | Definition::Chart(item)
        | Definition::BlockInterface(item) => (*item, db::item_root(db, item.loc(db))?),
        Definition::Symbol(position) => {
            let symbol = db::global_index(db, ws).symbols.get(*position)?;
            let (SymbolSource::Declared, Some(index)) = (symbol.source, symbol.name_loc.item)
            else {
                return None;
            };
            let item = ItemId {
                file: symbol.name_loc.file,
                index,
            };
            let root = db::item_root(db, item.loc(db))?;
            let node = root
                .descendants()
                .filter(|n| n.kind() == SyntaxKind::SYMBOL)
                .find(|n| n.text_range().contains_range(symbol.name_loc.range))?;
            (item, node)
        }
        Definition::Variable { owner, name } => {
            (*owner, var_decl(db, *owner, name)?.syntax().clone())
        }
        Definition::Predefined { .. } => return None,
        Definition::Instance { group, name } => {
            let root = db::item_root(db, group.loc(db)).and_then(ast::Group::cast)?;
            let instance = root.instances().find(|i| {
                i.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
            })?;
            (*group, instance.syntax().clone())
        }
        Definition::State { graph, number } => {
            let state = state_node(db, *graph, *number)?;
            // A state found by its number is not negative: its number is one token.
            let token = state.number()?.token().clone();
            return Some((*graph, state.syntax().clone(), token));
        }
        Definition::Sequencer { chart, name } => {
            (*chart, sequencer_node(db, *chart, name)?.syntax().clone())
        }
        Definition::Action { chart, name } => {
            let root = db::item_root(db, chart.loc(db)).and_then(ast::Chart::cast)?;
            let action = root.actions().find(|a| {
                a.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
            })?;
            (*chart, action.syntax().clone())
        }
        Definition::Step {
            chart,
            sequencer,
            name,
        }
        | Definition::ChartTransition {
            chart,
            sequencer,
            name,
        } => {
            let want_step = matches!(definition, Definition::Step { .. });
            let sequencer = sequencer_node(db, *chart, sequencer)?;
            let node = sequencer.syntax().descendants().find(|n| {
                let kind_fits = match n.kind() {
                    SyntaxKind::STEP => want_step,
                    SyntaxKind::CHART_TRANS | SyntaxKind::JUMP | SyntaxKind::LOOP => !want_step,
                    _ => false,
                };
                kind_fits && name_token(n).is_some_and(|t| t.text().eq_ignore_ascii_case(name))
            })?;
            (*chart, node)
        }
    };
    let token = match definition {
        Definition::BlockInterface(_) => ast::BlockInterface::cast(node.clone())
            .and_then(|b| b.block())
            .and_then(|b| {
                b.syntax()
                    .descendants_with_tokens()
                    .filter_map(|e| e.into_token())
                    .find(|t| !t.kind().is_trivia())
            })?,
        _ => name_token(&node)?,
    };
    Some((item, node, token))
}

/// Where a definition is declared (absolute ranges). Predefined variables have no declaration.
pub fn declaration(
    db: &dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
) -> Option<Declaration> {
    if let Definition::Symbol(position) = definition {
        let symbol = db::global_index(db, ws).symbols.get(*position)?;
        if let SymbolSource::Imported(_) = symbol.source {
            let range = db::absolute_range(db, &symbol.name_loc);
            return Some(Declaration {
                file: symbol.name_loc.file,
                full_range: range,
                focus_range: range,
                name: symbol.name.clone(),
                kind: SymbolKind::Symbol,
                quoted: false,
            });
        }
    }
    let (item, node, token) = declaration_node(db, ws, definition)?;
    let start = item_start(db, item);
    let quoted = token.kind() == SyntaxKind::STRING;
    let focus = if quoted {
        resolve::string_inner_range(&token)
    } else {
        token.text_range()
    };
    let name = match definition {
        Definition::BlockInterface(_) => node
            .children()
            .find(|n| n.kind() == SyntaxKind::BLOCK_REF)
            .map(|n| n.text().to_string())
            .unwrap_or_default(),
        _ => ast::unquote(token.text()).to_owned(),
    };
    let focus_range = match definition {
        Definition::BlockInterface(_) => node
            .children()
            .find(|n| n.kind() == SyntaxKind::BLOCK_REF)
            .map_or(focus, |n| n.text_range()),
        _ => focus,
    };
    Some(Declaration {
        file: item.file,
        full_range: node.text_range() + start,
        focus_range: focus_range + start,
        name,
        kind: symbol_kind(definition, &node),
        quoted,
    })
}

/// The kind of a definition, for icons.
fn symbol_kind(definition: &Definition, node: &SyntaxNode) -> SymbolKind {
    match definition {
        Definition::Graph(_) => SymbolKind::Graph,
        Definition::Group(_) => SymbolKind::Group,
        Definition::Chart(_) => SymbolKind::Chart,
        Definition::BlockInterface(_) => SymbolKind::BlockInterface,
        Definition::Symbol(_) => SymbolKind::Symbol,
        Definition::Variable { .. } => {
            let is_message =
                ast::VarDecl::cast(node.clone()).is_some_and(|d| d.msg_kind().is_some());
            if is_message {
                SymbolKind::Message
            } else {
                SymbolKind::Variable
            }
        }
        Definition::Predefined { .. } => SymbolKind::PredefinedVariable,
        Definition::Instance { .. } => SymbolKind::Instance,
        Definition::State { .. } => SymbolKind::State,
        Definition::Sequencer { .. } => SymbolKind::Sequencer,
        Definition::Step { .. } => SymbolKind::Step,
        Definition::ChartTransition { .. } | Definition::Action { .. } => {
            SymbolKind::ChartTransition
        }
    }
}

/// The kind of the item at `item`.
pub(crate) fn item_kind(db: &dyn salsa::Database, item: ItemId) -> Option<ItemKind> {
    db::file_summary(db, item.file)
        .items
        .get(item.index as usize)
        .map(|s| s.kind)
}

/// The name of a graph, group or chart item as declared.
fn item_name(db: &dyn salsa::Database, graph: ItemId) -> Option<String> {
    db::file_summary(db, graph.file)
        .items
        .get(graph.index as usize)
        .and_then(|s| s.name.clone())
}

// ------------------------------------------------------------------------------ references

/// Every reference to `definition` in the workspace: its declaration first (if it has one in
/// a workspace file or an imported table), then the uses in workspace order.
pub fn references(
    db: &dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
) -> Vec<Reference> {
    let mut out = Vec::new();
    if let Some(decl) = declaration(db, ws, definition) {
        out.push(Reference {
            file: decl.file,
            range: decl.focus_range,
            kind: ReferenceKind::Declaration,
            quoted: decl.quoted,
        });
    }
    let index = db::global_index(db, ws);
    let same = |a: &str, b: &str| a.eq_ignore_ascii_case(b);
    let mut scan = |items: &[ItemId], matches: &dyn Fn(&UseTarget) -> bool| {
        for &item in items {
            let uses = item_uses(db, ws, item.loc(db));
            let start = item_start(db, item);
            for u in uses.uses.iter().filter(|u| matches(&u.target)) {
                out.push(Reference {
                    file: item.file,
                    range: u.range + start,
                    kind: u.kind,
                    quoted: u.quoted,
                });
            }
        }
    };
    let groups = || items_of_kind(db, ws, &[ItemKind::Group]);
    match definition {
        Definition::Graph(graph) => {
            let bound = item_name(db, *graph)
                .and_then(|name| index.graph(&name))
                .is_some_and(|g| g.file == graph.file && g.item == graph.index);
            if bound {
                scan(
                    &groups(),
                    &|t| matches!(t, UseTarget::Graph(g) if g == graph),
                );
            }
        }
        Definition::Group(_)
        | Definition::Chart(_)
        | Definition::Sequencer { .. }
        | Definition::ChartTransition { .. } => {}
        Definition::BlockInterface(interface) => {
            let graphs = items_of_kind(db, ws, &[ItemKind::Graph]);
            scan(
                &graphs,
                &|t| matches!(t, UseTarget::BlockInterface(i) if i == interface),
            );
        }
        Definition::Symbol(position) => {
            let bound = index
                .symbols
                .get(*position)
                .and_then(|s| index.symbol_position(&s.name))
                == Some(*position);
            if bound {
                let items = items_of_kind(
                    db,
                    ws,
                    &[
                        ItemKind::Graph,
                        ItemKind::Group,
                        ItemKind::Chart,
                        ItemKind::BlockInterface,
                    ],
                );
                scan(
                    &items,
                    &|t| matches!(t, UseTarget::Symbol(p) if p == position),
                );
            }
        }
        Definition::Variable { owner, name } => match item_kind(db, *owner) {
            Some(ItemKind::Graph) => {
                scan(
                    &[*owner],
                    &|t| matches!(t, UseTarget::Var(n) if same(n, name)),
                );
                scan(
                    &groups(),
                    &|t| matches!(t, UseTarget::Formal { graph, name: n } if graph == owner && same(n, name)),
                );
            }
            Some(ItemKind::Chart) => {
                scan(
                    &[*owner],
                    &|t| matches!(t, UseTarget::Var(n) if same(n, name)),
                );
            }
            Some(ItemKind::BlockInterface) => {
                let graphs = items_of_kind(db, ws, &[ItemKind::Graph]);
                scan(
                    &graphs,
                    &|t| matches!(t, UseTarget::InterfaceParam { interface, name: n } if interface == owner && same(n, name)),
                );
            }
            _ => {}
        },
        Definition::Predefined { graph, name } => {
            scan(
                &[*graph],
                &|t| matches!(t, UseTarget::Predefined(n) if n == name),
            );
            scan(
                &groups(),
                &|t| matches!(t, UseTarget::PredefinedFormal { graph: g, name: n } if g == graph && n == name),
            );
        }
        Definition::Instance { group, name } => {
            scan(
                &[*group],
                &|t| matches!(t, UseTarget::Instance(n) if same(n, name)),
            );
        }
        Definition::State { graph, number } => {
            scan(
                &[*graph],
                &|t| matches!(t, UseTarget::State(n) if n == number),
            );
        }
        Definition::Step {
            chart,
            sequencer,
            name,
        } => {
            scan(
                &[*chart],
                &|t| matches!(t, UseTarget::Step { sequencer: s, name: n } if same(s, sequencer) && same(n, name)),
            );
        }
        Definition::Action { chart, name } => {
            scan(
                &[*chart],
                &|t| matches!(t, UseTarget::Action(n) if same(n, name)),
            );
        }
    }
    // The uses in tests name other items' definitions.
    let wanted = folded(definition);
    let tests = items_of_kind(db, ws, &[ItemKind::Test]);
    scan(
        &tests,
        &|t| matches!(t, UseTarget::Def(d) if folded(d) == wanted),
    );
    out
}

/// A definition with its names upper-cased (names compare without case).
fn folded(definition: &Definition) -> Definition {
    let up = |s: &String| s.to_ascii_uppercase();
    match definition {
        Definition::Variable { owner, name } => Definition::Variable {
            owner: *owner,
            name: up(name),
        },
        Definition::Instance { group, name } => Definition::Instance {
            group: *group,
            name: up(name),
        },
        Definition::Sequencer { chart, name } => Definition::Sequencer {
            chart: *chart,
            name: up(name),
        },
        Definition::Action { chart, name } => Definition::Action {
            chart: *chart,
            name: up(name),
        },
        Definition::Step {
            chart,
            sequencer,
            name,
        } => Definition::Step {
            chart: *chart,
            sequencer: up(sequencer),
            name: up(name),
        },
        Definition::ChartTransition {
            chart,
            sequencer,
            name,
        } => Definition::ChartTransition {
            chart: *chart,
            sequencer: up(sequencer),
            name: up(name),
        },
        other => other.clone(),
    }
}

/// The name of a definition as declared (the number of a state).
pub fn definition_name(db: &dyn salsa::Database, ws: Workspace, definition: &Definition) -> String {
    match definition {
        Definition::Graph(item) | Definition::Group(item) | Definition::Chart(item) => {
            item_name(db, *item).unwrap_or_default()
        }
        Definition::BlockInterface(_) => declaration(db, ws, definition)
            .map(|d| d.name)
            .unwrap_or_default(),
        Definition::Symbol(position) => db::global_index(db, ws)
            .symbols
            .get(*position)
            .map(|s| s.name.clone())
            .unwrap_or_default(),
        Definition::Variable { name, .. }
        | Definition::Instance { name, .. }
        | Definition::Sequencer { name, .. }
        | Definition::Step { name, .. }
        | Definition::ChartTransition { name, .. }
        | Definition::Action { name, .. } => name.clone(),
        Definition::Predefined { name, .. } => (*name).to_owned(),
        Definition::State { number, .. } => number.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ide::fixture;

    /// Renders what the cursor refers to and all its references as `path range 'text' kind`.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let analysis = f.host.analysis();
        let rendered = analysis.with_db(|db, ws| {
            let Some(file) = analysis.file(&f.position.path) else {
                return "no file".to_owned();
            };
            let Some(at) = definition_at(db, ws, file, f.position.offset) else {
                return "nothing".to_owned();
            };
            let mut out = format!(
                "{} '{}'\n",
                describe(&at.definition),
                f.slice(&f.position.path, at.range)
            );
            for r in references(db, ws, &at.definition) {
                let path = r.file.path(db).clone();
                out.push_str(&format!(
                    "{path} {:?} '{}' {:?}\n",
                    r.range,
                    f.slice(&path, r.range),
                    r.kind
                ));
            }
            out
        });
        rendered.unwrap_or_else(|_| "cancelled".to_owned())
    }

    fn describe(definition: &Definition) -> String {
        match definition {
            Definition::Graph(_) => "graph".into(),
            Definition::Group(_) => "group".into(),
            Definition::Chart(_) => "chart".into(),
            Definition::BlockInterface(_) => "block interface".into(),
            Definition::Symbol(i) => format!("symbol #{i}"),
            Definition::Variable { name, .. } => format!("variable {name}"),
            Definition::Predefined { name, .. } => format!("predefined {name}"),
            Definition::Instance { name, .. } => format!("instance {name}"),
            Definition::State { number, .. } => format!("state {number}"),
            Definition::Sequencer { name, .. } => format!("sequencer {name}"),
            Definition::Step {
                sequencer, name, ..
            } => format!("step {sequencer}.{name}"),
            Definition::ChartTransition {
                sequencer, name, ..
            } => format!("chart transition {sequencer}.{name}"),
            Definition::Action { name, .. } => format!("action {name}"),
        }
    }

    const VALVE: &str = r#"//- graphs.higraph
graph Ventil "valve" <
  in < Oben : BOOL; Zeit : TIME; T_Start : TIMER; >
  out < Auf : BOOL; >
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  activate CurrentState;
  state 0 < C: L CurrentState; T MW 10; >
  state 1 < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U Oben; FP M 1.0; >
  trans 1->0 < U IM_Ab; U "Start"; !: R IM_Ab; SE T_Start; >
>
//- group.higraph
group Anlage fc FC 1 db "AnlageDB" <
  instance V1 : Ventil < Oben := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Ab; >
  instance V2 : Ventil < Oben := "Start"; OM_Oben := V1.IM_Ab; ManualMode := Start; >
>
//- symbols.higraph
symbols <
  Start : E 0.0 BOOL "start button";
  AnlageDB : DB 1;
>
"#;

    fn with_cursor(fixture: &str, path: &str, needle: &str) -> String {
        // Puts `$0` before the first occurrence of `needle` in file `path`.
        let marker = format!("//- {path}\n");
        let start = fixture.find(&marker).map_or(0, |i| i + marker.len());
        let at = fixture[start..].find(needle).map_or(start, |i| start + i);
        format!("{}$0{}", &fixture[..at], &fixture[at..])
    }

    #[test]
    fn graph_variable_is_found_in_instructions_and_every_instance() {
        let text = with_cursor(VALVE, "graphs.higraph", "IM_Ab; U");
        insta::assert_snapshot!(check(&text), @"
        variable IM_Ab 'IM_Ab'
        graphs.higraph 108..113 'IM_Ab' Declaration
        graphs.higraph 372..377 'IM_Ab' Read
        graphs.higraph 395..400 'IM_Ab' Write
        group.higraph 119..124 'IM_Ab' Write
        group.higraph 184..189 'IM_Ab' Write
        ");
    }

    #[test]
    fn formal_of_an_actual_refers_to_the_graph_variable() {
        let text = with_cursor(VALVE, "group.higraph", "Oben := Start");
        insta::assert_snapshot!(check(&text), @"
        variable Oben 'Oben'
        graphs.higraph 30..34 'Oben' Declaration
        graphs.higraph 337..341 'Oben' Read
        group.higraph 62..66 'Oben' Name
        group.higraph 153..157 'Oben' Name
        ");
    }

    #[test]
    fn symbol_uses_in_graphs_groups_and_both_spellings() {
        let text = with_cursor(VALVE, "symbols.higraph", "Start :");
        insta::assert_snapshot!(check(&text), @"
        symbol #0 'Start'
        symbols.higraph 12..17 'Start' Declaration
        graphs.higraph 382..387 'Start' Read
        group.higraph 70..75 'Start' Read
        group.higraph 162..167 'Start' Read
        group.higraph 205..210 'Start' Read
        ");
    }

    #[test]
    fn predefined_variables_have_uses_but_no_declaration() {
        let text = with_cursor(VALVE, "graphs.higraph", "CurrentState; T");
        insta::assert_snapshot!(check(&text), @"
        predefined CurrentState 'CurrentState'
        graphs.higraph 166..178 'CurrentState' Name
        graphs.higraph 197..209 'CurrentState' Read
        ");
    }

    #[test]
    fn access_kinds_follow_appendix_e() {
        // `SE` on a timer reads and writes it; `supervise` reads its time.
        let text = with_cursor(VALVE, "graphs.higraph", "T_Start");
        insta::assert_snapshot!(check(&text), @"
        variable T_Start 'T_Start'
        graphs.higraph 56..63 'T_Start' Declaration
        graphs.higraph 405..412 'T_Start' ReadWrite
        ");
    }

    #[test]
    fn states_instances_and_graph_names() {
        let state = with_cursor(VALVE, "graphs.higraph", "1 < E:");
        insta::assert_snapshot!(check(&state), @"
        state 1 '1'
        graphs.higraph 230..231 '1' Declaration
        graphs.higraph 331..332 '1' Name
        graphs.higraph 363..364 '1' Name
        ");
        let instance = with_cursor(VALVE, "group.higraph", "V2.IM_Ab");
        insta::assert_snapshot!(check(&instance), @"
        instance V2 'V2'
        group.higraph 139..141 'V2' Declaration
        group.higraph 116..118 'V2' Name
        ");
        let graph = with_cursor(VALVE, "group.higraph", "Ventil <");
        insta::assert_snapshot!(check(&graph), @"
        graph 'Ventil'
        graphs.higraph 6..12 'Ventil' Declaration
        group.higraph 53..59 'Ventil' Name
        group.higraph 144..150 'Ventil' Name
        ");
    }

    #[test]
    fn chart_variables_steps_and_symbols() {
        let text = r#"//- chart.higraph
chart Mischer <
  in < Freigabe : BOOL; Heizung : BOOL; >
  sequencer RUN <
    start < Freigabe; >
    step START < init < Heizung := FALSE; > N Heizung; >
    trans T1 < not Heizung and "Start"; >
    step ENDE < >
    jump J1 -> start < Freigabe; >
  >
>
//- symbols.higraph
symbols < Start : E 0.0; >
"#;
        let var = text.replacen("N Heizung", "N $0Heizung", 1);
        insta::assert_snapshot!(check(&var), @"
        variable Heizung 'Heizung'
        chart.higraph 40..47 'Heizung' Declaration
        chart.higraph 124..131 'Heizung' Write
        chart.higraph 146..153 'Heizung' Write
        chart.higraph 176..183 'Heizung' Read
        ");
        let step = text.replacen("-> start", "-> $0start", 1);
        insta::assert_snapshot!(check(&step), @"
        step RUN.START 'start'
        chart.higraph 109..114 'START' Declaration
        chart.higraph 232..237 'start' Name
        ");
        let symbol = text.replacen("\"Start\"", "\"$0Start\"", 1);
        insta::assert_snapshot!(check(&symbol), @"
        symbol #0 'Start'
        symbols.higraph 10..15 'Start' Declaration
        chart.higraph 189..194 'Start' Read
        ");
    }

    const TESTED: &str = r#"//- plant.higraph
graph Ventil <
  in < Oben : BOOL; >
  out < Auf : BOOL; >
  activate CurrentState;
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
symbols < Start : E 0.0 BOOL; "Motor 1" : A 1.0 BOOL; >
//- tests.higraph
test T1 <
  run Anlage, Mischer;
  set Start := TRUE;
  set V1.Oben := TRUE;
  set Mischer.Freigabe := TRUE;
  step;
  expect Anlage.V1.Auf and V1.state = 0 and V1.ManualMode = FALSE;
  expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
  command Mischer start;
  confirm Mischer.Heizen;
>
"#;

    #[test]
    fn test_paths_refer_to_their_declarations() {
        let var = with_cursor(TESTED, "tests.higraph", "Oben :=");
        insta::assert_snapshot!(check(&var), @"
        variable Oben 'Oben'
        plant.higraph 22..26 'Oben' Declaration
        plant.higraph 101..105 'Oben' Read
        plant.higraph 204..208 'Oben' Name
        tests.higraph 63..67 'Oben' Write
        ");
        let from_graph = with_cursor(TESTED, "plant.higraph", "Auf; >");
        insta::assert_snapshot!(check(&from_graph), @"
        variable Auf 'Auf'
        plant.higraph 45..48 'Auf' Declaration
        plant.higraph 109..112 'Auf' Write
        tests.higraph 136..139 'Auf' Read
        ");
        let instance = with_cursor(TESTED, "tests.higraph", "V1.state");
        insta::assert_snapshot!(check(&instance), @"
        instance V1 'V1'
        plant.higraph 190..192 'V1' Declaration
        tests.higraph 60..62 'V1' Name
        tests.higraph 133..135 'V1' Name
        tests.higraph 144..146 'V1' Name
        tests.higraph 161..163 'V1' Name
        ");
        let group = with_cursor(TESTED, "plant.higraph", "Anlage fc");
        insta::assert_snapshot!(check(&group), @"
        group 'Anlage'
        plant.higraph 154..160 'Anlage' Declaration
        tests.higraph 16..22 'Anlage' Name
        tests.higraph 126..132 'Anlage' Name
        ");
        let chart = with_cursor(TESTED, "tests.higraph", "Mischer start");
        insta::assert_snapshot!(check(&chart), @"
        chart 'Mischer'
        plant.higraph 229..236 'Mischer' Declaration
        tests.higraph 24..31 'Mischer' Name
        tests.higraph 83..90 'Mischer' Name
        tests.higraph 193..200 'Mischer' Name
        tests.higraph 246..253 'Mischer' Name
        tests.higraph 271..278 'Mischer' Name
        ");
        let step = with_cursor(TESTED, "tests.higraph", "Heizen.T");
        insta::assert_snapshot!(check(&step), @"
        step RUN.Heizen 'Heizen'
        plant.higraph 316..322 'Heizen' Declaration
        tests.higraph 205..211 'Heizen' Name
        tests.higraph 279..285 'Heizen' Read
        ");
        let sequencer = with_cursor(TESTED, "tests.higraph", "RUN.");
        insta::assert_snapshot!(check(&sequencer), @"
        sequencer RUN 'RUN'
        plant.higraph 277..280 'RUN' Declaration
        tests.higraph 201..204 'RUN' Name
        ");
        let symbol = with_cursor(TESTED, "tests.higraph", "Start :=");
        insta::assert_snapshot!(check(&symbol), @"
        symbol #0 'Start'
        plant.higraph 370..375 'Start' Declaration
        plant.higraph 212..217 'Start' Read
        tests.higraph 39..44 'Start' Write
        ");
        let quoted = with_cursor(TESTED, "tests.higraph", "Motor 1\"");
        insta::assert_snapshot!(check(&quoted), @"
        symbol #1 'Motor 1'
        plant.higraph 391..398 'Motor 1' Declaration
        tests.higraph 226..233 'Motor 1' Read
        ");
        let chart_var = with_cursor(TESTED, "plant.higraph", "Freigabe : BOOL");
        insta::assert_snapshot!(check(&chart_var), @"
        variable Freigabe 'Freigabe'
        plant.higraph 246..254 'Freigabe' Declaration
        plant.higraph 295..303 'Freigabe' Read
        plant.higraph 342..350 'Freigabe' Read
        tests.higraph 91..99 'Freigabe' Write
        ");
        let predefined = with_cursor(TESTED, "tests.higraph", "ManualMode");
        insta::assert_snapshot!(check(&predefined), @"
        predefined ManualMode 'ManualMode'
        tests.higraph 164..174 'ManualMode' Read
        ");
        let member = with_cursor(TESTED, "tests.higraph", "state = 0");
        insta::assert_snapshot!(check(&member), @"nothing");
    }

    #[test]
    fn calls_name_the_symbol_the_interface_and_its_parameters() {
        let text = r#"//- g.higraph
graph G <
  in < A : BOOL; >
  state 0 < C: CALL "Dosieren" (Menge := MW 2, Fertig := A); >
  trans any->0 < U INIT_SD; >
>
//- b.higraph
block "Dosieren" < in < Menge : INT; > out < Fertig : BOOL; > >
symbols < Dosieren : FC 10; >
"#;
        let param = text.replacen("Fertig :=", "$0Fertig :=", 1);
        insta::assert_snapshot!(check(&param), @"
        variable Fertig 'Fertig'
        b.higraph 45..51 'Fertig' Declaration
        g.higraph 76..82 'Fertig' Name
        ");
        let value = text.replacen(":= A)", ":= $0A)", 1);
        insta::assert_snapshot!(check(&value), @"
        variable A 'A'
        g.higraph 17..18 'A' Declaration
        g.higraph 86..87 'A' Write
        ");
        let callee = text.replacen("CALL \"", "CALL \"$0", 1);
        insta::assert_snapshot!(check(&callee), @"
        symbol #0 'Dosieren'
        b.higraph 74..82 'Dosieren' Declaration
        b.higraph 7..15 'Dosieren' Name
        g.higraph 50..58 'Dosieren' Name
        ");
    }

    #[test]
    fn unresolved_names_and_keywords_refer_to_nothing() {
        assert_eq!(check("graph G < state 0 < C: U $0Nix; > >"), "nothing");
        assert_eq!(check("graph G < $0state 0 < > >"), "nothing");
        assert_eq!(check("graph G < state 0 < C: U $0E 1.0; > >"), "nothing");
    }

    #[test]
    fn iec_instances_steps_and_actions() {
        let text = "chart Ampel <
  profile iec;
  stat < Uhr : TON; Start : BOOL; Zeit : TIME; >
  action Zaehlen < Start := FALSE; >
  sequencer Haupt <
    step Rot < P1 Zaehlen; run < Uhr(IN := Start, ET => Zeit); > >
    trans Weiter < Uhr.Q and Rot.T > T#1S; >
    step Gruen < >
  >
>
";
        insta::assert_snapshot!(check(&text.replacen("Uhr :", "$0Uhr :", 1)), @"
        variable Uhr 'Uhr'
        main.higraph 38..41 'Uhr' Declaration
        main.higraph 221..224 'Uhr' Read
        main.higraph 168..171 'Uhr' ReadWrite
        ");
        insta::assert_snapshot!(check(&text.replacen("IN := Start", "IN := $0Start", 1)), @"
        variable Start 'Start'
        main.higraph 49..54 'Start' Declaration
        main.higraph 97..102 'Start' Write
        main.higraph 178..183 'Start' Read
        ");
        insta::assert_snapshot!(check(&text.replacen("Rot.T", "$0Rot.T", 1)), @"
        step Haupt.Rot 'Rot'
        main.higraph 144..147 'Rot' Declaration
        main.higraph 231..234 'Rot' Read
        ");
        insta::assert_snapshot!(check(&text.replacen("P1 Zaehlen", "P1 $0Zaehlen", 1)), @"
        action Zaehlen 'Zaehlen'
        main.higraph 87..94 'Zaehlen' Declaration
        main.higraph 153..160 'Zaehlen' Name
        ");
    }
}

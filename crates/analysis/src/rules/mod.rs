//! The rules of `diagnostics.md` §3, one module per family. Each module checks one kind of
//! item (or the whole workspace) and pushes [`Diag`]s into the [`Ctx`].
//!
//! | module       | codes |
//! |--------------|-------|
//! | `names`      | HG1101–HG1103: name rules of every declared name |
//! | `decls`      | HG1201, HG1203–HG1206, HG1213, HG1215: variable declarations of graphs, charts and `block` interfaces |
//! | `graph`      | HG1202, HG1211, HG1212 (graph declarations), HG2xxx, HG3001–HG3003, HG3007, HG3101, HG3102 |
//! | `stl`        | operand resolution in graphs; HG1104, HG1207–HG1210, HG1214, HG3004–HG3006, HG3008, HG4xxx |
//! | `group`      | HG3103, HG3104, HG5xxx, HG8xxx |
//! | `symbols`    | HG6xxx, HG4309, HG4310, HG1301 (workspace-wide) |
//! | `chart`      | HG7xxx and the chart side of HG1xxx/HG3xxx/HG4101 |
//! | `test`       | HG9001–HG9010: the structure of tests (paths and types are the lowering's) |
//!
//! Shared by the modules: `edit` (the text edits of quick fixes), `has_error` (C1) and
//! `Ctx::with_closest_fix` ("did you mean" fixes); `stl::time` checks the time values of
//! graphs and charts.

use std::collections::BTreeSet;

use higraph_syntax::{SyntaxKind, SyntaxNode, TextRange, TextSize, ast};

use crate::{
    db::{self, File, ItemLoc, Workspace},
    diag::{Diag, Loc},
    index::GlobalIndex,
    lang::Mnemonic,
    rules::graph::facts::MemberFacts,
};

pub(crate) mod chart;
pub(crate) mod decls;
mod edit;
pub(crate) mod graph;
pub(crate) mod group;
mod names;
pub(crate) mod stl;
pub(crate) mod symbols;
pub(crate) mod test;

/// What the rules found in one item.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ItemAnalysis {
    pub diags: Vec<Diag>,
    /// Names (upper case) of the global symbols this item uses (for HG6004).
    pub used_symbols: BTreeSet<String>,
}

/// The context of the rules of one item.
pub(crate) struct Ctx<'a> {
    pub db: &'a dyn salsa::Database,
    pub ws: Workspace,
    pub file: File,
    pub item: u32,
    pub mnemonic: Mnemonic,
    pub index: &'a GlobalIndex,
    pub out: ItemAnalysis,
    /// Are the syntax nodes being checked rooted at a graph member rather than at the item?
    /// Then [`Ctx::loc`] makes member-relative places.
    pub in_member: bool,
}

impl Ctx<'_> {
    /// A place in the tree being checked: the current item, or the current graph member.
    pub fn loc(&self, range: TextRange) -> Loc {
        if self.in_member {
            Loc::in_member(self.file, self.item, range)
        } else {
            Loc::in_item(self.file, self.item, range)
        }
    }

    /// A place relative to the item, also while a member is being checked (for positions the
    /// graph's scope knows, such as where a new declaration goes).
    pub fn item_loc(&self, range: TextRange) -> Loc {
        Loc::in_item(self.file, self.item, range)
    }

    /// A diagnostic at a range of the current item.
    pub fn diag(&self, code: &'static str, range: TextRange, message: impl Into<String>) -> Diag {
        Diag::new(code, self.loc(range), message)
    }

    pub fn push(&mut self, diag: Diag) {
        self.out.diags.push(diag);
    }

    /// `diag` with the fix "Replace with 'best'" at `range`, where `best` is the candidate
    /// closest to `written` ([`closest`](crate::closest::closest)); unchanged if none is close.
    pub fn with_closest_fix<'c>(
        &self,
        diag: Diag,
        range: TextRange,
        written: &str,
        candidates: impl IntoIterator<Item = &'c str>,
    ) -> Diag {
        match crate::closest::closest(written, candidates) {
            Some(best) => diag
                .fix(format!("Replace with '{best}'"), self.loc(range), best)
                .preferred(),
            None => diag,
        }
    }

    /// Records a use of a global symbol (HG6004).
    pub fn use_symbol(&mut self, name: &str) {
        self.out.used_symbols.insert(crate::index::key(name));
    }
}

impl<'a> Ctx<'a> {
    /// The context for checking `item`.
    pub(crate) fn for_item(
        db: &'a dyn salsa::Database,
        ws: Workspace,
        item: ItemLoc<'_>,
    ) -> Ctx<'a> {
        let file = item.file(db);
        Ctx {
            db,
            ws,
            file,
            item: item.index(db),
            mnemonic: db::file_mnemonic(db, ws, file),
            index: db::global_index(db, ws),
            out: ItemAnalysis::default(),
            in_member: false,
        }
    }
}

pub(crate) fn check_item(
    db: &dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'_>,
) -> ItemAnalysis {
    let Some(root) = db::item_root(db, item) else {
        return ItemAnalysis::default();
    };
    let mut ctx = Ctx::for_item(db, ws, item);
    let item_node = ast::Item::cast(root);
    match item_node.clone() {
        Some(ast::Item::Graph(graph)) => check_graph(&mut ctx, item, &graph),
        Some(ast::Item::Group(group)) => {
            names::check_group(&mut ctx, &group);
            group::check(&mut ctx, &group);
        }
        Some(ast::Item::Chart(chart)) => {
            names::check_chart(&mut ctx, &chart);
            chart::check(&mut ctx, &chart);
        }
        Some(ast::Item::Symbols(table)) => {
            names::check_symbols(&mut ctx, &table);
            symbols::check_table(&mut ctx, &table);
        }
        Some(ast::Item::BlockInterface(interface)) => {
            names::check_block_interface(&mut ctx, &interface);
            decls::check_block_interface(&mut ctx, &interface);
            symbols::check_block_interface(&mut ctx, &interface);
        }
        Some(ast::Item::Test(test)) => {
            test::check(&mut ctx, &test);
            let (diags, symbols) = crate::lower::check_test(db, ws, ctx.file, ctx.item, &test);
            ctx.out.diags.extend(diags);
            for symbol in symbols {
                ctx.use_symbol(&symbol);
            }
        }
        Some(ast::Item::Mnemonic(_)) | None => {}
    }
    if is_later_duplicate(&ctx, item_node.as_ref()) {
        // C3: a graph, group or chart whose name an earlier one already has (HG1301), or a
        // second `block` item for a block (HG4310), is reported (workspace-wide) and otherwise
        // ignored; the symbols it names still count as used (HG6004), as for a duplicate
        // instance.
        ctx.out.diags.clear();
    }
    ctx.out
}

/// Is `symbol` (of the item being checked) a later declaration of a symbol name (C3)?
pub(crate) fn is_later_symbol(ctx: &Ctx<'_>, symbol: &ast::Symbol) -> bool {
    let Some(name) = symbol.name() else {
        return false;
    };
    let Some(token) = name.token() else {
        return false;
    };
    ctx.index
        .symbol(&name.text())
        .is_some_and(|first| first.name_loc != ctx.loc(token.text_range()))
}

/// Is the item being checked a graph, group or chart whose name an earlier graph, group or
/// chart of the workspace already has, or a `block` item for a block that an earlier one
/// describes (HG4310)?
fn is_later_duplicate(ctx: &Ctx<'_>, item: Option<&ast::Item>) -> bool {
    let name = match item {
        Some(ast::Item::Graph(graph)) => graph.name(),
        Some(ast::Item::Group(group)) => group.name(),
        Some(ast::Item::Chart(chart)) => chart.name(),
        Some(ast::Item::BlockInterface(_)) => return symbols::is_later_interface(ctx),
        _ => None,
    };
    let Some(name) = name else {
        return false;
    };
    ctx.index
        .items_named(&name.text())
        .next()
        .is_some_and(|first| !(first.file == ctx.file && first.item == ctx.item))
}

/// A graph: its names and declarations from its own tree; its structure from its member
/// facts ([`db::graph_structure`], placed afterwards); its STL chunk by chunk
/// ([`db::chunk_stl`]). After a keystroke in one member, only the chunk of members around it
/// is analysed again, and the structure rules only if the member's facts changed.
fn check_graph(ctx: &mut Ctx<'_>, item: ItemLoc<'_>, graph: &ast::Graph) {
    let db = ctx.db;
    names::check_graph(ctx, graph);
    let name = graph.name().map(|n| n.text()).unwrap_or_default();
    graph::check_declarations(ctx, graph, &name);

    let layout = db::graph_layout(db, item);
    let structure = db::graph_structure(db, ctx.ws, item);
    if !structure.diags.is_empty() {
        // Back from the virtual layout: the real offset of every member.
        let offsets = layout.member_offsets(db);
        let place = |at: TextSize| graph::VirtualLayout::place(at, &offsets);
        for diag in &structure.diags {
            ctx.out.diags.push(if layout.virtual_ok {
                diag.map_ranges(|r| TextRange::new(place(r.start()), place(r.end())))
            } else {
                diag.clone()
            });
        }
    }

    let Some(scope) = db::graph_scope(db, item) else {
        return;
    };
    let mut label_prios = structure.label_prios.iter().copied();
    let mut found = stl::MemberStl::default();
    for (&chunk, &start) in layout.chunks.iter().zip(&layout.offsets) {
        let transitions = db::chunk_facts(db, chunk)
            .iter()
            .filter(|f| matches!(f, MemberFacts::Trans(_)))
            .count();
        let prios: Vec<Option<u64>> = label_prios.by_ref().take(transitions).collect();
        found.merge(db::chunk_stl(db, ctx.ws, item, chunk, prios), start);
    }
    // Each chunk was merged at its start, so the places are item-relative already; placing
    // at offset 0 only ends their being marked member-relative.
    let duplicates = duplicate_states(db, layout);
    ctx.out.diags.extend(
        found
            .diags
            .iter()
            .filter(|d| !duplicates.iter().any(|r| r.contains_range(d.at.range)))
            .map(|d| d.place_member(0.into())),
    );
    ctx.out.used_symbols.extend(found.used_symbols);
    let mut scope = scope.clone();
    for (used, here) in scope.used_vars.iter_mut().zip(&found.used_vars) {
        *used |= *here;
    }
    scope.used_predefined.extend(found.used_predefined);
    stl::report_unused(ctx, &scope);
}

/// The ranges (relative to the item) of the states whose number an earlier state has
/// (HG2101): C3 ignores them, so their STL findings are dropped; the variables they use still
/// count as used (HG1210).
fn duplicate_states(db: &dyn salsa::Database, layout: &db::GraphLayout<'_>) -> Vec<TextRange> {
    let facts: Vec<_> = layout
        .chunks
        .iter()
        .map(|&chunk| db::chunk_facts(db, chunk))
        .collect();
    let mut seen = std::collections::HashSet::new();
    let mut ranges = Vec::new();
    for ((&chunk, &start), facts) in layout.chunks.iter().zip(&layout.offsets).zip(&facts) {
        for ((green, offset), fact) in chunk.members(db).iter().zip(facts.iter()) {
            if let MemberFacts::State(state) = fact
                && state.number.is_some()
                && !seen.insert(state.key.as_str())
            {
                let len = green.0.text_len();
                ranges.push(TextRange::at(start + *offset, len));
            }
        }
    }
    ranges
}

/// The structure rules of a graph on its member facts ([`db::graph_structure`]).
pub(crate) fn check_graph_structure(
    db: &dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'_>,
) -> db::GraphStructure {
    let Some(header) = db::graph_header(db, item) else {
        return db::GraphStructure::default();
    };
    let facts = db::graph_facts(db, item);
    let layout = if facts.virtual_ok {
        graph::VirtualLayout::Virtual
    } else {
        graph::VirtualLayout::Real(db::graph_layout(db, item).member_offsets(db))
    };
    let model = graph::GraphModel::new(
        header.name.clone(),
        facts.members(),
        header.declares_init_sd,
        layout,
    );
    let mut ctx = Ctx::for_item(db, ws, item);
    graph::check_structure(&mut ctx, header, &model);
    db::GraphStructure {
        diags: ctx.out.diags,
        label_prios: model
            .transitions
            .iter()
            .map(|t| t.label_priority())
            .collect(),
    }
}

/// The STL analysis of one member of a graph item (`member` is the member's own tree).
pub(crate) fn check_member_stl(
    db: &dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'_>,
    member: &SyntaxNode,
    label_prio: Option<u64>,
) -> stl::MemberStl {
    let Some(scope) = db::graph_scope(db, item) else {
        return stl::MemberStl::default();
    };
    let mut ctx = Ctx::for_item(db, ws, item);
    ctx.in_member = true;
    stl::check_member(&mut ctx, scope, member, label_prio)
}

/// Does the node contain an error node? A construct with a syntax error gets no diagnostics of
/// the rules that would read its broken parts (C1).
pub(crate) fn has_error(node: &SyntaxNode) -> bool {
    node.descendants().any(|n| n.kind() == SyntaxKind::ERROR)
}

pub(crate) fn check_workspace(db: &dyn salsa::Database, ws: Workspace) -> Vec<Diag> {
    let mut out = Vec::new();
    symbols::check_workspace(db, ws, &mut out);
    group::check_workspace(db, ws, &mut out);
    out
}

/// The global symbols used anywhere in a file (HG6004), per item, unioned.
#[salsa::tracked(returns(ref))]
pub fn file_symbol_uses(db: &dyn salsa::Database, ws: Workspace, file: File) -> BTreeSet<String> {
    let mut uses = BTreeSet::new();
    for index in 0..db::file_summary(db, file).items.len() {
        let item = ItemLoc::new(db, file, index as u32);
        uses.extend(db::item_analysis(db, ws, item).used_symbols.iter().cloned());
    }
    uses
}

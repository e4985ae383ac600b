//! The salsa database: inputs (one per file, plus the workspace with its configuration and
//! imported symbol tables) and the queries from text to diagnostics.
//!
//! ```text
//! File.contents ─ parse ─┬─ file_summary (item kinds and names, mnemonic)  ─┐
//!                        └─ item_syntax (one green node per item) ──┬────────┼─ global_index
//!                                                                   │        │
//!                                    item_diagnostics(ws, item) ◄───┴────────┘
//!                                                 │
//!                  file_diagnostics(ws, file) ◄───┴── workspace_diagnostics(ws)
//! ```
//!
//! Every item is analysed from its own green node, whose offsets start at the item. A green
//! node does not know where it stands in the file, so an edit in one item leaves the green
//! nodes of the others equal: salsa backdates them, and their analyses are reused. Ranges are
//! made absolute only at the very end ([`file_diagnostics`]).

use std::sync::Arc;

use higraph_syntax::{GreenNode, Parse, SyntaxKind, SyntaxNode, TextRange, TextSize, ast};

use crate::{
    FileContents,
    config::Config,
    diag::{Diag, Loc},
    index::GlobalIndex,
    lang::Mnemonic,
    rules::{self, graph::facts::MemberFacts},
    sdf::Import,
};

/// One file of the workspace.
#[salsa::input(debug)]
pub struct File {
    /// Workspace-relative path with `/` separators.
    #[returns(ref)]
    pub path: String,
    #[returns(ref)]
    pub contents: Arc<FileContents>,
    /// The previous parse and the edit that turned its text into `contents`, when the host
    /// knows them ([`crate::AnalysisHost::apply_edits`]): [`parse`] then reparses only the
    /// edited block.
    #[returns(ref)]
    pub reparse_base: Option<Arc<ReparseBase>>,
}

/// What [`parse`] needs to reparse a file incrementally.
#[derive(Debug, PartialEq, Eq)]
pub struct ReparseBase {
    pub old: Parse,
    pub edit: higraph_syntax::Edit,
}

/// The workspace: its files in workspace order, configuration and imports.
#[salsa::input(debug)]
pub struct Workspace {
    /// The `.higraph` files in workspace order.
    #[returns(ref)]
    pub files: Vec<File>,
    #[returns(ref)]
    pub config: Arc<Config>,
    /// `higraph.toml` itself, if the workspace has one (for HG6101 and HG6005 ranges).
    #[returns(copy)]
    pub config_file: Option<File>,
    /// Imported STEP 7 symbol tables, in `higraph.toml` order.
    #[returns(ref)]
    pub imports: Vec<Import>,
}

/// One top-level item of a file, by position in the file's item list.
#[salsa::interned(debug)]
pub struct ItemLoc<'db> {
    #[returns(copy)]
    pub file: File,
    #[returns(copy)]
    pub index: u32,
}

/// What kind of item stands at a position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ItemKind {
    Mnemonic,
    Graph,
    Group,
    Chart,
    Symbols,
    BlockInterface,
    /// A `test` item (`runtime.md` §5); test names have their own namespace.
    Test,
}

/// Per item: its kind and name. Position-independent, so edits inside items leave it equal.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FileSummary {
    pub items: Vec<ItemSummary>,
    /// The first `mnemonic` directive of the file.
    pub mnemonic: Option<Mnemonic>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ItemSummary {
    pub kind: ItemKind,
    pub name: Option<String>,
    /// The name token, relative to the item's start.
    pub name_range: Option<TextRange>,
    /// A chart type (`chart type NAME`), which no test can run.
    pub chart_type: bool,
}

/// The database. Clones are cheap snapshots for concurrent readers.
#[salsa::db]
#[derive(Clone, Default)]
pub struct RootDatabase {
    storage: salsa::Storage<Self>,
}

#[salsa::db]
impl salsa::Database for RootDatabase {}

impl RootDatabase {
    /// A database that reports every salsa event to `on_event` (tests use it to record which
    /// queries executed).
    pub fn with_event_callback(
        on_event: impl Fn(salsa::Event) + Send + Sync + 'static,
    ) -> RootDatabase {
        RootDatabase {
            storage: salsa::Storage::new(Some(Box::new(on_event))),
        }
    }
}

/// The syntax tree of a file. Files that are not text have an empty tree.
#[salsa::tracked(returns(ref))]
pub fn parse(db: &dyn salsa::Database, file: File) -> Parse {
    match (&**file.contents(db), file.reparse_base(db)) {
        (FileContents::Text(text), Some(base)) => base.old.reparse(&base.edit, text),
        (FileContents::Text(text), None) => higraph_syntax::parse(text),
        _ => higraph_syntax::parse(""),
    }
}

/// The top-level item nodes of a parse, in text order.
pub fn item_nodes(parse: &Parse) -> impl Iterator<Item = SyntaxNode> + use<> {
    parse
        .syntax_node()
        .children()
        .filter(|n| ast::Item::cast(n.clone()).is_some())
}

fn item_kind(kind: SyntaxKind) -> Option<ItemKind> {
    Some(match kind {
        SyntaxKind::MNEMONIC => ItemKind::Mnemonic,
        SyntaxKind::GRAPH => ItemKind::Graph,
        SyntaxKind::GROUP => ItemKind::Group,
        SyntaxKind::CHART => ItemKind::Chart,
        SyntaxKind::SYMBOLS => ItemKind::Symbols,
        SyntaxKind::BLOCK_INTERFACE => ItemKind::BlockInterface,
        SyntaxKind::TEST => ItemKind::Test,
        _ => return None,
    })
}

/// The kinds and names of a file's items, and its mnemonic directive.
#[salsa::tracked(returns(ref))]
pub fn file_summary(db: &dyn salsa::Database, file: File) -> FileSummary {
    let parse = parse(db, file);
    let mut summary = FileSummary::default();
    for node in item_nodes(parse) {
        let Some(kind) = item_kind(node.kind()) else {
            continue;
        };
        let start = node.text_range().start();
        let mut chart_type = false;
        let name_node = match ast::Item::cast(node.clone()) {
            Some(ast::Item::Graph(g)) => g.name(),
            Some(ast::Item::Group(g)) => g.name(),
            Some(ast::Item::Chart(c)) => {
                chart_type = c.is_type();
                c.name()
            }
            Some(ast::Item::Test(t)) => t.name(),
            Some(ast::Item::Mnemonic(m)) => {
                let set = m.set().and_then(|t| Mnemonic::parse(t.text()));
                if summary.mnemonic.is_none() {
                    summary.mnemonic = set;
                }
                None
            }
            _ => None,
        };
        let name = name_node.as_ref().map(|n| n.text());
        let name_range = name_node
            .and_then(|n| n.token())
            .map(|t| t.text_range() - start);
        summary.items.push(ItemSummary {
            kind,
            name,
            name_range,
            chart_type,
        });
    }
    summary
}

/// A green node compared with [`higraph_syntax::green_eq`]: two versions of a tree are
/// equal in time proportional to what an edit changed.
#[derive(Debug, Clone, Eq)]
pub struct Green(pub GreenNode);

impl PartialEq for Green {
    fn eq(&self, other: &Green) -> bool {
        higraph_syntax::green_eq(&self.0, &other.0)
    }
}

/// The green nodes of a file's items, in text order: one walk over the file's top level,
/// so that [`item_syntax`] of each item costs a lookup, not a walk to the item.
#[salsa::tracked(returns(ref))]
pub fn file_items(db: &dyn salsa::Database, file: File) -> Vec<Green> {
    item_nodes(parse(db, file))
        .map(|n| Green(n.green().to_owned()))
        .collect()
}

/// The green node of one item: its syntax with offsets relative to the item's start.
#[salsa::tracked(returns(clone))]
pub fn item_syntax<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> Option<Green> {
    file_items(db, item.file(db))
        .get(item.index(db) as usize)
        .cloned()
}

/// A graph member's green node (a `state`, `trans`, variable section, ...), compared and
/// hashed by address: equal addresses are the same node (the interned [`Chunk`] keeps it
/// alive), and equal content at another address only costs a recomputation. An incremental
/// reparse keeps the green nodes of the members it did not touch, so their analyses are
/// found again.
#[derive(Debug, Clone)]
pub struct MemberGreen(pub GreenNode);

impl PartialEq for MemberGreen {
    fn eq(&self, other: &MemberGreen) -> bool {
        std::ptr::eq::<higraph_syntax::rowan::GreenNodeData>(&*self.0, &*other.0)
    }
}

impl Eq for MemberGreen {}

impl std::hash::Hash for MemberGreen {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        std::ptr::hash::<higraph_syntax::rowan::GreenNodeData, H>(&*self.0, state)
    }
}

impl MemberGreen {
    /// The member's own tree (offsets relative to the member's start).
    pub fn root(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.0.clone())
    }
}

/// A run of consecutive members of a graph: each member's green node with its offset from
/// the chunk's start. Per-member results are gathered chunk by chunk ([`chunk_facts`],
/// [`chunk_stl`]), so that after a keystroke the graph's analysis touches a few hundred
/// memoized chunks instead of thousands of members.
#[salsa::interned(debug)]
pub struct Chunk<'db> {
    #[returns(ref)]
    pub members: Vec<(MemberGreen, TextSize)>,
}

/// The members of a graph item in chunks, with the chunks' offsets in the item.
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct GraphLayout<'db> {
    pub chunks: Vec<Chunk<'db>>,
    pub offsets: Vec<TextSize>,
    /// See [`GraphFacts::virtual_ok`].
    pub virtual_ok: bool,
}

impl GraphLayout<'_> {
    /// The offset in the item of every member, in text order.
    pub fn member_offsets(&self, db: &dyn salsa::Database) -> Vec<TextSize> {
        let mut offsets = Vec::new();
        for (chunk, &start) in self.chunks.iter().zip(&self.offsets) {
            offsets.extend(chunk.members(db).iter().map(|(_, offset)| start + *offset));
        }
        offsets
    }
}

/// Where chunks end is decided by the members themselves (content-defined chunking): after a
/// member whose address hashes to 0 modulo 16, and after at most 64 members. A changed
/// member is a new node at a new address, so an edit moves at most the two boundaries around
/// it, and every other chunk stays the same interned value.
fn ends_chunk(member: &MemberGreen, len: usize) -> bool {
    const MAX_MEMBERS: usize = 64;
    let address = &*member.0 as *const higraph_syntax::rowan::GreenNodeData as usize;
    let mixed = (address >> 4).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    (mixed >> 60) == 0 || len >= MAX_MEMBERS
}

/// The layout of a graph item (empty for other items). Runs on every edit of the item, but
/// only walks the green children of the graph's body.
#[salsa::tracked(returns(ref))]
pub fn graph_layout<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> GraphLayout<'db> {
    use higraph_syntax::rowan::NodeOrToken;
    let mut layout = GraphLayout::default();
    let Some(Green(graph)) = item_syntax(db, item) else {
        return layout;
    };
    if graph.kind() != SyntaxKind::GRAPH.into() {
        return layout;
    }
    let mut offset = TextSize::from(0);
    layout.virtual_ok = true;
    for child in graph.children() {
        let len = child.text_len();
        if let NodeOrToken::Node(body) = child
            && body.kind() == SyntaxKind::BODY.into()
        {
            layout.virtual_ok = u32::from(offset) < crate::rules::graph::VirtualLayout::SLOT
                && body.children().len() < crate::rules::graph::VirtualLayout::MAX_MEMBERS;
            let mut at = offset;
            let mut chunk: Vec<(MemberGreen, TextSize)> = Vec::new();
            let mut start = at;
            for element in body.children() {
                if let NodeOrToken::Node(node) = element {
                    if chunk.is_empty() {
                        start = at;
                    }
                    if u32::from(node.text_len()) >= crate::rules::graph::VirtualLayout::SLOT {
                        layout.virtual_ok = false;
                    }
                    let member = MemberGreen(node.to_owned());
                    let done = ends_chunk(&member, chunk.len() + 1);
                    chunk.push((member, at - start));
                    if done {
                        layout
                            .chunks
                            .push(Chunk::new(db, std::mem::take(&mut chunk)));
                        layout.offsets.push(start);
                    }
                }
                at += element.text_len();
            }
            if !chunk.is_empty() {
                layout.chunks.push(Chunk::new(db, chunk));
                layout.offsets.push(start);
            }
        }
        offset += len;
    }
    layout
}

/// The facts of every member of a chunk, in order. A chunk is small, so recomputing it
/// whole after an edit costs less than salsa would spend verifying per-member queries.
#[salsa::tracked(returns(ref))]
pub fn chunk_facts<'db>(db: &'db dyn salsa::Database, chunk: Chunk<'db>) -> Arc<[MemberFacts]> {
    chunk
        .members(db)
        .iter()
        .map(|(green, _)| MemberFacts::of(&green.root()))
        .collect()
}

/// The facts of every member of a graph, in text order, without positions: equal as long as
/// no member's facts change, whatever an edit did to offsets or chunk boundaries. The
/// graph's structure rules depend on this alone ([`graph_structure`]), so a keystroke that
/// changes no fact (most keystrokes in instructions) does not run them.
#[derive(Debug, Clone, Eq, Default)]
pub struct GraphFacts {
    pub chunks: Vec<Arc<[MemberFacts]>>,
    /// Can positions be expressed as (member, offset in member) in the virtual layout of
    /// [`crate::rules::graph::VirtualLayout`]? (Members shorter than 64 KiB, fewer than
    /// 65535 of them, the graph's `<` within its first 64 KiB.)
    pub virtual_ok: bool,
}

impl GraphFacts {
    pub fn members(&self) -> impl Iterator<Item = &MemberFacts> + Clone {
        self.chunks.iter().flat_map(|c| c.iter())
    }
}

impl PartialEq for GraphFacts {
    fn eq(&self, other: &GraphFacts) -> bool {
        if self.virtual_ok != other.virtual_ok {
            return false;
        }
        // Usually the chunks line up and all but the edited one are the same allocation.
        let aligned = self.chunks.len() == other.chunks.len()
            && self
                .chunks
                .iter()
                .zip(&other.chunks)
                .all(|(a, b)| a.len() == b.len());
        if aligned {
            self.chunks
                .iter()
                .zip(&other.chunks)
                .all(|(a, b)| Arc::ptr_eq(a, b) || a == b)
        } else {
            self.members().eq(other.members())
        }
    }
}

/// The member facts of a graph item (empty for other items).
#[salsa::tracked(returns(ref))]
pub fn graph_facts<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> GraphFacts {
    let layout = graph_layout(db, item);
    GraphFacts {
        chunks: layout
            .chunks
            .iter()
            .map(|&chunk| chunk_facts(db, chunk).clone())
            .collect(),
        virtual_ok: layout.virtual_ok,
    }
}

/// What the structure rules of a graph found, with positions in the virtual layout (see
/// [`crate::rules::graph::VirtualLayout`]), and the priorities transition labels show.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct GraphStructure {
    pub diags: Vec<Diag>,
    /// Per transition, in text order: the priority its label shows (§2.3), if any.
    pub label_prios: Vec<Option<u64>>,
}

/// The structure rules of a graph (numbering, endpoints, priorities, startup, reachability,
/// operating modes) on its member facts and header. Positions do not move with edits, so
/// this is recomputed only when a fact or the header changes.
#[salsa::tracked(returns(ref))]
pub fn graph_structure<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> GraphStructure {
    rules::check_graph_structure(db, ws, item)
}

/// The header of a graph item, as the structure rules need it (`None` for other items).
#[salsa::tracked(returns(ref))]
pub(crate) fn graph_header<'db>(
    db: &'db dyn salsa::Database,
    item: ItemLoc<'db>,
) -> Option<rules::graph::GraphHeader> {
    match item_root(db, item).and_then(ast::Item::cast) {
        Some(ast::Item::Graph(graph)) => Some(rules::graph::GraphHeader::of(&graph)),
        _ => None,
    }
}

/// What a graph declares (the scope its operands resolve in), without uses.
#[salsa::tracked(returns(ref))]
pub(crate) fn graph_scope<'db>(
    db: &'db dyn salsa::Database,
    item: ItemLoc<'db>,
) -> Option<crate::resolve::GraphScope> {
    match item_root(db, item).and_then(ast::Item::cast) {
        Some(ast::Item::Graph(graph)) => Some(crate::resolve::GraphScope::new(&graph)),
        _ => None,
    }
}

/// The operating-mode facts of a chunk's members, merged (for the graph's interface).
#[salsa::tracked(returns(ref))]
pub(crate) fn chunk_modes<'db>(
    db: &'db dyn salsa::Database,
    chunk: Chunk<'db>,
) -> rules::group::interface::ModeFacts {
    let mut modes = rules::group::interface::ModeFacts::default();
    for (green, _) in chunk.members(db) {
        modes.merge(&rules::group::interface::ModeFacts::of(&green.root()));
    }
    modes
}

/// The STL findings of a chunk's members, merged; places relative to the chunk (still
/// marked [`crate::diag::Loc::in_member`]). `label_prios` holds, for each transition of the
/// chunk in order, the priority its label shows, if any.
#[salsa::tracked(returns(ref))]
pub(crate) fn chunk_stl<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
    chunk: Chunk<'db>,
    label_prios: Vec<Option<u64>>,
) -> rules::stl::MemberStl {
    let mut merged = rules::stl::MemberStl::default();
    let mut prios = label_prios.into_iter();
    for ((green, offset), facts) in chunk.members(db).iter().zip(chunk_facts(db, chunk).iter()) {
        let label_prio = match facts {
            MemberFacts::Trans(_) => prios.next().flatten(),
            MemberFacts::State(_) | MemberFacts::Permanent { .. } => None,
            MemberFacts::Other => continue,
        };
        let found = rules::check_member_stl(db, ws, item, &green.root(), label_prio);
        merged.merge(&found, *offset);
    }
    merged
}

/// The item's syntax tree, rooted at the item (offsets relative to the item's start).
pub fn item_root(db: &dyn salsa::Database, item: ItemLoc<'_>) -> Option<SyntaxNode> {
    item_syntax(db, item).map(|green| SyntaxNode::new_root(green.0))
}

/// Where each item of a file starts (to make item-relative ranges absolute).
#[salsa::tracked(returns(ref))]
pub fn item_offsets(db: &dyn salsa::Database, file: File) -> Vec<TextSize> {
    item_nodes(parse(db, file))
        .map(|n| n.text_range().start())
        .collect()
}

/// The mnemonic set of a file: its directive, else the workspace setting.
pub fn file_mnemonic(db: &dyn salsa::Database, ws: Workspace, file: File) -> Mnemonic {
    file_summary(db, file)
        .mnemonic
        .unwrap_or(ws.config(db).mnemonic)
}

/// All global names of the workspace: graphs, groups, charts, symbols, block interfaces.
#[salsa::tracked(returns(ref))]
pub fn global_index(db: &dyn salsa::Database, ws: Workspace) -> GlobalIndex {
    GlobalIndex::build(db, ws)
}

/// The rules' findings in one item: diagnostics (ranges relative to the item unless a `Loc`
/// names another place) and the global symbols it uses.
#[salsa::tracked(returns(ref))]
pub fn item_analysis<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> rules::ItemAnalysis {
    rules::check_item(db, ws, item)
}

/// The diagnostics of one item.
pub fn item_diagnostics<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> &'db [Diag] {
    &item_analysis(db, ws, item).diags
}

/// Diagnostics that need the whole workspace (duplicate global names, unused symbols, ...).
#[salsa::tracked(returns(ref))]
pub fn workspace_diagnostics(db: &dyn salsa::Database, ws: Workspace) -> Vec<Diag> {
    rules::check_workspace(db, ws)
}

/// Makes a `Loc` absolute: the range in its file.
pub fn absolute_range(db: &dyn salsa::Database, loc: &Loc) -> TextRange {
    match loc.item {
        Some(index) => {
            let offset = item_offsets(db, loc.file)
                .get(index as usize)
                .copied()
                .unwrap_or_default();
            loc.range + offset
        }
        None => loc.range,
    }
}

//! HG81xx: what `build` needs beyond `check` (`export.md` §3–§4). `check` never reports these
//! codes; `build` reports them for the groups and charts it covers, and refuses to build when
//! one of them is an error.
//!
//! | code   | target  | what |
//! |--------|---------|------|
//! | HG8101 | awl     | a group without `fc` or `db`; fix: insert the next free numbers |
//! | HG8102 | awl     | text the STEP 7 source would contain that Windows-1252 cannot encode |
//! | HG8103 | plcopen | a chart variable, symbol, address or constant of an S7-only type |
//! | HG8104 | plcopen | (info) PCS 7 chart logic PLCopen cannot express: kept in the documentation |
//! | HG8105 | awl     | a group's FC is declared as an external block by a `block` item |
//! | HG8106 | plcopen | a name declared in a chart is a keyword of IEC 61131-3 |
//!
//! Everything per item is a salsa query (`group_encoding`, `item_block_numbers`, `chart_rules`),
//! so that the language server can ask for these diagnostics after every edit and pay only for
//! the edited items.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::sync::OnceLock;

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
};

use super::Target;
use crate::address::{self, Area, BlockKind};
use crate::db::{self, File, ItemKind, ItemLoc, Workspace};
use crate::diag::{Diag, Loc};
use crate::index::{GlobalIndex, SymbolSource, key};
use crate::lang::Type;
use crate::rules::group::blocks::{Clause, generated_blocks};
use crate::rules::symbols::resolve_block_ref;
use crate::{Analysis, Cancellable, Diagnostic, FileId, check};

/// The build-only diagnostics of the groups and charts `(file, item)` for `target`.
pub(super) fn diagnostics(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    target: Target,
) -> Vec<(File, Diagnostic)> {
    let diags = build_diags(db, ws, groups, charts, target);
    check::convert_extra(db, ws, &diags)
}

impl Analysis {
    /// The build-only diagnostics (HG81xx) of every group and chart of the workspace for
    /// `target`, as `build` would report them (configured severities and `higraph-allow`
    /// comments applied), with the output file of each ([`Analysis::files`]). For the
    /// fixtures and for the language server, which can show them (HG8101's quick fix
    /// inserts the missing `fc`/`db`) without running a build.
    pub fn build_diagnostics(&self, target: Target) -> Cancellable<Vec<(FileId, Diagnostic)>> {
        self.with_db(|db, ws| {
            let (groups, charts) = workspace_items(db, ws);
            let ids = &check::output_file_table(db, ws).ids;
            diagnostics(db, ws, &groups, &charts, target)
                .into_iter()
                .filter_map(|(file, d)| Some((*ids.get(&file)?, d)))
                .collect()
        })
    }
}

/// Items as `(file, index in the file)`.
type Items = Vec<(File, u32)>;

/// The fix of HG8101 for the group of `file` whose name token is at `name_range` (absolute),
/// converted like a diagnostic's fix; `None` if that group has both clauses, HG8101 is switched
/// off, or no free number is left. The language server shows no HG81xx (they depend on the
/// build target, and `check` accepts what they report); it offers this fix as a quick fix of
/// `check`'s HG8002/HG8003 on the same name ([`crate::ide::code_actions`]).
pub(crate) fn missing_clause_fix(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    name_range: TextRange,
) -> Option<crate::Fix> {
    let offsets = db::item_offsets(db, file);
    let item = db::file_summary(db, file)
        .items
        .iter()
        .enumerate()
        .find(|(i, summary)| {
            summary.kind == ItemKind::Group
                && summary
                    .name_range
                    .zip(offsets.get(*i))
                    .is_some_and(|(range, &offset)| range + offset == name_range)
        })
        .map(|(i, _)| i as u32)?;
    let free = free_numbers(db, ws).get(&(file, item));
    let diag = missing_clauses(db, ItemLoc::new(db, file, item), free)?;
    check::convert_extra(db, ws, &[diag])
        .into_iter()
        .next()
        .and_then(|(_, d)| d.fixes.into_iter().next())
}

/// Every group and every chart of the workspace, in workspace order.
pub(crate) fn workspace_items(db: &dyn salsa::Database, ws: Workspace) -> (Items, Items) {
    let mut groups = Vec::new();
    let mut charts = Vec::new();
    for &file in ws.files(db) {
        for (i, item) in db::file_summary(db, file).items.iter().enumerate() {
            match item.kind {
                ItemKind::Group => groups.push((file, i as u32)),
                ItemKind::Chart => charts.push((file, i as u32)),
                _ => {}
            }
        }
    }
    (groups, charts)
}

/// The diagnostics before conversion, each once (a graph two groups instantiate is looked at
/// once), in the order groups, then charts.
fn build_diags(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    target: Target,
) -> Vec<Diag> {
    let mut out = Vec::new();
    let mut seen: HashSet<Diag> = HashSet::new();
    let mut push = |diag: &Diag, out: &mut Vec<Diag>| {
        if seen.insert(diag.clone()) {
            out.push(diag.clone());
        }
    };
    if target.awl() {
        let free = free_numbers(db, ws);
        let index = db::global_index(db, ws);
        let mut graphs_done: HashSet<(File, u32)> = HashSet::new();
        let mut symbols_done: HashSet<String> = HashSet::new();
        for &(file, item) in groups {
            let loc = ItemLoc::new(db, file, item);
            if let Some(diag) = missing_clauses(db, loc, free.get(&(file, item))) {
                push(&diag, &mut out);
            }
            for diag in external_block_clashes(db, ws, file, item) {
                push(&diag, &mut out);
            }
            let mut items = vec![loc];
            for graph in instantiated_graphs(db, ws, loc) {
                if graphs_done.insert(graph) {
                    items.push(ItemLoc::new(db, graph.0, graph.1));
                }
            }
            for &item in &items {
                for diag in item_encoding(db, item) {
                    push(diag, &mut out);
                }
                let used = &db::item_analysis(db, ws, item).used_symbols;
                for name in used {
                    if symbols_done.insert(name.clone()) {
                        for diag in symbol_encoding(db, index, name) {
                            push(&diag, &mut out);
                        }
                    }
                }
            }
        }
    }
    if target.plcopen() {
        for &(file, item) in charts {
            for diag in chart_rules(db, ws, ItemLoc::new(db, file, item)) {
                push(diag, &mut out);
            }
        }
    }
    out
}

// ============================================================================ HG8101

/// The clause of a group, if written (also when its name is missing).
fn clause_node(group: &ast::Group, kind: SyntaxKind) -> Option<SyntaxNode> {
    group.syntax().children().find(|n| n.kind() == kind)
}

/// HG8101 for one group, with the fix inserting the numbers `free` assigns to it.
fn missing_clauses(
    db: &dyn salsa::Database,
    item: ItemLoc<'_>,
    free: Option<&(Option<u32>, Option<u32>)>,
) -> Option<Diag> {
    let group = db::item_root(db, item).and_then(ast::Group::cast)?;
    let fc = clause_node(&group, SyntaxKind::FC_CLAUSE);
    let db_clause = clause_node(&group, SyntaxKind::DB_CLAUSE);
    if fc.is_some() && db_clause.is_some() {
        return None;
    }
    let name = group.name()?;
    let token = name.token()?;
    let group_name = name.text();
    let what = match (&fc, &db_clause) {
        (None, None) => "'fc' and 'db' clauses",
        (None, Some(_)) => "'fc' clause",
        _ => "'db' clause",
    };
    let at = |range| Loc::in_item(item.file(db), item.index(db), range);
    let mut diag = Diag::new(
        "HG8101",
        at(token.text_range()),
        format!("group {group_name} has no {what}; build generates the FC and DB they name"),
    );
    let (free_fc, free_db) = free.copied().unwrap_or_default();
    // The grammar: `group NAME [fc block_name] [db block_name] [STRING]`.
    let fix = match (&fc, &db_clause) {
        (None, None) => free_fc.zip(free_db).map(|(f, d)| {
            (
                name.syntax().text_range().end(),
                format!("fc FC {f} db DB {d}"),
            )
        }),
        (None, Some(_)) => {
            free_fc.map(|f| (name.syntax().text_range().end(), format!("fc FC {f}")))
        }
        (Some(fc), None) => free_db.map(|d| (fc.text_range().end(), format!("db DB {d}"))),
        (Some(_), Some(_)) => None,
    };
    if let Some((offset, text)) = fix {
        diag = diag
            .fix(
                format!("Insert '{text}'"),
                at(TextRange::empty(offset)),
                format!(" {text}"),
            )
            .preferred();
    }
    Some(diag)
}

/// The FC and DB numbers the fix of HG8101 inserts in each group that lacks a clause: the
/// smallest numbers from 1 that no group's `fc`/`db`, no block reference or address of any
/// item and no symbol uses, handed out in workspace order so that two fixes never collide.
#[salsa::tracked(returns(ref))]
fn free_numbers(
    db: &dyn salsa::Database,
    ws: Workspace,
) -> HashMap<(File, u32), (Option<u32>, Option<u32>)> {
    let (groups, _) = workspace_items(db, ws);
    // The groups that lack a clause; most workspaces have none, and then nothing is scanned.
    let wanting: Vec<(File, u32, bool, bool)> = groups
        .into_iter()
        .filter_map(|(file, item)| {
            let group =
                db::item_root(db, ItemLoc::new(db, file, item)).and_then(ast::Group::cast)?;
            let need_fc = clause_node(&group, SyntaxKind::FC_CLAUSE).is_none();
            let need_db = clause_node(&group, SyntaxKind::DB_CLAUSE).is_none();
            (need_fc || need_db).then_some((file, item, need_fc, need_db))
        })
        .collect();
    if wanting.is_empty() {
        return HashMap::new();
    }
    let mut used_fc: HashSet<u32> = HashSet::new();
    let mut used_db: HashSet<u32> = HashSet::new();
    for block in generated_blocks(db, ws) {
        match block.clause {
            Clause::Fc => used_fc.insert(block.number),
            Clause::Db => used_db.insert(block.number),
        };
    }
    for symbol in &db::global_index(db, ws).symbols {
        if let Some(address) = &symbol.address {
            note_address(address, &mut used_fc, &mut used_db);
        }
    }
    for &file in ws.files(db) {
        for item in 0..db::file_summary(db, file).items.len() {
            let numbers = item_block_numbers(db, ws, ItemLoc::new(db, file, item as u32));
            for &(fc, n) in numbers {
                if fc {
                    used_fc.insert(n);
                } else {
                    used_db.insert(n);
                }
            }
        }
    }
    let mut next_fc = 1u32;
    let mut next_db = 1u32;
    let mut free = HashMap::new();
    for (file, item, need_fc, need_db) in wanting {
        let fc = need_fc.then(|| next_free(&mut next_fc, &used_fc)).flatten();
        let dbn = need_db.then(|| next_free(&mut next_db, &used_db)).flatten();
        free.insert((file, item), (fc, dbn));
    }
    free
}

/// The smallest number from `*next` that `used` does not hold (at most 65535, the largest
/// block number); `*next` moves past it.
fn next_free(next: &mut u32, used: &HashSet<u32>) -> Option<u32> {
    while *next <= 65535 {
        let n = *next;
        *next += 1;
        if !used.contains(&n) {
            return Some(n);
        }
    }
    None
}

fn note_address(address: &address::Address, fc: &mut HashSet<u32>, dbs: &mut HashSet<u32>) {
    match address.block_kind() {
        Some(BlockKind::Fc) => {
            fc.insert(address.number);
        }
        Some(BlockKind::Db) => {
            dbs.insert(address.number);
        }
        _ => {}
    }
    if address.area == Area::DataBlock
        && let Some(n) = address.db
    {
        dbs.insert(n);
    }
}

/// The FC (`true`) and DB (`false`) numbers one item refers to: block references (CALL
/// targets and instance DBs, `block` interfaces, `fc`/`db` clauses) and addresses
/// (`FC 10`, `DB10.DBX 0.0`).
#[salsa::tracked(returns(ref))]
fn item_block_numbers<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> Vec<(bool, u32)> {
    let Some(root) = db::item_root(db, item) else {
        return Vec::new();
    };
    let set = db::file_mnemonic(db, ws, item.file(db));
    let index = db::global_index(db, ws);
    let mut fc = HashSet::new();
    let mut dbs = HashSet::new();
    for node in root.descendants() {
        match node.kind() {
            SyntaxKind::BLOCK_REF => {
                if let Some(address) = ast::BlockRef::cast(node)
                    .and_then(|r| resolve_block_ref(index, set, &r).address())
                {
                    note_address(&address, &mut fc, &mut dbs);
                }
            }
            SyntaxKind::ADDRESS => {
                if let Some(address) = ast::Address::cast(node)
                    .and_then(|a| address::read(&a.compact_text(), set))
                    .and_then(|r| r.address.ok())
                {
                    note_address(&address, &mut fc, &mut dbs);
                }
            }
            _ => {}
        }
    }
    let mut numbers: Vec<(bool, u32)> = fc
        .into_iter()
        .map(|n| (true, n))
        .chain(dbs.into_iter().map(|n| (false, n)))
        .collect();
    numbers.sort_unstable();
    numbers
}

// ============================================================================ HG8105

/// The FCs that `block` items declare as external blocks: number → the first item's block
/// reference (place and text).
#[salsa::tracked(returns(ref))]
fn external_fcs(db: &dyn salsa::Database, ws: Workspace) -> HashMap<u32, (Loc, String)> {
    let index = db::global_index(db, ws);
    let mut fcs = HashMap::new();
    for entry in &index.block_interfaces {
        let Some(reference) = db::item_root(db, ItemLoc::new(db, entry.file, entry.item))
            .and_then(ast::BlockInterface::cast)
            .and_then(|b| b.block())
        else {
            continue;
        };
        let set = db::file_mnemonic(db, ws, entry.file);
        let Some(address) = resolve_block_ref(index, set, &reference).address() else {
            continue;
        };
        if address.block_kind() == Some(BlockKind::Fc) {
            let text = entry
                .reference
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            fcs.entry(address.number)
                .or_insert((entry.reference_loc, text));
        }
    }
    fcs
}

/// HG8105: the FC a group generates is declared by a `block` item as a block outside the
/// workspace (`check` reports calls of it, HG8010, but not the declaration).
fn external_block_clashes(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
) -> Vec<Diag> {
    let external = external_fcs(db, ws);
    if external.is_empty() {
        return Vec::new();
    }
    generated_blocks(db, ws)
        .iter()
        .filter(|b| b.clause == Clause::Fc && b.name_loc.file == file && b.name_loc.item == Some(item))
        .filter_map(|block| {
            let (at, written) = external.get(&block.number)?;
            Some(
                Diag::new(
                    "HG8105",
                    block.name_loc,
                    format!(
                        "FC {} is declared as an external block by 'block {written}'; building group {} would overwrite it",
                        block.number, block.group
                    ),
                )
                .related(*at, format!("'block {written}' declares FC {}", block.number)),
            )
        })
        .collect()
}

// ============================================================================ HG8102

/// The graphs a group instantiates (each once, in run order).
fn instantiated_graphs(
    db: &dyn salsa::Database,
    ws: Workspace,
    group: ItemLoc<'_>,
) -> Vec<(File, u32)> {
    let Some(group) = db::item_root(db, group).and_then(ast::Group::cast) else {
        return Vec::new();
    };
    let index = db::global_index(db, ws);
    let mut graphs = Vec::new();
    for instance in group.instances() {
        let Some(graph) = instance.graph().and_then(|g| index.graph(&g.text())) else {
            continue;
        };
        let at = (graph.file, graph.item);
        if !graphs.contains(&at) {
            graphs.push(at);
        }
    }
    graphs
}

/// The characters Windows-1252 can encode beyond ASCII: what `encoding_rs` decodes its 128
/// upper bytes to (the same table the writer encodes with).
fn cp1252_upper() -> &'static HashSet<char> {
    static SET: OnceLock<HashSet<char>> = OnceLock::new();
    SET.get_or_init(|| {
        let bytes: Vec<u8> = (0x80..=0xFF).collect();
        let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(&bytes);
        text.chars().collect()
    })
}

/// Can Windows-1252 encode `c`?
pub(crate) fn in_cp1252(c: char) -> bool {
    c.is_ascii() || cp1252_upper().contains(&c)
}

/// HG8102 for a text at `at` (a token): one diagnostic covering its first through its last
/// character that Windows-1252 cannot encode; `None` if it has none.
fn encoding_diag(text: &str, at: Loc) -> Option<Diag> {
    // The first character Windows-1252 lacks, the end of the last one, and how many follow.
    let mut first: Option<(usize, char)> = None;
    let mut last_end = 0;
    let mut more = 0usize;
    for (i, c) in text.char_indices().filter(|&(_, c)| !in_cp1252(c)) {
        if first.is_none() {
            first = Some((i, c));
        } else {
            more += 1;
        }
        last_end = i + c.len_utf8();
    }
    let (first, c) = first?;
    let start = at.range.start() + TextSize::from(first as u32);
    let end = at.range.start() + TextSize::from(last_end as u32);
    let more = match more {
        0 => String::new(),
        1 => "; 1 more character of this text is not either".to_owned(),
        n => format!("; {n} more characters of this text are not either"),
    };
    Some(Diag::new(
        "HG8102",
        Loc {
            range: TextRange::new(start, end),
            ..at
        },
        format!(
            "'{c}' (U+{:04X}) is not in Windows-1252, the encoding of STEP 7 sources{more}",
            c as u32
        ),
    ))
}

/// HG8102 in one group or graph: every string (comments, display names, quoted symbols) and
/// character constant. Line comments (`//`) are not written into the source.
#[salsa::tracked(returns(ref))]
fn item_encoding<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> Vec<Diag> {
    // Most files are ASCII throughout: nothing to look at.
    if item.file(db).contents(db).text().is_ascii() {
        return Vec::new();
    }
    let Some(root) = db::item_root(db, item) else {
        return Vec::new();
    };
    let (file, index) = (item.file(db), item.index(db));
    root.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| {
            matches!(t.kind(), SyntaxKind::STRING | SyntaxKind::CHAR) && !t.text().is_ascii()
        })
        .filter_map(|t| encoding_diag(t.text(), Loc::in_item(file, index, t.text_range())))
        .collect()
}

/// HG8102 for a symbol the generated code uses (its name and comment go into `symbols.sdf`).
fn symbol_encoding(db: &dyn salsa::Database, index: &GlobalIndex, name: &str) -> Vec<Diag> {
    let Some(symbol) = index.symbol(name) else {
        return Vec::new();
    };
    match symbol.source {
        SymbolSource::Declared => {
            let at = symbol.name_loc;
            let Some(item) = at.item else {
                return Vec::new();
            };
            let wanted = key(&symbol.name);
            symbols_encoding(db, ItemLoc::new(db, at.file, item))
                .iter()
                .filter(|(name, _)| *name == wanted)
                .map(|(_, diag)| diag.clone())
                .collect()
        }
        SymbolSource::Imported(_) => {
            // An imported table was read from its file; point at the name.
            let text = format!("{}{}", symbol.name, symbol.comment.as_deref().unwrap_or(""));
            match text.chars().find(|&c| !in_cp1252(c)) {
                Some(c) => vec![Diag::new(
                    "HG8102",
                    symbol.name_loc,
                    format!(
                        "'{c}' (U+{:04X}) is not in Windows-1252, the encoding of STEP 7 sources",
                        c as u32
                    ),
                )],
                None => Vec::new(),
            }
        }
    }
}

/// HG8102 in the declarations of one `symbols` item, with the (upper case) name of the symbol
/// each belongs to; scanned once per item, not once per symbol.
#[salsa::tracked(returns(ref))]
fn symbols_encoding<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> Vec<(String, Diag)> {
    let Some(root) = db::item_root(db, item).and_then(ast::Symbols::cast) else {
        return Vec::new();
    };
    let (file, index) = (item.file(db), item.index(db));
    let mut out = Vec::new();
    for decl in root.symbols() {
        let name = key(&decl.name().map(|n| n.text()).unwrap_or_default());
        for token in tokens_of(decl.syntax())
            .filter(|t| t.kind() == SyntaxKind::STRING && !t.text().is_ascii())
        {
            if let Some(diag) =
                encoding_diag(token.text(), Loc::in_item(file, index, token.text_range()))
            {
                out.push((name.clone(), diag));
            }
        }
    }
    out
}

fn tokens_of(node: &SyntaxNode) -> impl Iterator<Item = SyntaxToken> + use<> {
    node.descendants_with_tokens()
        .filter_map(|e| e.into_token())
}

// ==================================================================== HG8103, HG8104

/// The S7-only types that IEC 61131-3 lacks.
fn s7_only(ty: Type) -> bool {
    matches!(ty, Type::S5Time | Type::Timer | Type::Counter)
}

/// HG8103, HG8104 and HG8106 in one chart.
#[salsa::tracked(returns(ref))]
fn chart_rules<'db>(db: &'db dyn salsa::Database, ws: Workspace, item: ItemLoc<'db>) -> Vec<Diag> {
    let Some(chart) = db::item_root(db, item).and_then(ast::Chart::cast) else {
        return Vec::new();
    };
    let file = item.file(db);
    let at = |range| Loc::in_item(file, item.index(db), range);
    let chart_name = chart.name().map(|n| n.text()).unwrap_or_default();
    // An IEC chart (`docs/iec.md`): its cyclic jumps, qualifiers, actions and function block
    // variables are IEC constructs the export writes as they are.
    let iec = chart.profile() == ast::Profile::Iec;
    let mut out = Vec::new();

    // HG8103: variables, then the symbols and addresses the chart uses, then constants.
    let mut vars: HashSet<String> = HashSet::new();
    for decl in chart
        .var_sections()
        .flat_map(|s| s.decls().collect::<Vec<_>>())
    {
        let name = decl.name().map(|n| n.text()).unwrap_or_default();
        vars.insert(key(&name));
        let Some(ty_ref) = decl.ty() else {
            continue;
        };
        if let Some(ty) = crate::index::declared_type(&ty_ref)
            && s7_only(ty)
        {
            out.push(Diag::new(
                "HG8103",
                at(ty_ref.syntax().text_range()),
                s7_message(&name, ty),
            ));
        }
    }
    let set = db::file_mnemonic(db, ws, file);
    let index = db::global_index(db, ws);
    let mut reported: BTreeSet<String> = BTreeSet::new();
    for path in chart.syntax().descendants().filter_map(ast::Path::cast) {
        let (written, found) = if let Some(address) = path.address() {
            let compact = address.compact_text();
            let ty = address::read(&compact, set)
                .and_then(|r| r.address.ok())
                .map(|a| a.ty());
            (compact.to_ascii_uppercase(), ty)
        } else if let Some(symbol) = path.symbol() {
            let name = symbol.name();
            let ty = index.symbol(&name).and_then(|s| s.ty);
            (key(&name), ty)
        } else {
            let segments: Vec<ast::NameRef> = path.segments().collect();
            let [name] = segments.as_slice() else {
                continue;
            };
            let name = name.text();
            if vars.contains(&key(&name)) {
                continue;
            }
            let ty = match index.symbol(&name) {
                Some(symbol) => symbol.ty,
                None => address::read(&name, set)
                    .filter(|r| !r.other_set)
                    .and_then(|r| r.address.ok())
                    .map(|a| a.ty()),
            };
            (key(&name), ty)
        };
        if let Some(ty) = found
            && s7_only(ty)
            && reported.insert(written)
        {
            let text = path.syntax().text().to_string();
            out.push(Diag::new(
                "HG8103",
                at(path.syntax().text_range()),
                s7_message(text.trim(), ty),
            ));
        }
    }
    for token in tokens_of(chart.syntax()).filter(|t| t.kind() == SyntaxKind::TYPED_CONST) {
        let upper = token.text().to_ascii_uppercase();
        // The initial value of a variable reported at its type is the same mistake.
        let in_reported_decl = token
            .parent_ancestors()
            .find_map(ast::VarDecl::cast)
            .and_then(|d| d.ty())
            .and_then(|t| crate::index::declared_type(&t))
            .is_some_and(s7_only);
        if !in_reported_decl && (upper.starts_with("S5T#") || upper.starts_with("S5TIME#")) {
            out.push(Diag::new(
                "HG8103",
                at(token.text_range()),
                s7_message(token.text(), Type::S5Time),
            ));
        }
    }

    // HG8106: declared names that IEC 61131-3 reserves.
    for node in chart
        .syntax()
        .descendants()
        .filter(|n| n.kind() == SyntaxKind::NAME)
    {
        let declares = node.parent().is_some_and(|p| {
            matches!(
                p.kind(),
                SyntaxKind::CHART
                    | SyntaxKind::VAR_DECL
                    | SyntaxKind::SEQUENCER
                    | SyntaxKind::STEP
                    | SyntaxKind::CHART_TRANS
                    | SyntaxKind::JUMP
                    | SyntaxKind::LOOP
                    | SyntaxKind::CHART_ACTION
            )
        });
        let Some(token) = node.first_token().filter(|t| t.kind() == SyntaxKind::IDENT) else {
            continue;
        };
        if declares && is_iec_keyword(token.text()) {
            out.push(Diag::new(
                "HG8106",
                at(token.text_range()),
                format!(
                    "'{}' is a keyword of IEC 61131-3; PLCopen tools cannot read it as a name",
                    token.text()
                ),
            ));
        }
    }

    // HG8104: the chart's properties, then `min`/`max` and `confirm` of its steps.
    let documented = |feature: String| {
        format!(
            "{feature} has no PLCopen equivalent; the export keeps it only in the documentation of {chart_name}"
        )
    };
    for prop in chart.props() {
        // `switching T` (transitions switch on their own) is what an IEC SFC does.
        let is_switching = prop
            .keyword()
            .is_some_and(|k| k.kind() == SyntaxKind::SWITCHING_KW);
        // The profile chooses how the chart is exported; nothing of it is lost.
        if prop
            .keyword()
            .is_some_and(|k| k.kind() == SyntaxKind::PROFILE_KW)
        {
            continue;
        }
        if is_switching
            && prop
                .value()
                .is_some_and(|v| v.text().eq_ignore_ascii_case("T"))
        {
            continue;
        }
        let range = item_range(prop.syntax());
        let text = collapsed(prop.syntax());
        out.push(Diag::new(
            "HG8104",
            at(range),
            documented(format!("'{text}'")),
        ));
    }
    let sequencers: Vec<ast::Sequencer> = chart.sequencers().collect();
    // One sequencer: its start step is the block's initial step, the caller decides when the
    // block runs; several of different priorities: one may displace another (`runtime.md` §4.4).
    if let [only] = sequencers.as_slice()
        && let Some(start) = only.start()
        && start.conditions().next().is_some()
        && let Some(keyword) = start.syntax().first_token()
    {
        let name = only.name().map(|n| n.text()).unwrap_or_default();
        out.push(Diag::new(
            "HG8104",
            at(keyword.text_range()),
            documented(format!(
                "the start condition of sequencer {name}, the chart's only sequencer,"
            )),
        ));
    }
    let prio = |s: &ast::Sequencer| {
        s.prio()
            .and_then(|p| p.value())
            .and_then(|v| v.text().parse::<i64>().ok())
            .unwrap_or(1)
    };
    if let Some(first) = sequencers.first()
        && sequencers.iter().any(|s| prio(s) != prio(first))
        && let Some(token) = chart.name().and_then(|n| n.token())
    {
        out.push(Diag::new(
            "HG8104",
            at(token.text_range()),
            documented("displacing a running sequencer by one of higher priority".to_owned()),
        ));
    }
    for sequencer in &sequencers {
        let name = sequencer.name().map(|n| n.text()).unwrap_or_default();
        let parts = [
            sequencer
                .pre()
                .map(|p| (p.syntax().clone(), p.statements().next().is_some())),
            sequencer
                .post()
                .map(|p| (p.syntax().clone(), p.statements().next().is_some())),
        ];
        for (part, written) in parts.into_iter().flatten() {
            if let (true, Some(keyword)) = (written, part.first_token()) {
                out.push(Diag::new(
                    "HG8104",
                    at(keyword.text_range()),
                    documented(format!("'{}' of sequencer {name}", keyword.text())),
                ));
            }
        }
    }
    // A jump or loop after a step without a successor transition (the end step, the last step
    // of a parallel branch): an IEC selection divergence needs that transition first.
    for node in chart
        .syntax()
        .descendants()
        .filter(|n| matches!(n.kind(), SyntaxKind::JUMP | SyntaxKind::LOOP))
    {
        let successor = std::iter::successors(node.next_sibling(), |n| n.next_sibling())
            .filter_map(ast::SeqElement::cast)
            .find(|e| !matches!(e, ast::SeqElement::Jump(_) | ast::SeqElement::Loop(_)));
        // In an IEC chart the jump is the step's exit: a transition and a jump step.
        if successor.is_some() || iec {
            continue;
        }
        let header_end = node
            .children()
            .find(|c| c.kind() == SyntaxKind::NAME)
            .map(|n| n.text_range().end());
        let (Some(first), Some(end)) = (node.first_token(), header_end) else {
            continue;
        };
        let header = TextRange::new(first.text_range().start(), end);
        let text = collapsed_range(&node, header);
        out.push(Diag::new(
            "HG8104",
            at(header),
            documented(format!(
                "'{text}' after a step without a successor transition"
            )),
        ));
    }
    for step in chart.syntax().descendants().filter_map(ast::Step::cast) {
        let step_name = step.name().map(|n| n.text()).unwrap_or_default();
        for time in step.times() {
            let text = collapsed(time.syntax());
            out.push(Diag::new(
                "HG8104",
                at(item_range(time.syntax())),
                documented(format!("'{text}' of step {step_name}")),
            ));
        }
        if let Some(confirm) = step.confirm() {
            out.push(Diag::new(
                "HG8104",
                at(item_range(confirm.syntax())),
                documented(format!("'confirm' of step {step_name}")),
            ));
        }
    }
    out
}

/// The keywords and elementary type names of IEC 61131-3 (3rd edition) that are not reserved
/// in this language already (`diagnostics.md` Appendix A reserves the shared type names,
/// `TRUE FALSE AND OR XOR NOT` and the STL operations).
const IEC_KEYWORDS: &[&str] = &[
    "ABSTRACT",
    "ACTION",
    "ARRAY",
    "AT",
    "BY",
    "CASE",
    "CLASS",
    "CONFIGURATION",
    "CONSTANT",
    "CONTINUE",
    "DO",
    "ELSE",
    "ELSIF",
    "EN",
    "END_ACTION",
    "END_CASE",
    "END_CLASS",
    "END_CONFIGURATION",
    "END_FOR",
    "END_FUNCTION",
    "END_FUNCTION_BLOCK",
    "END_IF",
    "END_INTERFACE",
    "END_METHOD",
    "END_NAMESPACE",
    "END_PROGRAM",
    "END_REPEAT",
    "END_RESOURCE",
    "END_STEP",
    "END_STRUCT",
    "END_TRANSITION",
    "END_TYPE",
    "END_VAR",
    "END_WHILE",
    "ENO",
    "EXIT",
    "EXTENDS",
    "F_EDGE",
    "FINAL",
    "FOR",
    "FROM",
    "FUNCTION",
    "FUNCTION_BLOCK",
    "IF",
    "IMPLEMENTS",
    "INITIAL_STEP",
    "INTERFACE",
    "INTERNAL",
    "INTERVAL",
    "LDATE",
    "LDT",
    "LINT",
    "LREAL",
    "LTIME",
    "LTOD",
    "LWORD",
    "METHOD",
    "MOD",
    "NAMESPACE",
    "NON_RETAIN",
    "NULL",
    "OF",
    "ON",
    "OVERLAP",
    "OVERRIDE",
    "PRIORITY",
    "PRIVATE",
    "PROGRAM",
    "PROTECTED",
    "PUBLIC",
    "R_EDGE",
    "READ_ONLY",
    "READ_WRITE",
    "REF",
    "REF_TO",
    "REPEAT",
    "RESOURCE",
    "RETAIN",
    "RETURN",
    "SINGLE",
    "SINT",
    "STEP",
    "STRUCT",
    "SUPER",
    "TASK",
    "THEN",
    "THIS",
    "TO",
    "TRANSITION",
    "TYPE",
    "UDINT",
    "UINT",
    "ULINT",
    "UNTIL",
    "USINT",
    "USING",
    "VAR",
    "VAR_ACCESS",
    "VAR_CONFIG",
    "VAR_EXTERNAL",
    "VAR_GLOBAL",
    "VAR_IN_OUT",
    "VAR_INPUT",
    "VAR_OUTPUT",
    "VAR_TEMP",
    "WCHAR",
    "WHILE",
    "WITH",
    "WSTRING",
];

fn is_iec_keyword(name: &str) -> bool {
    IEC_KEYWORDS.contains(&name.to_ascii_uppercase().as_str())
}

fn s7_message(x: &str, ty: Type) -> String {
    format!("'{x}' is {ty}, an S7 type that IEC 61131-3 lacks; PLCopen XML cannot express it")
}

/// A property or step item without its `;` (§2.3 "item, property"): from its first through its
/// last token before the `;`.
fn item_range(node: &SyntaxNode) -> TextRange {
    let mut significant =
        tokens_of(node).filter(|t| !t.kind().is_trivia() && t.kind() != SyntaxKind::SEMI);
    let Some(first) = significant.next() else {
        return node.text_range();
    };
    let last = significant.last().unwrap_or_else(|| first.clone());
    TextRange::new(first.text_range().start(), last.text_range().end())
}

/// The significant tokens of a node within `range`, joined by single spaces.
fn collapsed_range(node: &SyntaxNode, range: TextRange) -> String {
    tokens_of(node)
        .filter(|t| !t.kind().is_trivia() && range.contains_range(t.text_range()))
        .map(|t| t.text().to_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The significant tokens of a node joined by single spaces, without the `;`.
fn collapsed(node: &SyntaxNode) -> String {
    tokens_of(node)
        .filter(|t| !t.kind().is_trivia() && t.kind() != SyntaxKind::SEMI)
        .map(|t| t.text().to_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::in_cp1252;

    /// The set agrees with what `encoding_rs` encodes without error.
    #[test]
    fn windows_1252_is_what_encoding_rs_encodes() {
        for c in [
            'a', 'ä', 'ß', '€', 'µ', '°', '\u{81}', 'Ω', '✓', '→', 'ł', '中', '\u{FFFD}',
        ] {
            let mut buf = [0u8; 4];
            let (_, _, unmappable) = encoding_rs::WINDOWS_1252.encode(c.encode_utf8(&mut buf));
            assert_eq!(in_cp1252(c), !unmappable, "{c:?}");
        }
        assert!(in_cp1252('€') && in_cp1252('ä') && !in_cp1252('Ω') && !in_cp1252('✓'));
    }
}

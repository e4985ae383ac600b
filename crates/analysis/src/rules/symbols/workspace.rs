//! Workspace-wide symbol rules: HG1301 (a top-level name used twice, not both symbols), HG6003
//! (two symbols with one name), HG6002 (two symbols on one address), HG6004 (a declared symbol
//! nobody uses), HG4310 (two interfaces for one block), and HG6001/HG6006 for imported symbols.
//! "First" and "later" follow workspace order (§2.1).

use std::collections::{HashMap, HashSet};

use higraph_syntax::{
    SyntaxKind, TextRange,
    ast::{self, AstNode},
};

use super::{
    block_interface_addresses, is_local, symbol_display,
    table::{default_type, name_length_problem, type_fit_problem},
};
use crate::{
    address::Address,
    db::{self, File, ItemKind, ItemLoc, Workspace},
    diag::{Diag, Loc},
    index::{self, GlobalIndex, Symbol, SymbolSource},
    lang::Type,
    rules::file_symbol_uses,
};

/// The workspace-wide symbol rules, in one pass over the global index.
pub(super) fn check(db: &dyn salsa::Database, ws: Workspace, out: &mut Vec<Diag>) {
    let index = db::global_index(db, ws);
    let order = WorkspaceOrder::new(db, ws);
    check_namespace(db, index, &order, out);
    check_addresses(index, out);
    check_unused(db, ws, index, out);
    check_imported(index, out);
    check_interfaces(db, ws, out);
}

/// Sort keys for workspace order: files by position, imports after all files.
struct WorkspaceOrder {
    files: HashMap<File, usize>,
    file_count: usize,
}

impl WorkspaceOrder {
    fn new(db: &dyn salsa::Database, ws: Workspace) -> WorkspaceOrder {
        let files: HashMap<File, usize> = ws
            .files(db)
            .iter()
            .enumerate()
            .map(|(i, &f)| (f, i))
            .collect();
        WorkspaceOrder {
            file_count: files.len(),
            files,
        }
    }

    fn of_loc(&self, loc: &Loc) -> (usize, u32, u32) {
        let file = self.files.get(&loc.file).copied().unwrap_or(usize::MAX);
        (file, loc.item.unwrap_or(0), u32::from(loc.range.start()))
    }

    fn of_symbol(&self, symbol: &Symbol) -> (usize, u32, u32) {
        match symbol.source {
            SymbolSource::Declared => self.of_loc(&symbol.name_loc),
            SymbolSource::Imported(i) => (
                self.file_count + i,
                0,
                u32::from(symbol.name_loc.range.start()),
            ),
        }
    }
}

/// One top-level name.
struct TopLevel<'a> {
    order: (usize, u32, u32),
    name: &'a str,
    /// `a graph`, `a group`, `a chart`; `None` for a symbol.
    item_kind: Option<&'static str>,
    loc: Loc,
}

impl TopLevel<'_> {
    fn kind(&self) -> &'static str {
        self.item_kind.unwrap_or("a symbol")
    }
}

fn item_kind_name(kind: ItemKind) -> &'static str {
    match kind {
        ItemKind::Graph => "a graph",
        ItemKind::Group => "a group",
        _ => "a chart",
    }
}

/// HG1301 and HG6003.
fn check_namespace(
    db: &dyn salsa::Database,
    index: &GlobalIndex,
    order: &WorkspaceOrder,
    out: &mut Vec<Diag>,
) {
    let mut by_name: HashMap<String, Vec<TopLevel<'_>>> = HashMap::new();
    for item in &index.items {
        by_name
            .entry(index::key(&item.name))
            .or_default()
            .push(TopLevel {
                order: order.of_loc(&item.name_loc),
                name: &item.name,
                item_kind: Some(item_kind_name(item.kind)),
                loc: item.name_loc,
            });
    }
    for symbol in &index.symbols {
        by_name
            .entry(index::key(&symbol.name))
            .or_default()
            .push(TopLevel {
                order: order.of_symbol(symbol),
                name: &symbol.name,
                item_kind: None,
                loc: symbol.name_loc,
            });
    }
    let mut groups: Vec<Vec<TopLevel<'_>>> =
        by_name.into_values().filter(|v| v.len() > 1).collect();
    for entries in &mut groups {
        entries.sort_by_key(|e| e.order);
    }
    groups.sort_by_key(|entries| entries.first().map(|e| e.order));
    for entries in &groups {
        report_duplicates(db, entries, out);
    }
}

fn report_duplicates(db: &dyn salsa::Database, entries: &[TopLevel<'_>], out: &mut Vec<Diag>) {
    let Some(first) = entries.first() else {
        return;
    };
    let first_symbol = entries.iter().find(|e| e.item_kind.is_none());
    for later in &entries[1..] {
        let later_is_symbol = later.item_kind.is_none();
        if !(later_is_symbol && first.item_kind.is_none()) {
            out.push(
                Diag::new(
                    "HG1301",
                    later.loc,
                    format!(
                        "'{}' is already the name of {} in {}",
                        later.name,
                        first.kind(),
                        first.loc.file.path(db)
                    ),
                )
                .related(first.loc, format!("{} '{}'", first.kind(), first.name)),
            );
        }
        if let Some(original) = first_symbol.filter(|s| later_is_symbol && s.order < later.order) {
            out.push(
                Diag::new(
                    "HG6003",
                    later.loc,
                    format!(
                        "symbol '{}' is already defined in {}",
                        later.name,
                        original.loc.file.path(db)
                    ),
                )
                .related(
                    original.loc,
                    format!("symbol '{}' is defined here", original.name),
                ),
            );
        }
    }
}

/// Is this symbol the first of its name (later duplicates are ignored, C3)?
fn is_first_of_name(index: &GlobalIndex, symbol: &Symbol) -> bool {
    index
        .symbol(&symbol.name)
        .is_some_and(|first| std::ptr::eq(first, symbol))
}

/// HG6002: two symbols whose normalised addresses are equal.
fn check_addresses(index: &GlobalIndex, out: &mut Vec<Diag>) {
    let mut owners: HashMap<&Address, &Symbol> = HashMap::new();
    for symbol in &index.symbols {
        let Some(address) = &symbol.address else {
            continue;
        };
        if !is_first_of_name(index, symbol) {
            continue;
        }
        match owners.get(address) {
            Some(first) => out.push(
                Diag::new(
                    "HG6002",
                    symbol.address_loc,
                    format!(
                        "{} is already named by symbol {}",
                        symbol.address_text.trim(),
                        symbol_display(first)
                    ),
                )
                .related(
                    first.name_loc,
                    format!(
                        "symbol {} names {}",
                        symbol_display(first),
                        first.address_text.trim()
                    ),
                ),
            ),
            None => {
                owners.insert(address, symbol);
            }
        }
    }
}

/// HG6004: declared symbols that nothing in the workspace refers to.
fn check_unused(db: &dyn salsa::Database, ws: Workspace, index: &GlobalIndex, out: &mut Vec<Diag>) {
    let mut used: HashSet<&String> = HashSet::new();
    for &file in ws.files(db) {
        used.extend(file_symbol_uses(db, ws, file).iter());
    }
    // The declarations of each `symbols` item, walked once per item (not once per symbol).
    let mut declarations: HashMap<(File, u32), HashMap<TextRange, TextRange>> = HashMap::new();
    for symbol in &index.symbols {
        if symbol.source != SymbolSource::Declared
            || used.contains(&index::key(&symbol.name))
            || !is_first_of_name(index, symbol)
        {
            continue;
        }
        let mut diag = Diag::new(
            "HG6004",
            symbol.name_loc,
            format!("symbol '{}' is never used", symbol.name),
        );
        if let Some(item) = symbol.name_loc.item {
            let file = symbol.name_loc.file;
            let nodes = declarations
                .entry((file, item))
                .or_insert_with(|| symbol_nodes(db, file, item));
            if let Some(&range) = nodes.get(&symbol.name_loc.range) {
                let loc = Loc::in_item(file, item, range);
                diag = diag.fix(format!("Remove symbol '{}'", symbol.name), loc, "");
            }
        }
        out.push(diag);
    }
}

/// The whole declaration of every declared symbol of a `symbols` item (for the HG6004 fix),
/// by the range of its name.
fn symbol_nodes(db: &dyn salsa::Database, file: File, item: u32) -> HashMap<TextRange, TextRange> {
    let Some(root) = db::item_root(db, ItemLoc::new(db, file, item)) else {
        return HashMap::new();
    };
    root.descendants()
        .filter(|n| n.kind() == SyntaxKind::SYMBOL)
        .filter_map(ast::Symbol::cast)
        .filter_map(|s| {
            let name = s.name()?.token()?.text_range();
            Some((name, s.syntax().text_range()))
        })
        .collect()
}

/// HG6001 (type does not fit: on the data type field; local data: on the address field) and
/// HG6006 (on the name field) for imported symbols.
fn check_imported(index: &GlobalIndex, out: &mut Vec<Diag>) {
    for symbol in &index.symbols {
        if symbol.source == SymbolSource::Declared {
            continue;
        }
        if let Some(message) = name_length_problem(&symbol.name) {
            out.push(Diag::new("HG6006", symbol.name_loc, message));
        }
        let Some(address) = &symbol.address else {
            continue;
        };
        let address_text = symbol.address_text.trim();
        if is_local(address) {
            out.push(Diag::new(
                "HG6001",
                symbol.address_loc,
                format!(
                    "symbol {}: {address_text} cannot have a global symbol",
                    symbol.name
                ),
            ));
            continue;
        }
        let declared = symbol.ty.filter(|&t| t != Type::Block);
        if let Some(message) = declared
            .filter(|_| symbol.type_text.is_some())
            .and_then(|ty| type_fit_problem(&symbol.name, address_text, address, ty))
        {
            // On the data type field, as on a declared symbol's type.
            let loc = symbol.type_loc.unwrap_or(symbol.address_loc);
            let mut diag = Diag::new("HG6001", loc, message);
            if let (Some(default), Some(type_loc)) = (default_type(address), symbol.type_loc) {
                diag = diag.fix(
                    format!("Use the type {default}"),
                    type_loc,
                    default.to_string(),
                );
            }
            out.push(diag);
        }
    }
}

/// HG4310: a second `block` item for the same block.
fn check_interfaces(db: &dyn salsa::Database, ws: Workspace, out: &mut Vec<Diag>) {
    let mut first: HashMap<&Address, &super::blocks::InterfaceTarget> = HashMap::new();
    for target in block_interface_addresses(db, ws) {
        match first.get(&target.address) {
            Some(original) => out.push(
                Diag::new(
                    "HG4310",
                    target.reference_loc,
                    format!(
                        "interface of {} is already declared in {}",
                        target.reference,
                        original.file.path(db)
                    ),
                )
                .related(
                    original.reference_loc,
                    format!("interface of {}", original.reference),
                ),
            ),
            None => {
                first.insert(&target.address, target);
            }
        }
    }
}

//! The workspace-wide name index: graphs, groups, charts, global symbols (declared and
//! imported) and block interfaces, in workspace order (`diagnostics.md` §2.1).
//!
//! Built from position-independent per-item data, so an edit inside an item that does not
//! change any global name leaves the index equal and nothing downstream re-runs.

use std::collections::HashMap;

use higraph_syntax::{TextRange, ast, ast::AstNode};

use crate::{
    address::{self, Address},
    db::{self, File, ItemKind, ItemLoc, Workspace},
    diag::Loc,
    lang::{Mnemonic, Type},
    sdf,
};

/// A graph, group or chart.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GlobalItem {
    pub kind: ItemKind,
    pub name: String,
    pub file: File,
    pub item: u32,
    /// The name token (relative to the item).
    pub name_loc: Loc,
    /// A chart type (`chart type NAME`).
    pub chart_type: bool,
}

/// Where a symbol comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SymbolSource {
    /// A `symbols` block of a `.higraph` file.
    Declared,
    /// An imported STEP 7 symbol table (index into the workspace's imports).
    Imported(usize),
}

/// A global symbol.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    pub name: String,
    /// Written as a quoted string.
    pub quoted: bool,
    pub source: SymbolSource,
    /// The name (declared symbols: the NAME/STRING token; imported: the name field, without
    /// quotes and padding).
    pub name_loc: Loc,
    /// The address as written.
    pub address_text: String,
    pub address_loc: Loc,
    /// The address, if it is well-formed.
    pub address: Option<Address>,
    /// The declared type as written.
    pub type_text: Option<String>,
    pub type_loc: Option<Loc>,
    /// The effective type: declared, else the address's; `None` if unknown.
    pub ty: Option<Type>,
    pub comment: Option<String>,
}

/// A `block` interface item.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockInterfaceEntry {
    pub file: File,
    pub item: u32,
    /// The block reference as written (`FC 10`, `"Dosieren"`).
    pub reference: String,
    pub reference_loc: Loc,
}

/// Everything with a workspace-wide name.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct GlobalIndex {
    /// Graphs, groups and charts in workspace order.
    pub items: Vec<GlobalItem>,
    /// Symbols in workspace order (imports last).
    pub symbols: Vec<Symbol>,
    pub block_interfaces: Vec<BlockInterfaceEntry>,
    /// Tests in workspace order: a namespace of their own (`runtime.md` §5.1, HG9002).
    pub tests: Vec<GlobalItem>,
    items_by_name: HashMap<String, Vec<usize>>,
    tests_by_name: HashMap<String, usize>,
    symbols_by_name: HashMap<String, Vec<usize>>,
}

/// The case-insensitive key of a name (ASCII case folding, §2.2).
pub fn key(name: &str) -> String {
    name.to_ascii_uppercase()
}

impl GlobalIndex {
    pub(crate) fn build(db: &dyn salsa::Database, ws: Workspace) -> GlobalIndex {
        let mut index = GlobalIndex::default();
        for &file in ws.files(db) {
            let summary = db::file_summary(db, file);
            for (i, item) in summary.items.iter().enumerate() {
                let i = i as u32;
                match item.kind {
                    ItemKind::Graph | ItemKind::Group | ItemKind::Chart => {
                        if let (Some(name), Some(range)) = (&item.name, item.name_range) {
                            index.items.push(GlobalItem {
                                kind: item.kind,
                                name: name.clone(),
                                file,
                                item: i,
                                name_loc: Loc::in_item(file, i, range),
                                chart_type: item.chart_type,
                            });
                        }
                    }
                    ItemKind::Test => {
                        if let (Some(name), Some(range)) = (&item.name, item.name_range) {
                            index.tests.push(GlobalItem {
                                kind: item.kind,
                                name: name.clone(),
                                file,
                                item: i,
                                name_loc: Loc::in_item(file, i, range),
                                chart_type: false,
                            });
                        }
                    }
                    ItemKind::Symbols => {
                        let loc = ItemLoc::new(db, file, i);
                        index
                            .symbols
                            .extend(item_symbols(db, ws, loc).iter().cloned());
                    }
                    ItemKind::BlockInterface => {
                        let loc = ItemLoc::new(db, file, i);
                        if let Some(entry) = block_interface_entry(db, loc) {
                            index.block_interfaces.push(entry);
                        }
                    }
                    ItemKind::Mnemonic => {}
                }
            }
        }
        for table in sdf::imported_tables(db, ws) {
            index.symbols.extend(table.symbols.iter().cloned());
        }
        for (i, item) in index.items.iter().enumerate() {
            index
                .items_by_name
                .entry(key(&item.name))
                .or_default()
                .push(i);
        }
        for (i, test) in index.tests.iter().enumerate() {
            index.tests_by_name.entry(key(&test.name)).or_insert(i);
        }
        for (i, symbol) in index.symbols.iter().enumerate() {
            index
                .symbols_by_name
                .entry(key(&symbol.name))
                .or_default()
                .push(i);
        }
        index
    }

    /// The first graph, group or chart of that name (case-insensitive), any kind.
    pub fn item(&self, name: &str) -> Option<&GlobalItem> {
        self.items_by_name
            .get(&key(name))
            .and_then(|v| v.first())
            .map(|&i| &self.items[i])
    }

    /// Every graph, group or chart of that name, in workspace order.
    pub fn items_named(&self, name: &str) -> impl Iterator<Item = &GlobalItem> {
        self.items_by_name
            .get(&key(name))
            .into_iter()
            .flatten()
            .map(|&i| &self.items[i])
    }

    /// The first test of that name (case-insensitive), in workspace order.
    pub fn test(&self, name: &str) -> Option<&GlobalItem> {
        self.tests_by_name.get(&key(name)).map(|&i| &self.tests[i])
    }

    /// The first graph of that name.
    pub fn graph(&self, name: &str) -> Option<&GlobalItem> {
        self.items_named(name).find(|i| i.kind == ItemKind::Graph)
    }

    /// The first symbol of that name (duplicates bind to the first, C3).
    pub fn symbol(&self, name: &str) -> Option<&Symbol> {
        self.symbols_by_name
            .get(&key(name))
            .and_then(|v| v.first())
            .map(|&i| &self.symbols[i])
    }

    /// The position in [`GlobalIndex::symbols`] of the first symbol of that name (the one
    /// references bind to).
    pub fn symbol_position(&self, name: &str) -> Option<usize> {
        self.symbols_by_name
            .get(&key(name))
            .and_then(|v| v.first())
            .copied()
    }

    /// Every symbol of that name, in workspace order.
    pub fn symbols_named(&self, name: &str) -> impl Iterator<Item = &Symbol> {
        self.symbols_by_name
            .get(&key(name))
            .into_iter()
            .flatten()
            .map(|&i| &self.symbols[i])
    }

    /// The first symbol naming `address`.
    pub fn symbol_for_address(&self, address: &Address) -> Option<&Symbol> {
        self.symbols
            .iter()
            .find(|s| s.address.as_ref() == Some(address))
    }
}

/// The symbols of one `symbols` item.
#[salsa::tracked(returns(ref))]
pub fn item_symbols<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> Vec<Symbol> {
    let file = item.file(db);
    let index = item.index(db);
    let Some(root) = db::item_root(db, item) else {
        return Vec::new();
    };
    let Some(table) = ast::Symbols::cast(root) else {
        return Vec::new();
    };
    let mnemonic = db::file_mnemonic(db, ws, file);
    let loc = |range: TextRange| Loc::in_item(file, index, range);
    table
        .symbols()
        .filter_map(|symbol| {
            let name = symbol.name()?;
            let token = name.token()?;
            let address = symbol.address()?;
            let address_text = address.compact_text();
            let read = address::read(&address_text, mnemonic).and_then(|r| r.address.ok());
            let type_text = symbol
                .ty()
                .and_then(|t| t.name())
                .map(|t| t.text().to_owned());
            let declared = symbol.ty().and_then(|t| declared_type(&t));
            let ty = match &type_text {
                Some(_) => declared,
                None => read.as_ref().map(|a| a.ty()),
            };
            Some(Symbol {
                name: name.text(),
                quoted: token.kind() == higraph_syntax::SyntaxKind::STRING,
                source: SymbolSource::Declared,
                name_loc: loc(token.text_range()),
                address_text: address.syntax().text().to_string(),
                address_loc: loc(address.syntax().text_range()),
                address: read,
                type_text,
                type_loc: symbol.ty().map(|t| loc(t.syntax().text_range())),
                ty,
                comment: symbol.comment().map(|c| c.value()),
            })
        })
        .collect()
}

/// The type written in a declaration (`STRING[n]` with its length), if it is a known type.
pub fn declared_type(ty: &ast::TypeRef) -> Option<Type> {
    declared_type_in(ty, false)
}

/// [`declared_type`]; `interface` allows the block-interface-only types (POINTER, ANY, the
/// block types).
pub(crate) fn declared_type_in(ty: &ast::TypeRef, interface: bool) -> Option<Type> {
    let name = ty.name()?;
    let parsed = Type::from_name(name.text(), interface)?;
    match (parsed, ty.length()) {
        (Type::String(_), Some(len)) => len.text().parse::<u16>().ok().map(Type::String),
        (parsed, _) => Some(parsed),
    }
}

fn block_interface_entry(
    db: &dyn salsa::Database,
    item: ItemLoc<'_>,
) -> Option<BlockInterfaceEntry> {
    let file = item.file(db);
    let index = item.index(db);
    let root = db::item_root(db, item)?;
    let interface = ast::BlockInterface::cast(root)?;
    let reference = interface.block()?;
    Some(BlockInterfaceEntry {
        file,
        item: index,
        reference: reference.syntax().text().to_string(),
        reference_loc: Loc::in_item(file, index, reference.syntax().text_range()),
    })
}

/// Reads an address in the given set, ignoring errors.
pub fn read_address(text: &str, mnemonic: Mnemonic) -> Option<Address> {
    let compact: String = text.split_whitespace().collect();
    address::read(&compact, mnemonic).and_then(|r| r.address.ok())
}

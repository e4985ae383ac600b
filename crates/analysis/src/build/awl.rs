//! One group → its STEP 7 source: lowered alone (like a run list of one group), its names
//! gathered from the lowering's side table (`lower::LowerNames`) and the workspace index, then
//! written by `higraph_export::awl` (the shape of the code is explained there) and encoded as
//! Windows-1252 with CR LF line ends.

use std::collections::HashMap;

use higraph_export::awl::{self as awlgen, BlockName, Names, SymbolInfo};
use higraph_syntax::ast::{self, AstNode};

use super::BuildOptions;
use crate::db::{self, File, ItemLoc, Workspace};
use crate::index::{self, GlobalIndex};
use crate::lang::Mnemonic;
use crate::lower::Lowerer;

/// A group's generated source.
#[derive(Debug, Clone)]
#[allow(dead_code)] // read by the orchestrator (being written)
pub(super) struct GroupSource {
    /// The file name (`<group>.awl`).
    pub file_name: String,
    /// Windows-1252, CR LF.
    pub bytes: Vec<u8>,
    /// The symbols the source uses (its FC and DB included), for `symbols.sdf`.
    pub symbols: Vec<higraph_export::sdf::Symbol>,
}

/// The source of the group `item` of `file`. `Err` says why it cannot be generated: the group
/// cannot be lowered, names no `fc`/`db` block numbers, or has a name or comment that
/// Windows-1252 cannot hold (the orchestrator refuses builds with errors first, so these are
/// bug guards).
pub(super) fn group_source(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    options: &BuildOptions,
) -> Result<GroupSource, String> {
    let loc = ItemLoc::new(db, file, item);
    let Some(ast::Item::Group(group)) = db::item_root(db, loc).and_then(ast::Item::cast) else {
        return Err("not a group".to_owned());
    };
    let name = group.name().map(|n| n.text()).unwrap_or_default();
    let mut lw = Lowerer::new(db, ws);
    let g = lw
        .group(file, item)
        .ok_or_else(|| format!("group {name} cannot be lowered"))?;
    let index = db::global_index(db, ws);
    let mnemonic = ws.config(db).mnemonic;
    let block = |r: Option<ast::BlockRef>, kind: &str| -> Result<BlockName, String> {
        let r = r.ok_or_else(|| format!("group {name} has no `{}` clause", kind.to_lowercase()))?;
        let text = if let Some(a) = r.address() {
            a.syntax().text().to_string()
        } else if let Some(n) = r.name_ref() {
            n.text()
        } else if let Some(s) = r.symbol_ref() {
            s.name()
        } else {
            String::new()
        };
        block_name(index, &text, mnemonic)
            .filter(|b| b.kind == kind)
            .ok_or_else(|| format!("group {name}: `{text}` is no {kind} block"))
    };
    let fc = block(group.fc(), "FC")?;
    let dbn = block(group.db(), "DB")?;
    let instances: Vec<ast::Instance> = {
        // The instances the lowering kept: the first of each name.
        let mut seen = std::collections::HashSet::new();
        group
            .instances()
            .filter(|i| i.name().is_some_and(|n| seen.insert(index::key(&n.text()))))
            .collect()
    };
    let lowered = &lw.program.groups[g as usize];
    let instance_comments = lowered
        .instances
        .iter()
        .map(|li| {
            instances
                .iter()
                .find(|i| i.name().is_some_and(|n| n.text() == li.name))
                .and_then(|i| i.comment())
                .map(|c| c.value())
        })
        .collect();
    let blocks = lw
        .program
        .blocks
        .iter()
        .map(|b| block_name(index, &b.name, mnemonic).unwrap_or_default())
        .collect();
    let symbols = index
        .symbols
        .iter()
        .map(|s| {
            let address = s
                .address
                .as_ref()
                .map_or_else(|| s.address_text.clone(), |a| a.display(mnemonic));
            let ty = s
                .type_text
                .clone()
                .or_else(|| s.ty.map(|t| t.to_string()))
                .unwrap_or_default();
            (
                index::key(&s.name),
                SymbolInfo {
                    name: s.name.clone(),
                    address,
                    ty: ty.to_uppercase(),
                    comment: s.comment.clone().unwrap_or_default(),
                },
            )
        })
        .fold(HashMap::new(), |mut map, (k, v)| {
            map.entry(k).or_insert(v);
            map
        });
    let names = Names {
        group: name.clone(),
        comment: group.comment().map(|c| c.value()),
        fc,
        db: dbn,
        instance_comments,
        own_cells: lw
            .names
            .group_own
            .get(g as usize)
            .cloned()
            .unwrap_or_default(),
        actual_symbols: lw
            .names
            .actual_symbols
            .get(g as usize)
            .cloned()
            .unwrap_or_default(),
        operand_symbols: std::mem::take(&mut lw.names.operand_symbols),
        literals: std::mem::take(&mut lw.names.literals),
        time_symbols: std::mem::take(&mut lw.names.time_symbols),
        blocks,
        call_dbs: lw
            .names
            .call_dbs
            .iter()
            .filter_map(|(o, text)| Some((*o, block_name(index, text, mnemonic)?)))
            .collect(),
        symbols,
        var_comments: var_comments(db, index, &lw.program),
    };
    let opt = awlgen::Options {
        absolute: options.absolute,
        with_ob1: options.with_ob1,
        mnemonic: match mnemonic {
            Mnemonic::Simatic => awlgen::Mnemonic::Simatic,
            Mnemonic::International => awlgen::Mnemonic::International,
        },
    };
    let out = awlgen::generate(&lw.program, g, &names, opt).map_err(|e| e.to_string())?;
    let bytes =
        higraph_export::cp1252::encode(&out.text).map_err(|e| format!("group {name}: {e}"))?;
    Ok(GroupSource {
        file_name: format!("{name}.awl"),
        bytes,
        symbols: out.symbols,
    })
}

/// The comments of the declared variables of the program's graphs, for the DB members.
fn var_comments(
    db: &dyn salsa::Database,
    index: &GlobalIndex,
    program: &higraph_runtime::Program,
) -> HashMap<(u32, u16), String> {
    let mut out = HashMap::new();
    for (g, graph) in program.graphs.iter().enumerate() {
        let Some(item) = index.graph(&graph.name) else {
            continue;
        };
        let loc = ItemLoc::new(db, item.file, item.item);
        let Some(ast::Item::Graph(node)) = db::item_root(db, loc).and_then(ast::Item::cast) else {
            continue;
        };
        for (_, decl) in crate::rules::decls::declarations(node.var_sections()) {
            let (Some(name), Some(comment)) = (decl.name(), decl.comment()) else {
                continue;
            };
            let name = name.text();
            if let Some(v) = graph.vars.iter().position(|v| v.name == name) {
                out.entry((g as u32, v as u16))
                    .or_insert_with(|| comment.value());
            }
        }
    }
    out
}

/// A block by its address (`FC 1`, `FC1`) or symbol.
fn block_name(index: &GlobalIndex, text: &str, mnemonic: Mnemonic) -> Option<BlockName> {
    let compact: String = text.split_whitespace().collect();
    let unquoted = ast::unquote(&compact).to_owned();
    if let Some(a) = index::read_address(&compact, mnemonic)
        .or_else(|| index::read_address(&compact, Mnemonic::Simatic))
        && let Some(kind) = a.block_kind()
    {
        return Some(BlockName {
            kind: kind.as_str().to_owned(),
            number: a.number,
            symbol: None,
        });
    }
    let symbol = index.symbol(&unquoted)?;
    let a = symbol.address.as_ref()?;
    Some(BlockName {
        kind: a.block_kind()?.as_str().to_owned(),
        number: a.number,
        symbol: Some(symbol.name.clone()),
    })
}

/// A generated group source: file name, bytes, symbols.
pub type GroupSourceFiles = (String, Vec<u8>, Vec<higraph_export::sdf::Symbol>);

impl crate::Analysis {
    /// The STEP 7 source `build` writes for the group `name`: its file name, its bytes and the
    /// symbols it uses. `None`: the workspace has no such group. Diagnostics are not checked
    /// here (that is `build`'s business).
    pub fn group_source(
        &self,
        name: &str,
        options: &BuildOptions,
    ) -> crate::Cancellable<Option<Result<GroupSourceFiles, String>>> {
        self.with_db(|db, ws| {
            let index = db::global_index(db, ws);
            let item = index.items.iter().find(|i| {
                i.kind == db::ItemKind::Group && index::key(&i.name) == index::key(name)
            })?;
            Some(
                group_source(db, ws, item.file, item.item, options)
                    .map(|s| (s.file_name, s.bytes, s.symbols)),
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::{AnalysisHost, FileContents, WorkspaceData};

    /// `symbols.sdf` as `build` writes it reads back through the workspace's own `.sdf`
    /// import with the same names, addresses, types and comments, and no problems.
    #[test]
    fn symbols_sdf_round_trip() {
        use higraph_export::sdf::{Symbol, write};
        let symbols = vec![
            Symbol {
                name: "GG_Bohrmaschine".into(),
                address: "FC 1".into(),
                ty: "FC 1".into(),
                comment: "FC of graph group Bohrmaschine".into(),
            },
            Symbol {
                name: "DB_GG_Bohrmaschine".into(),
                address: "DB 1".into(),
                ty: "DB 1".into(),
                comment: String::new(),
            },
            Symbol {
                name: "Starttaster".into(),
                address: "E 0.7".into(),
                ty: "BOOL".into(),
                comment: "Start \u{e4}".into(),
            },
            Symbol {
                name: "Wert".into(),
                address: "MW 10".into(),
                ty: "INT".into(),
                comment: "a value".into(),
            },
            Symbol {
                name: "Zeit".into(),
                address: "T 4".into(),
                ty: "TIMER".into(),
                comment: String::new(),
            },
        ];
        let bytes = write(&symbols).expect("Windows-1252");
        let mut data = WorkspaceData {
            config: Some((
                "higraph.toml".into(),
                FileContents::from_bytes(b"[workspace]\nsymbols = [\"symbols.sdf\"]\n".to_vec()),
            )),
            ..WorkspaceData::default()
        };
        data.imports.insert("symbols.sdf".into(), Ok(bytes));
        let mut host = AnalysisHost::new();
        host.load(data);
        let read = host
            .analysis()
            .with_db(|db, ws| {
                let tables = crate::sdf::imported_tables(db, ws);
                assert_eq!(tables.len(), 1);
                assert!(tables[0].problems.is_empty(), "{:?}", tables[0].problems);
                tables[0]
                    .symbols
                    .iter()
                    .map(|s| {
                        (
                            s.name.clone(),
                            s.address
                                .as_ref()
                                .map(|a| a.display(crate::lang::Mnemonic::Simatic))
                                .unwrap_or_default(),
                            s.type_text.clone().unwrap_or_default(),
                            s.comment.clone().unwrap_or_default(),
                        )
                    })
                    .collect::<Vec<_>>()
            })
            .unwrap();
        let want: Vec<_> = symbols
            .iter()
            .map(|s| {
                (
                    s.name.clone(),
                    s.address.clone(),
                    s.ty.clone(),
                    s.comment.clone(),
                )
            })
            .collect();
        assert_eq!(read, want);
    }
}

//! The blocks a group generates (`diagnostics.md` §3.8): HG8002/HG8003 (no `fc`/`db` clause),
//! HG8005 (the clause does not denote an FC/DB), and, workspace-wide, HG8004 (two groups
//! generate one block), HG8010 (a CALL of a generated FC, or a generated DB as instance DB) and
//! HG8011 (a `DBn.DBX...` address inside a generated DB).
//!
//! HG8010 and HG8011 scan every item syntactically ([`block_hits`], one salsa query per item),
//! so an edit re-scans only the edited item.

use std::collections::HashMap;

use higraph_syntax::{
    SyntaxKind, SyntaxNode, TextRange,
    ast::{self, AstNode},
};

use crate::{
    address::{self, Address, Area, BlockKind},
    db::{self, File, ItemKind, ItemLoc, Workspace},
    diag::{Diag, Loc},
    lang::{self, Mnemonic},
    resolve,
    rules::{
        Ctx,
        symbols::{
            BlockTarget, check_address, check_block_ref_case, node_text, resolve_block_ref,
            target_kind,
        },
    },
    sdf,
};

/// `fc` or `db`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Clause {
    Fc,
    Db,
}

impl Clause {
    fn kind(self) -> BlockKind {
        match self {
            Clause::Fc => BlockKind::Fc,
            Clause::Db => BlockKind::Db,
        }
    }

    fn upper(self) -> &'static str {
        match self {
            Clause::Fc => "FC",
            Clause::Db => "DB",
        }
    }

    /// The clause's block reference.
    fn reference(self, group: &ast::Group) -> Option<ast::BlockRef> {
        match self {
            Clause::Fc => group.fc(),
            Clause::Db => group.db(),
        }
    }

    /// The whole clause node (`fc FC1`).
    fn node(self, group: &ast::Group) -> Option<SyntaxNode> {
        let kind = match self {
            Clause::Fc => SyntaxKind::FC_CLAUSE,
            Clause::Db => SyntaxKind::DB_CLAUSE,
        };
        group.syntax().children().find(|n| n.kind() == kind)
    }
}

/// HG8002, HG8003, HG8005, HG1104 and the symbol uses of the `fc`/`db` clauses.
pub(super) fn check_clauses(ctx: &mut Ctx<'_>, group: &ast::Group, group_name: &str) {
    for clause in [Clause::Fc, Clause::Db] {
        match clause.reference(group) {
            Some(reference) => check_clause(ctx, clause, &reference),
            None => report_missing(ctx, group, group_name, clause),
        }
    }
}

fn report_missing(ctx: &mut Ctx<'_>, group: &ast::Group, group_name: &str, clause: Clause) {
    if clause.node(group).is_some() {
        // A clause without a name is a syntax error.
        return;
    }
    let Some(token) = group.name().and_then(|n| n.token()) else {
        return;
    };
    let (code, message) = match clause {
        Clause::Fc => ("HG8002", format!("group {group_name} does not name its FC")),
        Clause::Db => ("HG8003", format!("group {group_name} does not name its DB")),
    };
    let diag = ctx.diag(code, token.text_range(), message);
    ctx.push(diag);
}

fn check_clause(ctx: &mut Ctx<'_>, clause: Clause, reference: &ast::BlockRef) {
    let written = node_text(reference.syntax());
    let range = reference.syntax().text_range();
    if let Some(node) = reference.address()
        && check_address(ctx, &node).is_err()
    {
        return;
    }
    let index = ctx.index;
    let target = resolve_block_ref(index, ctx.mnemonic, reference);
    if let BlockTarget::Symbol(symbol) = target {
        ctx.use_symbol(&symbol.name);
        check_block_ref_case(ctx, reference, &symbol.name);
    }
    let upper = clause.upper();
    let message = match &target {
        BlockTarget::Invalid => return,
        BlockTarget::NotASymbol => format!(
            "'{written}' is not a global symbol; add '{written} : {upper} n;' to a symbols block"
        ),
        BlockTarget::Absolute(_) | BlockTarget::Symbol(_) => {
            let Some(address) = target.address() else {
                return;
            };
            if address.block_kind() == Some(clause.kind()) {
                return;
            }
            let Some(kind) = target_kind(&target, ctx.mnemonic) else {
                return;
            };
            let article = match clause {
                Clause::Fc => "an",
                Clause::Db => "a",
            };
            format!("'{written}' is not {article} {upper}: it is {kind}")
        }
    };
    let diag = ctx.diag("HG8005", range, message);
    ctx.push(diag);
}

/// A block that a group generates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct GeneratedBlock {
    pub clause: Clause,
    /// The FC or DB number.
    pub number: u32,
    /// The group's name as declared.
    pub group: String,
    /// The name after `fc`/`db`.
    pub name_loc: Loc,
    /// The whole `fc`/`db` clause.
    pub clause_loc: Loc,
}

/// The FCs and DBs the groups of the workspace generate, in workspace order (clauses that do
/// not denote a block of the right kind are left out).
#[salsa::tracked(returns(ref))]
pub(crate) fn generated_blocks(db: &dyn salsa::Database, ws: Workspace) -> Vec<GeneratedBlock> {
    let index = db::global_index(db, ws);
    let mut blocks = Vec::new();
    for &file in ws.files(db) {
        let set = db::file_mnemonic(db, ws, file);
        for (i, summary) in db::file_summary(db, file).items.iter().enumerate() {
            if summary.kind != ItemKind::Group {
                continue;
            }
            let item = i as u32;
            let Some(group) =
                db::item_root(db, ItemLoc::new(db, file, item)).and_then(ast::Group::cast)
            else {
                continue;
            };
            let name = group.name().map(|n| n.text()).unwrap_or_default();
            // C3: a later group of a name (HG1301) is ignored; it generates nothing.
            if index
                .items_named(&name)
                .next()
                .is_some_and(|first| !(first.file == file && first.item == item))
            {
                continue;
            }
            for clause in [Clause::Fc, Clause::Db] {
                let (Some(reference), Some(node)) = (clause.reference(&group), clause.node(&group))
                else {
                    continue;
                };
                let address = resolve_block_ref(index, set, &reference).address();
                let Some(address) = address.filter(|a| a.block_kind() == Some(clause.kind()))
                else {
                    continue;
                };
                blocks.push(GeneratedBlock {
                    clause,
                    number: address.number,
                    group: name.clone(),
                    // A quoted name without its quotes (§2.3 reference).
                    name_loc: Loc::in_item(
                        file,
                        item,
                        crate::resolve::block_reference_range(&reference),
                    ),
                    clause_loc: Loc::in_item(file, item, node.text_range()),
                });
            }
        }
    }
    blocks
}

/// The first group generating each block (later ones get HG8004).
fn owners(blocks: &[GeneratedBlock]) -> HashMap<(Clause, u32), &GeneratedBlock> {
    let mut owners = HashMap::new();
    for block in blocks {
        owners.entry((block.clause, block.number)).or_insert(block);
    }
    owners
}

/// HG8004, HG8010 and HG8011.
pub(super) fn check_workspace(db: &dyn salsa::Database, ws: Workspace, out: &mut Vec<Diag>) {
    let blocks = generated_blocks(db, ws);
    let first = owners(blocks);
    for block in blocks {
        let Some(original) = first.get(&(block.clause, block.number)) else {
            continue;
        };
        if std::ptr::eq(*original, block) {
            continue;
        }
        out.push(
            Diag::new(
                "HG8004",
                block.name_loc,
                format!(
                    "{} {} is already generated by group {}",
                    block.clause.upper(),
                    block.number,
                    original.group
                ),
            )
            .related(
                original.name_loc,
                format!(
                    "group {} generates {} {}",
                    original.group,
                    original.clause.upper(),
                    original.number
                ),
            ),
        );
    }
    if blocks.is_empty() {
        return;
    }
    for &file in ws.files(db) {
        for index in 0..db::file_summary(db, file).items.len() {
            let item = ItemLoc::new(db, file, index as u32);
            out.extend(block_hits(db, ws, item).iter().cloned());
        }
    }
    out.extend(imported_hits(db, ws).iter().cloned());
}

/// HG8010 and HG8011 in one item.
#[salsa::tracked(returns(ref))]
pub(crate) fn block_hits<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: ItemLoc<'db>,
) -> Vec<Diag> {
    let blocks = generated_blocks(db, ws);
    if blocks.is_empty() {
        return Vec::new();
    }
    let Some(root) = db::item_root(db, item) else {
        return Vec::new();
    };
    let scan = Scan {
        db,
        ws,
        file: item.file(db),
        item: item.index(db),
        set: db::file_mnemonic(db, ws, item.file(db)),
        owners: owners(blocks),
    };
    let mut out = Vec::new();
    match root.kind() {
        SyntaxKind::GRAPH => {
            scan.calls(&root, &mut out);
            scan.db_addresses(&root, true, &mut out);
        }
        SyntaxKind::CHART | SyntaxKind::GROUP | SyntaxKind::SYMBOLS => {
            scan.db_addresses(&root, false, &mut out);
        }
        _ => {}
    }
    out
}

/// HG8011 for imported symbols whose address lies in a generated DB.
#[salsa::tracked(returns(ref))]
fn imported_hits(db: &dyn salsa::Database, ws: Workspace) -> Vec<Diag> {
    let blocks = generated_blocks(db, ws);
    let owners = owners(blocks);
    let mut out = Vec::new();
    for table in sdf::imported_tables(db, ws) {
        for symbol in &table.symbols {
            let Some(address) = &symbol.address else {
                continue;
            };
            if let Some(diag) =
                db_address_hit(&owners, address, &symbol.address_text, symbol.address_loc)
            {
                out.push(diag);
            }
        }
    }
    out
}

/// HG8011 for one address, if it lies in a generated DB.
fn db_address_hit(
    owners: &HashMap<(Clause, u32), &GeneratedBlock>,
    address: &Address,
    written: &str,
    at: Loc,
) -> Option<Diag> {
    if address.area != Area::DataBlock {
        return None;
    }
    let db = address.db?;
    let owner = owners.get(&(Clause::Db, db))?;
    Some(
        Diag::new(
            "HG8011",
            at,
            format!(
                "{} lies in DB {db}, which group {} generates; its layout is not under your control",
                written.trim(),
                owner.group
            ),
        )
        .related(
            owner.clause_loc,
            format!("group {} generates DB {db}", owner.group),
        ),
    )
}

/// The syntactic scan of one item.
struct Scan<'a> {
    db: &'a dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    set: Mnemonic,
    owners: HashMap<(Clause, u32), &'a GeneratedBlock>,
}

impl Scan<'_> {
    fn loc(&self, range: TextRange) -> Loc {
        Loc::in_item(self.file, self.item, range)
    }

    /// HG8011 for every `DBn.DBX...` address of the item; in graphs only in statements that
    /// are analysed (C4) and never inside `[ ... ]`.
    fn db_addresses(&self, root: &SyntaxNode, stl: bool, out: &mut Vec<Diag>) {
        for node in root
            .descendants()
            .filter(|n| n.kind() == SyntaxKind::ADDRESS)
        {
            if node.ancestors().any(|a| a.kind() == SyntaxKind::INDIRECT) {
                continue;
            }
            if stl
                && let Some(stmt) = node.ancestors().find_map(ast::StlStmt::cast)
                && !is_analysed(&stmt, self.set)
            {
                continue;
            }
            let Some(address) = ast::Address::cast(node.clone()).and_then(|a| {
                address::read(&a.compact_text(), self.set).and_then(|r| r.address.ok())
            }) else {
                continue;
            };
            let at = self.loc(node.text_range());
            if let Some(diag) = db_address_hit(&self.owners, &address, &node_text(&node), at) {
                out.push(diag);
            }
        }
    }

    /// HG8010 for `CALL`/`CC` targets and `CALL` instance DBs.
    fn calls(&self, root: &SyntaxNode, out: &mut Vec<Diag>) {
        let statements = root
            .descendants()
            .filter(|n| n.kind() == SyntaxKind::STL_STMT)
            .filter_map(ast::StlStmt::cast);
        for stmt in statements {
            let op = stmt.opcode().map(|o| o.text()).unwrap_or_default();
            if !matches!(op.as_str(), "CALL" | "CC") || !is_analysed(&stmt, self.set) {
                continue;
            }
            let Some(args) = stmt.call_args() else {
                continue;
            };
            let mut refs = args.blocks();
            if let Some(target) = refs.next() {
                self.call_hit(&target, Clause::Fc, out);
            }
            if op == "CALL"
                && let Some(instance_db) = refs.next()
            {
                self.call_hit(&instance_db, Clause::Db, out);
            }
        }
    }

    fn call_hit(&self, reference: &ast::BlockRef, clause: Clause, out: &mut Vec<Diag>) {
        let index = db::global_index(self.db, self.ws);
        let Some(address) = resolve_block_ref(index, self.set, reference).address() else {
            return;
        };
        if address.block_kind() != Some(clause.kind()) {
            return;
        }
        let Some(owner) = self.owners.get(&(clause, address.number)) else {
            return;
        };
        let what = match clause {
            Clause::Fc => "called",
            Clause::Db => "used as an instance DB",
        };
        out.push(
            Diag::new(
                "HG8010",
                self.loc(resolve::block_reference_range(reference)),
                format!(
                    "{} {} is generated by group {} and cannot be {what}",
                    clause.upper(),
                    address.number,
                    owner.group
                ),
            )
            .related(
                owner.clause_loc,
                format!(
                    "group {} generates {} {}",
                    owner.group,
                    clause.upper(),
                    address.number
                ),
            ),
        );
    }
}

/// Is a statement analysed at all (C4: not after HG4003, HG4004 or HG4008)? Its opcode must
/// be an operation of the HiGraph subset in one of the two sets, it must not start with a jump
/// label, and it must not contain `[ ... ]`.
fn is_analysed(stmt: &ast::StlStmt, set: Mnemonic) -> bool {
    if stmt.jump_label().is_some() {
        return false;
    }
    if stmt
        .syntax()
        .descendants()
        .any(|n| n.kind() == SyntaxKind::INDIRECT)
    {
        return false;
    }
    let Some(op) = stmt.opcode().map(|o| o.text()) else {
        return true;
    };
    lang::is_subset_op(&op, set) || lang::is_subset_op(&op, set.other())
}

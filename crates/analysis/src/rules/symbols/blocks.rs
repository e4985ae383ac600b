//! `block` interface items: HG4309 (the reference must denote an FC, FB, SFC or SFB), HG1104
//! for a symbolic reference spelled in another case, HG4010 for a malformed address, and the
//! resolved interfaces of the workspace (for HG4310 and for CALL actuals in HG3104).

use higraph_syntax::ast::{self, AstNode};

use super::{
    BlockTarget, check_address, check_block_ref_case, node_text, resolve_block_ref, target_kind,
};
use crate::{
    address::Address,
    db::{self, File, ItemKind, ItemLoc, Workspace},
    diag::Loc,
    lang::Section,
    resolve,
    rules::{Ctx, decls},
};

/// HG4309, HG1104 and HG4010 for the block reference of one `block` item.
pub(super) fn check_interface(ctx: &mut Ctx<'_>, interface: &ast::BlockInterface) {
    let Some(reference) = interface.block() else {
        return;
    };
    let written = ast::unquote(&node_text(reference.syntax())).to_owned();
    let range = resolve::block_reference_range(&reference);
    if let Some(node) = reference.address()
        && check_address(ctx, &node).is_err()
    {
        return;
    }
    let target = resolve_block_ref(ctx.index, ctx.mnemonic, &reference);
    if let BlockTarget::Symbol(symbol) = target {
        check_block_ref_case(ctx, &reference, &symbol.name);
    }
    let message = match &target {
        BlockTarget::NotASymbol => format!("'{written}' is not a global symbol"),
        BlockTarget::Invalid => return,
        BlockTarget::Absolute(_) | BlockTarget::Symbol(_) => {
            if target
                .address()
                .and_then(|a| a.block_kind())
                .is_some_and(|k| k.is_callable())
            {
                return;
            }
            let Some(kind) = target_kind(&target, ctx.mnemonic) else {
                return;
            };
            format!("'{written}' is {kind}; only FC, FB, SFC and SFB interfaces can be declared")
        }
    };
    let diag = ctx.diag("HG4309", range, message);
    ctx.push(diag);
}

/// A `block` item whose reference resolves to a callable block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct InterfaceTarget {
    /// The block the interface describes.
    pub address: Address,
    pub file: File,
    pub item: u32,
    /// The block reference as written.
    pub reference: String,
    /// The reference (§2.3: a quoted symbol without its quotes).
    pub reference_loc: Loc,
}

/// Every `block` item of the workspace that describes an FC, FB, SFC or SFB, in workspace
/// order, with symbols resolved to their addresses.
#[salsa::tracked(returns(ref))]
pub(crate) fn block_interface_addresses(
    db: &dyn salsa::Database,
    ws: Workspace,
) -> Vec<InterfaceTarget> {
    let index = db::global_index(db, ws);
    let mut targets = Vec::new();
    for &file in ws.files(db) {
        let set = db::file_mnemonic(db, ws, file);
        for (i, summary) in db::file_summary(db, file).items.iter().enumerate() {
            if summary.kind != ItemKind::BlockInterface {
                continue;
            }
            let item = i as u32;
            let root = db::item_root(db, ItemLoc::new(db, file, item));
            let Some(reference) = root
                .and_then(ast::BlockInterface::cast)
                .and_then(|b| b.block())
            else {
                continue;
            };
            let address = resolve_block_ref(index, set, &reference).address();
            let Some(address) = address.filter(|a| a.block_kind().is_some_and(|k| k.is_callable()))
            else {
                continue;
            };
            targets.push(InterfaceTarget {
                address,
                file,
                item,
                reference: node_text(reference.syntax()),
                reference_loc: Loc::in_item(file, item, resolve::block_reference_range(&reference)),
            });
        }
    }
    targets
}

/// The section of the formal `name` in the interface at `file`/`item`; `None` if the
/// interface has no such parameter.
pub(crate) fn interface_formal_section(
    db: &dyn salsa::Database,
    file: File,
    item: u32,
    name: &str,
) -> Option<Section> {
    let root = db::item_root(db, ItemLoc::new(db, file, item))?;
    let interface = ast::BlockInterface::cast(root)?;
    decls::declarations(interface.var_sections())
        .find(|(_, d)| {
            d.name()
                .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
        })
        .map(|(kind, _)| kind)
}

//! Global symbols and the workspace namespace (`diagnostics.md` §3.6, §3.1.3, §3.4.4):
//!
//! * per `symbols` item ([`check_table`]): HG6001 (type and address of a symbol), HG6006 (name
//!   length), and the address rules HG4009/HG4010 for symbol addresses;
//! * per `block` item ([`check_block_interface`]): HG4309, and HG1104 for its symbol reference;
//! * workspace-wide ([`check_workspace`]): HG1301, HG6002, HG6003, HG6004, HG4310, and HG6001 /
//!   HG6006 for imported symbols. HG6005 and HG6007 come from the import itself
//!   ([`crate::sdf`]).
//!
//! The helpers here ([`resolve_block_ref`], [`address_fits`], [`check_address`], ...) are shared
//! with the group rules.

mod blocks;
mod table;
mod workspace;

use higraph_syntax::{
    SyntaxNode,
    ast::{self, AstNode},
};

use super::Ctx;
use crate::{
    address::{self, AddressError, Area, BlockKind, Size},
    db::Workspace,
    diag::Diag,
    index::{GlobalIndex, Symbol, SymbolSource},
    lang::{Mnemonic, Type},
};

/// The resolved `block` interfaces, shared with the group rules (HG3104).
pub(crate) use blocks::{block_interface_addresses, interface_formal_section};

/// HG6001, HG6006, HG4009, HG4010 for the symbols of one `symbols` block.
pub(crate) fn check_table(ctx: &mut Ctx<'_>, table: &ast::Symbols) {
    table::check(ctx, table);
}

/// HG4309 and HG1104 for one `block` interface item.
pub(crate) fn check_block_interface(ctx: &mut Ctx<'_>, interface: &ast::BlockInterface) {
    blocks::check_interface(ctx, interface);
}

/// Is the item being checked a `block` item for a block that an earlier `block` item already
/// describes (HG4310; ignored otherwise, C3)?
pub(crate) fn is_later_interface(ctx: &Ctx<'_>) -> bool {
    let targets = blocks::block_interface_addresses(ctx.db, ctx.ws);
    let Some(this) = targets
        .iter()
        .find(|t| t.file == ctx.file && t.item == ctx.item)
    else {
        return false;
    };
    targets
        .iter()
        .find(|t| t.address == this.address)
        .is_some_and(|first| !(first.file == this.file && first.item == this.item))
}

/// Workspace-wide rules: HG1301, HG6002, HG6003, HG6004, HG4310, and HG6001/HG6006 for
/// imported symbols.
pub(crate) fn check_workspace(db: &dyn salsa::Database, ws: Workspace, out: &mut Vec<Diag>) {
    workspace::check(db, ws, out);
}

/// What a block reference (`FC 10`, `FC10`, `Name`, `"Name"`) denotes.
#[derive(Debug, Clone)]
pub(crate) enum BlockTarget<'a> {
    /// An absolute address (of any kind).
    Absolute(address::Address),
    /// A global symbol.
    Symbol(&'a Symbol),
    /// A name or quoted name that is no global symbol.
    NotASymbol,
    /// A malformed absolute address (reported by [`check_address`]) or a broken reference.
    Invalid,
}

impl BlockTarget<'_> {
    /// The address the reference denotes, if known.
    pub fn address(&self) -> Option<address::Address> {
        match self {
            BlockTarget::Absolute(a) => Some(a.clone()),
            BlockTarget::Symbol(s) => s.address.clone(),
            BlockTarget::NotASymbol | BlockTarget::Invalid => None,
        }
    }
}

/// Resolves a block reference: an address (also written without a space, `FC1`), else a
/// global symbol.
pub(crate) fn resolve_block_ref<'a>(
    index: &'a GlobalIndex,
    set: Mnemonic,
    reference: &ast::BlockRef,
) -> BlockTarget<'a> {
    if let Some(node) = reference.address() {
        return match address::read(&node.compact_text(), set).map(|r| r.address) {
            Some(Ok(a)) => BlockTarget::Absolute(a),
            _ => BlockTarget::Invalid,
        };
    }
    let name = if let Some(name) = reference.name_ref() {
        let text = name.text();
        if let Some(a) = well_formed_address(&text, set) {
            return BlockTarget::Absolute(a);
        }
        text
    } else if let Some(symbol) = reference.symbol_ref() {
        symbol.name()
    } else {
        return BlockTarget::Invalid;
    };
    match index.symbol(&name) {
        Some(symbol) => BlockTarget::Symbol(symbol),
        None => BlockTarget::NotASymbol,
    }
}

/// The address an identifier written without a space denotes (§2.4 rule 1): a well-formed
/// address of the active set (`T1`, `MW10`, `FC1`, not `M1`).
pub(crate) fn well_formed_address(text: &str, set: Mnemonic) -> Option<address::Address> {
    crate::resolve::address_without_space(text, set).and_then(|r| r.address.ok())
}

/// How a symbol is named in a message: as declared, with the quotes of a quoted declaration.
pub(crate) fn symbol_display(symbol: &Symbol) -> String {
    if symbol.quoted && symbol.source == SymbolSource::Declared {
        format!("\"{}\"", symbol.name)
    } else {
        symbol.name.clone()
    }
}

/// Does a type fit the size of an address (Appendix D, rule 2)? Block addresses fit no type
/// of a symbol or graph formal.
pub(crate) fn address_fits(address: &address::Address, ty: Type) -> bool {
    match (address.area, address.size) {
        (Area::Timer, _) => ty == Type::Timer,
        (Area::Counter, _) => ty == Type::Counter,
        (Area::Block(_), _) | (_, Size::None) => false,
        (_, Size::Bit) => ty == Type::Bool,
        (_, Size::Byte) => matches!(ty, Type::Byte | Type::Char),
        (_, Size::Word) => matches!(ty, Type::Word | Type::Int | Type::S5Time | Type::Date),
        (_, Size::Dword) => matches!(
            ty,
            Type::Dword | Type::Dint | Type::Real | Type::Time | Type::TimeOfDay
        ),
    }
}

/// The size of an address in words (`bit`, `word`, `double word`, `timer`, ...).
pub(crate) fn size_name(address: &address::Address) -> &'static str {
    match (address.area, address.size) {
        (Area::Timer, _) => "timer",
        (Area::Counter, _) => "counter",
        (Area::Block(_), _) | (_, Size::None) => "block",
        (_, Size::Bit) => "bit",
        (_, Size::Byte) => "byte",
        (_, Size::Word) => "word",
        (_, Size::Dword) => "double word",
    }
}

/// `a DB`, `an FC`, ... for a block kind.
pub(crate) fn block_kind_article(kind: BlockKind) -> &'static str {
    match kind {
        BlockKind::Ob => "an OB",
        BlockKind::Fc => "an FC",
        BlockKind::Fb => "an FB",
        BlockKind::Db => "a DB",
        BlockKind::Sfc => "an SFC",
        BlockKind::Sfb => "an SFB",
        BlockKind::Udt => "a UDT",
    }
}

/// What a resolved block reference is, for messages: `a DB`, `the address MW 10`,
/// `a symbol of DB 10`.
pub(crate) fn target_kind(target: &BlockTarget<'_>, set: Mnemonic) -> Option<String> {
    match target {
        BlockTarget::Absolute(a) => Some(match a.block_kind() {
            Some(kind) => block_kind_article(kind).to_owned(),
            None => format!("the address {}", a.display(set)),
        }),
        BlockTarget::Symbol(s) => s
            .address
            .as_ref()
            .map(|a| format!("a symbol of {}", a.display(set))),
        BlockTarget::NotASymbol | BlockTarget::Invalid => None,
    }
}

/// Where local data and the like end up: areas that cannot carry a global symbol (HG6001).
pub(crate) fn is_local(address: &address::Address) -> bool {
    address.area == Area::Local
}

/// The outcome of [`check_address`] for an address that did not read well.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum AddressProblem {
    /// `DBX...` without `DBn.` (HG4011, or HG6001 for a symbol).
    NeedsDb,
    /// `DIX...` (HG4011, or HG6001 for a symbol).
    InstanceDb,
    /// HG4009 or HG4010, already reported.
    Reported,
}

/// Reads an `ADDRESS` node in the file's set (addresses of the other set are translated) and
/// reports HG4009 (bit number above 7) and HG4010 (malformed) the way every address is
/// reported ([`crate::resolve::report_address_error`]). The HG4011 cases are returned for the
/// caller: a group actual reports HG4011, a symbol HG6001.
pub(crate) fn check_address(
    ctx: &mut Ctx<'_>,
    node: &ast::Address,
) -> Result<address::Address, AddressProblem> {
    let compact = node.compact_text();
    let Some(read) = address::read(&compact, ctx.mnemonic)
        .or_else(|| address::read(&compact, ctx.mnemonic.other()))
    else {
        return Err(AddressProblem::Reported);
    };
    match read.address {
        Ok(a) => Ok(a),
        Err(AddressError::NeedsDb) => Err(AddressProblem::NeedsDb),
        Err(AddressError::InstanceDb) => Err(AddressProblem::InstanceDb),
        Err(error) => {
            let written = node.syntax().text().to_string();
            crate::resolve::report_address_error(ctx, node.syntax().text_range(), &written, &error);
            Err(AddressProblem::Reported)
        }
    }
}

/// The text of a node as written, without surrounding white space.
pub(crate) fn node_text(node: &SyntaxNode) -> String {
    node.text().to_string().trim().to_owned()
}

/// HG1104 for a block reference (a name or a quoted name) that names the symbol `declared` in
/// another case.
pub(crate) fn check_block_ref_case(ctx: &mut Ctx<'_>, reference: &ast::BlockRef, declared: &str) {
    if let Some(token) = reference
        .name_ref()
        .and_then(|n| n.token())
        .or_else(|| reference.symbol_ref().and_then(|s| s.token()))
    {
        let used = ast::unquote(token.text()).to_owned();
        check_case(ctx, &token, &used, declared);
    }
}

/// HG1104 for a reference spelled in another case than its declaration.
pub(crate) fn check_case(
    ctx: &mut Ctx<'_>,
    token: &higraph_syntax::SyntaxToken,
    used: &str,
    declared: &str,
) {
    if used.eq_ignore_ascii_case(declared) {
        crate::resolve::case_hint(
            ctx,
            crate::resolve::string_inner_range(token),
            used,
            declared,
        );
    }
}

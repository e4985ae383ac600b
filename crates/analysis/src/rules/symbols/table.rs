//! The rules of one `symbols` block: HG6001 (unknown type, a type that does not fit the
//! address, an address that cannot carry a global symbol), HG6006 (name longer than 24
//! characters) and HG4009/HG4010 for the addresses.

use higraph_syntax::ast::{self, AstNode};

use super::{AddressProblem, address_fits, check_address, is_local, node_text, size_name};
use crate::{address::Address, index, lang::Type, rules::Ctx};

/// The longest symbol name STEP 7 accepts (HG6006).
pub(crate) const MAX_SYMBOL_NAME: usize = 24;

/// HG6001, HG6006, HG4009 and HG4010 for every symbol of one `symbols` block.
pub(super) fn check(ctx: &mut Ctx<'_>, table: &ast::Symbols) {
    for symbol in table.symbols() {
        // A later symbol of a name is reported (HG6003, HG1301) and otherwise ignored (C3).
        if !crate::rules::is_later_symbol(ctx, &symbol) {
            check_symbol(ctx, &symbol);
        }
    }
}

fn check_symbol(ctx: &mut Ctx<'_>, symbol: &ast::Symbol) {
    let Some(token) = symbol.name().and_then(|n| n.token()) else {
        return;
    };
    let declared = token.text().to_owned();
    let name = ast::unquote(&declared).to_owned();
    if let Some(message) = name_length_problem(&name) {
        let diag = ctx.diag("HG6006", token.text_range(), message);
        ctx.push(diag);
    }
    let Some(address_node) = symbol.address() else {
        return;
    };
    let address_text = node_text(address_node.syntax());
    let address = match check_address(ctx, &address_node) {
        Ok(a) if is_local(&a) => None,
        Ok(a) => Some(a),
        Err(AddressProblem::Reported) => return,
        Err(AddressProblem::NeedsDb | AddressProblem::InstanceDb) => None,
    };
    let Some(address) = address else {
        let diag = ctx.diag(
            "HG6001",
            address_node.syntax().text_range(),
            format!("symbol {declared}: {address_text} cannot have a global symbol"),
        );
        ctx.push(diag);
        return;
    };
    if let Some(ty) = symbol.ty() {
        check_type(ctx, &declared, &address_text, &address, &ty);
    }
}

/// HG6006's message if the name (quotes not counted) is longer than 24 characters.
pub(crate) fn name_length_problem(name: &str) -> Option<String> {
    let n = name.chars().count();
    (n > MAX_SYMBOL_NAME).then(|| {
        format!("symbol name '{name}' has {n} characters; STEP 7 allows at most {MAX_SYMBOL_NAME}")
    })
}

/// HG6001 for the declared type of a symbol.
fn check_type(
    ctx: &mut Ctx<'_>,
    declared: &str,
    address_text: &str,
    address: &Address,
    ty: &ast::TypeRef,
) {
    let Some(type_name) = ty.name() else {
        return;
    };
    let range = ty.syntax().text_range();
    let Some(parsed) = index::declared_type(ty) else {
        let diag = ctx.diag(
            "HG6001",
            range,
            format!("unknown data type '{}'", type_name.text()),
        );
        ctx.push(diag);
        return;
    };
    if let Some(message) = type_fit_problem(declared, address_text, address, parsed) {
        let mut diag = ctx.diag("HG6001", range, message);
        if let Some(default) = default_type(address) {
            diag = diag.fix(
                format!("Use the type {default}"),
                ctx.loc(range),
                default.to_string(),
            );
        }
        ctx.push(diag);
    }
}

/// HG6001's second message if `ty` does not fit the address (a block address takes no type).
pub(crate) fn type_fit_problem(
    symbol: &str,
    address_text: &str,
    address: &Address,
    ty: Type,
) -> Option<String> {
    (!address_fits(address, ty)).then(|| {
        format!(
            "symbol {symbol}: type {ty} does not fit address {address_text} ({})",
            size_name(address)
        )
    })
}

/// The type of an address, if a symbol may carry it.
pub(crate) fn default_type(address: &Address) -> Option<Type> {
    let ty = address.ty();
    (ty != Type::Block).then_some(ty)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{address, lang::Mnemonic};

    fn addr(text: &str) -> Address {
        address::read(text, Mnemonic::Simatic)
            .and_then(|r| r.address.ok())
            .expect("address")
    }

    #[test]
    fn types_fit_sizes() {
        assert!(type_fit_problem("S", "MW 10", &addr("MW10"), Type::Int).is_none());
        assert_eq!(
            type_fit_problem("S", "MW 10", &addr("MW10"), Type::Bool).as_deref(),
            Some("symbol S: type BOOL does not fit address MW 10 (word)")
        );
        assert!(type_fit_problem("S", "FC 1", &addr("FC1"), Type::Word).is_some());
        assert_eq!(name_length_problem("short"), None);
        assert!(name_length_problem(&"x".repeat(25)).is_some());
    }
}

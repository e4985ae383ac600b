//! The right-hand side of an actual parameter (`diagnostics.md` §2.4 "In a group"): `Name` and
//! `"Name"` are global symbols, an address is an address (also written without a space, `MW10`),
//! a constant is a constant, `Inst.Msg` is a message target.
//!
//! Resolution reports HG4101 (`'{name}' is not a global symbol`), HG4102 (an address area used
//! as a name), HG4103 (a symbol spelled like an address), HG1104 (case), HG4009–HG4012
//! (addresses), records symbol uses (HG6004), and gives the value's type for HG5104/HG5105.

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
    literal::{self, Acceptance, Literal},
};

use crate::{
    address::{self, Address},
    closest::closest,
    index::Symbol,
    lang::{self, Mnemonic, Type},
    resolve,
    rules::{
        Ctx,
        symbols::{
            AddressProblem, address_fits, check_address, check_case, node_text, well_formed_address,
        },
    },
};

/// A resolved actual value.
#[derive(Debug, Clone)]
pub(crate) enum Value<'a> {
    Symbol(&'a Symbol),
    Address(Address),
    Constant(Literal),
    /// `Inst.Msg` (checked by the message rules only).
    Message,
    /// Unresolved, broken or not checkable.
    Unknown,
}

impl Value<'_> {
    /// The type of the value; `None` if unknown (C2) or a message target.
    pub fn ty(&self) -> Option<String> {
        match self {
            Value::Symbol(s) => s.ty.map(|t| t.to_string()),
            Value::Address(a) => Some(a.ty().to_string()),
            Value::Constant(lit) => Some(literal::literal_type(lit).to_owned()),
            Value::Message | Value::Unknown => None,
        }
    }

    /// Is the value compatible with a formal of type `formal` (Appendix D)? `None` when a type
    /// is unknown.
    pub fn compatible(&self, formal: Type) -> Option<bool> {
        match self {
            Value::Symbol(s) => s.ty.map(|t| same_type(t, formal)),
            Value::Address(a) => Some(address_fits(a, formal)),
            Value::Constant(lit) => {
                Some(literal::accepts(&formal.to_string(), lit) == Acceptance::Accepted)
            }
            Value::Message | Value::Unknown => None,
        }
    }

    /// Is it a constant?
    pub fn is_constant(&self) -> bool {
        matches!(self, Value::Constant(_))
    }

    /// Can it carry an external message (§2.7a): a global bit address, or a BOOL symbol on
    /// one? `None` if the type is unknown.
    pub fn is_external_message(&self) -> Option<bool> {
        match self {
            Value::Address(a) => Some(a.is_global_bit()),
            Value::Symbol(s) => {
                let ty = s.ty?;
                Some(ty == Type::Bool && s.address.as_ref().is_some_and(|a| a.is_global_bit()))
            }
            Value::Constant(_) => Some(false),
            Value::Message | Value::Unknown => None,
        }
    }

    /// The address it denotes (an address, or a symbol's address).
    pub fn address(&self) -> Option<&Address> {
        match self {
            Value::Symbol(s) => s.address.as_ref(),
            Value::Address(a) => Some(a),
            _ => None,
        }
    }
}

/// Equal types; STRING lengths are not compared (Appendix D, rule 1).
fn same_type(a: Type, b: Type) -> bool {
    matches!((a, b), (Type::String(_), Type::String(_))) || a == b
}

/// Resolves an actual value, reporting what fails.
pub(crate) fn resolve<'a>(ctx: &mut Ctx<'a>, operand: &ast::Operand) -> Value<'a> {
    match operand {
        ast::Operand::Address(node) => resolve_address(ctx, node),
        ast::Operand::NameRef(name) => resolve_name(ctx, name),
        ast::Operand::SymbolRef(symbol) => resolve_quoted(ctx, symbol),
        ast::Operand::VarRef(var) => {
            let name = var.name().map(|t| t.text().to_owned()).unwrap_or_default();
            report_unresolved(ctx, &name, var.syntax().text_range(), false);
            Value::Unknown
        }
        ast::Operand::Literal(lit) => literal::check_literal(&lit.text())
            .map(Value::Constant)
            .unwrap_or(Value::Unknown),
        ast::Operand::MessageTarget(_) => Value::Message,
        ast::Operand::Indirect(_) | ast::Operand::Status(_) | ast::Operand::Path(_) => {
            Value::Unknown
        }
    }
}

fn resolve_address<'a>(ctx: &mut Ctx<'a>, node: &ast::Address) -> Value<'a> {
    let written = node_text(node.syntax());
    let range = node.syntax().text_range();
    match check_address(ctx, node) {
        Ok(a) => {
            report_local(ctx, &a, &written, range);
            Value::Address(a)
        }
        Err(AddressProblem::NeedsDb) => {
            let diag = ctx.diag(
                "HG4011",
                range,
                format!(
                    "'{written}' needs a data block number ('DBn.{written}'); no DB can be opened in HiGraph"
                ),
            );
            ctx.push(diag);
            Value::Unknown
        }
        Err(AddressProblem::InstanceDb) => {
            let diag = ctx.diag(
                "HG4011",
                range,
                "instance-DB operands are not available in HiGraph",
            );
            ctx.push(diag);
            Value::Unknown
        }
        Err(AddressProblem::Reported) => Value::Unknown,
    }
}

/// HG4012 for temporary local data.
fn report_local(ctx: &mut Ctx<'_>, address: &Address, written: &str, range: TextRange) {
    if address.area == address::Area::Local {
        let diag = ctx.diag(
            "HG4012",
            range,
            format!(
                "'{written}' is temporary local data of the generated FC; its value is not kept"
            ),
        );
        ctx.push(diag);
    }
}

fn resolve_name<'a>(ctx: &mut Ctx<'a>, name: &ast::NameRef) -> Value<'a> {
    let Some(token) = name.token() else {
        return Value::Unknown;
    };
    let text = name.text();
    let range = token.text_range();
    let index = ctx.index;
    let symbol = index.symbol(&text);
    if let Some(address) = well_formed_address(&text, ctx.mnemonic) {
        if symbol.is_some_and(|s| s.address.as_ref() != Some(&address)) {
            let quoted = format!("\"{text}\"");
            let diag = ctx
                .diag(
                    "HG4103",
                    range,
                    format!(
                        "'{text}' is read as the address {}, not as the symbol {text}",
                        address.display(ctx.mnemonic)
                    ),
                )
                .fix(format!("Replace with '{quoted}'"), ctx.loc(range), quoted);
            ctx.push(diag);
        }
        report_local(ctx, &address, &text, range);
        return Value::Address(address);
    }
    if let Some(word) = resolve::area_word(&text, ctx.mnemonic) {
        return resolve_area_word(ctx, &text, range, &word);
    }
    match symbol {
        Some(symbol) => {
            ctx.use_symbol(&symbol.name);
            check_case(ctx, &token, &text, &symbol.name);
            Value::Symbol(symbol)
        }
        None => match other_set_address(&text, ctx.mnemonic) {
            Some(address) => Value::Address(address),
            None => {
                report_unresolved(ctx, &text, range, false);
                Value::Unknown
            }
        },
    }
}

/// A bare area identifier or register name (§2.4 rule 2): HG4102 if a symbol of that name
/// exists (then it resolves as `"Name"`), else HG4010 (area) or HG4101 (register).
fn resolve_area_word<'a>(
    ctx: &mut Ctx<'a>,
    text: &str,
    range: TextRange,
    word: &resolve::AreaWord,
) -> Value<'a> {
    let index = ctx.index;
    if let Some(symbol) = index.symbol(text) {
        let quoted = format!("\"{text}\"");
        let diag = ctx
            .diag(
                "HG4102",
                range,
                format!(
                    "'{text}' reads as the address area {} ({}); write \"{text}\" for the symbol",
                    word.canonical, word.meaning
                ),
            )
            .fix(format!("Replace with '{quoted}'"), ctx.loc(range), quoted);
        ctx.push(diag);
        ctx.use_symbol(&symbol.name);
        return Value::Symbol(symbol);
    }
    if word.register {
        report_unresolved(ctx, text, range, false);
        return Value::Unknown;
    }
    let reason = match address::read(text, ctx.mnemonic).map(|r| r.address) {
        Some(Err(address::AddressError::Malformed(reason))) => reason,
        _ => format!("{} needs a number", word.canonical),
    };
    let diag = ctx.diag(
        "HG4010",
        range,
        format!("'{text}' is not a valid address: {reason}"),
    );
    ctx.push(diag);
    Value::Unknown
}

/// An identifier that is a well-formed address only of the other mnemonic set; used when no
/// symbol of that name exists.
fn other_set_address(text: &str, set: Mnemonic) -> Option<Address> {
    address::read(text, set)
        .filter(|r| r.other_set)
        .and_then(|r| r.address.ok())
}

fn resolve_quoted<'a>(ctx: &mut Ctx<'a>, symbol_ref: &ast::SymbolRef) -> Value<'a> {
    let Some(token) = symbol_ref.token() else {
        return Value::Unknown;
    };
    let name = symbol_ref.name();
    let index = ctx.index;
    match index.symbol(&name) {
        Some(symbol) => {
            ctx.use_symbol(&symbol.name);
            check_case(ctx, &token, &name, &symbol.name);
            Value::Symbol(symbol)
        }
        None => {
            report_unresolved(ctx, &name, symbol_ref.syntax().text_range(), true);
            Value::Unknown
        }
    }
}

/// HG4101 in a group, with the closest symbol as a fix.
fn report_unresolved(ctx: &mut Ctx<'_>, name: &str, range: TextRange, quoted: bool) {
    let mut diag = ctx.diag("HG4101", range, format!("'{name}' is not a global symbol"));
    let index = ctx.index;
    let candidates = index.symbols.iter().map(|s| s.name.as_str());
    if let Some(best) = closest(name, candidates) {
        let text = if quoted {
            format!("\"{best}\"")
        } else {
            lang::operand_spelling(best)
        };
        diag = diag
            .fix(format!("Replace with '{text}'"), ctx.loc(range), text)
            .preferred();
    }
    ctx.push(diag);
}

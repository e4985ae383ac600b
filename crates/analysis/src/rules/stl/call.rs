//! Block calls (`diagnostics.md` §3.4.4): HG4301 (target cannot be called), HG4302 (instance
//! DB), HG4303 (type conflict), HG4304 (unknown parameter), HG4305 (missing parameters),
//! HG4306 (parameter given twice), HG4307 (interface unknown, off by default) and HG4308 (`CC`
//! with parameters or an instance DB).
//!
//! A callee's interface is known when the workspace has a `block` item for it; otherwise
//! HG4303–HG4306 are not evaluated and the actuals count as uses of unknown access (C4,
//! Appendix E). HG4301 replaces HG4101 for CALL/CC targets.

use std::collections::HashMap;

use higraph_syntax::{SyntaxKind, TextRange, TextSize, ast, ast::AstNode, literal};

use super::{
    Ctx,
    access::{self, Access},
    statement::{self, type_name},
};
use crate::{
    address::{Address, BlockKind},
    closest, db,
    index::{self, Symbol},
    lang::{Section, Type},
    resolve::{self, GraphScope, Resolved, Role, Target, Usage},
    rules::{decls, symbols::block_kind_article},
};

/// A `CALL` or `CC` statement.
pub(super) struct Call<'s> {
    pub stmt: &'s ast::StlStmt,
    /// `CALL` or `CC`.
    pub op: &'s str,
    /// The operation as written.
    pub display: &'s str,
    pub opcode_range: TextRange,
    pub stmt_range: TextRange,
    /// The transition's label when the call is in a condition part (HG4402).
    pub condition_of: Option<&'s str>,
}

/// Checks a call. Returns `false` if the statement is not analysed further (HG4003/HG4004 on
/// an actual).
pub(super) fn check(ctx: &mut Ctx<'_>, scope: &mut GraphScope, call: &Call<'_>) -> bool {
    let Some(args) = call.stmt.call_args() else {
        let message = format!("'{}' needs an operand", call.display);
        let diag = ctx.diag("HG4206", call.opcode_range, message);
        ctx.push(diag);
        return true;
    };
    // `CC FC [MW 50]`: an indirect target is HG4004 alone (C4).
    if let Some(indirect) = args.syntax().children().find_map(ast::Indirect::cast) {
        let operand = ast::Operand::Indirect(indirect);
        statement::forbidden_operand(ctx, scope, &operand);
        return false;
    }
    let params: Vec<ast::Param> = args.params().collect();
    for param in &params {
        if let Some(value) = param.value()
            && statement::forbidden_operand(ctx, scope, &value)
        {
            return false;
        }
    }
    let blocks: Vec<ast::BlockRef> = args.blocks().collect();
    let Some(target) = blocks.first() else {
        return true;
    };
    let instance_db = blocks.get(1);
    let callee = resolve_target(ctx, scope, target);
    let is_cc = call.op == "CC";
    if is_cc {
        check_conditional_call(ctx, scope, call, callee.as_ref(), instance_db, &params);
    } else {
        check_instance_db(ctx, scope, callee.as_ref(), instance_db);
    }
    let formals = callee.as_ref().and_then(|c| interface_of(ctx, c));
    let actuals = match (&callee, &formals) {
        (Some(callee), Some(formals)) if !is_cc => {
            check_parameters(ctx, scope, callee, formals, &params)
        }
        _ => unchecked_parameters(ctx, scope, &params),
    };
    report_other_set(ctx, call, &actuals);
    if let Some(callee) = &callee {
        if let Some(formals) = &formals {
            missing_parameters(ctx, callee, formals, &params, is_cc);
        } else if !is_cc {
            let message = format!(
                "interface of {} is unknown; its parameters are not checked",
                callee.text
            );
            let diag = ctx.diag("HG4307", callee.reference, message);
            ctx.push(diag);
        }
    }
    if let Some(transition) = call.condition_of {
        let target_text = target.syntax().text().to_string();
        statement::action_in_condition(
            ctx,
            call.stmt,
            call.stmt_range,
            call.display,
            &target_text,
            transition,
        );
    }
    true
}

// ------------------------------------------------------------------------------ target

/// A callable block, as far as it is known.
#[derive(Debug, Clone)]
struct Callee {
    /// The target as written (`FC 10`, `"Dosieren"`).
    text: String,
    /// The whole target, quotes included (for edits).
    range: TextRange,
    /// The target as a reference (§2.3: a quoted symbol without its quotes), where the
    /// diagnostics about it go.
    reference: TextRange,
    /// The block kind; `None` for a symbol whose address cannot be read.
    kind: Option<BlockKind>,
    address: Option<Address>,
    /// The symbol the target names, if any.
    symbol: Option<String>,
}

/// Resolves a CALL/CC target. Reports HG4301 (and address errors) and returns `None` if it
/// cannot be called.
fn resolve_target(ctx: &mut Ctx<'_>, scope: &GraphScope, target: &ast::BlockRef) -> Option<Callee> {
    let text = target.syntax().text().to_string();
    let range = target.syntax().text_range();
    if let Some(address) = target.address() {
        let addr = resolve::read_address_node(ctx, &address).address?;
        return callee_at(ctx, text, range, range, addr, None);
    }
    let (name, reference) = if let Some(name_ref) = target.name_ref() {
        let token = name_ref.token()?;
        let name = token.text().to_owned();
        if let Some(read) = resolve::address_without_space(&name, ctx.mnemonic) {
            return match read.address {
                Ok(addr) => {
                    resolve::shadowed_name_warning(ctx, scope, range, &name, &addr);
                    callee_at(ctx, text, range, range, addr, None)
                }
                Err(error) => {
                    resolve::report_address_error(ctx, range, &text, &error);
                    None
                }
            };
        }
        (name, token.text_range())
    } else {
        let symbol_ref = target.symbol_ref()?;
        (symbol_ref.name(), resolve::block_reference_range(target))
    };
    let index = ctx.index;
    if let Some(symbol) = index.symbol(&name) {
        resolve::case_hint(ctx, reference, &name, &symbol.name);
        ctx.use_symbol(&symbol.name);
        return callee_of_symbol(ctx, text, range, reference, &name, symbol);
    }
    not_callable(ctx, range, reference, &name);
    None
}

/// A target that is an absolute block address (or a symbol's).
fn callee_at(
    ctx: &mut Ctx<'_>,
    text: String,
    range: TextRange,
    reference: TextRange,
    addr: Address,
    symbol: Option<String>,
) -> Option<Callee> {
    match addr.block_kind() {
        Some(kind) if kind.is_callable() => Some(Callee {
            text,
            range,
            reference,
            kind: Some(kind),
            address: Some(addr),
            symbol,
        }),
        _ => {
            // `a DB`, `a symbol of E 1.0` (the wording of HG4309).
            let what = match (&symbol, addr.block_kind()) {
                (Some(_), _) => format!("a symbol of {}", addr.display(ctx.mnemonic)),
                (None, Some(kind)) => block_kind_article(kind).to_owned(),
                (None, None) => format!("the address {}", addr.display(ctx.mnemonic)),
            };
            let name = symbol.unwrap_or(text);
            cannot_be_called(ctx, reference, &name, &what);
            None
        }
    }
}

fn callee_of_symbol(
    ctx: &mut Ctx<'_>,
    text: String,
    range: TextRange,
    reference: TextRange,
    name: &str,
    symbol: &Symbol,
) -> Option<Callee> {
    match &symbol.address {
        Some(addr) => callee_at(
            ctx,
            text,
            range,
            reference,
            addr.clone(),
            Some(name.to_owned()),
        ),
        // The symbol's address is malformed (HG6001 elsewhere): callable as far as we know.
        None => Some(Callee {
            text,
            range,
            reference,
            kind: None,
            address: None,
            symbol: Some(symbol.name.clone()),
        }),
    }
}

/// HG4301 for a name that is no symbol: a graph, group or chart, or nothing at all. The
/// diagnostic covers the reference; the fix replaces the whole target (quotes included).
fn not_callable(ctx: &mut Ctx<'_>, range: TextRange, reference: TextRange, name: &str) {
    let index = ctx.index;
    let item = index.item(name);
    let message = match item.map(|i| i.kind) {
        Some(db::ItemKind::Graph) => {
            format!("'{name}' is a graph; graphs are instantiated in groups, not called")
        }
        Some(db::ItemKind::Group) => format!("'{name}' is a group, which cannot be called"),
        Some(db::ItemKind::Chart) => format!("'{name}' is a chart, which cannot be called"),
        _ => format!("unknown block '{name}'"),
    };
    let mut diag = ctx.diag("HG4301", reference, message);
    let callable = index.symbols.iter().filter(|s| {
        s.address
            .as_ref()
            .and_then(|a| a.block_kind())
            .is_some_and(|k| k.is_callable())
    });
    if let Some(best) = closest::closest(name, callable.map(|s| s.name.as_str())) {
        let text = if best.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            best.to_owned()
        } else {
            format!("\"{best}\"")
        };
        diag = diag
            .fix(format!("Replace with {text}"), ctx.loc(range), text)
            .preferred();
    }
    ctx.push(diag);
}

fn cannot_be_called(ctx: &mut Ctx<'_>, range: TextRange, name: &str, what: &str) {
    let message = format!("'{name}' is {what}, which cannot be called");
    let diag = ctx.diag("HG4301", range, message);
    ctx.push(diag);
}

// ------------------------------------------------------------------------------ instance DB

/// HG4302: an FB/SFB needs an instance DB, an FC/SFC takes none, and the DB must be one.
fn check_instance_db(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    callee: Option<&Callee>,
    instance_db: Option<&ast::BlockRef>,
) {
    let kind = callee.and_then(|c| c.kind);
    let needs_db = matches!(kind, Some(BlockKind::Fb | BlockKind::Sfb));
    let takes_no_db = matches!(kind, Some(BlockKind::Fc | BlockKind::Sfc));
    match (callee, instance_db) {
        (Some(callee), None) if needs_db => {
            let block = &callee.text;
            let message = format!("{block} needs an instance DB: 'CALL {block}, DB n'");
            let diag = ctx.diag("HG4302", callee.reference, message);
            ctx.push(diag);
        }
        (Some(callee), Some(db)) if takes_no_db => {
            // The DB is still resolved: its uses count, and its own errors (HG4010, ...) are
            // reported as well (C6).
            resolve_db(ctx, scope, db);
            let message = format!("{} takes no instance DB", callee.text);
            let removal = TextRange::new(callee.range.end(), db.syntax().text_range().end());
            let reference = resolve::block_reference_range(db);
            let diag = ctx.diag("HG4302", reference, message).fix(
                "Remove the instance DB",
                ctx.loc(removal),
                "",
            );
            ctx.push(diag);
        }
        (_, Some(db)) if !resolve_db(ctx, scope, db) => {
            let name = block_ref_name(db);
            let message = format!("'{name}' is not a data block");
            let diag = ctx.diag("HG4302", resolve::block_reference_range(db), message);
            ctx.push(diag);
        }
        _ => {}
    }
}

/// Resolves an instance DB reference: `true` if it is a DB (or cannot be told).
fn resolve_db(ctx: &mut Ctx<'_>, scope: &GraphScope, db: &ast::BlockRef) -> bool {
    let range = db.syntax().text_range();
    let text = db.syntax().text().to_string();
    if let Some(address) = db.address() {
        return resolve::read_address_node(ctx, &address)
            .address
            .is_none_or(|a| a.block_kind() == Some(BlockKind::Db));
    }
    let (name, reference) = if let Some(name_ref) = db.name_ref() {
        let Some(token) = name_ref.token() else {
            return true;
        };
        let name = token.text().to_owned();
        if let Some(read) = resolve::address_without_space(&name, ctx.mnemonic) {
            return match read.address {
                Ok(addr) => {
                    resolve::shadowed_name_warning(ctx, scope, range, &name, &addr);
                    addr.block_kind() == Some(BlockKind::Db)
                }
                Err(error) => {
                    resolve::report_address_error(ctx, range, &text, &error);
                    true
                }
            };
        }
        (name, token.text_range())
    } else if let Some(symbol_ref) = db.symbol_ref() {
        (symbol_ref.name(), resolve::block_reference_range(db))
    } else {
        return true;
    };
    let index = ctx.index;
    let Some(symbol) = index.symbol(&name) else {
        return false;
    };
    resolve::case_hint(ctx, reference, &name, &symbol.name);
    ctx.use_symbol(&symbol.name);
    symbol
        .address
        .as_ref()
        .is_none_or(|a| a.block_kind() == Some(BlockKind::Db))
}

/// A block reference's name for messages: without quotes.
fn block_ref_name(block: &ast::BlockRef) -> String {
    match block.symbol_ref() {
        Some(symbol) => symbol.name(),
        None => block.syntax().text().to_string(),
    }
}

/// HG4308: `CC` with parameters, an instance DB, or an FB/SFB target.
fn check_conditional_call(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    call: &Call<'_>,
    callee: Option<&Callee>,
    instance_db: Option<&ast::BlockRef>,
    params: &[ast::Param],
) {
    if let Some(db) = instance_db {
        // HG4308 covers a DB given at all; its own errors (HG4010, ...) are reported too (C6).
        resolve_db(ctx, scope, db);
    }
    let function_block = matches!(
        callee.and_then(|c| c.kind),
        Some(BlockKind::Fb | BlockKind::Sfb)
    );
    let has_params = call
        .stmt
        .syntax()
        .descendants()
        .any(|n| n.kind() == SyntaxKind::PARAM_LIST);
    if has_params || instance_db.is_some() || function_block || !params.is_empty() {
        let diag = ctx.diag(
            "HG4308",
            call.stmt_range,
            "'CC' calls only an FC or SFC without parameters",
        );
        ctx.push(diag);
    }
}

// ------------------------------------------------------------------------------ interface

/// A formal parameter of a known interface.
#[derive(Debug, Clone)]
struct Formal {
    name: String,
    section: Section,
    /// `None` if the declared type is unknown.
    ty: Option<Type>,
}

impl Formal {
    fn access(&self) -> Access {
        match self.section {
            Section::In => Access::Read,
            Section::Out => Access::Write,
            Section::InOut | Section::Stat => Access::ReadWrite,
        }
    }
}

/// The parameters of the callee's `block` interface, if the workspace declares one (the
/// first in workspace order).
fn interface_of(ctx: &Ctx<'_>, callee: &Callee) -> Option<Vec<Formal>> {
    let index = ctx.index;
    let entry = index.block_interfaces.iter().find(|entry| {
        let (address, symbol) = interface_target(ctx, &entry.reference);
        match (&callee.address, address) {
            (Some(a), Some(b)) => *a == b,
            _ => match (&callee.symbol, symbol) {
                (Some(a), Some(b)) => a.eq_ignore_ascii_case(&b),
                _ => false,
            },
        }
    })?;
    let item = db::ItemLoc::new(ctx.db, entry.file, entry.item);
    let root = db::item_root(ctx.db, item)?;
    let interface = ast::BlockInterface::cast(root)?;
    let mut formals: Vec<Formal> = Vec::new();
    for (kind, decl) in decls::declarations(interface.var_sections()) {
        if kind == Section::Stat {
            continue;
        }
        let Some(name) = decl.name().map(|n| n.text()) else {
            continue;
        };
        if formals.iter().any(|f| f.name.eq_ignore_ascii_case(&name)) {
            continue;
        }
        formals.push(Formal {
            name,
            section: kind,
            ty: decl.ty().and_then(|t| index::declared_type_in(&t, true)),
        });
    }
    Some(formals)
}

/// What a `block` item's reference names: a block address and/or a symbol name.
fn interface_target(ctx: &Ctx<'_>, reference: &str) -> (Option<Address>, Option<String>) {
    let trimmed = reference.trim();
    if trimmed.starts_with('"') {
        let name = ast::unquote(trimmed).to_owned();
        let address = ctx.index.symbol(&name).and_then(|s| s.address.clone());
        return (address, Some(name));
    }
    if let Some(address) =
        index::read_address(trimmed, ctx.mnemonic).filter(|a| a.block_kind().is_some())
    {
        return (Some(address), None);
    }
    let address = ctx.index.symbol(trimmed).and_then(|s| s.address.clone());
    (address, Some(trimmed.to_owned()))
}

// ------------------------------------------------------------------------------ parameters

/// Parameters against a known interface: HG4303, HG4304, HG4306, and the access rules.
fn check_parameters<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    callee: &Callee,
    formals: &[Formal],
    params: &[ast::Param],
) -> Vec<Resolved<'a>> {
    let mut seen: HashMap<String, TextRange> = HashMap::new();
    let mut actuals = Vec::new();
    for param in params {
        let Some(formal_ref) = param.formal() else {
            continue;
        };
        let Some(token) = formal_ref.token() else {
            continue;
        };
        let written = token.text().to_owned();
        let range = token.text_range();
        let key = index::key(&written);
        let formal = formals
            .iter()
            .find(|f| f.name.eq_ignore_ascii_case(&written));
        if let Some(first) = seen.get(&key) {
            let message = format!("parameter '{written}' is given twice");
            let diag = ctx
                .diag("HG4306", range, message)
                .related(ctx.loc(*first), format!("'{written}' is first given here"))
                .fix(
                    "Remove the later parameter",
                    ctx.loc(parameter_removal(param)),
                    "",
                );
            ctx.push(diag);
        } else {
            seen.insert(key, range);
        }
        match formal {
            Some(formal) => resolve::case_hint(ctx, range, &written, &formal.name),
            None => unknown_parameter(ctx, callee, formals, params, &seen, &written, range),
        }
        let Some(value) = param.value() else { continue };
        let resolved = resolve_actual(ctx, scope, &value);
        let access = formal.map_or(Access::Unknown, Formal::access);
        if let Some(formal) = formal {
            check_compatibility(ctx, callee, formal, &resolved);
        }
        access::check(ctx, scope, &resolved, access, Some("CALL"));
        actuals.push(resolved);
    }
    actuals
}

/// Parameters of a call whose interface is unknown (or of a `CC`): only resolved, as uses of
/// unknown access.
fn unchecked_parameters<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    params: &[ast::Param],
) -> Vec<Resolved<'a>> {
    let mut actuals = Vec::new();
    for value in params.iter().filter_map(ast::Param::value) {
        let resolved = resolve_actual(ctx, scope, &value);
        access::check(ctx, scope, &resolved, Access::Unknown, Some("CALL"));
        actuals.push(resolved);
    }
    actuals
}

fn resolve_actual<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    value: &ast::Operand,
) -> Resolved<'a> {
    let usage = Usage {
        role: Role::Operand,
        implied: None,
    };
    resolve::resolve_operand(ctx, scope, value, usage)
}

/// HG4304: a parameter name that the interface lacks.
fn unknown_parameter(
    ctx: &mut Ctx<'_>,
    callee: &Callee,
    formals: &[Formal],
    params: &[ast::Param],
    seen: &HashMap<String, TextRange>,
    written: &str,
    range: TextRange,
) {
    let message = format!("{} has no parameter '{written}'", callee.text);
    let mut diag = ctx.diag("HG4304", range, message);
    let given = |f: &&Formal| {
        seen.contains_key(&index::key(&f.name))
            || params.iter().any(|p| {
                p.formal()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(&f.name))
            })
    };
    let unassigned = formals.iter().filter(|f| !given(f));
    if let Some(best) = closest::closest(written, unassigned.map(|f| f.name.as_str())) {
        diag = diag
            .fix(format!("Rename to '{best}'"), ctx.loc(range), best)
            .preferred();
    }
    ctx.push(diag);
}

/// The range removing a parameter together with the comma before it.
fn parameter_removal(param: &ast::Param) -> TextRange {
    let range = param.syntax().text_range();
    let comma = std::iter::successors(param.syntax().prev_sibling_or_token(), |e| {
        e.prev_sibling_or_token()
    })
    .find(|e| !e.kind().is_trivia());
    match comma {
        Some(e) if e.kind() == SyntaxKind::COMMA => e.text_range().cover(range),
        _ => range,
    }
}

/// HG4305: an FC or SFC call that leaves parameters out.
fn missing_parameters(
    ctx: &mut Ctx<'_>,
    callee: &Callee,
    formals: &[Formal],
    params: &[ast::Param],
    is_cc: bool,
) {
    if !matches!(callee.kind, Some(BlockKind::Fc | BlockKind::Sfc)) {
        return;
    }
    if is_cc && !params.is_empty() {
        return;
    }
    let missing: Vec<String> = formals
        .iter()
        .filter(|f| {
            !params.iter().any(|p| {
                p.formal()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(&f.name))
            })
        })
        .map(|f| format!("'{}'", f.name))
        .collect();
    if missing.is_empty() {
        return;
    }
    let message = format!(
        "call of {} lacks parameter(s) {}",
        callee.text,
        missing.join(", ")
    );
    let diag = ctx.diag("HG4305", callee.reference, message);
    ctx.push(diag);
}

// ------------------------------------------------------------------------------ HG4303

/// HG4303: an actual that is not compatible with its formal (Appendix D).
fn check_compatibility(ctx: &mut Ctx<'_>, callee: &Callee, formal: &Formal, actual: &Resolved<'_>) {
    let Some(formal_ty) = formal.ty else { return };
    let message = match compatible(formal_ty, formal.section, actual) {
        Some(Compatibility::Compatible) | None => return,
        Some(Compatibility::ConstantToOutput) => format!(
            "parameter {} of {} is an output; a constant cannot receive a value",
            formal.name, callee.text
        ),
        Some(Compatibility::Conflict) => {
            let actual_ty = actual_type_name(actual);
            let exact = matches!(
                (formal_ty, actual.ty),
                (Type::Int, Some(Type::Word)) | (Type::Dint, Some(Type::Dword))
            );
            let suffix = if exact {
                "; formal and actual types must match exactly"
            } else {
                ""
            };
            format!(
                "type conflict: parameter {} of {} is {formal_ty}, the actual {} is {actual_ty}{suffix}",
                formal.name, callee.text, actual.text
            )
        }
    };
    let diag = ctx.diag("HG4303", actual.range, message);
    ctx.push(diag);
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Compatibility {
    Compatible,
    Conflict,
    ConstantToOutput,
}

/// Appendix D. `None` when a type involved is unknown (C2).
fn compatible(formal: Type, section: Section, actual: &Resolved<'_>) -> Option<Compatibility> {
    let verdict = |ok: bool| {
        Some(if ok {
            Compatibility::Compatible
        } else {
            Compatibility::Conflict
        })
    };
    match actual.target.as_ref()? {
        Target::Constant(lit) => {
            if matches!(section, Section::Out | Section::InOut) {
                return Some(Compatibility::ConstantToOutput);
            }
            match formal {
                Type::Pointer => verdict(lit.class == literal::LiteralClass::Pointer),
                Type::Any | Type::BlockFc | Type::BlockFb | Type::BlockDb | Type::Block => {
                    verdict(false)
                }
                _ => verdict(
                    literal::accepts(&formal.to_string(), lit) == literal::Acceptance::Accepted,
                ),
            }
        }
        Target::Address(addr) => verdict(address_fits(formal, addr)),
        Target::Symbol(symbol) => match &symbol.address {
            Some(addr) if addr.block_kind().is_some() => verdict(address_fits(formal, addr)),
            _ => typed_fits(formal, actual.ty?),
        },
        Target::Var(_) | Target::Predefined(_) => typed_fits(formal, actual.ty?),
    }
}

/// Rule 1 (typed operands), with ANY and POINTER (rule 5).
fn typed_fits(formal: Type, actual: Type) -> Option<Compatibility> {
    let ok = match (formal, actual) {
        (Type::Any | Type::Pointer, _) => true,
        (Type::String(_), Type::String(_)) => true,
        (f, a) => f == a,
    };
    Some(if ok {
        Compatibility::Compatible
    } else {
        Compatibility::Conflict
    })
}

/// Rules 2, 4 and 5 for an absolute address.
fn address_fits(formal: Type, addr: &Address) -> bool {
    use crate::address::Size;
    if matches!(formal, Type::Any | Type::Pointer) {
        return true;
    }
    if let Some(kind) = addr.block_kind() {
        return matches!(
            (formal, kind),
            (Type::BlockFc, BlockKind::Fc)
                | (Type::BlockFb, BlockKind::Fb)
                | (Type::BlockDb, BlockKind::Db)
        );
    }
    match addr.ty() {
        Type::Timer => formal == Type::Timer,
        Type::Counter => formal == Type::Counter,
        _ => match addr.size {
            Size::Bit => formal == Type::Bool,
            Size::Byte => matches!(formal, Type::Byte | Type::Char),
            Size::Word => matches!(formal, Type::Word | Type::Int | Type::S5Time | Type::Date),
            Size::Dword => matches!(
                formal,
                Type::Dword | Type::Dint | Type::Real | Type::Time | Type::TimeOfDay
            ),
            Size::None => false,
        },
    }
}

fn actual_type_name(actual: &Resolved<'_>) -> String {
    match &actual.target {
        Some(Target::Symbol(symbol))
            if symbol
                .address
                .as_ref()
                .is_some_and(|a| a.block_kind().is_some()) =>
        {
            Type::Block.to_string()
        }
        _ => type_name(actual),
    }
}

// ------------------------------------------------------------------------------ HG4007

/// HG4007 once per call, for addresses of the other mnemonic set among the actuals, with the
/// call rewritten.
fn report_other_set(ctx: &mut Ctx<'_>, call: &Call<'_>, actuals: &[Resolved<'_>]) {
    let offending: Vec<&(TextRange, String)> = actuals
        .iter()
        .filter_map(|a| a.other_set.as_ref())
        .collect();
    let Some((first_range, first_token)) = offending.first() else {
        return;
    };
    let range = offending
        .iter()
        .fold(*first_range, |range, (r, _)| range.cover(*r));
    let rewrite = translated_call(call, actuals).map(|text| (call.stmt_range, text));
    statement::other_set_diag(ctx, range, first_token, rewrite);
}

/// The call as written, with every actual of the other mnemonic set replaced by its
/// translation (`CALL FC 10 (x := E 1.0)` for `CALL FC 10 (x := I 1.0)` in a SIMATIC file).
fn translated_call(call: &Call<'_>, actuals: &[Resolved<'_>]) -> Option<String> {
    let node = call.stmt.syntax();
    let text = node.text().to_string();
    let start = node.text_range().start();
    let slice = |from: TextSize, to: TextSize| -> Option<&str> {
        text.get(usize::from(from.checked_sub(start)?)..usize::from(to.checked_sub(start)?))
    };
    let mut out = String::new();
    let mut at = call.stmt_range.start();
    for actual in actuals.iter().filter(|a| a.other_set.is_some()) {
        out.push_str(slice(at, actual.range.start())?);
        out.push_str(actual.translated.as_deref().unwrap_or(&actual.text));
        at = actual.range.end();
    }
    out.push_str(slice(at, call.stmt_range.end())?);
    Some(out)
}

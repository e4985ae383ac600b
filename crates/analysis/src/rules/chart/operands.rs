//! Operand resolution in charts (`diagnostics.md` §2.4 "In a chart"): a `Name` is a variable of
//! the chart, else a global symbol, else an address written without a space; `"Name"` is a
//! global symbol; `SFC.` paths are the chart's runtime interface; other dotted paths are
//! external references.
//!
//! Diagnostics: HG4101 (unresolved operand; HG3005 for time values, in `times`), HG1104 (case
//! of a variable or symbol reference), HG7309 (a chart type uses something outside its
//! interface), HG7310 (external reference in a plain chart) and the address rules HG4009–HG4012.
//! Every resolution counts as a use (HG1210, HG6004), also in constructs with syntax errors,
//! whose diagnostics are skipped (C1).

use higraph_syntax::{
    TextRange, TextSize,
    ast::{self, AstNode},
};

use super::Scope;
use crate::{
    address::{self, Address},
    closest::closest,
    lang::{self, Type},
    resolve,
    rules::Ctx,
};

/// What an operand denotes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Target {
    /// A chart variable (index into [`Scope::vars`]).
    Var(usize),
    /// A global symbol: its name, type and address.
    Symbol {
        name: String,
        ty: Option<Type>,
        address: Option<Address>,
    },
    /// An absolute address; `None` if it is malformed.
    Address(Option<Address>),
    /// `SFC.…`: the chart's runtime interface.
    Sfc,
    /// Another dotted path: an external reference.
    External,
    /// What only an IEC chart has (`docs/iec.md` §3, §6).
    Iec(IecTarget),
    /// Nothing.
    Unresolved,
}

/// The operands of the IEC profile.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum IecTarget {
    /// `Inst.M`: a member of a function block instance (the variable's index into
    /// [`Scope::vars`]). Also in a PCS 7 chart, where the instance is HG7502, so that its uses
    /// do not cascade.
    FbMember {
        var: usize,
        member: &'static crate::iec::FbMember,
    },
    /// `Step.X` (BOOL: the step is active) or `Step.T` (TIME: how long it has been active).
    StepFlag { step: String, time: bool },
}

impl Target {
    /// The type of the operand; `None` if unknown (§2.4).
    pub fn ty(&self, scope: &Scope) -> Option<Type> {
        match self {
            Target::Var(i) => scope.vars.get(*i).and_then(|v| v.ty),
            Target::Symbol { ty, .. } => *ty,
            Target::Address(a) => a.as_ref().map(Address::ty),
            Target::Iec(IecTarget::FbMember { member, .. }) => Some(member.ty),
            Target::Iec(IecTarget::StepFlag { time, .. }) => {
                Some(if *time { Type::Time } else { Type::Bool })
            }
            Target::Sfc | Target::External | Target::Unresolved => None,
        }
    }

    /// Is it the same operand as `other` (HG7311): the same variable, the same symbol, the
    /// same normalised address, or a symbol together with its own address?
    pub fn same_as(&self, other: &Target) -> bool {
        match (self, other) {
            (Target::Var(a), Target::Var(b)) => a == b,
            (Target::Symbol { name: a, .. }, Target::Symbol { name: b, .. }) => {
                a.eq_ignore_ascii_case(b)
            }
            (
                Target::Symbol {
                    address: Some(s), ..
                },
                Target::Address(Some(a)),
            )
            | (
                Target::Address(Some(a)),
                Target::Symbol {
                    address: Some(s), ..
                },
            ) => s == a,
            (Target::Address(Some(a)), Target::Address(Some(b))) => a == b,
            (Target::Iec(a @ IecTarget::FbMember { .. }), Target::Iec(b)) => a == b,
            _ => false,
        }
    }
}

/// How to report an operand that does not resolve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Unresolved {
    /// HG4101.
    Operand,
    /// HG3005 (reported by the caller).
    TimeValue,
}

/// Resolves a chart path. With `report` false (a construct with a syntax error, C1, or a
/// value that another rule already rejects) only the use is recorded.
pub(crate) fn resolve(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    path: &ast::Path,
    unresolved: Unresolved,
    report: bool,
) -> Target {
    if let Some(address) = path.address() {
        let target = Target::Address(read_address(ctx, &address, report));
        if report {
            outside_interface(ctx, scope, path, "an absolute address");
        }
        return target;
    }
    if let Some(symbol) = path.symbol() {
        return quoted_symbol(ctx, scope, &symbol, path, unresolved, report);
    }
    let segments: Vec<ast::NameRef> = path.segments().collect();
    match segments.as_slice() {
        [] => Target::Unresolved,
        [name] => plain_name(ctx, scope, name, path, unresolved, report),
        [first, second] if iec_path(scope, first, second) => {
            member_path(ctx, scope, first, second, report)
        }
        [first, ..] => {
            if first.text().eq_ignore_ascii_case("SFC") {
                return Target::Sfc;
            }
            if report {
                external(ctx, scope, path);
            }
            Target::External
        }
    }
}

/// Is `first.second` a member of a function block instance (in any chart) or a step flag (in
/// an IEC chart)?
fn iec_path(scope: &Scope, first: &ast::NameRef, second: &ast::NameRef) -> bool {
    let name = first.text();
    match scope.var(&name) {
        Some(i) => scope.vars[i].fb.is_some(),
        None => {
            let flag = second.text();
            scope.iec
                && scope.has_step(&name)
                && (flag.eq_ignore_ascii_case("X") || flag.eq_ignore_ascii_case("T"))
        }
    }
}

/// `Inst.M` (HG7505 for an unknown member, in an IEC chart) or `Step.X`/`Step.T`.
fn member_path(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    first: &ast::NameRef,
    second: &ast::NameRef,
    report: bool,
) -> Target {
    let (Some(first_token), Some(second_token)) = (first.token(), second.token()) else {
        return Target::Unresolved;
    };
    let name = first_token.text();
    let Some(i) = scope.var(name) else {
        let flag = second_token.text();
        if report && let Some(step) = scope.steps.iter().find(|s| s.eq_ignore_ascii_case(name)) {
            resolve::case_hint(ctx, first_token.text_range(), name, &step.clone());
        }
        return Target::Iec(IecTarget::StepFlag {
            step: name.to_owned(),
            time: flag.eq_ignore_ascii_case("T"),
        });
    };
    scope.used[i] = true;
    let Some(fb) = scope.vars[i].fb else {
        return Target::Unresolved;
    };
    let report = report && scope.iec;
    if report {
        resolve::case_hint(ctx, first_token.text_range(), name, &scope.vars[i].name);
    }
    let member_name = second_token.text();
    let range = second_token.text_range();
    match fb.member(member_name) {
        Some(member) => {
            if report {
                resolve::case_hint(ctx, range, member_name, member.name);
            }
            Target::Iec(IecTarget::FbMember { var: i, member })
        }
        None => {
            if report {
                let diag = ctx.diag(
                    "HG7505",
                    range,
                    format!(
                        "{name} is a {}, which has no member '{member_name}'",
                        fb.name()
                    ),
                );
                let diag = ctx.with_closest_fix(
                    diag,
                    range,
                    member_name,
                    fb.members().iter().map(|m| m.name),
                );
                ctx.push(diag);
            }
            Target::Unresolved
        }
    }
}

/// `Name`: a variable, else a global symbol, else an address written without a space.
fn plain_name(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    name_ref: &ast::NameRef,
    path: &ast::Path,
    unresolved: Unresolved,
    report: bool,
) -> Target {
    let range = path.syntax().text_range();
    let Some(token) = name_ref.token() else {
        return Target::Unresolved;
    };
    let name = token.text();
    if let Some(i) = scope.var(name) {
        scope.used[i] = true;
        if report {
            resolve::case_hint(ctx, token.text_range(), name, &scope.vars[i].name);
        }
        return Target::Var(i);
    }
    if let Some(target) = symbol(ctx, name) {
        if report {
            if let Target::Symbol { name: declared, .. } = &target {
                resolve::case_hint(ctx, token.text_range(), name, declared);
            }
            outside_interface(ctx, scope, path, "a global symbol");
        }
        return target;
    }
    if let Some(read) = address::read(name, ctx.mnemonic)
        && !read.other_set
        && let Ok(address) = read.address
    {
        if report {
            outside_interface(ctx, scope, path, "an absolute address");
        }
        return Target::Address(Some(address));
    }
    if report && unresolved == Unresolved::Operand {
        unresolved_name(ctx, scope, name, range);
    }
    Target::Unresolved
}

/// `"Name"`: a global symbol.
fn quoted_symbol(
    ctx: &mut Ctx<'_>,
    scope: &Scope,
    symbol_ref: &ast::SymbolRef,
    path: &ast::Path,
    unresolved: Unresolved,
    report: bool,
) -> Target {
    let range = path.syntax().text_range();
    let name = symbol_ref.name();
    if let Some(target) = symbol(ctx, &name) {
        if report {
            if let (Target::Symbol { name: declared, .. }, Some(token)) =
                (&target, symbol_ref.token())
            {
                // The reference is the name without its quotes (§2.3).
                let start = token.text_range().start() + TextSize::from(1);
                let inner = TextRange::at(start, TextSize::of(name.as_str()));
                resolve::case_hint(ctx, inner, &name, declared);
            }
            outside_interface(ctx, scope, path, "a global symbol");
        }
        return target;
    }
    if report && unresolved == Unresolved::Operand {
        let mut diag = ctx.diag(
            "HG4101",
            range,
            format!("\"{name}\" is not a global symbol"),
        );
        let candidates: Vec<&str> = ctx.index.symbols.iter().map(|s| s.name.as_str()).collect();
        if let Some(best) = closest(&name, candidates) {
            diag = diag
                .fix(
                    format!("Replace with '\"{best}\"'"),
                    ctx.loc(range),
                    format!("\"{best}\""),
                )
                .preferred();
        }
        ctx.push(diag);
    }
    Target::Unresolved
}

/// The global symbol of that name, recorded as used (HG6004).
fn symbol(ctx: &mut Ctx<'_>, name: &str) -> Option<Target> {
    let index = ctx.index;
    let symbol = index.symbol(name)?;
    ctx.use_symbol(name);
    Some(Target::Symbol {
        name: symbol.name.clone(),
        ty: symbol.ty,
        address: symbol.address.clone(),
    })
}

/// HG4101 for `Name`, with the fix that replaces it by the closest variable or symbol name.
fn unresolved_name(ctx: &mut Ctx<'_>, scope: &Scope, name: &str, range: TextRange) {
    let mut diag = ctx.diag(
        "HG4101",
        range,
        format!(
            "'{name}' is neither a variable of {} nor a global symbol",
            scope.chart.owner()
        ),
    );
    let index = ctx.index;
    let mut candidates: Vec<&str> = scope
        .vars
        .iter()
        .filter(|v| !v.duplicate)
        .map(|v| v.name.as_str())
        .collect();
    if !scope.chart.is_type {
        candidates.extend(index.symbols.iter().map(|s| s.name.as_str()));
    }
    if let Some(best) = closest(name, candidates) {
        let text = lang::operand_spelling(best);
        diag = diag
            .fix(format!("Replace with '{text}'"), ctx.loc(range), text)
            .preferred();
    }
    ctx.push(diag);
}

/// HG7309: a chart type may only use its own interface.
fn outside_interface(ctx: &mut Ctx<'_>, scope: &Scope, path: &ast::Path, what: &str) {
    if !scope.chart.is_type {
        return;
    }
    let range = path.syntax().text_range();
    let text = path.syntax().text().to_string();
    let diag = ctx.diag(
        "HG7309",
        range,
        format!(
            "chart type {} may only use its own interface; {text} is {what}",
            scope.chart.name
        ),
    );
    ctx.push(diag);
}

/// HG7309 (chart type) or HG7310 (plain chart) for an external reference.
fn external(ctx: &mut Ctx<'_>, scope: &Scope, path: &ast::Path) {
    let range = path.syntax().text_range();
    if scope.chart.is_type {
        outside_interface(ctx, scope, path, "an external reference");
        return;
    }
    let text = super::collapsed(path.syntax());
    let diag = ctx.diag(
        "HG7310",
        range,
        format!("'{text}' is an external reference; it is not checked"),
    );
    ctx.push(diag);
}

/// Reads an address written in a chart; HG4009–HG4012 when `report`. Addresses of the other
/// mnemonic set are read in their translated form.
fn read_address(ctx: &mut Ctx<'_>, address: &ast::Address, report: bool) -> Option<Address> {
    let compact = address.compact_text();
    let written = address.syntax().text().to_string();
    let range = address.syntax().text_range();
    let read = address::read(&compact, ctx.mnemonic)?;
    match read.address {
        Ok(a) => {
            if report {
                resolve::local_data_warning(ctx, range, &written, &a);
            }
            Some(a)
        }
        Err(error) => {
            if report {
                resolve::report_address_error(ctx, range, &written, &error);
            }
            None
        }
    }
}

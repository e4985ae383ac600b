//! Variable declarations, shared by graphs, charts and `block` interfaces: HG1201 (a name
//! declared twice), HG1203 (`msg` outside a graph's `in_out`), HG1204 (`msg` on a type other
//! than BOOL), HG1205/HG1206 (initial value), HG1213 (`STRING[n]` length), HG1215 (unknown
//! type), and HG1210's diagnostic for an unused variable. The rules of one owner stay with it
//! (HG1202 and `activate` in `graph::decls`; which variables are used in `stl` and `chart`).
//!
//! [`section_kind`] and [`declarations`] read the sections as written, also for the places
//! that take declarations without checking them (graph scopes, graph interfaces seen from a
//! group, `block` interfaces seen from a CALL).

use std::collections::HashMap;

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
    literal::{self, Acceptance},
};

use super::{Ctx, edit, has_error};
use crate::{
    index,
    lang::{Section, Type},
};

/// The item that declares the variables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Owner {
    /// A graph: message variables (`msg`) are allowed in `in_out`.
    Graph,
    /// A chart: it has no message variables.
    Chart,
    /// A `block` interface: POINTER, ANY and the block types are allowed, `msg` is not.
    BlockInterface,
}

impl Owner {
    /// Are the block-interface-only types allowed?
    fn interface_types(self) -> bool {
        self == Owner::BlockInterface
    }

    /// May `msg` stand in `in_out`?
    fn has_messages(self) -> bool {
        self == Owner::Graph
    }
}

/// The block-interface-only type names (`language.md` §3.1).
const INTERFACE_TYPES: &[&str] = &["POINTER", "ANY", "BLOCK_FC", "BLOCK_FB", "BLOCK_DB"];

/// A declared variable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Var {
    /// As declared.
    pub name: String,
    pub name_range: TextRange,
    pub section: Section,
    /// `None` if the type is missing or invalid (unknown, §2.4).
    pub ty: Option<Type>,
    /// The whole declaration (for the HG1210 fix).
    pub decl_range: TextRange,
    /// A later duplicate (HG1201): ignored by references (C3).
    pub duplicate: bool,
    /// A chart variable of a standard function block type (`docs/iec.md` §3); `ty` is then
    /// `None`.
    pub fb: Option<crate::iec::FbType>,
}

/// The section a `VarSection` opens; `None` if its keyword is missing or unknown.
pub(crate) fn section_kind(section: &ast::VarSection) -> Option<Section> {
    section
        .keyword()
        .and_then(|k| Section::from_keyword(k.text()))
}

/// Every declaration of the sections whose keyword is known, with its section, in text order.
pub(crate) fn declarations(
    sections: impl IntoIterator<Item = ast::VarSection>,
) -> impl Iterator<Item = (Section, ast::VarDecl)> {
    sections.into_iter().flat_map(|section| {
        let kind = section_kind(&section);
        kind.into_iter()
            .flat_map(move |kind| section.decls().map(move |decl| (kind, decl)))
    })
}

/// The declaration rules inside a `block` interface (POINTER, ANY and the block types allowed).
pub(crate) fn check_block_interface(ctx: &mut Ctx<'_>, interface: &ast::BlockInterface) {
    let reference = interface
        .block()
        .map(|b| b.syntax().text().to_string())
        .unwrap_or_default();
    check_sections(
        ctx,
        interface.var_sections(),
        Owner::BlockInterface,
        &format!("block {reference}"),
        |_, _, _, _| {},
    );
}

/// HG1201, HG1203–HG1206, HG1213 and HG1215 for every declaration of the sections; returns
/// the variables in declaration order. `owner_text` is the `{owner}` of messages (`graph G`,
/// `chart C`, `block FC 10`). `each` is called for every declared name that is not a later
/// duplicate, right after HG1201 (graphs report HG1202 there).
pub(crate) fn check_sections(
    ctx: &mut Ctx<'_>,
    sections: impl IntoIterator<Item = ast::VarSection>,
    owner: Owner,
    owner_text: &str,
    mut each: impl FnMut(&mut Ctx<'_>, &ast::VarDecl, &str, TextRange),
) -> Vec<Var> {
    let mut vars: Vec<Var> = Vec::new();
    let mut first: HashMap<String, usize> = HashMap::new();
    for (section, decl) in declarations(sections) {
        let Some(token) = decl.name().and_then(|n| n.token()) else {
            continue;
        };
        let name = token.text().to_owned();
        let name_range = token.text_range();
        let earlier = first.get(&index::key(&name)).map(|&i| &vars[i]);
        if let Some(earlier) = earlier {
            let diag = ctx
                .diag(
                    "HG1201",
                    name_range,
                    format!("variable '{name}' is already declared in {owner_text}"),
                )
                .related(
                    ctx.loc(earlier.name_range),
                    format!("first declaration of '{}'", earlier.name),
                );
            ctx.push(diag);
        } else {
            first.insert(index::key(&name), vars.len());
        }
        let duplicate = earlier.is_some();
        // C3: a later duplicate is reported (HG1201) and otherwise ignored.
        if !duplicate {
            each(ctx, &decl, &name, name_range);
        }
        // C1: a broken declaration still declares its name; its other parts are not checked.
        let checked = !has_error(decl.syntax()) && !duplicate;
        let ty = checked_type(ctx, &decl, owner, checked);
        if checked {
            check_msg(ctx, &decl, &name, section, owner, ty);
            if let Some(ty) = ty {
                check_initial_value(ctx, &decl, ty);
            }
        }
        vars.push(Var {
            name,
            name_range,
            section,
            ty,
            decl_range: decl.syntax().text_range(),
            duplicate,
            fb: fb_type(&decl, owner),
        });
    }
    vars
}

/// The standard function block type of a chart variable (the chart rules report where it
/// may not stand: HG7502, HG7504).
fn fb_type(decl: &ast::VarDecl, owner: Owner) -> Option<crate::iec::FbType> {
    if owner != Owner::Chart {
        return None;
    }
    let name = decl.ty()?.name()?;
    crate::iec::FbType::from_name(name.text())
}

/// The declared type, if it is known and valid; HG1215 and HG1213 (when `report`) make it
/// unknown. A standard function block type in a chart is not a data type and no error here.
fn checked_type(
    ctx: &mut Ctx<'_>,
    decl: &ast::VarDecl,
    owner: Owner,
    report: bool,
) -> Option<Type> {
    let type_ref = decl.ty()?;
    let name = type_ref.name()?;
    let interface = owner.interface_types();
    let Some(ty) = Type::from_name(name.text(), interface) else {
        if report
            && !(owner == Owner::Chart && crate::iec::FbType::from_name(name.text()).is_some())
        {
            let mut candidates: Vec<&str> = Type::NAMES.to_vec();
            if interface {
                candidates.extend_from_slice(INTERFACE_TYPES);
            }
            let diag = ctx.diag(
                "HG1215",
                name.text_range(),
                format!("unknown data type '{}'", name.text()),
            );
            let diag = ctx.with_closest_fix(diag, name.text_range(), name.text(), candidates);
            ctx.push(diag);
        }
        return None;
    };
    match (ty, type_ref.length()) {
        (Type::String(_), Some(length)) => {
            let n = length.text();
            match n.parse::<u16>() {
                Ok(n @ 1..=254) => Some(Type::String(n)),
                _ => {
                    if report {
                        let diag = ctx.diag(
                            "HG1213",
                            type_ref.syntax().text_range(),
                            format!("string length {n} is outside 1..254"),
                        );
                        ctx.push(diag);
                    }
                    None
                }
            }
        }
        (ty, _) => Some(ty),
    }
}

/// HG1203 and HG1204: `msg` outside a graph's `in_out`, and `msg` on a type other than BOOL.
fn check_msg(
    ctx: &mut Ctx<'_>,
    decl: &ast::VarDecl,
    name: &str,
    section: Section,
    owner: Owner,
    ty: Option<Type>,
) {
    let Some(msg) = decl.msg_kind() else {
        return;
    };
    if !owner.has_messages() || section != Section::InOut {
        let diag = ctx
            .diag(
                "HG1203",
                msg.syntax().text_range(),
                match owner {
                    Owner::Graph => format!(
                        "message variables belong in 'in_out'; '{name}' is in '{}'",
                        section.as_str()
                    ),
                    Owner::Chart => format!(
                        "message variables belong in the 'in_out' section of a graph; \
                         '{name}' is declared in a chart"
                    ),
                    Owner::BlockInterface => format!(
                        "message variables belong in the 'in_out' section of a graph; \
                         '{name}' is declared in a block interface"
                    ),
                },
            )
            .fix(
                "Remove the 'msg' clause",
                ctx.loc(edit::removal_range(msg.syntax())),
                "",
            );
        ctx.push(diag);
    }
    if let (Some(ty), Some(type_ref)) = (ty, decl.ty())
        && ty != Type::Bool
    {
        let range = type_ref.syntax().text_range();
        let diag = ctx
            .diag(
                "HG1204",
                range,
                format!("message variable '{name}' must be BOOL, not {ty}"),
            )
            .fix("Change the type to BOOL", ctx.loc(range), "BOOL");
        ctx.push(diag);
    }
}

/// HG1205 and HG1206: the initial value must fit the declared type (Appendix C.2).
fn check_initial_value(ctx: &mut Ctx<'_>, decl: &ast::VarDecl, ty: Type) {
    let Some(lit) = decl.initial_value().and_then(|v| v.literal()) else {
        return;
    };
    let range = lit.syntax().text_range();
    let text = lit.text().trim().to_owned();
    // A malformed or out-of-range constant has an unknown type (HG0006/HG0007, C2).
    let Ok(value) = literal::check_literal(&text) else {
        return;
    };
    let message = if matches!(ty, Type::Timer | Type::Counter) {
        format!("{ty} variables take no initial value")
    } else {
        match literal::accepts(&ty.to_string(), &value) {
            Acceptance::Accepted => return,
            Acceptance::Mismatch => format!("initial value {text} does not fit type {ty}"),
            Acceptance::OutOfRange { min, max } => {
                let diag = ctx.diag(
                    "HG1206",
                    range,
                    format!("initial value {text} is out of range for {ty} ({min} to {max})"),
                );
                ctx.push(diag);
                return;
            }
        }
    };
    let diag = ctx.diag("HG1205", range, message);
    ctx.push(diag);
}

/// HG1210 (a): a variable of `owner_text` that is never used; the declaration of a `stat`
/// variable can be removed.
pub(crate) fn report_unused(ctx: &mut Ctx<'_>, owner_text: &str, var: &Var) {
    let message = format!("variable '{}' is never used in {owner_text}", var.name);
    let mut diag = ctx.diag("HG1210", var.name_range, message);
    if var.section == Section::Stat {
        diag = diag.fix(
            format!("Remove the declaration of '{}'", var.name),
            ctx.loc(var.decl_range),
            "",
        );
    }
    ctx.push(diag);
}

//! Chart variables: HG1201 (duplicates), HG1203 (`msg` in a chart), HG1204 (`msg` on a type
//! other than BOOL), HG1205/HG1206 (initial values), HG1213 (`STRING[n]` length), HG1215
//! (unknown type) and HG1210 (unused variables).

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
    literal::{Acceptance, accepts, check_literal},
};

use super::{ChartInfo, Scope, Var, has_error};
use crate::{
    closest::closest,
    lang::{Section, Type},
    rules::Ctx,
};

/// Declares the chart's variables in declaration order, reporting the declaration rules.
pub(crate) fn declare(ctx: &mut Ctx<'_>, info: &ChartInfo) -> Vec<Var> {
    let mut vars: Vec<Var> = Vec::new();
    for section in info.chart.var_sections() {
        let Some(kind) = section
            .keyword()
            .and_then(|k| Section::from_keyword(k.text()))
        else {
            continue;
        };
        for decl in section.decls() {
            if let Some(var) = declare_one(ctx, info, &vars, kind, &decl) {
                vars.push(var);
            }
        }
    }
    vars
}

/// One declaration: HG1201 against the earlier ones, then its type and initial value.
fn declare_one(
    ctx: &mut Ctx<'_>,
    info: &ChartInfo,
    earlier: &[Var],
    section: Section,
    decl: &ast::VarDecl,
) -> Option<Var> {
    let token = decl.name()?.token()?;
    let name = token.text().to_owned();
    let name_range = token.text_range();
    let first = earlier
        .iter()
        .find(|v| !v.duplicate && v.name.eq_ignore_ascii_case(&name));
    if let Some(first) = first {
        let diag = ctx
            .diag(
                "HG1201",
                name_range,
                format!("variable '{name}' is already declared in {}", info.owner()),
            )
            .related(
                ctx.loc(first.name_range),
                format!("first declaration of '{}'", first.name),
            );
        ctx.push(diag);
    }
    let broken = has_error(decl.syntax());
    let ty = declared_type(ctx, decl, broken);
    if !broken {
        check_msg(ctx, decl, &name, section, ty);
        check_initial_value(ctx, decl, ty);
    }
    Some(Var {
        name,
        name_range,
        section,
        ty,
        decl_range: decl.syntax().text_range(),
        duplicate: first.is_some(),
    })
}

/// The declared type; HG1213 and HG1215 make it unknown (`None`).
fn declared_type(ctx: &mut Ctx<'_>, decl: &ast::VarDecl, broken: bool) -> Option<Type> {
    let type_ref = decl.ty()?;
    let name = type_ref.name()?;
    let Some(ty) = Type::from_name(name.text(), false) else {
        if !broken {
            let mut diag = ctx.diag(
                "HG1215",
                name.text_range(),
                format!("unknown data type '{}'", name.text()),
            );
            if let Some(best) = closest(name.text(), Type::NAMES.iter().copied()) {
                diag = diag.fix(
                    format!("Replace with '{best}'"),
                    ctx.loc(name.text_range()),
                    best,
                );
            }
            ctx.push(diag);
        }
        return None;
    };
    let Type::String(_) = ty else {
        return Some(ty);
    };
    let Some(length) = type_ref.length() else {
        return Some(ty);
    };
    match length.text().parse::<u64>() {
        Ok(n) if (1..=254).contains(&n) => Some(Type::String(n as u16)),
        _ => {
            if !broken {
                let diag = ctx.diag(
                    "HG1213",
                    type_ref.syntax().text_range(),
                    format!("string length {} is outside 1..254", length.text()),
                );
                ctx.push(diag);
            }
            None
        }
    }
}

/// HG1203: a chart has no message variables; HG1204: `msg` only on BOOL.
fn check_msg(
    ctx: &mut Ctx<'_>,
    decl: &ast::VarDecl,
    name: &str,
    section: Section,
    ty: Option<Type>,
) {
    let Some(msg) = decl.msg_kind() else {
        return;
    };
    let range = msg.syntax().text_range();
    let diag = ctx
        .diag(
            "HG1203",
            range,
            format!(
                "message variables belong in 'in_out'; '{name}' is in '{}'",
                section.as_str()
            ),
        )
        .fix(
            "Remove the 'msg' clause",
            ctx.loc(removal_range(msg.syntax())),
            "",
        );
    ctx.push(diag);
    if let (Some(ty), Some(type_ref)) = (ty, decl.ty())
        && ty != Type::Bool
    {
        let type_range = type_ref.syntax().text_range();
        let diag = ctx
            .diag(
                "HG1204",
                type_range,
                format!("message variable '{name}' must be BOOL, not {ty}"),
            )
            .fix("Change the type to BOOL", ctx.loc(type_range), "BOOL");
        ctx.push(diag);
    }
}

/// A node's range plus the white space before it, so that removing it leaves clean text.
fn removal_range(node: &higraph_syntax::SyntaxNode) -> TextRange {
    let start = node
        .prev_sibling_or_token()
        .filter(|e| e.kind().is_trivia())
        .map_or(node.text_range().start(), |e| e.text_range().start());
    TextRange::new(start, node.text_range().end())
}

/// HG1205 and HG1206: the initial value must fit the declared type (Appendix C.2).
fn check_initial_value(ctx: &mut Ctx<'_>, decl: &ast::VarDecl, ty: Option<Type>) {
    let (Some(ty), Some(literal)) = (ty, decl.initial_value().and_then(|v| v.literal())) else {
        return;
    };
    let text = literal.text();
    let range = literal.syntax().text_range();
    // A malformed or out-of-range constant already has HG0006/HG0007.
    let Ok(value) = check_literal(&text) else {
        return;
    };
    let message = if matches!(ty, Type::Timer | Type::Counter) {
        Some(("HG1205", format!("{ty} variables take no initial value")))
    } else {
        match accepts(&ty.to_string(), &value) {
            Acceptance::Accepted => None,
            Acceptance::Mismatch => Some((
                "HG1205",
                format!("initial value {text} does not fit type {ty}"),
            )),
            Acceptance::OutOfRange { min, max } => Some((
                "HG1206",
                format!("initial value {text} is out of range for {ty} ({min} to {max})"),
            )),
        }
    };
    if let Some((code, message)) = message {
        let diag = ctx.diag(code, range, message);
        ctx.push(diag);
    }
}

/// HG1210 (a): a chart variable that no operand of the chart resolves to.
pub(crate) fn report_unused(ctx: &mut Ctx<'_>, scope: &Scope) {
    for (var, used) in scope.vars.iter().zip(&scope.used) {
        if var.duplicate || *used {
            continue;
        }
        let mut diag = ctx.diag(
            "HG1210",
            var.name_range,
            format!(
                "variable '{}' is never used in {}",
                var.name,
                scope.chart.owner()
            ),
        );
        if var.section == Section::Stat {
            diag = diag.fix(
                format!("Remove the declaration of '{}'", var.name),
                ctx.loc(var.decl_range),
                "",
            );
        }
        ctx.push(diag);
    }
}

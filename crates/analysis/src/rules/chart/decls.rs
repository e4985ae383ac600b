//! Chart variables: the declaration rules of every variable ([`crate::rules::decls`]: HG1201,
//! HG1203 — a chart has no message variables —, HG1204–HG1206, HG1213, HG1215) and HG1210
//! (unused variables).

use higraph_syntax::ast::AstNode;

use super::{ChartInfo, Scope, Var};
use crate::{
    lang::Section,
    rules::{
        Ctx,
        decls::{self, Owner},
    },
};

/// Declares the chart's variables in declaration order, reporting the declaration rules.
pub(crate) fn declare(ctx: &mut Ctx<'_>, info: &ChartInfo) -> Vec<Var> {
    let owner = info.owner();
    decls::check_sections(
        ctx,
        info.chart.var_sections(),
        Owner::Chart,
        &owner,
        |_, _, _, _| {},
    )
}

/// Standard function block types of chart variables: HG7502 in a PCS 7 chart (on the type
/// name), HG7504 in an IEC chart outside `stat` or with an initial value.
pub(crate) fn check_fb_types(ctx: &mut Ctx<'_>, info: &ChartInfo, vars: &[Var]) {
    let iec = info.is_iec();
    for (section, decl) in crate::rules::decls::declarations(info.chart.var_sections()) {
        let Some(type_name) = decl.ty().and_then(|t| t.name()) else {
            continue;
        };
        let Some(fb) = crate::iec::FbType::from_name(type_name.text()) else {
            continue;
        };
        let Some(name) = decl.name().and_then(|n| n.token()) else {
            continue;
        };
        // C3: a later duplicate is reported by HG1201 only.
        if vars
            .iter()
            .any(|v| v.duplicate && v.name_range == name.text_range())
        {
            continue;
        }
        if !iec {
            let diag = ctx.diag(
                "HG7502",
                type_name.text_range(),
                format!("function block type {} needs 'profile iec;'", fb.name()),
            );
            let diag = super::with_profile_fix(ctx, diag, &info.chart);
            ctx.push(diag);
            continue;
        }
        if section != Section::Stat {
            let diag = ctx.diag(
                "HG7504",
                type_name.text_range(),
                format!(
                    "function block instance {} must be declared in 'stat', not in '{}'",
                    name.text(),
                    section.as_str()
                ),
            );
            ctx.push(diag);
        } else if let Some(init) = decl.initial_value() {
            let diag = ctx.diag(
                "HG7504",
                init.syntax().text_range(),
                format!(
                    "function block instance {} takes no initial value; set its inputs in a call",
                    name.text()
                ),
            );
            ctx.push(diag);
        }
    }
}

/// HG1210 (a): a chart variable that no operand of the chart resolves to.
pub(crate) fn report_unused(ctx: &mut Ctx<'_>, scope: &Scope) {
    let owner = scope.chart.owner();
    for (var, used) in scope.vars.iter().zip(&scope.used) {
        if var.duplicate || *used {
            continue;
        }
        decls::report_unused(ctx, &owner, var);
    }
}

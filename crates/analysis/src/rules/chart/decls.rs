//! Chart variables: the declaration rules of every variable ([`crate::rules::decls`]: HG1201,
//! HG1203 — a chart has no message variables —, HG1204–HG1206, HG1213, HG1215) and HG1210
//! (unused variables).

use super::{ChartInfo, Scope, Var};
use crate::rules::{
    Ctx,
    decls::{self, Owner},
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

//! Time values in charts — a step's `min` and `max` and the time of an action qualifier:
//! resolution of time operands with HG3005 (does not resolve) and its chart fix, then the
//! checks shared with graphs ([`crate::rules::stl::time`]): HG3004 (not of type TIME), HG3006
//! (negative) and HG3008 (zero); and HG7405 (`min` longer than `max`). `{owner}` is `chart C`.

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
};

use super::{
    Scope, has_error,
    operands::{self, Target, Unresolved},
};
use crate::{
    resolve,
    rules::{
        Ctx,
        stl::time::{TimeKind, check_time_value},
    },
};

/// Checks one time value. `item` is the whole `min`/`max` item (removed by HG3008's fix; none
/// for qualifier times). Returns the value in milliseconds when it is a valid time constant
/// (for HG7405).
pub(crate) fn check(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    value: &ast::Operand,
    kind: TimeKind,
    item: Option<TextRange>,
    report: bool,
) -> Option<i64> {
    match value {
        ast::Operand::Literal(_) if report => check_time_value(ctx, value, None, kind, item),
        ast::Operand::Path(path) => {
            let report = report && !has_error(path.syntax());
            operand(ctx, scope, value, path, kind, report);
            None
        }
        _ => None,
    }
}

/// A time operand: HG3005 if it does not resolve, HG3004 if its type is known and not TIME.
fn operand(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    value: &ast::Operand,
    path: &ast::Path,
    kind: TimeKind,
    report: bool,
) {
    let target = operands::resolve(ctx, scope, path, Unresolved::TimeValue, report);
    if !report {
        return;
    }
    if target == Target::Unresolved {
        let range = path.syntax().text_range();
        let name = path
            .symbol()
            .map(|s| s.name())
            .unwrap_or_else(|| path.syntax().text().to_string());
        let mut diag = resolve::time_operand_not_found(ctx, range, &name, &scope.chart.owner());
        if let Some((at, text)) = declare_time_edit(scope, &name) {
            diag = diag.fix(
                format!("Declare '{name} : TIME;' in 'in'"),
                ctx.loc(at),
                text,
            );
        }
        ctx.push(diag);
        return;
    }
    check_time_value(ctx, value, target.ty(scope), kind, None);
}

/// Where and what to insert to declare `name : TIME;` in the chart's `in` section (created
/// right after the chart's `<` if there is none).
fn declare_time_edit(scope: &Scope, name: &str) -> Option<(TextRange, String)> {
    let chart = &scope.chart.chart;
    let in_section = chart.var_sections().find(|s| {
        s.keyword()
            .is_some_and(|k| k.kind() == higraph_syntax::SyntaxKind::IN_KW)
    });
    if let Some(section) = in_section {
        let open = section
            .syntax()
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .find(|t| t.kind() == higraph_syntax::SyntaxKind::L_ANGLE)?;
        let at = TextRange::empty(open.text_range().end());
        return Some((at, format!(" {name} : TIME;")));
    }
    let open = chart.body()?.l_angle()?;
    let at = TextRange::empty(open.text_range().end());
    Some((at, format!("\n  in < {name} : TIME; >")))
}

/// HG7405: a step's constant `min` is longer than its constant `max`. Each side is its value
/// in milliseconds, the item's range and the constant as written.
pub(crate) fn check_min_max(
    ctx: &mut Ctx<'_>,
    step: &str,
    (min, min_range, min_text): (i64, TextRange, String),
    (max, max_range, max_text): (i64, TextRange, String),
) {
    if min <= max {
        return;
    }
    let diag = ctx
        .diag(
            "HG7405",
            min_range,
            format!(
                "step {step}: minimum run time {min_text} is longer than maximum run time {max_text}"
            ),
        )
        .related(ctx.loc(max_range), format!("maximum run time {max_text}"));
    ctx.push(diag);
}

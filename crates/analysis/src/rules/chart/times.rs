//! Time values in charts — a step's `min` and `max` and the time of an action qualifier:
//! HG3004 (not of type TIME), HG3005 (does not resolve), HG3006 (negative) and HG3008 (zero).
//! `{owner}` is `chart C`.

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
    literal::{LiteralClass, LiteralValue, check_literal, literal_type},
};

use super::{
    Scope, has_error,
    operands::{self, Target, Unresolved},
};
use crate::{lang::Type, rules::Ctx};

/// Where a time value stands (the part of HG3008's message).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimeKind {
    Min,
    Max,
    Action,
}

impl TimeKind {
    fn what(self) -> &'static str {
        match self {
            TimeKind::Min => "minimum run time",
            TimeKind::Max => "maximum run time",
            TimeKind::Action => "action time",
        }
    }
}

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
        ast::Operand::Literal(literal) => {
            if report {
                constant(ctx, literal, kind, item)
            } else {
                None
            }
        }
        ast::Operand::Path(path) => {
            let report = report && !has_error(path.syntax());
            operand(ctx, scope, path, report);
            None
        }
        _ => None,
    }
}

/// A constant time value: HG3004 for another class, HG3006 if negative, HG3008 if zero.
fn constant(
    ctx: &mut Ctx<'_>,
    literal: &ast::Literal,
    kind: TimeKind,
    item: Option<TextRange>,
) -> Option<i64> {
    let text = literal.text();
    let range = literal.syntax().text_range();
    // Malformed constants already have HG0006/HG0007.
    let value = check_literal(&text).ok()?;
    let millis = match value.value {
        LiteralValue::Duration { millis } => Some(millis),
        _ => None,
    };
    if value.class != LiteralClass::IecTime {
        let mut diag = ctx.diag(
            "HG3004",
            range,
            format!(
                "a time value must be of type TIME; {text} is {}",
                literal_type(&value)
            ),
        );
        if let (LiteralClass::S5Time, Some(millis)) = (value.class, millis) {
            let rewritten = iec_time(millis);
            diag = diag.fix(format!("Rewrite as {rewritten}"), ctx.loc(range), rewritten);
        }
        ctx.push(diag);
        return None;
    }
    let millis = millis?;
    if millis < 0 {
        let diag = ctx.diag("HG3006", range, format!("time value {text} is negative"));
        ctx.push(diag);
    } else if millis == 0 {
        let mut diag = ctx.diag(
            "HG3008",
            range,
            format!(
                "time value {text} is zero, so the {} has no useful effect",
                kind.what()
            ),
        );
        if let Some(item) = item {
            diag = diag.fix(format!("Remove the {}", kind.what()), ctx.loc(item), "");
        }
        ctx.push(diag);
    }
    Some(millis)
}

/// A time operand: HG3005 if it does not resolve, HG3004 if its type is known and not TIME.
fn operand(ctx: &mut Ctx<'_>, scope: &mut Scope, path: &ast::Path, report: bool) {
    let target = operands::resolve(ctx, scope, path, Unresolved::TimeValue, report);
    if !report {
        return;
    }
    let range = path.syntax().text_range();
    let written = path.syntax().text().to_string();
    if target == Target::Unresolved {
        let name = path
            .symbol()
            .map(|s| s.name())
            .unwrap_or_else(|| written.clone());
        let mut diag = ctx.diag(
            "HG3005",
            range,
            format!(
                "time operand '{name}' is neither a variable of {} nor a global symbol",
                scope.chart.owner()
            ),
        );
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
    if let Some(ty) = target.ty(scope)
        && ty != Type::Time
    {
        let diag = ctx.diag(
            "HG3004",
            range,
            format!("a time value must be of type TIME; {written} is {ty}"),
        );
        ctx.push(diag);
    }
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

/// A duration as the equal `T#` constant (`T#1H1M`, `T#0MS`).
fn iec_time(millis: i64) -> String {
    const UNITS: [(&str, u64); 5] = [
        ("D", 86_400_000),
        ("H", 3_600_000),
        ("M", 60_000),
        ("S", 1_000),
        ("MS", 1),
    ];
    if millis == 0 {
        return "T#0MS".to_owned();
    }
    let mut rest = millis.unsigned_abs();
    let mut out = String::from(if millis < 0 { "T#-" } else { "T#" });
    for (unit, size) in UNITS {
        let n = rest / size;
        if n > 0 {
            out.push_str(&format!("{n}{unit}"));
            rest -= n * size;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::iec_time;

    #[test]
    fn rewrites_durations_as_iec_time() {
        assert_eq!(iec_time(3_660_000), "T#1H1M");
        assert_eq!(iec_time(10), "T#10MS");
        assert_eq!(iec_time(0), "T#0MS");
        assert_eq!(iec_time(90_061_001), "T#1D1H1M1S1MS");
    }
}

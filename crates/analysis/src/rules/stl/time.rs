//! Time values (`diagnostics.md` §3.3): HG3004 (not of type TIME), HG3006 (negative) and
//! HG3008 (zero). Shared by graphs (`wait`, `supervise`) and charts (`min`, `max`, qualifier
//! times). HG3005 (unresolved) belongs to resolution: see
//! [`crate::resolve::time_operand_not_found`].

use higraph_syntax::{
    TextRange, ast,
    literal::{self, LiteralClass, LiteralValue},
};

use super::Ctx;
use crate::lang::Type;

/// What a time value sets, for HG3008's message and fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimeKind {
    /// `wait` of a graph state.
    Wait,
    /// `supervise` of a graph state.
    Supervision,
    /// `min` of a chart step.
    MinRunTime,
    /// `max` of a chart step.
    MaxRunTime,
    /// The time of a chart action qualifier (`L`, `D`, `SD`, `DS`, `SL`).
    ActionTime,
}

impl TimeKind {
    fn phrase(self) -> &'static str {
        match self {
            TimeKind::Wait => "wait time",
            TimeKind::Supervision => "supervision time",
            TimeKind::MinRunTime => "minimum run time",
            TimeKind::MaxRunTime => "maximum run time",
            TimeKind::ActionTime => "action time",
        }
    }

    /// The title of HG3008's fix: a graph's `wait`/`supervise` is "the item", a chart step's
    /// `min`/`max` is named.
    fn removal_title(self) -> String {
        match self {
            TimeKind::MinRunTime | TimeKind::MaxRunTime => format!("Remove the {}", self.phrase()),
            TimeKind::Wait | TimeKind::Supervision | TimeKind::ActionTime => {
                "Remove the item".to_owned()
            }
        }
    }
}

/// Checks one time value: HG3004, HG3006 and HG3008. Returns the value in milliseconds when it
/// is a valid `T#` constant (a step's `min` and `max` are compared for HG7405).
///
/// * `value` — the value as parsed (a constant or an operand);
/// * `ty` — the operand's resolved type; `None` when unknown or unresolved (then only
///   constants are checked; report HG3005 separately);
/// * `kind` — what the value sets (HG3008's wording and fix title);
/// * `item` — the whole item (`wait T#0S;`, `max T#0S;`), removed by HG3008's fix; pass `None`
///   for qualifier times, which get no fix.
pub(crate) fn check_time_value(
    ctx: &mut Ctx<'_>,
    value: &ast::Operand,
    ty: Option<Type>,
    kind: TimeKind,
    item: Option<TextRange>,
) -> Option<i64> {
    let range = value.syntax().text_range();
    let text = value.syntax().text().to_string();
    let ast::Operand::Literal(lit) = value else {
        if let Some(ty) = ty.filter(|t| *t != Type::Time) {
            not_a_time(ctx, range, &text, &ty.to_string(), None);
        }
        return None;
    };
    // HG0006 / HG0007: the syntax checks report a malformed constant; its type is unknown.
    let constant = literal::check_literal(&lit.text()).ok()?;
    let millis = match constant.value {
        LiteralValue::Duration { millis } => Some(millis),
        _ => None,
    };
    match (constant.class, millis) {
        (LiteralClass::IecTime, Some(ms)) if ms < 0 => {
            let diag = ctx.diag("HG3006", range, format!("time value {text} is negative"));
            ctx.push(diag);
        }
        (LiteralClass::IecTime, Some(0)) => zero_time(ctx, range, &text, kind, item),
        (LiteralClass::IecTime, _) => {}
        (LiteralClass::S5Time, Some(ms)) => {
            not_a_time(ctx, range, &text, "S5TIME", Some(iec_time_text(ms)));
        }
        _ => not_a_time(ctx, range, &text, literal::literal_type(&constant), None),
    }
    millis.filter(|_| constant.class == LiteralClass::IecTime)
}

/// HG3004, with the `T#` rewrite of an `S5T#` constant.
fn not_a_time(ctx: &mut Ctx<'_>, range: TextRange, text: &str, ty: &str, rewrite: Option<String>) {
    let message = format!("a time value must be of type TIME; {text} is {ty}");
    let mut diag = ctx.diag("HG3004", range, message);
    if let Some(rewrite) = rewrite {
        diag = diag.fix(format!("Rewrite as {rewrite}"), ctx.loc(range), rewrite);
    }
    ctx.push(diag);
}

/// HG3008: a zero time constant.
fn zero_time(
    ctx: &mut Ctx<'_>,
    range: TextRange,
    text: &str,
    kind: TimeKind,
    item: Option<TextRange>,
) {
    let message = format!(
        "time value {text} is zero, so the {} has no useful effect",
        kind.phrase()
    );
    let mut diag = ctx.diag("HG3008", range, message);
    if let Some(item) = item.filter(|_| kind != TimeKind::ActionTime) {
        diag = diag.fix(kind.removal_title(), ctx.loc(item), "");
    }
    ctx.push(diag);
}

/// A duration as the shortest `T#` constant (`T#1H1M`, `T#0S`).
pub(crate) fn iec_time_text(millis: i64) -> String {
    if millis == 0 {
        return "T#0S".to_owned();
    }
    let sign = if millis < 0 { "-" } else { "" };
    let mut rest = millis.unsigned_abs();
    let mut text = format!("T#{sign}");
    for (unit, size) in [
        ("D", 86_400_000),
        ("H", 3_600_000),
        ("M", 60_000),
        ("S", 1_000),
        ("MS", 1),
    ] {
        let count = rest / size;
        rest %= size;
        if count > 0 {
            text.push_str(&format!("{count}{unit}"));
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::iec_time_text;

    #[test]
    fn writes_durations_as_iec_time() {
        assert_eq!(iec_time_text(0), "T#0S");
        assert_eq!(iec_time_text(3_660_000), "T#1H1M");
        assert_eq!(iec_time_text(10), "T#10MS");
        assert_eq!(iec_time_text(-1500), "T#-1S500MS");
    }
}

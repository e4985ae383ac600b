//! Tests (`runtime.md` §5, §6): the structure rules HG9001–HG9010. The paths, values and
//! types of a test (HG91xx) need the test's run list resolved and belong to the lowering
//! (`lower/`); the results (HG99xx) to the runner.
//!
//! Test names have their own namespace (HG9002, in workspace order through the index) and
//! are exempt from the name rules HG11xx. A statement with a syntax error gets no diagnostic
//! of these rules (C1).

use std::collections::HashSet;

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
    literal::{self, LiteralClass, LiteralValue},
};

use super::{Ctx, edit, has_error};
use crate::{db::ItemKind, index};

/// The cycle time when a test has no `cycle` statement, in ms.
pub const DEFAULT_CYCLE_MS: i128 = 10;
/// The shortest and longest cycle time, in ms (HG9003).
const CYCLE_RANGE_MS: (i128, i128) = (1, 10_000);
/// The largest `step` count (HG9004).
const MAX_STEPS: i64 = 1_000_000;

pub(crate) fn check(ctx: &mut Ctx<'_>, test: &ast::Test) {
    let Some((name, name_range)) = test
        .name()
        .and_then(|n| Some((n.text(), n.token()?.text_range())))
    else {
        return;
    };
    duplicate_name(ctx, &name, name_range);
    let stmts: Vec<ast::TestStmt> = test
        .statements()
        .filter(|s| !has_error(s.syntax()))
        .collect();
    order(ctx, test, &name, &stmts);
    run_list(ctx, &name, name_range, &stmts);
    if !stmts
        .iter()
        .any(|s| matches!(s, ast::TestStmt::Expect(_) | ast::TestStmt::Until(_)))
    {
        let diag = ctx.diag("HG9005", name_range, format!("test {name} checks nothing"));
        ctx.push(diag);
    }
    times(ctx, &stmts);
    symbol_uses(ctx, test);
}

/// A test path whose first segment names a global symbol uses it (HG6004): a symbol, or a
/// block's stub (`"Dosieren".Menge`). The rest of path resolution is the lowering's.
fn symbol_uses(ctx: &mut Ctx<'_>, test: &ast::Test) {
    let Some(body) = test.body() else {
        return;
    };
    for path in body.syntax().descendants().filter_map(ast::TestPath::cast) {
        let first = match (path.symbol(), path.segments().next()) {
            (Some(symbol), _) => symbol.name(),
            (None, Some(name)) => name.text(),
            (None, None) => continue,
        };
        if ctx.index.symbol(&first).is_some() {
            ctx.use_symbol(&first);
        }
    }
}

/// HG9002: a test name an earlier test (workspace order) already has.
fn duplicate_name(ctx: &mut Ctx<'_>, name: &str, range: TextRange) {
    let Some(first) = ctx.index.test(name) else {
        return;
    };
    if first.name_loc == ctx.loc(range) {
        return;
    }
    let message = format!(
        "test '{name}' is already defined in {}",
        first.name_loc.file.path(ctx.db)
    );
    let diag = ctx
        .diag("HG9002", range, message)
        .related(first.name_loc, format!("the first test '{}'", first.name));
    ctx.push(diag);
}

/// HG9001: `cycle` and `run` come first, once each.
fn order(ctx: &mut Ctx<'_>, test: &ast::Test, name: &str, stmts: &[ast::TestStmt]) {
    let top = test
        .body()
        .and_then(|b| b.l_angle())
        .map(|t| TextRange::empty(t.text_range().end()));
    let mut first: [Option<TextRange>; 2] = [None, None];
    let mut seen_other = false;
    for stmt in stmts {
        let slot = match stmt {
            ast::TestStmt::Cycle(_) => 0,
            ast::TestStmt::Run(_) => 1,
            _ => {
                seen_other = true;
                continue;
            }
        };
        let node = stmt.syntax();
        let kw = stmt.keyword();
        let range = edit::without_semi(node);
        if let Some(earlier) = first[slot] {
            let diag = ctx
                .diag("HG9001", range, format!("test {name} already has '{kw}'"))
                .related(ctx.loc(earlier), format!("the first '{kw}'"))
                .fix("Remove it", ctx.loc(edit::removal_range(node)), "");
            ctx.push(diag);
            continue;
        }
        first[slot] = Some(range);
        if seen_other {
            let mut diag = ctx.diag(
                "HG9001",
                range,
                format!("'{kw}' must come first in test {name}"),
            );
            if let Some(top) = top {
                let moved = format!("\n{}{}", edit::indentation(node), node.text());
                diag = diag.fix_edits(
                    "Move it to the top of the test",
                    vec![
                        (ctx.loc(top), moved),
                        (ctx.loc(edit::removal_range(node)), String::new()),
                    ],
                );
            }
            ctx.push(diag);
        }
    }
}

/// Can a test run the item? Groups and plain charts.
fn runnable(item: &index::GlobalItem) -> bool {
    item.kind == ItemKind::Group || (item.kind == ItemKind::Chart && !item.chart_type)
}

/// HG9006, HG9007 and HG9008: the run list.
fn run_list(ctx: &mut Ctx<'_>, name: &str, name_range: TextRange, stmts: &[ast::TestStmt]) {
    let runs: Vec<&ast::TestRun> = stmts
        .iter()
        .filter_map(|s| match s {
            ast::TestStmt::Run(run) => Some(run),
            _ => None,
        })
        .collect();
    if runs.is_empty() {
        if !ctx.index.items.iter().any(runnable) {
            let diag = ctx.diag(
                "HG9008",
                name_range,
                format!("test {name} has nothing to run"),
            );
            ctx.push(diag);
        }
        return;
    }
    let mut seen = HashSet::new();
    for run in runs {
        let entries: Vec<ast::NameRef> = run.entries().collect();
        for (i, entry) in entries.iter().enumerate() {
            let Some(token) = entry.token() else {
                continue;
            };
            let (x, range) = (token.text().to_owned(), token.text_range());
            if let Some(kind) = not_runnable(ctx, &x) {
                let diag = ctx.diag(
                    "HG9006",
                    range,
                    format!("'{x}' is {kind}; a test runs groups and charts"),
                );
                let candidates: Vec<&str> = ctx
                    .index
                    .items
                    .iter()
                    .filter(|i| runnable(i))
                    .map(|i| i.name.as_str())
                    .collect();
                let diag = ctx.with_closest_fix(diag, range, &x, candidates);
                ctx.push(diag);
                continue;
            }
            if !seen.insert(index::key(&x)) {
                let removal = if entries.len() == 1 {
                    edit::removal_range(run.syntax())
                } else if i == 0 {
                    TextRange::new(range.start(), entries[1].syntax().text_range().start())
                } else {
                    TextRange::new(entries[i - 1].syntax().text_range().end(), range.end())
                };
                let diag = ctx
                    .diag("HG9007", range, format!("'{x}' is already in the run list"))
                    .fix("Remove it", ctx.loc(removal), "");
                ctx.push(diag);
            }
        }
    }
}

/// What a run entry is when it is not a group or plain chart (`None` if it is one).
fn not_runnable(ctx: &Ctx<'_>, x: &str) -> Option<&'static str> {
    let items: Vec<&index::GlobalItem> = ctx.index.items_named(x).collect();
    if items.iter().any(|i| runnable(i)) {
        return None;
    }
    Some(match items.first() {
        Some(item) if item.kind == ItemKind::Graph => "a graph",
        Some(item) if item.kind == ItemKind::Chart => "a chart type",
        Some(_) => "no group or chart",
        None if ctx.index.symbol(x).is_some() => "a global symbol",
        None if ctx.index.test(x).is_some() => "a test",
        None => "not defined",
    })
}

/// HG9003, HG9004, HG9009, HG9010: cycle time, step counts, wait and within times.
fn times(ctx: &mut Ctx<'_>, stmts: &[ast::TestStmt]) {
    // The cycle time in ms; `None` when the first `cycle` is not usable (HG9009 is then not
    // checked: HG9003 or a syntax error says what to fix first).
    let mut cycle = Some(DEFAULT_CYCLE_MS);
    if let Some(time) = stmts.iter().find_map(|s| match s {
        ast::TestStmt::Cycle(c) => Some(c.time()),
        _ => None,
    }) {
        cycle = time.and_then(|lit| {
            let time = Exact::of(&lit)?;
            let whole = time.whole_ms();
            let in_range =
                whole.is_some_and(|ms| (CYCLE_RANGE_MS.0..=CYCLE_RANGE_MS.1).contains(&ms));
            if !in_range {
                let text = lit.text();
                let diag = ctx.diag(
                    "HG9003",
                    lit.syntax().text_range(),
                    format!("cycle time {text} must be whole milliseconds from T#1MS to T#10S"),
                );
                ctx.push(diag);
                return None;
            }
            whole
        });
    }
    for stmt in stmts {
        let time = match stmt {
            ast::TestStmt::Wait(wait) => wait.time(),
            ast::TestStmt::Until(until) => until.time(),
            ast::TestStmt::Step(step) => {
                step_count(ctx, step);
                continue;
            }
            _ => continue,
        };
        let Some(lit) = time else {
            continue;
        };
        let Some(exact) = Exact::of(&lit) else {
            continue;
        };
        let (text, range) = (lit.text(), lit.syntax().text_range());
        if exact.scaled < 0 {
            let diag = ctx.diag("HG9004", range, format!("time {text} is negative"));
            ctx.push(diag);
        } else if exact.scaled == 0 {
            let diag = ctx.diag("HG9010", range, format!("{text} runs no cycle"));
            ctx.push(diag);
        } else if let Some(cycle) = cycle {
            let per_cycle = cycle * exact.unit;
            if exact.scaled % per_cycle != 0 {
                let n = exact.scaled.div_euclid(per_cycle) + 1;
                let diag = ctx.diag(
                    "HG9009",
                    range,
                    format!("{text} is not a multiple of the cycle time; {n} cycles are run"),
                );
                ctx.push(diag);
            }
        }
    }
}

/// HG9004: `step N` with N outside 1..1000000.
fn step_count(ctx: &mut Ctx<'_>, step: &ast::TestStep) {
    let Some(count) = step.count() else {
        return;
    };
    let ok = count
        .text()
        .parse::<i64>()
        .is_ok_and(|n| (1..=MAX_STEPS).contains(&n));
    if !ok {
        let diag = ctx.diag(
            "HG9004",
            count.text_range(),
            format!("step count {} is outside 1..{MAX_STEPS}", count.text()),
        );
        ctx.push(diag);
    }
}

/// A `T#` constant's exact value: `scaled / unit` milliseconds (a fraction such as
/// `T#1.5MS` is kept, not truncated).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Exact {
    pub scaled: i128,
    pub unit: i128,
}

/// Fraction digits kept: finer fractions are not a whole millisecond anyway.
const MAX_FRACTION_DIGITS: u32 = 18;

impl Exact {
    /// The value of a valid IEC time constant; `None` for anything else (malformed
    /// constants are syntax errors, HG0006/HG0007).
    pub fn of(lit: &ast::Literal) -> Option<Exact> {
        let text = lit.text();
        let constant = literal::check_literal(&text).ok()?;
        if constant.class != LiteralClass::IecTime
            || !matches!(constant.value, LiteralValue::Duration { .. })
        {
            return None;
        }
        Exact::parse(&text)
    }

    /// Whole milliseconds, if the value is a whole number of them.
    pub fn whole_ms(self) -> Option<i128> {
        (self.scaled % self.unit == 0).then(|| self.scaled / self.unit)
    }

    /// `T#1H_2.5M`, `TIME#-3S`: the body after `#` as groups of a number and a unit.
    fn parse(text: &str) -> Option<Exact> {
        let body = text.split_once('#')?.1;
        let (negative, body) = match body.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, body),
        };
        let upper = body.to_ascii_uppercase().replace('_', "");
        let bytes = upper.as_bytes();
        // (integer digits, fraction digits, unit in ms) per group.
        let mut groups: Vec<(&str, &str, i128)> = Vec::new();
        let mut i = 0;
        while i < bytes.len() {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            let number = &upper[start..i];
            let unit_start = i;
            while i < bytes.len() && bytes[i].is_ascii_alphabetic() {
                i += 1;
            }
            let unit = match &upper[unit_start..i] {
                "D" => 86_400_000,
                "H" => 3_600_000,
                "M" => 60_000,
                "S" => 1_000,
                "MS" => 1,
                _ => return None,
            };
            let (int, frac) = number.split_once('.').unwrap_or((number, ""));
            if int.is_empty() && frac.is_empty() {
                return None;
            }
            groups.push((int, frac, unit));
        }
        let digits = groups
            .iter()
            .map(|(_, f, _)| f.len() as u32)
            .max()
            .unwrap_or(0)
            .min(MAX_FRACTION_DIGITS);
        let unit = 10i128.pow(digits);
        let mut scaled: i128 = 0;
        for (int, frac, ms) in groups {
            let int: i128 = if int.is_empty() { 0 } else { int.parse().ok()? };
            let frac = &frac[..frac.len().min(MAX_FRACTION_DIGITS as usize)];
            let frac_value: i128 = if frac.is_empty() {
                0
            } else {
                frac.parse().ok()?
            };
            let frac_scaled = frac_value * 10i128.pow(digits - frac.len() as u32);
            let group = int
                .checked_mul(unit)?
                .checked_add(frac_scaled)?
                .checked_mul(ms)?;
            scaled = scaled.checked_add(group)?;
        }
        Some(Exact {
            scaled: if negative { -scaled } else { scaled },
            unit,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::Exact;

    fn exact(text: &str) -> Option<(i128, i128)> {
        Exact::parse(text).map(|e| (e.scaled, e.unit))
    }

    #[test]
    fn exact_times() {
        assert_eq!(exact("T#10MS"), Some((10, 1)));
        assert_eq!(exact("T#1.5MS"), Some((15, 10)));
        assert_eq!(exact("T#2.5H"), Some((90_000_000, 10)));
        assert_eq!(exact("TIME#-3S"), Some((-3000, 1)));
        assert_eq!(exact("t#1h_1m_0s500ms"), Some((3_660_500, 1)));
        assert_eq!(exact("T#0MS"), Some((0, 1)));
        assert_eq!(exact("T#1X"), None);
        assert_eq!(Exact::parse("T#0.0005S").and_then(|e| e.whole_ms()), None);
        assert_eq!(
            Exact::parse("T#1.5S").and_then(|e| e.whole_ms()),
            Some(1500)
        );
    }
}

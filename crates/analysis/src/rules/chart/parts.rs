//! The parts of sequencers and steps: HG7209 (repeated part), HG7204 (more than 50 statements),
//! HG7205 (more than 16 atomic conditions), HG7301 (empty start condition), HG7302/HG7303
//! (qualifier times), HG7401 (`confirm` without `switching step;`) and HG7404 (`max` without
//! `run time_monitoring;`).

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange,
    ast::{self, AstNode},
};

use super::{body_children, first_token, props::ChartProps, sequencer_header, without_semi};
use crate::rules::Ctx;

/// HG7209, HG7204, HG7205 and HG7301 for a sequencer's `start`, `pre` and `post` parts.
/// In an IEC chart HG7204, HG7205 and HG7301 do not apply (a `start` part is HG7503 there).
pub(crate) fn check_sequencer(
    ctx: &mut Ctx<'_>,
    sequencer: &ast::Sequencer,
    name: &str,
    iec: bool,
) {
    let parts: Vec<SyntaxNode> = sequencer
        .body()
        .map(|b| {
            b.syntax()
                .children()
                .filter(|n| {
                    matches!(
                        n.kind(),
                        SyntaxKind::START_PART | SyntaxKind::PRE_PART | SyntaxKind::POST_PART
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    repeated_parts(ctx, &parts, &format!("sequencer {name}"));
    if iec {
        return;
    }
    for part in &parts {
        match part.kind() {
            SyntaxKind::START_PART => {
                if let Some(keyword) = first_token(part) {
                    let element = format!("start condition of sequencer {name}");
                    condition_limit(ctx, part, &element, keyword.text_range());
                }
            }
            _ => statement_limit(ctx, part, "sequencer", name),
        }
    }
    let start = parts.iter().find(|p| p.kind() == SyntaxKind::START_PART);
    let empty = start.is_none_or(|s| !body_children(s).any(|n| n.kind() == SyntaxKind::CONDITION));
    if empty {
        let range = start
            .and_then(first_token)
            .map_or(sequencer_header(sequencer), |t| t.text_range());
        let diag = ctx.diag(
            "HG7301",
            range,
            format!(
                "sequencer {name} has an empty start condition; an empty start condition is false, so the sequencer never runs"
            ),
        );
        ctx.push(diag);
    }
}

/// HG7209, HG7204, HG7401 and HG7404 for one step.
pub(crate) fn check_step(
    ctx: &mut Ctx<'_>,
    step: &ast::Step,
    name: &str,
    props: &ChartProps,
    chart: &str,
) {
    let items: Vec<SyntaxNode> = body_children(step.syntax())
        .filter(|n| {
            matches!(
                n.kind(),
                SyntaxKind::STEP_PHASE | SyntaxKind::STEP_TIME | SyntaxKind::CONFIRM
            )
        })
        .collect();
    repeated_parts(ctx, &items, &format!("step {name}"));
    for item in &items {
        match item.kind() {
            SyntaxKind::STEP_PHASE if !props.iec => statement_limit(ctx, item, "step", name),
            SyntaxKind::STEP_PHASE => {}
            SyntaxKind::CONFIRM => confirm(ctx, item, props, chart),
            _ => {
                let is_max = first_token(item).is_some_and(|k| k.kind() == SyntaxKind::MAX_KW);
                if is_max && !props.time_monitoring {
                    max_without_monitoring(ctx, item, name);
                }
            }
        }
    }
}

/// HG7209: a second part of the same kind (`init`, `run`, `term`, `min`, `max`, `confirm`;
/// `start`, `pre`, `post`).
fn repeated_parts(ctx: &mut Ctx<'_>, parts: &[SyntaxNode], owner: &str) {
    let mut seen: Vec<SyntaxToken> = Vec::new();
    for part in parts {
        let Some(keyword) = first_token(part) else {
            continue;
        };
        let Some(first) = seen.iter().find(|k| k.kind() == keyword.kind()) else {
            seen.push(keyword);
            continue;
        };
        let word = keyword.text().to_ascii_lowercase();
        let diag = ctx
            .diag(
                "HG7209",
                keyword.text_range(),
                format!("{owner} already has a '{word}' part"),
            )
            .related(ctx.loc(first.text_range()), format!("the first '{word}'"));
        ctx.push(diag);
    }
}

/// HG7204: at most 50 statements in a part; reported once, on the 51st.
fn statement_limit(ctx: &mut Ctx<'_>, part: &SyntaxNode, owner: &str, name: &str) {
    let statements: Vec<SyntaxNode> = body_children(part)
        .filter(|n| n.kind() == SyntaxKind::ASSIGNMENT)
        .collect();
    let Some(beyond) = statements.get(50) else {
        return;
    };
    let word = first_token(part)
        .map(|k| k.text().to_ascii_lowercase())
        .unwrap_or_default();
    let diag = ctx.diag(
        "HG7204",
        without_semi(beyond),
        format!(
            "the {word} part of {owner} {name} has {} statements; at most 50 are allowed",
            statements.len()
        ),
    );
    ctx.push(diag);
}

/// HG7205 for a `trans`, `jump` or `loop`: `element` is its rendering, `header` its range.
pub(crate) fn check_conditions(
    ctx: &mut Ctx<'_>,
    node: &SyntaxNode,
    element: &str,
    header: TextRange,
) {
    condition_limit(ctx, node, element, header);
}

/// HG7205: at most 16 atomic conditions.
fn condition_limit(ctx: &mut Ctx<'_>, node: &SyntaxNode, element: &str, range: TextRange) {
    let n: usize = body_children(node)
        .filter_map(ast::Condition::cast)
        .filter_map(|c| c.expr())
        .map(|e| atomic_conditions(&e))
        .sum();
    if n > 16 {
        let diag = ctx.diag(
            "HG7205",
            range,
            format!("{element} has {n} conditions; at most 16 are allowed"),
        );
        ctx.push(diag);
    }
}

/// Atomic conditions: a comparison counts once; a Boolean operand or constant outside a
/// comparison counts once; `not` and parentheses do not count.
fn atomic_conditions(expr: &ast::Expr) -> usize {
    match expr {
        ast::Expr::Path(_) | ast::Expr::Literal(_) | ast::Expr::TestPath(_) => 1,
        ast::Expr::Paren(p) => p.expr().map_or(0, |e| atomic_conditions(&e)),
        ast::Expr::Prefix(p) => p.operand().map_or(0, |e| atomic_conditions(&e)),
        ast::Expr::Bin(b) => {
            let op = b.op_text().unwrap_or_default();
            if matches!(op.as_str(), "and" | "or" | "xor") {
                b.lhs().map_or(0, |e| atomic_conditions(&e))
                    + b.rhs().map_or(0, |e| atomic_conditions(&e))
            } else {
                1
            }
        }
    }
}

/// HG7401: `confirm` has an effect only with `switching step;` (the default mode is `T`).
fn confirm(ctx: &mut Ctx<'_>, item: &SyntaxNode, props: &ChartProps, chart: &str) {
    let mode = props.switching.as_deref().unwrap_or("T");
    if mode.eq_ignore_ascii_case("step") {
        return;
    }
    let Some(keyword) = first_token(item) else {
        return;
    };
    let diag = ctx.diag(
        "HG7401",
        keyword.text_range(),
        format!("'confirm' only has an effect with 'switching step;'; chart {chart} uses {mode}"),
    );
    ctx.push(diag);
}

/// HG7404: `max` is checked only with `run time_monitoring;`.
fn max_without_monitoring(ctx: &mut Ctx<'_>, item: &SyntaxNode, step: &str) {
    let mut diag = ctx.diag(
        "HG7404",
        without_semi(item),
        format!(
            "step {step} has a maximum run time, but 'run time_monitoring;' is not set, so it is never checked"
        ),
    );
    if let Some((at, text)) = add_time_monitoring(item) {
        diag = diag.fix("Add 'run time_monitoring;' to the chart", ctx.loc(at), text);
    }
    ctx.push(diag);
}

/// Where to insert `run time_monitoring;`: right after the chart's `<`.
fn add_time_monitoring(item: &SyntaxNode) -> Option<(TextRange, String)> {
    let chart = item.ancestors().find_map(ast::Chart::cast)?;
    let open = chart.body()?.l_angle()?;
    Some((
        TextRange::empty(open.text_range().end()),
        "\n  run time_monitoring;".to_owned(),
    ))
}

/// HG7302 (`L D SD DS SL DL` need a time) and HG7303 (`N S R P P1 P0` take none). Returns whether the
/// time, if any, belongs there.
pub(crate) fn check_qualifier_time(
    ctx: &mut Ctx<'_>,
    action: &ast::QualifierAction,
    qualifier: &SyntaxToken,
    operand: &str,
    time: Option<&ast::Operand>,
) -> bool {
    let q = qualifier.text();
    let needs_time = ["L", "D", "SD", "DS", "SL", "DL"]
        .iter()
        .any(|t| t.eq_ignore_ascii_case(q));
    match (needs_time, time) {
        (true, None) => {
            let diag = ctx.diag(
                "HG7302",
                qualifier.text_range(),
                format!("qualifier {q} needs a time: '{q} {operand}, T#...;'"),
            );
            ctx.push(diag);
            true
        }
        (false, Some(time)) => {
            let comma = action
                .syntax()
                .children_with_tokens()
                .filter_map(|e| e.into_token())
                .find(|t| t.kind() == SyntaxKind::COMMA);
            let time_range = time.syntax().text_range();
            let mut diag = ctx.diag("HG7303", time_range, format!("qualifier {q} takes no time"));
            if let Some(comma) = comma {
                let removal = TextRange::new(comma.text_range().start(), time_range.end());
                let text = time.syntax().text().to_string();
                diag = diag.fix(format!("Remove ', {text}'"), ctx.loc(removal), "");
            }
            ctx.push(diag);
            false
        }
        _ => true,
    }
}

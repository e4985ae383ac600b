//! Wait times and operating modes: HG3001 (`waits` without a wait time), HG3002 (wait time
//! without `waits`), HG3003 (second `wait`/`supervise`), HG3007 (`wait`/`supervise` outside a
//! state), HG3101 (`auto` and `manual`), HG3102 (transition without an operating mode).

use higraph_syntax::{SyntaxNode, TextRange, ast, ast::AstNode};

use super::{
    edit,
    model::{GraphModel, StateEntry, TransEntry},
};
use crate::{diag::Loc, rules::Ctx};

/// Runs the wait-time and operating-mode rules.
pub(super) fn check(ctx: &mut Ctx<'_>, graph: &ast::Graph, model: &GraphModel) {
    check_waits_attribute(ctx, model);
    check_unused_waits(ctx, model);
    check_second_items(ctx, model);
    check_misplaced_items(ctx, graph);
    check_modes(ctx, model);
}

/// HG3001: `waits` where no wait time applies.
fn check_waits_attribute(ctx: &mut Ctx<'_>, model: &GraphModel) {
    let any_wait = model
        .states
        .iter()
        .any(|s| s.first.is_none() && !s.waits().is_empty());
    for t in &model.transitions {
        let Some((_, attr)) = t.attributes.iter().find(|(w, _)| w == "waits") else {
            continue;
        };
        let message = if t.is_normal() || t.is_return() {
            let Some(source) = model.existing(t.source_end()) else {
                continue;
            };
            let state = &model.states[source];
            if !state.waits().is_empty() {
                continue;
            }
            let s = t.source.as_ref().map_or("", |e| e.text.as_str());
            format!(
                "transition {} waits, but state {s} has no wait time",
                t.label
            )
        } else if t.is_any() {
            if any_wait {
                continue;
            }
            format!(
                "any-transition {} waits, but no state of {} has a wait time",
                t.label, model.name
            )
        } else {
            continue;
        };
        let diag = ctx.diag("HG3001", attr.syntax().text_range(), message).fix(
            "Remove 'waits'",
            ctx.loc(edit::removal_range(attr.syntax())),
            "",
        );
        ctx.push(diag);
    }
}

/// The normal and return transitions leaving a state.
fn outgoing(model: &GraphModel, state: usize) -> Vec<&TransEntry> {
    model
        .transitions
        .iter()
        .filter(|t| {
            (t.is_normal() || t.is_return()) && model.existing(t.source_end()) == Some(state)
        })
        .collect()
}

/// HG3002: a wait time that no transition honours.
fn check_unused_waits(ctx: &mut Ctx<'_>, model: &GraphModel) {
    if model
        .transitions
        .iter()
        .any(|t| t.is_any() && t.has("waits"))
    {
        return;
    }
    for (i, state) in model.states.iter().enumerate() {
        if state.first.is_some() {
            continue;
        }
        let Some(wait) = state.waits().into_iter().next() else {
            continue;
        };
        let leaving = outgoing(model, i);
        if leaving.iter().any(|t| t.has("waits")) {
            continue;
        }
        let message = format!(
            "the wait time of state {} has no effect: no transition leaving it is marked 'waits'",
            state.number.text()
        );
        let mut diag = ctx.diag("HG3002", edit::without_semi(wait.syntax()), message);
        let edits: Vec<(Loc, String)> = leaving
            .iter()
            .filter_map(|t| t.target.as_ref())
            .map(|e| {
                let end = e.node.syntax().text_range().end();
                (ctx.loc(TextRange::empty(end)), " waits".to_owned())
            })
            .collect();
        if !edits.is_empty() {
            diag = diag.fix_edits("Mark the transitions leaving the state 'waits'", edits);
        }
        ctx.push(diag);
    }
}

/// HG3003: a second `wait` or `supervise` in one state.
fn check_second_items(ctx: &mut Ctx<'_>, model: &GraphModel) {
    for state in &model.states {
        let waits: Vec<SyntaxNode> = state.waits().iter().map(|w| w.syntax().clone()).collect();
        let supervisions: Vec<SyntaxNode> = state
            .supervisions()
            .iter()
            .map(|s| s.syntax().clone())
            .collect();
        report_later_items(ctx, state, &waits, "wait time");
        report_later_items(ctx, state, &supervisions, "supervision time");
    }
}

fn report_later_items(ctx: &mut Ctx<'_>, state: &StateEntry, items: &[SyntaxNode], what: &str) {
    let Some((first, later)) = items.split_first() else {
        return;
    };
    for item in later {
        let message = format!(
            "state {} already has a {what}; only one is allowed",
            state.number.text()
        );
        let diag = ctx
            .diag("HG3003", edit::without_semi(item), message)
            .related(
                ctx.loc(edit::without_semi(first)),
                format!("the first {what}"),
            )
            .fix(
                "Remove the later item",
                ctx.loc(edit::removal_range(item)),
                "",
            );
        ctx.push(diag);
    }
}

/// HG3007: `wait` or `supervise` in a transition or in `permanent`.
fn check_misplaced_items(ctx: &mut Ctx<'_>, graph: &ast::Graph) {
    let bodies = graph.members().filter_map(|m| match m {
        ast::GraphMember::Trans(t) => t.body(),
        ast::GraphMember::Permanent(p) => p.body(),
        _ => None,
    });
    for body in bodies {
        for item in body.body_items() {
            let (keyword, node) = match &item {
                ast::BodyItem::Wait(w) => ("wait", w.syntax()),
                ast::BodyItem::Supervise(s) => ("supervise", s.syntax()),
                ast::BodyItem::Block(_) => continue,
            };
            let diag = ctx
                .diag(
                    "HG3007",
                    edit::without_semi(node),
                    format!("'{keyword}' is only allowed in a state"),
                )
                .fix(
                    format!("Remove the '{keyword}' item"),
                    ctx.loc(edit::removal_range(node)),
                    "",
                );
            ctx.push(diag);
        }
    }
}

/// HG3101 and HG3102.
fn check_modes(ctx: &mut Ctx<'_>, model: &GraphModel) {
    for t in &model.transitions {
        check_both_modes(ctx, t);
    }
    let any_mode = model
        .transitions
        .iter()
        .any(|t| !t.startup && (t.has("auto") || t.has("manual")));
    if !any_mode {
        return;
    }
    for t in &model.transitions {
        let Some(header) = t.header else {
            continue;
        };
        if t.startup || t.has("auto") || t.has("manual") {
            continue;
        }
        let message = format!(
            "transition {} has no operating mode, while other transitions of {} have one",
            t.label, model.name
        );
        let diag = ctx.diag("HG3102", header, message);
        ctx.push(diag);
    }
}

/// HG3101: `auto` and `manual` on one transition; two fixes, one per attribute.
fn check_both_modes(ctx: &mut Ctx<'_>, t: &TransEntry) {
    let attrs = &t.attributes;
    let first = |word: &str| attrs.iter().find(|(w, _)| w == word).map(|(_, a)| a);
    let (Some(auto), Some(manual)) = (first("auto"), first("manual")) else {
        return;
    };
    let later = if auto.syntax().text_range().start() > manual.syntax().text_range().start() {
        auto
    } else {
        manual
    };
    let message = format!(
        "transition {} is marked both 'auto' and 'manual'; ManualMode and AutomaticMode must never both be 1, so it can never fire",
        t.label
    );
    let mut diag = ctx.diag("HG3101", later.syntax().text_range(), message);
    for word in ["auto", "manual"] {
        let edits: Vec<(Loc, String)> = attrs
            .iter()
            .filter(|(w, _)| w == word)
            .map(|(_, a)| (ctx.loc(edit::removal_range(a.syntax())), String::new()))
            .collect();
        diag = diag.fix_edits(format!("Remove '{word}'"), edits);
    }
    ctx.push(diag);
}

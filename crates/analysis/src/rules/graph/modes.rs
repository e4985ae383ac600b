//! Wait times and operating modes: HG3001 (`waits` without a wait time), HG3002 (wait time
//! without `waits`), HG3003 (second `wait`/`supervise`), HG3007 (`wait`/`supervise` outside a
//! state), HG3101 (`auto` and `manual`), HG3102 (transition without an operating mode).

use higraph_syntax::TextRange;

use super::model::{BodyItem, GraphModel, StateEntry, TransEntry};
use crate::{diag::Loc, rules::Ctx};

/// Runs the wait-time and operating-mode rules.
pub(super) fn check(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    check_waits_attribute(ctx, model);
    check_unused_waits(ctx, model);
    check_second_items(ctx, model);
    check_misplaced_items(ctx, model);
    check_modes(ctx, model);
}

/// HG3001: `waits` where no wait time applies.
fn check_waits_attribute(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    let any_wait = model
        .states
        .iter()
        .any(|s| s.first.is_none() && s.has_wait());
    for t in &model.transitions {
        let Some(attr) = t.attributes().find(|a| a.word == "waits") else {
            continue;
        };
        let message = if t.is_normal() || t.is_return() {
            let Some(source) = t.source_state else {
                continue;
            };
            let state = &model.states[source];
            if state.has_wait() {
                continue;
            }
            let s = t.source.as_ref().map_or("", |e| e.text);
            format!(
                "transition {} waits, but state {s} has no wait time",
                t.label()
            )
        } else if t.is_any() {
            if any_wait {
                continue;
            }
            format!(
                "any-transition {} waits, but no state of {} has a wait time",
                t.label(),
                model.name
            )
        } else {
            continue;
        };
        let diag = ctx.diag("HG3001", attr.range, message).fix(
            "Remove 'waits'",
            ctx.loc(attr.removal),
            "",
        );
        ctx.push(diag);
    }
}

/// The normal and return transitions leaving a state.
fn check_unused_waits(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
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
        let leaving: Vec<&TransEntry> = model
            .leaving(i)
            .iter()
            .map(|&t| &model.transitions[t])
            .collect();
        if leaving.iter().any(|t| t.has("waits")) {
            continue;
        }
        let message = format!(
            "the wait time of state {} has no effect: no transition leaving it is marked 'waits'",
            state.number()
        );
        let mut diag = ctx.diag("HG3002", wait.range, message);
        let edits: Vec<(Loc, String)> = leaving
            .iter()
            .filter_map(|t| t.target.as_ref())
            .map(|e| {
                (
                    ctx.loc(TextRange::empty(e.range.end())),
                    " waits".to_owned(),
                )
            })
            .collect();
        if !edits.is_empty() {
            diag = diag.fix_edits("Mark the transitions leaving the state 'waits'", edits);
        }
        ctx.push(diag);
    }
}

/// HG3003: a second `wait` or `supervise` in one state.
fn check_second_items(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for state in &model.states {
        report_later_items(ctx, state, &state.waits(), "wait time");
        report_later_items(ctx, state, &state.supervisions(), "supervision time");
    }
}

fn report_later_items(ctx: &mut Ctx<'_>, state: &StateEntry<'_>, items: &[BodyItem], what: &str) {
    let Some((first, later)) = items.split_first() else {
        return;
    };
    for item in later {
        let message = format!(
            "state {} already has a {what}; only one is allowed",
            state.number()
        );
        let diag = ctx
            .diag("HG3003", item.range, message)
            .related(ctx.loc(first.range), format!("the first {what}"))
            .fix("Remove the later item", ctx.loc(item.removal), "");
        ctx.push(diag);
    }
}

/// HG3007: `wait` or `supervise` in a transition or in `permanent`.
fn check_misplaced_items(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for item in &model.misplaced {
        let keyword = item.keyword;
        let diag = ctx
            .diag(
                "HG3007",
                item.range,
                format!("'{keyword}' is only allowed in a state"),
            )
            .fix(
                format!("Remove the '{keyword}' item"),
                ctx.loc(item.removal),
                "",
            );
        ctx.push(diag);
    }
}

fn check_modes(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
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
        let Some(header) = t.header() else {
            continue;
        };
        if t.startup || t.has("auto") || t.has("manual") {
            continue;
        }
        let message = format!(
            "transition {} has no operating mode, while other transitions of {} have one",
            t.label(),
            model.name
        );
        let diag = ctx.diag("HG3102", header, message);
        ctx.push(diag);
    }
}

/// HG3101: `auto` and `manual` on one transition; two fixes, one per attribute.
fn check_both_modes(ctx: &mut Ctx<'_>, t: &TransEntry<'_>) {
    let first = |word: &str| t.attributes().find(|a| a.word == word);
    let (Some(auto), Some(manual)) = (first("auto"), first("manual")) else {
        return;
    };
    let later = if auto.range.start() > manual.range.start() {
        auto
    } else {
        manual
    };
    let message = format!(
        "transition {} is marked both 'auto' and 'manual'; ManualMode and AutomaticMode must never both be 1, so it can never fire",
        t.label()
    );
    let mut diag = ctx.diag("HG3101", later.range, message);
    for word in ["auto", "manual"] {
        let edits: Vec<(Loc, String)> = t
            .attributes()
            .filter(|a| a.word == word)
            .map(|a| (ctx.loc(a.removal), String::new()))
            .collect();
        diag = diag.fix_edits(format!("Remove '{word}'"), edits);
    }
    ctx.push(diag);
}

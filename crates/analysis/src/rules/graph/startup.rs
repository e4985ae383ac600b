//! Startup and reachability: HG2201 (no startup transition), HG2202 (a second one), HG2203
//! (startup transition with `auto`/`manual`/`waits`), HG2401 (unreachable state; off after
//! HG2201, C4) and HG2402 (state without a way out).

use std::collections::BTreeSet;

use higraph_syntax::TextRange;

use super::{
    GraphHeader,
    model::{GraphModel, PrioRange},
};
use crate::{lang, rules::Ctx};

/// Runs the startup and reachability rules.
pub(super) fn check(ctx: &mut Ctx<'_>, header: &GraphHeader, model: &GraphModel<'_>) {
    if model.startups().next().is_none() {
        missing_startup(ctx, header, model);
    } else {
        check_startups(ctx, model);
        check_reachability(ctx, model);
    }
    check_dead_ends(ctx, model);
}

/// HG2201, with the fix that inserts a startup transition.
fn missing_startup(ctx: &mut Ctx<'_>, header: &GraphHeader, model: &GraphModel<'_>) {
    let Some(name_range) = header.name_range else {
        return;
    };
    let message = format!(
        "graph {} has no startup transition (an any-transition that queries INIT_SD), so it has no initial state",
        model.name
    );
    let mut diag = ctx.diag("HG2201", name_range, message);
    let state = model
        .states
        .iter()
        .filter(|s| s.in_range())
        .filter_map(|s| s.value)
        .min()
        .unwrap_or(0);
    let prio = model.lowest_free_priority(PrioRange::Any);
    let op = lang::op_in_set("U", ctx.mnemonic);
    let member = format!("trans any->{state} prio {prio} \"startup\" < {op} INIT_SD; >");
    if let Some((at, text)) = header.insert_member(&model.layout, &member) {
        diag = diag.fix("Insert a startup transition", ctx.loc(at), text);
    }
    ctx.push(diag);
}

fn check_startups(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    let mut first: Option<(String, Option<TextRange>)> = None;
    for t in model.startups() {
        for attr in t.attributes() {
            let word = attr.word;
            if !matches!(word, "auto" | "manual" | "waits") {
                continue;
            }
            let message = format!(
                "the startup transition has '{word}', so a restart may not initialise graph {}",
                model.name
            );
            let diag = ctx.diag("HG2203", attr.range, message).fix(
                format!("Remove '{word}'"),
                ctx.loc(attr.removal),
                "",
            );
            ctx.push(diag);
        }
        let Some((first_label, first_header)) = &first else {
            first = Some((t.label(), t.header()));
            continue;
        };
        let Some(header) = t.header() else {
            continue;
        };
        let message = format!(
            "graph {} already has a startup transition ({first_label}); the initial state must be unique",
            model.name
        );
        let mut diag = ctx.diag("HG2202", header, message);
        if let Some(first_header) = *first_header {
            diag = diag.related(
                ctx.loc(first_header),
                format!("the first startup transition {first_label}"),
            );
        }
        ctx.push(diag);
    }
}

/// HG2401: states outside the closure of the initial states and any-transition targets over
/// normal transitions.
fn check_reachability(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    let Some(first) = model.startups().next() else {
        return;
    };
    if first.target_state.is_none() {
        return;
    }
    let initial_text = first.target.as_ref().map_or("", |e| e.text);
    // Breadth-first from the targets of the any-transitions along normal transitions.
    let mut successors: Vec<Vec<usize>> = vec![Vec::new(); model.states.len()];
    for t in model.transitions.iter().filter(|t| t.is_normal()) {
        if let (Some(from), Some(to)) = (t.source_state, t.target_state) {
            successors[from].push(to);
        }
    }
    let mut reached: BTreeSet<usize> = model
        .transitions
        .iter()
        .filter(|t| t.is_any())
        .filter_map(|t| t.target_state)
        .collect();
    let mut queue: Vec<usize> = reached.iter().copied().collect();
    while let Some(state) = queue.pop() {
        for &next in &successors[state] {
            if reached.insert(next) {
                queue.push(next);
            }
        }
    }
    for (i, state) in model.states.iter().enumerate() {
        if state.first.is_some() || reached.contains(&i) {
            continue;
        }
        let message = format!(
            "state {} cannot be reached from the initial state {initial_text}",
            state.number()
        );
        let diag = ctx.diag("HG2401", state.header(), message);
        ctx.push(diag);
    }
}

/// HG2402: a state that only a restart leaves.
fn check_dead_ends(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    // A way out of state i: a normal transition from i to another state, a return
    // transition from i, or a non-startup any-transition to another state.
    let mut any_targets: Vec<usize> = Vec::new();
    let mut way_out = vec![false; model.states.len()];
    for t in &model.transitions {
        if t.is_any()
            && !t.startup
            && let Some(target) = t.target_state
            && !any_targets.contains(&target)
        {
            any_targets.push(target);
        }
        let Some(source) = t.source_state else {
            continue;
        };
        if t.is_return() || (t.is_normal() && t.target_state.is_some_and(|s| s != source)) {
            way_out[source] = true;
        }
    }
    for (i, state) in model.states.iter().enumerate() {
        if state.first.is_some() {
            continue;
        }
        let by_any = any_targets.iter().any(|&s| s != i);
        if !way_out[i] && !by_any {
            let message = format!(
                "state {} has no way out; only a restart leaves it",
                state.number()
            );
            let diag = ctx.diag("HG2402", state.header(), message);
            ctx.push(diag);
        }
    }
}

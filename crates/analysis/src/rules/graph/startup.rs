//! Startup and reachability: HG2201 (no startup transition), HG2202 (a second one), HG2203
//! (startup transition with `auto`/`manual`/`waits`), HG2401 (unreachable state; off after
//! HG2201, C4) and HG2402 (state without a way out).

use std::collections::BTreeSet;

use higraph_syntax::{TextRange, ast, ast::AstNode};

use super::{
    edit,
    model::{GraphModel, PrioRange},
};
use crate::{lang, rules::Ctx};

/// Runs the startup and reachability rules.
pub(super) fn check(ctx: &mut Ctx<'_>, graph: &ast::Graph, model: &GraphModel) {
    if model.startups().next().is_none() {
        missing_startup(ctx, graph, model);
    } else {
        check_startups(ctx, model);
        check_reachability(ctx, model);
    }
    check_dead_ends(ctx, model);
}

/// HG2201, with the fix that inserts a startup transition.
fn missing_startup(ctx: &mut Ctx<'_>, graph: &ast::Graph, model: &GraphModel) {
    let Some(name) = graph.name().and_then(|n| n.token()) else {
        return;
    };
    let message = format!(
        "graph {} has no startup transition (an any-transition that queries INIT_SD), so it has no initial state",
        model.name
    );
    let mut diag = ctx.diag("HG2201", name.text_range(), message);
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
    if let Some((at, text)) = member_insertion(graph, &member) {
        diag = diag.fix("Insert a startup transition", ctx.loc(at), text);
    }
    ctx.push(diag);
}

/// Where a new member goes: on its own line after the graph's last member, or right after the
/// body's `<`.
fn member_insertion(graph: &ast::Graph, member: &str) -> Option<(TextRange, String)> {
    let body = graph.body()?;
    let last = body.syntax().children().last();
    match last {
        Some(node) => Some(edit::insert_member_after(&node, member)),
        None => {
            let open = body.l_angle()?;
            Some((
                TextRange::empty(open.text_range().end()),
                format!("\n  {member}\n"),
            ))
        }
    }
}

/// HG2202 and HG2203.
fn check_startups(ctx: &mut Ctx<'_>, model: &GraphModel) {
    let mut first: Option<(&str, Option<TextRange>)> = None;
    for t in model.startups() {
        for (word, attr) in &t.attributes {
            if !matches!(word.as_str(), "auto" | "manual" | "waits") {
                continue;
            }
            let message = format!(
                "the startup transition has '{word}', so a restart may not initialise graph {}",
                model.name
            );
            let diag = ctx.diag("HG2203", attr.syntax().text_range(), message).fix(
                format!("Remove '{word}'"),
                ctx.loc(edit::removal_range(attr.syntax())),
                "",
            );
            ctx.push(diag);
        }
        let Some((first_label, first_header)) = first else {
            first = Some((&t.label, t.header));
            continue;
        };
        let Some(header) = t.header else {
            continue;
        };
        let message = format!(
            "graph {} already has a startup transition ({first_label}); the initial state must be unique",
            model.name
        );
        let mut diag = ctx.diag("HG2202", header, message);
        if let Some(first_header) = first_header {
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
fn check_reachability(ctx: &mut Ctx<'_>, model: &GraphModel) {
    let Some(first) = model.startups().next() else {
        return;
    };
    if model.existing(first.target_end()).is_none() {
        return;
    }
    let initial_text = first.target.as_ref().map_or("", |e| e.text.as_str());
    let mut reached: BTreeSet<usize> = model
        .transitions
        .iter()
        .filter(|t| t.is_any())
        .filter_map(|t| model.existing(t.target_end()))
        .collect();
    let edges: Vec<(usize, usize)> = model
        .transitions
        .iter()
        .filter(|t| t.is_normal())
        .filter_map(|t| {
            Some((
                model.existing(t.source_end())?,
                model.existing(t.target_end())?,
            ))
        })
        .collect();
    loop {
        let before = reached.len();
        for &(from, to) in &edges {
            if reached.contains(&from) {
                reached.insert(to);
            }
        }
        if reached.len() == before {
            break;
        }
    }
    for (i, state) in model.states.iter().enumerate() {
        if state.first.is_some() || reached.contains(&i) {
            continue;
        }
        let message = format!(
            "state {} cannot be reached from the initial state {initial_text}",
            state.number.text()
        );
        let diag = ctx.diag("HG2401", state.header, message);
        ctx.push(diag);
    }
}

/// HG2402: a state that only a restart leaves.
fn check_dead_ends(ctx: &mut Ctx<'_>, model: &GraphModel) {
    for (i, state) in model.states.iter().enumerate() {
        if state.first.is_some() {
            continue;
        }
        let way_out = model.transitions.iter().any(|t| {
            let from_here = model.existing(t.source_end()) == Some(i);
            let target = model.existing(t.target_end());
            (t.is_normal() && from_here && target.is_some_and(|s| s != i))
                || (t.is_return() && from_here)
                || (t.is_any() && !t.startup && target.is_some_and(|s| s != i))
        });
        if !way_out {
            let message = format!(
                "state {} has no way out; only a restart leaves it",
                state.number.text()
            );
            let diag = ctx.diag("HG2402", state.header, message);
            ctx.push(diag);
        }
    }
}

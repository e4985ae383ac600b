//! States, endpoints and limits: HG2001, HG2002 (limits, C5), HG2101 (duplicate state number),
//! HG2102 (state number range), HG2103 (missing state), HG2104 (misplaced `any`/`return`),
//! HG2105 (numbering gaps), HG2106 (repeated attribute).

use std::collections::BTreeSet;

use super::{
    GraphHeader,
    model::{End, GraphModel},
};
use crate::rules::Ctx;

/// At most this many states per graph (HG2001).
const MAX_STATES: usize = 255;
/// At most this many transitions per graph (HG2002).
const MAX_TRANSITIONS: usize = 4090;
/// How many missing numbers HG2105 lists.
const MISSING_SHOWN: usize = 5;

/// Runs the structure rules.
pub(super) fn check(ctx: &mut Ctx<'_>, header: &GraphHeader, model: &GraphModel<'_>) {
    check_limits(ctx, model);
    check_state_numbers(ctx, model);
    check_endpoints(ctx, model);
    check_numbering(ctx, header, model);
    check_repeated_attributes(ctx, model);
}

/// HG2001 and HG2002, each once, on the first element beyond the limit.
fn check_limits(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    let graph = &model.name;
    if let Some(state) = model.states.get(MAX_STATES) {
        let n = model.states.len();
        let diag = ctx.diag(
            "HG2001",
            state.header(),
            format!("graph {graph} has {n} states; at most {MAX_STATES} are allowed"),
        );
        ctx.push(diag);
    }
    let headers: Vec<_> = model
        .transitions
        .iter()
        .filter_map(|t| t.header())
        .collect();
    if let Some(&header) = headers.get(MAX_TRANSITIONS) {
        let n = headers.len();
        let diag = ctx.diag(
            "HG2002",
            header,
            format!("graph {graph} has {n} transitions; at most {MAX_TRANSITIONS} are allowed"),
        );
        ctx.push(diag);
    }
}

/// HG2101 and HG2102.
fn check_state_numbers(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    let used: BTreeSet<u64> = model.states.iter().filter_map(|s| s.value).collect();
    let free = (0..).find(|n| !used.contains(n)).unwrap_or(0);
    for state in &model.states {
        let number = state.number();
        let range = state.number_range();
        if let Some(first) = state.first.and_then(|i| model.states.get(i)) {
            let diag = ctx
                .diag(
                    "HG2101",
                    range,
                    format!(
                        "state number {number} is already used in graph {}",
                        model.name
                    ),
                )
                .related(
                    ctx.loc(first.header()),
                    format!("first state {}", first.number()),
                )
                .fix(
                    format!("Renumber to {free}"),
                    ctx.loc(range),
                    free.to_string(),
                );
            ctx.push(diag);
        }
        if !state.in_range() {
            let diag = ctx.diag(
                "HG2102",
                range,
                format!("state number {number} is outside 0..65535"),
            );
            ctx.push(diag);
        }
    }
}

/// HG2103 and HG2104.
fn check_endpoints(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for t in &model.transitions {
        let any_to_return = t.is_any() && t.target_end() == Some(End::Return);
        let ends = [
            (&t.source, t.source_state, true),
            (&t.target, t.target_state, false),
        ];
        for (endpoint, state, is_source) in ends {
            let Some(endpoint) = endpoint else {
                continue;
            };
            let range = endpoint.range;
            let message = match endpoint.end {
                End::State(_) if state.is_none() => format!(
                    "state {} does not exist in graph {}",
                    endpoint.text, model.name
                ),
                End::Any if !is_source => "'any' can only be the source of a transition".into(),
                End::Return if any_to_return => {
                    "'return' cannot be the target of an any-transition".into()
                }
                End::Return if is_source => {
                    "'return' can only be the target of a transition".into()
                }
                _ => continue,
            };
            let code = if matches!(endpoint.end, End::State(_)) {
                "HG2103"
            } else {
                "HG2104"
            };
            let diag = ctx.diag(code, range, message);
            ctx.push(diag);
        }
    }
}

/// HG2105: the distinct state numbers are not 0..n−1.
fn check_numbering(ctx: &mut Ctx<'_>, header: &GraphHeader, model: &GraphModel<'_>) {
    let Some(name_range) = header.name_range else {
        return;
    };
    let numbers: BTreeSet<u64> = model
        .states
        .iter()
        .filter(|s| s.in_range())
        .filter_map(|s| s.value)
        .collect();
    let n = numbers.len() as u64;
    if n == 0 || numbers.iter().copied().eq(0..n) {
        return;
    }
    let missing: Vec<u64> = (0..n).filter(|k| !numbers.contains(k)).collect();
    let mut list: Vec<String> = missing
        .iter()
        .take(MISSING_SHOWN)
        .map(u64::to_string)
        .collect();
    if missing.len() > MISSING_SHOWN {
        list.push("…".to_owned());
    }
    let message = format!(
        "states of {} are not numbered 0 to {} without gaps (missing: {})",
        model.name,
        n - 1,
        list.join(", ")
    );
    let renumbered = |value: u64| numbers.iter().position(|&v| v == value);
    let mut edits = Vec::new();
    for state in model.states.iter().filter(|s| s.in_range()) {
        if let Some(new) = state.value.and_then(renumbered)
            && state.value != Some(new as u64)
        {
            edits.push((ctx.loc(state.number_range()), new.to_string()));
        }
    }
    for t in &model.transitions {
        let ends = [(&t.source, t.source_state), (&t.target, t.target_state)];
        for (endpoint, state) in ends {
            let (Some(endpoint), Some(state)) = (endpoint, state.and_then(|i| model.states.get(i)))
            else {
                continue;
            };
            if !state.in_range() {
                continue;
            }
            if let Some(new) = state.value.and_then(renumbered)
                && (state.value != Some(new as u64) || endpoint.text != new.to_string())
            {
                edits.push((ctx.loc(endpoint.range), new.to_string()));
            }
        }
    }
    let diag = ctx
        .diag("HG2105", name_range, message)
        .fix_edits(format!("Renumber the states 0 to {}", n - 1), edits);
    ctx.push(diag);
}

/// HG2106: an attribute repeated in one state or transition header.
fn check_repeated_attributes(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for attrs in model.headers() {
        let mut seen: Vec<&str> = Vec::new();
        for attr in attrs {
            let word = attr.word;
            if !seen.contains(&word) {
                seen.push(word);
                continue;
            }
            let diag = ctx
                .diag(
                    "HG2106",
                    attr.range,
                    format!("attribute '{word}' is given twice"),
                )
                .fix(
                    format!("Remove the repeated '{word}'"),
                    ctx.loc(attr.removal),
                    "",
                );
            ctx.push(diag);
        }
    }
}

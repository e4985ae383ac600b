//! Transitions and priorities: HG2301/HG2302 (duplicate explicit priority per range), HG2303
//! (priority outside 1..65535, explicit or implicit), HG2304 (self-loop), HG2305
//! (unconditional any-transition), HG2306 (transition shadowed by an unconditional one).

use rustc_hash::FxHashMap as HashMap;

use super::model::{GraphModel, PrioRange, TransEntry};
use crate::rules::Ctx;

/// The highest valid priority (HG2303).
const MAX_PRIORITY: u64 = 65535;

/// Runs the priority and transition rules.
pub(super) fn check(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for (range, members) in model.ranges() {
        check_duplicates(ctx, model, *range, members);
    }
    for t in &model.transitions {
        check_range(ctx, t);
        check_self_loop(ctx, t);
        check_unconditional_any(ctx, t);
    }
    check_shadowed(ctx, model);
}

/// HG2301 and HG2302: two explicit priorities of one range are equal.
fn check_duplicates(
    ctx: &mut Ctx<'_>,
    model: &GraphModel<'_>,
    range: PrioRange,
    members: &[usize],
) {
    let mut first: HashMap<i128, usize> = HashMap::default();
    let mut free = None;
    for &i in members {
        let t = &model.transitions[i];
        let (Some(p), Some(at)) = (t.explicit_value(), t.prio_range()) else {
            continue;
        };
        let Some(&earlier) = first.get(&p) else {
            first.insert(p, i);
            continue;
        };
        let other = &model.transitions[earlier];
        let written = t.prio_text();
        let free = *free.get_or_insert_with(|| model.lowest_free_priority(range));
        let (code, message) = match range {
            PrioRange::Any => (
                "HG2302",
                format!(
                    "any-transition {}: priority {written} is already used by {}",
                    t.label(),
                    other.label()
                ),
            ),
            PrioRange::State(_) => (
                "HG2301",
                format!(
                    "transition {}: priority {written} is already used by {}",
                    t.label(),
                    other.label()
                ),
            ),
        };
        let mut diag = ctx.diag(code, at, message);
        if let Some(other_clause) = other.prio_range() {
            diag = diag.related(
                ctx.loc(other_clause),
                format!("priority {} of {}", other.prio_text(), other.label()),
            );
        }
        let diag = diag.fix(
            format!("Use priority {free}"),
            ctx.loc(at),
            format!("prio {free}"),
        );
        ctx.push(diag);
    }
}

/// The explicit priority as written.
/// HG2303: an explicit priority outside 1..65535 (on the prio clause), or an implicit one
/// above 65535 (on the header).
fn check_range(ctx: &mut Ctx<'_>, t: &TransEntry<'_>) {
    let message = |p: &str| format!("priority {p} is outside 1..{MAX_PRIORITY} (1 is the highest)");
    match (t.explicit_value(), t.prio_range()) {
        (Some(p), Some(clause)) => {
            if !(1..=i128::from(MAX_PRIORITY)).contains(&p) {
                let diag = ctx.diag("HG2303", clause, message(t.prio_text()));
                ctx.push(diag);
            }
        }
        _ => {
            if let (Some(p), Some(header)) = (t.priority, t.header())
                && p > MAX_PRIORITY
            {
                let diag = ctx.diag("HG2303", header, message(&p.to_string()));
                ctx.push(diag);
            }
        }
    }
}

/// HG2304: a normal transition back to its own source state.
fn check_self_loop(ctx: &mut Ctx<'_>, t: &TransEntry<'_>) {
    let Some(header) = t.header() else {
        return;
    };
    if t.is_normal() && t.source_end() == t.target_end() {
        let message = format!(
            "transition {} leads back to its own source state",
            t.label()
        );
        let diag = ctx.diag("HG2304", header, message);
        ctx.push(diag);
    }
}

/// HG2305: an any-transition with an empty condition.
fn check_unconditional_any(ctx: &mut Ctx<'_>, t: &TransEntry<'_>) {
    let Some(header) = t.header() else {
        return;
    };
    if t.is_any() && t.empty_condition() {
        let message = format!(
            "any-transition {} has no condition and fires in every cycle",
            t.label()
        );
        let diag = ctx.diag("HG2305", header, message);
        ctx.push(diag);
    }
}

/// Can a transition always fire when it is checked: an empty condition and no `auto`,
/// `manual` or `waits`?
fn always_fires(t: &TransEntry<'_>) -> bool {
    t.empty_condition() && !t.has("auto") && !t.has("manual") && !t.has("waits")
}

/// HG2306: a normal or return transition checked after an unconditional one of its state.
fn check_shadowed(ctx: &mut Ctx<'_>, model: &GraphModel<'_>) {
    for (range, members) in model.ranges() {
        let PrioRange::State(_) = range else {
            continue;
        };
        let members: Vec<&TransEntry> = members
            .iter()
            .map(|&i| &model.transitions[i])
            .filter(|t| t.is_normal() || t.is_return())
            .collect();
        // The unconditional transition checked first shadows every later one.
        let Some((u, q)) = members
            .iter()
            .filter(|u| always_fires(u))
            .filter_map(|u| Some((*u, u.priority?)))
            .min_by_key(|&(_, q)| q)
        else {
            continue;
        };
        for t in &members {
            let (Some(p), Some(header)) = (t.priority, t.header()) else {
                continue;
            };
            if p <= q {
                continue;
            }
            let message = format!(
                "transition {} can never fire: {} (priority {q}) has no condition and is checked first",
                t.label(),
                u.label()
            );
            let mut diag = ctx.diag("HG2306", header, message);
            if let Some(u_header) = u.header() {
                diag = diag.related(ctx.loc(u_header), format!("{} has no condition", u.label()));
            }
            ctx.push(diag);
        }
    }
}

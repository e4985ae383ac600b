//! HG7311: a step writes an operand in `term`, and a successor step writes it in `init`, `run`
//! or through a qualifier in the same cycle, so the `term` value never takes effect.
//!
//! Successor steps follow the definition of `diagnostics.md` §3.7: the step-kind unit after
//! the next transition (or after the enclosing `alt` at the end of an alternative branch), the
//! first transition of each branch of a following `alt`, the transition after the enclosing
//! `parallel` for the last step of a parallel branch, and the targets of attached jumps and
//! loops.

use super::{
    exprs::{Part, Write},
    model::{ElemId, Kind, Tree},
};
use crate::rules::Ctx;

/// Checks every `term` statement of every step against the writes of its successors. `writes`
/// holds the writes of each element of the tree (empty for all but steps).
pub(crate) fn check(ctx: &mut Ctx<'_>, tree: &Tree, writes: &[Vec<Write>]) {
    for step in tree.steps() {
        let Some(own) = writes.get(step) else {
            continue;
        };
        let terms: Vec<&Write> = own.iter().filter(|w| w.part == Part::Term).collect();
        if terms.is_empty() {
            continue;
        }
        let successors = successors(tree, step);
        for term in terms {
            for &successor in &successors {
                let Some(theirs) = writes.get(successor) else {
                    continue;
                };
                report(ctx, tree, step, successor, term, theirs);
            }
        }
    }
}

/// One diagnostic per `term` statement and successor step; Rel. lists every write.
fn report(
    ctx: &mut Ctx<'_>,
    tree: &Tree,
    step: ElemId,
    successor: ElemId,
    term: &Write,
    theirs: &[Write],
) {
    let clashes: Vec<&Write> = theirs
        .iter()
        .filter(|w| w.part != Part::Term && w.target.same_as(&term.target))
        .collect();
    let Some(first) = clashes.first() else {
        return;
    };
    let name = tree.elems[step].label();
    let other = tree.elems[successor].label();
    let mut diag = ctx.diag(
        "HG7311",
        term.range,
        format!(
            "step {name} writes {} in 'term', and successor {other} writes it in '{}' in the same cycle; the 'term' value never takes effect",
            term.text,
            first.part.display()
        ),
    );
    for clash in &clashes {
        diag = diag.related(
            ctx.loc(clash.range),
            format!(
                "step {other} writes {} in '{}'",
                clash.text,
                clash.part.display()
            ),
        );
    }
    ctx.push(diag);
}

/// The successor steps of a step, without repetitions, in the order found.
pub(crate) fn successors(tree: &Tree, step: ElemId) -> Vec<ElemId> {
    let mut out = Vec::new();
    if let Some(next) = tree.next_unit(step)
        && !tree.elems[next].kind.is_step_kind()
    {
        out.extend(through_transition(tree, next));
    }
    for attachment in tree.attachments(step) {
        let target = tree.elems[attachment]
            .target
            .as_ref()
            .and_then(|(t, _)| tree.step_named(t));
        out.extend(target);
    }
    let mut unique = Vec::new();
    for s in out {
        if !unique.contains(&s) {
            unique.push(s);
        }
    }
    unique
}

/// The steps activated when a transition-kind unit fires.
fn through_transition(tree: &Tree, unit: ElemId) -> Vec<ElemId> {
    match tree.elems[unit].kind {
        Kind::Trans => match tree.next_unit(unit) {
            Some(next) if tree.elems[next].kind.is_step_kind() => tree.first_steps(next),
            _ => Vec::new(),
        },
        Kind::Alt => tree.elems[unit]
            .branches
            .iter()
            .filter_map(|&b| tree.units(b).first().copied())
            .filter(|&first| !tree.elems[first].kind.is_step_kind())
            .flat_map(|first| through_transition(tree, first))
            .collect(),
        _ => Vec::new(),
    }
}

//! The topology of a sequencer (`diagnostics.md` §3.7): alternation of steps and transitions
//! (HG7001), branches (HG7002–HG7005), jumps and loops (HG7006–HG7011, and HG1104 on their
//! targets), reachability of steps (HG7012) and the limits HG7201–HG7203.
//!
//! Cascades (§2.7 C4): HG7006 turns off HG7007, HG7008 and HG7011 for its element; HG7012 is
//! not evaluated for a sequencer that has any of HG7001 to HG7010.

use higraph_syntax::{
    SyntaxKind, TextRange,
    ast::{self, AstNode},
};

use super::{
    body_children,
    model::{ElemId, Kind, ListId, Tree},
};
use crate::{resolve, rules::Ctx};

/// Checks the topology of one sequencer.
///
/// In an IEC chart (`docs/iec.md` §2) the sequence may be cyclic: a jump may follow the last
/// step (no HG7010), an `alt` branch may end with a jump or consist of one (no HG7004, HG7009
/// for them), an `alt` whose branches all end with a jump may end the sequencer (no HG7001),
/// and one step is enough (HG7202 only without steps).
pub(crate) fn check(ctx: &mut Ctx<'_>, tree: &Tree, sequencer: &str, header: TextRange, iec: bool) {
    let step_count = tree.steps().count();
    check_limits(ctx, tree, sequencer, header, step_count, iec);
    let enough_steps = step_count >= if iec { 1 } else { 2 };
    let mut structural = alternation(ctx, tree, sequencer, enough_steps, iec);
    structural |= branches(ctx, tree, iec);
    structural |= attachments(ctx, tree, sequencer, iec);
    if !structural {
        reachability(ctx, tree);
    }
}

// ------------------------------------------------------------------------------------ limits

/// HG7202 (fewer than 2 steps), HG7201 (more than 255 steps), HG7203 (more than 255 chart
/// transitions). C5: limits count elements whose header parsed and are reported once.
fn check_limits(
    ctx: &mut Ctx<'_>,
    tree: &Tree,
    sequencer: &str,
    header: TextRange,
    steps: usize,
    iec: bool,
) {
    if iec && steps == 0 {
        let diag = ctx.diag(
            "HG7202",
            header,
            format!("sequencer {sequencer} has 0 step(s); an initial step is required"),
        );
        ctx.push(diag);
    } else if !iec && steps < 2 {
        let diag = ctx.diag(
            "HG7202",
            header,
            format!(
                "sequencer {sequencer} has {steps} step(s); a start step and an end step are required"
            ),
        );
        ctx.push(diag);
    }
    let named = |pred: fn(Kind) -> bool| -> Vec<ElemId> {
        (0..tree.elems.len())
            .filter(|&e| pred(tree.elems[e].kind) && tree.elems[e].name.is_some())
            .collect()
    };
    let counted_steps = named(|k| k == Kind::Step);
    if let Some(&beyond) = counted_steps.get(255) {
        let diag = ctx.diag(
            "HG7201",
            tree.elems[beyond].header,
            format!(
                "sequencer {sequencer} has {} steps; at most 255 are allowed",
                counted_steps.len()
            ),
        );
        ctx.push(diag);
    }
    let transitions = named(Kind::is_chart_transition);
    if let Some(&beyond) = transitions.get(255) {
        let diag = ctx.diag(
            "HG7203",
            tree.elems[beyond].header,
            format!(
                "sequencer {sequencer} has {} transitions; at most 255 are allowed",
                transitions.len()
            ),
        );
        ctx.push(diag);
    }
}

// ------------------------------------------------------------------------------- alternation

/// HG7001: (a) two units of the same kind in a row, in any list; (b)/(c) the sequencer does
/// not begin/end with a plain step (only with at least 2 steps; otherwise HG7202 applies).
fn alternation(
    ctx: &mut Ctx<'_>,
    tree: &Tree,
    sequencer: &str,
    enough_steps: bool,
    iec: bool,
) -> bool {
    let mut found = false;
    for list in 0..tree.lists.len() {
        for pair in tree.units(list).windows(2) {
            let (previous, unit) = (&tree.elems[pair[0]], &tree.elems[pair[1]]);
            if previous.kind.is_step_kind() != unit.kind.is_step_kind() {
                continue;
            }
            let expected = if previous.kind.is_step_kind() {
                "transition"
            } else {
                "step"
            };
            let diag = ctx.diag(
                "HG7001",
                unit.header,
                format!(
                    "expected a {expected} after {}, found {}",
                    previous.render(),
                    unit.render()
                ),
            );
            ctx.push(diag);
            found = true;
        }
    }
    if !enough_steps {
        return found;
    }
    let units = tree.units(0);
    if let Some(&first) = units.first()
        && tree.elems[first].kind != Kind::Step
    {
        let elem = &tree.elems[first];
        let diag = ctx.diag(
            "HG7001",
            elem.header,
            format!(
                "sequencer {sequencer} must begin with a step (its start step); found {}",
                elem.render()
            ),
        );
        ctx.push(diag);
        found = true;
    }
    if let Some(&last) = units.last()
        && tree.elems[last].kind != Kind::Step
        && !(iec && all_branches_jump(tree, last))
    {
        let elem = &tree.elems[last];
        let diag = ctx.diag(
            "HG7001",
            elem.header,
            format!(
                "sequencer {sequencer} must end with a step (its end step); found {}",
                elem.render()
            ),
        );
        ctx.push(diag);
        found = true;
    }
    found
}

// ---------------------------------------------------------------------------------- branches

/// HG7002 (fewer than 2 branches), HG7003/HG7004 (branch shapes), HG7005 (unconditioned first
/// transition of an alternative branch).
fn branches(ctx: &mut Ctx<'_>, tree: &Tree, iec: bool) -> bool {
    let mut found = false;
    for (id, elem) in tree.elems.iter().enumerate() {
        let parallel = match elem.kind {
            Kind::Parallel => true,
            Kind::Alt => false,
            _ => continue,
        };
        if elem.branches.len() < 2 {
            report_branch_count(ctx, tree, id, parallel);
            found = true;
        }
        for &branch in &elem.branches {
            if iec && !parallel && ends_with_jump(tree, branch) {
                // An IEC alternative branch may end with a jump instead of converging, or be
                // a single jump; it still begins with a transition (or is that jump).
                if !tree.units(branch).is_empty() {
                    found |= branch_begins_with_transition(ctx, tree, branch);
                    found |= unconditioned_first(ctx, tree, branch);
                }
                continue;
            }
            found |= branch_shape(ctx, tree, branch, parallel);
            if !parallel {
                found |= unconditioned_first(ctx, tree, branch);
            }
        }
    }
    found
}

/// HG7002, with the fix that dissolves a single branch.
fn report_branch_count(ctx: &mut Ctx<'_>, tree: &Tree, id: ElemId, parallel: bool) {
    let elem = &tree.elems[id];
    let what = if parallel { "parallel" } else { "alt" };
    let n = elem.branches.len();
    let mut diag = ctx.diag(
        "HG7002",
        elem.header,
        format!("{what} needs at least 2 branches; it has {n}"),
    );
    if n == 1
        && let Some(inner) = single_branch_inner(elem.node.syntax())
    {
        // Two deletions around the branch's elements, so the fix stays small however much
        // the branch holds.
        let outer = elem.node.syntax().text_range();
        diag = diag.fix_edits(
            format!("Dissolve the {what}"),
            vec![
                (
                    ctx.loc(TextRange::new(outer.start(), inner.start())),
                    String::new(),
                ),
                (
                    ctx.loc(TextRange::new(inner.end(), outer.end())),
                    String::new(),
                ),
            ],
        );
    }
    ctx.push(diag);
}

/// The range between the `<` and `>` of the only branch of a parallel or alt, without the
/// white space at its ends.
fn single_branch_inner(node: &higraph_syntax::SyntaxNode) -> Option<TextRange> {
    let branch = body_children(node).find(|n| n.kind() == SyntaxKind::BRANCH)?;
    let body = ast::Body::cast(branch.children().find(|n| n.kind() == SyntaxKind::BODY)?)?;
    let open = body.l_angle()?.text_range().end();
    let close = body.r_angle()?.text_range().start();
    // The first and last children between them that are not white space (the body's own
    // children only: nested bodies are not walked, so nested fixes cost nothing extra).
    let mut inside = body.syntax().children_with_tokens().filter(|e| {
        let r = e.text_range();
        r.start() >= open && r.end() <= close && e.kind() != SyntaxKind::WHITESPACE
    });
    let Some(first) = inside.next() else {
        return Some(TextRange::empty(open));
    };
    let end = inside
        .last()
        .unwrap_or_else(|| first.clone())
        .text_range()
        .end();
    Some(TextRange::new(first.text_range().start(), end))
}

/// HG7003 (parallel branch) and HG7004 (alternative branch). A branch wrong at both ends gets
/// the "begins with" variant (§2.7a).
fn branch_shape(ctx: &mut Ctx<'_>, tree: &Tree, branch: ListId, parallel: bool) -> bool {
    let units = tree.units(branch);
    let fits = |e: &ElemId| tree.elems[*e].kind.is_step_kind() == parallel;
    let problem = match (units.first(), units.last()) {
        (None, _) | (_, None) => "is empty".to_owned(),
        (Some(first), _) if !fits(first) => format!("begins with {}", tree.elems[*first].render()),
        (_, Some(last)) if !fits(last) => format!("ends with {}", tree.elems[*last].render()),
        _ => return false,
    };
    let Some(keyword) = tree.lists[branch].keyword else {
        return false;
    };
    let (code, message) = if parallel {
        (
            "HG7003",
            format!("a parallel branch must begin and end with a step; this one {problem}"),
        )
    } else {
        (
            "HG7004",
            format!(
                "an alternative branch must begin and end with a transition; this one {problem}"
            ),
        )
    };
    let diag = ctx.diag(code, keyword, message);
    ctx.push(diag);
    true
}

/// Does the branch's element list end with a jump (attached to its last step, or the
/// branch's only element)?
fn ends_with_jump(tree: &Tree, branch: ListId) -> bool {
    let elems = &tree.lists[branch].elems;
    match elems.last() {
        Some(&last) if tree.elems[last].kind == Kind::Jump => {
            let units = tree.units(branch);
            match units.last() {
                // A single jump: the branch is that transition and its jump.
                None => elems.len() == 1,
                Some(&unit) => tree.elems[unit].kind == Kind::Step,
            }
        }
        _ => false,
    }
}

/// Is `unit` an `alt` each of whose branches ends with a jump (IEC: it may end a sequencer)?
fn all_branches_jump(tree: &Tree, unit: ElemId) -> bool {
    let elem = &tree.elems[unit];
    elem.kind == Kind::Alt
        && !elem.branches.is_empty()
        && elem.branches.iter().all(|&b| ends_with_jump(tree, b))
}

/// HG7004's "begins with" variant alone (IEC branches that end with a jump).
fn branch_begins_with_transition(ctx: &mut Ctx<'_>, tree: &Tree, branch: ListId) -> bool {
    let Some(&first) = tree.units(branch).first() else {
        return false;
    };
    if !tree.elems[first].kind.is_step_kind() {
        return false;
    }
    let Some(keyword) = tree.lists[branch].keyword else {
        return false;
    };
    let diag = ctx.diag(
        "HG7004",
        keyword,
        format!(
            "an alternative branch must begin and end with a transition; this one begins with {}",
            tree.elems[first].render()
        ),
    );
    ctx.push(diag);
    true
}

/// HG7005: the first unit of an alternative branch is a `trans` without conditions.
fn unconditioned_first(ctx: &mut Ctx<'_>, tree: &Tree, branch: ListId) -> bool {
    let Some(&first) = tree.units(branch).first() else {
        return false;
    };
    let elem = &tree.elems[first];
    if elem.kind != Kind::Trans || !elem.conditions().is_empty() {
        return false;
    }
    let diag = ctx.diag(
        "HG7005",
        elem.header,
        format!(
            "first transition {} of an alternative branch has no condition, so it would always win",
            elem.label()
        ),
    );
    ctx.push(diag);
    true
}

// ------------------------------------------------------------------------------- attachments

/// HG7006–HG7011 for every jump and loop; HG1104 on targets spelled in another case.
fn attachments(ctx: &mut Ctx<'_>, tree: &Tree, sequencer: &str, iec: bool) -> bool {
    let mut found = false;
    for (id, elem) in tree.elems.iter().enumerate() {
        if !elem.kind.is_attachment() {
            continue;
        }
        let what = if elem.kind == Kind::Jump {
            "jump"
        } else {
            "loop"
        };
        let attached = match tree.attached_to(id) {
            None if iec => tree.branch_jump_source(id),
            other => other,
        };
        let source = match attached {
            Some(a) if tree.elems[a].kind == Kind::Step => Some(a),
            _ => {
                let diag = ctx.diag(
                    "HG7009",
                    elem.header,
                    format!("{what} {} must directly follow a step", elem.label()),
                );
                ctx.push(diag);
                found = true;
                None
            }
        };
        if let Some(source) = source
            && !iec
            && elem.list == 0
            && tree.units(0).last() == Some(&source)
        {
            let diag = ctx.diag(
                "HG7010",
                elem.header,
                format!(
                    "{what} {} follows the end step {}, which has no successor",
                    elem.label(),
                    tree.elems[source].label()
                ),
            );
            ctx.push(diag);
            found = true;
        }
        let Some((target, range)) = &elem.target else {
            continue;
        };
        let Some(step) = tree.step_named(target) else {
            report_unknown_target(ctx, tree, id, sequencer, what);
            found = true;
            continue;
        };
        report_target_case(ctx, tree, step, target, *range);
        match elem.kind {
            Kind::Loop => found |= loop_target(ctx, tree, id, source, step),
            _ => {
                if let Some(source) = source {
                    jump_into_branch(ctx, tree, id, source, step);
                }
            }
        }
    }
    found
}

/// HG7006: the target names no step of the sequencer.
fn report_unknown_target(ctx: &mut Ctx<'_>, tree: &Tree, id: ElemId, sequencer: &str, what: &str) {
    let elem = &tree.elems[id];
    let Some((target, range)) = &elem.target else {
        return;
    };
    let message = if tree.transition_named(target) {
        format!(
            "{what} {}: '{target}' is a transition, not a step",
            elem.label()
        )
    } else {
        format!(
            "{what} {}: sequencer {sequencer} has no step '{target}'",
            elem.label()
        )
    };
    let mut diag = ctx.diag("HG7006", *range, message);
    let names: Vec<&str> = tree
        .steps()
        .filter_map(|s| tree.elems[s].name.as_deref())
        .collect();
    diag = ctx.with_closest_fix(diag, *range, target, names);
    ctx.push(diag);
}

/// HG1104 on a jump or loop target that names its step in another letter case.
fn report_target_case(ctx: &mut Ctx<'_>, tree: &Tree, step: ElemId, used: &str, range: TextRange) {
    if let Some(declared) = tree.elems[step].name.as_deref() {
        resolve::case_hint(ctx, range, used, declared);
    }
}

/// HG7007 (the loop crosses a branch boundary) and HG7008 (the loop leads forward).
fn loop_target(
    ctx: &mut Ctx<'_>,
    tree: &Tree,
    id: ElemId,
    source: Option<ElemId>,
    step: ElemId,
) -> bool {
    let elem = &tree.elems[id];
    let Some((target, range)) = &elem.target else {
        return false;
    };
    if tree.elems[step].list != elem.list {
        let diag = ctx.diag(
            "HG7007",
            *range,
            format!(
                "loop {} would cross a branch boundary: step {target} is not on the same branch level",
                elem.label()
            ),
        );
        ctx.push(diag);
        return true;
    }
    let Some(source) = source else {
        return false;
    };
    let list = &tree.lists[elem.list].elems;
    let position = |e: ElemId| list.iter().position(|&x| x == e);
    // The target may be the source step itself (a loop back to the same step).
    if position(step) > position(source) {
        let diag = ctx.diag(
            "HG7008",
            *range,
            format!(
                "loop {} must lead back to an earlier step; {target} comes after {}",
                elem.label(),
                tree.elems[source].label()
            ),
        );
        ctx.push(diag);
        return true;
    }
    false
}

/// HG7011: a jump whose source and target are not in the same branches of the parallels.
fn jump_into_branch(ctx: &mut Ctx<'_>, tree: &Tree, id: ElemId, source: ElemId, target: ElemId) {
    let mut leaves = false;
    let mut enters = false;
    for branch in tree.parallel_branches() {
        match (tree.contains(branch, source), tree.contains(branch, target)) {
            (true, false) => leaves = true,
            (false, true) => enters = true,
            _ => {}
        }
    }
    let direction = match (leaves, enters) {
        (true, _) => "leaves",
        (false, true) => "enters",
        (false, false) => return,
    };
    let elem = &tree.elems[id];
    let target_elem = &tree.elems[target];
    let diag = ctx
        .diag(
            "HG7011",
            elem.header,
            format!(
                "jump {} {direction} a parallel branch; the other branches are not synchronised",
                elem.label()
            ),
        )
        .related(
            ctx.loc(target_elem.header),
            format!("target step {}", target_elem.label()),
        );
    ctx.push(diag);
}

// ------------------------------------------------------------------------------ reachability

/// Is a condition the literal `b` (`TRUE`/`FALSE`, parentheses allowed)?
fn is_literal(condition: &ast::Condition, b: &str) -> bool {
    let mut expr = condition.expr();
    while let Some(ast::Expr::Paren(p)) = &expr {
        expr = p.expr();
    }
    matches!(expr, Some(ast::Expr::Literal(l)) if l.text().trim().eq_ignore_ascii_case(b))
}

/// A transition is statically true if it has no conditions or all are the literal `TRUE`.
pub(crate) fn statically_true(conditions: &[ast::Condition]) -> bool {
    conditions.iter().all(|c| is_literal(c, "TRUE"))
}

/// A transition is statically false if one of its conditions is the literal `FALSE`.
pub(crate) fn statically_false(conditions: &[ast::Condition]) -> bool {
    conditions.iter().any(|c| is_literal(c, "FALSE"))
}

/// HG7012: steps that cannot become active. The reached set grows monotonically, pass by pass,
/// until it is stable (jumps and loops may reach steps of earlier passes).
fn reachability(ctx: &mut Ctx<'_>, tree: &Tree) {
    if tree.steps().next().is_none() {
        return;
    }
    let mut reached = vec![false; tree.elems.len()];
    loop {
        let before = reached.clone();
        flow(tree, 0, true, &mut reached);
        if reached == before {
            break;
        }
    }
    for step in tree.steps() {
        if !reached[step] {
            let elem = &tree.elems[step];
            let diag = ctx.diag(
                "HG7012",
                elem.header,
                format!("step {} can never become active", elem.label()),
            );
            ctx.push(diag);
        }
    }
}

/// One pass over a list entered when `entry` holds; returns whether its end is passed.
fn flow(tree: &Tree, list: ListId, entry: bool, reached: &mut [bool]) -> bool {
    let mut incoming = entry;
    for &id in &tree.lists[list].elems {
        let elem = &tree.elems[id];
        incoming = match elem.kind {
            Kind::Jump | Kind::Loop => {
                follow_attachment(tree, id, reached);
                continue;
            }
            Kind::Step => {
                if incoming {
                    reached[id] = true;
                }
                reached[id]
            }
            Kind::Parallel => {
                let mut all = !elem.branches.is_empty();
                for &branch in &elem.branches {
                    all &= flow(tree, branch, incoming, reached);
                }
                all
            }
            Kind::Trans => incoming && !statically_false(&elem.conditions()),
            Kind::Alt => {
                let mut any = false;
                let mut blocked = false;
                for &branch in &elem.branches {
                    any |= flow(tree, branch, incoming && !blocked, reached);
                    blocked |= first_statically_true(tree, branch);
                }
                any
            }
        };
    }
    incoming
}

/// A jump or loop from a reached step activates its target unless it is statically false.
fn follow_attachment(tree: &Tree, id: ElemId, reached: &mut [bool]) {
    let elem = &tree.elems[id];
    let Some(source) = tree.attached_to(id).or_else(|| tree.branch_jump_source(id)) else {
        return;
    };
    if !reached[source] || statically_false(&elem.conditions()) {
        return;
    }
    if let Some(target) = elem.target.as_ref().and_then(|(t, _)| tree.step_named(t)) {
        reached[target] = true;
    }
}

/// Does the branch begin with a statically true `trans` (so branches to its right never run)?
fn first_statically_true(tree: &Tree, branch: ListId) -> bool {
    tree.units(branch).first().is_some_and(|&u| {
        tree.elems[u].kind == Kind::Trans && statically_true(&tree.elems[u].conditions())
    })
}

//! Names and comments of steps, chart transitions, jumps and loops: HG7101 (longer than 16
//! characters), HG7102 (only digits), HG7103 (duplicate in the sequencer) and HG7104 (comment
//! longer than 80 characters).

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
};

use super::model::{Kind, Tree};
use crate::rules::Ctx;

/// Checks the names and comments of every element of one sequencer.
/// In an IEC chart names may be longer than 16 characters (HG7101 does not apply).
pub(crate) fn check(ctx: &mut Ctx<'_>, tree: &Tree, sequencer: &str, iec: bool) {
    let mut steps: Vec<(String, TextRange)> = Vec::new();
    let mut transitions: Vec<(String, TextRange)> = Vec::new();
    for elem in &tree.elems {
        let (Some(name), Some(range)) = (&elem.name, elem.name_range) else {
            check_comment(ctx, &elem.node);
            continue;
        };
        let (space, what) = match elem.kind {
            Kind::Step => (&mut steps, "step"),
            kind if kind.is_chart_transition() => (&mut transitions, "transition"),
            _ => {
                check_comment(ctx, &elem.node);
                if !iec {
                    check_length(ctx, name, range);
                }
                check_digits(ctx, name, range, elem.kind);
                continue;
            }
        };
        if let Some((first, first_range)) = space.iter().find(|(n, _)| n.eq_ignore_ascii_case(name))
        {
            let diag = ctx
                .diag(
                    "HG7103",
                    range,
                    format!("{what} name '{name}' is already used in sequencer {sequencer}"),
                )
                .related(
                    ctx.loc(*first_range),
                    format!("first {what} named '{first}'"),
                );
            // C3: the later element is reported and otherwise ignored.
            ctx.push(diag);
        } else {
            check_comment(ctx, &elem.node);
            if !iec {
                check_length(ctx, name, range);
            }
            check_digits(ctx, name, range, elem.kind);
            space.push((name.clone(), range));
        }
    }
}

/// For each element of the tree: is it a step or chart transition whose name an earlier one
/// of the sequencer has (HG7103)? Such an element is otherwise ignored (C3).
pub(crate) fn later_duplicates(tree: &Tree) -> Vec<bool> {
    let mut steps = std::collections::HashSet::new();
    let mut transitions = std::collections::HashSet::new();
    tree.elems
        .iter()
        .map(|elem| {
            let Some(name) = &elem.name else {
                return false;
            };
            let seen = match elem.kind {
                Kind::Step => &mut steps,
                kind if kind.is_chart_transition() => &mut transitions,
                _ => return false,
            };
            !seen.insert(name.to_ascii_uppercase())
        })
        .collect()
}

/// HG7101: at most 16 characters (Unicode scalar values, §2.7a).
fn check_length(ctx: &mut Ctx<'_>, name: &str, range: TextRange) {
    let n = name.chars().count();
    if n > 16 {
        let diag = ctx.diag(
            "HG7101",
            range,
            format!("name '{name}' has {n} characters; at most 16 are allowed"),
        );
        ctx.push(diag);
    }
}

/// HG7102: a name of digits only (the parser tolerates integers here, §2.8).
fn check_digits(ctx: &mut Ctx<'_>, name: &str, range: TextRange, kind: Kind) {
    if name.is_empty() || !name.bytes().all(|b| b.is_ascii_digit()) {
        return;
    }
    let prefix = if kind == Kind::Step { "S" } else { "T" };
    let diag = ctx
        .diag(
            "HG7102",
            range,
            format!("name '{name}' must not consist only of digits"),
        )
        .fix(
            format!("Rename to '{prefix}{name}'"),
            ctx.loc(range),
            format!("{prefix}{name}"),
        );
    ctx.push(diag);
}

/// HG7104: a comment of at most 80 characters, quotes not counted.
fn check_comment(ctx: &mut Ctx<'_>, node: &ast::SeqElement) {
    let comment = match node {
        ast::SeqElement::Step(s) => s.comment(),
        ast::SeqElement::Trans(t) => t.comment(),
        ast::SeqElement::Jump(j) => j.comment(),
        ast::SeqElement::Loop(l) => l.comment(),
        ast::SeqElement::Parallel(_) | ast::SeqElement::Alt(_) => None,
    };
    let Some(comment) = comment else {
        return;
    };
    let n = comment.value().chars().count();
    if n > 80 {
        let range = comment
            .token()
            .map_or(comment.syntax().text_range(), |t| t.text_range());
        let diag = ctx.diag(
            "HG7104",
            range,
            format!("comment has {n} characters; at most 80 are allowed"),
        );
        ctx.push(diag);
    }
}

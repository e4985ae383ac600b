//! Sequence charts: `chart [type] NAME ["comment"] < sections, properties, sequencers >`,
//! sequencers with steps, transitions, branches, jumps and loops, and chart expressions.

use std::fmt;

use super::{Parser, Scope, items, lazy, stl};
use crate::{SyntaxKind, SyntaxKind::*};

const QUALIFIERS: &[&str] = &[
    "N", "S", "R", "P", "L", "D", "SD", "DS", "SL", "P1", "P0", "DL",
];

pub(crate) fn chart(p: &mut Parser<'_>) {
    p.start(CHART);
    p.bump_keyword();
    // `type` is the keyword only when a name follows it.
    if p.at_kw(TYPE_KW) && matches!(p.nth(1), IDENT) {
        p.bump_keyword();
    }
    let construct = format!("chart {}", p.nth_text(0));
    if !p.name() {
        p.error_expected("a chart name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    p.opt_comment_string();
    p.start(BODY);
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, &[]) {
            if items::at_var_section(p) {
                items::var_section(p, &[Scope::Chart]);
            } else if p.at_kw(SEQUENCER_KW) {
                sequencer(p);
            } else if p.at_member_start(Scope::Chart) && p.at_kw(ACTION_KW) {
                action(p);
            } else if p.at_kw(MODE_KW)
                || p.at_kw(SWITCHING_KW)
                || p.at_kw(RUN_KW)
                || p.at_kw(PROFILE_KW)
            {
                chart_prop(p);
            } else {
                p.error_and_recover(
                    "a chart member ('sequencer', 'action', 'mode', 'switching', 'run', 'profile', a variable section) or '>'",
                );
            }
        }
    }
    p.finish_node();
    p.finish_node();
}

/// `action NAME ["comment"] < statements >`
fn action(p: &mut Parser<'_>) {
    p.start(CHART_ACTION);
    p.bump_keyword();
    let construct = format!("action {}", p.nth_text(0));
    if !p.name() {
        p.error_expected("an action name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    p.opt_comment_string();
    body_of(p, &construct, BodyKind::Statements);
    p.finish_node();
}

/// `mode auto;`, `switching T;`, `run cyclic;`, `profile iec;`
fn chart_prop(p: &mut Parser<'_>) {
    p.start(CHART_PROP);
    let word = p.nth_text(0);
    p.bump_keyword();
    if p.at(IDENT) && !p.nth_on_new_line(0) {
        p.bump_node(NAME_REF, 1);
        let element = lazy(|f| write!(f, "'{}'", word.to_ascii_lowercase()));
        p.expect_semi(&element, |p| p.at(IDENT));
    } else {
        p.error_and_recover("a value");
    }
    p.finish_node();
}

/// A step, transition, jump or loop name: an identifier, or (tolerated, HG7102) an integer.
fn element_name(p: &mut Parser<'_>) -> bool {
    if matches!(p.current(), IDENT | NUMBER) {
        p.bump_node(NAME, 1);
        true
    } else {
        false
    }
}

/// `sequencer NAME [prio N] < members >`
fn sequencer(p: &mut Parser<'_>) {
    p.start(SEQUENCER);
    p.bump_keyword();
    let construct = format!("sequencer {}", p.nth_text(0));
    if !element_name(p) {
        p.error_expected("a sequencer name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    if p.at_kw(PRIO_KW) {
        p.start(PRIO_CLAUSE);
        p.bump_keyword();
        // Any number, also negative (`-3`): HG7207 reports it.
        let n = p.signed_number_len(false);
        if n > 0 {
            for _ in 0..n {
                p.bump();
            }
        } else {
            p.finish_node();
            p.error_expected("a priority");
            if !p.recover_header() {
                p.finish_node();
                return;
            }
            p.start(PRIO_CLAUSE);
        }
        p.finish_node();
    }
    p.start(BODY);
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, &[Scope::Chart]) {
            if p.at_kw(SEQUENCER_KW) && matches!(p.nth(1), IDENT | NUMBER) {
                // A new sequencer closes this one (the member keyword of the chart).
                p.error_unclosed(open, &construct);
                break;
            }
            if p.at_kw(START_KW) && p.nth(1) == L_ANGLE {
                part(p, START_PART, "start condition", true);
            } else if p.at_kw(PRE_KW) && p.nth(1) == L_ANGLE {
                part(p, PRE_PART, "pre part", false);
            } else if p.at_kw(POST_KW) && p.nth(1) == L_ANGLE {
                part(p, POST_PART, "post part", false);
            } else if !seq_element(p) {
                p.error_and_recover("a sequencer element or '>'");
            }
        }
    }
    p.finish_node();
    p.finish_node();
}

/// `start < conditions >`, `pre < statements >`, `post < statements >`, and the step phases
/// `init`/`run`/`term`.
fn part(p: &mut Parser<'_>, kind: SyntaxKind, construct: &str, conditions: bool) {
    p.start(kind);
    p.bump_keyword();
    body_of(
        p,
        &construct,
        if conditions {
            BodyKind::Conditions
        } else {
            BodyKind::Statements
        },
    );
    p.finish_node();
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum BodyKind {
    Conditions,
    Statements,
    StepItems,
    Branches,
    Elements,
}

/// `< ... >` of a sequencer element or part.
fn body_of(p: &mut Parser<'_>, construct: &dyn fmt::Display, kind: BodyKind) {
    p.start(BODY);
    let Some(open) = p.expect_open(construct) else {
        p.finish_node();
        return;
    };
    loop {
        // Inside a branch, `branch <` closes the branch; inside a parallel/alt, any sequencer
        // member keyword other than `branch` closes it.
        let closes = match kind {
            BodyKind::Branches => {
                p.at_member_start(Scope::Sequencer) && !p.at_kw(BRANCH_KW)
                    || p.at_member_start(Scope::Chart)
            }
            BodyKind::Elements => {
                (p.at_kw(BRANCH_KW) && p.nth(1) == L_ANGLE)
                    || (p.at_kw(SEQUENCER_KW) && matches!(p.nth(1), IDENT | NUMBER))
                    || p.at_member_start(Scope::Chart)
            }
            _ => false,
        };
        if closes {
            p.error_unclosed(open, construct);
            break;
        }
        let scopes: &[Scope] = match kind {
            BodyKind::Branches | BodyKind::Elements => &[Scope::Chart],
            _ => &[Scope::Sequencer, Scope::Chart],
        };
        if p.body_ends(open, construct, scopes) {
            break;
        }
        match kind {
            BodyKind::Conditions => condition(p),
            BodyKind::Statements => assignment(p),
            BodyKind::StepItems => step_item(p),
            BodyKind::Branches => {
                if p.at_kw(BRANCH_KW) && p.nth(1) == L_ANGLE {
                    p.start(BRANCH);
                    p.bump_keyword();
                    body_of(p, &"branch", BodyKind::Elements);
                    p.finish_node();
                } else {
                    p.error_and_recover("'branch' or '>'");
                }
            }
            BodyKind::Elements => {
                if !seq_element(p) {
                    p.error_and_recover("a sequencer element or '>'");
                }
            }
        }
    }
    p.finish_node();
}

/// A step, transition, `parallel`, `alt`, jump or loop. Returns `false` if none starts here.
fn seq_element(p: &mut Parser<'_>) -> bool {
    if p.at_kw(STEP_KW) {
        named_element(p, STEP, "step", BodyKind::StepItems, false);
    } else if p.at_kw(TRANS_KW) {
        named_element(p, CHART_TRANS, "transition", BodyKind::Conditions, false);
    } else if p.at_kw(JUMP_KW) {
        named_element(p, JUMP, "jump", BodyKind::Conditions, true);
    } else if p.at_kw(LOOP_KW) {
        named_element(p, LOOP, "loop", BodyKind::Conditions, true);
    } else if (p.at_kw(PARALLEL_KW) || p.at_kw(ALT_KW)) && p.nth(1) == L_ANGLE {
        if !p.fits(1) {
            // HG0012: the construct, up to its balancing `>`, stays flat in an ERROR node.
            p.error_too_deep();
            p.start(ERROR);
            p.bump_keyword();
            p.skip_balanced(L_ANGLE, R_ANGLE);
            p.finish_node();
            return true;
        }
        let is_parallel = p.at_kw(PARALLEL_KW);
        p.start(if is_parallel { PARALLEL } else { ALT });
        p.bump_keyword();
        p.nested(|p| {
            body_of(
                p,
                &if is_parallel { "parallel" } else { "alt" },
                BodyKind::Branches,
            );
        });
        p.finish_node();
    } else {
        return false;
    }
    true
}

/// `step NAME ["c"] < .. >`, `trans NAME ["c"] < .. >`, `jump NAME -> TARGET ["c"] < .. >`.
fn named_element(p: &mut Parser<'_>, kind: SyntaxKind, what: &str, body: BodyKind, arrow: bool) {
    p.start(kind);
    p.bump_keyword();
    let construct = format!("{what} {}", p.nth_text(0));
    let mut header_ok = true;
    if !element_name(p) {
        p.error_expected(&format!("a {what} name"));
        header_ok = p.recover_header();
    } else if arrow {
        if !p.at_arrow() {
            p.error_expected("'->'");
            header_ok = p.recover_header();
        } else {
            p.bump_node(ARROW, 2);
            if matches!(p.current(), IDENT | NUMBER) {
                p.bump_node(NAME_REF, 1);
            } else {
                p.error_expected("a target step");
                header_ok = p.recover_header();
            }
        }
    }
    if header_ok {
        p.opt_comment_string();
        body_of(p, &construct, body);
    }
    p.finish_node();
}

/// `init < .. >`, `run < .. >`, `term < .. >`, `N Valve;`, `L Pump, T#5S;`, `min T#1S;`,
/// `max T#10M;`, `confirm;`.
fn step_item(p: &mut Parser<'_>) {
    let phase = ["init", "run", "term"]
        .iter()
        .find(|w| p.at_word(w))
        .copied();
    if let Some(phase) = phase.filter(|_| p.nth(1) == L_ANGLE) {
        part(p, STEP_PHASE, phase, false);
    } else if p.at_kw(MIN_KW) || p.at_kw(MAX_KW) {
        p.start(STEP_TIME);
        let word = p.nth_text(0);
        p.bump_keyword();
        if !chart_operand(p) {
            p.error_and_recover("a time value");
        } else {
            let element = lazy(|f| write!(f, "'{}'", word.to_ascii_lowercase()));
            p.expect_semi(&element, at_step_item);
        }
        p.finish_node();
    } else if p.at_kw(CONFIRM_KW) {
        p.start(CONFIRM);
        p.bump_keyword();
        p.expect_semi(&"'confirm'", at_step_item);
        p.finish_node();
    } else if p.at(IDENT) && QUALIFIERS.iter().any(|q| p.at_word(q)) {
        p.start(QUALIFIER_ACTION);
        let action = p.nth_text(0);
        let element = lazy(|f| write!(f, "the '{action}' action"));
        p.bump_node(QUALIFIER, 1);
        if !chart_operand(p) {
            p.error_and_recover("an operand");
            p.finish_node();
            return;
        }
        if p.at(COMMA) {
            p.bump();
            if !chart_operand(p) {
                p.error_and_recover("a time value");
                p.finish_node();
                return;
            }
        }
        p.expect_semi(&element, at_step_item);
        p.finish_node();
    } else {
        p.error_and_recover(
            "a step item ('init', 'run', 'term', a qualifier, 'min', 'max', 'confirm') or '>'",
        );
    }
}

fn at_step_item(p: &Parser<'_>) -> bool {
    p.at(IDENT)
        && (["min", "max", "confirm"].iter().any(|w| p.at_word(w))
            || QUALIFIERS.iter().any(|q| p.at_word(q))
            || (["init", "run", "term"].iter().any(|w| p.at_word(w)) && p.nth(1) == L_ANGLE))
}

/// `expr;`
fn condition(p: &mut Parser<'_>) {
    p.start(CONDITION);
    let recoveries = p.recoveries();
    if expr(p).is_none() {
        p.error_and_recover("a condition or '>'");
    } else if p.recoveries() == recoveries {
        p.expect_semi(&"the condition", at_operand);
    }
    p.finish_node();
}

/// `path := expr;`
fn assignment(p: &mut Parser<'_>) {
    p.start(ASSIGNMENT);
    if !path(p) {
        p.error_and_recover("an assignment or '>'");
        p.finish_node();
        return;
    }
    if !p.at_assign() {
        p.error_and_recover("':='");
        p.finish_node();
        return;
    }
    p.bump_node(ASSIGN_OP, 2);
    let recoveries = p.recoveries();
    if expr(p).is_none() {
        p.error_and_recover("an expression");
    } else if p.recoveries() == recoveries {
        p.expect_semi(&"the assignment", |p| matches!(p.current(), IDENT | STRING));
    }
    p.finish_node();
}

/// Can an operand begin here (on the same line as the previous token)?
fn at_operand(p: &Parser<'_>) -> bool {
    p.nth_starts_operand(0)
}

/// `expr = xor_expr { or xor_expr }` and so on down. Returns `None` (consuming nothing) if
/// no expression starts here; errors inside are reported and recovered.
///
/// The functions below return the *height* of what they built: the number of binary,
/// prefix and parenthesised expressions (and ERROR nodes holding operands) on the longest
/// path down to an operand. Called with `p.depth` levels open, they keep `depth + height` within
/// [`super::NESTING_LIMIT`]: an operator, `not` or `(` that would pass it reports HG0012
/// (`Parser::error_too_deep`) and its part of the expression stays flat in an ERROR node. A
/// left-associative chain (`a or b or c ...`) nests its left operand one level deeper with
/// every operator, which is why the heights are needed and not only the open levels.
pub(crate) fn expr(p: &mut Parser<'_>) -> Option<u32> {
    binary(p, 0)
}

/// The chained binary operator levels, lowest precedence first (docs/iec.md §4). The
/// comparison (not chained, [`comparison`]) stands between `and` and `+ -`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Level {
    Or,
    Xor,
    And,
    Additive,
    Multiplicative,
}

const LEVELS: [Level; 3] = [Level::Or, Level::Xor, Level::And];

/// Number of tokens of a chained binary operator of `level` here, or 0.
fn chain_op_len(p: &Parser<'_>, level: Level) -> usize {
    let at = match level {
        Level::Or => p.at_kw(OR_KW),
        Level::Xor => p.at_kw(XOR_KW),
        Level::And => p.at_kw(AND_KW),
        // Not the `-` of `->`.
        Level::Additive => p.at(PLUS) || (p.at(MINUS) && !(p.nth(1) == R_ANGLE && p.nth_joined(1))),
        // `MOD` only when an operand follows (`x\n mod := 1;` is a new assignment).
        Level::Multiplicative => {
            p.at(STAR) || p.at(SLASH) || (p.at_kw(MOD_KW) && p.nth_starts_operand(1))
        }
    };
    usize::from(at)
}

/// Adds a chain operator to the tree: keywords as their keyword kind, punctuation as lexed.
fn bump_chain_op(p: &mut Parser<'_>) {
    if p.at(IDENT) {
        p.bump_keyword();
    } else {
        p.bump();
    }
}

fn binary(p: &mut Parser<'_>, level: usize) -> Option<u32> {
    if level == LEVELS.len() {
        return comparison(p);
    }
    chain(p, LEVELS[level], |p| binary(p, level + 1))
}

fn arithmetic(p: &mut Parser<'_>, level: Level) -> Option<u32> {
    match level {
        Level::Additive => chain(p, level, |p| arithmetic(p, Level::Multiplicative)),
        _ => chain(p, level, unary),
    }
}

/// `operand { op operand }`, left-associative, for the chained operators of `level`.
fn chain(
    p: &mut Parser<'_>,
    level: Level,
    operand: impl Fn(&mut Parser<'_>) -> Option<u32>,
) -> Option<u32> {
    let checkpoint = p.checkpoint();
    let mut height = operand(p)?;
    while chain_op_len(p, level) > 0 {
        if !p.fits(height + 1) {
            // The rest of the chain, flat: its operands side by side in one ERROR node.
            p.error_too_deep();
            p.start(ERROR);
            let mut rest = 0;
            while chain_op_len(p, level) > 0 {
                bump_chain_op(p);
                match p.nested(&operand) {
                    Some(h) => rest = rest.max(h),
                    None => {
                        p.error_and_recover("an operand");
                        break;
                    }
                }
            }
            p.finish_node();
            return Some(height.max(rest + 1));
        }
        p.start_at(checkpoint, BIN_EXPR);
        bump_chain_op(p);
        let Some(right) = p.nested(&operand) else {
            p.error_and_recover("an operand");
            p.finish_node();
            return Some(height + 1);
        };
        height = height.max(right) + 1;
        p.finish_node();
    }
    Some(height)
}

/// Number of tokens of a comparison operator here, or 0. A lone `>` is a comparison only if
/// an operand follows on the same line (the block rule, language.md §1.3;
/// [`Parser::r_angle_closes`]).
fn compare_op_len(p: &Parser<'_>) -> usize {
    let joined = |kind| p.nth(1) == kind && p.nth_joined(1);
    match p.current() {
        L_ANGLE if joined(R_ANGLE) || joined(EQ) => 2,
        R_ANGLE if joined(EQ) => 2,
        EQ | L_ANGLE => 1,
        // A lone `>` compares only where it does not close the block.
        R_ANGLE => usize::from(!p.r_angle_closes()),
        _ => 0,
    }
}

fn comparison(p: &mut Parser<'_>) -> Option<u32> {
    let checkpoint = p.checkpoint();
    let left = arithmetic(p, Level::Additive)?;
    let n = compare_op_len(p);
    if n == 0 {
        return Some(left);
    }
    // Too deep: the operator and the right operand stay flat beside the left one.
    let wrap = p.fits(left + 1);
    if wrap {
        p.start_at(checkpoint, BIN_EXPR);
    } else {
        p.error_too_deep();
        p.start(ERROR);
    }
    if n == 2 {
        p.bump_node(COMPARE_OP, 2);
    } else {
        p.bump();
    }
    let right = p.nested(|p| arithmetic(p, Level::Additive));
    if right.is_none() {
        p.error_and_recover("an operand");
    }
    p.finish_node();
    let right = right.unwrap_or(0);
    Some(if wrap {
        left.max(right) + 1
    } else {
        left.max(right + 1)
    })
}

/// Is a prefix operator here: `not`, or a `-` that is not part of a negative number (`-5`
/// stays one LITERAL)?
fn at_prefix_op(p: &Parser<'_>) -> bool {
    p.at_kw(NOT_KW) || (p.at(MINUS) && stl::literal_len(p) == 0 && !p.at_arrow())
}

fn unary(p: &mut Parser<'_>) -> Option<u32> {
    if at_prefix_op(p) {
        if !p.fits(1) {
            return Some(too_deep_operand(p));
        }
        p.start(PREFIX_EXPR);
        if p.at(MINUS) {
            p.bump();
        } else {
            p.bump_keyword();
        }
        let inner = p.nested(unary);
        if inner.is_none() {
            p.error_and_recover("an operand");
        }
        p.finish_node();
        return Some(inner.unwrap_or(0) + 1);
    }
    primary(p)
}

fn primary(p: &mut Parser<'_>) -> Option<u32> {
    if p.at(L_PAREN) {
        if !p.fits(1) {
            return Some(too_deep_operand(p));
        }
        p.start(PAREN_EXPR);
        p.bump();
        let recoveries = p.recoveries();
        let inner = p.nested(expr);
        if inner.is_none() {
            p.error_and_recover("an expression");
        } else if p.recoveries() == recoveries {
            if p.at(R_PAREN) {
                p.bump();
            } else {
                p.error_and_recover("')'");
            }
        }
        p.finish_node();
        return Some(inner.unwrap_or(0) + 1);
    }
    chart_operand(p).then_some(0)
}

/// HG0012 at a `not`, unary `-` or `(` that would nest too deep: the prefix operators, then
/// the parenthesised expression (up to its balancing `)`) or the operand, flat in one ERROR
/// node.
fn too_deep_operand(p: &mut Parser<'_>) -> u32 {
    p.error_too_deep();
    p.start(ERROR);
    while at_prefix_op(p) {
        if p.at(MINUS) {
            p.bump();
        } else {
            p.bump_keyword();
        }
    }
    if p.at(L_PAREN) {
        p.skip_balanced(L_PAREN, R_PAREN);
    } else {
        chart_operand(p);
    }
    p.finish_node();
    0
}

/// An operand in a chart: a constant, an address, `"symbol"` or a dotted path; in a test, a
/// constant or a test path.
fn chart_operand(p: &mut Parser<'_>) -> bool {
    if stl::literal(p) {
        return true;
    }
    if p.in_test {
        return super::test::test_path(p);
    }
    path(p)
}

/// `NAME { . NAME }`, `"symbol"` or an address, wrapped in a PATH node.
fn path(p: &mut Parser<'_>) -> bool {
    match p.current() {
        STRING => {
            p.start(PATH);
            p.bump_node(SYMBOL_REF, 1);
            p.finish_node();
            true
        }
        IDENT => {
            p.start(PATH);
            if !stl::address(p) {
                p.bump_node(NAME_REF, 1);
                while p.at(DOT) && p.nth_joined(0) && p.nth(1) == IDENT && p.nth_joined(1) {
                    p.bump();
                    p.bump_node(NAME_REF, 1);
                }
            }
            p.finish_node();
            true
        }
        _ => false,
    }
}

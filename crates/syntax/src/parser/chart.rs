//! Sequence charts: `chart [type] NAME ["comment"] < sections, properties, sequencers >`,
//! sequencers with steps, transitions, branches, jumps and loops, and chart expressions.

use std::fmt;

use rowan::TextRange;

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
            } else if p.at_kw(ACTION_KW) && p.nth(1) == IDENT {
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
            BodyKind::Statements => top_statement(p),
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

/// Is the current identifier the keyword `kw` of a structured statement: spelled like it and
/// not followed by `:=` or `.` (then it is a variable: `If := TRUE;`, `Case.X := 1;`)?
fn at_stmt_kw(p: &Parser<'_>, kw: SyntaxKind) -> bool {
    p.at_kw(kw) && !p.nth_is_assign(1) && p.nth(1) != DOT
}

/// A keyword that ends a list of statements inside `IF` or `CASE` (`ELSIF`, `ELSE`,
/// `END_IF`, `END_CASE`), or the start of a case label (a number: no statement begins with
/// one).
fn at_stmt_list_end(p: &Parser<'_>) -> bool {
    [ELSIF_KW, ELSE_KW, END_IF_KW, END_CASE_KW]
        .iter()
        .any(|&kw| at_stmt_kw(p, kw))
        || p.signed_number_len(false) > 0
}

/// Does the enclosing body end here: a `>` at statement start, the end of the file, an item
/// or a member keyword of the sequencer or chart (language.md §1.4)?
fn at_body_end(p: &Parser<'_>) -> bool {
    p.at(R_ANGLE)
        || p.at_eof()
        || p.at_item_start()
        || p.at_member_start(Scope::Sequencer)
        || p.at_member_start(Scope::Chart)
}

/// A statement of a step phase, `pre`, `post` or action body (docs/iec.md §5). A keyword
/// that only continues an `IF` or `CASE` stands here alone: one HG0001.
fn top_statement(p: &mut Parser<'_>) {
    if [ELSIF_KW, ELSE_KW, END_IF_KW, END_CASE_KW]
        .iter()
        .any(|&kw| at_stmt_kw(p, kw))
    {
        p.error_and_recover("a statement");
    } else {
        statement(p);
    }
}

/// `assignment | if_stmt | case_stmt | fb_call`.
fn statement(p: &mut Parser<'_>) {
    let structured = at_stmt_kw(p, IF_KW) || at_stmt_kw(p, CASE_KW);
    if structured && !p.fits(1) {
        too_deep_statement(p);
    } else if at_stmt_kw(p, IF_KW) {
        p.nested(if_stmt);
    } else if at_stmt_kw(p, CASE_KW) {
        p.nested(case_stmt);
    } else if p.at(IDENT) && p.nth(1) == L_PAREN {
        fb_call(p);
    } else {
        assignment(p);
    }
}

/// Statements up to the end of the enclosing list ([`at_stmt_list_end`], [`at_body_end`]).
/// In a case arm, also up to `NAME :` (a label that is not an integer constant: no statement
/// begins so).
fn statement_list(p: &mut Parser<'_>, in_case: bool) {
    let at_bad_label =
        |p: &Parser<'_>| in_case && p.at(IDENT) && p.nth(1) == COLON && !p.nth_is_assign(1);
    while !(at_stmt_list_end(p) || at_body_end(p) || at_bad_label(p)) {
        statement(p);
    }
}

/// HG0012 at an `IF` or `CASE` that would nest too deep: the statement, up to its balancing
/// `END_IF`/`END_CASE` and `;`, flat in one ERROR node. Stops early at a `>` that closes the
/// body, the end of the file or an item keyword that starts a line.
fn too_deep_statement(p: &mut Parser<'_>) {
    p.error_too_deep();
    p.start(ERROR);
    let mut open = 0usize;
    while !(p.at_eof() || p.r_angle_closes() || (p.nth_on_new_line(0) && p.at_item_start())) {
        if at_stmt_kw(p, IF_KW) || at_stmt_kw(p, CASE_KW) {
            open += 1;
        } else if at_stmt_kw(p, END_IF_KW) || at_stmt_kw(p, END_CASE_KW) {
            open = open.saturating_sub(1);
            if open == 0 {
                p.bump();
                if p.at(SEMI) {
                    p.bump();
                }
                break;
            }
        }
        p.bump();
    }
    p.finish_node();
}

/// After an `IF`/`ELSIF` condition or a `CASE` selector: `THEN`/`OF`. When it is missing,
/// one HG0001; if the keyword follows later on the line, the tokens up to it are skipped.
fn expect_stmt_kw(p: &mut Parser<'_>, kw: SyntaxKind, text: &str) {
    if p.at_kw(kw) {
        p.bump_keyword();
        return;
    }
    p.error_expected(text);
    // Look a little ahead on this line for the keyword.
    let ahead = (1..64)
        .take_while(|&k| !p.nth_on_new_line(k) && !matches!(p.nth(k), SEMI | R_ANGLE | L_ANGLE))
        .find(|&k| p.nth_is_kw(k, kw));
    if let Some(k) = ahead {
        p.start(ERROR);
        for _ in 0..k {
            p.bump();
        }
        p.finish_node();
        p.bump_keyword();
    }
}

/// `IF c THEN stmts { ELSIF c THEN stmts } [ ELSE stmts ] END_IF ;`
fn if_stmt(p: &mut Parser<'_>) {
    p.start(IF_STMT);
    let start = p.nth_range(0);
    p.bump_keyword();
    if condition_expr(p, THEN_KW) {
        expect_stmt_kw(p, THEN_KW, "'THEN'");
    }
    statement_list(p, false);
    while at_stmt_kw(p, ELSIF_KW) {
        p.start(ELSIF_CLAUSE);
        p.bump_keyword();
        if condition_expr(p, THEN_KW) {
            expect_stmt_kw(p, THEN_KW, "'THEN'");
        }
        statement_list(p, false);
        p.finish_node();
    }
    if at_stmt_kw(p, ELSE_KW) {
        else_clause(p);
    }
    end_stmt(p, END_IF_KW, "'END_IF'", start);
    p.finish_node();
}

/// The condition of `IF`/`ELSIF` or the selector of `CASE`; `false` after an error.
fn condition_expr(p: &mut Parser<'_>, then: SyntaxKind) -> bool {
    // `IF THEN`; but `IF Then THEN`, `IF Then + 1 > 2 THEN` (a variable named like the
    // keyword: what follows continues the expression).
    let continues = matches!(
        p.nth(1),
        PLUS | MINUS | STAR | SLASH | EQ | L_ANGLE | R_ANGLE | DOT
    ) || [then, AND_KW, OR_KW, XOR_KW, MOD_KW]
        .iter()
        .any(|&kw| p.nth_is_kw(1, kw));
    if p.at_kw(then) && !continues {
        p.error_expected("an expression");
        return false;
    }
    let recoveries = p.recoveries();
    if expr(p).is_none() {
        p.error_expected("an expression");
        return false;
    }
    p.recoveries() == recoveries
}

/// `ELSE stmts` of an `IF` or a `CASE`.
fn else_clause(p: &mut Parser<'_>) {
    p.start(ELSE_CLAUSE);
    p.bump_keyword();
    statement_list(p, false);
    p.finish_node();
}

/// `END_IF;` / `END_CASE;`: one HG0001 where the keyword is missing (the statements before
/// it stay in the statement).
fn end_stmt(p: &mut Parser<'_>, kw: SyntaxKind, text: &'static str, start: TextRange) {
    if at_stmt_kw(p, kw) {
        p.bump_keyword();
        p.expect_semi(&text, |p| matches!(p.current(), IDENT | STRING));
    } else {
        let opened = if kw == END_IF_KW { "'IF'" } else { "'CASE'" };
        p.error_expected_related(text, start, &format!("this {opened} is not closed"));
    }
}

/// `CASE e OF { labels : stmts } [ ELSE stmts ] END_CASE ;`
fn case_stmt(p: &mut Parser<'_>) {
    p.start(CASE_STMT);
    let start = p.nth_range(0);
    p.bump_keyword();
    if condition_expr(p, OF_KW) {
        expect_stmt_kw(p, OF_KW, "'OF'");
    }
    loop {
        if at_body_end(p)
            || [ELSE_KW, END_IF_KW, END_CASE_KW, ELSIF_KW]
                .iter()
                .any(|&kw| at_stmt_kw(p, kw))
        {
            break;
        }
        case_arm(p);
    }
    if at_stmt_kw(p, ELSE_KW) {
        else_clause(p);
    }
    end_stmt(p, END_CASE_KW, "'END_CASE'", start);
    p.finish_node();
}

/// `label { , label } : stmts`. A label that is not an integer constant is one HG0001; the
/// arm's statements after its `:` are still read.
fn case_arm(p: &mut Parser<'_>) {
    p.start(CASE_ARM);
    let mut labels_ok = true;
    loop {
        if !case_label(p) {
            p.error_expected("a case label (an integer constant or range)");
            labels_ok = false;
            break;
        }
        if p.at(COMMA) {
            p.bump();
        } else {
            if !p.at_colon() {
                p.error_expected("',' or ':'");
                labels_ok = false;
            }
            break;
        }
    }
    if !labels_ok {
        // Skip to the arm's `:` (its statements are still read) or past a `;`.
        p.start(ERROR);
        while !p.at_eof() && !p.at_colon() && !p.at(SEMI) && !p.at(R_ANGLE) && !at_stmt_list_end(p)
        {
            p.bump();
        }
        if p.at(SEMI) {
            p.bump();
        }
        p.finish_node();
    }
    if p.at_colon() {
        p.bump();
        statement_list(p, true);
    }
    p.finish_node();
}

/// `[-]INT [ .. [-]INT ]` as a CASE_LABEL node.
fn case_label(p: &mut Parser<'_>) -> bool {
    let n = p.signed_number_len(true);
    if n == 0 {
        return false;
    }
    p.start(CASE_LABEL);
    for _ in 0..n {
        p.bump();
    }
    if p.at(DOT) && p.nth(1) == DOT && p.nth_joined(1) {
        p.bump();
        p.bump();
        let m = p.signed_number_len(true);
        if m == 0 {
            p.error_expected("the end of the range (an integer constant)");
        }
        for _ in 0..m {
            p.bump();
        }
    }
    p.finish_node();
    true
}

/// `NAME ( [ arg { , arg } ] ) ;` with `arg = NAME := expr | NAME => path`.
fn fb_call(p: &mut Parser<'_>) {
    p.start(FB_CALL);
    let callee = p.nth_text(0);
    p.bump_node(NAME_REF, 1);
    p.bump(); // (
    let mut closed = false;
    if p.at(R_PAREN) {
        p.bump();
        closed = true;
    } else {
        loop {
            if !fb_arg(p) {
                break;
            }
            if p.at(COMMA) {
                p.bump();
                continue;
            }
            if p.at(R_PAREN) {
                p.bump();
                closed = true;
            } else {
                p.error_expected("',' or ')'");
            }
            break;
        }
    }
    if closed {
        let element = lazy(|f| write!(f, "the call of '{callee}'"));
        p.expect_semi(&element, |p| matches!(p.current(), IDENT | STRING));
    } else {
        recover_call(p);
    }
    p.finish_node();
}

/// After an error in a call: skips the rest of the call on its line, up to and including its
/// `)` and `;`.
fn recover_call(p: &mut Parser<'_>) {
    let at_stop =
        |p: &Parser<'_>| p.at_eof() || p.at(SEMI) || p.nth_on_new_line(0) || p.r_angle_closes();
    if !at_stop(p) {
        p.start(ERROR);
        while !at_stop(p) {
            let close = p.at(R_PAREN);
            p.bump();
            if close {
                break;
            }
        }
        p.finish_node();
    }
    if p.at(SEMI) {
        p.bump();
    }
}

/// One argument of a call; `false` after an error (reported).
fn fb_arg(p: &mut Parser<'_>) -> bool {
    p.start(FB_ARG);
    let ok = if !p.at(IDENT) {
        p.error_expected("a parameter name");
        false
    } else {
        p.bump_node(NAME_REF, 1);
        if p.at_assign() {
            p.bump_node(ASSIGN_OP, 2);
            let recoveries = p.recoveries();
            if expr(p).is_none() {
                p.error_expected("an expression");
                false
            } else {
                p.recoveries() == recoveries
            }
        } else if p.at(EQ) && p.nth(1) == R_ANGLE && p.nth_joined(1) {
            p.bump_node(OUTPUT_OP, 2);
            if path(p) {
                true
            } else {
                p.error_expected("a variable");
                false
            }
        } else {
            p.error_expected("':=' or '=>'");
            false
        }
    };
    p.finish_node();
    ok
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

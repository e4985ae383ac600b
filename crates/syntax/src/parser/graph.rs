//! State graphs: `graph NAME ["comment"] < members >` with variable sections, `activate`,
//! `permanent`, states and transitions.

use super::{Parser, Scope, items, lazy, stl};
use crate::SyntaxKind::*;

pub(crate) fn graph(p: &mut Parser<'_>) {
    p.start(GRAPH);
    p.bump_keyword();
    let construct = format!("graph {}", p.nth_text(0));
    if !p.name() {
        p.error_expected("a graph name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    p.opt_comment_string();
    p.start(BODY);
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, &[]) {
            member(p);
        }
    }
    p.finish_node();
    p.finish_node();
}

pub(super) fn member(p: &mut Parser<'_>) {
    if items::at_var_section(p) {
        items::var_section(p, &[Scope::Graph]);
    } else if p.at_kw(ACTIVATE_KW) {
        activate(p);
    } else if p.at_kw(PERMANENT_KW) {
        p.start(PERMANENT);
        p.bump_keyword();
        stl::instruction_body(p, &"permanent");
        p.finish_node();
    } else if p.at_kw(STATE_KW) {
        state(p);
    } else if p.at_kw(TRANS_KW) {
        trans(p);
    } else {
        p.error_and_recover("a graph member ('state', 'trans', 'in', 'out', 'in_out', 'stat', 'activate', 'permanent') or '>'");
    }
}

/// `activate CurrentState, StateChange;`
fn activate(p: &mut Parser<'_>) {
    p.start(ACTIVATE);
    p.bump_keyword();
    loop {
        if p.at(IDENT) {
            p.bump_node(NAME_REF, 1);
        } else {
            p.error_and_recover("a predefined variable");
            p.finish_node();
            return;
        }
        if p.at(COMMA) {
            p.bump();
        } else {
            break;
        }
    }
    p.expect_semi(&"'activate'", |p| p.at_member_start(Scope::Graph));
    p.finish_node();
}

/// Number of tokens of an `INT` (a state number, endpoint or priority) at the current
/// position: `4` or `-4` (tolerated here, reported by the analysis: HG2102, HG2303); 0 if none.
fn int_len(p: &Parser<'_>) -> usize {
    p.signed_number_len(true)
}

/// `state N ["name"] {fault|message} < items >`
fn state(p: &mut Parser<'_>) {
    p.start(STATE);
    p.bump_keyword();
    let n = int_len(p);
    // The number as written: `-` and the digits, or the digits.
    let number = (n > 0).then(|| (p.nth_text(0), if n == 2 { p.nth_text(1) } else { "" }));
    let construct = lazy(|f| match number {
        Some((first, second)) => write!(f, "state {first}{second}"),
        None => f.write_str("state"),
    });
    let mut header_ok = true;
    if n > 0 {
        for _ in 0..n {
            p.bump();
        }
        loop {
            if p.at(STRING) {
                p.bump_node(COMMENT_STRING, 1);
            } else if p.at_kw(FAULT_KW) || p.at_kw(MESSAGE_KW) {
                p.start(ATTRIBUTE);
                p.bump_keyword();
                p.finish_node();
            } else {
                break;
            }
        }
    } else {
        p.error_expected("a state number");
        header_ok = p.recover_header();
    }
    if header_ok {
        stl::instruction_body(p, &construct);
    }
    p.finish_node();
}

/// `trans A->B {prio N | auto | manual | waits | fault | "name"} < body >`
fn trans(p: &mut Parser<'_>) {
    p.start(TRANS);
    p.bump_keyword();
    let source = endpoint_text(p);
    if !endpoint(p) {
        p.error_expected("a state number, 'any' or 'return'");
        if p.recover_header() {
            stl::instruction_body(p, &"transition");
        }
        p.finish_node();
        return;
    }
    if !p.at_arrow() {
        p.error_expected("'->'");
        if p.recover_header() {
            stl::instruction_body(p, &"transition");
        }
        p.finish_node();
        return;
    }
    p.bump_node(ARROW, 2);
    let target = endpoint_text(p);
    if !endpoint(p) {
        p.error_expected("a state number, 'any' or 'return'");
        if p.recover_header() {
            stl::instruction_body(p, &"transition");
        }
        p.finish_node();
        return;
    }
    let construct = lazy(|f| {
        write!(
            f,
            "transition {}{}->{}{}",
            source.0, source.1, target.0, target.1
        )
    });
    loop {
        if p.at_kw(PRIO_KW) {
            p.start(PRIO_CLAUSE);
            p.bump_keyword();
            let n = int_len(p);
            if n > 0 {
                for _ in 0..n {
                    p.bump();
                }
                p.finish_node();
            } else {
                p.finish_node();
                p.error_expected("a priority");
                if p.recover_header() {
                    break;
                }
                p.finish_node();
                return;
            }
        } else if [AUTO_KW, MANUAL_KW, WAITS_KW, FAULT_KW]
            .iter()
            .any(|&kw| p.at_kw(kw))
        {
            p.start(ATTRIBUTE);
            p.bump_keyword();
            p.finish_node();
        } else if p.at(STRING) {
            p.bump_node(COMMENT_STRING, 1);
        } else {
            break;
        }
    }
    stl::instruction_body(p, &construct);
    p.finish_node();
}

/// The endpoint at the current position as written, for messages: `-1` is two tokens.
fn endpoint_text<'t>(p: &Parser<'t>) -> (&'t str, &'t str) {
    if int_len(p) == 2 {
        (p.nth_text(0), p.nth_text(1))
    } else {
        (p.nth_text(0), "")
    }
}

/// `4`, `-4` (tolerated; it names no state), `any` or `return`.
fn endpoint(p: &mut Parser<'_>) -> bool {
    let n = int_len(p);
    if n > 0 {
        p.bump_node(ENDPOINT, n);
    } else if p.at_kw(ANY_KW) || p.at_kw(RETURN_KW) {
        p.start(ENDPOINT);
        p.bump_keyword();
        p.finish_node();
    } else {
        return false;
    }
    true
}

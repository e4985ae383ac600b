//! Tests (`runtime.md` §5.1): `test NAME ["description"] < statements >`. Every statement
//! begins with its keyword; expressions are the chart expressions (`chart::expr`) whose
//! paths are test paths (`TEST_PATH`: `(NAME | "symbol") { . NAME }` or an address).

use super::{Parser, chart, lazy, stl};
use crate::{SyntaxKind, SyntaxKind::*};

pub(crate) fn test(p: &mut Parser<'_>) {
    p.start(TEST);
    p.bump_keyword();
    let construct = format!("test {}", p.nth_text(0));
    if !p.name() {
        p.error_expected("a test name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    p.opt_comment_string();
    if !p.at(L_ANGLE) && p.at_item_start() {
        // `test T "x"` and the next item: the test has no body; the next item stays whole.
        p.error_expected(&format!("'<' to open {construct}"));
        p.finish_node();
        return;
    }
    p.start(BODY);
    if let Some(open) = p.expect_open(&construct) {
        let outer = std::mem::replace(&mut p.in_test, true);
        while !p.body_ends(open, &construct, &[]) {
            if !statement(p) {
                p.error_and_recover(
                    "a test statement ('cycle', 'run', 'set', 'step', 'wait', 'until', 'expect', \
                     'command', 'confirm', 'restart') or '>'",
                );
            }
        }
        p.in_test = outer;
    }
    p.finish_node();
    p.finish_node();
}

/// The statement keyword at the current position, if any.
fn statement_keyword(p: &Parser<'_>) -> Option<SyntaxKind> {
    let kw = p.nth_keyword(0);
    matches!(
        kw,
        CYCLE_KW
            | RUN_KW
            | SET_KW
            | STEP_KW
            | WAIT_KW
            | UNTIL_KW
            | EXPECT_KW
            | COMMAND_KW
            | CONFIRM_KW
            | RESTART_KW
    )
    .then_some(kw)
}

/// Can a test statement begin here (for the HG0002 decision of a missing `;`)?
fn at_statement(p: &Parser<'_>) -> bool {
    statement_keyword(p).is_some()
}

/// One statement. Returns `false` (consuming nothing) if none begins here.
fn statement(p: &mut Parser<'_>) -> bool {
    let Some(kw) = statement_keyword(p) else {
        return false;
    };
    let word = p.nth_text(0);
    let element = lazy(move |f| write!(f, "'{}'", word.to_ascii_lowercase()));
    match kw {
        CYCLE_KW => {
            p.start(TEST_CYCLE);
            p.bump_keyword();
            if time_constant(p) {
                p.expect_semi(&element, at_statement);
            }
        }
        WAIT_KW => {
            p.start(TEST_WAIT);
            p.bump_keyword();
            if time_constant(p) {
                p.expect_semi(&element, at_statement);
            }
        }
        RUN_KW => {
            p.start(TEST_RUN);
            p.bump_keyword();
            if p.at(IDENT) {
                p.bump_node(NAME_REF, 1);
                let mut ok = true;
                while p.at(COMMA) {
                    p.bump();
                    if p.at(IDENT) {
                        p.bump_node(NAME_REF, 1);
                    } else {
                        p.error_and_recover("a group or chart name");
                        ok = false;
                        break;
                    }
                }
                if ok {
                    p.expect_semi(&element, at_statement);
                }
            } else {
                p.error_and_recover("a group or chart name");
            }
        }
        SET_KW => {
            p.start(TEST_SET);
            p.bump_keyword();
            if !test_path(p) {
                p.error_and_recover("a path");
            } else if !p.at_assign() {
                p.error_and_recover("':='");
            } else {
                p.bump_node(ASSIGN_OP, 2);
                let recoveries = p.recoveries();
                if chart::expr(p).is_none() {
                    p.error_and_recover("an expression");
                } else if p.recoveries() == recoveries {
                    p.expect_semi(&element, at_statement);
                }
            }
        }
        STEP_KW => {
            p.start(TEST_STEP);
            p.bump_keyword();
            // Any whole number, also negative: HG9004 reports the range.
            for _ in 0..p.signed_number_len(true) {
                p.bump();
            }
            p.expect_semi(&element, at_statement);
        }
        UNTIL_KW => {
            p.start(TEST_UNTIL);
            p.bump_keyword();
            let recoveries = p.recoveries();
            if chart::expr(p).is_none() {
                p.error_and_recover("a condition");
            } else if p.recoveries() == recoveries {
                if p.at_kw(WITHIN_KW) {
                    p.start(WITHIN_CLAUSE);
                    p.bump_keyword();
                    let ok = time_constant(p);
                    p.finish_node();
                    if ok {
                        p.opt_comment_string();
                        p.expect_semi(&element, at_statement);
                    }
                } else {
                    p.error_and_recover("'within'");
                }
            }
        }
        EXPECT_KW => {
            p.start(TEST_EXPECT);
            p.bump_keyword();
            let recoveries = p.recoveries();
            if chart::expr(p).is_none() {
                p.error_and_recover("a condition");
            } else if p.recoveries() == recoveries {
                p.opt_comment_string();
                p.expect_semi(&element, at_statement);
            }
        }
        COMMAND_KW => {
            p.start(TEST_COMMAND);
            p.bump_keyword();
            if !p.at(IDENT) {
                p.error_and_recover("a chart name");
            } else {
                p.bump_node(NAME_REF, 1);
                if p.at(IDENT) && !p.nth_on_new_line(0) {
                    p.bump_node(NAME_REF, 1);
                    p.expect_semi(&element, at_statement);
                } else {
                    p.error_and_recover("a command");
                }
            }
        }
        CONFIRM_KW => {
            p.start(TEST_CONFIRM);
            p.bump_keyword();
            if test_path(p) {
                p.expect_semi(&element, at_statement);
            } else {
                p.error_and_recover("a step path");
            }
        }
        _ => {
            p.start(TEST_RESTART);
            p.bump_keyword();
            if p.at_kw(COLD_KW) || p.at_kw(WARM_KW) {
                p.bump_keyword();
                p.expect_semi(&element, at_statement);
            } else {
                p.error_and_recover("'cold' or 'warm'");
            }
        }
    }
    p.finish_node();
    true
}

/// A `T#`/`TIME#` constant (LITERAL node); reports HG0001 and recovers otherwise. Returns
/// whether there was one.
fn time_constant(p: &mut Parser<'_>) -> bool {
    if p.at(TYPED_CONST) && is_time_prefix(p.nth_text(0)) && stl::literal(p) {
        return true;
    }
    p.error_and_recover("a time constant (T#...)");
    false
}

fn is_time_prefix(text: &str) -> bool {
    let prefix = text.split('#').next().unwrap_or("");
    prefix.eq_ignore_ascii_case("T") || prefix.eq_ignore_ascii_case("TIME")
}

/// A test path (TEST_PATH node): an address, or `NAME`/`"symbol"` followed by `.NAME`
/// segments written together. Returns `false` (consuming nothing) if none starts here.
pub(crate) fn test_path(p: &mut Parser<'_>) -> bool {
    match p.current() {
        STRING => {
            p.start(TEST_PATH);
            p.bump_node(SYMBOL_REF, 1);
            segments(p);
        }
        IDENT => {
            p.start(TEST_PATH);
            if !stl::address(p) {
                p.bump_node(NAME_REF, 1);
                segments(p);
            }
        }
        _ => return false,
    }
    p.finish_node();
    true
}

fn segments(p: &mut Parser<'_>) {
    while p.at(DOT) && p.nth_joined(0) && p.nth(1) == IDENT && p.nth_joined(1) {
        p.bump();
        p.bump_node(NAME_REF, 1);
    }
}

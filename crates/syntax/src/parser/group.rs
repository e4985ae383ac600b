//! Graph groups: `group NAME [fc ..] [db ..] ["comment"] < options and instances >`.

use super::{Parser, Scope, lazy, stl};
use crate::SyntaxKind::*;

pub(crate) fn group(p: &mut Parser<'_>) {
    p.start(GROUP);
    p.bump_keyword();
    let construct = format!("group {}", p.nth_text(0));
    if !p.name() {
        p.error_expected("a group name");
        if !p.recover_header() {
            p.finish_node();
            return;
        }
    }
    loop {
        let clause = if p.at_kw(FC_KW) {
            FC_CLAUSE
        } else if p.at_kw(DB_KW) {
            DB_CLAUSE
        } else {
            break;
        };
        p.start(clause);
        p.bump_keyword();
        let ok = stl::block_ref(p);
        p.finish_node();
        if !ok {
            p.error_expected("a block name");
            if !p.recover_header() {
                p.finish_node();
                return;
            }
            break;
        }
    }
    p.opt_comment_string();
    p.start(BODY);
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, &[]) {
            if p.at_kw(OPTION_KW) {
                option(p);
            } else if p.at_kw(INSTANCE_KW) {
                instance(p);
            } else {
                p.error_and_recover("'option', 'instance' or '>'");
            }
        }
    }
    p.finish_node();
    p.finish_node();
}

/// `option NAME [INT];`
fn option(p: &mut Parser<'_>) {
    p.start(OPTION);
    p.bump_keyword();
    if p.name() {
        // Any number, also negative (`-5`): HG8008 reports it.
        let n = p.signed_number_len(false);
        if n > 0 && !p.nth_on_new_line(0) {
            for _ in 0..n {
                p.bump();
            }
        }
        p.expect_semi(&"the option", |p| p.at_member_start(Scope::Group));
    } else {
        p.error_and_recover("an option name");
    }
    p.finish_node();
}

/// `instance NAME : GRAPH ["comment"] < actuals >`
fn instance(p: &mut Parser<'_>) {
    p.start(INSTANCE);
    p.bump_keyword();
    let construct = format!("instance {}", p.nth_text(0));
    let header_ok = if !p.name() {
        p.error_expected("an instance name");
        p.recover_header()
    } else if !p.at_colon() {
        p.error_expected("':'");
        p.recover_header()
    } else {
        p.bump();
        if p.at(IDENT) {
            p.bump_node(NAME_REF, 1);
            p.opt_comment_string();
            true
        } else {
            p.error_expected("a graph name");
            p.recover_header()
        }
    };
    if header_ok {
        p.start(BODY);
        if let Some(open) = p.expect_open(&construct) {
            while !p.body_ends(open, &construct, &[Scope::Group]) {
                if p.at(IDENT) {
                    actual(p);
                } else {
                    p.error_and_recover("an actual parameter or '>'");
                }
            }
        }
        p.finish_node();
    }
    p.finish_node();
}

/// `Formal := operand;` or `Formal := Inst.Msg;`
fn actual(p: &mut Parser<'_>) {
    p.start(ACTUAL);
    let name = p.nth_text(0);
    let element = lazy(|f| write!(f, "the actual parameter {name}"));
    p.bump_node(NAME_REF, 1);
    if !p.at_assign() {
        p.error_and_recover("':='");
        p.finish_node();
        return;
    }
    p.bump_node(ASSIGN_OP, 2);
    let recoveries = p.recoveries();
    // The value may begin on a later line: the line rule of language.md §1.3 is for STL
    // operands only.
    let is_message = p.at(IDENT) && p.nth(1) == DOT && p.nth(2) == IDENT && !stl::at_db_address(p);
    if is_message {
        p.start(MESSAGE_TARGET);
        p.bump_node(NAME_REF, 1);
        p.bump();
        p.bump_node(NAME_REF, 1);
        p.finish_node();
    } else if !stl::operand(p) {
        p.error_and_recover("an operand, a constant or 'Instance.Message'");
        p.finish_node();
        return;
    }
    if p.recoveries() == recoveries {
        p.expect_semi(&element, |p| p.at(IDENT));
    }
    p.finish_node();
}

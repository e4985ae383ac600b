//! File level: items, `mnemonic`, `symbols`, `block` interfaces and variable sections (shared
//! by graphs, charts and block interfaces).

use rowan::TextRange;

use super::{Parser, Scope, chart, graph, group, lazy, stl, test};
use crate::{SyntaxError, SyntaxKind::*, error::ErrorCode};

pub(crate) fn source_file(p: &mut Parser<'_>) {
    p.start_root();
    // HG0010 / HG0011: the first `mnemonic` must be the first item; later ones are ignored.
    let mut first_mnemonic: Option<(TextRange, String)> = None;
    let mut seen_item = false;
    while !p.at_eof() {
        let start = p.nth_range(0).start();
        let mut set = None;
        // The directive's keyword and set as written, for the HG0010 fix to move (`None`
        // without a valid set: then there is nothing sound to move).
        let mut directive = None;
        if p.at_kw(MNEMONIC_KW) {
            directive = (p.nth_is_kw(1, SIMATIC_KW) || p.nth_is_kw(1, INTERNATIONAL_KW))
                .then(|| (p.nth_text(0), p.nth_text(1)));
            set = Some(mnemonic(p));
        } else if p.at(R_ANGLE) {
            let range = p.nth_range(0);
            p.bump_node(ERROR, 1);
            p.push_error(
                SyntaxError::new(ErrorCode::HG0008, range, "'>' without an open block").with_fix(
                    "Delete the '>'",
                    range,
                    "",
                ),
            );
        } else if !item(p) {
            p.error_expected(
                "an item ('graph', 'group', 'chart', 'symbols', 'block', 'test' or 'mnemonic')",
            );
            recover_item(p);
        }
        if let Some(set) = set {
            let range = TextRange::new(start, p.last_end());
            match &first_mnemonic {
                None => {
                    if seen_item {
                        let mut error = SyntaxError::new(
                            ErrorCode::HG0010,
                            range,
                            "'mnemonic' must be the first item of the file",
                        );
                        // Move: insert it at the top (only comments may precede it there),
                        // delete it here.
                        if let Some((keyword, set)) = directive {
                            let top = TextRange::empty(p.text_start());
                            error = error.with_fix_edits(
                                "Move it to the top of the file",
                                vec![(top, format!("{keyword} {set};\n")), (range, String::new())],
                            );
                        }
                        p.push_error(error);
                    }
                    first_mnemonic = Some((range, set));
                }
                Some((first, set)) => {
                    let message =
                        format!("second 'mnemonic' directive; the first one ({set}) applies");
                    p.push_error(
                        SyntaxError::new(ErrorCode::HG0011, range, message)
                            .with_related(*first, "the first 'mnemonic' directive")
                            .with_fix("Delete it", range, ""),
                    );
                }
            }
        }
        seen_item = true;
    }
    p.flush_rest();
    p.finish_node();
}

/// Recovery at file level: skips to the next item keyword, past the next `;` or past the `>`
/// that balances a `<` skipped on the way (so `grap G < ... >` is one error, not two).
fn recover_item(p: &mut Parser<'_>) {
    p.start(ERROR);
    let mut depth = 0usize;
    let mut first = true;
    while !p.at_eof() {
        match p.current() {
            SEMI if depth == 0 => {
                p.bump();
                break;
            }
            L_ANGLE => depth += 1,
            R_ANGLE if depth == 0 => break,
            R_ANGLE => {
                depth -= 1;
                if depth == 0 {
                    p.bump();
                    break;
                }
            }
            _ if !first && p.at_item_start() => break,
            _ => {}
        }
        p.bump();
        first = false;
    }
    p.finish_node();
}

/// Parses an item if the current token starts one.
fn item(p: &mut Parser<'_>) -> bool {
    if p.at_kw(GRAPH_KW) {
        graph::graph(p);
    } else if p.at_kw(GROUP_KW) {
        group::group(p);
    } else if p.at_kw(CHART_KW) {
        chart::chart(p);
    } else if p.at_kw(SYMBOLS_KW) {
        symbols(p);
    } else if p.at_kw(BLOCK_KW) {
        block_interface(p);
    } else if p.at_kw(TEST_KW) {
        test::test(p);
    } else {
        return false;
    }
    true
}

/// `mnemonic simatic;` — returns the set as written in lower case (for HG0011's message).
fn mnemonic(p: &mut Parser<'_>) -> String {
    p.start(MNEMONIC);
    p.bump_keyword();
    let set = if p.at_kw(SIMATIC_KW) || p.at_kw(INTERNATIONAL_KW) {
        let set = p.nth_text(0).to_ascii_lowercase();
        p.bump_keyword();
        // An item keyword on the same line begins the next item (diagnostics.md HG0002).
        p.expect_semi(&"the 'mnemonic' directive", |p| p.at_item_start());
        set
    } else {
        p.error_and_recover("'simatic' or 'international'");
        "unknown".to_owned()
    };
    p.finish_node();
    set
}

/// `symbols < Name : address [type] ["comment"]; ... >`
fn symbols(p: &mut Parser<'_>) {
    p.start(SYMBOLS);
    p.bump_keyword();
    if let Some(open) = p.expect_open(&"the symbol table") {
        while !p.body_ends(open, &"the symbol table", &[]) {
            if p.at(IDENT) || p.at(STRING) {
                symbol(p);
            } else {
                p.error_and_recover("a symbol or '>'");
            }
        }
    }
    p.finish_node();
}

fn symbol(p: &mut Parser<'_>) {
    p.start(SYMBOL);
    let name = p.nth_text(0);
    p.bump_node(NAME, 1);
    let element = lazy(|f| write!(f, "symbol {name}"));
    if p.at_colon() {
        p.bump();
        if stl::address_in_table(p) {
            // A name or string followed by `:` begins the next symbol: it is neither the
            // type nor the comment of this one, whose `;` is missing (HG0002).
            if p.at(IDENT) && !p.nth_on_new_line(0) && !at_symbol(p) && !type_ref(p) {
                p.finish_node();
                return;
            }
            if !at_symbol(p) {
                p.opt_comment_string();
            }
            p.expect_semi(&element, |p| matches!(p.current(), IDENT | STRING));
        } else {
            p.error_and_recover("an address");
        }
    } else {
        p.error_and_recover("':'");
    }
    p.finish_node();
}

/// `NAME :` or `STRING :` (not `:=`): the beginning of a symbol.
fn at_symbol(p: &Parser<'_>) -> bool {
    matches!(p.current(), IDENT | STRING)
        && p.nth(1) == COLON
        && !(p.nth(2) == EQ && p.nth_joined(2))
}

/// `block FC 10 ["comment"] < var sections >`
fn block_interface(p: &mut Parser<'_>) {
    p.start(BLOCK_INTERFACE);
    p.bump_keyword();
    let construct = format!("block {}", stl::block_ref_text(p));
    if !stl::block_ref(p) {
        p.error_expected("a block (FC, FB, SFC, SFB or a symbol)");
    }
    p.opt_comment_string();
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, &[]) {
            if at_var_section(p) {
                var_section(p, &[]);
            } else {
                p.error_and_recover("'in', 'out', 'in_out', 'stat' or '>'");
            }
        }
    }
    p.finish_node();
}

/// `in <`, `out <`, `in_out <`, `stat <`.
pub(crate) fn at_var_section(p: &Parser<'_>) -> bool {
    (p.at_kw(IN_KW) || p.at_kw(OUT_KW) || p.at_kw(IN_OUT_KW) || p.at_kw(STAT_KW))
        && p.nth(1) == L_ANGLE
}

/// `in < Name : TYPE [msg in|out] [:= constant] ["comment"]; ... >`
pub(crate) fn var_section(p: &mut Parser<'_>, scopes: &[Scope]) {
    p.start(VAR_SECTION);
    let word = p.nth_text(0);
    let construct = lazy(|f| write!(f, "section '{}'", word.to_ascii_lowercase()));
    p.bump_keyword();
    if let Some(open) = p.expect_open(&construct) {
        while !p.body_ends(open, &construct, scopes) {
            if p.at(IDENT) {
                var_decl(p);
            } else {
                p.error_and_recover("a declaration or '>'");
            }
        }
    }
    p.finish_node();
}

fn var_decl(p: &mut Parser<'_>) {
    p.start(VAR_DECL);
    let name = p.nth_text(0);
    let element = lazy(|f| write!(f, "the declaration of {name}"));
    p.bump_node(NAME, 1);
    if !p.at_colon() {
        p.error_and_recover("':'");
        p.finish_node();
        return;
    }
    p.bump();
    if !p.at(IDENT) {
        p.error_and_recover("a type");
        p.finish_node();
        return;
    }
    if !type_ref(p) {
        p.finish_node();
        return;
    }
    if p.at_kw(MSG_KW) && (p.nth_is_kw(1, IN_KW) || p.nth_is_kw(1, OUT_KW)) {
        p.start(MSG_KIND);
        p.bump_keyword();
        p.bump_keyword();
        p.finish_node();
    }
    if p.at_assign() {
        p.start(INITIAL_VALUE);
        p.bump_node(ASSIGN_OP, 2);
        if !stl::literal(p) {
            p.error_and_recover("a constant");
            p.finish_node();
            p.finish_node();
            return;
        }
        p.finish_node();
    }
    p.opt_comment_string();
    p.expect_semi(&element, |p| p.at(IDENT));
    p.finish_node();
}

/// `BOOL`, `STRING[20]`. Returns `false` after an error (already recovered).
pub(crate) fn type_ref(p: &mut Parser<'_>) -> bool {
    p.start(TYPE_REF);
    p.bump();
    if p.at(L_BRACK) && !p.nth_on_new_line(0) {
        p.bump();
        if p.at(NUMBER) {
            p.bump();
        }
        if p.at(R_BRACK) {
            p.bump();
        } else {
            p.finish_node();
            p.error_and_recover("']'");
            return false;
        }
    }
    p.finish_node();
    true
}

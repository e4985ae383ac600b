//! STL: instruction bodies (labels, blocks, `wait`/`supervise`), statements, opcodes,
//! operands, addresses, constants and CALL arguments.

use std::fmt;

use super::{Parser, Scope, lazy};
use crate::{SyntaxKind, SyntaxKind::*};

/// Address-area identifiers of both mnemonic sets (diagnostics.md Appendix A.2). The parser
/// accepts both sets; analysis decides which is legal (HG4007). `DI` is the instance data
/// block of `AUF DI 2` (HG4003 alone, as for `AUF DB 2`).
const AREAS: &[&str] = &[
    "E", "A", "M", "L", "I", "Q", "EB", "EW", "ED", "AB", "AW", "AD", "MB", "MW", "MD", "LB", "LW",
    "LD", "IB", "IW", "ID", "QB", "QW", "QD", "PEB", "PEW", "PED", "PAB", "PAW", "PAD", "PIB",
    "PIW", "PID", "PQB", "PQW", "PQD", "PE", "PA", "PI", "PQ", "DBX", "DBB", "DBW", "DBD", "DIX",
    "DIB", "DIW", "DID", "T", "Z", "C", "DB", "FC", "FB", "SFC", "SFB", "OB", "UDT", "DI",
];

/// Areas that name blocks (`FC 10`, `DB 5`, `UDT 5`; language.md §3.5).
const BLOCK_AREAS: &[&str] = &["OB", "FC", "FB", "DB", "SFC", "SFB", "UDT"];

/// Operations that open a bracket: `U(` and friends, also written `U (`.
const BRACKET_OPS: &[&str] = &["U", "UN", "O", "ON", "X", "XN", "A", "AN"];

fn is_area(word: &str) -> bool {
    // Areas are 1 to 3 ASCII letters; most names are longer, so check the length first.
    word.len() <= 3 && AREAS.iter().any(|a| a.eq_ignore_ascii_case(word))
}

/// Is `word` the one-letter identifier `letter` (either case)? Cheaper than `at_word`.
fn is_letter(word: &str, letter: u8) -> bool {
    word.len() == 1 && word.as_bytes()[0].eq_ignore_ascii_case(&letter)
}

/// `word` = area letters followed by digits (`E1`, `MW10`, `DBX5`)?
fn is_area_with_number(word: &str) -> bool {
    let split = word
        .find(|c: char| c.is_ascii_digit())
        .unwrap_or(word.len());
    let (area, digits) = word.split_at(split);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) && is_area(area)
}

fn is_db_name(word: &str) -> bool {
    word.len() > 2
        && word.as_bytes()[..2].eq_ignore_ascii_case(b"DB")
        && word.as_bytes()[2..].iter().all(|b| b.is_ascii_digit())
}

/// `DBX`, `DBB`, `DBW`, `DBD`, optionally followed by digits.
fn is_db_access(word: &str) -> bool {
    word.len() >= 3
        && word.is_char_boundary(3)
        && ["DBX", "DBB", "DBW", "DBD"]
            .iter()
            .any(|a| a.eq_ignore_ascii_case(&word[..3]))
        && word[3..].bytes().all(|b| b.is_ascii_digit())
}

fn is_integer(text: &str) -> bool {
    !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit())
}

/// Does the check of the constant token `text` (`validation`) report nothing?
fn constant_is_valid(kind: SyntaxKind, text: &str) -> bool {
    let mut errors = Vec::new();
    let range = rowan::TextRange::empty(0.into());
    if kind == NUMBER {
        crate::validation::check_number(text, range, &mut errors);
    } else {
        crate::validation::check_constant_token(kind, text, range, &mut errors);
    }
    errors.is_empty()
}

/// `P#` and what may be an area with nothing after it (`P#M`, `P#DBX`, `P#DB10.DBX`; also
/// `P#MW`, which the check of the whole constant then reports): a pointer written with a
/// space after the area once a number follows.
fn is_pointer_area(text: &str) -> bool {
    text.len() > 2
        && text.as_bytes()[..2].eq_ignore_ascii_case(b"P#")
        && text.ends_with(|c: char| c.is_ascii_alphabetic())
}

/// Word flags: what the grammar asks about a token's text, worked out once per distinct
/// token when it is lexed ([`word_flags`]) and tested with [`Parser::nth_has`]. The
/// identifier flags are set only on `IDENT` tokens, the number flags only on `NUMBER` tokens.
pub(crate) mod word {
    /// An address area ([`super::AREAS`]): `E`, `MW`, `DBX`, `FC`, ...
    pub(crate) const AREA: u16 = 1 << 0;
    /// An area that names blocks ([`super::BLOCK_AREAS`]).
    pub(crate) const BLOCK_AREA: u16 = 1 << 1;
    /// An operation that opens a bracket ([`super::BRACKET_OPS`]).
    pub(crate) const BRACKET_OP: u16 = 1 << 2;
    /// `CALL` or `CC`.
    pub(crate) const CALL: u16 = 1 << 3;
    /// A word that forms an operation with punctuation written against it: `RND` (`RND+`,
    /// `RND-`), `MCR` (`MCR(`, `)MCR`), `AR1` and `AR2` (`+AR1`, `+AR2`).
    pub(crate) const JOINED_OP: u16 = 1 << 4;
    /// `TRUE` or `FALSE`.
    pub(crate) const BOOL: u16 = 1 << 5;
    /// `C` (the `C-:` label).
    pub(crate) const LETTER_C: u16 = 1 << 6;
    /// `E`, `C` or `X` (the `E:`, `C:`, `X:` labels).
    pub(crate) const LABEL_LETTER: u16 = 1 << 7;
    /// `I`, `D` or `R` (the type of a comparison).
    pub(crate) const CMP_TYPE: u16 = 1 << 8;
    /// Area letters followed by digits: `E1`, `MW10`.
    pub(crate) const AREA_WITH_NUMBER: u16 = 1 << 9;
    /// `DB` followed by digits: `DB10`.
    pub(crate) const DB_NAME: u16 = 1 << 10;
    /// `DBX`, `DBB`, `DBW`, `DBD`, optionally followed by digits.
    pub(crate) const DB_ACCESS: u16 = 1 << 11;
    /// A number of digits only.
    pub(crate) const INTEGER: u16 = 1 << 12;
    /// The number `0`.
    pub(crate) const ZERO: u16 = 1 << 13;
    /// A number, typed constant or character constant whose check (HG0006/HG0007) reports
    /// nothing: most constants repeat, so each distinct one is checked once.
    pub(crate) const VALID_CONSTANT: u16 = 1 << 14;
    /// A typed constant `P#` + letters (`P#M`, `P#DBX`, `P#DB10.DBX`): the first part of a
    /// pointer written with a space after the area (`P#M 100.0`).
    pub(crate) const POINTER_AREA: u16 = 1 << 15;
}

/// The [`word`] flags of a token.
pub(crate) fn word_flags(kind: SyntaxKind, text: &str) -> u16 {
    let flag = |condition: bool, flag: u16| if condition { flag } else { 0 };
    match kind {
        IDENT => {
            let is_any = |words: &[&str]| words.iter().any(|w| w.eq_ignore_ascii_case(text));
            flag(is_area(text), word::AREA)
                | flag(is_any(BLOCK_AREAS), word::BLOCK_AREA)
                | flag(is_any(BRACKET_OPS), word::BRACKET_OP)
                | flag(is_any(&["CALL", "CC"]), word::CALL)
                | flag(is_any(&["RND", "MCR", "AR1", "AR2"]), word::JOINED_OP)
                | flag(is_any(&["TRUE", "FALSE"]), word::BOOL)
                | flag(is_letter(text, b'C'), word::LETTER_C)
                | flag(is_any(&["E", "C", "X"]), word::LABEL_LETTER)
                | flag(is_any(&["I", "D", "R"]), word::CMP_TYPE)
                | flag(is_area_with_number(text), word::AREA_WITH_NUMBER)
                | flag(is_db_name(text), word::DB_NAME)
                | flag(is_db_access(text), word::DB_ACCESS)
        }
        NUMBER => {
            flag(is_integer(text), word::INTEGER)
                | flag(text == "0", word::ZERO)
                | flag(constant_is_valid(kind, text), word::VALID_CONSTANT)
        }
        TYPED_CONST => {
            flag(constant_is_valid(kind, text), word::VALID_CONSTANT)
                | flag(is_pointer_area(text), word::POINTER_AREA)
        }
        CHAR => flag(constant_is_valid(kind, text), word::VALID_CONSTANT),
        _ => 0,
    }
}

/// `I`, `D` or `R` as a whole identifier at `n` joined to the previous token.
fn nth_is_cmp_type(p: &Parser<'_>, n: usize) -> bool {
    p.nth_joined(n) && p.nth_has(n, word::CMP_TYPE)
}

/// Number of tokens of an STL comparison at the current position (`==I <>I >I <I >=I <=I`
/// and the same with `D` and `R`), or 0.
pub(crate) fn comparison_len(p: &Parser<'_>) -> usize {
    let second_joined = |kind| p.nth(1) == kind && p.nth_joined(1);
    match p.current() {
        EQ if second_joined(EQ) && nth_is_cmp_type(p, 2) => 3,
        L_ANGLE if (second_joined(R_ANGLE) || second_joined(EQ)) && nth_is_cmp_type(p, 2) => 3,
        R_ANGLE if second_joined(EQ) && nth_is_cmp_type(p, 2) => 3,
        L_ANGLE | R_ANGLE if nth_is_cmp_type(p, 1) => 2,
        _ => 0,
    }
}

/// Number of tokens of a block label at the current position (`E:` `C-:` `C:` `X:` `?:`
/// `!:`), or 0. Labels are formed only at statement start inside instruction bodies; the
/// callers guarantee that.
fn label_len(p: &Parser<'_>) -> usize {
    let colon_at = |n: usize| p.nth(n) == COLON && p.nth_joined(n);
    // The token after the first decides most cases; the text is looked at last.
    match (p.current(), p.nth(1)) {
        (IDENT, MINUS) if p.nth_joined(1) && colon_at(2) && p.nth_has(0, word::LETTER_C) => 3,
        (IDENT, COLON) if colon_at(1) && p.nth_has(0, word::LABEL_LETTER) => 2,
        (QUESTION | BANG, _) if colon_at(1) => 2,
        _ => 0,
    }
}

pub(crate) fn at_label(p: &Parser<'_>) -> bool {
    label_len(p) > 0
}

/// `NAME:` (not `NAME:=`) at statement start that is not a block label: a jump label.
fn at_jump_label(p: &Parser<'_>) -> bool {
    p.at(IDENT)
        && p.nth(1) == COLON
        && p.nth_joined(1)
        && !(p.nth(2) == EQ && p.nth_joined(2))
        && label_len(p) == 0
}

/// Number of tokens of the opcode at the current position, or 0 if no statement starts here.
fn opcode_len(p: &Parser<'_>) -> usize {
    let cmp = comparison_len(p);
    if cmp > 0 {
        return cmp;
    }
    match p.current() {
        IDENT => {
            let bracket =
                p.nth(1) == L_PAREN && !p.nth_on_new_line(1) && p.nth_has(0, word::BRACKET_OP);
            // `RND+`, `RND-`, `MCR(` (HG4003).
            let joined = matches!(p.nth(1), PLUS | MINUS | L_PAREN)
                && p.nth_joined(1)
                && p.nth_has(0, word::JOINED_OP);
            if bracket || joined { 2 } else { 1 }
        }
        // `)MCR`, `+AR1`, `+AR2` (HG4003).
        R_PAREN | PLUS if p.nth_joined(1) && p.nth_has(1, word::JOINED_OP) => 2,
        R_PAREN | EQ => 1,
        PLUS if nth_is_cmp_type(p, 1) => 2,
        PLUS => 1,
        MINUS | STAR | SLASH if nth_is_cmp_type(p, 1) => 2,
        _ => 0,
    }
}

/// Can an STL statement start here?
pub(crate) fn at_stmt_start(p: &Parser<'_>) -> bool {
    p.at(SEMI) || opcode_len(p) > 0
}

/// The body of a state, transition or `permanent`: labelled blocks of statements, `wait` and
/// `supervise` items, and statements before the first label (an unlabelled block).
pub(crate) fn instruction_body(p: &mut Parser<'_>, construct: &dyn fmt::Display) {
    p.start(BODY);
    let Some(open) = p.expect_open(construct) else {
        p.finish_node();
        return;
    };
    let mut in_block = false;
    loop {
        let closes = comparison_len(p) == 0
            && (p.at(R_ANGLE)
                || p.at_eof()
                || p.at_item_start()
                || p.at_member_start(Scope::Graph));
        if closes {
            // Close the open block first so that the `>` belongs to the body.
            if in_block {
                p.finish_node();
            }
            p.body_ends(open, construct, &[Scope::Graph]);
            break;
        }
        let label = label_len(p);
        if label > 0 {
            if in_block {
                p.finish_node();
            }
            p.start(BLOCK);
            p.bump_node(LABEL, label);
            in_block = true;
        } else if p.at_kw(WAIT_KW) || p.at_kw(SUPERVISE_KW) {
            if in_block {
                p.finish_node();
                in_block = false;
            }
            time_item(p);
        } else {
            if !in_block {
                p.start(BLOCK);
                in_block = true;
            }
            if at_stmt_start(p) || at_jump_label(p) {
                stl_stmt(p);
            } else {
                p.error_and_recover("an STL statement, a label or '>'");
            }
        }
    }
    p.finish_node();
}

/// `wait T#2S;` / `supervise T#10S;`
fn time_item(p: &mut Parser<'_>) {
    let is_wait = p.at_kw(WAIT_KW);
    p.start(if is_wait { WAIT_ITEM } else { SUPERVISE_ITEM });
    let word = p.nth_text(0);
    p.bump_keyword();
    let recoveries = p.recoveries();
    // The value may begin on a later line: the line rule of language.md §1.3 is for STL
    // operands only.
    if !operand(p) {
        p.error_and_recover("a time constant or operand");
    } else if p.recoveries() == recoveries {
        let element = lazy(|f| write!(f, "the '{}' item", word.to_ascii_lowercase()));
        p.expect_semi(&element, |p| {
            at_stmt_start(p) || p.at_kw(WAIT_KW) || p.at_kw(SUPERVISE_KW)
        });
    }
    p.finish_node();
}

/// One STL statement: `[label:] [opcode [operand | call args]] ;`
pub(crate) fn stl_stmt(p: &mut Parser<'_>) {
    p.start(STL_STMT);
    if at_jump_label(p) {
        p.bump_node(JUMP_LABEL, 2);
    }
    if p.at(SEMI) {
        p.bump();
        p.finish_node();
        return;
    }
    let n = opcode_len(p);
    if n == 0 {
        p.error_and_recover("an STL operation");
        p.finish_node();
        return;
    }
    // An opcode has at most three tokens (`==I`); they are shown without the space between.
    let op = [p.nth_text(0), p.nth_text(1), p.nth_text(2)];
    let is_call = p.nth_has(0, word::CALL);
    let op = &op[..n];
    p.bump_node(OPCODE, n);
    let element = lazy(|f| write!(f, "'{}'", op.concat()));
    // A label after the operation is never its operand (diagnostics.md HG0002).
    let operand_follows = !p.nth_on_new_line(0) && !p.at(SEMI) && !at_label(p) && !at_jump_label(p);
    if operand_follows {
        let recoveries = p.recoveries();
        if n == 1 && is_call {
            call_args(p);
        } else {
            // No operand is fine here; `expect_semi` reports a token that cannot follow.
            operand(p);
        }
        if p.recoveries() > recoveries {
            // The arguments reported and recovered already.
            p.finish_node();
            return;
        }
    }
    p.expect_semi(&element, |p| at_stmt_start(p) || at_jump_label(p));
    p.finish_node();
}

/// `FC 10 [, DB 10] [( P := x, ... )]`. Errors are reported and recovered here. The
/// parameter list may open on a later line: only the target is held to the operation's line
/// (language.md §1.3), and no statement begins with `(`.
fn call_args(p: &mut Parser<'_>) {
    p.start(CALL_ARGS);
    if at_indirect(p) {
        // `CC FC [MW 50]`: an indirect call (HG4004).
        indirect(p);
        p.finish_node();
        return;
    }
    if !block_ref(p) {
        p.error_and_recover("a block to call");
        p.finish_node();
        return;
    }
    if p.at(COMMA) && !p.nth_on_new_line(0) {
        p.bump();
        if !block_ref(p) {
            p.error_and_recover("an instance data block");
            p.finish_node();
            return;
        }
    }
    if p.at(L_PAREN) {
        p.start(PARAM_LIST);
        p.bump();
        loop {
            if p.at(R_PAREN) {
                p.bump();
                break;
            }
            if p.at(IDENT) && p.nth(1) == COLON && p.nth(2) == EQ && p.nth_joined(2) {
                p.start(PARAM);
                p.bump_node(NAME_REF, 1);
                p.bump_node(ASSIGN_OP, 2);
                let recoveries = p.recoveries();
                let ok = operand(p);
                p.finish_node();
                if p.recoveries() > recoveries {
                    break;
                }
                if !ok {
                    p.error_and_recover("an actual parameter");
                    break;
                }
                if p.at(COMMA) {
                    p.bump();
                } else if !p.at(R_PAREN) {
                    p.error_and_recover("',' or ')'");
                    break;
                }
            } else {
                p.error_and_recover("a parameter 'NAME := value' or ')'");
                break;
            }
        }
        p.finish_node();
    }
    p.finish_node();
}

/// Text of the block reference at the current position, for messages.
pub(crate) fn block_ref_text(p: &Parser<'_>) -> String {
    let word = p.nth_text(0);
    if p.nth_has(0, word::BLOCK_AREA) && p.nth(1) == NUMBER && !p.nth_on_new_line(1) {
        format!("{word} {}", p.nth_text(1))
    } else {
        word.to_owned()
    }
}

/// `FC 10`, `FC10`, `Name`, `"Name"`.
pub(crate) fn block_ref(p: &mut Parser<'_>) -> bool {
    match p.current() {
        IDENT => {
            p.start(BLOCK_REF);
            if p.nth_has(0, word::BLOCK_AREA) && p.nth(1) == NUMBER && !p.nth_on_new_line(1) {
                p.bump_node(ADDRESS, 2);
            } else {
                p.bump_node(NAME_REF, 1);
            }
            p.finish_node();
            true
        }
        STRING => {
            p.start(BLOCK_REF);
            p.bump_node(SYMBOL_REF, 1);
            p.finish_node();
            true
        }
        _ => false,
    }
}

/// Number of tokens of an absolute address at the current position, or 0. `spelled_together`
/// also accepts a lone identifier (`MW10`) — used in symbol tables, where an identifier in
/// address position can only be an address.
fn address_len(p: &Parser<'_>) -> usize {
    if p.current() != IDENT {
        return 0;
    }
    // DB10.DBX 5.1, DB10.DBW4, DB10.DBX5.1
    if p.nth(1) == DOT
        && p.nth_joined(1)
        && p.nth_joined(2)
        && p.nth_has(0, word::DB_NAME)
        && p.nth_has(2, word::DB_ACCESS)
    {
        if p.nth_text(2).len() == 3 {
            return if p.nth(3) == NUMBER && !p.nth_on_new_line(3) {
                4
            } else {
                3
            };
        }
        if p.nth(3) == DOT && p.nth_joined(3) && p.nth(4) == NUMBER && p.nth_joined(4) {
            return 5;
        }
        return 3;
    }
    // E 1.0, MW 10, T 5, FC 10
    if p.nth(1) == NUMBER && !p.nth_on_new_line(1) && p.nth_has(0, word::AREA) {
        return 2;
    }
    // E1.0, M10.7
    if p.nth(1) == DOT
        && p.nth_joined(1)
        && p.nth_joined(2)
        && p.nth_has(2, word::INTEGER)
        && p.nth_has(0, word::AREA_WITH_NUMBER)
    {
        return 3;
    }
    0
}

/// `DB10.DBX ...` at the current position — always a data-block address (language.md §3.5).
pub(crate) fn at_db_address(p: &Parser<'_>) -> bool {
    p.nth_has(0, word::DB_NAME)
        && p.nth(1) == DOT
        && p.nth_joined(1)
        && p.nth_joined(2)
        && p.nth_has(2, word::DB_ACCESS)
}

/// An absolute address (ADDRESS node) if one starts here.
pub(crate) fn address(p: &mut Parser<'_>) -> bool {
    let n = address_len(p);
    if n > 0 {
        p.bump_node(ADDRESS, n);
    }
    n > 0
}

/// An address in a symbol table: any address form, or a lone identifier (`MW10`, `FC1`).
pub(crate) fn address_in_table(p: &mut Parser<'_>) -> bool {
    let n = address_len(p);
    if n > 0 {
        p.bump_node(ADDRESS, n);
        true
    } else if p.at(IDENT) {
        p.bump_node(ADDRESS, 1);
        true
    } else {
        false
    }
}

/// `P#M 100.0`: a pointer written with white space after its area (language.md §3.5) — the
/// typed constant `P#M` and a number on its line with only spaces or tabs between.
fn at_spaced_pointer(p: &Parser<'_>) -> bool {
    p.nth_has(0, word::POINTER_AREA)
        && p.nth(1) == NUMBER
        && !p.nth_on_new_line(1)
        && p.text_between(0, 1)
            .bytes()
            .skip(p.nth_text(0).len())
            .take_while(|b| !b.is_ascii_digit())
            .all(|b| b == b' ' || b == b'\t')
}

/// Number of tokens of a constant at the current position, or 0.
pub(crate) fn literal_len(p: &Parser<'_>) -> usize {
    match p.current() {
        TYPED_CONST if at_spaced_pointer(p) => 2,
        NUMBER | TYPED_CONST | CHAR => 1,
        MINUS if p.nth(1) == NUMBER && p.nth_joined(1) => 2,
        IDENT if p.nth_has(0, word::BOOL) => 1,
        _ => 0,
    }
}

/// A constant (LITERAL node). Numbers are checked here (HG0007); typed and character
/// constants are checked as tokens wherever they stand.
pub(crate) fn literal(p: &mut Parser<'_>) -> bool {
    let n = literal_len(p);
    if n == 0 {
        return false;
    }
    if n == 2 && p.at(TYPED_CONST) {
        // `P#M 100.0`: checked as one constant.
        let text = p.text_between(0, 1);
        let range = rowan::TextRange::new(p.nth_range(0).start(), p.nth_range(1).end());
        let mut errors = Vec::new();
        crate::validation::check_number(text, range, &mut errors);
        for error in errors {
            p.push_error(error);
        }
        p.bump_node_unchecked(LITERAL, 2);
        return true;
    }
    // A lone number is known to be valid or not (`word::VALID_CONSTANT`).
    let is_number = p.at(NUMBER) || p.at(MINUS);
    if is_number && !(n == 1 && p.nth_has(0, word::VALID_CONSTANT)) {
        let start = p.nth_range(0).start();
        let end = p.nth_range(n - 1).end();
        let negative;
        let text = if n == 1 {
            p.nth_text(0)
        } else {
            negative = format!("{}{}", p.nth_text(0), p.nth_text(1));
            &negative
        };
        let range = rowan::TextRange::new(start, end);
        let mut errors = Vec::new();
        crate::validation::check_number(text, range, &mut errors);
        for error in errors {
            p.push_error(error);
        }
    }
    p.bump_node(LITERAL, n);
    true
}

/// One STL operand (or a time value): an address, `#Name`, a name, `"symbol"`, a constant,
/// `[...]` (indirect, HG4004) or a status bit such as `==0` (HG4003). Returns `false` without
/// consuming anything if no operand starts here.
pub(crate) fn operand(p: &mut Parser<'_>) -> bool {
    let n = address_len(p);
    if n > 0 {
        p.bump_node(ADDRESS, n);
        return true;
    }
    if literal(p) {
        return true;
    }
    if at_indirect(p) {
        indirect(p);
        return true;
    }
    match p.current() {
        HASH if p.nth(1) == IDENT && p.nth_joined(1) => p.bump_node(VAR_REF, 2),
        STRING => p.bump_node(SYMBOL_REF, 1),
        IDENT => p.bump_node(NAME_REF, 1),
        EQ | L_ANGLE | R_ANGLE => {
            let n = status_len(p);
            if n == 0 {
                return false;
            }
            p.bump_node(STATUS_OPERAND, n);
        }
        _ => return false,
    }
    true
}

/// `==0 <>0 >0 <0 >=0 <=0` written without spaces.
fn status_len(p: &Parser<'_>) -> usize {
    let zero_at = |n: usize| p.nth_has(n, word::ZERO) && p.nth_joined(n);
    let joined = |n: usize, kind| p.nth(n) == kind && p.nth_joined(n);
    match p.current() {
        EQ if joined(1, EQ) && zero_at(2) => 3,
        L_ANGLE if joined(1, R_ANGLE) && zero_at(2) => 3,
        L_ANGLE | R_ANGLE if joined(1, EQ) && zero_at(2) => 3,
        L_ANGLE | R_ANGLE if zero_at(1) => 2,
        _ => 0,
    }
}

/// `[...]`, or an area or a size letter (`B`, `W`, `D`) and `[...]` on its line: `MW [MD 10]`,
/// `E [AR1, P#0.0]`, `W [AR1,P#2.0]`, `B[AR1,P#0.0]`, `FC [MW 50]` — memory- and
/// register-indirect operands (HG4004; diagnostics.md §2.8).
fn at_indirect(p: &Parser<'_>) -> bool {
    match p.current() {
        L_BRACK => true,
        // The text is looked at only before a `[`, which is rare.
        IDENT if p.nth(1) == L_BRACK && !p.nth_on_new_line(1) => {
            p.nth_has(0, word::AREA)
                || matches!(
                    p.nth_text(0).as_bytes(),
                    [b'B' | b'W' | b'D' | b'b' | b'w' | b'd']
                )
        }
        _ => false,
    }
}

/// `[ ... ]`, optionally after an area (`MW [MD 10]`) — everything up to the matching `]` on
/// the statement.
fn indirect(p: &mut Parser<'_>) {
    p.start(INDIRECT);
    if p.at(IDENT) {
        p.bump();
    }
    p.bump();
    while !p.at_eof() && !p.at(R_BRACK) && !p.at(SEMI) && !p.at(R_ANGLE) {
        p.bump();
    }
    if p.at(R_BRACK) {
        p.bump();
    } else {
        p.error_and_recover("']'");
    }
    p.finish_node();
}

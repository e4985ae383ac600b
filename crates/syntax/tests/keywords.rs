//! Keywords are contextual (language.md §7): every keyword of the language may be a name.
//!
//! Generated test: every keyword (`SyntaxKind::KEYWORDS`) is put in every position where the
//! grammar takes a NAME; the program must parse without a diagnostic, and the keyword must
//! stand as an identifier in the node that holds a name at that position.
//!
//! A template marks each name position with the kind of node that holds the name there
//! (`{NAME}`, `{NAME_REF}`, ...).

use higraph_syntax::{SyntaxKind, TextSize, parse};

/// Positions in which every keyword is a name.
const EVERYWHERE: &[&str] = &[
    // Graph names and variables, as in the example of the issue (one line).
    "graph {NAME} < in < {NAME} : BOOL; > state 0 < > trans any->0 prio 1 < U INIT_SD; > >",
    "graph {NAME} \"c\" <\n  state 0 < >\n  trans any->0 prio 1 < U INIT_SD; >\n>\n",
    "graph G <\n  in < {NAME} : BOOL; Go : BOOL; >\n  out < {NAME} : BOOL; >\n  state 0 < >\n>\n",
    "graph G <\n  in_out < {NAME} : BOOL msg in; {NAME} : BOOL msg out; >\n  stat < {NAME} : INT := 1 \"c\"; >\n  state 0 < >\n>\n",
    "graph G < stat < {NAME} : BOOL; {NAME} : INT; > in < {NAME} : BOOL; > activate CurrentState; >",
    // Any name in a type position (HG1215).
    "graph G <\n  in < X : {TYPE_REF}; Y : {TYPE_REF} := 1; >\n>\n",
    "graph G < activate {NAME_REF}, {NAME_REF}; state 0 < > >",
    // STL operands in states, transitions and permanent instructions.
    "graph G <\n  state 0 < E: S {NAME_REF}; C: U {NAME_REF}; = {NAME_REF}; L #{VAR_REF}; X: R {NAME_REF}; >\n  trans 0->1 < U {NAME_REF}; UN {NAME_REF}; !: S {NAME_REF}; >\n  permanent < C-: U {NAME_REF}; C: = {NAME_REF}; >\n>\n",
    "graph G < state 0 < C: U {NAME_REF}; > trans 0->1 prio 1 < U {NAME_REF}; > state 1 < C: T {NAME_REF}; > >",
    "graph G < state 0 < supervise {NAME_REF}; wait {NAME_REF}; C: U X; > >",
    "graph G <\n  state 0 <\n    C: CALL {NAME_REF}, {NAME_REF} ({NAME_REF} := {NAME_REF}, P := #{VAR_REF});\n    CALL FC 1 (\n      {NAME_REF} := {NAME_REF});\n  >\n>\n",
    // Groups: names, fc/db, options, instances, formals, actuals, message targets.
    "group {NAME} fc {NAME_REF} db {NAME_REF} \"c\" <\n  option {NAME} 5;\n  option {NAME};\n  instance {NAME} : {NAME_REF} \"c\" <\n    {NAME_REF} := {NAME_REF};\n    {NAME_REF} := {NAME_REF}.{NAME_REF};\n    {NAME_REF} := E 0.0;\n  >\n  instance B : G < {NAME_REF} := {NAME_REF}; >\n>\n",
    "group G < instance {NAME} : {NAME_REF} < {NAME_REF} := {NAME_REF}.{NAME_REF}; {NAME_REF} := #{VAR_REF}; > instance C : G < > >",
    // Symbols and block interfaces.
    "symbols <\n  {NAME} : M 0.0 BOOL \"c\";\n  X : M 0.1 {TYPE_REF};\n  {NAME} : MW 2;\n>\n",
    "symbols < {NAME} : M 0.0; Y : FC 1; >",
    "block {NAME_REF} \"c\" <\n  in < {NAME} : INT; >\n  out < {NAME} : BOOL; >\n>\n",
    // Charts: names, variables, sequencers, elements and jump/loop targets.
    "chart {NAME} \"c\" <\n  in < {NAME} : BOOL; >\n  out < {NAME} : BOOL; >\n  sequencer {NAME} prio 1 <\n    step {NAME} \"c\" < >\n    trans {NAME} \"c\" < >\n    jump {NAME} -> {NAME_REF} < >\n    step B < >\n    loop {NAME} -> {NAME_REF} < >\n    parallel < branch < step {NAME} < > > branch < step X < > > >\n    alt < branch < trans {NAME} < > > branch < trans Y < > > >\n  >\n  sequencer {NAME} < step A < > >\n>\n",
    "chart type {NAME} < in < {NAME} : BOOL; > >",
    "chart {NAME} < sequencer {NAME} < step {NAME} < > trans {NAME} < > step B < > > >",
    // Tests: names, run lists, commands (the positions outside expressions).
    "test {NAME} \"c\" <\n  run {NAME_REF}, {NAME_REF};\n  command {NAME_REF} {NAME_REF};\n>\n",
    "graph G < state 0 < > > test {NAME} < run {NAME_REF}; step; >",
];

/// Positions inside chart expressions. `and`, `or`, `xor` and `not` are the operators there
/// (and reserved words, language.md §7), so they are left out.
const CHART_EXPRESSIONS: &[&str] = &[
    "chart C <\n  run {NAME_REF};\n  sequencer S <\n    start < {NAME_REF}; >\n    pre < {NAME_REF} := {NAME_REF}; >\n    post < {NAME_REF}.{NAME_REF} := 1; >\n    step A <\n      init < {NAME_REF}.{NAME_REF} := {NAME_REF}; >\n      run < {NAME_REF} := 1; >\n      N {NAME_REF};\n      L {NAME_REF}, {NAME_REF};\n      max {NAME_REF};\n    >\n    trans T1 < {NAME_REF} and not {NAME_REF} or {NAME_REF} >= 1 xor {NAME_REF} = {NAME_REF}; >\n    trans T2 < ({NAME_REF}); {NAME_REF} > {NAME_REF}; {NAME_REF} <> 2; >\n    step B < >\n  >\n>\n",
    "chart C < sequencer S < step A < > trans T < {NAME_REF} and {NAME_REF}; > step B < > > >",
    // Test paths and expressions.
    "test T <\n  set {NAME_REF}.{NAME_REF} := {NAME_REF};\n  set \"s\".{NAME_REF} := not {NAME_REF};\n  expect {NAME_REF} = {NAME_REF} \"m\";\n  until {NAME_REF}.{NAME_REF} within T#1S;\n  confirm {NAME_REF}.{NAME_REF}.{NAME_REF};\n  expect ({NAME_REF} or {NAME_REF}) and {NAME_REF} > 1;\n>\n",
];

/// Positions in IEC statements (docs/iec.md §5): actions, conditions of `IF`, selectors of
/// `CASE`, calls. Besides the operators, `IF` and `CASE` are left out: at statement start they
/// begin their statement unless `:=` or `.` follows, so `If(...)` is no call.
const IEC_STATEMENTS: &[&str] = &[
    "chart C <\n  profile iec;\n  action {NAME} \"c\" < {NAME_REF} := -{NAME_REF} * 2 MOD {NAME_REF}; >\n  sequencer S <\n    step A <\n      run <\n        IF {NAME_REF} THEN {NAME_REF}.{NAME_REF} := 1;\n        ELSIF {NAME_REF} + 1 > {NAME_REF} THEN {NAME_REF} := {NAME_REF};\n        ELSE {NAME_REF} := 2; END_IF;\n        CASE {NAME_REF} OF 1, 2..3: {NAME_REF} := 2; ELSE {NAME_REF}.{NAME_REF} := 3; END_CASE;\n      >\n      P1 {NAME_REF};\n      DL {NAME_REF}, T#1S;\n    >\n  >\n>\n",
];

/// The callee of a call: a statement keyword followed by `(` begins its statement.
const IEC_CALLS: &[&str] = &[
    "chart C < action A <\n  {NAME_REF}({NAME_REF} := {NAME_REF} - 1, {NAME_REF} => {NAME_REF}.{NAME_REF});\n  X(); > >",
];

/// Jump labels (`NAME:` at statement start, parsed so that HG4003 can report them). `wait`
/// and `supervise` at statement start always begin a state item (language.md §1.4).
const JUMP_LABELS: &[&str] = &["graph G < state 0 < C: {JUMP_LABEL}: U X; > >"];

/// A template with its name positions replaced by `word`: the text and each name's offset
/// with the kind of node expected to hold it.
fn instantiate(template: &str, word: &str) -> (String, Vec<(TextSize, String)>) {
    let mut text = String::new();
    let mut names = Vec::new();
    let mut rest = template;
    while let Some(open) = rest.find('{') {
        let close = rest[open..].find('}').expect("unclosed marker") + open;
        text.push_str(&rest[..open]);
        names.push((
            TextSize::new(text.len() as u32),
            rest[open + 1..close].to_owned(),
        ));
        text.push_str(word);
        rest = &rest[close + 1..];
    }
    text.push_str(rest);
    (text, names)
}

fn check(template: &str, word: &str) -> Result<(), String> {
    let (text, names) = instantiate(template, word);
    let parse = parse(&text);
    if !parse.errors().is_empty() {
        return Err(format!("{text}\n{:#?}", parse.errors()));
    }
    let root = parse.syntax_node();
    for (offset, expected) in names {
        let token = root
            .token_at_offset(offset)
            .right_biased()
            .ok_or_else(|| format!("{text}\nno token at {offset:?}"))?;
        let parent = token.parent().map(|p| format!("{:?}", p.kind()));
        if token.kind() != SyntaxKind::IDENT
            || token.text() != word
            || parent.as_deref() != Some(expected.as_str())
        {
            return Err(format!(
                "{text}\nat {offset:?}: {:?} {:?} in {parent:?}, expected IDENT in {expected}\n{}",
                token.kind(),
                token.text(),
                parse.debug_tree()
            ));
        }
    }
    Ok(())
}

fn check_all(templates: &[&str], skip: &[SyntaxKind]) {
    let mut failures = Vec::new();
    for &(word, kind) in SyntaxKind::KEYWORDS.iter() {
        if skip.contains(&kind) {
            continue;
        }
        // Keywords are case-insensitive: try the word as the keyword list spells it and
        // capitalised.
        let capitalised = format!("{}{}", word[..1].to_uppercase(), &word[1..]);
        for spelling in [word, capitalised.as_str()] {
            for (i, template) in templates.iter().enumerate() {
                if let Err(message) = check(template, spelling) {
                    failures.push((format!("'{spelling}' in template {i}"), message));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures: {}; the first:\n{}",
        failures.len(),
        failures
            .iter()
            .map(|(at, _)| at.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        failures[0].1
    );
}

#[test]
fn every_keyword_is_a_name_in_every_name_position() {
    check_all(EVERYWHERE, &[]);
}

#[test]
fn every_keyword_but_the_operators_is_a_name_in_chart_expressions() {
    use SyntaxKind::*;
    check_all(CHART_EXPRESSIONS, &[AND_KW, OR_KW, XOR_KW, NOT_KW]);
}

#[test]
fn every_keyword_but_the_operators_if_and_case_is_a_name_in_iec_statements() {
    use SyntaxKind::*;
    check_all(
        IEC_STATEMENTS,
        &[AND_KW, OR_KW, XOR_KW, NOT_KW, IF_KW, CASE_KW],
    );
    check_all(
        IEC_CALLS,
        &[
            AND_KW,
            OR_KW,
            XOR_KW,
            NOT_KW,
            IF_KW,
            CASE_KW,
            ELSIF_KW,
            ELSE_KW,
            END_IF_KW,
            END_CASE_KW,
        ],
    );
}

#[test]
fn every_keyword_but_wait_and_supervise_is_a_jump_label() {
    use SyntaxKind::*;
    check_all(JUMP_LABELS, &[WAIT_KW, SUPERVISE_KW]);
}

/// The test can fail: a keyword where the grammar takes it as a keyword is not a name.
#[test]
fn a_keyword_where_the_grammar_wants_it_is_no_name() {
    assert!(check("graph G < {NAME} 0 < > >", "state").is_err());
    assert!(check("graph G < state 0 < C: U X; > {NAME} 0 < > >", "state").is_err());
    assert!(check("test T < {NAME_REF} x; >", "expect").is_err());
    // `IF` begins a statement unless `:=` or `.` follows.
    assert!(check("chart C < action A < {NAME_REF}(X := 1); > >", "if").is_err());
    assert!(check("chart C < action A < {NAME_REF} := 1; > >", "if").is_ok());
}

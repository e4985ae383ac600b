//! Properties of the parser on arbitrary input: it never panics, the tree's text equals the
//! input, and every diagnostic range lies inside the input on character boundaries. Inputs are
//! random token soups and random mutations (tokens and bytes deleted, duplicated, swapped) of
//! every fixture and example file.

mod common;

use std::{fs, path::Path};

use common::{collect, corpus};
use higraph_syntax::{lexer::tokenize, parse};
use proptest::prelude::*;

fn check_invariants(text: &str) {
    let parse = parse(text);
    let root = parse.syntax_node();
    assert_eq!(root.to_string(), text, "lossless round trip");
    let len = text.len();
    for e in parse.errors() {
        let (start, end) = (usize::from(e.range.start()), usize::from(e.range.end()));
        assert!(
            start <= end && end <= len,
            "{e} out of bounds for {len} bytes"
        );
        assert!(
            text.is_char_boundary(start) && text.is_char_boundary(end),
            "{e}"
        );
        for r in &e.related {
            assert!(
                usize::from(r.range.end()) <= len,
                "{e}: related out of bounds"
            );
        }
    }
    // Every token is in exactly one place: token ranges tile the input.
    let mut offset = 0usize;
    for token in root
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
    {
        assert_eq!(usize::from(token.text_range().start()), offset);
        offset = usize::from(token.text_range().end());
    }
    assert_eq!(offset, len);
}

const VOCABULARY: &[&str] = &[
    "graph",
    "group",
    "chart",
    "symbols",
    "block",
    "mnemonic",
    "simatic",
    "state",
    "trans",
    "any",
    "return",
    "prio",
    "in",
    "out",
    "in_out",
    "stat",
    "msg",
    "activate",
    "permanent",
    "wait",
    "supervise",
    "instance",
    "option",
    "sequencer",
    "step",
    "parallel",
    "alt",
    "branch",
    "jump",
    "loop",
    "start",
    "init",
    "run",
    "term",
    "and",
    "or",
    "not",
    "profile",
    "action",
    "IF",
    "THEN",
    "ELSIF",
    "ELSE",
    "END_IF",
    "CASE",
    "OF",
    "END_CASE",
    "MOD",
    "P1",
    "DL",
    "=>",
    "..",
    "U",
    "UN",
    "O",
    "=",
    "S",
    "R",
    "L",
    "T",
    "CALL",
    "E",
    "C",
    "X",
    "E 1.0",
    "MW10",
    "DB10.DBX 5.1",
    "#Ab",
    "\"sym\"",
    "\"open",
    "'c'",
    "'open",
    "T#5S",
    "B#16#FF",
    "16#FF",
    "-5",
    "1.5e3",
    "<",
    ">",
    ";",
    ":",
    ":=",
    "->",
    ",",
    ".",
    "(",
    ")",
    "[",
    "]",
    "?:",
    "!:",
    "C-:",
    "E:",
    "==I",
    ">I",
    "+",
    "-",
    "*",
    "/",
    "#",
    "$",
    "ä",
    "😀",
    "\n",
    "\r\n",
    "\r",
    " ",
    "\t",
    "// c\n",
    "\u{FEFF}",
    "0",
    "12",
    "x",
    "Name",
];

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(VOCABULARY), 0..80).prop_map(|parts| {
        let mut text = String::new();
        for part in parts {
            text.push_str(part);
            text.push(' ');
        }
        text
    })
}

#[derive(Debug, Clone)]
enum Mutation {
    DeleteToken(usize),
    DuplicateToken(usize),
    SwapTokens(usize, usize),
    DeleteBytes(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::DeleteToken),
        any::<usize>().prop_map(Mutation::DuplicateToken),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapTokens(a, b)),
        (any::<usize>(), 1usize..4).prop_map(|(a, n)| Mutation::DeleteBytes(a, n)),
    ]
}

fn mutate(text: &str, mutation: &Mutation) -> String {
    let tokens: Vec<&str> = tokenize(text).into_iter().map(|t| t.text).collect();
    if tokens.is_empty() {
        return text.to_owned();
    }
    let n = tokens.len();
    let mut parts = tokens.clone();
    match *mutation {
        Mutation::DeleteToken(i) => {
            parts.remove(i % n);
        }
        Mutation::DuplicateToken(i) => parts.insert(i % n, tokens[i % n]),
        Mutation::SwapTokens(a, b) => parts.swap(a % n, b % n),
        Mutation::DeleteBytes(at, len) => {
            let mut bytes = text.as_bytes().to_vec();
            let start = at % bytes.len();
            let end = (start + len).min(bytes.len());
            bytes.drain(start..end);
            return String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    parts.concat()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_token_soup(text in token_soup()) {
        check_invariants(&text);
    }

    #[test]
    fn random_strings(text in "\\PC{0,200}") {
        check_invariants(&text);
    }

    #[test]
    fn mutated_fixtures(index in any::<usize>(), mutations in prop::collection::vec(mutation(), 1..6)) {
        let corpus = corpus();
        prop_assume!(!corpus.is_empty());
        let mut text = corpus[index % corpus.len()].clone();
        for m in &mutations {
            text = mutate(&text, m);
        }
        check_invariants(&text);
    }
}

#[test]
fn every_fixture_round_trips() {
    let corpus = corpus();
    assert!(corpus.len() > 20, "corpus too small: {}", corpus.len());
    for text in &corpus {
        check_invariants(text);
    }
}

/// The bundled examples are valid: no syntax diagnostic at all.
#[test]
fn examples_parse_without_diagnostics() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    collect(&root, &mut files);
    assert!(files.len() >= 7, "examples missing: {files:?}");
    for path in files {
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let parse = parse(&text);
        assert!(
            parse.errors().is_empty(),
            "{}: {:?}",
            path.display(),
            parse.errors()
        );
    }
}

//! The nesting limit (HG0012) and the bound on listed syntax errors (HG0013), on inputs far past
//! them, on the test thread's 2 MiB stack: the parser reports the first construct that nests
//! too deep once, keeps the tree lossless and no deeper than the limit allows, and lists at
//! most `MAX_SYNTAX_ERRORS` errors.

use higraph_syntax::{
    ErrorCode, MAX_SYNTAX_ERRORS, NESTING_LIMIT, Parse, SyntaxNode, WalkEvent, parse,
};

fn chart(elements: &str, condition: &str) -> String {
    format!(
        "chart C < sequencer S < step A < > {elements} trans T < {condition}; > step B < > > >\n"
    )
}

fn action(statements: &str) -> String {
    format!("chart C < action A < {statements} > sequencer S < step A < > > >\n")
}

/// The depth of the deepest node or token (the root is 0), counted without recursion.
fn tree_depth(root: &SyntaxNode) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for event in root.preorder_with_tokens() {
        match event {
            WalkEvent::Enter(_) => {
                deepest = deepest.max(depth);
                depth += 1;
            }
            WalkEvent::Leave(_) => depth -= 1,
        }
    }
    deepest
}

fn count(parse: &Parse, code: ErrorCode) -> usize {
    parse.errors().iter().filter(|e| e.code == code).count()
}

/// Most tree levels a text may reach: four per nesting level (a `parallel`, its body, its
/// branch and the branch's body), plus the fixed levels of items, members and operands.
fn depth_bound() -> usize {
    4 * NESTING_LIMIT as usize + 32
}

fn check_deep(what: &str, text: &str, expected_hg0012: usize) {
    let parse = parse(text);
    let root = parse.syntax_node();
    assert_eq!(root.to_string(), text, "{what}: not lossless");
    assert_eq!(
        count(&parse, ErrorCode::HG0012),
        expected_hg0012,
        "{what}: {:?}",
        parse.errors()
    );
    let depth = tree_depth(&root);
    assert!(depth <= depth_bound(), "{what}: tree {depth} deep");
    // The printer of `higraph-lsp parse` indents by depth.
    assert!(!parse.debug_tree().is_empty());
}

#[test]
fn nesting_past_the_limit_is_reported_once_and_cut() {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(|| {
            let n = 20_000;
            check_deep(
                "parentheses",
                &chart("", &format!("{}x{}", "(".repeat(n), ")".repeat(n))),
                1,
            );
            check_deep("not", &chart("", &format!("{}x", "not ".repeat(40_000))), 1);
            // Test expressions are chart expressions with test paths.
            check_deep(
                "test parentheses",
                &format!(
                    "test T < expect {}x.y{} \"m\"; until {}E 0.1 within T#1S; >\n",
                    "(".repeat(n),
                    ")".repeat(n),
                    "not ".repeat(n)
                ),
                2,
            );
            check_deep(
                "or chain",
                &chart("", &format!("x{}", " or x".repeat(40_000))),
                1,
            );
            check_deep(
                "comparison chain",
                &chart("", &format!("x{}", " and x = x".repeat(20_000))),
                1,
            );
            // Arithmetic (docs/iec.md §4): unary minus, chains of `+`, `*`, `MOD`, mixed.
            check_deep(
                "unary minus",
                &chart("", &format!("{}x", "- ".repeat(40_000))),
                1,
            );
            check_deep(
                "minus not",
                &chart("", &format!("{}x", "-not ".repeat(20_000))),
                1,
            );
            check_deep(
                "plus chain",
                &chart("", &format!("x{}", " + x".repeat(40_000))),
                1,
            );
            check_deep(
                "minus chain",
                &chart("", &format!("x{}", "-1".repeat(40_000))),
                1,
            );
            check_deep(
                "mod chain",
                &chart("", &format!("x{}", " MOD x".repeat(40_000))),
                1,
            );
            check_deep(
                "mixed arithmetic",
                &chart("", &format!("x{}", " * x + -(x - x) / x".repeat(20_000))),
                1,
            );
            // Structured statements (docs/iec.md §5): nested IF and CASE, closed and unclosed.
            check_deep(
                "nested IF",
                &action(&format!(
                    "{}x := 1;{}",
                    "IF a THEN ".repeat(100_000),
                    " END_IF;".repeat(100_000)
                )),
                1,
            );
            let ifs = 20_000;
            check_deep(
                "nested ELSE IF",
                &action(&format!(
                    "{}x := 1;{}",
                    "IF a THEN y := 1; ELSE ".repeat(ifs),
                    " END_IF;".repeat(ifs)
                )),
                1,
            );
            check_deep(
                "nested CASE",
                &action(&format!(
                    "{}x := 1;{}",
                    "CASE a OF 1: ".repeat(ifs),
                    " END_CASE;".repeat(ifs)
                )),
                1,
            );
            let text = action(&"IF (a) THEN CASE - x OF 1..2: ".repeat(ifs));
            let unclosed = parse(&text);
            assert_eq!(unclosed.syntax_node().to_string(), text);
            assert!((1..=2).contains(&count(&unclosed, ErrorCode::HG0012)));
            assert!(tree_depth(&unclosed.syntax_node()) <= depth_bound());
            // An expression inside deep statements: the levels add up.
            check_deep(
                "expression in IFs",
                &action(&format!(
                    "{}x := {}1{};{}",
                    "IF a THEN ".repeat(200),
                    "(".repeat(100),
                    ")".repeat(100),
                    " END_IF;".repeat(200)
                )),
                1,
            );
            for keyword in ["parallel", "alt"] {
                let open = format!("{keyword} < branch < ").repeat(5_000);
                check_deep(
                    keyword,
                    &chart(&format!("{open}step Z < >{}", " > >".repeat(5_000)), "x"),
                    1,
                );
            }
            // Unbalanced: no `)` at all. The recovery after the cut may meet another
            // construct too deep (the `>` after the condition read as a comparison).
            let text = chart("", &"(not ".repeat(30_000));
            let parse = parse(&text);
            assert_eq!(parse.syntax_node().to_string(), text);
            assert!((1..=2).contains(&count(&parse, ErrorCode::HG0012)));
            assert!(tree_depth(&parse.syntax_node()) <= depth_bound());
            // Deep STL brackets are statements side by side, not nesting.
            let stl = format!(
                "graph G < state 0 < C: {}U E 0.0;{} > >",
                "U( ; ".repeat(20_000),
                " );".repeat(20_000)
            );
            check_deep("STL brackets", &stl, 0);
        })
        .expect("thread")
        .join()
        .expect("no panic");
}

#[test]
fn nesting_at_the_limit_is_accepted() {
    let n = NESTING_LIMIT as usize;
    check_deep(
        "parentheses",
        &chart("", &format!("{}x{}", "(".repeat(n), ")".repeat(n))),
        0,
    );
    check_deep("not", &chart("", &format!("{}x", "not ".repeat(n))), 0);
    check_deep("unary minus", &chart("", &format!("{}x", "-".repeat(n))), 0);
    check_deep(
        "or chain",
        &chart("", &format!("x{}", " or x".repeat(n))),
        0,
    );
    check_deep(
        "plus chain",
        &chart("", &format!("x{}", " + x".repeat(n))),
        0,
    );
    check_deep(
        "times chain",
        &chart("", &format!("x{}", " * x".repeat(n))),
        0,
    );
    check_deep(
        "nested IF",
        &action(&format!(
            "{}x := 1;{}",
            "IF a THEN ".repeat(n),
            " END_IF;".repeat(n)
        )),
        0,
    );
    check_deep(
        "nested IF",
        &action(&format!(
            "{}x := 1;{}",
            "IF a THEN ".repeat(n + 1),
            " END_IF;".repeat(n + 1)
        )),
        1,
    );
    let open = "alt < branch < ".repeat(n);
    check_deep(
        "alt",
        &chart(&format!("{open}trans U < x; >{}", " > >".repeat(n)), "x"),
        0,
    );
    // One more of each is too deep.
    check_deep(
        "parentheses",
        &chart("", &format!("{}x{}", "(".repeat(n + 1), ")".repeat(n + 1))),
        1,
    );
    check_deep("not", &chart("", &format!("{}x", "not ".repeat(n + 1))), 1);
    check_deep(
        "unary minus",
        &chart("", &format!("{}x", "-".repeat(n + 1))),
        1,
    );
    check_deep(
        "or chain",
        &chart("", &format!("x{}", " or x".repeat(n + 1))),
        1,
    );
    check_deep(
        "plus chain",
        &chart("", &format!("x{}", " + x".repeat(n + 1))),
        1,
    );
    check_deep(
        "times chain",
        &chart("", &format!("x{}", " * x".repeat(n + 1))),
        1,
    );
}

#[test]
fn syntax_errors_past_the_bound_are_summarised() {
    let text = ">".repeat(1 << 20);
    let parse = parse(&text);
    let errors = parse.errors();
    assert_eq!(errors.len(), MAX_SYNTAX_ERRORS + 1);
    assert!(
        errors[..MAX_SYNTAX_ERRORS]
            .iter()
            .all(|e| e.code == ErrorCode::HG0008)
    );
    let summary = &errors[MAX_SYNTAX_ERRORS];
    assert_eq!(summary.code, ErrorCode::HG0013);
    assert_eq!(usize::from(summary.range.start()), MAX_SYNTAX_ERRORS);
    assert_eq!(
        summary.message,
        format!(
            "{} more syntax errors in this file are not listed",
            (1 << 20) - MAX_SYNTAX_ERRORS
        )
    );
    // Exactly the bound: all listed.
    let parse = higraph_syntax::parse(&">".repeat(MAX_SYNTAX_ERRORS));
    assert_eq!(parse.errors().len(), MAX_SYNTAX_ERRORS);
    assert_eq!(count(&parse, ErrorCode::HG0013), 0);
}

#[test]
fn a_summarised_parse_is_reparsed_whole() {
    // A graph member edited in a file whose errors were summarised: the incremental path
    // would keep the summary of the old text; the result must equal a full parse.
    let text = format!(
        "graph G <\n  state 0 < >\n  trans 0->0 < >\n>\n{}\n",
        ">".repeat(150)
    );
    let old = parse(&text);
    assert_eq!(count(&old, ErrorCode::HG0013), 1);
    let at = text.find("< >").expect("state body") + 1;
    let edit = higraph_syntax::Edit {
        delete: higraph_syntax::TextRange::empty((at as u32).into()),
        insert: " S E 0.0; ".to_owned(),
    };
    let new_text = edit.apply(&text).expect("edit applies");
    assert!(old.reparse_member(&edit, &new_text).is_none());
    assert_eq!(old.reparse(&edit, &new_text), parse(&new_text));
}

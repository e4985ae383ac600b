//! Depth and size robustness of the real binary (issue 10): `check`, `parse` and `fmt` on
//! nesting far past the parser's limit and on a graph with more members than the structure
//! rules' virtual layout holds exit normally (no stack overflow, no panic), and a language
//! server session over such a document answers hover, semantic tokens and folding.

#[path = "lsp/client.rs"]
#[allow(dead_code)]
mod client;

use std::process::{Command, Output};

use client::{Server, TempTree};
use serde_json::json;

fn chart(elements: &str, condition: &str) -> String {
    format!(
        "chart C <\n  sequencer S <\n    step A < >\n    {elements}\n    trans T < {condition}; >\n    step B < >\n  >\n>\n"
    )
}

/// The pathological documents: name and text.
fn documents() -> Vec<(&'static str, String)> {
    let parens = 20_000;
    vec![
        (
            "parens",
            chart(
                "",
                &format!("{}x{}", "(".repeat(parens), ")".repeat(parens)),
            ),
        ),
        ("not", chart("", &format!("{}x", "not ".repeat(40_000)))),
        ("or", chart("", &format!("x{}", " or x".repeat(40_000)))),
        // IEC charts (docs/iec.md): arithmetic and nested statements.
        ("minus", chart("", &format!("{}x", "- ".repeat(40_000)))),
        (
            "plus",
            chart("", &format!("x{}", " + x * x".repeat(20_000))),
        ),
        (
            "if",
            format!(
                "chart C <\n  profile iec;\n  action A < {}x := 1;{} >\n  sequencer S < step A < P1 A; > >\n>\n",
                "IF a THEN CASE n OF 1: ".repeat(50_000),
                " END_CASE; END_IF;".repeat(50_000)
            ),
        ),
        (
            "alt",
            chart(
                &format!(
                    "{}trans U < y; >{}",
                    "alt < branch < ".repeat(3_000),
                    " > >".repeat(3_000)
                ),
                "x",
            ),
        ),
        (
            "parallel",
            chart(
                &format!(
                    "{}step Z < >{}",
                    "parallel < branch < ".repeat(3_000),
                    " > >".repeat(3_000)
                ),
                "x",
            ),
        ),
    ]
}

fn run(tree: &TempTree, args: &[&str]) -> Output {
    Command::new(client::binary())
        .args(args)
        .current_dir(tree.path())
        .output()
        .expect("the binary runs")
}

/// Exited with a status (not killed by a signal such as the abort of a stack overflow), and
/// not 101 (a panic).
fn assert_normal_exit(what: &str, output: &Output, allowed: &[i32]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    let code = output.status.code();
    assert!(
        code.is_some_and(|c| allowed.contains(&c)),
        "{what}: exit {:?}, stderr: {}",
        output.status,
        stderr.chars().take(2000).collect::<String>()
    );
    assert!(!stderr.contains("overflowed its stack"), "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
}

#[test]
fn check_parse_and_fmt_survive_deep_nesting() {
    for (name, text) in documents() {
        let tree = TempTree::new();
        tree.file("deep.higraph", &text);
        let check = run(&tree, &["check", "--format", "json", "deep.higraph"]);
        assert_normal_exit(name, &check, &[1]);
        let json: serde_json::Value =
            serde_json::from_slice(&check.stdout).expect("check prints JSON");
        let hg0012 = json["diagnostics"]
            .as_array()
            .expect("diagnostics")
            .iter()
            .filter(|d| d["code"] == "HG0012")
            .count();
        assert_eq!(hg0012, 1, "{name}: HG0012 once");
        let human = run(&tree, &["check", "deep.higraph"]);
        assert_normal_exit(name, &human, &[1]);
        let parse = run(&tree, &["parse", "deep.higraph"]);
        assert_normal_exit(name, &parse, &[0]);
        assert!(
            String::from_utf8_lossy(&parse.stderr).contains("HG0012"),
            "{name}: parse reports HG0012"
        );
        // A file with syntax errors is left unchanged (exit 1), never half-written.
        let fmt = run(&tree, &["fmt", "--check", "deep.higraph"]);
        assert_normal_exit(name, &fmt, &[1]);
        let fmt = run(&tree, &["fmt", "deep.higraph"]);
        assert_normal_exit(name, &fmt, &[1]);
        assert_eq!(
            std::fs::read_to_string(tree.path().join("deep.higraph")).expect("read"),
            text,
            "{name}: fmt left the file as it was"
        );
    }
}

#[test]
fn fmt_and_check_of_a_graph_past_the_virtual_layout() {
    // 70 000 members: more than the 65 534 the structure rules' virtual layout holds; the
    // formatter's priorities once overflowed a u32 offset here.
    let tree = TempTree::new();
    let text = format!("graph G <\n{}>\n", "trans 0->0 < >\n".repeat(70_000));
    tree.file("big.higraph", &text);
    let fmt = run(&tree, &["fmt", "--check", "big.higraph"]);
    assert_normal_exit("fmt --check", &fmt, &[0, 1]);
    let check = run(&tree, &["check", "--format", "json", "big.higraph"]);
    assert_normal_exit("check", &check, &[0, 1]);
    serde_json::from_slice::<serde_json::Value>(&check.stdout).expect("check prints JSON");
}

#[test]
fn a_megabyte_of_closing_brackets_gives_a_small_report() {
    let tree = TempTree::new();
    tree.file("gt.higraph", ">".repeat(1 << 20));
    let check = run(&tree, &["check", "--format", "json", "gt.higraph"]);
    assert_normal_exit("check", &check, &[1]);
    // 100 listed errors and one summary: a few hundred kilobytes at most, not 800 MB.
    assert!(
        check.stdout.len() < 1 << 20,
        "{} bytes of JSON",
        check.stdout.len()
    );
    let json: serde_json::Value = serde_json::from_slice(&check.stdout).expect("JSON");
    let diagnostics = json["diagnostics"].as_array().expect("diagnostics");
    assert_eq!(diagnostics.len(), 101);
    assert_eq!(diagnostics[100]["code"], "HG0013");
}

#[test]
fn the_server_answers_over_a_deep_document() {
    let tree = TempTree::new();
    let documents = documents();
    for (name, text) in &documents {
        tree.file(&format!("{name}.higraph"), text);
    }
    let mut server = Server::indexed(&tree.path());
    for (name, text) in &documents {
        let uri = tree.uri(&format!("{name}.higraph"));
        server.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
        );
        let diagnostics = server.wait_for_diagnostics(&uri, 1);
        assert_eq!(
            diagnostics.iter().filter(|d| d["code"] == "HG0012").count(),
            1,
            "{name}: HG0012 once"
        );
        // Positions on the deep line: its start, the middle of the nesting, its end.
        let (line, longest) = text
            .lines()
            .enumerate()
            .max_by_key(|(_, l)| l.len())
            .expect("lines");
        let width = u32::try_from(longest.len()).expect("small");
        for character in [4, width / 2, width] {
            let position = json!({"line": line, "character": character});
            let hover = server.request(
                "textDocument/hover",
                json!({"textDocument": {"uri": uri}, "position": position}),
            );
            assert!(hover.is_ok(), "{name}: hover {hover:?}");
        }
        let tokens = server.request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": {"uri": uri}}),
        );
        assert!(tokens.is_ok(), "{name}: semantic tokens {tokens:?}");
        let folding = server.request(
            "textDocument/foldingRange",
            json!({"textDocument": {"uri": uri}}),
        );
        assert!(folding.is_ok(), "{name}: folding {folding:?}");
        let symbols = server.request(
            "textDocument/documentSymbol",
            json!({"textDocument": {"uri": uri}}),
        );
        assert!(symbols.is_ok(), "{name}: symbols {symbols:?}");
    }
    assert_eq!(server.shutdown_and_exit(), 0);
}

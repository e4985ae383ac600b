//! Range formatting and semantic tokens delta end to end (`tooling.md` §4): the real binary
//! over stdio on an open document.

use serde_json::{Value, json};

use crate::client::{Server, TempTree};

/// Two graphs out of layout and a symbol table between them.
const TEXT: &str = "graph A <\n    state 0 <  >\n  trans any->0 < U x; >\n>\n\n\
    symbols <\n  S : E 0.0;\n  Long : E 0.1;\n>\n\n\
    graph B <\n  state 0 < >\n      state 1 < >\n  trans 0->1 < U y; >\n>\n";

fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\n");
    tree.file("main.higraph", TEXT);
    tree
}

fn open(server: &mut Server, uri: &str, text: &str) {
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
}

fn replace_all(server: &mut Server, uri: &str, version: i64, text: &str) {
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]}),
    );
}

fn range(start: (usize, usize), end: (usize, usize)) -> Value {
    json!({"start": {"line": start.0, "character": start.1}, "end": {"line": end.0, "character": end.1}})
}

/// Applies LSP text edits to an ASCII text.
fn apply_edits(text: &str, edits: &Value) -> String {
    let offset = |position: &Value| {
        let line = position["line"].as_u64().expect("line") as usize;
        let character = position["character"].as_u64().expect("character") as usize;
        text.split_inclusive('\n')
            .take(line)
            .map(str::len)
            .sum::<usize>()
            + character
    };
    let mut edits: Vec<(usize, usize, String)> = edits
        .as_array()
        .expect("edits")
        .iter()
        .map(|e| {
            (
                offset(&e["range"]["start"]),
                offset(&e["range"]["end"]),
                e["newText"].as_str().expect("newText").to_owned(),
            )
        })
        .collect();
    edits.sort_by_key(|edit| std::cmp::Reverse(edit.0));
    let mut out = text.to_owned();
    for (start, end, new_text) in edits {
        out.replace_range(start..end, &new_text);
    }
    out
}

fn range_formatting(server: &mut Server, uri: &str, range: Value) -> Result<Value, Value> {
    server.request(
        "textDocument/rangeFormatting",
        json!({"textDocument": {"uri": uri}, "range": range,
               "options": {"tabSize": 2, "insertSpaces": true}}),
    )
}

#[test]
fn range_formatting_lays_out_the_items_the_range_touches() {
    let tree = workspace();
    let (mut server, init) = Server::initialized(&tree.path(), json!({}));
    assert_eq!(
        init["capabilities"]["documentRangeFormattingProvider"], true,
        "{init}"
    );
    let uri = tree.uri("main.higraph");
    open(&mut server, &uri, TEXT);

    // A range inside graph B (line 12 is `      state 1 < >`): graph B only.
    let edits = range_formatting(&mut server, &uri, range((12, 6), (12, 9))).expect("edits");
    let new = apply_edits(TEXT, &edits);
    let full = server
        .request(
            "textDocument/formatting",
            json!({"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": true}}),
        )
        .expect("full formatting");
    let formatted = apply_edits(TEXT, &full);
    let graph_b = |text: &str| text[text.find("graph B").expect("graph B")..].to_owned();
    assert_eq!(graph_b(&new), graph_b(&formatted), "{new}");
    assert!(
        new.starts_with("graph A <\n    state 0 <  >\n"),
        "graph A is left alone: {new}"
    );
    assert!(new.contains("  S : E 0.0;\n"), "{new}");

    // A range from graph A into the table: those two, and again idempotent.
    let edits = range_formatting(&mut server, &uri, range((1, 0), (6, 3))).expect("edits");
    let both = apply_edits(TEXT, &edits);
    assert!(both.starts_with("graph A <\n  state 0 < >\n"), "{both}");
    assert!(both.contains("  S    : E 0.0;\n"), "{both}");
    assert!(both.contains("      state 1 < >\n"), "{both}");
    replace_all(&mut server, &uri, 2, &both);
    let again = range_formatting(&mut server, &uri, range((1, 0), (6, 3))).expect("edits");
    assert_eq!(again, json!([]));

    // Syntax errors: refused with RequestFailed and a message.
    replace_all(&mut server, &uri, 3, "graph A < state 0 < C: U a > >\n");
    let error = range_formatting(&mut server, &uri, range((0, 0), (0, 5))).expect_err("refused");
    assert_eq!(error["code"], -32803, "{error}");
    assert!(
        error["message"]
            .as_str()
            .is_some_and(|m| m.contains("syntax error")),
        "{error}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// The flat integers of a tokens answer's `data`.
fn data(answer: &Value) -> Vec<u64> {
    answer["data"]
        .as_array()
        .expect("data")
        .iter()
        .map(|n| n.as_u64().expect("an integer"))
        .collect()
}

#[test]
fn semantic_tokens_delta_answers_edits_against_the_previous_result() {
    let tree = workspace();
    let (mut server, init) = Server::initialized(&tree.path(), json!({}));
    assert_eq!(
        init["capabilities"]["semanticTokensProvider"]["full"],
        json!({"delta": true}),
        "{init}"
    );
    let uri = tree.uri("main.higraph");
    open(&mut server, &uri, TEXT);
    let doc = json!({"uri": uri});

    let first = server
        .request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": doc}),
        )
        .expect("tokens");
    let first_id = first["resultId"].as_str().expect("a result id").to_owned();
    let old = data(&first);
    assert!(!old.is_empty());

    // A new state in graph B.
    let changed = TEXT.replace("      state 1 < >\n", "      state 1 < >\n  state 2 < >\n");
    replace_all(&mut server, &uri, 2, &changed);
    let delta = server
        .request(
            "textDocument/semanticTokens/full/delta",
            json!({"textDocument": doc, "previousResultId": first_id}),
        )
        .expect("a delta");
    let delta_id = delta["resultId"].as_str().expect("a result id").to_owned();
    assert_ne!(delta_id, first_id);
    let edits = delta["edits"].as_array().expect("edits");
    assert!(!edits.is_empty(), "{delta}");
    let mut applied = old.clone();
    for edit in edits.iter().rev() {
        let start = edit["start"].as_u64().expect("start") as usize;
        let count = edit["deleteCount"].as_u64().expect("deleteCount") as usize;
        let inserted: Vec<u64> = edit["data"]
            .as_array()
            .map(|d| d.iter().filter_map(Value::as_u64).collect())
            .unwrap_or_default();
        applied.splice(start..start + count, inserted);
    }
    // Nothing changed since: a delta on the new id has no edits.
    let unchanged = server
        .request(
            "textDocument/semanticTokens/full/delta",
            json!({"textDocument": doc, "previousResultId": delta_id}),
        )
        .expect("a delta");
    assert_eq!(unchanged["edits"], json!([]), "{unchanged}");
    let full = server
        .request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": doc}),
        )
        .expect("tokens");
    assert_eq!(applied, data(&full));
    assert!(applied.len() > old.len());

    // An unknown id (or an outdated one) gets the full tokens.
    let fallback = server
        .request(
            "textDocument/semanticTokens/full/delta",
            json!({"textDocument": doc, "previousResultId": "no such id"}),
        )
        .expect("tokens");
    assert_eq!(data(&fallback), data(&full));
    assert!(fallback["resultId"].is_string(), "{fallback}");
    let outdated = server
        .request(
            "textDocument/semanticTokens/full/delta",
            json!({"textDocument": doc, "previousResultId": first_id}),
        )
        .expect("tokens");
    assert_eq!(data(&outdated), data(&full));

    // Closed: the tokens are forgotten (full tokens from the file on disk, without an id).
    let last = outdated["resultId"].as_str().expect("an id").to_owned();
    server.notify("textDocument/didClose", json!({"textDocument": doc}));
    let closed = server
        .request(
            "textDocument/semanticTokens/full/delta",
            json!({"textDocument": doc, "previousResultId": last}),
        )
        .expect("tokens");
    assert_eq!(data(&closed), old, "the disk text");
    assert!(closed.get("resultId").is_none(), "{closed}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

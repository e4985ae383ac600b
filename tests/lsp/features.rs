//! Editor features end to end on a copy of `examples/drilling`: rename across files that are
//! not open, completion, navigation, outline and the other requests of `tooling.md` §4.

use serde_json::{Value, json};

use crate::client::{Server, TempTree, repo_root};

/// A copy of the drilling machine example.
fn drilling() -> TempTree {
    let tree = TempTree::new();
    let root = repo_root().join("examples/drilling");
    for relative in [
        "higraph.toml",
        "bohrmaschine.higraph",
        "symbols.higraph",
        "graphs/bohren.higraph",
        "graphs/motor.higraph",
        "graphs/spanner.higraph",
        "graphs/ventil_2e.higraph",
    ] {
        tree.file(
            relative,
            std::fs::read(root.join(relative)).expect("the example"),
        );
    }
    tree
}

fn text(tree: &TempTree, relative: &str) -> String {
    std::fs::read_to_string(tree.path().join(relative)).expect("read")
}

/// The 0-based line and column (ASCII lines) of the first `needle` after `after`.
fn find(text: &str, after: &str, needle: &str) -> (u64, u64) {
    let context = text.find(after).expect("the context");
    let start = context + text[context..].find(needle).expect("the needle");
    let line = text[..start].matches('\n').count() as u64;
    let column = (start - text[..start].rfind('\n').map_or(0, |n| n + 1)) as u64;
    (line, column)
}

fn position(uri: &str, (line, character): (u64, u64)) -> Value {
    json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}})
}

/// Applies LSP text edits to a text (edits do not overlap).
fn apply_edits(text: &str, edits: &[Value]) -> String {
    let offset = |position: &Value| {
        let line = position["line"].as_u64().expect("line") as usize;
        let character = position["character"].as_u64().expect("character") as usize;
        let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
        let line_text = text[start..].split('\n').next().unwrap_or("");
        // UTF-16 columns to bytes.
        let mut units = 0;
        let mut bytes = 0;
        for c in line_text.chars() {
            if units >= character {
                break;
            }
            units += c.len_utf16();
            bytes += c.len_utf8();
        }
        start + bytes
    };
    let mut edits: Vec<(usize, usize, String)> = edits
        .iter()
        .map(|e| {
            (
                offset(&e["range"]["start"]),
                offset(&e["range"]["end"]),
                e["newText"].as_str().unwrap_or_default().to_owned(),
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

#[test]
fn rename_reaches_files_that_are_not_open() {
    let tree = drilling();
    let mut server = Server::indexed(&tree.path());
    let ventil = "graphs/ventil_2e.higraph";
    let uri = tree.uri(ventil);
    let at = find(&text(&tree, ventil), "in_out", "IM_Ab");

    let prepared = server
        .request("textDocument/prepareRename", position(&uri, at))
        .expect("IM_Ab can be renamed");
    assert_eq!(prepared["placeholder"], "IM_Ab", "{prepared}");
    assert_eq!(prepared["range"]["start"]["line"], at.0, "{prepared}");

    let mut params = position(&uri, at);
    params["newName"] = json!("IM_Senken");
    let edit = server
        .request("textDocument/rename", params)
        .expect("a workspace edit");
    let changes = edit["changes"].as_object().expect("changes by URI");
    let group = tree.uri("bohrmaschine.higraph");
    assert!(changes.contains_key(&group), "{edit}");
    assert!(changes.contains_key(&uri), "{edit}");
    for (relative, file_uri) in [("bohrmaschine.higraph", &group), (ventil, &uri)] {
        let edits = changes[file_uri.as_str()].as_array().expect("edits");
        let renamed = apply_edits(&text(&tree, relative), edits);
        tree.file(relative, renamed);
    }
    assert!(text(&tree, "bohrmaschine.higraph").contains("Vorschub.IM_Senken;"));
    assert_eq!(text(&tree, ventil).matches("IM_Senken").count(), 3);
    // The renamed workspace is as clean as before.
    let report = tree.check_json();
    assert_eq!(report["summary"]["errors"], 0, "{report}");
    assert_eq!(report["summary"]["warnings"], 0, "{report}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// Renaming a formal from the group (`Oben     := Bohrer_Oben;`) to a longer name keeps the
/// actuals of the instance aligned: a formatted workspace stays formatted.
#[test]
fn rename_keeps_the_workspace_formatted() {
    let tree = drilling();
    assert!(tree.fmt_check(), "the example is formatted");
    let mut server = Server::indexed(&tree.path());
    let group = "bohrmaschine.higraph";
    let at = find(&text(&tree, group), "instance", "Oben     :=");
    let mut params = position(&tree.uri(group), at);
    params["newName"] = json!("Oben_Endlage");
    let edit = server
        .request("textDocument/rename", params)
        .expect("a workspace edit");
    let changes = edit["changes"].as_object().expect("changes by URI");
    assert!(changes.len() >= 2, "{edit}");
    for relative in [
        "bohrmaschine.higraph",
        "graphs/ventil_2e.higraph",
        "graphs/bohren.higraph",
        "graphs/motor.higraph",
        "graphs/spanner.higraph",
    ] {
        if let Some(edits) = changes.get(&tree.uri(relative)) {
            let edits = edits.as_array().expect("edits");
            let renamed = apply_edits(&text(&tree, relative), edits);
            tree.file(relative, renamed);
        }
    }
    assert!(
        text(&tree, group).contains("Oben_Endlage := Bohrer_Oben;"),
        "{}",
        text(&tree, group)
    );
    assert!(tree.fmt_check(), "{}", text(&tree, group));
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn an_invalid_new_name_is_refused_with_a_message_and_no_edit() {
    let tree = drilling();
    let mut server = Server::indexed(&tree.path());
    let ventil = "graphs/ventil_2e.higraph";
    let uri = tree.uri(ventil);
    let at = find(&text(&tree, ventil), "in_out", "IM_Ab");
    for new_name in ["1abc", "IM_Auf"] {
        let mut params = position(&uri, at);
        params["newName"] = json!(new_name);
        let error = server
            .request("textDocument/rename", params)
            .expect_err("refused");
        assert_eq!(error["code"], -32803, "{new_name}: {error}");
        assert!(
            !error["message"].as_str().unwrap_or("").is_empty(),
            "{error}"
        );
    }
    // A predefined variable cannot be renamed.
    let init = find(&text(&tree, ventil), "trans any->0", "INIT_SD");
    let error = server
        .request("textDocument/prepareRename", position(&uri, init))
        .expect_err("refused");
    assert_eq!(error["code"], -32803, "{error}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn completion_after_an_instance_offers_its_incoming_messages() {
    let tree = drilling();
    let mut server = Server::indexed(&tree.path());
    let group = "bohrmaschine.higraph";
    let uri = tree.uri(group);
    let original = text(&tree, group);
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": original}}),
    );
    let (line, column) = find(&original, "OM_Senken", "Vorschub.");
    let after_dot = (line, column + "Vorschub.".len() as u64);
    let result = server
        .request("textDocument/completion", position(&uri, after_dot))
        .expect("completions");
    let items = result.as_array().expect("a list");
    let labels: Vec<&str> = items.iter().filter_map(|i| i["label"].as_str()).collect();
    assert!(
        labels.contains(&"IM_Ab") && labels.contains(&"IM_Auf"),
        "{labels:?}"
    );
    assert!(
        !labels.contains(&"OM_Oben"),
        "outgoing messages are no targets: {labels:?}"
    );
    let item = items.iter().find(|i| i["label"] == "IM_Ab").expect("IM_Ab");
    assert_eq!(item["textEdit"]["newText"], "IM_Ab", "{item}");
    assert_eq!(item["textEdit"]["range"]["start"]["line"], line, "{item}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn navigation_outline_and_the_other_requests_answer() {
    let tree = drilling();
    let mut server = Server::indexed(&tree.path());
    let group = tree.uri("bohrmaschine.higraph");
    let ventil = tree.uri("graphs/ventil_2e.higraph");
    let group_text = text(&tree, "bohrmaschine.higraph");
    let message = find(&group_text, "OM_Senken", "IM_Ab");

    let definition = server
        .request("textDocument/definition", position(&group, message))
        .expect("a definition");
    assert_eq!(definition[0]["uri"], ventil.as_str(), "{definition}");
    let declaration = find(&text(&tree, "graphs/ventil_2e.higraph"), "in_out", "IM_Ab");
    assert_eq!(
        definition[0]["range"]["start"]["line"], declaration.0,
        "{definition}"
    );

    let hover = server
        .request("textDocument/hover", position(&group, message))
        .expect("a hover");
    assert_eq!(hover["contents"]["kind"], "markdown", "{hover}");
    assert!(
        hover["contents"]["value"]
            .as_str()
            .is_some_and(|text| text.contains("BOOL")),
        "{hover}"
    );

    let mut params = position(&group, message);
    params["context"] = json!({"includeDeclaration": true});
    let references = server
        .request("textDocument/references", params)
        .expect("references");
    let files: Vec<&str> = references
        .as_array()
        .expect("locations")
        .iter()
        .filter_map(|l| l["uri"].as_str())
        .collect();
    assert!(
        files.contains(&group.as_str()) && files.contains(&ventil.as_str()),
        "{files:?}"
    );

    let outline = server
        .request(
            "textDocument/documentSymbol",
            json!({"textDocument": {"uri": ventil}}),
        )
        .expect("an outline");
    assert_eq!(outline[0]["name"], "Ventil_2E", "{outline}");
    assert!(
        outline[0]["children"]
            .as_array()
            .is_some_and(|c| !c.is_empty()),
        "{outline}"
    );

    let symbols = server
        .request("workspace/symbol", json!({"query": "Vorschub"}))
        .expect("workspace symbols");
    assert!(
        symbols
            .as_array()
            .expect("symbols")
            .iter()
            .any(|s| s["location"]["uri"] == group.as_str()),
        "{symbols}"
    );

    let folds = server
        .request(
            "textDocument/foldingRange",
            json!({"textDocument": {"uri": ventil}}),
        )
        .expect("folds");
    assert!(folds.as_array().is_some_and(|f| !f.is_empty()), "{folds}");

    let tokens = server
        .request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": {"uri": ventil}}),
        )
        .expect("tokens");
    let data = tokens["data"].as_array().expect("data");
    assert!(!data.is_empty() && data.len().is_multiple_of(5), "{tokens}");

    let highlights = server
        .request("textDocument/documentHighlight", position(&group, message))
        .expect("highlights");
    assert!(highlights.is_array(), "{highlights}");

    let hints = server
        .request(
            "textDocument/inlayHint",
            json!({"textDocument": {"uri": ventil}, "range": {"start": {"line": 0, "character": 0}, "end": {"line": 100, "character": 0}}}),
        )
        .expect("inlay hints");
    let labels: Vec<&str> = hints
        .as_array()
        .expect("hints")
        .iter()
        .filter_map(|h| h["label"].as_str())
        .collect();
    assert!(labels.iter().any(|l| l.contains("Oben")), "{labels:?}");

    let formatting = server
        .request(
            "textDocument/formatting",
            json!({"textDocument": {"uri": ventil}, "options": {"tabSize": 2, "insertSpaces": true}}),
        )
        .expect("formatting edits");
    assert!(formatting.is_array(), "{formatting}");

    let selection = server
        .request(
            "textDocument/selectionRange",
            json!({"textDocument": {"uri": group}, "positions": [{"line": message.0, "character": message.1}]}),
        )
        .expect("selection ranges");
    assert!(selection[0]["parent"].is_object(), "{selection}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn quick_fixes_are_code_actions_with_their_diagnostic() {
    let tree = TempTree::new();
    // HG0002: a missing `;` has a quick fix.
    let text = "graph A <\n  in < Oben : BOOL >\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n";
    tree.file(
        "higraph.toml",
        "[diagnostics]\nHG2402 = \"off\"\nHG1210 = \"off\"\n",
    )
    .file("a.higraph", text);
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("a.higraph");
    server.drain(std::time::Duration::from_millis(200));
    let diagnostics = server.diagnostics.get(&uri).cloned().unwrap_or_default();
    let with_fix = diagnostics.first().cloned().expect("a diagnostic");
    let actions = server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": with_fix["range"], "context": {"diagnostics": [with_fix]}}),
        )
        .expect("code actions");
    let action = &actions[0];
    assert_eq!(action["kind"], "quickfix", "{actions}");
    assert_eq!(
        action["diagnostics"][0]["code"], with_fix["code"],
        "{actions}"
    );
    let edits = action["edit"]["changes"][uri.as_str()]
        .as_array()
        .expect("edits");
    let fixed = apply_edits(text, edits);

    // Without the client's diagnostics (fixes at the cursor) the server attaches its own,
    // as it published it.
    let at_cursor = server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": with_fix["range"], "context": {"diagnostics": []}}),
        )
        .expect("code actions");
    assert_eq!(at_cursor[0]["title"], action["title"], "{at_cursor}");
    assert_eq!(
        at_cursor[0]["diagnostics"],
        json!([with_fix]),
        "{at_cursor}"
    );

    // Kinds are hierarchical: `quickfix` answers `quickfix` and the root kind, not a sub-kind
    // or another kind.
    let only = |server: &mut Server, kind: &str| {
        server
            .request(
                "textDocument/codeAction",
                json!({"textDocument": {"uri": uri}, "range": with_fix["range"],
                       "context": {"diagnostics": [], "only": [kind]}}),
            )
            .expect("code actions")
            .as_array()
            .map_or(0, Vec::len)
    };
    assert_eq!(only(&mut server, "quickfix"), 1);
    assert_eq!(only(&mut server, ""), 1);
    assert_eq!(only(&mut server, "quickfix.foo"), 0);
    assert_eq!(only(&mut server, "refactor"), 0);

    tree.file("a.higraph", &fixed);
    assert_eq!(tree.check_json()["summary"]["errors"], 0, "{fixed}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// Of "Replace with 'Oben'" and "Declare 'Obenx'", the replacement is the preferred fix (what
/// a client applies on "auto fix"); a completion inserting `#Ab` is filtered by `Ab`, the text
/// the user types for it.
#[test]
fn the_likely_fix_is_preferred_and_completions_carry_their_filter_text() {
    let tree = TempTree::new();
    let text = "graph A <\n  in < Oben : BOOL; >\n  out < Ab : BOOL; >\n  state 0 < C: U Obenx; = Ab; >\n  trans any->0 < U INIT_SD; >\n>\n";
    tree.file("a.higraph", text);
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("a.higraph");
    server.drain(std::time::Duration::from_millis(200));
    let (line, column) = find(text, "state 0", "Obenx");
    let range = json!({"start": {"line": line, "character": column},
                       "end": {"line": line, "character": column + 5}});
    let actions = server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": range, "context": {"diagnostics": []}}),
        )
        .expect("code actions");
    let actions = actions.as_array().expect("a list");
    let preferred: Vec<&Value> = actions
        .iter()
        .filter(|a| a["isPreferred"] == true)
        .collect();
    assert_eq!(preferred.len(), 1, "{actions:?}");
    assert_eq!(preferred[0]["title"], "Replace with 'Oben'", "{actions:?}");
    assert!(
        actions.iter().any(|a| a["title"]
            .as_str()
            .is_some_and(|t| t.starts_with("Declare"))
            && a.get("isPreferred").is_none()),
        "{actions:?}"
    );

    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    let (line, column) = find(text, "state 0", "Ab;");
    let result = server
        .request(
            "textDocument/completion",
            position(&uri, (line, column + 1)),
        )
        .expect("completions");
    let items = result.as_array().expect("a list");
    let ab = items.iter().find(|i| i["label"] == "Ab").expect("Ab");
    assert_eq!(ab["textEdit"]["newText"], "#Ab", "{ab}");
    assert_eq!(ab["filterText"], "Ab", "{ab}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn render_request_returns_an_svg_and_refuses_unknown_names() {
    let tree = drilling();
    let mut server = Server::indexed(&tree.path());
    let result = server
        .request("higraph/render", json!({"name": "Ventil_2E"}))
        .expect("a picture");
    let svg = result["svg"].as_str().expect("an svg string");
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{svg:.80}"
    );
    assert!(svg.contains("Initialisierung"), "state names are drawn");
    let error = server
        .request("higraph/render", json!({"name": "Gibtsnicht"}))
        .expect_err("an unknown name is refused");
    assert_eq!(error["code"], -32803, "{error}");
    assert!(
        error["message"]
            .as_str()
            .is_some_and(|m| m.contains("Ventil_2E")),
        "{error}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn render_request_names_the_candidates_of_a_shared_name() {
    let tree = drilling();
    tree.file(
        "graphs/zweiter.higraph",
        "// a second Motor\ngraph Motor <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
    );
    let mut server = Server::indexed(&tree.path());
    let error = server
        .request("higraph/render", json!({"name": "motor"}))
        .expect_err("a shared name is refused, not a silent pick");
    let message = error["message"].as_str().expect("a message");
    assert!(
        message.contains("graph Motor at graphs/motor.higraph:")
            && message.contains("graph Motor at graphs/zweiter.higraph:2"),
        "{error}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

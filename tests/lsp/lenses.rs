//! Count lenses end to end (issue 15, item 2): `textDocument/codeLens` answers unresolved
//! lenses (range and data), `codeLens/resolve` adds the title and the command
//! `higraph.showReferences` with the arguments of `editor.action.showReferences` (URI,
//! position, locations), the locations being what find-references answers; the `▶ Run test`
//! lenses stay as they were. On the small workspace `tests/data/testing`.

use serde_json::{Value, json};

use crate::client::{Server, TempTree, repo_root};

/// A copy of `tests/data/testing`.
fn workspace() -> TempTree {
    let tree = TempTree::new();
    let root = repo_root().join("tests/data/testing");
    for relative in ["higraph.toml", "anlage.higraph", "tests.higraph"] {
        tree.file(
            relative,
            std::fs::read(root.join(relative)).expect("the data"),
        );
    }
    tree
}

fn lenses(server: &mut Server, uri: &str) -> Vec<Value> {
    server
        .request(
            "textDocument/codeLens",
            json!({"textDocument": {"uri": uri}}),
        )
        .expect("codeLens answers")
        .as_array()
        .cloned()
        .expect("a list of lenses")
}

#[test]
fn count_lenses_resolve_to_the_references() {
    let tree = workspace();
    let (mut server, result) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    assert_eq!(
        result["capabilities"]["codeLensProvider"]["resolveProvider"], true,
        "{result}"
    );
    server.wait_for_progress_end();

    let uri = tree.uri("anlage.higraph");
    let unresolved = lenses(&mut server, &uri);
    assert!(
        unresolved
            .iter()
            .all(|lens| lens["command"].is_null() && lens["data"][0] == unresolved[0]["data"][0]),
        "{unresolved:?}"
    );
    let resolved: Vec<Value> = unresolved
        .iter()
        .map(|lens| {
            server
                .request("codeLens/resolve", lens.clone())
                .expect("codeLens/resolve answers")
        })
        .collect();
    let summary: Vec<String> = resolved
        .iter()
        .map(|lens| {
            format!(
                "{}: {}",
                lens["range"]["start"]["line"],
                lens["command"]["title"].as_str().unwrap_or("-")
            )
        })
        .collect();
    assert_eq!(
        summary,
        [
            "2: 2 uses",
            "3: 3 uses",
            "5: 1 instance",
            "5: 1 reference",
            "8: 2 incoming transitions",
            "8: 1 outgoing transition",
            "9: 1 incoming transition",
            "9: 1 outgoing transition",
            "14: 1 instance",
            "14: 0 internal messages",
        ],
        "{resolved:?}"
    );

    // Every command opens the references view at the counted name (the lens's range ends
    // with it, the data holds only the document's and the kind's numbers); a symbol's locations are its
    // references.
    for lens in &resolved {
        let command = &lens["command"];
        assert_eq!(command["command"], "higraph.showReferences", "{lens}");
        assert_eq!(command["arguments"][0], uri);
        let (at, end) = (&command["arguments"][1], &lens["range"]["end"]);
        assert_eq!(at["line"], end["line"], "{lens}");
        assert_eq!(
            at["character"].as_u64().map(|c| c + 1),
            end["character"].as_u64(),
            "{lens}"
        );
        let data = lens["data"].as_array().expect("data");
        assert!(
            data.len() == 2 && data.iter().all(Value::is_u64),
            "only the document's and the kind's numbers: {lens}"
        );
    }
    let taster = &resolved[0];
    let references = server
        .request(
            "textDocument/references",
            json!({
                "textDocument": {"uri": uri},
                "position": taster["command"]["arguments"][1],
                "context": {"includeDeclaration": false},
            }),
        )
        .expect("references answers");
    assert_eq!(taster["command"]["arguments"][2], references);

    // The test lenses are there as before, resolved already, and resolve leaves them alone.
    let tests = lenses(&mut server, &tree.uri("tests.higraph"));
    let titles: Vec<&str> = tests
        .iter()
        .filter_map(|lens| lens["command"]["title"].as_str())
        .collect();
    assert_eq!(titles, ["▶ Run test", "▶ Run test"]);
    let again = server
        .request("codeLens/resolve", tests[0].clone())
        .expect("codeLens/resolve answers");
    assert_eq!(again, tests[0]);

    assert_eq!(server.shutdown_and_exit(), 0);
}

/// The data names the document by its number in the server's lens table, which only keeps
/// open documents: after `didClose` a listed lens resolves to the plain label `outdated`;
/// data that is not `[document, kind]` with a known kind is an error, never a crash.
#[test]
fn stale_or_made_up_lens_data_is_answered() {
    let tree = workspace();
    let (mut server, _) = Server::initialized(&tree.path(), json!({}));
    let uri = tree.uri("anlage.higraph");
    let text = std::fs::read_to_string(tree.path().join("anlage.higraph")).expect("the text");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    let listed = lenses(&mut server, &uri);
    let lens = listed.first().cloned().expect("a count lens");
    let resolved = server
        .request("codeLens/resolve", lens.clone())
        .expect("codeLens/resolve answers");
    assert_eq!(resolved["command"]["command"], "higraph.showReferences");
    // Listing again keeps the document's number.
    assert_eq!(lenses(&mut server, &uri)[0]["data"], lens["data"]);

    for data in [
        json!({"uri": uri, "kind": "symbolUses"}),
        json!([lens["data"][0], 7]),
        json!("x"),
    ] {
        let mut made_up = lens.clone();
        made_up["data"] = data;
        let error = server
            .request("codeLens/resolve", made_up)
            .expect_err("made-up data is an error");
        assert!(
            error["message"]
                .as_str()
                .is_some_and(|m| m.contains("code lens")),
            "{error}"
        );
    }

    server.notify(
        "textDocument/didClose",
        json!({"textDocument": {"uri": uri}}),
    );
    let stale = server
        .request("codeLens/resolve", lens)
        .expect("codeLens/resolve answers");
    assert_eq!(stale["command"]["title"], "outdated", "{stale}");
    assert_eq!(stale["command"]["command"], "", "{stale}");

    assert_eq!(server.shutdown_and_exit(), 0);
}

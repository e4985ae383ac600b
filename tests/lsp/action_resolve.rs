//! `codeAction/resolve` end to end (issue 15, item 5): a rename fix (HG1101, a name ending
//! with `_`) needs the workspace rename engine. A client that resolves edits
//! (`codeAction.resolveSupport` with `edit`) gets the action without its edit and with data,
//! and the edit from `codeAction/resolve`; a client that does not gets the edit at once, the
//! same edit.

use serde_json::{Value, json};

use crate::client::{Server, TempTree};

const GRAPH: &str = "graph Schalter <\n  in < Ein_ : BOOL; >\n  out < Licht : BOOL; >\n  state 0 < >\n  state 1 < C: = Licht; >\n  trans any->0 prio 1 < U INIT_SD; >\n  trans 0->1 prio 1 < U Ein_; >\n  trans 1->0 prio 1 < UN Ein_; >\n>\n";
const GROUP: &str = "symbols <\n  Taster : E 0.0 BOOL;\n  Lampe : A 0.0 BOOL;\n>\ngroup Anlage fc FC1 db DB1 <\n  instance Flur : Schalter < Ein_ := Taster; Licht := Lampe; >\n>\n";

fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("schalter.higraph", GRAPH)
        .file("anlage.higraph", GROUP);
    tree
}

/// The code actions at the HG1101 diagnostic of `schalter.higraph`.
fn rename_actions(server: &mut Server, tree: &TempTree) -> (Value, Vec<Value>) {
    let uri = tree.uri("schalter.higraph");
    server.drain(std::time::Duration::from_millis(200));
    let diagnostic = server
        .diagnostics
        .get(&uri)
        .cloned()
        .unwrap_or_default()
        .into_iter()
        .find(|d| d["code"] == "HG1101")
        .expect("HG1101 on Ein_");
    let actions = server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": diagnostic["range"],
                   "context": {"diagnostics": [diagnostic]}}),
        )
        .expect("code actions");
    let actions: Vec<Value> = actions
        .as_array()
        .expect("a list")
        .iter()
        .filter(|a| a["diagnostics"][0]["code"] == "HG1101")
        .cloned()
        .collect();
    assert_eq!(actions.len(), 1, "{actions:?}");
    (diagnostic, actions)
}

/// The edits of one file: (line, character, new text) of each start, sorted.
type FileEdits = (String, Vec<(u64, u64, String)>);

/// The edits of a workspace edit as (file name, sorted `[line, character, newText]`).
fn edits(edit: &Value) -> Vec<FileEdits> {
    let mut out: Vec<FileEdits> = edit["changes"]
        .as_object()
        .expect("changes")
        .iter()
        .map(|(uri, edits)| {
            let name = uri.rsplit('/').next().unwrap_or_default().to_owned();
            let mut list: Vec<(u64, u64, String)> = edits
                .as_array()
                .expect("edits")
                .iter()
                .map(|e| {
                    (
                        e["range"]["start"]["line"].as_u64().unwrap_or(0),
                        e["range"]["start"]["character"].as_u64().unwrap_or(0),
                        e["newText"].as_str().unwrap_or_default().to_owned(),
                    )
                })
                .collect();
            list.sort();
            (name, list)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn rename_fixes_resolve_their_edit_when_the_client_can_and_come_whole_otherwise() {
    // A client that resolves edits.
    let tree = workspace();
    let capabilities = json!({
        "window": {"workDoneProgress": true},
        "textDocument": {"codeAction": {"resolveSupport": {"properties": ["edit"]}}},
    });
    let (mut server, result) = Server::initialized(&tree.path(), capabilities);
    assert_eq!(
        result["capabilities"]["codeActionProvider"]["resolveProvider"], true,
        "{result}"
    );
    server.wait_for_progress_end();
    let (_, actions) = rename_actions(&mut server, &tree);
    let lazy = &actions[0];
    assert_eq!(lazy["title"], "Rename to 'Ein'", "{lazy}");
    assert!(lazy.get("edit").is_none(), "no edit before resolve: {lazy}");
    assert_eq!(lazy["data"]["code"], "HG1101", "{lazy}");
    assert_eq!(lazy["data"]["fix"], 0, "{lazy}");
    let resolved = server
        .request("codeAction/resolve", lazy.clone())
        .expect("codeAction/resolve answers");
    assert_eq!(resolved["title"], lazy["title"], "{resolved}");
    let resolved_edits = edits(&resolved["edit"]);
    // The declaration and both uses in the graph (minimal edits: the `_` deleted), the
    // formal in the group.
    assert_eq!(
        resolved_edits,
        vec![
            ("anlage.higraph".to_owned(), vec![(5, 29, "Ein".to_owned())]),
            (
                "schalter.higraph".to_owned(),
                vec![
                    (1, 10, String::new()),
                    (6, 27, String::new()),
                    (7, 28, String::new()),
                ]
            ),
        ],
        "{resolved}"
    );
    // An action listed before a file changed is not resolved against the new text.
    let uri = tree.uri("schalter.higraph");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": GRAPH}}),
    );
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2},
               "contentChanges": [{"range": {"start": {"line": 3, "character": 11},
                                             "end": {"line": 3, "character": 11}}, "text": " "}]}),
    );
    server.wait_for_diagnostics(&uri, 2);
    let stale = server.request("codeAction/resolve", lazy.clone());
    assert_eq!(
        stale.expect_err("a stale action is refused")["code"],
        -32801,
        "ContentModified"
    );
    assert_eq!(server.shutdown_and_exit(), 0);

    // A client without resolve support gets the same edit in the list.
    let tree = workspace();
    let (mut server, result) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    assert_eq!(
        result["capabilities"]["codeActionProvider"]["resolveProvider"], false,
        "{result}"
    );
    server.wait_for_progress_end();
    let (_, actions) = rename_actions(&mut server, &tree);
    let eager = &actions[0];
    assert!(eager.get("data").is_none(), "{eager}");
    assert_eq!(edits(&eager["edit"]), resolved_edits, "{eager}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

//! Pull diagnostics (LSP 3.17): a client that announces `textDocument.diagnostic` pulls the
//! same diagnostics as `check` gives, with result ids that change exactly when a file's
//! diagnostics change, `unchanged` reports otherwise, test failures (HG99xx) until an edit,
//! and no `textDocument/publishDiagnostics` at all. A client that does not announce it is
//! still pushed to.

use std::collections::HashMap;
use std::time::Duration;

use serde_json::{Value, json};

use crate::client::{Server, TempTree, repo_root};
use crate::diagnostics::{from_check, from_map, rich_workspace};

/// The capabilities of a client that pulls (and accepts refresh requests).
fn pulling() -> Value {
    json!({
        "window": {"workDoneProgress": true},
        "textDocument": {"diagnostic": {"relatedDocumentSupport": false}},
        "workspace": {"diagnostics": {"refreshSupport": true}},
    })
}

/// `workspace/diagnostic` with the previous result ids `previous` (uri → id).
fn workspace_pull(server: &mut Server, previous: &HashMap<String, String>) -> Vec<Value> {
    let previous: Vec<Value> = previous
        .iter()
        .map(|(uri, id)| json!({"uri": uri, "value": id}))
        .collect();
    let report = server
        .request(
            "workspace/diagnostic",
            json!({"identifier": "higraph", "previousResultIds": previous}),
        )
        .expect("workspace/diagnostic answers");
    report["items"].as_array().cloned().expect("items")
}

fn document_pull(server: &mut Server, uri: &str, previous: Option<&str>) -> Value {
    server
        .request(
            "textDocument/diagnostic",
            json!({"textDocument": {"uri": uri}, "identifier": "higraph", "previousResultId": previous}),
        )
        .expect("textDocument/diagnostic answers")
}

fn ids(items: &[Value]) -> HashMap<String, String> {
    items
        .iter()
        .map(|item| {
            (
                item["uri"].as_str().expect("uri").to_owned(),
                item["resultId"].as_str().expect("a result id").to_owned(),
            )
        })
        .collect()
}

fn no_publications(server: &mut Server) {
    server.drain(Duration::from_millis(300));
    assert!(
        server.publications.is_empty(),
        "a pulling client was pushed to: {:?}",
        server.publications
    );
}

#[test]
fn a_pulling_client_gets_checks_diagnostics_with_result_ids_and_no_push() {
    let tree = rich_workspace();
    let (mut server, result) = Server::initialized(&tree.path(), pulling());
    assert_eq!(
        result["capabilities"]["diagnosticProvider"],
        json!({"identifier": "higraph", "interFileDependencies": true, "workspaceDiagnostics": true}),
        "{result}"
    );
    server.wait_for_progress_end();

    // Every workspace file is reported in full; together they are `check`'s diagnostics.
    let first = workspace_pull(&mut server, &HashMap::new());
    assert!(first.iter().all(|item| item["kind"] == "full"), "{first:?}");
    let pulled: HashMap<String, Vec<Value>> = first
        .iter()
        .map(|item| {
            (
                item["uri"].as_str().expect("uri").to_owned(),
                item["items"].as_array().cloned().expect("items"),
            )
        })
        .collect();
    for file in [
        "ventil.higraph",
        "anlage.higraph",
        "graphs/pumpe.higraph",
        "zusatz/doppelt.higraph",
    ] {
        let uri = tree.uri(file);
        assert!(pulled.contains_key(&uri), "{uri} not reported: {first:?}");
    }
    let expected = from_check(&tree.check_json());
    assert_eq!(from_map(&pulled, &tree), expected);

    // Nothing changed: every file is unchanged, with the same id.
    let first_ids = ids(&first);
    let second = workspace_pull(&mut server, &first_ids);
    assert_eq!(second.len(), first.len());
    assert!(
        second.iter().all(|item| item["kind"] == "unchanged"),
        "{second:?}"
    );
    assert_eq!(ids(&second), first_ids);

    // A document pull with the current id is unchanged too.
    let uri = tree.uri("graphs/pumpe.higraph");
    let id = first_ids[&uri].clone();
    let same = document_pull(&mut server, &uri, Some(&id));
    assert_eq!(same, json!({"kind": "unchanged", "resultId": id}));

    // An edit that changes the file's diagnostics gives a new id and the new diagnostics.
    let text = std::fs::read_to_string(tree.path().join("graphs/pumpe.higraph")).expect("read");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    let opened = document_pull(&mut server, &uri, Some(&id));
    assert_eq!(
        opened["kind"], "unchanged",
        "opening changes nothing: {opened}"
    );
    let edited = text.replace("U INIT_SD", "U NICHT_DA");
    assert_ne!(edited, text);
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": edited}]}),
    );
    let changed = document_pull(&mut server, &uri, Some(&id));
    assert_eq!(changed["kind"], "full", "{changed}");
    let new_id = changed["resultId"].as_str().expect("an id").to_owned();
    assert_ne!(new_id, id);
    std::fs::write(tree.path().join("graphs/pumpe.higraph"), &edited).expect("write");
    let mut now = pulled.clone();
    now.insert(
        uri.clone(),
        changed["items"].as_array().cloned().expect("items"),
    );
    assert_eq!(from_map(&now, &tree), from_check(&tree.check_json()));
    assert_ne!(now[&uri], pulled[&uri]);

    // The workspace pull names the changed file in full, with its version, the others
    // unchanged.
    let third = workspace_pull(&mut server, &first_ids);
    for item in &third {
        if item["uri"] == uri.as_str() {
            assert_eq!(item["kind"], "full", "{item}");
            assert_eq!(item["resultId"], new_id.as_str());
            assert_eq!(item["version"], 2);
        } else {
            assert_eq!(item["kind"], "unchanged", "{item}");
        }
    }
    // Undoing the edit gives back the old diagnostics, and so the old id.
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": text}]}),
    );
    let undone = document_pull(&mut server, &uri, Some(&new_id));
    assert_eq!(undone["kind"], "full", "{undone}");
    assert_eq!(undone["resultId"], id.as_str());

    no_publications(&mut server);
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn a_client_that_does_not_pull_is_still_pushed_to() {
    let tree = rich_workspace();
    let (mut server, _) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    server.wait_for_progress_end();
    server.drain(Duration::from_millis(300));
    assert!(!server.publications.is_empty());
    assert_eq!(
        from_map(&server.diagnostics, &tree),
        from_check(&tree.check_json())
    );
    // It may still pull: the same diagnostics.
    let items = workspace_pull(&mut server, &HashMap::new());
    let pulled: HashMap<String, Vec<Value>> = items
        .iter()
        .map(|item| {
            (
                item["uri"].as_str().expect("uri").to_owned(),
                item["items"].as_array().cloned().expect("items"),
            )
        })
        .collect();
    assert_eq!(from_map(&pulled, &tree), from_check(&tree.check_json()));
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn test_failures_are_pulled_until_an_edit_and_the_client_is_asked_to_refresh() {
    let tree = TempTree::new();
    let root = repo_root().join("tests/data/testing");
    for relative in ["higraph.toml", "anlage.higraph", "tests.higraph"] {
        tree.file(
            relative,
            std::fs::read(root.join(relative)).expect("the data"),
        );
    }
    let (mut server, _) = Server::initialized(&tree.path(), pulling());
    server.wait_for_progress_end();
    let uri = tree.uri("tests.higraph");
    let clean = document_pull(&mut server, &uri, None);
    let clean_id = clean["resultId"].as_str().expect("an id").to_owned();
    let hg99 = |report: &Value| {
        report["items"]
            .as_array()
            .into_iter()
            .flatten()
            .filter(|d| d["code"].as_str().is_some_and(|c| c.starts_with("HG99")))
            .count()
    };
    assert_eq!(hg99(&clean), 0, "{clean}");

    server
        .request(
            "workspace/executeCommand",
            json!({"command": "higraph.runTest", "arguments": [{"uri": uri, "name": "Falsch"}]}),
        )
        .expect("the test runs");
    let failed = document_pull(&mut server, &uri, Some(&clean_id));
    assert_eq!(failed["kind"], "full", "{failed}");
    assert_eq!(hg99(&failed), 1, "{failed}");
    let failed_id = failed["resultId"].as_str().expect("an id").to_owned();
    assert_ne!(failed_id, clean_id);
    server.drain(Duration::from_millis(200));
    assert!(
        server
            .server_requests
            .iter()
            .any(|r| r["method"] == "workspace/diagnostic/refresh"),
        "{:?}",
        server.server_requests
    );

    // An edit of another file clears them: back to the clean id.
    let other = tree.uri("anlage.higraph");
    let anlage = std::fs::read_to_string(tree.path().join("anlage.higraph")).expect("read");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": other, "languageId": "higraph", "version": 1, "text": anlage}}),
    );
    server.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": other, "version": 2},
            "contentChanges": [{"text": format!("{anlage}// edited\n")}],
        }),
    );
    let cleared = document_pull(&mut server, &uri, Some(&failed_id));
    assert_eq!(cleared["kind"], "full", "{cleared}");
    assert_eq!(hg99(&cleared), 0, "{cleared}");
    assert_eq!(cleared["resultId"], clean_id.as_str());
    no_publications(&mut server);
    assert_eq!(server.shutdown_and_exit(), 0);
}

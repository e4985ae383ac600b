//! Tests in the editor (`runtime.md` §8, §9.4.4): the `▶ Run test` code lens, the command
//! `higraph.runTest` (the `--format json` object, failures published as diagnostics until a
//! file changes), `higraph/simulate` (the JSON trace) and `higraph/tests`, on the small
//! workspace `tests/data/testing` (a lamp that follows a switch, one passing and one failing
//! test).

use std::time::Duration;

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

fn titles(lenses: &[Value]) -> Vec<&str> {
    lenses
        .iter()
        .map(|lens| lens["command"]["title"].as_str().expect("a title"))
        .collect()
}

fn run_test(server: &mut Server, uri: &str, name: &str) -> Result<Value, Value> {
    server.request(
        "workspace/executeCommand",
        json!({"command": "higraph.runTest", "arguments": [{"uri": uri, "name": name}]}),
    )
}

fn codes(diagnostics: &[Value]) -> Vec<&str> {
    diagnostics
        .iter()
        .filter_map(|d| d["code"].as_str())
        .collect()
}

/// Waits for a publication of `uri` (any version) whose diagnostics satisfy `matches`.
fn wait_for_publication(
    server: &mut Server,
    uri: &str,
    what: &str,
    matches: impl Fn(&[Value]) -> bool,
) -> Vec<Value> {
    let message = server.wait_for(what, |m| {
        m["method"] == "textDocument/publishDiagnostics"
            && m["params"]["uri"] == uri
            && m["params"]["diagnostics"]
                .as_array()
                .is_some_and(|d| matches(d))
    });
    message["params"]["diagnostics"]
        .as_array()
        .cloned()
        .unwrap_or_default()
}

#[test]
fn the_lens_runs_a_test_whose_failures_are_published_until_an_edit() {
    let tree = workspace();
    let (mut server, result) = Server::initialized(
        &tree.path(),
        json!({
            "window": {"workDoneProgress": true},
            "workspace": {"codeLens": {"refreshSupport": true}},
        }),
    );
    let capabilities = &result["capabilities"];
    assert_eq!(
        capabilities["executeCommandProvider"]["commands"],
        json!(["higraph.runTest", "higraph.build"]),
        "{result}"
    );
    assert!(capabilities["codeLensProvider"].is_object(), "{result}");
    server.wait_for_progress_end();

    let uri = tree.uri("tests.higraph");
    let text = std::fs::read_to_string(tree.path().join("tests.higraph")).expect("read");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    let clean = server.wait_for_diagnostics(&uri, 1);
    assert!(
        codes(&clean).iter().all(|c| !c.starts_with("HG99")),
        "{clean:?}"
    );

    // One lens per test header, on the header's line, before any run.
    let before = lenses(&mut server, &uri);
    assert_eq!(titles(&before), ["▶ Run test", "▶ Run test"]);
    assert_eq!(before[0]["range"]["start"]["line"], 1);
    assert_eq!(before[1]["range"]["start"]["line"], 9);
    let command = &before[0]["command"];
    assert_eq!(command["command"], "higraph.runTest");
    assert_eq!(
        command["arguments"],
        json!([{"uri": uri, "name": "Einschalten"}])
    );

    // Clicking the lens: the editor executes its command with its arguments.
    let passed = server
        .request(
            "workspace/executeCommand",
            json!({"command": command["command"], "arguments": command["arguments"]}),
        )
        .expect("the test runs");
    assert_eq!(passed["name"], "Einschalten", "{passed}");
    assert_eq!(passed["file"], "tests.higraph", "{passed}");
    assert_eq!(passed["result"], "passed", "{passed}");
    assert_eq!(passed["cycles"], 2, "{passed}");
    assert_eq!(passed["time_ms"], 20, "{passed}");
    assert_eq!(passed["failures"], json!([]), "{passed}");
    assert_eq!(
        passed["range"]["start"],
        json!({"line": 1, "character": 5}),
        "the name"
    );

    let failed = run_test(&mut server, &uri, "Falsch").expect("the test runs");
    assert_eq!(failed["result"], "failed", "{failed}");
    let failure = &failed["failures"][0];
    assert_eq!(failure["code"], "HG9901", "{failed}");
    assert_eq!(failure["file"], "tests.higraph", "{failed}");
    assert_eq!(
        failure["range"],
        json!({"start": {"line": 12, "character": 9}, "end": {"line": 12, "character": 14}}),
        "the failure is at the expected expression: {failed}"
    );
    assert_eq!(failure["cycle"], 2, "{failed}");
    assert_eq!(failure["values"], json!({"Lampe": false}), "{failed}");
    let message = failure["message"].as_str().expect("a message");
    assert!(
        message.starts_with("expect failed: the lamp is on: at cycle 2"),
        "{message}"
    );

    // HG9901 is published with the file's own diagnostics, as an error at the expression.
    let published = wait_for_publication(&mut server, &uri, "HG9901 published", |d| {
        d.iter().any(|d| d["code"] == "HG9901")
    });
    let hg9901 = published
        .iter()
        .find(|d| d["code"] == "HG9901")
        .expect("HG9901");
    assert_eq!(hg9901["severity"], 1);
    assert_eq!(hg9901["range"], failure["range"]);
    assert_eq!(hg9901["message"], failure["message"]);

    // The lenses show the results, and the server asked the client to refresh them.
    assert_eq!(
        titles(&lenses(&mut server, &uri)),
        ["▶ Run test — passed", "▶ Run test — failed (1)"]
    );
    server.drain(Duration::from_millis(200));
    assert!(
        server
            .server_requests
            .iter()
            .any(|r| r["method"] == "workspace/codeLens/refresh"),
        "{:?}",
        server.server_requests
    );

    // Running it again replaces its failures (one HG9901, not two).
    server.drain(Duration::from_millis(200));
    server.notifications.clear();
    run_test(&mut server, &uri, "Falsch").expect("the test runs again");
    let again = wait_for_publication(&mut server, &uri, "HG9901 published again", |d| {
        d.iter().any(|d| d["code"] == "HG9901")
    });
    assert_eq!(
        codes(&again).iter().filter(|c| **c == "HG9901").count(),
        1,
        "{again:?}"
    );

    // An edit of any workspace file removes them, and the lenses forget the results.
    server.drain(Duration::from_millis(200));
    server.notifications.clear();
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
    wait_for_publication(&mut server, &uri, "HG9901 removed", |d| {
        d.iter().all(|d| d["code"] != "HG9901")
    });
    assert_eq!(
        titles(&lenses(&mut server, &uri)),
        ["▶ Run test", "▶ Run test"]
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn simulate_answers_the_trace_and_tests_lists_the_tests() {
    let tree = workspace();
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("tests.higraph");

    let listed = server
        .request("higraph/tests", json!({}))
        .expect("higraph/tests answers");
    let names: Vec<&str> = listed["tests"]
        .as_array()
        .expect("tests")
        .iter()
        .map(|t| t["name"].as_str().expect("a name"))
        .collect();
    assert_eq!(names, ["Einschalten", "Falsch"], "{listed}");
    assert_eq!(listed["tests"][0]["uri"], uri.as_str(), "{listed}");
    assert_eq!(listed["tests"][1]["range"]["start"]["line"], 9, "{listed}");

    // Without a URI: the test of that name (names are case-insensitive).
    let trace = server
        .request("higraph/simulate", json!({"name": "einschalten"}))
        .expect("higraph/simulate answers");
    assert_eq!(trace["version"], 1, "{trace}");
    assert_eq!(trace["test"], "Einschalten", "{trace}");
    assert_eq!(trace["file"], "tests.higraph", "{trace}");
    assert_eq!(trace["result"], "passed", "{trace}");
    assert_eq!(trace["run"], json!(["Anlage"]), "{trace}");
    let cycles = trace["cycles"].as_array().expect("cycles");
    assert_eq!(cycles.len(), 2, "{trace}");
    let second = &cycles[1]["instances"][0];
    assert_eq!(second["instance"], "Flur", "{trace}");
    assert_eq!(second["state"], 1, "{trace}");
    assert_eq!(
        second["fired"],
        json!({"kind": "normal", "from": 0, "to": 1, "prio": 1}),
        "{trace}"
    );
    // The fired transition is the one the picture names `0->1:1`.
    let svg = server
        .request("higraph/render", json!({"name": "Schalter"}))
        .expect("render")["svg"]
        .as_str()
        .expect("an svg")
        .to_owned();
    assert!(svg.contains("data-trans=\"0-&gt;1:1\""), "{svg}");
    assert!(svg.contains("data-state=\"1\""), "{svg}");

    // With a URI, and a failing test: the failures are in the trace.
    let failing = server
        .request("higraph/simulate", json!({"name": "Falsch", "uri": uri}))
        .expect("higraph/simulate answers");
    assert_eq!(failing["result"], "failed", "{failing}");
    assert_eq!(failing["failures"][0]["code"], "HG9901", "{failing}");

    // Unknown tests and commands are refused.
    let unknown = server
        .request("higraph/simulate", json!({"name": "Nichts"}))
        .expect_err("no such test");
    assert!(
        unknown["message"]
            .as_str()
            .is_some_and(|m| m.contains("Nichts")),
        "{unknown}"
    );
    let no_test = run_test(&mut server, &uri, "Nichts").expect_err("no such test");
    assert_eq!(no_test["code"], -32803, "{no_test}");
    let no_command = server
        .request(
            "workspace/executeCommand",
            json!({"command": "higraph.other", "arguments": []}),
        )
        .expect_err("no such command");
    assert_eq!(no_command["code"], -32602, "{no_command}");
    let no_argument = server
        .request(
            "workspace/executeCommand",
            json!({"command": "higraph.runTest", "arguments": []}),
        )
        .expect_err("no argument");
    assert_eq!(no_argument["code"], -32602, "{no_argument}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn a_long_test_run_is_cancelled_by_the_client_or_an_edit() {
    let tree = workspace();
    tree.file(
        "lang.higraph",
        "test Lang \"five million cycles\" <\n  run Anlage;\n  step 1000000;\n  step 1000000;\n  step 1000000;\n  step 1000000;\n  step 1000000;\n>\n",
    );
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("lang.higraph");

    // `$/cancelRequest`: the request ends (RequestCancelled) and the server goes on.
    let id = server.send_request(
        "workspace/executeCommand",
        json!({"command": "higraph.runTest", "arguments": [{"uri": uri, "name": "Lang"}]}),
    );
    std::thread::sleep(Duration::from_millis(300));
    server.notify("$/cancelRequest", json!({"id": id}));
    let cancelled = server.response(&id).expect_err("cancelled");
    assert_eq!(cancelled["code"], -32800, "{cancelled}");

    // An edit while it runs: ContentModified, and the edit is applied at once.
    let id = server.send_request(
        "workspace/executeCommand",
        json!({"command": "higraph.runTest", "arguments": [{"uri": uri, "name": "Lang"}]}),
    );
    std::thread::sleep(Duration::from_millis(300));
    let other = tree.uri("anlage.higraph");
    let anlage = std::fs::read_to_string(tree.path().join("anlage.higraph")).expect("read");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": other, "languageId": "higraph", "version": 1, "text": format!("{anlage}// edited\n")}}),
    );
    let modified = server.response(&id).expect_err("cancelled by the edit");
    assert_eq!(modified["code"], -32801, "{modified}");
    server.wait_for_diagnostics(&other, 1);
    assert_eq!(server.shutdown_and_exit(), 0);
}

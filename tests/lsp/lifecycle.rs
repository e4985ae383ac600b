//! The lifecycle of LSP 3.17: `initialize` (capabilities, position encoding), indexing with
//! `$/progress`, `shutdown` and `exit` with their exit statuses, and what is refused before
//! `initialize` and after `shutdown`.

use serde_json::{Value, json};

use crate::client::{Server, TempTree, file_uri};

fn small_workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file(
            "a.higraph",
            "graph A <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
        );
    tree
}

#[test]
fn initialize_announces_incremental_sync_and_utf16() {
    let tree = small_workspace();
    let (server, result) = Server::initialized(&tree.path(), json!({}));
    let capabilities = &result["capabilities"];
    assert_eq!(capabilities["positionEncoding"], "utf-16", "{result}");
    assert_eq!(capabilities["textDocumentSync"]["change"], 2, "{result}");
    assert_eq!(
        capabilities["textDocumentSync"]["openClose"], true,
        "{result}"
    );
    assert_eq!(result["serverInfo"]["name"], "higraph-lsp");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn without_arguments_and_with_stdio_the_binary_is_the_server() {
    let tree = small_workspace();
    for args in [&[][..], &["--stdio"][..], &["lsp"][..]] {
        let mut server = Server::start_with(&tree.path(), args);
        let result = server.request(
            "initialize",
            json!({"processId": null, "rootUri": file_uri(&tree.path()), "capabilities": {}}),
        );
        assert!(result.is_ok(), "{args:?}: {result:?}");
        server.notify("initialized", json!({}));
        assert_eq!(server.shutdown_and_exit(), 0, "{args:?}");
    }
}

#[test]
fn exit_without_shutdown_ends_with_status_1() {
    let tree = small_workspace();
    let (mut server, _) = Server::initialized(&tree.path(), json!({}));
    server.notify("exit", Value::Null);
    assert_eq!(server.exit_status(), 1);
}

#[test]
fn exit_before_initialize_ends_with_status_1() {
    let tree = small_workspace();
    let mut server = Server::start(&tree.path());
    server.notify("exit", Value::Null);
    assert_eq!(server.exit_status(), 1);
}

#[test]
fn the_end_of_the_input_ends_the_server_with_status_1() {
    let tree = small_workspace();
    let (mut server, _) = Server::initialized(&tree.path(), json!({}));
    server.close_stdin();
    assert_eq!(server.exit_status(), 1);
}

#[test]
fn requests_before_initialize_are_refused_with_server_not_initialized() {
    let tree = small_workspace();
    let mut server = Server::start(&tree.path());
    let error = server
        .request("workspace/symbol", json!({"query": ""}))
        .expect_err("refused");
    assert_eq!(error["code"], -32002, "{error}");
    // Notifications before `initialize` are dropped, and initialization still works.
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": tree.uri("a.higraph"), "languageId": "higraph", "version": 1, "text": ""}}),
    );
    let result = server.request(
        "initialize",
        json!({"processId": null, "rootUri": file_uri(&tree.path()), "capabilities": {}}),
    );
    assert!(result.is_ok(), "{result:?}");
    server.notify("initialized", json!({}));
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn a_second_initialize_and_requests_after_shutdown_are_invalid() {
    let tree = small_workspace();
    let (mut server, _) = Server::initialized(&tree.path(), json!({}));
    let again = server
        .request("initialize", json!({"capabilities": {}}))
        .expect_err("refused");
    assert_eq!(again["code"], -32600, "{again}");
    assert_eq!(server.request("shutdown", Value::Null), Ok(Value::Null));
    let after = server
        .request("shutdown", Value::Null)
        .expect_err("refused");
    assert_eq!(after["code"], -32600, "{after}");
    server.notify("exit", Value::Null);
    assert_eq!(server.exit_status(), 0);
}

#[test]
fn indexing_reports_progress_and_registers_file_watchers() {
    let tree = small_workspace();
    let (mut server, _) = Server::initialized(
        &tree.path(),
        json!({
            "window": {"workDoneProgress": true},
            "workspace": {"didChangeWatchedFiles": {"dynamicRegistration": true}},
        }),
    );
    let begin = server.wait_for("progress begin", |m| {
        m["method"] == "$/progress" && m["params"]["value"]["kind"] == "begin"
    });
    let token = begin["params"]["token"].clone();
    server.wait_for_progress_end();
    let methods: Vec<&str> = server
        .server_requests
        .iter()
        .filter_map(|r| r["method"].as_str())
        .collect();
    assert!(
        methods.contains(&"window/workDoneProgress/create"),
        "{methods:?}"
    );
    assert!(
        methods.contains(&"client/registerCapability"),
        "{methods:?}"
    );
    let create = server
        .server_requests
        .iter()
        .find(|r| r["method"] == "window/workDoneProgress/create")
        .expect("a create request");
    assert_eq!(create["params"]["token"], token);
    let registration = server
        .server_requests
        .iter()
        .find(|r| r["method"] == "client/registerCapability")
        .expect("a registration");
    let watchers = &registration["params"]["registrations"][0]["registerOptions"]["watchers"];
    let patterns: Vec<&str> = watchers
        .as_array()
        .expect("watchers")
        .iter()
        .filter_map(|w| w["globPattern"].as_str())
        .collect();
    assert_eq!(patterns, ["**/*.higraph", "**/higraph.toml", "**/*.sdf"]);
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn without_client_support_there_is_no_progress_and_no_registration() {
    let tree = small_workspace();
    let (mut server, _) = Server::initialized(&tree.path(), json!({}));
    // A request is answered after indexing (it sees the loaded workspace).
    let _ = server.request("workspace/symbol", json!({"query": ""}));
    server.drain(std::time::Duration::from_millis(200));
    assert!(
        server.server_requests.is_empty(),
        "{:?}",
        server.server_requests
    );
    assert!(
        server
            .notifications
            .iter()
            .all(|m| m["method"] != "$/progress"),
        "{:?}",
        server.notifications
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

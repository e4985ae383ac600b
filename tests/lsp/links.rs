//! Document links and `codeDescription.href` end to end (issue 15, item 4): symbol-table paths
//! in `higraph.toml` link to the file, codes in `higraph-allow` comments and on published
//! diagnostics link to the rule's page under the `rulesBaseUri` base.

use std::path::Path;

use serde_json::{Value, json};

use crate::client::{Server, TempTree, file_uri};

/// A workspace with one symbol table inside it, one entry outside it, and an allow comment
/// naming a known and an unknown code (the unknown one is HG6104, a published diagnostic).
fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file(
        "higraph.toml",
        "[workspace]\nsymbols = [\"plc/symbols.sdf\", \"../outside.sdf\"]\n",
    )
    .file(
        "plc/symbols.sdf",
        "\"Start\",\"E 0.0\",\"BOOL\",\"start button\"\n",
    )
    .file("main.higraph", "// higraph-allow: HG1210, HG9999\n");
    tree
}

/// Starts a server on `root` with `initializationOptions` and whether the client shows
/// `codeDescription`; waits until the workspace is indexed.
fn start(root: &Path, options: Value, code_description: bool) -> Server {
    let mut server = Server::start(root);
    server
        .request(
            "initialize",
            json!({
                "processId": null,
                "rootUri": file_uri(root),
                "workspaceFolders": [{"uri": file_uri(root), "name": "ws"}],
                "initializationOptions": options,
                "capabilities": {
                    "window": {"workDoneProgress": true},
                    "textDocument": {"publishDiagnostics": {"codeDescriptionSupport": code_description}},
                },
            }),
        )
        .expect("initialize succeeds");
    server.notify("initialized", json!({}));
    server.wait_for_progress_end();
    server
}

fn links(server: &mut Server, uri: &str) -> Vec<Value> {
    server
        .request(
            "textDocument/documentLink",
            json!({"textDocument": {"uri": uri}}),
        )
        .expect("documentLink answers")
        .as_array()
        .cloned()
        .unwrap_or_default()
}

/// The published diagnostics of `uri` once they are not empty.
fn published(server: &mut Server, uri: &str) -> Vec<Value> {
    let message = server.wait_for(&format!("diagnostics of {uri}"), |m| {
        m["method"] == "textDocument/publishDiagnostics"
            && m["params"]["uri"] == uri
            && m["params"]["diagnostics"]
                .as_array()
                .is_some_and(|d| !d.is_empty())
    });
    message["params"]["diagnostics"]
        .as_array()
        .cloned()
        .unwrap_or_default()
}

fn range(line: u64, start: u64, end: u64) -> Value {
    json!({"start": {"line": line, "character": start}, "end": {"line": line, "character": end}})
}

#[test]
fn links_and_code_descriptions_under_the_configured_base() {
    let tree = workspace();
    let base = "https://example.org/higraph/docs/rules";
    let mut server = start(&tree.path(), json!({"rulesBaseUri": base}), true);

    let toml = links(&mut server, &tree.uri("higraph.toml"));
    assert_eq!(toml.len(), 1, "{toml:?}");
    assert_eq!(toml[0]["range"], range(1, 12, 27));
    assert_eq!(toml[0]["target"], tree.uri("plc/symbols.sdf").as_str());

    let source = tree.uri("main.higraph");
    let codes = links(&mut server, &source);
    assert_eq!(codes.len(), 1, "{codes:?}");
    assert_eq!(codes[0]["range"], range(0, 18, 24));
    assert_eq!(codes[0]["target"], format!("{base}/HG1210.md").as_str());

    let diagnostics = published(&mut server, &source);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert_eq!(diagnostics[0]["code"], "HG6104");
    assert_eq!(
        diagnostics[0]["codeDescription"]["href"],
        format!("{base}/HG6104.md").as_str()
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn default_base_is_the_workspace_docs_folder_and_needs_client_support() {
    let tree = workspace();
    tree.file("docs/rules/HG1210.md", "# HG1210\n");
    let mut server = start(&tree.path(), Value::Null, false);
    let source = tree.uri("main.higraph");
    let codes = links(&mut server, &source);
    assert_eq!(codes.len(), 1, "{codes:?}");
    assert_eq!(
        codes[0]["target"],
        format!("{}/HG1210.md", tree.uri("docs/rules")).as_str()
    );
    // The client does not show code descriptions: none are sent.
    let diagnostics = published(&mut server, &source);
    assert_eq!(diagnostics[0]["code"], "HG6104");
    assert!(
        diagnostics[0].get("codeDescription").is_none(),
        "{diagnostics:?}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn no_rule_links_without_a_base() {
    let tree = workspace();
    let mut server = start(&tree.path(), json!({"rulesBaseUri": ""}), true);
    assert!(links(&mut server, &tree.uri("main.higraph")).is_empty());
    // File links do not depend on the base.
    assert_eq!(links(&mut server, &tree.uri("higraph.toml")).len(), 1);
    let diagnostics = published(&mut server, &tree.uri("main.higraph"));
    assert!(
        diagnostics[0].get("codeDescription").is_none(),
        "{diagnostics:?}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

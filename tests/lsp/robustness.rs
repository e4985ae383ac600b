//! Robustness (`tooling.md` §4): whatever arrives — garbage, unknown methods, bad
//! parameters, positions out of range, changes to documents that are not open — every request
//! gets exactly one answer, no handler fails internally, and the server keeps working.
//! Cancellation with `$/cancelRequest` and by edits.

use std::time::Duration;

use serde_json::{Value, json};

use crate::client::{Rng, Server, TempTree};

const GRAPH: &str = "// Ventil für Öl 😀\ngraph Ventil <\n  in < Oben : BOOL; >\n  in_out < IM_Ab : BOOL msg in; >\n  state 0 < C: U Oben; >\n  state 1 \"Oben\" < >\n  trans any->0 < U INIT_SD; >\n  trans 0->1 prio 1 < U IM_Ab; !: R IM_Ab; >\n  trans 1->0 < U Oben; >\n>\n";
const GROUP: &str = "group Anlage fc FC 1 db DB 1 <\n  instance V : Ventil < Oben := E 0.0; >\n>\n";

/// Text fragments random edits insert: valid pieces, broken ones, non-ASCII, line breaks.
const FRAGMENTS: &[&str] = &[
    "",
    "state 9 < >",
    "<",
    ">",
    ";",
    " U Oben;",
    "ä😀",
    "\r\n",
    "\n",
    "trans 0->1 < >",
    "$",
    "\"",
    "// ",
    "graph",
    "instance W : Ventil < >",
    "V.IM_Ab",
    "#",
    "\t",
    "prio 300",
];

/// Message bodies that are not JSON, not an object, or not a JSON-RPC message.
const UNREADABLE: &[&[u8]] = &[
    b"{oops",
    b"[1,2,3]",
    b"\"string\"",
    b"{}",
    b"{\"jsonrpc\":\"1.0\",\"method\":\"initialized\"}",
    b"\xff\xfe{",
];

/// Request methods with (mostly) valid parameters at a position.
const POSITION_METHODS: &[&str] = &[
    "textDocument/hover",
    "textDocument/completion",
    "textDocument/definition",
    "textDocument/references",
    "textDocument/documentHighlight",
    "textDocument/prepareRename",
    "textDocument/rename",
    "textDocument/prepareCallHierarchy",
];

const DOCUMENT_METHODS: &[&str] = &[
    "textDocument/documentSymbol",
    "textDocument/foldingRange",
    "textDocument/documentLink",
    "textDocument/semanticTokens/full",
    "textDocument/formatting",
    "textDocument/semanticTokens/full/delta",
    "textDocument/codeLens",
];

const RANGE_METHODS: &[&str] = &[
    "textDocument/semanticTokens/range",
    "textDocument/inlayHint",
    "textDocument/codeAction",
    "textDocument/rangeFormatting",
];

/// The state of the random conversation.
struct Session {
    server: Server,
    rng: Rng,
    /// URIs that may be named (open, closed, never opened, not files).
    uris: Vec<String>,
    /// Open documents: URI and version.
    open: Vec<(String, i64)>,
    /// Request ids sent, to be answered exactly once each.
    ids: Vec<Value>,
    next_id: u64,
    /// How many answers with a `null` id the garbage should get.
    null_id_errors: usize,
}

impl Session {
    fn fresh_id(&mut self) -> Value {
        self.next_id += 1;
        let id = if self.rng.chance(30) {
            json!(format!("r{}", self.next_id))
        } else {
            json!(1000 + self.next_id)
        };
        self.ids.push(id.clone());
        id
    }

    fn position(&mut self) -> Value {
        let line = if self.rng.chance(10) {
            10_000
        } else {
            self.rng.below(14)
        };
        let character = if self.rng.chance(10) {
            100_000
        } else {
            self.rng.below(50)
        };
        json!({"line": line, "character": character})
    }

    fn range(&mut self) -> Value {
        json!({"start": self.position(), "end": self.position()})
    }

    fn any_uri(&mut self) -> String {
        self.rng.pick(&self.uris).clone()
    }

    fn request(&mut self, method: &str, params: Value) {
        let id = self.fresh_id();
        self.server
            .send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
    }

    /// Sends one random message.
    fn step(&mut self) {
        match self.rng.below(20) {
            // A valid ranged edit of an open document (maybe with a reversed range).
            0..=3 if !self.open.is_empty() => {
                let at = self.rng.below(self.open.len());
                self.open[at].1 += 1;
                let (uri, version) = self.open[at].clone();
                let text = *self.rng.pick(FRAGMENTS);
                let range = self.range();
                self.server.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": uri, "version": version},
                           "contentChanges": [{"range": range, "text": text}]}),
                );
            }
            // A change to a document that is not open, or with a stale version.
            4 => {
                let uri = self.any_uri();
                let range = self.range();
                self.server.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": uri, "version": 1},
                           "contentChanges": [{"range": range, "text": "x"}]}),
                );
            }
            // Open or close.
            5 => {
                let uri = self.any_uri();
                if let Some(at) = self.open.iter().position(|(u, _)| *u == uri) {
                    self.open.remove(at);
                    self.server.notify(
                        "textDocument/didClose",
                        json!({"textDocument": {"uri": uri}}),
                    );
                } else {
                    let text = if self.rng.chance(50) { GRAPH } else { GROUP };
                    self.server.notify(
                        "textDocument/didOpen",
                        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
                    );
                    if uri.starts_with("file:") {
                        self.open.push((uri, 1));
                    }
                }
            }
            // Requests at a position, on a document, over a range.
            6..=8 => {
                let method = *self.rng.pick(POSITION_METHODS);
                let uri = self.any_uri();
                let position = self.position();
                let params = json!({
                    "textDocument": {"uri": uri},
                    "position": position,
                    "context": {"includeDeclaration": true},
                    "newName": *self.rng.pick(&["Neu", "", "1abc", "state", "IM_Auf"]),
                });
                self.request(method, params);
            }
            9 => {
                let method = *self.rng.pick(DOCUMENT_METHODS);
                let uri = self.any_uri();
                self.request(
                    method,
                    json!({"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": true}, "previousResultId": "1"}),
                );
            }
            10 => {
                let method = *self.rng.pick(RANGE_METHODS);
                let uri = self.any_uri();
                let range = self.range();
                self.request(
                    method,
                    json!({"textDocument": {"uri": uri}, "range": range, "context": {"diagnostics": []}, "options": {"tabSize": 2, "insertSpaces": true}}),
                );
            }
            // A count lens to resolve, at any position, of any kind.
            11 if self.rng.chance(30) => {
                let uri = self.any_uri();
                let kind = *self.rng.pick(&[0, 4, 6, 7, 1000]);
                let document = *self.rng.pick(&[0, 1, 2, 3, u64::MAX]);
                let data = if self.rng.chance(20) {
                    json!({"uri": uri, "kind": "stateIncoming"})
                } else {
                    json!([document, kind])
                };
                let range = self.range();
                self.request("codeLens/resolve", json!({"range": range, "data": data}));
            }
            11 => {
                let uri = self.any_uri();
                let positions = vec![self.position(), self.position()];
                self.request(
                    "textDocument/selectionRange",
                    json!({"textDocument": {"uri": uri}, "positions": positions}),
                );
            }
            12 => {
                let query = *self.rng.pick(&["", "V", "Ventil.1", "zzz"]);
                self.request("workspace/symbol", json!({"query": query}));
            }
            // Bad parameters for a known method.
            13 => {
                let method = *self.rng.pick(POSITION_METHODS);
                let params = self
                    .rng
                    .pick(&[
                        json!("x"),
                        json!({}),
                        json!([1, 2]),
                        json!({"textDocument": 5}),
                    ])
                    .clone();
                self.request(method, params);
            }
            // Unknown methods, `$/` requests, notification methods sent as requests.
            14 => {
                let method = *self.rng.pick(&[
                    "higraph/unknown",
                    "$/unknown",
                    "textDocument/didSave",
                    "workspace/executeCommand",
                ]);
                self.request(method, json!({}));
            }
            15 => {
                self.server.notify("$/unknownNotification", json!({}));
                self.server.notify("unknown/notification", json!(null));
            }
            // Cancel a request that may be running, finished or never existed.
            16 => {
                let id = match self.ids.last() {
                    Some(id) if self.rng.chance(80) => id.clone(),
                    _ => json!(99_999),
                };
                self.server.notify("$/cancelRequest", json!({"id": id}));
            }
            // Unreadable bodies: not JSON, not an object, not a JSON-RPC message.
            17 => {
                let body = *self.rng.pick(UNREADABLE);
                let mut frame = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
                frame.extend_from_slice(body);
                self.server.send_raw(&frame);
                self.null_id_errors += 1;
            }
            // A header without a length.
            18 => {
                self.server.send_raw(b"X-Garbage: yes\r\n\r\n");
                self.null_id_errors += 1;
            }
            // A response to a request the server never sent.
            _ => {
                self.server
                    .send(&json!({"jsonrpc": "2.0", "id": 424_242, "result": null}));
            }
        }
    }
}

fn random_session(seed: u64, steps: usize) {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("ventil.higraph", GRAPH)
        .file("anlage.higraph", GROUP);
    let server = Server::indexed(&tree.path());
    let uris = vec![
        tree.uri("ventil.higraph"),
        tree.uri("anlage.higraph"),
        tree.uri("neu.higraph"),
        tree.uri("sub/zwei.higraph"),
        tree.uri("higraph.toml"),
        "untitled:Untitled-1".to_owned(),
        "file:///elsewhere/x.higraph".to_owned(),
    ];
    let mut session = Session {
        server,
        rng: Rng(seed),
        uris,
        open: Vec::new(),
        ids: Vec::new(),
        next_id: 0,
        null_id_errors: 0,
    };
    for _ in 0..steps {
        session.step();
    }

    let Session {
        mut server,
        ids,
        null_id_errors,
        ..
    } = session;
    for id in &ids {
        if let Err(error) = server.response(id) {
            assert_ne!(
                error["code"], -32603,
                "seed {seed}: internal error for {id}: {error}"
            );
        }
    }
    server.wait_for_null_id_errors(null_id_errors);
    server.drain(Duration::from_millis(200));
    assert_eq!(server.null_id_errors.len(), null_id_errors, "seed {seed}");
    assert!(
        server.answered_twice.is_empty(),
        "seed {seed}: {:?}",
        server.answered_twice
    );
    let internal: Vec<&Value> = server
        .notifications
        .iter()
        .filter(|m| {
            m["method"] == "window/logMessage"
                && m["params"]["message"]
                    .as_str()
                    .is_some_and(|text| text.contains("internal error"))
        })
        .collect();
    assert!(internal.is_empty(), "seed {seed}: {internal:?}");

    // Still working: a new document gets its diagnostics, requests are answered.
    let uri = tree.uri("danach.higraph");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": "graph Danach <\n> $\n"}}),
    );
    let published = server.wait_for_diagnostics(&uri, 1);
    assert!(
        published.iter().any(|d| d["code"] == "HG0009"),
        "seed {seed}: {published:?}"
    );
    let symbols = server.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    assert!(symbols.is_ok(), "seed {seed}: {symbols:?}");
    assert_eq!(server.shutdown_and_exit(), 0, "seed {seed}");
}

#[test]
fn random_valid_and_broken_messages_get_answers_and_the_server_survives() {
    for seed in [1, 7, 2026] {
        random_session(seed, 400);
    }
}

#[test]
fn malformed_messages_get_parse_errors_and_reading_goes_on() {
    let tree = TempTree::new();
    let mut server = Server::indexed(&tree.path());
    server.send_raw(b"Content-Length: 5\r\n\r\n{oops");
    server.wait_for_null_id_errors(1);
    assert_eq!(
        server.null_id_errors[0]["error"]["code"], -32700,
        "{:?}",
        server.null_id_errors
    );
    server.send_raw(b"Content-Length: 2\r\n\r\n[]");
    server.wait_for_null_id_errors(2);
    assert_eq!(
        server.null_id_errors[1]["error"]["code"], -32600,
        "{:?}",
        server.null_id_errors
    );
    // An invalid request with a readable id is answered with that id.
    server.send(&json!({"jsonrpc": "1.0", "id": 77, "method": "shutdown"}));
    let error = server.response(&json!(77)).expect_err("refused");
    assert_eq!(error["code"], -32600, "{error}");
    let unknown = server
        .request("higraph/unknown", json!({}))
        .expect_err("unknown");
    assert_eq!(unknown["code"], -32601, "{unknown}");
    let dollar = server.request("$/unknown", json!({})).expect_err("unknown");
    assert_eq!(dollar["code"], -32601, "{dollar}");
    let bad = server
        .request("textDocument/documentSymbol", json!({"textDocument": 3}))
        .expect_err("bad params");
    assert_eq!(bad["code"], -32602, "{bad}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// A workspace large enough that requests take a moment: the max-graph workload.
fn large_workspace() -> (TempTree, String) {
    let tree = TempTree::new();
    let mut text = String::from(
        "graph Gross <\n  in < Oben : BOOL; >\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n",
    );
    for state in 1..250 {
        text.push_str(&format!(
            "  state {state} \"S{state}\" < C: U Oben; = Oben; >\n"
        ));
        text.push_str(&format!(
            "  trans {}->{state} < U Oben; U Oben; O Oben; >\n",
            state - 1
        ));
    }
    text.push_str(">\n");
    tree.file("gross.higraph", &text);
    (tree, text)
}

#[test]
fn cancelled_requests_are_answered_once_with_a_result_or_request_cancelled() {
    let (tree, _) = large_workspace();
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("gross.higraph");
    for _ in 0..5 {
        let id = server.send_request(
            "textDocument/semanticTokens/full",
            json!({"textDocument": {"uri": uri}}),
        );
        server.notify("$/cancelRequest", json!({"id": id}));
        match server.response(&id) {
            Ok(result) => assert!(result["data"].is_array(), "{result}"),
            Err(error) => assert_eq!(error["code"], -32800, "{error}"),
        }
    }
    server.drain(Duration::from_millis(100));
    assert!(
        server.answered_twice.is_empty(),
        "{:?}",
        server.answered_twice
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn an_edit_during_a_request_answers_it_content_modified_or_with_a_result() {
    let (tree, text) = large_workspace();
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("gross.higraph");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    for version in 2..8 {
        let id = server.send_request("workspace/symbol", json!({"query": "S"}));
        server.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version},
                   "contentChanges": [{"range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 0}}, "text": "  // x\n"}]}),
        );
        match server.response(&id) {
            Ok(result) => assert!(result.is_array(), "{result}"),
            Err(error) => assert_eq!(error["code"], -32801, "{error}"),
        }
    }
    // Afterwards requests see the edited text.
    let symbols = server
        .request(
            "textDocument/documentSymbol",
            json!({"textDocument": {"uri": uri}}),
        )
        .expect("document symbols");
    assert_eq!(symbols[0]["range"]["start"]["line"], 0, "{symbols}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

//! A seeded random language-server session: a few thousand messages — opens, closes, edits
//! at random places (with garbage), requests at random positions, cancellations, unknown
//! methods — after which the diagnostics the server published for every file must equal
//! those of `check --format json` on the same final texts written to disk.

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::client::{Rng, Server, TempTree, file_uri};

const GRAPH: &str = "// Ventil für Öl 😀\ngraph Ventil <\n  in < Oben : BOOL; >\n  in_out < IM_Ab : BOOL msg in; >\n  state 0 < C: U Oben; >\n  state 1 \"Oben\" < >\n  trans any->0 < U INIT_SD; >\n  trans 0->1 prio 1 < U IM_Ab; !: R IM_Ab; >\n  trans 1->0 < U Oben; >\n>\n";
const GROUP: &str = "group Anlage fc FC 1 db DB 1 <\n  instance V : Ventil < Oben := E 0.0; >\n>\n";
const CHART: &str = "chart Mischer <\n  sequencer S <\n    step Start < >\n    trans T1 < Oben >\n    step Fuellen < >\n  >\n>\n";

/// What random edits insert: valid pieces, broken ones, non-ASCII, line breaks.
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
    "(((",
    "not not",
    "}{",
    "S5T#",
];

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
    "textDocument/semanticTokens/full",
    "textDocument/formatting",
    "textDocument/inlayHint",
    "textDocument/codeAction",
    "textDocument/codeLens",
];

/// The kinds of count lenses (`codeLens/resolve` data: their numbers), and some that are
/// none.
const LENS_KINDS: &[u64] = &[0, 1, 2, 3, 4, 5, 6, 7, 255];

/// One workspace file as the session sees it.
struct Doc {
    relative: &'static str,
    uri: String,
    /// On disk (and what the server falls back to when the document is closed).
    disk: Option<String>,
    /// The client's text and version while the document is open.
    open: Option<(String, i64)>,
    /// The last version ever sent for this URI (versions only grow).
    version: i64,
}

impl Doc {
    /// The text the analysis sees.
    fn text(&self) -> Option<&str> {
        self.open
            .as_ref()
            .map(|(text, _)| text.as_str())
            .or(self.disk.as_deref())
    }
}

/// The UTF-16 position of byte `offset` in `text` (lines end at `\n`; the session never
/// leaves a lone `\r`).
fn position(text: &str, offset: usize) -> Value {
    let before = &text[..offset];
    let line = before.matches('\n').count();
    let start = before.rfind('\n').map_or(0, |at| at + 1);
    let character: usize = before[start..].chars().map(char::len_utf16).sum();
    json!({"line": line, "character": character})
}

/// A random byte offset of `text` that is a character boundary and not between `\r` and
/// `\n`.
fn offset(rng: &mut Rng, text: &str) -> usize {
    let mut at = rng.below(text.len() + 1);
    while !text.is_char_boundary(at) || (at > 0 && text[..at].ends_with('\r')) {
        at -= 1;
    }
    at
}

/// A short run of random characters, some of which no token begins with.
fn garbage(rng: &mut Rng) -> String {
    const CHARS: &[char] = &[
        'a', 'Z', '0', '9', '_', ' ', '\n', '<', '>', ';', ':', '=', '$', '@', '{', '}', '~', '\\',
        '"', '\'', '#', '(', ')', 'ä', 'ß', '€', '😀', '\u{0}', '\u{FEFF}',
    ];
    let n = 1 + rng.below(12);
    (0..n).map(|_| *rng.pick(CHARS)).collect()
}

#[test]
fn a_random_session_ends_with_the_diagnostics_of_check() {
    random_session(false);
}

/// The same session with a client that pulls diagnostics (nothing is pushed): the final
/// `workspace/diagnostic` report must equal `check`.
#[test]
fn a_random_pulling_session_ends_with_the_diagnostics_of_check() {
    random_session(true);
}

/// A seeded random session of edits, opens, closes and requests — positions, documents,
/// lenses and their resolution, call hierarchies, pulled diagnostics, cancellations, unknown
/// methods — that ends with the diagnostics of `check --format json` on the same texts:
/// published ones, or with `pull` those of a final `workspace/diagnostic`.
fn random_session(pull: bool) {
    let started = Instant::now();
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("ventil.higraph", GRAPH)
        .file("anlage.higraph", GROUP)
        .file("mischer.higraph", CHART);
    let mut docs: Vec<Doc> = [
        ("ventil.higraph", Some(GRAPH)),
        ("anlage.higraph", Some(GROUP)),
        ("mischer.higraph", Some(CHART)),
        ("neu.higraph", None),
        ("sub/zwei.higraph", None),
    ]
    .into_iter()
    .map(|(relative, disk)| Doc {
        relative,
        uri: tree.uri(relative),
        disk: disk.map(str::to_owned),
        open: None,
        version: 0,
    })
    .collect();
    let mut capabilities = json!({"window": {"workDoneProgress": true}});
    if pull {
        capabilities["textDocument"] = json!({"diagnostic": {}});
    }
    let (mut server, _) = Server::initialized(&tree.path(), capabilities);
    server.wait_for_progress_end();
    let mut rng = Rng(if pull { 0x5eed_2027 } else { 0x5eed_2026 });
    let mut ids: Vec<Value> = Vec::new();
    let mut next_id = 10_000;
    let mut request = |server: &mut Server, ids: &mut Vec<Value>, method: &str, params: Value| {
        next_id += 1;
        let id = json!(next_id);
        server.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        ids.push(id);
    };

    for _ in 0..3000 {
        let at = rng.below(docs.len());
        match rng.below(24) {
            // An edit of an open document: a fragment, garbage, or a deletion.
            0..=6 => {
                let Some((text, _)) = &docs[at].open else {
                    continue;
                };
                let mut start = offset(&mut rng, text);
                let mut end = offset(&mut rng, text);
                if start > end {
                    std::mem::swap(&mut start, &mut end);
                }
                if end - start > 40 {
                    end = start;
                }
                let inserted = match rng.below(3) {
                    0 => garbage(&mut rng),
                    _ => (*rng.pick(FRAGMENTS)).to_owned(),
                };
                let range = json!({"start": position(text, start), "end": position(text, end)});
                let mut new_text = text.clone();
                new_text.replace_range(start..end, &inserted);
                let doc = &mut docs[at];
                doc.version += 1;
                doc.open = Some((new_text, doc.version));
                server.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": doc.uri, "version": doc.version},
                           "contentChanges": [{"range": range, "text": inserted}]}),
                );
            }
            // The whole text replaced.
            7 => {
                if docs[at].open.is_none() {
                    continue;
                }
                let text = rng.pick(&[GRAPH, GROUP, CHART, ""]).to_string();
                let doc = &mut docs[at];
                doc.version += 1;
                doc.open = Some((text.clone(), doc.version));
                server.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": doc.uri, "version": doc.version},
                           "contentChanges": [{"text": text}]}),
                );
            }
            // Open or close.
            8 => {
                let doc = &mut docs[at];
                if doc.open.take().is_some() {
                    server.notify(
                        "textDocument/didClose",
                        json!({"textDocument": {"uri": doc.uri}}),
                    );
                } else {
                    let text = doc.disk.clone().unwrap_or_else(|| GRAPH.to_owned());
                    doc.version += 1;
                    server.notify(
                        "textDocument/didOpen",
                        json!({"textDocument": {"uri": doc.uri, "languageId": "higraph",
                               "version": doc.version, "text": text}}),
                    );
                    doc.open = Some((text, doc.version));
                }
            }
            // Requests at a random position (also past the end).
            9..=12 => {
                let method = *rng.pick(POSITION_METHODS);
                let (line, character) = (rng.below(14), rng.below(60));
                let params = json!({
                    "textDocument": {"uri": docs[at].uri},
                    "position": {"line": line, "character": character},
                    "context": {"includeDeclaration": true, "triggerKind": 1},
                    "newName": *rng.pick(&["Neu", "", "1abc", "state", "IM_Auf"]),
                });
                request(&mut server, &mut ids, method, params);
            }
            13..=14 => {
                let method = *rng.pick(DOCUMENT_METHODS);
                let end = json!({"line": rng.below(20), "character": rng.below(30)});
                let params = json!({
                    "textDocument": {"uri": docs[at].uri},
                    "options": {"tabSize": 2, "insertSpaces": true},
                    "range": {"start": {"line": 0, "character": 0}, "end": end},
                    "context": {"diagnostics": []},
                });
                request(&mut server, &mut ids, method, params);
            }
            // Cancel a recent request (running, answered, or never sent).
            15..=16 => {
                let id = match ids.last() {
                    Some(id) if rng.chance(80) => id.clone(),
                    _ => json!(1),
                };
                server.notify("$/cancelRequest", json!({"id": id}));
            }
            // Unknown methods, as requests and as notifications.
            17 => {
                let method = *rng.pick(&["higraph/unknown", "$/unknown", "workspace/foo"]);
                request(&mut server, &mut ids, method, json!({}));
            }
            18 => server.notify("$/unknownNotification", json!({"x": 1})),
            // Pulled diagnostics, with a result id that may be stale or made up.
            19 => {
                let previous = *rng.pick(&["", "0", "ffffffffffffffff"]);
                let params = if rng.chance(50) {
                    json!({"textDocument": {"uri": docs[at].uri}, "previousResultId": previous})
                } else {
                    json!({"textDocument": {"uri": docs[at].uri}})
                };
                request(&mut server, &mut ids, "textDocument/diagnostic", params);
            }
            20 => {
                let previous = if rng.chance(50) {
                    json!([{"uri": docs[at].uri, "value": "0"}])
                } else {
                    json!([])
                };
                request(
                    &mut server,
                    &mut ids,
                    "workspace/diagnostic",
                    json!({"previousResultIds": previous}),
                );
            }
            // A code action to resolve (the data of a rename fix, maybe stale or made up).
            21 if rng.chance(30) => {
                let (line, character) = (rng.below(14), rng.below(60));
                let at_position = json!({"start": {"line": line, "character": character},
                                         "end": {"line": line, "character": character + 4}});
                let params = json!({
                    "title": "Rename", "kind": "quickfix",
                    "data": {"uri": docs[at].uri, "generation": rng.below(3000), "code": "HG1101",
                             "range": at_position, "fix": rng.below(2)},
                });
                request(&mut server, &mut ids, "codeAction/resolve", params);
            }
            // A count lens to resolve: any position, any kind (stale or made up).
            21 => {
                let (line, character) = (rng.below(14), rng.below(60));
                let kind = *rng.pick(LENS_KINDS);
                // The server numbers documents from 1 as it lists their lenses; 0 is never one.
                let document = rng.below(4);
                let params = json!({
                    "range": {"start": {"line": line, "character": 0},
                              "end": {"line": line, "character": character}},
                    "data": [document, kind],
                });
                request(&mut server, &mut ids, "codeLens/resolve", params);
            }
            // Calls of a call hierarchy item: any position, with or without the server's data.
            22 => {
                let (line, character) = (rng.below(14), rng.below(60));
                let direction =
                    *rng.pick(&["callHierarchy/incomingCalls", "callHierarchy/outgoingCalls"]);
                let at_position = json!({"start": {"line": line, "character": character},
                                         "end": {"line": line, "character": character}});
                let mut item = json!({"name": "V", "kind": 5, "uri": docs[at].uri,
                                      "range": at_position, "selectionRange": at_position});
                if rng.chance(50) {
                    item["data"] = json!({"path": docs[at].relative, "offset": rng.below(400)});
                }
                request(&mut server, &mut ids, direction, json!({"item": item}));
            }
            _ => request(
                &mut server,
                &mut ids,
                "workspace/symbol",
                json!({"query": *rng.pick(&["", "V", "Ventil", "zz"])}),
            ),
        }
    }

    // Every request is answered once, none with an internal error.
    for id in &ids {
        if let Err(error) = server.response(id) {
            assert_ne!(error["code"], -32603, "internal error for {id}: {error}");
        }
    }
    assert!(
        server.answered_twice.is_empty(),
        "{:?}",
        server.answered_twice
    );
    // The last version of every open document is published (or, pulling, the final pull
    // sees it); then the server goes quiet.
    let pulled = pull.then(|| {
        server
            .request("workspace/diagnostic", json!({"previousResultIds": []}))
            .expect("workspace/diagnostic answers")
    });
    if !pull {
        for doc in &docs {
            if let Some((_, version)) = &doc.open {
                server.wait_for_diagnostics(&doc.uri, *version);
            }
        }
    }
    server.drain(Duration::from_millis(500));
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
    assert!(internal.is_empty(), "{internal:?}");

    // The same texts on disk: `check` must report exactly what the server published.
    for doc in &docs {
        if let Some(text) = doc.text() {
            tree.file(doc.relative, text);
        }
    }
    let expected = from_check(&tree.check_json());
    let published = match &pulled {
        Some(report) => {
            assert!(
                server.diagnostics.is_empty(),
                "a pulling client gets no pushed diagnostics"
            );
            from_pull(report, &tree)
        }
        None => from_server(&server, &tree),
    };
    let missing: Vec<_> = expected.difference(&published).collect();
    let extra: Vec<_> = published.difference(&expected).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "check reports but the server did not publish:\n{missing:#?}\nthe server published but check does not report:\n{extra:#?}"
    );
    assert!(
        !expected.is_empty(),
        "the session ends with some diagnostics"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
    eprintln!("random session: {:?}", started.elapsed());
}

/// (file, code, severity, range, message).
type Comparable = (String, String, String, [u64; 4], String);

fn range(value: &Value) -> [u64; 4] {
    let n = |v: &Value| v.as_u64().unwrap_or(u64::MAX);
    [
        n(&value["start"]["line"]),
        n(&value["start"]["character"]),
        n(&value["end"]["line"]),
        n(&value["end"]["character"]),
    ]
}

fn from_check(report: &Value) -> BTreeSet<Comparable> {
    report["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| {
            let text = |key: &str| d[key].as_str().unwrap_or_default().to_owned();
            (
                text("file"),
                text("code"),
                text("severity"),
                range(&d["range"]),
                text("message"),
            )
        })
        .collect()
}

fn from_server(server: &Server, tree: &TempTree) -> BTreeSet<Comparable> {
    from_lists(server.diagnostics.iter(), tree)
}

/// The diagnostics of a `workspace/diagnostic` report (full reports, as no previous result
/// ids were sent).
fn from_pull(report: &Value, tree: &TempTree) -> BTreeSet<Comparable> {
    let items = report["items"].as_array().expect("items");
    let lists: Vec<(String, Vec<Value>)> = items
        .iter()
        .map(|item| {
            assert_eq!(item["kind"], "full", "{item}");
            (
                item["uri"].as_str().unwrap_or_default().to_owned(),
                item["items"].as_array().cloned().unwrap_or_default(),
            )
        })
        .collect();
    from_lists(lists.iter().map(|(uri, list)| (uri, list)), tree)
}

fn from_lists<'a>(
    lists: impl Iterator<Item = (&'a String, &'a Vec<Value>)>,
    tree: &TempTree,
) -> BTreeSet<Comparable> {
    let prefix = format!("{}/", file_uri(&tree.path()));
    let mut all = BTreeSet::new();
    for (uri, diagnostics) in lists {
        let file = uri.strip_prefix(&prefix).unwrap_or(uri).to_owned();
        for d in diagnostics {
            let severity = match d["severity"].as_u64() {
                Some(1) => "error",
                Some(2) => "warning",
                Some(3) => "info",
                Some(4) => "hint",
                _ => "?",
            };
            all.insert((
                file.clone(),
                d["code"].as_str().unwrap_or_default().to_owned(),
                severity.to_owned(),
                range(&d["range"]),
                d["message"].as_str().unwrap_or_default().to_owned(),
            ));
        }
    }
    all
}

/// The number of threads of a process (Linux: `/proc/PID/status`).
#[cfg(target_os = "linux")]
fn threads(pid: u32) -> usize {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .expect("the server's status")
        .lines()
        .find_map(|line| line.strip_prefix("Threads:"))
        .and_then(|n| n.trim().parse().ok())
        .expect("a thread count")
}

/// A burst of requests does not get a thread each (and their memory): at most a few
/// workers compute at once, the others wait for one.
#[cfg(target_os = "linux")]
#[test]
fn a_burst_of_requests_keeps_the_threads_bounded() {
    let tree = TempTree::new();
    let mut text = String::from(
        "graph Gross <\n  in < Oben : BOOL; >\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n",
    );
    for state in 1..120 {
        text.push_str(&format!(
            "  state {state} < C: U Oben; = Oben; >\n  trans {}->{state} < U Oben; >\n",
            state - 1
        ));
    }
    text.push_str(">\n");
    tree.file("gross.higraph", &text);
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("gross.higraph");
    let mut ids = Vec::new();
    let mut most = 0;
    for round in 0..300 {
        let method = [
            "textDocument/semanticTokens/full",
            "textDocument/foldingRange",
            "textDocument/documentSymbol",
        ][round % 3];
        ids.push(server.send_request(method, json!({"textDocument": {"uri": uri}})));
        if round % 50 == 0 {
            most = most.max(threads(server.pid()));
        }
    }
    for id in &ids {
        assert!(server.response(id).is_ok(), "{id}");
        most = most.max(threads(server.pid()));
    }
    // Idle blocking threads stay for a while: the count now is about the most there were.
    most = most.max(threads(server.pid()));
    assert!(most <= 64, "{most} threads");
    assert_eq!(server.shutdown_and_exit(), 0);
}

//! Published diagnostics (`diagnostics.md` §1.5, §4.4): for every workspace file, open or
//! not, the same (code, severity, file, range, message, related) as `check --format json` for
//! the same content; kept current through edits, closes, file events and configuration
//! changes; re-published only for files whose diagnostics changed; positions in the
//! negotiated encoding.

use std::collections::BTreeSet;
use std::time::Duration;

use serde_json::{Value, json};

use crate::client::{Server, TempTree, file_uri, repo_root};

/// One diagnostic as both sides can state it: code, severity, file, range, message, related
/// locations, and whether it is tagged unnecessary.
type Comparable = (
    String,
    String,
    String,
    [u64; 4],
    String,
    Vec<(String, [u64; 4], String)>,
    bool,
);

fn range(value: &Value) -> [u64; 4] {
    let n = |v: &Value| v.as_u64().unwrap_or(u64::MAX);
    [
        n(&value["start"]["line"]),
        n(&value["start"]["character"]),
        n(&value["end"]["line"]),
        n(&value["end"]["character"]),
    ]
}

/// The diagnostics of `check --format json`.
pub(crate) fn from_check(report: &Value) -> BTreeSet<Comparable> {
    report["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| {
            let code = d["code"].as_str().unwrap_or_default().to_owned();
            let unnecessary = ["HG1210", "HG1212", "HG6004"].contains(&code.as_str());
            (
                code,
                d["severity"].as_str().unwrap_or_default().to_owned(),
                d["file"].as_str().unwrap_or_default().to_owned(),
                range(&d["range"]),
                d["message"].as_str().unwrap_or_default().to_owned(),
                d["related"]
                    .as_array()
                    .expect("related")
                    .iter()
                    .map(|r| {
                        (
                            r["file"].as_str().unwrap_or_default().to_owned(),
                            range(&r["range"]),
                            r["message"].as_str().unwrap_or_default().to_owned(),
                        )
                    })
                    .collect(),
                unnecessary,
            )
        })
        .collect()
}

/// The diagnostics the server published last for each file.
fn from_server(server: &Server, tree: &TempTree) -> BTreeSet<Comparable> {
    from_map(&server.diagnostics, tree)
}

/// The diagnostics of each file by URI (published or pulled), comparable with `check`'s.
pub(crate) fn from_map(
    files: &std::collections::HashMap<String, Vec<Value>>,
    tree: &TempTree,
) -> BTreeSet<Comparable> {
    let prefix = format!("{}/", file_uri(&tree.path()));
    let file = |uri: &str| uri.strip_prefix(&prefix).unwrap_or(uri).to_owned();
    let mut all = BTreeSet::new();
    for (uri, diagnostics) in files {
        for d in diagnostics {
            assert_eq!(d["source"], "higraph", "{d}");
            let severity = match d["severity"].as_u64() {
                Some(1) => "error",
                Some(2) => "warning",
                Some(3) => "info",
                Some(4) => "hint",
                _ => "?",
            };
            let unnecessary = match &d["tags"] {
                Value::Null => false,
                tags => tags == &json!([1]),
            };
            all.insert((
                d["code"].as_str().unwrap_or_default().to_owned(),
                severity.to_owned(),
                file(uri),
                range(&d["range"]),
                d["message"].as_str().unwrap_or_default().to_owned(),
                d["relatedInformation"]
                    .as_array()
                    .map(|related| {
                        related
                            .iter()
                            .map(|r| {
                                (
                                    file(r["location"]["uri"].as_str().unwrap_or_default()),
                                    range(&r["location"]["range"]),
                                    r["message"].as_str().unwrap_or_default().to_owned(),
                                )
                            })
                            .collect()
                    })
                    .unwrap_or_default(),
                unnecessary,
            ));
        }
    }
    all
}

fn assert_same(server: &Server, tree: &TempTree) {
    let expected = from_check(&tree.check_json());
    let published = from_server(server, tree);
    let missing: Vec<_> = expected.difference(&published).collect();
    let extra: Vec<_> = published.difference(&expected).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "check reports but the server did not publish:\n{missing:#?}\nthe server published but check does not report:\n{extra:#?}"
    );
}

/// The `mistakes` example plus a symbol table with bad lines, an unused variable, a name
/// defined in two files (related information in another file) and a configuration problem.
pub(crate) fn rich_workspace() -> TempTree {
    let tree = TempTree::new();
    let mistakes = repo_root().join("examples/mistakes");
    for entry in std::fs::read_dir(&mistakes).expect("the mistakes example") {
        let entry = entry.expect("an entry");
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.ends_with(".higraph") {
            tree.file(&name, std::fs::read(entry.path()).expect("read"));
        }
    }
    tree.file(
        "higraph.toml",
        "[workspace]\nmnemonic = \"simatic\"\nsymbols = [\"plc/symbols.sdf\"]\nunknown_key = 1\n\n[diagnostics]\nHG2402 = \"hint\"\n",
    )
    .file(
        "plc/symbols.sdf",
        "\"Motor\",\"A 4.0\",\"BOOL\",\"\"\n\"Band\",\"A 4.1\",\"BOOL\"\n\"Rezept\",\"MD 20\",\"UDT 7\",\"\"\n",
    )
    .file(
        "graphs/pumpe.higraph",
        "// Pumpe für Öl 😀\ngraph Pumpe <\n  in < Ungenutzt : BOOL; >\n  state 0 < C: U Motor; >\n  trans any->0 < U INIT_SD; >\n>\n",
    )
    .file(
        // After `ventil.higraph` in workspace order: the later graph Ventil is the duplicate
        // (HG1301) and is otherwise ignored (C3), so the first keeps its own diagnostics.
        "zusatz/doppelt.higraph",
        "graph Ventil <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
    );
    tree
}

#[test]
fn diagnostics_of_every_file_at_start_equal_check_json() {
    let tree = rich_workspace();
    let mut server = Server::indexed(&tree.path());
    server.drain(Duration::from_millis(200));
    let codes: BTreeSet<String> = server
        .diagnostics
        .values()
        .flatten()
        .filter_map(|d| d["code"].as_str().map(str::to_owned))
        .collect();
    // The workspace exercises configuration, import, related-information and tag paths.
    for code in ["HG6101", "HG6005", "HG1210", "HG2301", "HG1301"] {
        assert!(codes.contains(code), "{code} missing from {codes:?}");
    }
    assert_same(&server, &tree);
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// A change of `text` replacing `range` (0-based lines and UTF-16 columns).
fn change(range: [u32; 4], text: &str) -> Value {
    json!({
        "range": {
            "start": {"line": range[0], "character": range[1]},
            "end": {"line": range[2], "character": range[3]},
        },
        "text": text,
    })
}

fn open(server: &mut Server, uri: &str, text: &str) {
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
}

fn edit(server: &mut Server, uri: &str, version: i64, changes: Vec<Value>) {
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": changes}),
    );
}

#[test]
fn edits_keep_diagnostics_equal_to_check_on_the_same_content() {
    let tree = rich_workspace();
    let mut server = Server::indexed(&tree.path());
    let path = "graphs/pumpe.higraph";
    let uri = tree.uri(path);
    let mut text = std::fs::read_to_string(tree.path().join(path)).expect("read");
    open(&mut server, &uri, &text);

    // Rename the graph to a name an earlier file uses (HG1301 here, and the graph is
    // otherwise ignored, C3), and use the variable; then a lexer error as the last edit, which only
    // changes this file's diagnostics: once it is published, every earlier publication
    // has arrived.
    let edits = [
        ([1, 6, 1, 11], "Anlage"),
        ([3, 23, 3, 23], " U Ungenutzt;"),
        ([5, 1, 5, 1], " $"),
    ];
    for (n, (range, new_text)) in edits.iter().enumerate() {
        let version = n as i64 + 2;
        edit(&mut server, &uri, version, vec![change(*range, new_text)]);
        text = apply(&text, *range, new_text);
        let published = server.wait_for_diagnostics(&uri, version);
        if n == 0 {
            assert!(
                published.iter().any(|d| d["code"] == "HG1301"),
                "{published:?}"
            );
        }
    }
    tree.file(path, &text);
    assert_same(&server, &tree);
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// `text` with `range` (UTF-16 line/column; this test's edits are in ASCII lines) replaced.
fn apply(text: &str, range: [u32; 4], new_text: &str) -> String {
    let offset = |line: u32, column: u32| {
        let start: usize = text
            .split_inclusive('\n')
            .take(line as usize)
            .map(str::len)
            .sum();
        start + column as usize
    };
    let (start, end) = (offset(range[0], range[1]), offset(range[2], range[3]));
    format!("{}{}{}", &text[..start], new_text, &text[end..])
}

#[test]
fn only_the_edited_document_and_files_whose_diagnostics_changed_are_published_again() {
    let tree = rich_workspace();
    let mut server = Server::indexed(&tree.path());
    server.drain(Duration::from_millis(200));
    let uri = tree.uri("steuerung.higraph");
    let text = std::fs::read_to_string(tree.path().join("steuerung.higraph")).expect("read");
    open(&mut server, &uri, &text);
    // Opening publishes the document's diagnostics with its version, changed or not.
    server.wait_for_diagnostics(&uri, 1);
    let before = server.publications.len();
    // A comment at the end changes nothing.
    let lines = text.lines().count() as u32;
    edit(
        &mut server,
        &uri,
        2,
        vec![change([lines, 0, lines, 0], "// nichts\n")],
    );
    // A lexer error changes this file's diagnostics only.
    edit(
        &mut server,
        &uri,
        3,
        vec![change([lines, 0, lines, 0], "$")],
    );
    server.wait_for_diagnostics(&uri, 3);
    server.drain(Duration::from_millis(200));
    let since: Vec<_> = server.publications[before..].to_vec();
    // Version 2 may be analysed on its own (then published although nothing changed) or
    // together with version 3; no other file is published either way.
    assert!(
        since == vec![(uri.clone(), Some(3))]
            || since == vec![(uri.clone(), Some(2)), (uri.clone(), Some(3))],
        "{since:?}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn every_workspace_file_is_published_clean_or_not_and_on_open_and_change() {
    // tooling.md §4: diagnostics are published for every workspace file, not only open ones.
    let tree = TempTree::new();
    tree.file("higraph.toml", QUIET)
        .file(
            "clean.higraph",
            "graph Clean <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
        )
        .file("broken.higraph", "$\n");
    let mut server = Server::indexed(&tree.path());
    server.drain(Duration::from_millis(200));
    let clean = tree.uri("clean.higraph");
    let broken = tree.uri("broken.higraph");
    assert_eq!(
        server.diagnostics.get(&clean).map(Vec::len),
        Some(0),
        "published empty"
    );
    assert_eq!(server.diagnostics.get(&broken).map(Vec::len), Some(1));

    // Opening a clean document publishes its (empty) diagnostics with the document's version;
    // so does an edit that changes nothing, and an edit whose version is not newer is applied
    // all the same.
    let text = std::fs::read_to_string(tree.path().join("clean.higraph")).expect("read");
    open(&mut server, &clean, &text);
    assert!(server.wait_for_diagnostics(&clean, 1).is_empty());
    edit(
        &mut server,
        &clean,
        2,
        vec![change([4, 0, 4, 0], "// nichts\n")],
    );
    assert!(server.wait_for_diagnostics(&clean, 2).is_empty());
    edit(&mut server, &clean, 2, vec![change([5, 0, 5, 0], "$")]);
    assert_eq!(server.wait_for_diagnostics(&clean, 2).len(), 1, "HG0009");
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// A configuration that switches off the hints tiny test graphs would get (a state without a
/// way out, an unused variable).
const QUIET: &str = "[diagnostics]\nHG2402 = \"off\"\nHG1210 = \"off\"\n";

#[test]
fn incremental_changes_apply_in_order_with_several_ranges() {
    let tree = TempTree::new();
    tree.file("higraph.toml", QUIET);
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("neu.higraph");
    open(
        &mut server,
        &uri,
        "graph Neu <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
    );
    // Several changes in one notification, each relative to the text after the previous.
    edit(
        &mut server,
        &uri,
        2,
        vec![
            change([1, 11, 1, 11], "C: U Fehlt; "),
            change([0, 6, 0, 9], "Neuer"),
            json!({"text": "graph Ganz <\n  state 0 < C: U Fehlt; >\n  trans any->0 < U INIT_SD; >\n>\n"}),
            change([1, 17, 1, 22], "Auch"),
        ],
    );
    let published = server.wait_for_diagnostics(&uri, 2);
    let messages: Vec<&str> = published
        .iter()
        .filter_map(|d| d["message"].as_str())
        .collect();
    assert_eq!(published.len(), 1, "{published:?}");
    assert!(messages[0].contains("'Auch'"), "{messages:?}");
    assert_eq!(
        published[0]["range"],
        json!({"start": {"line": 1, "character": 17}, "end": {"line": 1, "character": 21}})
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn closing_a_document_returns_to_the_text_on_disk() {
    let tree = TempTree::new();
    let clean = "graph A <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n";
    tree.file("higraph.toml", QUIET).file("a.higraph", clean);
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("a.higraph");
    open(&mut server, &uri, clean);
    edit(&mut server, &uri, 2, vec![change([3, 1, 3, 1], " $")]);
    assert_eq!(server.wait_for_diagnostics(&uri, 2).len(), 1);
    server.notify(
        "textDocument/didClose",
        json!({"textDocument": {"uri": uri}}),
    );
    let back = server.wait_for("diagnostics of the closed file", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(back["params"]["diagnostics"], json!([]), "{back}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn a_document_not_on_disk_is_analysed_while_open() {
    let tree = TempTree::new();
    tree.file("higraph.toml", QUIET).file(
        "a.higraph",
        "graph A <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
    );
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("entwurf.higraph");
    open(&mut server, &uri, "graph A <\n>\n");
    let published = server.wait_for_diagnostics(&uri, 1);
    assert!(
        published.iter().any(|d| d["code"] == "HG1301"),
        "{published:?}"
    );
    server.notify(
        "textDocument/didClose",
        json!({"textDocument": {"uri": uri}}),
    );
    let gone = server.wait_for("the closed document's diagnostics cleared", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(gone["params"]["diagnostics"], json!([]));
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn watched_file_events_add_change_and_remove_files_and_reload_the_configuration() {
    let tree = TempTree::new();
    tree.file("higraph.toml", QUIET).file(
        "a.higraph",
        "graph A <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
    );
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("graphs/b.higraph");
    let watched = |server: &mut Server, uri: &str, kind: u32| {
        server.notify(
            "workspace/didChangeWatchedFiles",
            json!({"changes": [{"uri": uri, "type": kind}]}),
        );
    };
    // Created: a graph without startup transition (HG2201).
    tree.file("graphs/b.higraph", "graph B <\n  state 0 < >\n>\n");
    watched(&mut server, &uri, 1);
    let created = server.wait_for("diagnostics of the new file", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert!(
        created["params"]["diagnostics"][0]["code"] == "HG2201",
        "{created}"
    );
    // The configuration switches the rule off.
    tree.file("higraph.toml", format!("{QUIET}HG2201 = \"off\"\n"));
    watched(&mut server, &tree.uri("higraph.toml"), 2);
    let reloaded = server.wait_for("diagnostics after the configuration change", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(reloaded["params"]["diagnostics"], json!([]), "{reloaded}");
    // Changed on disk: a lexer error.
    tree.file("graphs/b.higraph", "graph B <\n  state 0 < >\n> $\n");
    watched(&mut server, &uri, 2);
    let changed = server.wait_for("diagnostics of the changed file", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(
        changed["params"]["diagnostics"][0]["code"], "HG0009",
        "{changed}"
    );
    // Deleted.
    std::fs::remove_file(tree.path().join("graphs/b.higraph")).expect("delete");
    watched(&mut server, &uri, 3);
    let deleted = server.wait_for("diagnostics of the deleted file cleared", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(deleted["params"]["diagnostics"], json!([]), "{deleted}");
    // Files in skipped folders are not part of the workspace.
    tree.file("target/c.higraph", "graph C <\n>\n");
    watched(&mut server, &tree.uri("target/c.higraph"), 1);
    server.drain(Duration::from_millis(300));
    assert!(
        !server
            .diagnostics
            .contains_key(&tree.uri("target/c.higraph")),
        "{:?}",
        server.diagnostics
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn utf8_positions_when_the_client_offers_them() {
    let tree = TempTree::new();
    // HG0009 on `ä`, after an astral character and an umlaut on the same line.
    let text = "graph G \"😀 Öl\" < in < Zähler : INT; > >\n";
    tree.file(
        "higraph.toml",
        "[diagnostics]\nHG2201 = \"off\"\nHG1210 = \"off\"\n",
    )
    .file("g.higraph", text);
    let (mut server, result) = Server::initialized(
        &tree.path(),
        json!({
            "general": {"positionEncodings": ["utf-8", "utf-16"]},
            "window": {"workDoneProgress": true},
        }),
    );
    assert_eq!(
        result["capabilities"]["positionEncoding"], "utf-8",
        "{result}"
    );
    server.wait_for_progress_end();
    server.drain(Duration::from_millis(200));
    let uri = tree.uri("g.higraph");
    let byte = text.find('ä').expect("an umlaut") as u64;
    let published = server.diagnostics.get(&uri).cloned().unwrap_or_default();
    assert_eq!(published.len(), 1, "{published:?}");
    assert_eq!(
        published[0]["range"]["start"]["character"], byte,
        "{published:?}"
    );

    // An edit in UTF-8 columns: replace `Zähler` (bytes) with `Zaehler`.
    open(&mut server, &uri, text);
    let end = byte + 'ä'.len_utf8() as u64 + "hler".len() as u64;
    let start = byte - 1;
    edit(
        &mut server,
        &uri,
        2,
        vec![
            json!({"range": {"start": {"line": 0, "character": start}, "end": {"line": 0, "character": end}}, "text": "Zaehler"}),
        ],
    );
    assert_eq!(server.wait_for_diagnostics(&uri, 2), Vec::<Value>::new());
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn a_configuration_change_notification_reloads_higraph_toml() {
    let tree = TempTree::new();
    tree.file("higraph.toml", QUIET)
        .file("b.higraph", "graph B <\n  state 0 < >\n>\n");
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("b.higraph");
    let codes = |server: &Server| -> Vec<String> {
        server
            .diagnostics
            .get(&uri)
            .into_iter()
            .flatten()
            .filter_map(|d| d["code"].as_str().map(str::to_owned))
            .collect()
    };
    assert_eq!(codes(&server), ["HG2201"]);
    server.notifications.clear();
    tree.file("higraph.toml", format!("{QUIET}HG2201 = \"warning\"\n"));
    server.notify("workspace/didChangeConfiguration", json!({"settings": {}}));
    let reloaded = server.wait_for("diagnostics after the reload", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri.as_str()
    });
    assert_eq!(
        reloaded["params"]["diagnostics"][0]["severity"], 2,
        "{reloaded}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// The byte offset of a 0-based line and UTF-16 column, clamped as the server clamps: a line
/// past the last one is the end of the text, a column past the end of its line the end of the
/// line's content, a column inside a character that character's start. Lines end at LF, CR LF
/// or a lone CR.
fn utf16_offset(text: &str, line: u32, column: u32) -> usize {
    let bytes = text.as_bytes();
    let mut start = 0;
    for _ in 0..line {
        let Some(at) = bytes[start..]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
        else {
            return text.len();
        };
        let at = start + at;
        start = at
            + if bytes[at] == b'\r' && bytes.get(at + 1) == Some(&b'\n') {
                2
            } else {
                1
            };
    }
    let end = bytes[start..]
        .iter()
        .position(|&b| b == b'\n' || b == b'\r')
        .map_or(text.len(), |at| start + at);
    let mut units = 0;
    for (at, c) in text[start..end].char_indices() {
        if units + c.len_utf16() as u32 > column {
            return start + at;
        }
        units += c.len_utf16() as u32;
    }
    end
}

/// `text` with a range of UTF-16 positions replaced (a reversed range is put in order).
fn apply_utf16(text: &str, range: [u32; 4], new_text: &str) -> String {
    let a = utf16_offset(text, range[0], range[1]);
    let b = utf16_offset(text, range[2], range[3]);
    let (start, end) = (a.min(b), a.max(b));
    format!("{}{}{}", &text[..start], new_text, &text[end..])
}

/// The UTF-16 position of the end of `text`.
fn end_of(text: &str) -> (u32, u32) {
    let last = text.rsplit(['\n', '\r']).next().unwrap_or_default();
    let lines =
        text.matches('\n').count() + text.matches('\r').count() - text.matches("\r\n").count();
    (lines as u32, last.encode_utf16().count() as u32)
}

/// The changes of one `didChange`: ranges and new texts.
type Notification<'a> = Vec<([u32; 4], &'a str)>;

#[test]
fn keystroke_by_keystroke_edits_keep_diagnostics_equal_to_check() {
    // Each keystroke reaches the analysis as a byte-offset edit that reparses one block; the
    // server keeps the document's text and line index current edit by edit. After each group
    // of keystrokes the published diagnostics must equal `check` on the same text.
    let tree = rich_workspace();
    let mut server = Server::indexed(&tree.path());
    let path = "graphs/pumpe.higraph";
    let uri = tree.uri(path);
    let mut text = std::fs::read_to_string(tree.path().join(path)).expect("read");
    open(&mut server, &uri, &text);
    let mut version = 1;
    let mut send = |server: &mut Server, text: &mut String, changes: &[([u32; 4], &str)]| {
        version += 1;
        let values = changes.iter().map(|(r, t)| change(*r, t)).collect();
        edit(server, &uri, version, values);
        for (range, new_text) in changes {
            *text = apply_utf16(text, *range, new_text);
        }
        version
    };
    let typed = " U Motor; U Band;";
    // Groups of notifications, each a list of changes.
    let groups: Vec<Vec<Notification>> = vec![
        // Typing into the state's condition, one character per notification.
        typed
            .char_indices()
            .map(|(i, _)| {
                let column = 22 + i as u32;
                vec![([3, column, 3, column], &typed[i..=i])]
            })
            .collect(),
        // Deleting half of it again, backwards.
        (0..8)
            .map(|i| {
                let column = 22 + typed.len() as u32 - i;
                vec![([3, column - 1, 3, column], "")]
            })
            .collect(),
        // Line breaks (LF, CR LF, a lone CR) typed into a transition and removed again.
        vec![
            vec![([4, 16, 4, 16], "\n    ")],
            vec![([5, 4, 5, 4], "U Band;\r\n    ")],
            vec![([6, 0, 6, 0], "\r")],
            vec![([5, 4, 7, 0], "")],
        ],
        // After the astral character of the comment (two UTF-16 units), and inside it.
        vec![vec![([0, 18, 0, 18], " ß")], vec![([0, 17, 0, 17], "x")]],
        // Several changes in one notification, one spanning members, one past the end.
        vec![vec![
            ([2, 0, 4, 2], "  in < Neu : BOOL; >\n  state 1 < >\n  "),
            ([1, 6, 1, 11], "Kessel"),
            ([99, 0, 99, 5], "\n// Ende\n"),
        ]],
        // The whole graph deleted and typed back in one paste.
        vec![
            vec![([1, 0, 99, 0], "")],
            vec![(
                [1, 0, 1, 0],
                "graph Pumpe <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n",
            )],
        ],
    ];
    for (n, group) in groups.iter().enumerate() {
        for changes in group {
            send(&mut server, &mut text, changes);
        }
        // A run of `$` as long as the group number at the end: a lexer error that differs
        // from every earlier one, so the diagnostics change and are published; once they
        // are, everything before them has been applied.
        let (line, column) = end_of(&text);
        let marker = "$".repeat(n + 1);
        let version = send(
            &mut server,
            &mut text,
            &[([line, column, line, column], marker.as_str())],
        );
        server.wait_for_diagnostics(&uri, version);
        server.drain(Duration::from_millis(100));
        tree.file(path, &text);
        assert_same(&server, &tree);
        // The marker goes away with the next group's first edit.
        let (line, end) = end_of(&text);
        send(
            &mut server,
            &mut text,
            &[([line, end - marker.len() as u32, line, end], "")],
        );
    }
    assert_eq!(server.shutdown_and_exit(), 0);
}

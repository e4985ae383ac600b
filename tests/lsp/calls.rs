//! Call hierarchy and message flow end to end (issue 15, item 3), on the drilling example:
//! group → instances → graphs, the instances that send to an instance or to an incoming
//! message, and where an outgoing message goes.

use std::path::Path;

use serde_json::{Value, json};

use crate::client::{Server, TempTree, repo_root};

/// A copy of `examples/drilling`.
fn drilling() -> TempTree {
    let tree = TempTree::new();
    let root = repo_root().join("examples/drilling");
    copy(&root, &root, &tree);
    tree
}

fn copy(root: &Path, dir: &Path, tree: &TempTree) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("example directory")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            copy(root, &path, tree);
        } else {
            let relative = path.strip_prefix(root).expect("below the root");
            let text = std::fs::read(&path).expect("example file");
            tree.file(&relative.to_string_lossy(), text);
        }
    }
}

/// The LSP position (UTF-16) of the `nth` occurrence of `needle` in a file of the example.
fn position(relative: &str, needle: &str, nth: usize) -> Value {
    let text = std::fs::read_to_string(repo_root().join("examples/drilling").join(relative))
        .expect("example file");
    let offset = text
        .match_indices(needle)
        .nth(nth)
        .map(|(i, _)| i)
        .expect("needle in the file");
    let before = &text[..offset];
    let line = before.matches('\n').count();
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let character: usize = before[line_start..].chars().map(char::len_utf16).sum();
    json!({"line": line, "character": character})
}

fn prepare(server: &mut Server, tree: &TempTree, relative: &str, needle: &str) -> Value {
    let items = server
        .request(
            "textDocument/prepareCallHierarchy",
            json!({"textDocument": {"uri": tree.uri(relative)},
                   "position": position(relative, needle, 0)}),
        )
        .expect("prepareCallHierarchy answers");
    let items = items.as_array().cloned().unwrap_or_default();
    assert_eq!(items.len(), 1, "one item at {needle}: {items:?}");
    items[0].clone()
}

/// The calls of `item` (`incoming` or `outgoing`) as `(name, detail, item)`.
fn calls(server: &mut Server, item: &Value, direction: &str) -> Vec<(String, String, Value)> {
    let result = server
        .request(
            &format!("callHierarchy/{direction}Calls"),
            json!({"item": item}),
        )
        .expect("calls answer");
    let key = if direction == "incoming" {
        "from"
    } else {
        "to"
    };
    result
        .as_array()
        .cloned()
        .unwrap_or_default()
        .into_iter()
        .map(|call| {
            let target = call[key].clone();
            let name = target["name"].as_str().unwrap_or_default().to_owned();
            let detail = target["detail"].as_str().unwrap_or_default().to_owned();
            (name, detail, call)
        })
        .collect()
}

fn names(calls: &[(String, String, Value)]) -> Vec<String> {
    calls
        .iter()
        .map(|(name, detail, _)| format!("{name} ({detail})"))
        .collect()
}

#[test]
fn drilling_machine_call_hierarchy_and_message_flow() {
    let tree = drilling();
    let (mut server, init) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    assert_eq!(
        init["capabilities"]["callHierarchyProvider"], true,
        "{init}"
    );
    server.wait_for_progress_end();

    // Group → its instances, in run order.
    let group = prepare(
        &mut server,
        &tree,
        "bohrmaschine.higraph",
        "Bohrmaschine fc",
    );
    assert_eq!(group["name"], "Bohrmaschine");
    assert_eq!(group["kind"], 2, "a module: {group}");
    let instances = calls(&mut server, &group, "outgoing");
    assert_eq!(
        names(&instances),
        [
            "Bohren (Bohrmaschine : Bohren)",
            "Bohrmotor (Bohrmaschine : Motor)",
            "Vorschub (Bohrmaschine : Ventil_2E)",
            "Spanneinrichtung (Bohrmaschine : Spanner)",
        ]
    );

    // The item handed back by the client (with its `data`) is found again: Vorschub calls its
    // graph and the instance its reports go to; Bohren sends it its commands.
    let vorschub = instances[2].2["to"].clone();
    assert_eq!(
        names(&calls(&mut server, &vorschub, "outgoing")),
        ["Ventil_2E (graph)", "Bohren (Bohrmaschine : Bohren)"]
    );
    let senders = calls(&mut server, &vorschub, "incoming");
    assert_eq!(
        names(&senders),
        ["Bohrmaschine (group)", "Bohren (Bohrmaschine : Bohren)"]
    );
    // `Vorschub.IM_Ab` and `Vorschub.IM_Auf` in Bohren's block (lines 14 and 15).
    let ranges = &senders[1].2["fromRanges"];
    assert_eq!(ranges.as_array().map(Vec::len), Some(2), "{ranges}");
    assert_eq!(
        ranges[0]["start"],
        position("bohrmaschine.higraph", "Vorschub.IM_Ab", 0)
    );

    // A graph is called by the instances of it.
    let graph = prepare(&mut server, &tree, "graphs/motor.higraph", "Motor \"drill");
    assert_eq!(
        names(&calls(&mut server, &graph, "incoming")),
        ["Bohrmotor (Bohrmaschine : Motor)"]
    );

    // Who sends to Bohren's incoming message IM_Oben: Vorschub, at `Bohren.IM_Oben`.
    let im_oben = prepare(&mut server, &tree, "graphs/bohren.higraph", "IM_Oben :");
    assert_eq!(im_oben["kind"], 24, "an event: {im_oben}");
    let senders = calls(&mut server, &im_oben, "incoming");
    assert_eq!(names(&senders), ["Vorschub (Bohrmaschine : Ventil_2E)"]);
    assert_eq!(
        senders[0].2["fromRanges"][0]["start"],
        position("bohrmaschine.higraph", "Bohren.IM_Oben", 0)
    );

    // Where Bohren's outgoing message OM_Senken goes: Ventil_2E's IM_Ab.
    let om_senken = prepare(&mut server, &tree, "graphs/bohren.higraph", "OM_Senken :");
    assert_eq!(
        names(&calls(&mut server, &om_senken, "outgoing")),
        ["IM_Ab (Ventil_2E msg in)"]
    );

    // Nothing to prepare on a keyword.
    let none = server
        .request(
            "textDocument/prepareCallHierarchy",
            json!({"textDocument": {"uri": tree.uri("bohrmaschine.higraph")},
                   "position": position("bohrmaschine.higraph", "option", 0)}),
        )
        .expect("prepareCallHierarchy answers");
    assert!(none.is_null(), "{none}");

    // An item the workspace does not know (a stale or made-up one) has no calls.
    let mut stale = im_oben.clone();
    stale["data"] = json!({"path": "gone.higraph", "offset": 99_999});
    for direction in ["incoming", "outgoing"] {
        assert!(calls(&mut server, &stale, direction).is_empty());
    }
    stale["data"] = json!({"path": "graphs/bohren.higraph", "offset": 99_999});
    assert!(calls(&mut server, &stale, "incoming").is_empty());
    assert_eq!(server.shutdown_and_exit(), 0);
}

//! Signature help end to end (`tooling.md` §4): the capability with its trigger characters,
//! and the three contexts — an instance block, a CALL's parameter list and a chart step's
//! qualifier — over stdio with the real binary.

use serde_json::{Value, json};

use crate::client::{Server, TempTree, repo_root};

const EXTRA: &str = "block FC 10 \"Dosieren\" < in < Menge : INT \"litres\"; Start : BOOL; > out < Fertig : BOOL; > >
graph Dosierer <
  state 0 < CALL FC 10 (Menge := MW 2, Start := E 1.0); >
>
chart Mischer <
  sequencer S <
    start < TRUE; >
    step X < L M 2.0, T#5S; >
  >
>
";

/// The 0-based line and column of the end of the first `needle` after `after`.
fn after(text: &str, context: &str, needle: &str) -> Value {
    let start = text.find(context).expect("the context");
    let end = start + text[start..].find(needle).expect("the needle") + needle.len();
    let line = text[..end].matches('\n').count();
    let column = end - text[..end].rfind('\n').map_or(0, |n| n + 1);
    json!({ "line": line, "character": column })
}

/// The label of the active parameter of the first signature.
fn active_label(help: &Value) -> String {
    let signature = &help["signatures"][0];
    let label: Vec<u16> = signature["label"]
        .as_str()
        .expect("a label")
        .encode_utf16()
        .collect();
    let active = help["activeParameter"]
        .as_u64()
        .expect("an active parameter") as usize;
    let offsets = &signature["parameters"][active]["label"];
    let start = offsets[0].as_u64().expect("offsets") as usize;
    let end = offsets[1].as_u64().expect("offsets") as usize;
    String::from_utf16(&label[start..end]).expect("UTF-16")
}

#[test]
fn signature_help_in_instances_calls_and_qualifiers() {
    let tree = TempTree::new();
    let root = repo_root().join("examples/drilling");
    for relative in [
        "higraph.toml",
        "bohrmaschine.higraph",
        "symbols.higraph",
        "graphs/bohren.higraph",
        "graphs/motor.higraph",
        "graphs/spanner.higraph",
        "graphs/ventil_2e.higraph",
    ] {
        tree.file(
            relative,
            std::fs::read(root.join(relative)).expect("the example"),
        );
    }
    tree.file("extra.higraph", EXTRA);
    let (mut server, init) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    let provider = &init["capabilities"]["signatureHelpProvider"];
    let triggers = provider["triggerCharacters"].as_array().expect("triggers");
    for trigger in ["(", ",", "<"] {
        assert!(triggers.contains(&json!(trigger)), "{provider}");
    }
    server.wait_for_progress_end();

    let request = |server: &mut Server, uri: &str, position: Value| {
        server
            .request(
                "textDocument/signatureHelp",
                json!({"textDocument": {"uri": uri}, "position": position}),
            )
            .expect("an answer")
    };

    // In instance `Vorschub`, while `Unten`'s actual is written.
    let group = std::fs::read_to_string(tree.path().join("bohrmaschine.higraph")).expect("read");
    let uri = tree.uri("bohrmaschine.higraph");
    let help = request(
        &mut server,
        &uri,
        after(&group, "instance Vorschub", "Unten    :="),
    );
    let label = help["signatures"][0]["label"].as_str().expect("a label");
    assert!(label.starts_with("Ventil_2E < in Oben : BOOL;"), "{help}");
    assert_eq!(active_label(&help), "in Unten : BOOL", "{help}");
    let documentation = &help["signatures"][0]["parameters"][1]["documentation"];
    assert_eq!(documentation["value"], "limit switch bottom", "{help}");

    // In the CALL's parameter list, after the comma.
    let uri = tree.uri("extra.higraph");
    let help = request(&mut server, &uri, after(EXTRA, "CALL", "MW 2, "));
    assert_eq!(
        help["signatures"][0]["label"],
        "CALL FC 10 (in Menge : INT, in Start : BOOL, out Fertig : BOOL)",
        "{help}"
    );
    assert_eq!(active_label(&help), "in Start : BOOL", "{help}");

    // After the qualifier `L`, at the time.
    let help = request(&mut server, &uri, after(EXTRA, "step X", "M 2.0, "));
    assert_eq!(help["signatures"][0]["label"], "L operand, time", "{help}");
    assert_eq!(active_label(&help), "time", "{help}");
    let documentation = help["signatures"][0]["documentation"]["value"]
        .as_str()
        .expect("documentation");
    assert!(documentation.contains("needs a time"), "{help}");

    // Elsewhere: no signature.
    let help = request(&mut server, &uri, after(EXTRA, "graph", "Dosierer"));
    assert_eq!(help, Value::Null);
    assert_eq!(server.shutdown_and_exit(), 0);
}

//! Building from the editor (`export.md` §2, issue 13): the code action "Build this group" /
//! "Build this chart" on item headers and the command `higraph.build` it runs, which writes
//! the same files as `higraph-lsp build` into `build/` and answers what it wrote.

use serde_json::{Value, json};

use crate::client::{Server, TempTree};

const PLANT: &str = "symbols < Knopf : E 0.0; Lampe : A 0.0; >
graph Blink <
  in < Go : BOOL; >
  out < Light : BOOL; >
  state 0 \"Aus\" < C: CLR; = Light; >
  state 1 \"An\" < C: = Light; >
  trans any->0 prio 1 \"startup\" < U INIT_SD; >
  trans 0->1 < U Go; >
  trans 1->0 < UN Go; >
>
group Pult fc FC1 db DB1 <
  instance Anzeige : Blink < Go := Knopf; Light := Lampe; >
>
chart Ampel <
  in < Start : BOOL; >
  out < Rot : BOOL; >
  sequencer Lauf prio 1 <
    start < Start; >
    step Warten < N Rot; >
    trans Weiter < not Start; >
    step Ende < >
  >
>
";

fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("plant.higraph", PLANT);
    tree
}

/// The code actions at a position (no `only`: what a light bulb asks for).
fn actions_at(server: &mut Server, uri: &str, line: u32, character: u32) -> Vec<Value> {
    let at = json!({"line": line, "character": character});
    server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": {"start": at, "end": at},
                   "context": {"diagnostics": []}}),
        )
        .expect("code actions")
        .as_array()
        .cloned()
        .unwrap_or_default()
}

fn build(server: &mut Server, arguments: Value) -> Result<Value, Value> {
    server.request(
        "workspace/executeCommand",
        json!({"command": "higraph.build", "arguments": arguments}),
    )
}

#[test]
fn the_header_action_builds_its_item_and_the_command_reports_what_it_wrote() {
    let tree = workspace();
    let (mut server, result) =
        Server::initialized(&tree.path(), json!({"window": {"workDoneProgress": true}}));
    assert_eq!(
        result["capabilities"]["executeCommandProvider"]["commands"],
        json!(["higraph.runTest", "higraph.build"]),
        "{result}"
    );
    server.wait_for_progress_end();
    let uri = tree.uri("plant.higraph");

    // On the group's header (line 10, on its name) and on the chart's (line 13, on `chart`).
    let group = actions_at(&mut server, &uri, 10, 8);
    assert_eq!(group.len(), 1, "{group:?}");
    assert_eq!(group[0]["title"], "Build this group (Pult)");
    let command = &group[0]["command"];
    assert_eq!(command["command"], "higraph.build");
    assert_eq!(
        command["arguments"],
        json!([{"kind": "group", "name": "Pult"}])
    );
    let chart = actions_at(&mut server, &uri, 13, 0);
    assert_eq!(chart.len(), 1, "{chart:?}");
    assert_eq!(chart[0]["title"], "Build this chart (Ampel)");
    assert_eq!(
        chart[0]["command"]["arguments"],
        json!([{"kind": "chart", "name": "Ampel"}])
    );
    // Not inside the item, nor when only quick fixes are asked for.
    assert!(actions_at(&mut server, &uri, 11, 6).is_empty());
    let at = json!({"line": 10, "character": 8});
    let quickfixes = server
        .request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": uri}, "range": {"start": at, "end": at},
                   "context": {"diagnostics": [], "only": ["quickfix"]}}),
        )
        .expect("code actions");
    assert_eq!(quickfixes, json!([]));

    // Running the group's action writes its source and the symbol table.
    let answer = build(&mut server, command["arguments"].clone()).expect("built");
    assert_eq!(answer["refused"], false, "{answer}");
    assert_eq!(
        answer["files"],
        json!(["build/Pult.awl", "build/symbols.sdf"]),
        "{answer}"
    );
    assert!(
        answer["message"]
            .as_str()
            .is_some_and(|m| m.starts_with("built 1 group into build: 2 files written")),
        "{answer}"
    );
    let awl = tree.path().join("build/Pult.awl");
    let bytes = std::fs::read(&awl).expect("written");
    assert!(!tree.path().join("build/charts.xml").exists());

    // The CLI writes the same bytes; a second run writes nothing.
    let again = build(&mut server, command["arguments"].clone()).expect("built");
    assert_eq!(again["files"], json!([]), "{again}");
    assert_eq!(
        again["unchanged"],
        json!(["build/Pult.awl", "build/symbols.sdf"])
    );
    let cli = std::process::Command::new(crate::client::binary())
        .args(["build", "-o", "cli"])
        .current_dir(tree.path())
        .output()
        .expect("the CLI runs");
    assert!(cli.status.success(), "{cli:?}");
    assert_eq!(
        std::fs::read(tree.path().join("cli/Pult.awl")).expect("cli"),
        bytes
    );

    // Without an argument: the whole workspace, every target.
    let all = build(&mut server, json!([])).expect("built");
    assert_eq!(all["files"], json!(["build/charts.xml"]), "{all}");
    assert!(tree.path().join("build/charts.xml").is_file());

    // An unknown item and a malformed argument are refused.
    assert!(build(&mut server, json!([{"kind": "group", "name": "Nirgends"}])).is_err());
    assert!(build(&mut server, json!([{"kind": "graph", "name": "Blink"}])).is_err());
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn errors_in_the_editor_refuse_the_build_and_nothing_is_written() {
    let tree = workspace();
    let mut server = Server::indexed(&tree.path());
    let uri = tree.uri("plant.higraph");
    // The unsaved text of the editor counts: an instance of a graph that does not exist.
    let broken = PLANT.replace("instance Anzeige : Blink", "instance Anzeige : Blinker");
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": broken}}),
    );
    server.wait_for_diagnostics(&uri, 1);
    let answer = build(&mut server, json!([{"kind": "group", "name": "Pult"}])).expect("answered");
    assert_eq!(answer["refused"], true, "{answer}");
    assert_eq!(answer["files"], json!([]), "{answer}");
    let message = answer["message"].as_str().unwrap_or_default();
    assert!(message.starts_with("nothing built: "), "{answer}");
    assert!(message.contains("plant.higraph:12: error[HG"), "{answer}");
    assert!(!tree.path().join("build").exists());
    assert_eq!(server.shutdown_and_exit(), 0);
}

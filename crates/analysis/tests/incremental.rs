//! Incrementality: an edit inside one graph re-runs only what depends on it. The test records
//! which salsa queries execute after a one-character edit and checks that the analyses of the
//! other graph in the same file and of every other file are reused.

use std::sync::{Arc, Mutex};

use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

const VALVE: &str = "graph Ventil <
  in < Oben : BOOL; >
  out < Auf : BOOL; >
  state 0 < C: = Auf; >
  state 1 < >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U Oben; >
>

graph Motor <
  in < Start : BOOL; >
  state 0 < >
  state 1 < >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U Start; >
>
";

const GROUP: &str = "group Anlage fc FC 1 db DB 1 <
  instance V : Ventil < Oben := E 0.0; Auf := A 4.0; >
  instance M : Motor < Start := E 0.1; >
>
";

const SYMBOLS: &str = "symbols < Taster : E 0.2 BOOL; >\n";

/// Runs a full check and returns the executed queries (debug names of their keys).
fn executed(host: &AnalysisHost, log: &Arc<Mutex<Vec<String>>>) -> Vec<String> {
    log.lock().map(|mut l| l.clear()).ok();
    let _ = host.analysis().diagnostics();
    log.lock().map(|l| l.clone()).unwrap_or_default()
}

#[test]
fn editing_one_graph_reuses_the_other_items_and_files() {
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = log.clone();
    let mut host = AnalysisHost::with_event_callback(move |event| {
        if let salsa::EventKind::WillExecute { database_key } = event.kind {
            if let Ok(mut log) = sink.lock() {
                log.push(format!("{database_key:?}"));
            }
        }
    });
    host.load(WorkspaceData {
        files: vec![
            ("graphs.higraph".into(), FileContents::Text(VALVE.into())),
            ("group.higraph".into(), FileContents::Text(GROUP.into())),
            ("symbols.higraph".into(), FileContents::Text(SYMBOLS.into())),
        ],
        ..WorkspaceData::default()
    });
    let first = executed(&host, &log);
    let first_items = first
        .iter()
        .filter(|q| q.starts_with("item_analysis"))
        .count();
    assert_eq!(
        first_items, 4,
        "one analysis per item on the first run: {first:#?}"
    );

    // A one-character edit inside a transition of the first graph.
    let edited = VALVE.replacen("U Oben;", "UN Oben;", 1);
    assert!(host.set_file_contents("graphs.higraph", FileContents::Text(edited)));
    let second = executed(&host, &log);

    let analyses: Vec<&String> = second
        .iter()
        .filter(|q| q.starts_with("item_analysis"))
        .collect();
    assert_eq!(
        analyses.len(),
        1,
        "only the edited graph is re-analysed: {second:#?}"
    );
    // The edited file is re-parsed; the other files are not.
    let parses: Vec<&String> = second.iter().filter(|q| q.starts_with("parse(")).collect();
    assert_eq!(
        parses.len(),
        1,
        "only the edited file is re-parsed: {second:#?}"
    );
    // The workspace index did not change, so it is not rebuilt either.
    assert!(
        !second.iter().any(|q| q.starts_with("global_index")),
        "the global index is reused: {second:#?}"
    );
    // Nothing of the group or symbols files is recomputed.
    assert!(
        !second.iter().any(|q| q.starts_with("item_symbols")),
        "symbol tables are reused: {second:#?}"
    );
}

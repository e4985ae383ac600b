//! Work grows with the input, not faster: the salsa queries a check or a keystroke executes are
//! counted at one size and at eight times that size (counts, not times: tests do not time).
//! The timed families are in `crates/lsp/examples/scaling.rs`.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use higraph_analysis::{AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData};
use higraph_syntax::Edit;
use higraph_workload::scaling;

type Log = Arc<Mutex<Vec<String>>>;

fn host_with_log() -> (AnalysisHost, Log) {
    let log: Log = Arc::default();
    let sink = log.clone();
    let host = AnalysisHost::with_event_callback(move |event| {
        if let salsa::EventKind::WillExecute { database_key } = event.kind
            && let Ok(mut log) = sink.lock()
        {
            log.push(format!("{database_key:?}"));
        }
    });
    (host, log)
}

/// The executed queries of a full check, counted by query name.
fn executed(host: &AnalysisHost, log: &Log) -> BTreeMap<String, usize> {
    log.lock().map(|mut l| l.clear()).ok();
    let diagnostics = host.analysis().diagnostics();
    assert!(!diagnostics.is_empty());
    let mut counts = BTreeMap::new();
    for query in log.lock().map(|l| l.clone()).unwrap_or_default() {
        let name = query.split('(').next().unwrap_or("").to_owned();
        *counts.entry(name).or_insert(0) += 1;
    }
    counts
}

/// The queries one keystroke in the middle graph of a file of `n` graphs executes.
fn keystroke(n: usize) -> BTreeMap<String, usize> {
    let (mut host, log) = host_with_log();
    let text = scaling::items_in_one_file(n);
    let middle = scaling::small_graph(n / 2);
    let item = text.find(&middle).expect("the middle graph");
    let at = item + middle.find("UN Start").expect("UN") + 1;
    host.load(WorkspaceData {
        files: vec![("items.higraph".into(), FileContents::Text(text))],
        ..WorkspaceData::default()
    });
    executed(&host, &log);
    let edit = Edit {
        delete: TextRange::at(TextSize::from(at as u32), TextSize::from(1)),
        insert: "X".into(),
    };
    host.apply_edits("items.higraph", &[edit]).expect("edit");
    executed(&host, &log)
}

#[test]
fn a_keystroke_in_a_big_file_runs_the_rules_of_one_item() {
    let small = keystroke(40);
    let big = keystroke(320);
    // The rules run for the edited item only, at any file size.
    for query in ["item_analysis", "graph_layout", "chunk_stl", "graph_header"] {
        assert_eq!(
            small.get(query),
            big.get(query),
            "{query}: {small:#?} vs {big:#?}"
        );
        assert!(
            small.get(query).is_some_and(|&n| n <= 2),
            "{query}: {small:#?}"
        );
    }
    // Every other query runs a bounded number of times per item of the file (picking an
    // item's node from the file is per item), never per pair of items.
    for (query, &count) in &big {
        assert!(count <= 320, "{query} ran {count} times: {big:#?}");
    }
}

/// The queries a cold check of `n` files of one graph each executes.
fn cold_files(n: usize) -> BTreeMap<String, usize> {
    let (mut host, log) = host_with_log();
    host.load(WorkspaceData {
        files: scaling::files_in_workspace(n)
            .into_iter()
            .map(|(path, text)| (path, FileContents::Text(text)))
            .collect(),
        ..WorkspaceData::default()
    });
    executed(&host, &log)
}

#[test]
fn a_cold_check_of_many_files_runs_each_query_a_fixed_number_of_times_per_file() {
    let small = cold_files(20);
    let big = cold_files(160);
    assert!(small.get("parse").is_some_and(|&n| n == 20), "{small:#?}");
    for (query, &count) in &big {
        let before = small.get(query).copied().unwrap_or(0);
        // Graphs are cut into content-defined chunks, so the chunks per file vary a little
        // with the generated names: a quarter of slack, where a scan of every file per file
        // would be 64 times.
        assert!(
            count <= 10 * before,
            "{query}: {before} times for 20 files, {count} for 160"
        );
    }
}

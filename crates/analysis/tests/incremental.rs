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
        if let salsa::EventKind::WillExecute { database_key } = event.kind
            && let Ok(mut log) = sink.lock()
        {
            log.push(format!("{database_key:?}"));
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

/// A graph with `n` states in a ring, a transition per state and a startup transition.
fn ring(n: usize) -> String {
    let mut text = String::from("graph Ring <\n  in < Weiter : BOOL; Halt : BOOL; >\n");
    for i in 0..n {
        text.push_str(&format!("  state {i} < C: = Halt; >\n"));
    }
    text.push_str("  trans any->0 < U INIT_SD; >\n");
    for i in 0..n {
        text.push_str(&format!("  trans {i}->{} < U Weiter; >\n", (i + 1) % n));
    }
    text.push_str(">\n");
    text
}

#[test]
fn a_keystroke_in_a_transition_reanalyses_one_chunk_of_members() {
    let log: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = log.clone();
    let mut host = AnalysisHost::with_event_callback(move |event| {
        if let salsa::EventKind::WillExecute { database_key } = event.kind
            && let Ok(mut log) = sink.lock()
        {
            log.push(format!("{database_key:?}"));
        }
    });
    let text = ring(300);
    host.load(WorkspaceData {
        files: vec![("ring.higraph".into(), FileContents::Text(text.clone()))],
        ..WorkspaceData::default()
    });
    let first = executed(&host, &log);
    let chunks = first.iter().filter(|q| q.starts_with("chunk_stl")).count();
    assert!(chunks > 10, "the graph is analysed in chunks: {chunks}");

    // `U Weiter` → `UN Weiter` in the transition 150->151.
    let at = text
        .find("trans 150->151 < U")
        .map(|i| i + "trans 150->151 < U".len());
    let at = at.expect("the transition is there") as u32;
    let edit = higraph_syntax::Edit {
        delete: higraph_syntax::TextRange::empty(at.into()),
        insert: "N".to_owned(),
    };
    let edited = host.apply_edits("ring.higraph", &[edit]);
    let second = executed(&host, &log);
    let redone = second.iter().filter(|q| q.starts_with("chunk_stl")).count();
    assert!(
        (1..=3).contains(&redone),
        "only the chunks around the edited member are re-analysed: {redone} of {chunks}"
    );
    let facts = second
        .iter()
        .filter(|q| q.starts_with("chunk_facts"))
        .count();
    assert!(facts <= 3, "facts are reused: {facts}");

    // And the result is what a fresh analysis of the new text gives.
    let mut fresh = AnalysisHost::new();
    fresh.load(WorkspaceData {
        files: vec![(
            "ring.higraph".into(),
            FileContents::Text(edited.unwrap_or_default()),
        )],
        ..WorkspaceData::default()
    });
    assert_eq!(
        format!("{:?}", host.analysis().diagnostics()),
        format!("{:?}", fresh.analysis().diagnostics())
    );
}

/// Every `.higraph` file under `examples/`, grouped by workspace (folder of `higraph.toml`).
fn example_workspaces() -> Vec<Vec<(String, String)>> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(&root) else {
        return out;
    };
    let mut dirs: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    dirs.sort();
    for dir in dirs {
        let mut files = Vec::new();
        let mut stack = vec![dir.clone()];
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d).into_iter().flatten().flatten() {
                let path = entry.path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "higraph") {
                    let name = path
                        .strip_prefix(&dir)
                        .map(|p| p.to_string_lossy().replace('\\', "/"))
                        .unwrap_or_default();
                    files.push((name, std::fs::read_to_string(&path).unwrap_or_default()));
                }
            }
        }
        files.sort();
        out.push(files);
    }
    out
}

fn load(files: &[(String, String)]) -> AnalysisHost {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: files
            .iter()
            .map(|(p, t)| (p.clone(), FileContents::Text(t.clone())))
            .collect(),
        ..WorkspaceData::default()
    });
    host
}

/// Keystrokes applied with `apply_edits` (incremental reparse, chunked analysis) leave the
/// same diagnostics as loading the edited text into a fresh database — for edits all over
/// every example file, including ones that break and repair the syntax.
#[test]
fn keystrokes_give_the_diagnostics_of_a_fresh_analysis() {
    const TYPED: &[&str] = &[
        "X", ";", ">", "<", "\n", "1", " ", "U ", "INIT_SD", "prio 2 ",
    ];
    let mut seed: u64 = 0x5EED;
    let mut next = |bound: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as usize) % bound.max(1)
    };
    for workspace in example_workspaces() {
        let mut files = workspace.clone();
        let mut host = load(&files);
        let _ = host.analysis().diagnostics();
        for _ in 0..40 {
            let which = next(files.len());
            let (path, text) = files[which].clone();
            let mut at = next(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let delete = if next(3) == 0 && at < text.len() {
                text[at..].chars().next().map_or(0, char::len_utf8)
            } else {
                0
            };
            let edit = higraph_syntax::Edit {
                delete: higraph_syntax::TextRange::at((at as u32).into(), (delete as u32).into()),
                insert: TYPED[next(TYPED.len())].to_owned(),
            };
            let Some(new_text) = host.apply_edits(&path, std::slice::from_ref(&edit)) else {
                panic!("{edit:?} does not fit {path}");
            };
            files[which].1 = new_text;
            assert_eq!(
                format!("{:#?}", host.analysis().diagnostics()),
                format!("{:#?}", load(&files).analysis().diagnostics()),
                "after {edit:?} in {path}"
            );
        }
    }
}

/// A member longer than a virtual slot (64 KiB) makes the structure rules use real offsets;
/// their findings land on the right text either way.
#[test]
fn structure_findings_land_on_their_text_in_huge_graphs() {
    for statements in [10, 8000] {
        let mut text = String::from("graph G <\n  in < A : BOOL; >\n  state 0 < >\n");
        text.push_str("  trans any->0 < U INIT_SD; >\n  trans 0->0 <\n");
        for _ in 0..statements {
            text.push_str("    U A;\n");
        }
        // Beyond the first 64 KiB of the member when it is huge.
        text.push_str("    wait T#1S;\n");
        text.push_str("  >\n  trans 0->7 < U A; >\n>\n");
        let host = load(&[("g.higraph".to_owned(), text.clone())]);
        let diagnostics = host.analysis().diagnostics();
        let at = |code: &str| -> Vec<&str> {
            diagnostics
                .iter()
                .flat_map(|(_, ds)| ds)
                .filter(|d| d.code.as_str() == code)
                .map(|d| &text[usize::from(d.range.start())..usize::from(d.range.end())])
                .collect()
        };
        assert_eq!(at("HG2103"), vec!["7"], "with {statements} statements");
        assert_eq!(
            at("HG3007"),
            vec!["wait T#1S"],
            "with {statements} statements"
        );
    }
}

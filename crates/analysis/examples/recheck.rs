//! Profiling aid: re-checks max-graph after one-character edits, N times, optionally with a
//! completion request after each (`complete`) or with the whole-file views an editor asks for
//! after an edit (`views`: semantic tokens, inlay hints, symbols, folding; timed once).
//! `cargo run --release -p higraph-analysis --example recheck -- [N] [complete|views]`
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(50);
    let text = higraph_workload::max_graph(1);
    let path = "max_graph.higraph".to_owned();
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(path.clone(), FileContents::Text(text.clone()))],
        ..WorkspaceData::default()
    });
    let _ = host.analysis().diagnostics();
    let at = text
        .find("trans 0->")
        .and_then(|t| text[t..].find(" UN ").map(|i| t + i + 1))
        .expect("a UN condition");
    let complete = std::env::args().nth(2).is_some_and(|a| a == "complete");
    let views = std::env::args().nth(2).is_some_and(|a| a == "views");
    let position = higraph_analysis::ide::FilePosition {
        path: path.clone(),
        offset: ((at + 3) as u32).into(),
    };
    if complete {
        let _ = host.analysis().completions(&position);
    }
    let start = std::time::Instant::now();
    for i in 0..n {
        edit_and_check(&mut host, &path, at, i);
        if complete {
            complete_after_edit(&host, &position);
        }
        if views {
            let t = std::time::Instant::now();
            let analysis = host.analysis();
            let tokens = analysis.semantic_tokens(&path, None).map(|t| t.len());
            let t1 = t.elapsed();
            let hints = analysis.inlay_hints(&path, None).map(|h| h.len());
            let t2 = t.elapsed();
            let symbols = analysis.document_symbols(&path).map(|s| s.len());
            let t3 = t.elapsed();
            let folds = analysis.folding_ranges(&path).map(|f| f.len());
            let t4 = t.elapsed();
            if i == n - 1 {
                println!(
                    "after an edit: semantic tokens {t1:?} ({tokens:?}), inlay hints {:?} ({hints:?}), \
                     document symbols {:?} ({symbols:?}), folding {:?} ({folds:?})",
                    t2 - t1,
                    t3 - t2,
                    t4 - t3
                );
            }
        }
    }
    println!("{:?} per edit", start.elapsed() / n as u32);
}

/// One keystroke and the diagnostics after it (a separate function so that
/// `valgrind --tool=callgrind --collect-atstart=no --toggle-collect=*edit_and_check*` counts
/// exactly this work).
#[inline(never)]
fn edit_and_check(host: &mut AnalysisHost, path: &str, at: usize, i: usize) {
    let edit = higraph_syntax::Edit {
        delete: higraph_syntax::TextRange::at((at as u32).into(), 1.into()),
        insert: if i.is_multiple_of(2) { "O" } else { "U" }.to_owned(),
    };
    host.apply_edits(path, &[edit]);
    let _ = host.analysis().diagnostics().len();
}

/// Completion in the edited statement's operand, right after the edit.
#[inline(never)]
fn complete_after_edit(host: &AnalysisHost, position: &higraph_analysis::ide::FilePosition) {
    let items = host.analysis().completions(position).unwrap_or_default();
    assert!(!items.is_empty());
}

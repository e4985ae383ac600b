//! Editor-feature benchmarks (`tooling.md` §7): completion latency inside a transition of the
//! `max-graph` workload (one graph with 255 states and 4090 transitions).
//!
//! * `completion/max_graph_operand` — warm database, the cursor in the operand of a condition
//!   (`U Anf|`): the graph's variables, predefined variables and global symbols.
//! * `completion/max_graph_statement` — warm database, the cursor at the start of a
//!   statement: labels and the opcodes of the file's mnemonic set.
//! * `completion/max_graph_after_edit` — for comparison: one character typed in another
//!   transition (`apply_edits`), then the same operand completion (includes reparsing the
//!   edited transition and recomputing what completion needs of the edited graph).
//! * `views/max_graph_inlay_hints_range` — warm database, the inlay hints of 60 lines in the
//!   middle of the graph (what an editor asks for the visible part).
//! * `views/max_graph_document_symbols` — warm database, the whole outline (4 090
//!   transitions, 255 states, the variables).
//!
//! Run with `cargo bench -p higraph-analysis --bench ide`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use higraph_analysis::{
    AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData, ide::FilePosition,
};

const PATH: &str = "max_graph.higraph";

fn load(text: &str) -> AnalysisHost {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(PATH.to_owned(), FileContents::Text(text.to_owned()))],
        ..WorkspaceData::default()
    });
    host
}

/// The offset of `needle` inside the first transition whose header starts with `header`, plus
/// `skip` bytes.
fn offset_in(text: &str, header: &str, needle: &str, skip: usize) -> TextSize {
    let Some(at) = text
        .find(header)
        .and_then(|t| text[t..].find(needle).map(|i| t + i + skip))
    else {
        panic!("max-graph has no '{needle}' after '{header}'")
    };
    TextSize::from(u32::try_from(at).unwrap_or(0))
}

fn completion(c: &mut Criterion) {
    let text = higraph_workload::max_graph(1);
    let host = load(&text);
    let analysis = host.analysis();
    let _ = analysis.diagnostics();
    let operand = FilePosition {
        path: PATH.to_owned(),
        offset: offset_in(&text, "trans 100->101", "U Anforderung_2", "U Anf".len()),
    };
    let statement = FilePosition {
        path: PATH.to_owned(),
        offset: offset_in(&text, "trans 100->101", "U Anforderung_2", 0),
    };
    for position in [&operand, &statement] {
        let items = analysis.completions(position).unwrap_or_default();
        assert!(!items.is_empty(), "no completions at {position:?}");
    }
    let mut group = c.benchmark_group("completion");
    group.bench_function("max_graph_operand", |b| {
        b.iter(|| {
            analysis
                .completions(black_box(&operand))
                .map(|items| items.len())
        })
    });
    group.bench_function("max_graph_statement", |b| {
        b.iter(|| {
            analysis
                .completions(black_box(&statement))
                .map(|items| items.len())
        })
    });
    drop(analysis);

    // One character flipped in another transition (`UN` ↔ `ON`), then the operand completion.
    let mut host = host;
    let at = text
        .find("trans 0->")
        .and_then(|t| text[t..].find(" UN ").map(|i| t + i + 1));
    let Some(at) = at else {
        panic!("max-graph has no transition 0->n with a UN condition")
    };
    let mut flip = 0usize;
    group.bench_function("max_graph_after_edit", |b| {
        b.iter(|| {
            flip ^= 1;
            let edit = higraph_syntax::Edit {
                delete: TextRange::at(TextSize::from(at as u32), TextSize::from(1)),
                insert: if flip == 1 { "O" } else { "U" }.to_owned(),
            };
            host.apply_edits(PATH, &[edit]);
            host.analysis()
                .completions(&operand)
                .map(|items| items.len())
        })
    });
    group.finish();
}

fn views(c: &mut Criterion) {
    let text = higraph_workload::max_graph(1);
    let host = load(&text);
    let analysis = host.analysis();
    let _ = analysis.diagnostics();
    let start = offset_in(&text, "trans 100->101", "trans", 0);
    let end = text[usize::from(start)..]
        .match_indices('\n')
        .nth(60)
        .map_or(text.len(), |(i, _)| usize::from(start) + i);
    let visible = TextRange::new(start, TextSize::from(u32::try_from(end).unwrap_or(0)));
    let mut group = c.benchmark_group("views");
    group.bench_function("max_graph_inlay_hints_range", |b| {
        b.iter(|| {
            analysis
                .inlay_hints(PATH, Some(black_box(visible)))
                .map(|h| h.len())
        })
    });
    group.bench_function("max_graph_document_symbols", |b| {
        b.iter(|| analysis.document_symbols(black_box(PATH)).map(|s| s.len()))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = completion, views
}
criterion_main!(benches);

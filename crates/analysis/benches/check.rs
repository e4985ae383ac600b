//! Analysis benchmarks (`tooling.md` §7):
//!
//! * `check_cold/plant` — a cold `check` of the generated `plant` workload (300 graphs, 20
//!   groups, 10 charts, 5000 symbols): load into a fresh database and compute every file's
//!   diagnostics. Reported as throughput over the workload's bytes.
//! * `recheck_after_edit/max_graph` — with a warm database holding `max-graph`, change one
//!   character inside a transition (`AnalysisHost::apply_edits`, as the language server does
//!   for a keystroke) and recompute all diagnostics. The edited member is reparsed alone and
//!   only its chunk of members is analysed again.
//! * `recheck_after_edit/max_graph_whole_text` — the same edit, but handed over as a whole new
//!   text (`set_file_contents`, as for a file changed on disk): full reparse, every member new.
//!
//! Run with `cargo bench -p higraph-analysis`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use higraph_analysis::{AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData};
use higraph_syntax::Edit;

fn load(files: &[(String, String)]) -> AnalysisHost {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: files
            .iter()
            .map(|(path, text)| (path.clone(), FileContents::Text(text.clone())))
            .collect(),
        ..WorkspaceData::default()
    });
    host
}

fn check_cold(c: &mut Criterion) {
    let plant = higraph_workload::plant(1);
    let bytes: usize = plant.iter().map(|(_, text)| text.len()).sum();
    let mut group = c.benchmark_group("check_cold");
    group.throughput(Throughput::Bytes(bytes as u64));
    group.sample_size(10);
    group.bench_function("plant", |b| {
        b.iter(|| {
            let host = load(black_box(&plant));
            host.analysis().diagnostics().len()
        })
    });
    group.finish();
}

fn recheck_after_edit(c: &mut Criterion) {
    let text = higraph_workload::max_graph(1);
    let path = "max_graph.higraph".to_owned();
    let mut host = load(&[(path.clone(), text.clone())]);
    let _ = host.analysis().diagnostics();
    // One character inside the condition of a transition: `UN` ↔ `ON` of a statement.
    let at = text
        .find("trans 0->")
        .and_then(|t| text[t..].find(" UN ").map(|i| t + i + 1));
    let Some(at) = at else {
        panic!("max-graph has no transition 0->n with a UN condition")
    };
    let variants = [text.clone(), format!("{}O{}", &text[..at], &text[at + 1..])];
    let mut flip = 0usize;
    let mut group = c.benchmark_group("recheck_after_edit");
    group.bench_function("max_graph", |b| {
        b.iter(|| {
            flip ^= 1;
            let edit = Edit {
                delete: TextRange::at(TextSize::from(at as u32), TextSize::from(1)),
                insert: if flip == 1 { "O" } else { "U" }.to_owned(),
            };
            host.apply_edits(&path, &[edit]);
            host.analysis().diagnostics().len()
        })
    });
    group.sample_size(10);
    group.bench_function("max_graph_whole_text", |b| {
        b.iter(|| {
            flip ^= 1;
            host.set_file_contents(&path, FileContents::Text(variants[flip].clone()));
            host.analysis().diagnostics().len()
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = check_cold, recheck_after_edit
}
criterion_main!(benches);

//! Rename benchmark (`tooling.md` §7): renaming the message variable `IM_Bereit` of graph
//! `Zentrale` in the `max-group` workload, which all 255 instances of its group wire
//! (`OM_Bereit := Leitstand.IM_Bereit;`), so the rename edits the declaration, the graph's
//! uses and 255 actual parameters.
//!
//! * `rename/max_group_warm` — the workspace is checked (as in the language server after
//!   indexing); the rename reuses the cached per-item name uses.
//! * `rename/max_group_after_edit` — one character of another graph's file changed before each
//!   rename (the uses of that graph are recomputed; the group's are reused).
//! * `rename/max_group_cold` — a fresh database each time: parse, index and resolve what the
//!   rename needs, without computing diagnostics.
//!
//! Run with `cargo bench -p higraph-analysis --bench rename`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use higraph_analysis::{AnalysisHost, FileContents, TextSize, WorkspaceData, ide::FilePosition};

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

fn rename(c: &mut Criterion) {
    let target = higraph_workload::MAX_GROUP_RENAME;
    let files = higraph_workload::max_group(1);
    let Some((_, text)) = files.iter().find(|(p, _)| p == target.file) else {
        panic!("max-group has no {}", target.file)
    };
    let Some(offset) = text.find(&format!("{} :", target.variable)) else {
        panic!("{} is not declared in {}", target.variable, target.file)
    };
    let position = FilePosition {
        path: target.file.to_owned(),
        offset: TextSize::from(u32::try_from(offset).unwrap_or(0)),
    };
    let edits = |host: &AnalysisHost| match host.analysis().rename(&position, "IM_Fertig") {
        Ok(Ok(change)) => change.files.iter().map(|(_, e)| e.len()).sum::<usize>(),
        other => panic!("rename failed: {other:?}"),
    };

    let mut host = load(&files);
    let _ = host.analysis().diagnostics();
    assert!(edits(&host) > 255);
    let mut group = c.benchmark_group("rename");
    group.bench_function("max_group_warm", |b| b.iter(|| black_box(edits(&host))));

    // Another graph's file, one character flipped back and forth in a comment.
    let Some((other_path, other_text)) = files
        .iter()
        .find(|(p, _)| p.starts_with("graphs/") && p != target.file)
    else {
        panic!("max-group has only one graph")
    };
    let variants = [other_text.clone(), other_text.replacen("//", "//x", 1)];
    let mut flip = 0usize;
    group.bench_function("max_group_after_edit", |b| {
        b.iter(|| {
            flip ^= 1;
            host.set_file_contents(other_path, FileContents::Text(variants[flip].clone()));
            black_box(edits(&host))
        })
    });

    group.sample_size(10);
    group.bench_function("max_group_cold", |b| {
        b.iter(|| black_box(edits(&load(&files))))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = rename
}
criterion_main!(benches);

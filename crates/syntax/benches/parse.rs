//! Throughput of the lexer and the parser on the `max-graph` workload (seed 1): one graph with
//! 255 states and 4090 transitions, about 0.55 MB (`tooling.md` §7).
//!
//! * `logos` — the bare derived lexer, counting tokens (the floor for everything else);
//! * `tokenize` — `lexer::tokenize`: tokens with their text, byte-order mark and error runs;
//! * `parse` — `parse`: the full lossless tree plus the syntax diagnostics. Each iteration
//!   also drops the previous iteration's tree (freeing about 20k nodes and releasing their
//!   reference counts); this is the figure compared with `logos`.
//! * `parse_without_drop` — the same parse, but criterion's `iter_with_large_drop` keeps the
//!   trees until the timing of a batch is done, so freeing them is *not* counted. Only a
//!   breakdown of `parse` (how much of it is dropping the result), not a replacement for it.
//!
//! Run with `cargo bench -p higraph-syntax`; the figures are in MiB/s ("throughput").

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use higraph_syntax::SyntaxKind;
use logos::Logos;

fn max_graph(c: &mut Criterion) {
    let text = higraph_workload::max_graph(1);
    let bytes = text.len() as u64;

    let mut group = c.benchmark_group("logos");
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function("max_graph", |b| {
        b.iter(|| {
            let mut lexer = SyntaxKind::lexer(black_box(&text));
            let mut tokens = 0usize;
            while lexer.next().is_some() {
                tokens += 1;
            }
            tokens
        })
    });
    group.finish();

    let mut group = c.benchmark_group("tokenize");
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function("max_graph", |b| {
        b.iter(|| higraph_syntax::lexer::tokenize(black_box(&text)).len())
    });
    group.finish();

    let mut group = c.benchmark_group("parse");
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function("max_graph", |b| {
        b.iter(|| {
            let parse = higraph_syntax::parse(black_box(&text));
            assert!(parse.errors().is_empty(), "max-graph has syntax errors");
            parse
        })
    });
    group.finish();

    let mut group = c.benchmark_group("parse_without_drop");
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function("max_graph", |b| {
        b.iter_with_large_drop(|| higraph_syntax::parse(black_box(&text)))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // Small samples keep the whole `cargo bench -p higraph-syntax` run well under a minute.
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = max_graph
}
criterion_main!(benches);

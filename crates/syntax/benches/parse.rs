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
//! * `rowan_tree` — no lexing and no parsing: the same tree as `parse` makes (the same nodes,
//!   sharing the same tokens and nodes) built bottom-up from a prepared plan with
//!   `GreenNode::new`, then dropped. What rowan's tree alone costs: the floor under `parse`
//!   minus a `logos` pass, whatever the parser does.
//!
//! Run with `cargo bench -p higraph-syntax`; the figures are in MiB/s ("throughput").

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use higraph_syntax::SyntaxKind;
use higraph_syntax::rowan::{self, GreenNode, GreenNodeData, GreenToken, NodeOrToken};
use logos::Logos;
use rustc_hash::FxHashMap;

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

    let plan = TreePlan::new(higraph_syntax::parse(&text).green());
    let mut group = c.benchmark_group("rowan_tree");
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function("max_graph", |b| b.iter(|| plan.build()));
    group.finish();
}

/// The distinct nodes of a green tree, children before parents, for rebuilding the tree with
/// the same sharing.
struct TreePlan {
    nodes: Vec<(rowan::SyntaxKind, Vec<PlanChild>)>,
}

enum PlanChild {
    Token(GreenToken),
    /// A node built earlier, by index; `shared` if more than one parent refers to it (it is
    /// cloned, as the parser clones interned nodes; the others are moved, as the parser moves
    /// the nodes it owns).
    Node {
        index: usize,
        shared: bool,
    },
}

impl TreePlan {
    fn new(root: &GreenNodeData) -> TreePlan {
        let mut plan = TreePlan { nodes: Vec::new() };
        let mut index = FxHashMap::default();
        let mut parents = Vec::new();
        plan.add(root, &mut index, &mut parents);
        for (_, children) in &mut plan.nodes {
            for child in children {
                if let PlanChild::Node { index, shared } = child {
                    *shared = parents[*index] > 1;
                }
            }
        }
        plan
    }

    fn add(
        &mut self,
        node: &GreenNodeData,
        index: &mut FxHashMap<*const GreenNodeData, usize>,
        parents: &mut Vec<usize>,
    ) -> usize {
        if let Some(&i) = index.get(&(node as *const _)) {
            parents[i] += 1;
            return i;
        }
        let children = node
            .children()
            .map(|child| match child {
                NodeOrToken::Token(token) => PlanChild::Token(token.to_owned()),
                NodeOrToken::Node(node) => PlanChild::Node {
                    index: self.add(node, index, parents),
                    shared: false,
                },
            })
            .collect();
        self.nodes.push((node.kind(), children));
        parents.push(1);
        index.insert(node as *const _, self.nodes.len() - 1);
        self.nodes.len() - 1
    }

    fn build(&self) -> Option<GreenNode> {
        let mut built: Vec<Option<GreenNode>> = Vec::with_capacity(self.nodes.len());
        for (kind, children) in &self.nodes {
            // An iterator, not a vector: the parser's builder hands its children over the same way.
            let node = GreenNode::new(
                *kind,
                children.iter().map(|child| match *child {
                    PlanChild::Token(ref token) => NodeOrToken::Token(token.clone()),
                    PlanChild::Node {
                        index,
                        shared: true,
                    } => NodeOrToken::Node(built[index].clone().expect("built before")),
                    PlanChild::Node {
                        index,
                        shared: false,
                    } => NodeOrToken::Node(built[index].take().expect("built before")),
                }),
            );
            built.push(Some(node));
        }
        built.pop().flatten()
    }
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

//! Throughput of the group engine: instance turns per second on a generated group of 255
//! instances (five states, conditions, cyclic parts, a wait), without trace records.
//!
//! `cargo run --release -p higraph-runtime --example group_turns [cycles]`

#[path = "../tests/group_support/mod.rs"]
mod group_support;

use group_support::{GraphB, InstSpec, ProgramB, Sim};
use higraph_runtime::Ty;
use higraph_runtime::program::{GroupOptions, TimeValue};
use std::time::Instant;

const INSTANCES: usize = 255;

fn main() {
    let cycles: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let cyclic = "C: L #Cnt; + 1; T #Cnt; U Go; UN Halt; = Out;";
    let mut graph = GraphB::new(
        "Bench",
        &[
            ("Go", Ty::Bool),
            ("Halt", Ty::Bool),
            ("Out", Ty::Bool),
            ("Cnt", Ty::Int),
        ],
    );
    for n in 0..5u16 {
        graph = graph.state(n, cyclic);
    }
    graph = graph
        .wait(2, TimeValue::Const(20))
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("any->4 prio 2", "U M 0.7; U Halt;");
    for n in 0..4u16 {
        graph = graph.trans(
            &format!("{n}->{} waits", n + 1),
            "U Go; UN Halt; ?: L #Cnt; L 3; >=I; !: L 0; T #Cnt;",
        );
    }
    let graph = graph.trans("4->0", "U Go; !: L 0; T #Cnt;").build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    let names: Vec<String> = (0..INSTANCES).map(|i| format!("I{i}")).collect();
    let wires: Vec<[(&str, String); 2]> = (0..INSTANCES)
        .map(|i| {
            [
                ("Go", format!("M {}.{}", 10 + i / 8, i % 8)),
                ("Out", format!("M {}.{}", 100 + i / 8, i % 8)),
            ]
        })
        .collect();
    let wiring: Vec<Vec<(&str, &str)>> = wires
        .iter()
        .map(|w| w.iter().map(|(f, a)| (*f, a.as_str())).collect())
        .collect();
    let specs: Vec<InstSpec<'_>> = (0..INSTANCES)
        .map(|i| (names[i].as_str(), g, &wiring[i][..]))
        .collect();
    b.group("Bench", GroupOptions::default(), &specs);
    let mut sim = Sim::new(b.build());
    sim.record = false;
    // Every third instance never gets Go; the others run round.
    for i in (0..INSTANCES).filter(|i| i % 3 != 0) {
        sim.set(&format!("M {}.{}", 10 + i / 8, i % 8), 1);
    }
    sim.step();
    let start = Instant::now();
    for _ in 0..cycles {
        sim.step();
    }
    let secs = start.elapsed().as_secs_f64();
    let turns = cycles as f64 * INSTANCES as f64;
    let changes = sim.var("Bench", "I1", "CurrentState");
    println!(
        "{cycles} cycles × {INSTANCES} instances in {secs:.3} s: {:.0} turns/s (I1 in state {changes})",
        turns / secs
    );
}

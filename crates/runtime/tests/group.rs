//! The group engine against `runtime.md` §2: the worked examples E1–E5 of §9.3 cell by cell,
//! and the corner cases of §2.3–§2.8 (modes, waits, restarts, options, return transitions,
//! UsrMsgSend, trace parts).

mod group_support;

use group_support::{GraphB, ProgramB, Sim};
use higraph_runtime::group::GroupRt;
use higraph_runtime::program::{Graph, GroupOptions, Operand, Origin, Test, TimeValue};
use higraph_runtime::{Ty, Value};
use serde_json::json;

const PLAIN: GroupOptions = GroupOptions {
    cyclic_rlo0: false,
    any_once: false,
    precyclic_on_entry: false,
};

fn opts(cyclic_rlo0: bool, any_once: bool, precyclic_on_entry: bool) -> GroupOptions {
    GroupOptions {
        cyclic_rlo0,
        any_once,
        precyclic_on_entry,
    }
}

/// Asserts instance variables (read through the binding) after the current cycle.
fn check(sim: &mut Sim, group: &str, inst: &str, expect: &[(&str, u32)]) {
    for (var, want) in expect {
        let got = sim.var(group, inst, var);
        assert_eq!(got, *want, "cycle {}: {group}.{inst}.{var}", sim.cycle);
    }
}

fn check_mem(sim: &mut Sim, expect: &[(&str, u32)]) {
    for (addr, want) in expect {
        let got = sim.mem(addr);
        assert_eq!(got, *want, "cycle {}: {addr}", sim.cycle);
    }
}

fn parts(sim: &Sim, group: &str, inst: &str) -> Vec<String> {
    sim.rec(group, inst).parts.clone()
}

// ------------------------------------------------------------------------------------ E1

fn e1_graph() -> Graph {
    GraphB::new(
        "E1",
        &[
            ("NotAus", Ty::Bool),
            ("Start", Ty::Bool),
            ("Quit", Ty::Bool),
            ("Zaehler", Ty::Int),
        ],
    )
    .state(0, "")
    .state(1, "")
    .state(9, "E: L #Zaehler; + 1; T #Zaehler;")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("any->9 prio 2", "U NotAus;")
    .trans("0->1", "U Start;")
    .trans("9->0", "U Quit;")
    .build()
}

#[test]
fn e1_any_refiring_and_any_once() {
    let mut b = ProgramB::new();
    let g = b.graph(e1_graph());
    let wiring: &[(&str, &str)] = &[("NotAus", "M 0.0"), ("Start", "M 0.1"), ("Quit", "M 0.2")];
    b.group("P", PLAIN, &[("I", g, wiring)]);
    b.group("O", opts(false, true, false), &[("I", g, wiring)]);
    let mut sim = Sim::new(b.build());
    // (sets before the cycle, P: s p Zaehler StateChange, O: the same)
    type Row<'a> = (&'a [(&'a str, u32)], [u32; 4], [u32; 4]);
    let table: [Row<'_>; 7] = [
        (&[("M 0.1", 1)], [0, 0, 0, 1], [0, 0, 0, 1]),
        (&[], [1, 0, 0, 1], [1, 0, 0, 1]),
        (&[("M 0.0", 1), ("M 0.2", 1)], [9, 1, 1, 1], [9, 1, 1, 1]),
        (&[], [9, 9, 2, 1], [9, 1, 1, 0]),
        (&[], [9, 9, 3, 1], [9, 1, 1, 0]),
        (&[("M 0.0", 0)], [0, 9, 3, 1], [0, 9, 1, 1]),
        (&[], [1, 0, 3, 1], [1, 0, 1, 1]),
    ];
    for (sets, p, o) in table {
        for (addr, v) in sets {
            sim.set(addr, *v);
        }
        sim.step();
        for (group, row) in [("P", p), ("O", o)] {
            check(
                &mut sim,
                group,
                "I",
                &[
                    ("CurrentState", row[0]),
                    ("PreviousState", row[1]),
                    ("Zaehler", row[2]),
                    ("StateChange", row[3]),
                ],
            );
        }
        match sim.cycle {
            1 => {
                let f = sim.rec("P", "I").fired.clone().expect("initial entry");
                assert_eq!((f.kind, f.from, f.to, f.prio), ("initial", None, 0, None));
            }
            4 | 5 => {
                // P re-fires (`E` runs again); O is blocked by any->9 (prio 2).
                let f = sim.rec("P", "I").fired.clone().expect("re-firing");
                assert_eq!((f.kind, f.from, f.to, f.prio), ("any", None, 9, Some(2)));
                assert_eq!(parts(&sim, "P", "I"), ["state 9 E"]);
                let o = sim.rec("O", "I");
                assert!(o.fired.is_none());
                assert_eq!(o.blocked_by.as_ref().map(|b| b.prio), Some(2));
                assert!(o.parts.is_empty());
            }
            _ => assert!(sim.rec("O", "I").blocked_by.is_none()),
        }
    }
}

// ------------------------------------------------------------------------------------ E2

#[test]
fn e2_return_transition() {
    let graph = GraphB::new(
        "E2",
        &[
            ("Weiter", Ty::Bool),
            ("Stoer", Ty::Bool),
            ("Quit", Ty::Bool),
        ],
    )
    .state(0, "")
    .state(1, "")
    .state(2, "")
    .state(5, "")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("0->1", "U Weiter;")
    .trans("1->2 prio 2", "U Weiter;")
    .trans("1->5 prio 1", "U Stoer;")
    .trans("2->5", "U Stoer;")
    .trans("5->return", "U Quit; UN Stoer;")
    .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[(
            "I",
            g,
            &[("Weiter", "M 0.0"), ("Stoer", "M 0.1"), ("Quit", "M 0.2")],
        )],
    );
    let mut sim = Sim::new(b.build());
    let table: [(Option<&str>, u32, u32); 7] = [
        (None, 0, 0),
        (Some("M 0.0"), 1, 0),
        (Some("M 0.1"), 5, 1),
        (Some("M 0.2"), 1, 5),
        (Some("M 0.0"), 2, 1),
        (Some("M 0.1"), 5, 2),
        (Some("M 0.2"), 2, 5),
    ];
    for (input, s, p) in table {
        if let Some(a) = input {
            sim.set(a, 1);
        }
        sim.step();
        if let Some(a) = input {
            sim.set(a, 0);
        }
        check(
            &mut sim,
            "G",
            "I",
            &[
                ("CurrentState", s),
                ("PreviousState", p),
                ("StateChange", 1),
            ],
        );
        if matches!(sim.cycle, 4 | 7) {
            let f = sim.rec("G", "I").fired.clone().expect("return fires");
            assert_eq!((f.kind, f.from, f.to), ("return", Some(5), s as u16));
        }
    }
}

// ------------------------------------------------------------------------------------ E3

#[test]
fn e3_cyclic_rlo0_and_entry_cycle() {
    let graph = GraphB::new(
        "E3",
        &[
            ("Ein", Ty::Bool),
            ("Aus", Ty::Bool),
            ("L1", Ty::Bool),
            ("L2", Ty::Bool),
            ("L3", Ty::Bool),
        ],
    )
    .state(0, "")
    .state(1, "C: = L1; C: S L2; C: U Ein; = L3;")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("0->1", "U Ein;")
    .trans("1->0", "U Aus;")
    .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "R",
        opts(true, false, false),
        &[(
            "I",
            g,
            &[
                ("Ein", "M 0.0"),
                ("Aus", "M 0.1"),
                ("L1", "M 1.0"),
                ("L2", "M 1.1"),
                ("L3", "M 1.2"),
            ],
        )],
    );
    b.group(
        "N",
        PLAIN,
        &[(
            "I",
            g,
            &[
                ("Ein", "M 0.0"),
                ("Aus", "M 0.1"),
                ("L1", "M 2.0"),
                ("L2", "M 2.1"),
                ("L3", "M 2.2"),
            ],
        )],
    );
    let mut sim = Sim::new(b.build());
    // (set, R: s L1 L2 L3, N: s L1 L2 L3)
    let table: [(Option<&str>, [u32; 4], [u32; 4]); 4] = [
        (None, [0, 0, 0, 0], [0, 0, 0, 0]),
        (Some("M 0.0"), [1, 1, 1, 1], [1, 1, 1, 1]),
        (None, [1, 1, 1, 1], [1, 1, 1, 1]),
        (Some("M 0.1"), [0, 0, 1, 1], [0, 1, 1, 1]),
    ];
    for (set, r, n) in table {
        if let Some(a) = set {
            sim.set(a, 1);
        }
        sim.step();
        for (group, row) in [("R", r), ("N", n)] {
            check(
                &mut sim,
                group,
                "I",
                &[
                    ("CurrentState", row[0]),
                    ("L1", row[1]),
                    ("L2", row[2]),
                    ("L3", row[3]),
                ],
            );
        }
    }
    // The leaving turn: only the RLO-0 pass of state 1 has statements (no `!`, `X`, `E`).
    assert_eq!(parts(&sim, "R", "I"), ["state 1 C0"]);
    assert!(parts(&sim, "N", "I").is_empty());
}

// ------------------------------------------------------------------------------------ E4

#[test]
fn e4_wait_and_supervision() {
    let graph = GraphB::new("E4", &[("Go", Ty::Bool), ("Weiter", Ty::Bool)])
        .state(0, "")
        .state(1, "")
        .state(2, "")
        .wait(1, TimeValue::Const(50))
        .supervise(1, TimeValue::Const(80))
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Go;")
        .trans("1->2 waits", "U Weiter;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[
            ("A", g, &[("Go", "M 0.0"), ("Weiter", "M 0.1")]),
            ("B", g, &[("Go", "M 0.2"), ("Weiter", "M 0.3")]),
        ],
    );
    let mut sim = Sim::new(b.build());
    sim.set("M 0.0", 1);
    sim.set("M 0.1", 1);
    sim.set("M 0.2", 1);
    for k in 1..=11u32 {
        if k == 11 {
            sim.set("M 0.3", 1);
        }
        sim.step();
        // A: s, WT_CurrValue, WT_Expired, WT_Valid
        let a = match k {
            1 => [0, 0, 0, 0],
            2..=6 => [1, 50 - 10 * (k - 2), 0, 1],
            _ => [2, 0, 0, 0],
        };
        check(
            &mut sim,
            "G",
            "A",
            &[
                ("CurrentState", a[0]),
                ("WT_CurrValue", a[1]),
                ("WT_Expired", a[2]),
                ("WT_Valid", a[3]),
            ],
        );
        // B: s, ST_CurrValue, ST_Expired, ST_ExpiredPrev, ST_Valid
        let bst = match k {
            1 => [0, 0, 0, 0, 0],
            2..=9 => [1, 80 - 10 * (k - 2), 0, 0, 1],
            10 => [1, 0, 1, 0, 0],
            _ => [2, 0, 0, 1, 0],
        };
        check(
            &mut sim,
            "G",
            "B",
            &[
                ("CurrentState", bst[0]),
                ("ST_CurrValue", bst[1]),
                ("ST_Expired", bst[2]),
                ("ST_ExpiredPrev", bst[3]),
                ("ST_Valid", bst[4]),
            ],
        );
        // B's wait: 50 ms from cycle 2, expired in cycle 7, until B leaves state 1.
        let bwt = match k {
            1 => [0, 0],
            2..=6 => [50 - 10 * (k - 2), 0],
            7..=10 => [0, 1],
            _ => [0, 0],
        };
        check(
            &mut sim,
            "G",
            "B",
            &[("WT_CurrValue", bwt[0]), ("WT_Expired", bwt[1])],
        );
        let change_a = u32::from(matches!(k, 1 | 2 | 7));
        let change_b = u32::from(matches!(k, 1 | 2 | 11));
        check(&mut sim, "G", "A", &[("StateChange", change_a)]);
        check(&mut sim, "G", "B", &[("StateChange", change_b)]);
    }
}

// ------------------------------------------------------------------------------------ E5

fn e5_program(a_first: bool) -> higraph_runtime::Program {
    let auftraggeber = GraphB::new(
        "Auftraggeber",
        &[
            ("Start", Ty::Bool),
            ("OM_Go", Ty::Bool),
            ("IM_Fertig", Ty::Bool),
        ],
    )
    .msg("OM_Go", false)
    .msg("IM_Fertig", true)
    .state(0, "")
    .state(1, "E: S OM_Go;")
    .state(2, "")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("0->1", "U Start;")
    .trans("1->2", "U IM_Fertig; !: R IM_Fertig;")
    .build();
    let ausfuehrer = GraphB::new(
        "Ausfuehrer",
        &[("IM_Go", Ty::Bool), ("OM_Fertig", Ty::Bool)],
    )
    .msg("IM_Go", true)
    .msg("OM_Fertig", false)
    .state(0, "")
    .state(1, "E: S OM_Fertig;")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("0->1", "U IM_Go; !: R IM_Go;")
    .trans("1->0", "")
    .build();
    let mut b = ProgramB::new();
    let ga = b.graph(auftraggeber);
    let gb = b.graph(ausfuehrer);
    let a = ("A", ga, &[("Start", "M 0.0"), ("OM_Go", "B.IM_Go")][..]);
    let bb = ("B", gb, &[("OM_Fertig", "A.IM_Fertig")][..]);
    let order = if a_first { [a, bb] } else { [bb, a] };
    b.group("G", PLAIN, &order);
    b.build()
}

#[test]
fn e5_message_handshake_a_then_b() {
    let mut sim = Sim::new(e5_program(true));
    // (set, A: s IM_Fertig, B: s IM_Go)
    let table: [(bool, [u32; 2], [u32; 2]); 3] = [
        (false, [0, 0], [0, 0]),
        (true, [1, 1], [1, 0]),
        (false, [2, 0], [0, 0]),
    ];
    for (start, a, b) in table {
        if start {
            sim.set("M 0.0", 1);
        }
        sim.step();
        check(
            &mut sim,
            "G",
            "A",
            &[("CurrentState", a[0]), ("IM_Fertig", a[1])],
        );
        check(
            &mut sim,
            "G",
            "B",
            &[("CurrentState", b[0]), ("IM_Go", b[1])],
        );
        if sim.cycle == 2 {
            // The whole record of one cycle: parts in execution order.
            assert_eq!(
                serde_json::to_value(&sim.records).expect("json"),
                json!([
                    {"group": "G", "instance": "A", "state": 1, "previous": 0,
                     "state_change": true,
                     "fired": {"kind": "normal", "from": 0, "to": 1, "prio": 1},
                     "blocked_by": null, "parts": ["state 1 E"]},
                    {"group": "G", "instance": "B", "state": 1, "previous": 0,
                     "state_change": true,
                     "fired": {"kind": "normal", "from": 0, "to": 1, "prio": 1},
                     "blocked_by": null, "parts": ["trans 0->1 !", "state 1 E"]}
                ])
            );
        }
    }
    assert_eq!(parts(&sim, "G", "A"), ["trans 1->2 !"]);
    assert!(parts(&sim, "G", "B").is_empty());
}

#[test]
fn e5_message_handshake_b_then_a() {
    let mut sim = Sim::new(e5_program(false));
    // (set, B: s IM_Go, A: s IM_Fertig)
    let table: [(bool, [u32; 2], [u32; 2]); 4] = [
        (false, [0, 0], [0, 0]),
        (true, [0, 1], [1, 0]),
        (false, [1, 0], [2, 0]),
        (false, [0, 0], [2, 0]),
    ];
    for (start, b, a) in table {
        if start {
            sim.set("M 0.0", 1);
        }
        sim.step();
        check(
            &mut sim,
            "G",
            "B",
            &[("CurrentState", b[0]), ("IM_Go", b[1])],
        );
        check(
            &mut sim,
            "G",
            "A",
            &[("CurrentState", a[0]), ("IM_Fertig", a[1])],
        );
    }
}

// -------------------------------------------------------------------- §2.4 modes and order

#[test]
fn auto_and_manual_gate_before_conditions() {
    let graph = GraphB::new(
        "Modes",
        &[
            ("Go", Ty::Bool),
            ("RanAuto", Ty::Bool),
            ("RanManual", Ty::Bool),
            ("Second", Ty::Bool),
        ],
    )
    .state(0, "")
    .state(1, "")
    .state(2, "")
    .trans("any->0 prio 1", "U INIT_SD;")
    .trans("0->1 prio 1 auto", "SET; = RanAuto; U Go;")
    // Two condition blocks: the second runs only when the first ends with RLO = 1.
    .trans(
        "0->2 prio 2 manual",
        "SET; = RanManual; U Go; ?: SET; = Second;",
    )
    .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[
            ("Ma", g, &[("Go", "M 0.0")]),
            ("Au", g, &[("Go", "M 0.0"), ("AutomaticMode", "TRUE")]),
        ],
    );
    let mut sim = Sim::new(b.build());
    sim.step();
    sim.step();
    // No mode: nothing fires and no condition ran; Au's auto transition is tested but Go = 0.
    check(
        &mut sim,
        "G",
        "Ma",
        &[("CurrentState", 0), ("RanAuto", 0), ("RanManual", 0)],
    );
    check(&mut sim, "G", "Au", &[("CurrentState", 0), ("RanAuto", 1)]);
    sim.set_var("G", "Ma", "ManualMode", 1);
    sim.step();
    // Manual only: the auto transition is skipped before its conditions; the manual one's
    // first block ends with RLO = 0 (Go = 0), so the second block does not run.
    check(
        &mut sim,
        "G",
        "Ma",
        &[
            ("CurrentState", 0),
            ("RanAuto", 0),
            ("RanManual", 1),
            ("Second", 0),
        ],
    );
    sim.set("M 0.0", 1);
    sim.step();
    check(
        &mut sim,
        "G",
        "Ma",
        &[("CurrentState", 2), ("RanAuto", 0), ("Second", 1)],
    );
    check(
        &mut sim,
        "G",
        "Au",
        &[("CurrentState", 1), ("RanManual", 0)],
    );
}

// ------------------------------------------------------------------------------- §2.6 waits

#[test]
fn waits_without_wait_time_and_wait_read_once() {
    let graph = GraphB::new("Waits", &[("Go", Ty::Bool), ("Dauer", Ty::Time)])
        .state(0, "")
        .state(1, "")
        .state(2, "")
        .state(3, "")
        .state(4, "")
        .wait(2, TimeValue::Operand(Operand::Var(19)))
        .wait(3, TimeValue::Const(0))
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Go;")
        .trans("1->2 waits", "U Go;")
        .trans("2->3 waits", "U Go;")
        .trans("3->4 waits", "U Go;")
        .build();
    assert_eq!(graph.vars[19].name, "Dauer");
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[("I", g, &[("Go", "M 0.0"), ("Dauer", "MD 8")])],
    );
    let mut sim = Sim::new(b.build());
    sim.set("MD 8", 30);
    sim.set("M 0.0", 1);
    sim.step();
    sim.step();
    check(&mut sim, "G", "I", &[("CurrentState", 1), ("WT_Valid", 0)]);
    // State 1 has no wait time: its `waits` transition fires at once.
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 2), ("WT_Valid", 1), ("WT_CurrValue", 30)],
    );
    // The operand was read at entry; a later change does not matter.
    sim.set("MD 8", 1000);
    for (k, left) in [(4, 20), (5, 10)] {
        sim.step();
        assert_eq!(sim.cycle, k);
        check(
            &mut sim,
            "G",
            "I",
            &[("CurrentState", 2), ("WT_CurrValue", left)],
        );
    }
    // Expired in cycle 6 = 3 + ⌈30/10⌉; state 3's wait T#0MS means no wait time.
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[
            ("CurrentState", 3),
            ("WT_Valid", 0),
            ("WT_Expired", 0),
            ("WT_CurrValue", 0),
        ],
    );
    sim.step();
    check(&mut sim, "G", "I", &[("CurrentState", 4)]);
}

#[test]
fn wt_stop_pauses_the_wait() {
    let graph = GraphB::new("Stop", &[("Go", Ty::Bool)])
        .state(0, "")
        .state(1, "")
        .wait(0, TimeValue::Const(20))
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1 waits", "U Go;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[("I", g, &[("Go", "M 0.0"), ("WT_Stop", "M 0.1")])],
    );
    let mut sim = Sim::new(b.build());
    sim.set("M 0.0", 1);
    sim.step(); // entered with 20 (no update in the fresh cycle)
    check(&mut sim, "G", "I", &[("WT_CurrValue", 20), ("WT_Valid", 1)]);
    sim.set("M 0.1", 1);
    sim.step();
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 0), ("WT_CurrValue", 20)],
    );
    sim.set("M 0.1", 0);
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 0), ("WT_CurrValue", 10)],
    );
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 1), ("WT_Expired", 0)],
    );
}

// -------------------------------------------------------------------------- §2.8 restarts

fn restart_program(options: GroupOptions, two: bool) -> higraph_runtime::Program {
    let graph = GraphB::new("R", &[("Go", Ty::Bool), ("NE0", Ty::Int)])
        .state(0, "E: L #NE0; + 1; T #NE0;")
        .state(1, "C: = M 3.0; X: SET; = M 3.1;")
        .supervise(1, TimeValue::Const(20))
        .trans("any->0 prio 1", "U INIT_SD; !: SET; = M 3.2;")
        .trans("0->1", "U Go;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    if two {
        b.group(
            "G",
            options,
            &[("U1", g, &[("Go", "M 0.1")]), ("U2", g, &[("Go", "M 0.0")])],
        );
    } else {
        b.group("G", options, &[("I", g, &[("Go", "M 0.0")])]);
    }
    b.build()
}

#[test]
fn warm_restart_fires_the_startup_transition() {
    let mut sim = Sim::new(restart_program(opts(true, false, false), false));
    sim.step();
    let r = sim.rec("G", "I").clone();
    assert_eq!(r.fired.as_ref().map(|f| f.kind), Some("initial"));
    assert_eq!(r.parts, ["state 0 E"]);
    check_mem(&mut sim, &[("M 3.2", 0)]);
    sim.set("M 0.0", 1);
    sim.step();
    sim.set("M 0.0", 0);
    check_mem(&mut sim, &[("M 3.0", 1)]);
    sim.step();
    sim.step(); // 20 ms in state 1: supervision expired
    check(
        &mut sim,
        "G",
        "I",
        &[
            ("CurrentState", 1),
            ("ST_Expired", 1),
            ("ST_ExpiredPrev", 0),
            ("INIT_SD", 0),
        ],
    );
    sim.restart(false);
    sim.step();
    let r = sim.rec("G", "I").clone();
    let f = r.fired.expect("startup fires");
    assert_eq!(
        (f.kind, f.from, f.to, f.prio),
        ("startup", None, 0, Some(1))
    );
    assert_eq!(
        r.parts,
        ["trans any->0 !", "state 1 C0", "state 1 X", "state 0 E"]
    );
    // `!` ran, the RLO-0 pass reset M 3.0, `X` ran; ST_ExpiredPrev kept (a normal change
    // would copy ST_Expired = 1); nothing was reset.
    check_mem(&mut sim, &[("M 3.2", 1), ("M 3.0", 0), ("M 3.1", 1)]);
    check(
        &mut sim,
        "G",
        "I",
        &[
            ("CurrentState", 0),
            ("PreviousState", 1),
            ("StateChange", 1),
            ("ST_ExpiredPrev", 0),
            ("ST_Expired", 0),
            ("NE0", 2),
            ("INIT_SD", 1),
        ],
    );
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[
            ("CurrentState", 0),
            ("StateChange", 0),
            ("INIT_SD", 0),
            ("NE0", 2),
        ],
    );
}

#[test]
fn cold_restart_is_an_initial_entry() {
    let mut sim = Sim::new(restart_program(opts(true, false, false), false));
    sim.step();
    sim.set("M 0.0", 1);
    sim.step();
    sim.set("M 0.0", 0);
    check(&mut sim, "G", "I", &[("CurrentState", 1), ("NE0", 1)]);
    sim.restart(true);
    sim.step();
    let r = sim.rec("G", "I").clone();
    let f = r.fired.expect("initial entry");
    assert_eq!((f.kind, f.from, f.to, f.prio), ("initial", None, 0, None));
    // No `!`, no RLO-0 pass, no `X`.
    assert_eq!(r.parts, ["state 0 E"]);
    check_mem(&mut sim, &[("M 3.2", 0), ("M 3.1", 0)]);
    check(
        &mut sim,
        "G",
        "I",
        &[
            ("CurrentState", 0),
            ("PreviousState", 0),
            ("StateChange", 1),
            ("ST_ExpiredPrev", 0),
            ("NE0", 1),
        ],
    );
}

#[test]
fn any_once_warm_restart_leaves_the_initial_state_alone() {
    let mut sim = Sim::new(restart_program(opts(false, true, false), true));
    sim.set("M 0.0", 1);
    sim.step();
    sim.step();
    sim.set("M 0.0", 0);
    check(&mut sim, "G", "U1", &[("CurrentState", 0), ("NE0", 1)]);
    check(&mut sim, "G", "U2", &[("CurrentState", 1), ("NE0", 1)]);
    sim.restart(false);
    sim.step();
    let u1 = sim.rec("G", "U1").clone();
    assert!(u1.fired.is_none());
    assert_eq!(u1.blocked_by.map(|b| b.prio), Some(1));
    assert!(u1.parts.is_empty());
    check(
        &mut sim,
        "G",
        "U1",
        &[("CurrentState", 0), ("StateChange", 0), ("NE0", 1)],
    );
    let u2 = sim.rec("G", "U2").clone();
    assert_eq!(u2.fired.map(|f| f.kind), Some("startup"));
    check(
        &mut sim,
        "G",
        "U2",
        &[
            ("CurrentState", 0),
            ("PreviousState", 1),
            ("StateChange", 1),
            ("NE0", 2),
        ],
    );
}

#[test]
fn internal_messages_reset_when_fresh_only() {
    let graph = GraphB::new("Msg", &[("In", Ty::Bool), ("Out", Ty::Bool)])
        .msg("In", true)
        .msg("Out", false)
        .init("In", Value::Bool(true))
        .state(0, "")
        .trans("any->0 prio 1", "U INIT_SD;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("X", g, &[("Out", "Y.In")]), ("Y", g, &[])]);
    let program = b.build();
    assert_eq!(program.groups[0].internal_messages.len(), 1);
    let mut sim = Sim::new(program);
    // The cell starts TRUE (its initial value); the fresh group resets it.
    check(&mut sim, "G", "Y", &[("In", 1)]);
    sim.step();
    check(&mut sim, "G", "Y", &[("In", 0)]);
    // X's own `In` is no link target: untouched.
    check(&mut sim, "G", "X", &[("In", 1)]);
    sim.set_var("G", "Y", "In", 1);
    sim.step();
    check(&mut sim, "G", "Y", &[("In", 1)]);
    sim.restart(false);
    sim.step();
    check(&mut sim, "G", "Y", &[("In", 1)]);
    sim.restart(true);
    sim.step();
    check(&mut sim, "G", "Y", &[("In", 0)]);
}

// ------------------------------------------------------------------------------- options

#[test]
fn precyclic_on_entry_runs_the_new_states_pre_part() {
    let graph = GraphB::new("Pre", &[("Go", Ty::Bool), ("N", Ty::Int)])
        .state(0, "")
        .state(1, "E: SET; = M 4.0; C-: L #N; + 1; T #N; C: SET; = M 4.1;")
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Go;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "W",
        opts(false, false, true),
        &[("I", g, &[("Go", "M 0.0")])],
    );
    b.group("N", PLAIN, &[("I", g, &[("Go", "M 0.0")])]);
    let mut sim = Sim::new(b.build());
    sim.step();
    sim.set("M 0.0", 1);
    sim.step();
    assert_eq!(
        parts(&sim, "W", "I"),
        ["state 1 E", "state 1 C-", "state 1 C"]
    );
    assert_eq!(parts(&sim, "N", "I"), ["state 1 E", "state 1 C"]);
    check(&mut sim, "W", "I", &[("N", 1)]);
    check(&mut sim, "N", "I", &[("N", 0)]);
    sim.step();
    assert_eq!(parts(&sim, "W", "I"), ["state 1 C-", "state 1 C"]);
    check(&mut sim, "W", "I", &[("N", 2)]);
    check(&mut sim, "N", "I", &[("N", 1)]);
}

// ------------------------------------------------------------------------ return, messages

#[test]
fn return_needs_a_previous_state_of_the_graph() {
    let graph = GraphB::new("Ret", &[("Go", Ty::Bool), ("Tried", Ty::Bool)])
        .state(1, "")
        .state(2, "")
        .trans("any->1 prio 1", "U INIT_SD;")
        .trans("1->return prio 1", "SET; = Tried; U Go;")
        .trans("1->2 prio 2", "U Go;")
        .trans("2->return", "U Go; !: SET; = M 6.1;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("I", g, &[("Go", "M 0.0")])]);
    let mut sim = Sim::new(b.build());
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 1), ("PreviousState", 0)],
    );
    sim.set("M 0.0", 1);
    sim.step();
    // PreviousState 0 is no state: the return transition is not eligible and its
    // conditions did not run; the next one fires.
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 2), ("PreviousState", 1), ("Tried", 0)],
    );
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 1), ("PreviousState", 2)],
    );
    let r = sim.rec("G", "I").clone();
    let f = r.fired.expect("return");
    assert_eq!(
        (f.kind, f.from, f.to, f.prio),
        ("return", Some(2), 1, Some(1))
    );
    assert_eq!(r.parts, ["trans 2->1 !"]);
    check_mem(&mut sim, &[("M 6.1", 1)]);
    sim.step();
    check(
        &mut sim,
        "G",
        "I",
        &[("CurrentState", 2), ("PreviousState", 1), ("Tried", 1)],
    );
}

#[test]
fn usr_msg_send_follows_fault_and_message_states() {
    let graph = GraphB::new("Rep", &[("Go", Ty::Bool)])
        .state(0, "")
        .state(3, "")
        .reports(3)
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->3", "U Go;")
        .trans("3->0", "UN Go;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "G",
        PLAIN,
        &[("I", g, &[("Go", "M 0.0"), ("UsrMsgSend", "M 9.0")])],
    );
    let mut sim = Sim::new(b.build());
    sim.step();
    check_mem(&mut sim, &[("M 9.0", 0)]);
    sim.set("M 0.0", 1);
    sim.step();
    check(&mut sim, "G", "I", &[("CurrentState", 3)]);
    check_mem(&mut sim, &[("M 9.0", 1)]);
    sim.step();
    check_mem(&mut sim, &[("M 9.0", 1)]);
    sim.set("M 0.0", 0);
    sim.step();
    check(&mut sim, "G", "I", &[("CurrentState", 0)]);
    check_mem(&mut sim, &[("M 9.0", 0)]);
}

#[test]
fn permanent_parts_frame_the_turn() {
    let graph = GraphB::new("Perm", &[("Go", Ty::Bool), ("Order", Ty::Int)])
        .state(0, "X: L #Order; + 10; T #Order;")
        .state(
            1,
            "E: L #Order; + 100; T #Order; C: L #Order; + 1000; T #Order;",
        )
        .permanent("C-: L 1; T #Order; C: L #Order; + 5; T #Order;")
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Go; !: SET; = M 5.0;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("I", g, &[("Go", "M 0.0")])]);
    let mut sim = Sim::new(b.build());
    sim.step();
    sim.set("M 0.0", 1);
    sim.step();
    assert_eq!(
        parts(&sim, "G", "I"),
        [
            "permanent C-",
            "trans 0->1 !",
            "state 0 X",
            "state 1 E",
            "state 1 C",
            "permanent C"
        ]
    );
    // 1, then X +10, E +100, C +1000, permanent C +5.
    check(&mut sim, "G", "I", &[("Order", 1116)]);
}

#[test]
fn fresh_turn_skips_the_time_update() {
    // Permanent `C-` runs after step 0, so it sees whether the times were counted down.
    let graph = GraphB::new("Fresh", &[])
        .state(0, "")
        .permanent("C-: L WT_CurrValue; T MD 20;")
        .trans("any->0 prio 1", "U INIT_SD;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("I", g, &[])]);
    let mut sim = Sim::new(b.build());
    sim.set_var("G", "I", "WT_Valid", 1);
    sim.set_var("G", "I", "WT_CurrValue", 30);
    sim.step();
    check_mem(&mut sim, &[("MD 20", 30)]);
    // The initial entry loaded state 0's (absent) wait time.
    check(&mut sim, "G", "I", &[("WT_Valid", 0), ("WT_CurrValue", 0)]);
    sim.set_var("G", "I", "WT_Valid", 1);
    sim.set_var("G", "I", "WT_CurrValue", 30);
    sim.step();
    check_mem(&mut sim, &[("MD 20", 20)]);
}

#[test]
fn a_fault_stops_the_call_and_keeps_the_partial_record() {
    let graph = GraphB::new("Fault", &[("Go", Ty::Bool)])
        .state(0, "")
        .state(1, "E: SET; = M 5.0; E: L MW 70000;")
        .permanent("C: SET; = M 5.1;")
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Go;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("I", g, &[("Go", "M 0.0")]), ("J", g, &[])]);
    let mut sim = Sim::new(b.build());
    sim.step();
    sim.set("M 5.1", 0);
    sim.set("M 0.0", 1);
    let fault = sim.try_step().expect_err("access past byte 65535");
    assert!(!fault.reason.is_empty());
    // The change happened (CurrentState is written before `E`), the permanent `C` did not run,
    // and J had no turn.
    check(&mut sim, "G", "I", &[("CurrentState", 1)]);
    check_mem(&mut sim, &[("M 5.0", 1), ("M 5.1", 0)]);
    assert_eq!(sim.records.len(), 1);
    let r = sim.rec("G", "I");
    assert_eq!(r.parts, ["state 1 E"]);
    assert_eq!((r.state, r.previous), (0, 0));
}

#[test]
fn delta_is_the_tests_cycle_unless_given() {
    let graph = GraphB::new("Delta", &[])
        .state(0, "")
        .wait(0, TimeValue::Const(100))
        .trans("any->0 prio 1", "U INIT_SD;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group("G", PLAIN, &[("I", g, &[])]);
    let mut program = b.build();
    program.test = Some(Test {
        name: "t".to_owned(),
        cycle_ms: 25,
        run: Vec::new(),
        stmts: Vec::new(),
        watch: Vec::new(),
        origin: Origin::NONE,
    });
    let mut sim = Sim::new(program.clone());
    sim.step();
    sim.step();
    check(&mut sim, "G", "I", &[("WT_CurrValue", 75)]);
    let mut sim = Sim::new(program);
    sim.rts[0] = GroupRt::with_cycle_ms(40);
    sim.step();
    sim.step();
    check(&mut sim, "G", "I", &[("WT_CurrValue", 60)]);
}

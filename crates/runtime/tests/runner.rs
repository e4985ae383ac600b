//! The test runner (`runtime.md` §5.2, §6, §7) on hand-built programs: failing expects go on,
//! a failing `until` and a fault stop the test, restarts, the cycle limit, cancellation, the
//! JSON trace records and the VCD (read back with the `vcd` crate).

mod group_support;

use group_support::{GraphB, ProgramB};
use higraph_runtime::program::{
    CmpOp, Expr, GroupOptions, MemArea, Origin, Path, PathKind, Place, Program, RunEntry, Test,
    TestStmt, TestStmtKind, Width,
};
use higraph_runtime::test::{self, Outcome, RunOptions, TestRun};
use higraph_runtime::{Ty, Value};

const PLAIN: GroupOptions = GroupOptions {
    cyclic_rlo0: false,
    any_once: false,
    precyclic_on_entry: false,
};

/// `G.I`: states 0 and 1; `0->1 < U Start; >` with Start := M 0.0; state 1 sets Out := M 1.0
/// on entry; the startup transition `any->0 prio 1 < U INIT_SD; >`.
fn program(stmts: Vec<TestStmtKind>) -> Program {
    let graph = GraphB::new("G", &[("Start", Ty::Bool), ("Out", Ty::Bool)])
        .state(0, "")
        .state(1, "E: S Out;")
        .trans("any->0 prio 1", "U INIT_SD;")
        .trans("0->1", "U Start;")
        .trans("1->0", "UN Start;")
        .build();
    let mut b = ProgramB::new();
    let g = b.graph(graph);
    b.group(
        "Grp",
        PLAIN,
        &[("I", g, &[("Start", "M 0.0"), ("Out", "M 1.0")])],
    );
    let mut p = b.build();
    let watch = vec![start(), out(), state()];
    p.test = Some(Test {
        name: "T".into(),
        cycle_ms: 10,
        run: vec![RunEntry::Group(0)],
        stmts: stmts
            .into_iter()
            .enumerate()
            .map(|(i, kind)| TestStmt {
                kind,
                origin: Origin(i as u32),
            })
            .collect(),
        watch,
        origin: Origin(1000),
    });
    p
}

fn bit(byte: u32, bit: u8) -> Place {
    Place::Mem {
        area: MemArea::Memory,
        byte,
        width: Width::Bit(bit),
    }
}

fn start() -> Path {
    Path {
        text: "M0.0".into(),
        ty: Ty::Bool,
        kind: PathKind::Place(bit(0, 0)),
    }
}

fn out() -> Path {
    Path {
        text: "M1.0".into(),
        ty: Ty::Bool,
        kind: PathKind::Place(bit(1, 0)),
    }
}

fn state() -> Path {
    Path {
        text: "I.state".into(),
        ty: Ty::Word,
        kind: PathKind::InstState {
            group: 0,
            instance: 0,
            previous: false,
        },
    }
}

fn read(path: Path) -> Box<Expr> {
    Box::new(Expr::Read(path))
}

fn state_is(n: u16) -> Expr {
    Expr::Cmp(
        CmpOp::Eq,
        read(state()),
        Box::new(Expr::Const(Value::Word(n))),
    )
}

fn set(path: Path, value: bool) -> TestStmtKind {
    TestStmtKind::Set {
        target: path,
        value: Expr::Const(Value::Bool(value)),
    }
}

fn expect(cond: Expr) -> TestStmtKind {
    TestStmtKind::Expect {
        cond,
        message: None,
        expr_origin: Origin(500),
    }
}

fn step(cycles: u64) -> TestStmtKind {
    TestStmtKind::Step { cycles }
}

fn run(p: &Program, trace: bool) -> TestRun {
    test::run(
        p,
        &RunOptions {
            trace,
            cancelled: &|| false,
        },
    )
    .expect("not cancelled")
}

fn messages(r: &TestRun) -> Vec<&str> {
    r.failures.iter().map(|f| f.message.as_str()).collect()
}

#[test]
fn a_failing_expect_is_reported_and_the_test_goes_on() {
    let p = program(vec![
        expect(Expr::Read(out())),
        set(start(), true),
        step(2),
        expect(state_is(1)),
        TestStmtKind::Expect {
            cond: Expr::Not(read(out())),
            message: Some("Out stays off".into()),
            expr_origin: Origin(501),
        },
        step(1),
    ]);
    let r = run(&p, false);
    assert_eq!(r.outcome, Outcome::Failed);
    assert_eq!(
        messages(&r),
        [
            "expect failed: at cycle 0 (t = 0 ms): M1.0 = FALSE",
            "expect failed: Out stays off: at cycle 2 (t = 20 ms): M1.0 = TRUE",
        ]
    );
    assert_eq!(r.failures[0].code, "HG9901");
    assert_eq!(r.failures[0].origin, Origin(500));
    assert_eq!(r.failures[1].origin, Origin(501));
    assert_eq!(r.failures[1].statement, Origin(4));
    assert_eq!((r.failures[1].cycle, r.failures[1].time_ms), (2, 20));
    assert_eq!(
        r.failures[1].values,
        [("M1.0".to_string(), Value::Bool(true))]
    );
    // The step after the failures ran.
    assert_eq!((r.cycles, r.time_ms), (3, 30));
}

#[test]
fn passing_tests_pass() {
    let p = program(vec![
        expect(state_is(0)),
        set(start(), true),
        TestStmtKind::Until {
            cond: state_is(1),
            cycles: 5,
            within: "T#50MS".into(),
            message: None,
            expr_origin: Origin(500),
        },
        expect(Expr::Read(out())),
    ]);
    let r = run(&p, false);
    assert_eq!(r.outcome, Outcome::Passed, "{:?}", r.failures);
    // Cycle 1: initial entry; cycle 2: 0->1.
    assert_eq!(r.cycles, 2);
}

#[test]
fn an_until_that_never_holds_stops_the_test() {
    let p = program(vec![
        set(start(), true),
        TestStmtKind::Until {
            cond: Expr::And(Box::new(state_is(0)), read(out())),
            cycles: 3,
            within: "T#30MS".into(),
            message: Some("never".into()),
            expr_origin: Origin(500),
        },
        step(100),
        expect(state_is(7)),
    ]);
    let r = run(&p, false);
    assert_eq!(r.outcome, Outcome::Failed);
    assert_eq!(
        messages(&r),
        [
            "'I.state = 0 and M1.0' did not hold within T#30MS: never: at cycle 3: I.state = 1, M1.0 = TRUE"
        ]
    );
    assert_eq!(r.failures[0].code, "HG9902");
    assert_eq!(r.cycles, 3);
}

#[test]
fn an_until_that_holds_already_runs_no_cycle() {
    let p = program(vec![TestStmtKind::Until {
        cond: state_is(0),
        cycles: 3,
        within: "T#30MS".into(),
        message: None,
        expr_origin: Origin(500),
    }]);
    let r = run(&p, false);
    assert_eq!((r.outcome, r.cycles), (Outcome::Passed, 0));
}

#[test]
fn a_fault_stops_the_test() {
    let past_the_end = Path {
        text: "MW65535".into(),
        ty: Ty::Word,
        kind: PathKind::Place(Place::Mem {
            area: MemArea::Memory,
            byte: 65535,
            width: Width::Word,
        }),
    };
    let p = program(vec![
        step(1),
        TestStmtKind::Set {
            target: past_the_end,
            value: Expr::Const(Value::Word(1)),
        },
        step(5),
        expect(state_is(7)),
    ]);
    let r = run(&p, false);
    assert_eq!(r.outcome, Outcome::Error);
    assert_eq!(r.failures.len(), 1);
    let f = &r.failures[0];
    assert_eq!(f.code, "HG9903");
    assert!(
        f.message.starts_with("runtime fault at cycle 1: "),
        "{}",
        f.message
    );
    // A fault in a test statement points at the statement.
    assert_eq!((f.origin, f.statement), (Origin(1), Origin(1)));
    assert_eq!(r.cycles, 1);
}

#[test]
fn restarts_pass_init_sd_again() {
    let p = program(vec![
        set(start(), true),
        step(2),
        expect(state_is(1)),
        TestStmtKind::Restart { cold: false },
        // Warm: INIT_SD = 1 fires the startup transition into 0 (memory kept: Start TRUE).
        step(1),
        expect(state_is(0)),
        step(1),
        expect(state_is(1)),
        TestStmtKind::Restart { cold: true },
        // Cold: bit memory is reset, so Start is FALSE; the initial entry leads to 0.
        step(2),
        expect(state_is(0)),
        expect(Expr::Not(read(start()))),
    ]);
    let r = run(&p, true);
    assert_eq!(r.outcome, Outcome::Passed, "{:?}", messages(&r));
    let trace = r.trace.expect("trace");
    let init_sd: Vec<bool> = trace.cycles.iter().map(|c| c.init_sd).collect();
    assert_eq!(init_sd, [true, false, true, false, true, false]);
    let json = serde_json::to_value(&trace.cycles[2].before).unwrap();
    assert_eq!(json, serde_json::json!([{"restart": "warm"}]));
}

#[test]
fn more_than_ten_million_cycles_is_a_fault() {
    let mut p = program(vec![step(10_000_001)]);
    // Nothing to run makes the cycles cheap.
    if let Some(t) = &mut p.test {
        t.run.clear();
    }
    let r = run(&p, false);
    assert_eq!(r.outcome, Outcome::Error);
    assert_eq!(r.cycles, 10_000_000);
    assert_eq!(
        messages(&r),
        ["runtime fault at cycle 10000001: more than 10000000 cycles in one test"]
    );
}

#[test]
fn cancellation_is_asked_between_cycles() {
    let p = program(vec![step(1000)]);
    let asked = std::cell::Cell::new(0);
    let result = test::run(
        &p,
        &RunOptions {
            trace: false,
            cancelled: &|| {
                asked.set(asked.get() + 1);
                asked.get() > 5
            },
        },
    );
    assert!(result.is_none());
    assert_eq!(asked.get(), 6);
}

#[test]
fn the_trace_records_every_cycle() {
    let p = program(vec![
        set(start(), true),
        step(2),
        expect(state_is(1)),
        set(start(), false),
        step(1),
    ]);
    let r = run(&p, true);
    let trace = r.trace.expect("trace");
    assert_eq!(trace.cycles.len(), 3);
    let json = serde_json::to_value(&trace).unwrap();
    assert_eq!(json["version"], 1);
    assert_eq!(json["test"], "T");
    assert_eq!(json["run"], serde_json::json!(["Grp"]));
    assert_eq!(json["result"], "passed");
    assert_eq!(
        json["initial"]["watch"],
        serde_json::json!({"M0.0": false, "M1.0": false, "I.state": 0})
    );
    let c1 = &json["cycles"][0];
    assert_eq!(c1["cycle"], 1);
    assert_eq!(c1["time_ms"], 10);
    assert_eq!(c1["init_sd"], true);
    assert_eq!(
        c1["before"],
        serde_json::json!([{"set": "M0.0", "value": true}])
    );
    assert_eq!(c1["instances"][0]["fired"]["kind"], "initial");
    let c2 = &json["cycles"][1];
    assert_eq!(
        c2["watch"],
        serde_json::json!({"M0.0": true, "M1.0": true, "I.state": 1})
    );
    assert_eq!(
        c2["instances"][0]["parts"],
        serde_json::json!(["state 1 E"])
    );
    let c3 = &json["cycles"][2];
    assert_eq!(
        c3["before"],
        serde_json::json!([{"set": "M0.0", "value": false}])
    );
    assert_eq!(c3["instances"][0]["state"], 0);
    // The watch keeps the order of first use, whatever serde_json's map does.
    let text = serde_json::to_string(&trace).unwrap();
    let m0 = text.find("\"M0.0\":true,\"M1.0\"").expect("watch order");
    assert!(m0 > 0);
    // Deterministic: the same program gives the same bytes.
    let again = serde_json::to_string(&run(&p, true).trace.unwrap()).unwrap();
    assert_eq!(text, again);
}

#[test]
fn the_vcd_reads_back() {
    let p = program(vec![
        set(start(), true),
        step(2),
        set(start(), false),
        step(2),
    ]);
    let r = run(&p, true);
    let trace = r.trace.expect("trace");
    let text = higraph_runtime::vcd::write(&p, &trace, "9.9.9");
    assert!(text.starts_with("$version higraph-lsp 9.9.9 $end\n$timescale 1 ms $end\n"));
    assert!(!text.contains("$date"));

    let mut parser = vcd::Parser::new(text.as_bytes());
    let header = parser.parse_header().expect("header");
    assert_eq!(header.timescale, Some((1, vcd::TimescaleUnit::MS)));
    let find = |path: &[&str]| {
        header
            .find_var(path)
            .unwrap_or_else(|| panic!("{path:?} in\n{text}"))
            .code
    };
    let state = find(&["T", "Grp", "I", "state"]);
    let s1 = find(&["T", "Grp", "I", "S1"]);
    let change = find(&["T", "Grp", "I", "StateChange"]);
    let out_var = find(&["T", "watch", "M1.0"]);
    let state_watch = find(&["T", "watch", "I.state"]);
    assert_eq!(
        header.find_var(&["T", "Grp", "I", "state"]).unwrap().size,
        16
    );
    // Replay: (time, code) -> value.
    let mut time = 0;
    let mut seen: Vec<(u64, vcd::IdCode, String)> = Vec::new();
    for command in parser {
        match command.expect("command") {
            vcd::Command::Timestamp(t) => time = t,
            vcd::Command::ChangeScalar(code, v) => seen.push((time, code, v.to_string())),
            vcd::Command::ChangeVector(code, v) => seen.push((time, code, v.to_string())),
            _ => {}
        }
    }
    let at = |t: u64, code: vcd::IdCode| {
        seen.iter()
            .rfind(|(time, c, _)| *time <= t && *c == code)
            .map(|(_, _, v)| v.clone())
    };
    assert_eq!(at(0, state).as_deref(), Some("0"));
    assert_eq!(at(0, change).as_deref(), Some("1"));
    assert_eq!(at(20, state).as_deref(), Some("1"));
    assert_eq!(at(20, s1).as_deref(), Some("1"));
    assert_eq!(at(20, out_var).as_deref(), Some("1"));
    assert_eq!(at(20, state_watch).as_deref(), Some("1"));
    // Cycle 3: Start FALSE, 1->0.
    assert_eq!(at(30, state).as_deref(), Some("0"));
    assert_eq!(at(30, s1).as_deref(), Some("0"));
    // Cycle 4 changes only StateChange; the dump ends at the last cycle.
    assert_eq!(at(40, change).as_deref(), Some("0"));
    assert!(text.trim_end().lines().any(|l| l == "#40"));
}

#[test]
fn an_expression_without_paths_has_no_values() {
    let p = program(vec![expect(Expr::Const(Value::Bool(false)))]);
    let r = run(&p, false);
    assert_eq!(messages(&r), ["expect failed: at cycle 0 (t = 0 ms)"]);
}

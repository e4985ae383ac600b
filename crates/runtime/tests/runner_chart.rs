//! The test runner with a chart (`runtime.md` §5.2): commands are queued for the next cycle,
//! `confirm` needs an active step (else a fault), a restart puts the chart back to Ready.

mod chart_common;

use chart_common::{and, chart, chart_state, cmp, k, not, seq, step, step_path, trans};
use higraph_runtime::Value;
use higraph_runtime::program::{
    CmpOp, Command, Expr, Origin, Program, RunEntry, SfcFlag, StepMember, Switching, Test,
    TestStmt, TestStmtKind,
};
use higraph_runtime::test::{self, Outcome, RunOptions, TestRun};

/// Chart `C`: sequencer RUN (start condition SFC.RUN) with steps S1 (to be confirmed) and
/// S2, `T1` between them without condition; switching mode B, so S1 leaves once confirmed.
fn program(stmts: Vec<TestStmtKind>) -> Program {
    let run = seq(
        "RUN",
        1,
        vec![chart_common::sfc(SfcFlag::Run)],
        vec![step("S1").confirm(), step("S2")],
        vec![trans("T1", &[0], &[1], vec![])],
    );
    let mut c = chart("C", vec![], vec![run]);
    c.switching = Switching::B;
    Program {
        charts: vec![c],
        test: Some(Test {
            name: "T".into(),
            cycle_ms: 10,
            run: vec![RunEntry::Chart(0)],
            stmts: stmts
                .into_iter()
                .enumerate()
                .map(|(i, kind)| TestStmt {
                    kind,
                    origin: Origin(i as u32),
                })
                .collect(),
            watch: vec![],
            origin: Origin::NONE,
        }),
        ..Program::default()
    }
}

fn state_is(name: &str) -> Expr {
    cmp(
        CmpOp::Eq,
        chart_state("C.state", 0),
        k(Value::OpState(
            higraph_runtime::program::OpState::from_name(name).expect("a state") as u8,
        )),
    )
}

fn active(name: &str, index: u32) -> Expr {
    step_path(&format!("C.{name}"), 0, 0, index, StepMember::Active)
}

fn expect(cond: Expr) -> TestStmtKind {
    TestStmtKind::Expect {
        cond,
        message: None,
        expr_origin: Origin(500),
    }
}

fn confirm(index: u32, name: &str) -> TestStmtKind {
    TestStmtKind::Confirm {
        chart: 0,
        sequencer: 0,
        step: index,
        text: format!("C.{name}"),
    }
}

fn run(p: &Program) -> TestRun {
    test::run(
        p,
        &RunOptions {
            trace: true,
            cancelled: &|| false,
        },
    )
    .expect("not cancelled")
}

#[test]
fn commands_apply_in_the_next_cycle_and_confirm_moves_on() {
    let p = program(vec![
        expect(state_is("Ready")),
        TestStmtKind::Command {
            chart: 0,
            command: Command::Start,
        },
        expect(state_is("Ready")),
        TestStmtKind::Step { cycles: 1 },
        expect(and(state_is("Active"), active("S1", 0))),
        TestStmtKind::Step { cycles: 2 },
        expect(active("S1", 0)),
        confirm(0, "S1"),
        TestStmtKind::Step { cycles: 1 },
        expect(and(active("S2", 1), not(active("S1", 0)))),
    ]);
    let r = run(&p);
    assert_eq!(r.outcome, Outcome::Passed, "{:?}", r.failures);
    let trace = r.trace.expect("trace");
    let before = serde_json::to_value(&trace.cycles[0].before).unwrap();
    assert_eq!(
        before,
        serde_json::json!([{"command": "start", "chart": "C"}])
    );
    let confirmed = serde_json::to_value(&trace.cycles[3].before).unwrap();
    assert_eq!(confirmed, serde_json::json!([{"confirm": "C.S1"}]));
    assert_eq!(trace.cycles[0].charts[0].state, "Active");
}

#[test]
fn confirming_an_inactive_step_is_a_fault() {
    let p = program(vec![confirm(1, "S2"), TestStmtKind::Step { cycles: 5 }]);
    let r = run(&p);
    assert_eq!(r.outcome, Outcome::Error);
    assert_eq!(r.failures.len(), 1);
    assert_eq!(r.failures[0].code, "HG9903");
    assert!(
        r.failures[0]
            .message
            .starts_with("runtime fault at cycle 0: "),
        "{}",
        r.failures[0].message
    );
    assert_eq!(r.failures[0].origin, Origin(0));
    assert_eq!(r.cycles, 0);
}

#[test]
fn a_restart_puts_the_chart_back_to_ready() {
    let p = program(vec![
        TestStmtKind::Command {
            chart: 0,
            command: Command::Start,
        },
        TestStmtKind::Step { cycles: 1 },
        expect(state_is("Active")),
        TestStmtKind::Restart { cold: false },
        expect(and(state_is("Ready"), not(active("S1", 0)))),
        TestStmtKind::Step { cycles: 1 },
        expect(state_is("Ready")),
    ]);
    let r = run(&p);
    assert_eq!(r.outcome, Outcome::Passed, "{:?}", r.failures);
}

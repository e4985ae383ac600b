//! The chart engine (`runtime.md` §4): the worked examples E6 (§9.3) and §5.5, and one test per
//! rule of the chart cycle.

mod chart_common;

use chart_common::*;
use higraph_runtime::chart::{command_target, successor};
use higraph_runtime::program::{
    ChartTransKind, CmpOp, Command, OpState, Qualifier, SfcFlag, StepMember, Switching,
};
use higraph_runtime::value::Value;

// ------------------------------------------------------------------------------ E6

fn e6() -> Sim {
    let p_start = rd("P_Start", m(30, 0));
    let p_fertig = rd("P_Fertig", m(30, 1));
    let p_ende = rd("P_Ende", m(30, 2));
    // S1 = 0, A = 1, A2 = 2, B = 3, S9 = 4
    let run = seq(
        "RUN",
        1,
        vec![sfc(SfcFlag::Run)],
        vec![
            step("S1"),
            step("A").q(Qualifier::L, 0, Some(30)),
            step("A2"),
            step("B").q(Qualifier::N, 1, None),
            step("S9"),
        ],
        vec![
            trans("T1", &[0], &[1, 3], vec![p_start]),
            trans("TA", &[1], &[2], vec![p_fertig]),
            trans("T2", &[2, 3], &[4], vec![p_ende]),
        ],
    );
    let c = chart(
        "Par",
        vec![("Pumpe", a(2, 0)), ("Mixer", a(2, 1))],
        vec![run],
    );
    Sim::new(c, 10)
}

/// (cycle, M 30.x set before it, state, active steps, Pumpe, Mixer)
type E6Row = (
    u64,
    Option<(u32, u8)>,
    OpState,
    &'static [&'static str],
    bool,
    bool,
);

#[test]
fn e6_parallel_branch_and_l() {
    let mut s = e6();
    s.command(Command::Start);
    s.set(&m(30, 0), true);
    // (cycle, set, state, active, Pumpe, Mixer)
    let table: &[E6Row] = &[
        (1, None, OpState::Active, &["RUN.S1"], false, false),
        (2, None, OpState::Active, &["RUN.A", "RUN.B"], true, true),
        (3, None, OpState::Active, &["RUN.A", "RUN.B"], true, true),
        (4, None, OpState::Active, &["RUN.A", "RUN.B"], true, true),
        (5, None, OpState::Active, &["RUN.A", "RUN.B"], false, true),
        (
            6,
            Some((30, 1)),
            OpState::Active,
            &["RUN.A2", "RUN.B"],
            false,
            true,
        ),
        (7, Some((30, 2)), OpState::Active, &["RUN.S9"], false, false),
        (8, None, OpState::Active, &["RUN.S9"], false, false),
        (9, None, OpState::Active, &[], false, false),
        (10, None, OpState::Completed, &[], false, false),
    ];
    for &(k, set, state, active, pumpe, mixer) in table {
        if let Some((byte, b)) = set {
            s.set(&m(byte, b), true);
        }
        s.step();
        assert_eq!(s.k, k);
        assert_eq!(s.state(), state, "state after cycle {k}");
        assert_eq!(s.active_names(), active, "active after cycle {k}");
        assert_eq!(s.get(&a(2, 0)), pumpe, "Pumpe after cycle {k}");
        assert_eq!(s.get(&a(2, 1)), mixer, "Mixer after cycle {k}");
        assert_eq!(s.rec.state, state.name());
        assert_eq!(
            s.rec.actions.get("Pumpe"),
            Some(&serde_json::Value::Bool(pumpe)),
            "the trace lists every action every cycle"
        );
        match k {
            1 => {
                assert_eq!(s.rec.implicit, ["Starting->Active"]);
                assert_eq!(s.rec.commands.len(), 1);
                assert!(s.rec.commands[0].accepted);
                assert_eq!(s.fired(), [("RUN".into(), "start".into(), None)]);
                assert_eq!(s.rec.running.as_deref(), Some("RUN"));
                assert_eq!(s.phases(), ["RUN.S1 run"]);
            }
            2 => {
                assert_eq!(
                    s.fired(),
                    [("RUN".into(), "trans".into(), Some("T1".into()))]
                );
                assert_eq!(s.rec.fired[0].to, ["A", "B"]);
                assert_eq!(s.phases(), ["RUN.S1 term", "RUN.A run", "RUN.B run"]);
            }
            7 => {
                assert_eq!(s.rec.fired[0].from, ["A2", "B"]);
                assert_eq!(s.rec.fired[0].to, ["S9"]);
                assert_eq!(
                    s.phases(),
                    ["RUN.A2 term", "RUN.B term", "RUN.S9 init"],
                    "join: both last steps leave, the end step begins with init"
                );
            }
            8 => assert_eq!(s.phases(), ["RUN.S9 run"]),
            9 => {
                assert_eq!(s.phases(), ["RUN.S9 term"]);
                assert_eq!(s.rec.running, None, "RUN completed");
            }
            10 => assert_eq!(
                s.rec.implicit,
                ["Active->Completing", "Completing->Completed"]
            ),
            _ => {}
        }
    }
}

#[test]
fn e6_join_waits_for_all_branches() {
    let mut s = e6();
    s.command(Command::Start);
    s.set(&m(30, 0), true);
    s.set(&m(30, 2), true); // P_Ende already TRUE: T2 must still wait for A2
    s.steps(3);
    assert_eq!(s.active_names(), ["RUN.A", "RUN.B"]);
    s.set(&m(30, 1), true);
    s.step();
    assert_eq!(s.active_names(), ["RUN.A2", "RUN.B"]);
    s.step();
    assert_eq!(s.active_names(), ["RUN.S9"]);
}

// ------------------------------------------------------------------- §5.5 Abfuellen

fn abfuellen() -> Sim {
    let flasche_da = rd("Flasche_da", e(4, 0));
    let voll = rd("Voll", e(4, 1));
    let run = seq(
        "RUN",
        2,
        vec![sfc(SfcFlag::Run)],
        vec![
            step("BEREIT"),
            step("FUELLEN").q(Qualifier::N, 0, None).max(5000),
            step("ENDE"),
        ],
        vec![
            trans("T1", &[0], &[1], vec![flasche_da]),
            trans("T2", &[1], &[2], vec![voll]),
        ],
    );
    let halt = seq(
        "HALT",
        1,
        vec![sfc(SfcFlag::Holding)],
        vec![step("H1").init(vec![set_true(m(40, 0))]), step("H2")],
        vec![trans("TH", &[0], &[1], vec![])],
    );
    let mut c = chart("Abfuellen", vec![("Ventil", a(4, 0))], vec![run, halt]);
    c.time_monitoring = true;
    Sim::new(c, 100)
}

fn state_is(st: OpState) -> higraph_runtime::program::Expr {
    cmp(
        CmpOp::Eq,
        chart_state("Abfuellen.state", 0),
        k(Value::OpState(st as u8)),
    )
}

#[test]
fn abfuellen_hold_and_resume() {
    let mut s = abfuellen();
    let ventil = rd("Ventil", a(4, 0));
    let sperre = rd("Ventil_Sperre", m(40, 0));
    let fuellen = |member| step_path("Abfuellen.FUELLEN", 0, 0, 1, member);
    assert!(s.eval(&state_is(OpState::Ready)));
    s.command(Command::Start);
    s.step(); // 1
    assert_eq!(s.rec.implicit, ["Starting->Active"]);
    assert!(s.eval(&and(
        state_is(OpState::Active),
        step_path("Abfuellen.BEREIT", 0, 0, 0, StepMember::Active)
    )));
    s.set(&e(4, 0), true);
    s.step(); // 2: T1
    assert!(s.eval(&and(fuellen(StepMember::Active), ventil.clone())));
    s.command(Command::Hold);
    s.step(); // 3
    assert!(s.eval(&and(
        and(state_is(OpState::Holding), not(ventil.clone())),
        sperre.clone()
    )));
    assert!(
        s.eval(&fuellen(StepMember::Active)),
        "a suspended step stays active"
    );
    assert_eq!(s.rec.running.as_deref(), Some("HALT"));
    assert_eq!(s.rec.suspended.as_deref(), Some("RUN"));
    assert_eq!(s.phases(), ["HALT.H1 init"]);
    assert_eq!(s.t(0, 1), 100, "FUELLEN counted one cycle before the hold");
    // until Held within T#1S: 4 TH, 5 H2 run, 6 H2 term, 7 Held
    s.step(); // 4
    assert_eq!(
        s.fired(),
        [("HALT".into(), "trans".into(), Some("TH".into()))]
    );
    assert_eq!(s.phases(), ["HALT.H1 term", "HALT.H2 init"]);
    assert_eq!(s.state(), OpState::Holding);
    s.step(); // 5
    assert_eq!(s.phases(), ["HALT.H2 run"]);
    assert_eq!(s.state(), OpState::Holding);
    s.step(); // 6
    assert_eq!(s.phases(), ["HALT.H2 term"]);
    assert_eq!(s.state(), OpState::Holding);
    s.step(); // 7
    assert!(s.eval(&state_is(OpState::Held)));
    assert_eq!(s.rec.implicit, ["Holding->Held"]);
    assert!(!s.get(&a(4, 0)));
    assert_eq!(s.t(0, 1), 100, "hold time is not counted");
    s.command(Command::Resume);
    s.step(); // 8
    assert_eq!(s.rec.implicit, ["Resuming->Active"]);
    assert!(s.eval(&and(state_is(OpState::Active), ventil.clone())));
    assert_eq!(s.rec.running.as_deref(), Some("RUN"));
    assert_eq!(s.rec.suspended, None);
    assert_eq!(s.phases(), ["RUN.FUELLEN run"]);
    s.steps(49); // wait T#4900MS: 9..57
    assert_eq!(s.k, 57);
    assert_eq!(s.t(0, 1), 5000);
    assert!(s.eval(&not(fuellen(StepMember::Error))));
    s.step(); // 58
    assert_eq!(s.t(0, 1), 5100);
    assert!(s.eval(&step_path(
        "Abfuellen.RUN.FUELLEN.error",
        0,
        0,
        1,
        StepMember::Error
    )));
    assert_eq!(
        s.state(),
        OpState::Active,
        "a step error does not change the state"
    );
    s.set(&e(4, 1), true);
    s.step(); // 59: T2
    assert_eq!(
        s.fired(),
        [("RUN".into(), "trans".into(), Some("T2".into()))]
    );
    assert_eq!(s.phases(), ["RUN.FUELLEN term", "RUN.ENDE init"]);
    assert!(!s.eval(&state_is(OpState::Completed)));
    assert!(s.error(0, 1), "the error stays after the step left");
    s.step(); // 60
    assert_eq!(s.phases(), ["RUN.ENDE run"]);
    assert!(!s.eval(&state_is(OpState::Completed)));
    s.step(); // 61
    assert_eq!(s.phases(), ["RUN.ENDE term"]);
    assert!(!s.eval(&state_is(OpState::Completed)));
    s.step(); // 62
    assert!(s.eval(&state_is(OpState::Completed)));
    assert_eq!(
        s.rec.implicit,
        ["Active->Completing", "Completing->Completed"]
    );
    assert!(s.eval(&not(ventil)));
    assert!(s.eval(&sperre), "nothing reset the lock");
}

// ------------------------------------------------------------------ commands (§4.2)

#[test]
fn command_acceptance_table() {
    use Command as C;
    use OpState as S;
    let expected = |st: S, c: C| -> Option<S> {
        let accepted_in: &[S] = match c {
            C::Start => &[S::Ready, S::Completed, S::Aborted],
            C::Hold => &[S::Starting, S::Active, S::Resuming],
            C::Resume => &[S::Held, S::HeldError],
            C::Complete => &[S::Active],
            C::Reset => &[S::Completed, S::Aborted, S::Stopped],
            C::Error => &[
                S::Starting,
                S::Active,
                S::Holding,
                S::Held,
                S::Resuming,
                S::Completing,
            ],
            C::Abort => &[
                S::Starting,
                S::Active,
                S::Completing,
                S::ErrorCompleting,
                S::Completed,
                S::Holding,
                S::Held,
                S::Resuming,
                S::Error,
                S::HeldError,
                S::ResumingError,
                S::Stopping,
            ],
            C::Stop => &[
                S::Starting,
                S::Active,
                S::Completing,
                S::ErrorCompleting,
                S::Completed,
                S::Holding,
                S::Held,
                S::Resuming,
                S::Error,
                S::HeldError,
                S::ResumingError,
            ],
        };
        if !accepted_in.contains(&st) {
            return None;
        }
        Some(match (c, st) {
            (C::Start, _) => S::Starting,
            (C::Hold, _) => S::Holding,
            (C::Resume, S::Held) => S::Resuming,
            (C::Resume, _) => S::ResumingError,
            (C::Complete, _) => S::Completing,
            (C::Abort, _) => S::Aborting,
            (C::Stop, _) => S::Stopping,
            (C::Reset, _) => S::Ready,
            (C::Error, S::Completing) => S::ErrorCompleting,
            (C::Error, _) => S::Error,
        })
    };
    let mut accepted = 0;
    for st in OpState::ALL {
        for c in Command::ALL {
            assert_eq!(
                command_target(st, c),
                expected(st, c),
                "{} in {}",
                c.name(),
                st.name()
            );
            accepted += usize::from(expected(st, c).is_some());
        }
    }
    assert_eq!(accepted, 3 + 3 + 2 + 1 + 3 + 6 + 12 + 11);
    assert_eq!(successor(OpState::Error), Some(OpState::HeldError));
    assert_eq!(
        successor(OpState::ErrorCompleting),
        Some(OpState::Completed)
    );
    assert_eq!(successor(OpState::Active), None);
}

#[test]
fn rejected_commands_are_recorded_and_change_nothing() {
    let mut s = abfuellen();
    s.command(Command::Resume);
    s.command(Command::Hold);
    s.step();
    assert_eq!(s.state(), OpState::Ready);
    let cmds: Vec<(String, bool)> = s
        .rec
        .commands
        .iter()
        .map(|c| (c.command.clone(), c.accepted))
        .collect();
    assert_eq!(cmds, [("resume".into(), false), ("hold".into(), false)]);
    // commands apply in order within one cycle: start, then hold from Starting
    s.command(Command::Start);
    s.command(Command::Complete); // rejected in Starting
    s.command(Command::Hold);
    s.step();
    let accepted: Vec<bool> = s.rec.commands.iter().map(|c| c.accepted).collect();
    assert_eq!(accepted, [true, false, true]);
    assert_eq!(
        s.state(),
        OpState::Holding,
        "HALT runs: SFC.HOLDING holds the state"
    );
    assert_eq!(s.rec.running.as_deref(), Some("HALT"));
    assert_eq!(s.rec.suspended, None, "only Active -> Holding suspends");
}

#[test]
fn error_path_and_reset() {
    let mut s = abfuellen();
    s.command(Command::Start);
    s.set(&e(4, 0), true);
    s.steps(2);
    assert!(s.active(0, 1));
    s.command(Command::Error);
    s.step();
    // Active -> Error aborts RUN (FUELLEN term, ENDE init run term), Error -> HeldError
    assert_eq!(s.rec.implicit, ["Error->HeldError"]);
    assert_eq!(s.state(), OpState::HeldError);
    assert_eq!(
        s.phases(),
        [
            "RUN.FUELLEN term",
            "RUN.ENDE init",
            "RUN.ENDE run",
            "RUN.ENDE term"
        ]
    );
    assert_eq!(s.fired()[0].1, "abort");
    assert!(!s.active(0, 1));
    assert!(!s.get(&a(4, 0)));
    s.command(Command::Resume);
    s.step();
    assert_eq!(s.rec.implicit, ["ResumingError->Active"]);
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(s.rec.running.as_deref(), Some("RUN"), "RUN starts afresh");
    assert!(s.active(0, 0));
    s.command(Command::Stop);
    s.step();
    assert_eq!(s.state(), OpState::Stopped);
    s.command(Command::Reset);
    s.step();
    assert_eq!(s.state(), OpState::Ready);
}

// ------------------------------------------------------------- selection (§4.4)

#[test]
fn higher_priority_displaces_the_running_sequencer() {
    let low = seq(
        "LOW",
        2,
        vec![sfc(SfcFlag::Run), rd("M0.0", m(0, 0))],
        vec![
            step("L1").term(vec![set_true(m(1, 0))]),
            step("L2"),
            step("LEND")
                .init(vec![set_true(m(1, 1))])
                .run(vec![set_true(m(1, 2))])
                .term(vec![set_true(m(1, 3))]),
        ],
        vec![
            trans("LT1", &[0], &[1], vec![rd("M0.2", m(0, 2))]),
            trans("LT2", &[1], &[2], vec![rd("M0.2", m(0, 2))]),
        ],
    );
    let high = seq(
        "HIGH",
        1,
        vec![sfc(SfcFlag::Run), rd("M0.1", m(0, 1))],
        vec![step("H1"), step("H2")],
        vec![trans("HT", &[0], &[1], vec![k(Value::Bool(false))])],
    );
    let mut s = Sim::new(chart("C", vec![], vec![low, high]), 10);
    s.set(&m(0, 0), true);
    s.command(Command::Start);
    s.step();
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(s.rec.running.as_deref(), Some("LOW"));
    s.step();
    assert!(s.active(0, 0));
    // the low sequencer continues while its start condition is FALSE
    s.set(&m(0, 0), false);
    s.step();
    assert_eq!(s.rec.running.as_deref(), Some("LOW"));
    s.set(&m(0, 1), true);
    s.step();
    assert_eq!(s.rec.running.as_deref(), Some("HIGH"));
    assert_eq!(
        s.state(),
        OpState::Active,
        "displacing leaves the state unchanged"
    );
    assert_eq!(
        s.phases(),
        [
            "LOW.L1 term",
            "LOW.LEND init",
            "LOW.LEND run",
            "LOW.LEND term",
            "HIGH.H1 run"
        ]
    );
    let kinds: Vec<String> = s
        .fired()
        .into_iter()
        .map(|f| format!("{} {}", f.0, f.1))
        .collect();
    assert_eq!(kinds, ["LOW abort", "HIGH start"]);
    for b in 0..4 {
        assert!(s.get(&m(1, b)), "M1.{b}");
    }
    assert!(!s.active(0, 0));
    assert!(s.active(1, 0));
    // an aborted sequencer has not completed: the state stays Active
    s.set(&m(0, 1), false);
    s.step();
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(s.rec.running.as_deref(), Some("HIGH"));
}

#[test]
fn equal_priority_goes_to_text_order_and_empty_start_never_runs() {
    let mk = |name: &str, start| seq(name, 1, start, vec![step("X"), step("Y")], vec![]);
    let c = chart(
        "C",
        vec![],
        vec![
            mk("NONE", vec![]),
            mk("FIRST", vec![k(Value::Bool(true))]),
            mk("SECOND", vec![k(Value::Bool(true))]),
        ],
    );
    let mut s = Sim::new(c, 10);
    s.command(Command::Start);
    s.step();
    assert_eq!(s.rec.running.as_deref(), Some("FIRST"));
    // a start condition TRUE in Starting keeps the chart there
    assert_eq!(s.state(), OpState::Starting);
    assert!(s.rec.implicit.is_empty());
}

// --------------------------------------------------- run cyclic / run autostart

fn two_step(name: &str) -> higraph_runtime::program::Chart {
    chart(
        name,
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![step("S1"), step("E")],
            vec![trans("T", &[0], &[1], vec![])],
        )],
    )
}

#[test]
fn run_cyclic_restarts_after_completion() {
    let mut c = two_step("C");
    c.cyclic = true;
    let mut s = Sim::new(c, 10);
    s.command(Command::Start);
    s.step(); // 1 S1
    s.step(); // 2 T, E init
    s.step(); // 3 E run
    s.step(); // 4 E term: completed
    assert_eq!(s.phases(), ["RUN.E term"]);
    assert_eq!(s.state(), OpState::Active);
    s.step(); // 5
    assert_eq!(
        s.rec.implicit,
        [
            "Active->Completing",
            "Completing->Completed",
            "Completed->Starting",
            "Starting->Active"
        ]
    );
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(
        s.fired()[0].1,
        "start",
        "RUN starts again in the same cycle"
    );
    assert!(s.active(0, 0));
}

#[test]
fn run_autostart_starts_in_the_first_cycle_and_after_restart() {
    let mut c = two_step("C");
    c.autostart = true;
    let mut s = Sim::new(c.clone(), 10);
    s.step();
    assert_eq!(s.rec.commands[0].command, "start");
    assert_eq!(s.state(), OpState::Active);
    s.steps(3);
    s.step();
    assert_eq!(s.state(), OpState::Completed, "autostart is no cyclic run");
    s.step();
    assert_eq!(s.state(), OpState::Completed);
    assert!(s.rec.commands.is_empty());
    s.rt.restart();
    assert_eq!(s.state(), OpState::Ready);
    s.first = true;
    s.step();
    assert_eq!(s.state(), OpState::Active);
    // without autostart the chart waits for a command
    c.autostart = false;
    let mut s = Sim::new(c, 10);
    s.steps(2);
    assert_eq!(s.state(), OpState::Ready);
}

// ------------------------------------------------------------ abort and stop

#[test]
fn abort_and_stop_run_term_and_the_end_step_in_one_cycle() {
    for (cmd, via, end) in [
        (Command::Abort, "Aborting->Aborted", OpState::Aborted),
        (Command::Stop, "Stopping->Stopped", OpState::Stopped),
    ] {
        let c = chart(
            "C",
            vec![("Q", a(0, 0))],
            vec![seq(
                "RUN",
                1,
                vec![sfc(SfcFlag::Run)],
                vec![
                    step("S1"),
                    step("S2")
                        .q(Qualifier::N, 0, None)
                        .term(vec![set_true(m(2, 0))]),
                    step("E"),
                ],
                vec![
                    trans("T1", &[0], &[1], vec![]),
                    trans("T2", &[1], &[2], vec![k(Value::Bool(false))]),
                ],
            )],
        );
        let mut s = Sim::new(c, 10);
        s.command(Command::Start);
        s.steps(3);
        assert!(s.get(&a(0, 0)));
        s.command(cmd);
        s.step();
        assert_eq!(
            s.phases(),
            ["RUN.S2 term", "RUN.E init", "RUN.E run", "RUN.E term"]
        );
        assert_eq!(s.rec.implicit, [via]);
        assert_eq!(s.state(), end);
        assert!(s.get(&m(2, 0)));
        assert!(!s.get(&a(0, 0)), "aborted steps count inactive");
        assert!(s.active_names().is_empty());
        // the sequencer stays finished
        s.step();
        assert!(s.phases().is_empty());
        s.command(Command::Start);
        s.step();
        if end == OpState::Aborted {
            assert_eq!(s.state(), OpState::Active, "start is accepted in Aborted");
        } else {
            assert_eq!(s.state(), OpState::Stopped, "start is rejected in Stopped");
        }
    }
}

#[test]
fn abort_after_end_step_init_runs_only_the_rest() {
    let mut s = Sim::new(two_step("C"), 10);
    s.command(Command::Start);
    s.steps(2); // E init
    assert_eq!(s.phases(), ["RUN.S1 term", "RUN.E init"]);
    s.command(Command::Abort);
    s.step();
    assert_eq!(s.phases(), ["RUN.E run", "RUN.E term"]);
    assert_eq!(s.state(), OpState::Aborted);
}

// --------------------------------------------------------- switching and min

fn confirm_chart(switching: Switching, auto: bool, cond: bool, confirm_flag: bool) -> Sim {
    let mut s1 = step("S1");
    if confirm_flag {
        s1 = s1.confirm();
    }
    let mut c = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![s1, step("S2"), step("E")],
            vec![
                trans("T1", &[0], &[1], vec![rd("M0.0", m(0, 0))]),
                trans("T2", &[1], &[2], vec![k(Value::Bool(false))]),
            ],
        )],
    );
    c.switching = switching;
    c.mode_auto = auto;
    let mut s = Sim::new(c, 10);
    s.set(&m(0, 0), cond);
    s.command(Command::Start);
    s.step();
    assert!(s.active(0, 0));
    s
}

/// Runs three cycles without and one with a confirmation; returns whether S1 left in the
/// first three and whether it left after the confirmation.
fn switch_outcome(
    switching: Switching,
    auto: bool,
    cond: bool,
    confirm_flag: bool,
) -> (bool, bool) {
    let mut s = confirm_chart(switching, auto, cond, confirm_flag);
    s.steps(3);
    let early = !s.active(0, 0);
    if early {
        return (true, true);
    }
    s.rt.confirm(0, 0).expect("S1 is active");
    s.step();
    (false, !s.active(0, 0))
}

#[test]
fn switching_modes() {
    use Switching::*;
    // (mode, auto, condition, confirm flag) -> (leaves without confirmation, leaves with it)
    let cases = [
        (T, false, true, false, (true, true)),
        (T, false, false, false, (false, false)),
        (B, false, true, false, (false, true)),
        (B, false, false, false, (false, true)),
        (TAndB, false, true, false, (false, true)),
        (TAndB, false, false, false, (false, false)),
        (TOrB, false, true, false, (true, true)),
        (TOrB, false, false, false, (false, true)),
        (Step, false, true, true, (false, true)),
        (Step, false, false, true, (false, false)),
        (Step, false, true, false, (true, true)),
        (Step, false, false, false, (false, false)),
        // mode auto: B, T_and_B, T_or_B act as T; step stays
        (B, true, true, false, (true, true)),
        (B, true, false, false, (false, false)),
        (TAndB, true, true, false, (true, true)),
        (TOrB, true, false, false, (false, false)),
        (Step, true, true, true, (false, true)),
    ];
    for (mode, auto, cond, flag, want) in cases {
        assert_eq!(
            switch_outcome(mode, auto, cond, flag),
            want,
            "{mode:?} auto={auto} cond={cond} confirm={flag}"
        );
    }
}

#[test]
fn latch_is_consumed_when_the_step_leaves_and_confirm_needs_an_active_step() {
    let mut s = confirm_chart(Switching::B, false, false, false);
    assert!(s.rt.confirm(0, 1).is_err(), "S2 is inactive: a fault");
    let f = s.rt.confirm(0, 1).unwrap_err();
    assert!(f.reason.contains("C.RUN.S2"), "{}", f.reason);
    s.rt.confirm(0, 0).expect("active");
    s.step();
    assert!(s.active(0, 1));
    // S2's latch is not S1's: nothing moves on
    s.steps(2);
    assert!(s.active(0, 1));
    s.rt.confirm(0, 1).expect("active");
    s.step();
    assert!(s.active(0, 2));
}

fn min_chart(switching: Switching) -> Sim {
    let mut c = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![step("S1").min(30), step("S2"), step("E")],
            vec![
                trans("T1", &[0], &[1], vec![rd("M0.0", m(0, 0))]),
                trans("T2", &[1], &[2], vec![k(Value::Bool(false))]),
            ],
        )],
    );
    c.switching = switching;
    let mut s = Sim::new(c, 10);
    s.set(&m(0, 0), true);
    s.command(Command::Start);
    s
}

#[test]
fn min_time_delays_the_transition() {
    let mut s = min_chart(Switching::T);
    s.step(); // 1: S1 active, T = 0
    s.step(); // 2: T = 10
    s.step(); // 3: T = 20
    assert!(s.active(0, 0));
    assert_eq!(s.t(0, 0), 20);
    s.step(); // 4: T = 30 >= min
    assert!(s.active(0, 1));
    assert_eq!(s.t(0, 0), 30, "T is kept after the step left");
    assert_eq!(s.t(0, 1), 0);
}

#[test]
fn confirmation_overrides_min_in_b_and_t_or_b() {
    for (mode, overrides) in [
        (Switching::TOrB, true),
        (Switching::B, true),
        (Switching::TAndB, false),
    ] {
        let mut s = min_chart(mode);
        s.step();
        s.rt.confirm(0, 0).expect("active");
        s.step(); // T = 10 < min
        assert_eq!(s.active(0, 1), overrides, "{mode:?}");
    }
}

// ------------------------------------------------------------- qualifiers (§4.6)

/// A chart whose step Si (i = 0..) is active while M0.i... is driven by the test: one
/// sequencer per step, each with start condition M0.i and a single step, so a step is active
/// exactly while its sequencer runs. Steps hold a qualifier on action 0 (A0.0).
fn qualifier_chart(assocs: Vec<(Qualifier, Option<i32>)>) -> Sim {
    // One sequencer SEQ with steps IDLE, then one step per association reached by jumps from
    // IDLE while M1.i, and back to IDLE by a jump while not M1.i.
    let n = assocs.len() as u32;
    let mut steps = vec![step("IDLE")];
    for (i, (q, t)) in assocs.into_iter().enumerate() {
        steps.push(step(&format!("S{i}")).q(q, 0, t));
    }
    steps.push(step("E"));
    let mut ts = vec![];
    for i in 0..n {
        let cond = rd(&format!("M1.{i}"), m(1, i as u8));
        ts.push(tr(
            ChartTransKind::Jump,
            &format!("J{i}"),
            &[0],
            &[i + 1],
            vec![cond.clone()],
        ));
        ts.push(tr(
            ChartTransKind::Jump,
            &format!("B{i}"),
            &[i + 1],
            &[0],
            vec![not(cond)],
        ));
    }
    let c = chart(
        "C",
        vec![("X", a(0, 0))],
        vec![seq("SEQ", 1, vec![sfc(SfcFlag::Run)], steps, ts)],
    );
    let mut s = Sim::new(c, 10);
    s.command(Command::Start);
    s.step();
    s
}

/// Drives the qualifier chart: `plan[k]` = which of the M1.i are TRUE before cycle k; returns
/// X after each cycle. A step entered by a jump in cycle k is active from cycle k on.
fn drive(s: &mut Sim, plan: &[&[u8]]) -> Vec<bool> {
    let mut out = vec![];
    for on in plan {
        for b in 0..4 {
            s.set(&m(1, b), on.contains(&b));
        }
        s.step();
        out.push(s.get(&a(0, 0)));
    }
    out
}

#[test]
fn qualifier_n_and_p() {
    let mut s = qualifier_chart(vec![(Qualifier::N, None)]);
    assert_eq!(
        drive(&mut s, &[&[0], &[0], &[], &[]]),
        [true, true, false, false]
    );
    let mut s = qualifier_chart(vec![(Qualifier::P, None)]);
    assert_eq!(
        drive(&mut s, &[&[0], &[0], &[0], &[], &[0], &[0]]),
        [true, false, false, false, true, false]
    );
}

#[test]
fn qualifier_s_and_r() {
    let mut s = qualifier_chart(vec![(Qualifier::S, None), (Qualifier::R, None)]);
    // S step for one cycle: X stays set; R step resets; S again sets
    let out = drive(&mut s, &[&[0], &[], &[], &[1], &[], &[], &[0], &[]]);
    assert_eq!(out, [true, true, true, false, false, false, true, true]);
}

#[test]
fn qualifier_l() {
    let mut s = qualifier_chart(vec![(Qualifier::L, Some(30))]);
    let out = drive(&mut s, &[&[0], &[0], &[0], &[0], &[0], &[], &[0], &[0]]);
    // ET 0, 10, 20, 30 (Q) ...; leaving and re-entering restarts
    assert_eq!(out, [true, true, true, false, false, false, true, true]);
}

#[test]
fn qualifier_d() {
    let mut s = qualifier_chart(vec![(Qualifier::D, Some(20))]);
    let out = drive(&mut s, &[&[0], &[0], &[0], &[0], &[], &[0]]);
    assert_eq!(out, [false, false, true, true, false, false]);
}

#[test]
fn qualifier_sd() {
    // SD: the set survives leaving the step; the delay runs on; R resets
    let mut s = qualifier_chart(vec![(Qualifier::Sd, Some(20)), (Qualifier::R, None)]);
    let out = drive(&mut s, &[&[0], &[], &[], &[], &[1], &[]]);
    assert_eq!(out, [false, false, true, true, false, false]);
}

#[test]
fn qualifier_ds() {
    // DS: the step must stay active for the delay; then it is stored until R
    let mut s = qualifier_chart(vec![(Qualifier::Ds, Some(20)), (Qualifier::R, None)]);
    let out = drive(&mut s, &[&[0], &[], &[0], &[0], &[0], &[], &[], &[1], &[]]);
    assert_eq!(
        out,
        [false, false, false, false, true, true, true, false, false]
    );
}

#[test]
fn qualifier_sl() {
    // SL: set and limited: on for the time even after the step left, until R
    let mut s = qualifier_chart(vec![(Qualifier::Sl, Some(30)), (Qualifier::R, None)]);
    let out = drive(&mut s, &[&[0], &[], &[], &[], &[], &[0], &[], &[1], &[]]);
    assert_eq!(
        out,
        [true, true, true, false, false, false, false, false, false]
    );
}

#[test]
fn actions_of_a_suspended_sequencer_count_inactive() {
    let mut s = abfuellen();
    s.command(Command::Start);
    s.set(&e(4, 0), true);
    s.steps(2);
    assert!(s.get(&a(4, 0)));
    s.command(Command::Hold);
    s.step();
    assert!(!s.get(&a(4, 0)));
    assert_eq!(
        s.rec.actions.get("Ventil"),
        Some(&serde_json::Value::Bool(false))
    );
}

// ------------------------------------------------------- alternatives, jumps, loops

fn branching(conds: [bool; 4]) -> Sim {
    // S0 with: alt branches TA (-> SA), TB (-> SB) (leftmost first); loop L -> S0; jump J -> SJ
    let c = |i: u8| rd(&format!("M0.{i}"), m(0, i));
    let ch = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![
                step("S0").init(vec![set_true(m(2, 0))]),
                step("SA"),
                step("SB"),
                step("SJ"),
                step("E"),
            ],
            vec![
                tr(ChartTransKind::Jump, "J", &[0], &[3], vec![c(3)]),
                trans("TA", &[0], &[1], vec![c(0)]),
                trans("TB", &[0], &[2], vec![c(1)]),
                tr(ChartTransKind::Loop, "L", &[0], &[0], vec![c(2)]),
            ],
        )],
    );
    let mut s = Sim::new(ch, 10);
    s.command(Command::Start);
    s.step();
    for (i, v) in conds.into_iter().enumerate() {
        s.set(&m(0, i as u8), v);
    }
    s.step();
    s
}

#[test]
fn alt_leftmost_true_branch_wins() {
    let s = branching([true, true, false, false]);
    assert_eq!(
        s.fired(),
        [("RUN".into(), "trans".into(), Some("TA".into()))]
    );
    assert_eq!(s.active_names(), ["RUN.SA"]);
    let s = branching([false, true, true, true]);
    assert_eq!(s.fired()[0].2.as_deref(), Some("TB"));
}

#[test]
fn successor_first_then_loops_and_jumps_in_text_order() {
    // the jump J comes first in the text, but successor transitions are checked first
    let s = branching([true, false, true, true]);
    assert_eq!(s.fired()[0].2.as_deref(), Some("TA"));
    // without a true successor, J (text order before L) wins
    let s = branching([false, false, true, true]);
    assert_eq!(
        s.fired()[0],
        ("RUN".into(), "jump".into(), Some("J".into()))
    );
    assert_eq!(s.active_names(), ["RUN.SJ"]);
    // the loop re-activates S0 with its first phase
    let mut s = branching([false, false, true, false]);
    assert_eq!(
        s.fired()[0],
        ("RUN".into(), "loop".into(), Some("L".into()))
    );
    assert_eq!(s.phases(), ["RUN.S0 term", "RUN.S0 init"]);
    assert_eq!(s.t(0, 0), 0);
    s.set(&m(0, 2), false);
    s.step();
    assert_eq!(s.phases(), ["RUN.S0 run"]);
    assert_eq!(s.t(0, 0), 10);
}

// --------------------------------------------------------------- end step

#[test]
fn end_step_runs_init_run_term_over_three_cycles() {
    let ch = chart(
        "C",
        vec![("Q", a(0, 0))],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![
                step("S1"),
                step("E")
                    .q(Qualifier::N, 0, None)
                    .init(vec![set_true(m(3, 0))])
                    .run(vec![set_true(m(3, 1))])
                    .term(vec![set_true(m(3, 2))]),
            ],
            vec![trans("T", &[0], &[1], vec![])],
        )],
    );
    let mut s = Sim::new(ch, 10);
    s.command(Command::Start);
    s.step();
    let mut seen = vec![];
    for _ in 0..3 {
        s.step();
        seen.push([
            s.get(&m(3, 0)),
            s.get(&m(3, 1)),
            s.get(&m(3, 2)),
            s.get(&a(0, 0)),
        ]);
    }
    assert_eq!(
        seen,
        [
            [true, false, false, true],
            [true, true, false, true],
            [true, true, true, false]
        ]
    );
    assert_eq!(s.state(), OpState::Active);
    s.step();
    assert_eq!(s.state(), OpState::Completed);
    s.step();
    assert!(s.phases().is_empty(), "a completed sequencer runs no phase");
}

#[test]
fn pre_and_post_run_around_the_steps() {
    let mut sq = seq(
        "RUN",
        1,
        vec![sfc(SfcFlag::Run)],
        vec![step("S1"), step("E")],
        vec![trans("T", &[0], &[1], vec![rd("M0.0", m(0, 0))])],
    );
    // pre sets M0.0, so T sees it in the same cycle; post copies S1's activity
    sq.pre = vec![set_true(m(0, 0)).into()];
    sq.post = vec![assign(m(0, 1), step_path("S1", 0, 0, 0, StepMember::Active)).into()];
    let mut s = Sim::new(chart("C", vec![], vec![sq]), 10);
    s.command(Command::Start);
    s.step();
    assert!(s.get(&m(0, 0)));
    assert!(s.get(&m(0, 1)), "post sees S1 active after its hand-over");
    s.step();
    assert!(s.active(0, 1));
    assert!(!s.get(&m(0, 1)));
}

#[test]
fn stored_actions_survive_an_abort_until_reset() {
    let c = chart(
        "C",
        vec![("X", a(0, 0))],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![step("S1").q(Qualifier::S, 0, None).max(10), step("E")],
            vec![trans("T", &[0], &[1], vec![b_false()])],
        )],
    );
    let mut c = c;
    c.time_monitoring = true;
    let mut s = Sim::new(c, 10);
    s.command(Command::Start);
    s.steps(3);
    assert!(s.get(&a(0, 0)));
    assert!(s.error(0, 0), "T = 20 > max = 10");
    s.command(Command::Abort);
    s.step();
    assert_eq!(s.state(), OpState::Aborted);
    assert!(
        s.get(&a(0, 0)),
        "S memory persists across sequencer changes"
    );
    assert!(s.error(0, 0), "the error stays until reset");
    s.command(Command::Reset);
    s.step();
    assert_eq!(s.state(), OpState::Ready);
    assert!(!s.get(&a(0, 0)), "reset clears the action memories");
    assert!(!s.error(0, 0), "reset clears the step errors");
}

fn b_false() -> higraph_runtime::program::Expr {
    k(Value::Bool(false))
}

#[test]
fn an_action_has_one_time_the_first_active_association_s() {
    // S0: SD X, T#50MS; S1: L X, T#0MS. While S1 is active, t = 0 (S1's association is the
    // first timed one whose step is active), so the stored SD delay ends at once.
    let mut s = qualifier_chart(vec![(Qualifier::Sd, Some(50)), (Qualifier::L, Some(0))]);
    let out = drive(&mut s, &[&[0], &[1], &[1], &[]]);
    // cycle 1: S0, SD stored, t = 50: off. cycle 2: back to IDLE, t = 50, ET = 10: off.
    // cycle 3: S1, t = 0: SD's delay is over (a time per qualifier would give ET = 20 < 50),
    // and L with t = 0 is off. cycle 4: IDLE again, t = 50, ET = min(0 + 10, 50): off.
    assert_eq!(out, [false, false, true, false]);
}

#[test]
fn an_aborted_sequencer_is_a_candidate_again_from_the_next_cycle() {
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "S",
            1,
            vec![rd("M0.0", m(0, 0))],
            vec![step("S1"), step("E")],
            vec![trans("T", &[0], &[1], vec![b_false()])],
        )],
    );
    let mut s = Sim::new(c, 10);
    s.set(&m(0, 0), true);
    s.command(Command::Start);
    s.step();
    assert_eq!(
        s.state(),
        OpState::Starting,
        "a TRUE start condition holds Starting"
    );
    assert_eq!(s.rec.running.as_deref(), Some("S"));
    s.command(Command::Hold);
    s.step();
    assert_eq!(s.state(), OpState::Holding);
    assert_eq!(
        s.fired()[0].1,
        "abort",
        "Starting -> Holding aborts, only Active suspends"
    );
    assert_eq!(s.rec.running, None, "no restart in the cycle of the abort");
    assert_eq!(s.rec.suspended, None);
    s.step();
    assert_eq!(s.rec.running.as_deref(), Some("S"));
    assert_eq!(s.fired()[0].1, "start");
}

#[test]
fn a_join_waits_for_the_min_of_every_branch() {
    // S1, parallel < A (min T#30MS) | B >, T2 (TRUE), E
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![step("S1"), step("A").min(30), step("B"), step("E")],
            vec![
                trans("T1", &[0], &[1, 2], vec![]),
                trans("T2", &[1, 2], &[3], vec![]),
            ],
        )],
    );
    let mut s = Sim::new(c, 10);
    s.command(Command::Start);
    s.steps(2); // 2: A and B entered
    assert_eq!(s.active_names(), ["RUN.A", "RUN.B"]);
    s.steps(2); // 3, 4: T = 10, 20
    assert_eq!(
        s.active_names(),
        ["RUN.A", "RUN.B"],
        "B may not leave alone"
    );
    s.step(); // 5: T = 30
    assert_eq!(s.active_names(), ["RUN.E"]);
}

#[test]
fn equal_priority_does_not_displace() {
    let mk = |name: &str, bit: u8| {
        seq(
            name,
            1,
            vec![sfc(SfcFlag::Run), rd("M0.x", m(0, bit))],
            vec![step("X"), step("E")],
            vec![trans("T", &[0], &[1], vec![b_false()])],
        )
    };
    // FIRST comes first in the text, so it would win a tie, but the running one stays
    let c = chart("C", vec![], vec![mk("FIRST", 0), mk("SECOND", 1)]);
    let mut s = Sim::new(c, 10);
    s.set(&m(0, 1), true);
    s.command(Command::Start);
    s.step();
    assert_eq!(s.rec.running.as_deref(), Some("SECOND"));
    s.set(&m(0, 0), true);
    s.steps(2);
    assert_eq!(s.rec.running.as_deref(), Some("SECOND"));
    assert!(s.fired().is_empty());
}

#[test]
fn a_suspended_sequencer_is_discarded_without_phases() {
    let mut s = abfuellen();
    s.command(Command::Start);
    s.set(&e(4, 0), true);
    s.steps(2);
    s.command(Command::Hold);
    s.steps(4); // 3..6: HALT runs and completes
    assert_eq!(s.state(), OpState::Holding);
    s.step(); // 7
    assert_eq!(s.state(), OpState::Held);
    assert_eq!(s.rec.suspended.as_deref(), Some("RUN"));
    s.command(Command::Stop);
    s.step();
    assert_eq!(s.state(), OpState::Stopped);
    assert!(s.phases().is_empty(), "discarding runs no phase");
    assert_eq!(s.rec.suspended, None);
    assert!(!s.active(0, 1), "the suspended steps are inactive");
}

//! IEC 61131-3 profile (`docs/iec.md`): arithmetic, the standard function blocks, structured
//! statements, the chart execution of §7 and the qualifiers P1, P0, DL, with hand-built
//! programs (as the lowering would build them).

mod chart_common;

use chart_common::*;
use higraph_runtime::chart::{self, ChartRt};
use higraph_runtime::eval::{self, NoCharts, arith};
use higraph_runtime::fb;
use higraph_runtime::machine::Machine;
use higraph_runtime::program::{
    ArithOp, CellId, CellInfo, Chart, ChartTransKind, CmpOp, Command, Expr, FbCall, FbInstance,
    FbMember, FbType, OpState, Origin, Place, Profile, Program, Qualifier, Statement, StepMember,
    Stmt,
};
use higraph_runtime::trace::ChartRecord;
use higraph_runtime::value::{Ty, Value};

// ------------------------------------------------------------------------------ helpers

fn cell(p: &mut Program, ty: Ty) -> CellId {
    p.cells.push(CellInfo {
        ty,
        init: Value::zero(ty),
    });
    (p.cells.len() - 1) as CellId
}

/// A function block instance with fresh cells.
fn instance(p: &mut Program, name: &str, ty: FbType) -> FbInstance {
    let members = ty.members().map(|m| cell(p, m.ty())).collect();
    let state = ty.state_tys().iter().map(|t| cell(p, *t)).collect();
    FbInstance {
        name: name.to_owned(),
        ty,
        members,
        state,
    }
}

fn arith_e(op: ArithOp, a: Expr, b: Expr) -> Expr {
    Expr::Arith(op, Box::new(a), Box::new(b))
}

fn ev(e: &Expr) -> Result<Value, higraph_runtime::Fault> {
    let p = Program::default();
    let mut m = Machine::new(&p);
    eval::eval(e, &mut m, &p, &NoCharts)
}

fn cellv(c: CellId, ty: Ty) -> Expr {
    rd_ty(&format!("cell{c}"), Place::Cell(c), ty)
}

fn put(c: CellId, ty: Ty, value: Expr) -> Statement {
    Statement::Assign(Stmt {
        target: Place::Cell(c),
        ty,
        value,
        origin: Origin::NONE,
    })
}

/// A chart simulation of an IEC chart with the given cells.
fn iec_sim(mut c: Chart, p: Program, dt: u32) -> Sim {
    c.profile = Profile::Iec;
    let mut s = Sim::new(c, dt);
    s.p.cells = p.cells;
    s.m = Machine::new(&s.p);
    s.rt = ChartRt::new(&s.p, 0);
    s
}

fn read(s: &mut Sim, c: CellId, ty: Ty) -> Value {
    s.m.read_value(&Place::Cell(c), ty).expect("read")
}

// --------------------------------------------------------------------------- arithmetic

#[test]
fn integers_wrap_around() {
    let k16 = |x| k(Value::Int(x));
    let k32 = |x| k(Value::Dint(x));
    assert_eq!(
        ev(&arith_e(ArithOp::Add, k16(32767), k16(1))),
        Ok(Value::Int(-32768))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Sub, k16(-32768), k16(1))),
        Ok(Value::Int(32767))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Mul, k16(300), k16(300))),
        Ok(Value::Int(90000_i32 as i16))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Add, k32(i32::MAX), k32(1))),
        Ok(Value::Dint(i32::MIN))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Div, k32(i32::MIN), k32(-1))),
        Ok(Value::Dint(i32::MIN))
    );
    assert_eq!(
        ev(&Expr::Neg(Box::new(k16(-32768)))),
        Ok(Value::Int(-32768))
    );
    assert_eq!(ev(&Expr::Neg(Box::new(k32(5)))), Ok(Value::Dint(-5)));
}

#[test]
fn division_truncates_and_mod_has_the_sign_of_the_dividend() {
    let k16 = |x| k(Value::Int(x));
    assert_eq!(
        ev(&arith_e(ArithOp::Div, k16(-7), k16(2))),
        Ok(Value::Int(-3))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Div, k16(7), k16(-2))),
        Ok(Value::Int(-3))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Mod, k16(-7), k16(2))),
        Ok(Value::Int(-1))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Mod, k16(7), k16(-2))),
        Ok(Value::Int(1))
    );
    assert_eq!(
        ev(&arith_e(ArithOp::Mod, k16(6), k16(3))),
        Ok(Value::Int(0))
    );
}

#[test]
fn division_by_zero_is_a_runtime_fault() {
    let k16 = |x| k(Value::Int(x));
    let e = ev(&arith_e(ArithOp::Div, k16(1), k16(0))).expect_err("fault");
    assert_eq!(e.reason, "division by zero");
    let e = ev(&arith_e(ArithOp::Mod, k16(1), k16(0))).expect_err("fault");
    assert_eq!(e.reason, "MOD by zero");
    let e = ev(&arith_e(ArithOp::Div, k(Value::Time(1000)), k16(0))).expect_err("fault");
    assert_eq!(e.reason, "division by zero");
    // REAL is IEEE: no fault
    assert_eq!(
        ev(&arith_e(
            ArithOp::Div,
            k(Value::Real(1.0)),
            k(Value::Real(0.0))
        )),
        Ok(Value::Real(f32::INFINITY))
    );
}

#[test]
fn real_and_time_arithmetic() {
    assert_eq!(
        ev(&arith_e(
            ArithOp::Mul,
            k(Value::Real(1.5)),
            k(Value::Real(2.0))
        )),
        Ok(Value::Real(3.0))
    );
    assert_eq!(
        ev(&Expr::Neg(Box::new(k(Value::Real(2.5))))),
        Ok(Value::Real(-2.5))
    );
    assert_eq!(
        ev(&arith_e(
            ArithOp::Add,
            k(Value::Time(1000)),
            k(Value::Time(500))
        )),
        Ok(Value::Time(1500))
    );
    assert_eq!(
        ev(&arith_e(
            ArithOp::Sub,
            k(Value::Time(1000)),
            k(Value::Time(1500))
        )),
        Ok(Value::Time(-500))
    );
    assert_eq!(
        ev(&arith_e(
            ArithOp::Mul,
            k(Value::Time(1000)),
            k(Value::Int(3))
        )),
        Ok(Value::Time(3000))
    );
    assert_eq!(
        ev(&arith_e(
            ArithOp::Div,
            k(Value::Time(1000)),
            k(Value::Dint(4))
        )),
        Ok(Value::Time(250))
    );
    assert_eq!(
        ev(&Expr::Neg(Box::new(k(Value::Time(1000))))),
        Ok(Value::Time(-1000))
    );
    assert_eq!(
        arith(ArithOp::Add, Value::Int(1), Value::Dint(2)),
        Ok(Value::Dint(3))
    );
    // comparison of arithmetic results
    assert_eq!(
        ev(&cmp(
            CmpOp::Gt,
            arith_e(ArithOp::Add, k(Value::Int(2)), k(Value::Int(3))),
            k(Value::Int(4))
        )),
        Ok(Value::Bool(true))
    );
}

#[test]
fn arithmetic_prints_back_with_its_precedence() {
    let e = arith_e(
        ArithOp::Mul,
        arith_e(ArithOp::Add, k(Value::Int(1)), k(Value::Int(2))),
        Expr::Neg(Box::new(k(Value::Int(3)))),
    );
    assert_eq!(higraph_runtime::test::expr_text(&e), "(1 + 2) * -3");
    let e = arith_e(
        ArithOp::Sub,
        k(Value::Int(1)),
        arith_e(ArithOp::Sub, k(Value::Int(2)), k(Value::Int(3))),
    );
    assert_eq!(higraph_runtime::test::expr_text(&e), "1 - (2 - 3)");
    let e = arith_e(ArithOp::Mod, k(Value::Int(7)), k(Value::Int(2)));
    assert_eq!(higraph_runtime::test::expr_text(&e), "7 MOD 2");
}

// ------------------------------------------------------------------- function blocks

/// One instance on a machine, called at chosen virtual times.
struct Fb {
    m: Machine,
    fb: FbInstance,
}

impl Fb {
    fn new(ty: FbType) -> Fb {
        let mut p = Program::default();
        let fb = instance(&mut p, "X", ty);
        Fb {
            m: Machine::new(&p),
            fb,
        }
    }
    fn set(&mut self, member: FbMember, v: Value) {
        let c = self.fb.cell(member).expect("member");
        self.m.write_value(&Place::Cell(c), &v).expect("write");
    }
    fn b(&mut self, member: FbMember, v: bool) {
        self.set(member, Value::Bool(v));
    }
    fn get(&mut self, member: FbMember) -> Value {
        let c = self.fb.cell(member).expect("member");
        self.m
            .read_value(&Place::Cell(c), member.ty())
            .expect("read")
    }
    fn q(&mut self, member: FbMember) -> bool {
        self.get(member) == Value::Bool(true)
    }
    fn call_at(&mut self, now: u64) {
        self.m.now_ms = now;
        fb::call(&mut self.m, &self.fb).expect("call");
    }
}

#[test]
fn ton_delays_the_rising_edge() {
    use FbMember::*;
    let mut t = Fb::new(FbType::Ton);
    t.set(Pt, Value::Time(100));
    t.call_at(0);
    assert!(!t.q(Q));
    t.b(In, true);
    t.call_at(10);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(0)));
    t.call_at(60);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(50)));
    t.call_at(110);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(100)));
    t.call_at(500);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(100)));
    t.b(In, false);
    t.call_at(510);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(0)));
    // a new rising edge starts again from zero
    t.b(In, true);
    t.call_at(520);
    t.call_at(600);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(80)));
}

#[test]
fn tof_delays_the_falling_edge() {
    use FbMember::*;
    let mut t = Fb::new(FbType::Tof);
    t.set(Pt, Value::Time(100));
    t.call_at(0);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(0)));
    t.b(In, true);
    t.call_at(10);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(0)));
    t.b(In, false);
    t.call_at(100);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(0)));
    t.call_at(150);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(50)));
    t.call_at(200);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(100)));
    t.call_at(400);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(100)));
    t.b(In, true);
    t.call_at(410);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(0)));
}

#[test]
fn tp_gives_a_pulse_of_fixed_length() {
    use FbMember::*;
    let mut t = Fb::new(FbType::Tp);
    t.set(Pt, Value::Time(100));
    t.b(In, true);
    t.call_at(0);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(0)));
    t.b(In, false);
    t.call_at(30);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(30)));
    // a new rising edge while the pulse runs does not retrigger it
    t.b(In, true);
    t.call_at(50);
    assert_eq!((t.q(Q), t.get(Et)), (true, Value::Time(50)));
    t.call_at(100);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(100)));
    // ET stays at PT while IN stays TRUE, then drops to 0
    t.call_at(150);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(100)));
    t.b(In, false);
    t.call_at(160);
    assert_eq!((t.q(Q), t.get(Et)), (false, Value::Time(0)));
    t.b(In, true);
    t.call_at(170);
    assert!(t.q(Q));
}

#[test]
fn edge_detectors() {
    use FbMember::*;
    let mut r = Fb::new(FbType::RTrig);
    let mut seen = Vec::new();
    for clk in [false, true, true, false, true] {
        r.b(Clk, clk);
        r.call_at(0);
        seen.push(r.q(Q));
    }
    assert_eq!(seen, [false, true, false, false, true]);
    let mut f = Fb::new(FbType::FTrig);
    let mut seen = Vec::new();
    // IEC: M starts FALSE, so the first call with CLK = FALSE gives Q = TRUE
    for clk in [false, false, true, true, false, false] {
        f.b(Clk, clk);
        f.call_at(0);
        seen.push(f.q(Q));
    }
    assert_eq!(seen, [true, false, false, false, true, false]);
}

#[test]
fn ctu_counts_rising_edges_and_saturates() {
    use FbMember::*;
    let mut c = Fb::new(FbType::Ctu);
    c.set(Pv, Value::Int(3));
    for i in 0..8 {
        c.b(Cu, i % 2 == 1);
        c.call_at(0);
    }
    assert_eq!((c.get(Cv), c.q(Q)), (Value::Int(4), true));
    c.b(R, true);
    c.b(Cu, false);
    c.call_at(0);
    assert_eq!((c.get(Cv), c.q(Q)), (Value::Int(0), false));
    // a rising CU under R does not count, and its edge is used up
    c.b(Cu, true);
    c.call_at(0);
    c.b(R, false);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(0));
    c.set(Cv, Value::Int(32767));
    c.b(Cu, false);
    c.call_at(0);
    c.b(Cu, true);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(32767));
}

#[test]
fn ctd_loads_and_counts_down() {
    use FbMember::*;
    let mut c = Fb::new(FbType::Ctd);
    c.set(Pv, Value::Int(2));
    c.b(Ld, true);
    c.call_at(0);
    assert_eq!((c.get(Cv), c.q(Q)), (Value::Int(2), false));
    c.b(Ld, false);
    for i in 0..4 {
        c.b(Cd, i % 2 == 0);
        c.call_at(0);
    }
    assert_eq!((c.get(Cv), c.q(Q)), (Value::Int(0), true));
    c.set(Cv, Value::Int(-32768));
    c.b(Cd, true);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(-32768));
}

#[test]
fn ctud_counts_both_ways() {
    use FbMember::*;
    let mut c = Fb::new(FbType::Ctud);
    c.set(Pv, Value::Int(2));
    c.b(Cu, true);
    c.call_at(0);
    c.b(Cu, false);
    c.call_at(0);
    c.b(Cu, true);
    c.call_at(0);
    assert_eq!((c.get(Cv), c.q(Qu), c.q(Qd)), (Value::Int(2), true, false));
    // both edges in one call: no change
    c.b(Cu, false);
    c.call_at(0);
    c.b(Cu, true);
    c.b(Cd, true);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(2));
    c.b(Cd, false);
    c.call_at(0);
    c.b(Cd, true);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(1));
    // R before LD
    c.b(R, true);
    c.b(Ld, true);
    c.call_at(0);
    assert_eq!((c.get(Cv), c.q(Qu), c.q(Qd)), (Value::Int(0), false, true));
    c.b(R, false);
    c.call_at(0);
    assert_eq!(c.get(Cv), Value::Int(2));
}

#[test]
fn sr_is_set_dominant_and_rs_reset_dominant() {
    use FbMember::*;
    let mut sr = Fb::new(FbType::Sr);
    sr.b(S1, true);
    sr.b(R, true);
    sr.call_at(0);
    assert!(sr.q(Q1));
    sr.b(S1, false);
    sr.call_at(0);
    assert!(!sr.q(Q1));
    sr.b(S1, true);
    sr.b(R, false);
    sr.call_at(0);
    sr.b(S1, false);
    sr.call_at(0);
    assert!(sr.q(Q1), "SR keeps Q1");
    let mut rs = Fb::new(FbType::Rs);
    rs.b(S, true);
    rs.b(R1, true);
    rs.call_at(0);
    assert!(!rs.q(Q1));
    rs.b(R1, false);
    rs.call_at(0);
    rs.b(S, false);
    rs.call_at(0);
    assert!(rs.q(Q1), "RS keeps Q1");
}

#[test]
fn fb_types_and_members_by_name() {
    assert_eq!(FbType::from_name("r_trig"), Some(FbType::RTrig));
    assert_eq!(FbType::Ton.member("pt"), Some(FbMember::Pt));
    assert_eq!(FbType::Ton.member("CV"), None);
    assert_eq!(FbMember::Cv.ty(), Ty::Int);
    assert_eq!(
        FbType::Ctud.members().map(|m| m.name()).collect::<Vec<_>>(),
        ["CU", "CD", "R", "LD", "PV", "QU", "QD", "CV"]
    );
}

// ------------------------------------------------------------------------ IEC charts

/// A → B → C with conditions M0.0, M0.1, and `jump Back -> A` after C on M0.2.
fn cyclic() -> Chart {
    chart(
        "Ampel",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B"), step("C")],
            vec![
                trans("T1", &[0], &[1], vec![rd("M0.0", m(0, 0))]),
                trans("T2", &[1], &[2], vec![rd("M0.1", m(0, 1))]),
                tr(
                    ChartTransKind::Jump,
                    "Back",
                    &[2],
                    &[0],
                    vec![rd("M0.2", m(0, 2))],
                ),
            ],
        )],
    )
}

#[test]
fn the_initial_step_is_active_from_the_first_cycle_and_the_chart_is_active() {
    let mut s = iec_sim(cyclic(), Program::default(), 10);
    s.step();
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(s.active_names(), ["Seq.A"]);
    assert_eq!(s.t(0, 0), 0);
    s.steps(3);
    assert_eq!(s.t(0, 0), 30);
    assert_eq!(s.phases(), ["Seq.A run"]);
    assert_eq!(s.rec.running.as_deref(), Some("Seq"));
}

#[test]
fn a_step_entered_in_this_cycle_is_not_decided_again() {
    let mut s = iec_sim(cyclic(), Program::default(), 10);
    s.set(&m(0, 0), true);
    s.set(&m(0, 1), true);
    s.set(&m(0, 2), true);
    s.step();
    assert_eq!(
        s.active_names(),
        ["Seq.A"],
        "first cycle: only the initial step"
    );
    s.step();
    assert_eq!(s.active_names(), ["Seq.B"]);
    assert_eq!(s.phases(), ["Seq.A term", "Seq.B init", "Seq.B run"]);
    s.step();
    assert_eq!(s.active_names(), ["Seq.C"]);
    // the cyclic jump back to the initial step
    s.step();
    assert_eq!(s.active_names(), ["Seq.A"]);
    assert_eq!(
        s.fired(),
        [("Seq".to_owned(), "jump".to_owned(), Some("Back".to_owned()))]
    );
    assert_eq!(s.t(0, 0), 0);
}

#[test]
fn the_last_step_without_successor_stays_active() {
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B")],
            vec![trans("T1", &[0], &[1], vec![])],
        )],
    );
    let mut s = iec_sim(c, Program::default(), 10);
    s.steps(10);
    assert_eq!(s.active_names(), ["Seq.B"]);
    assert_eq!(s.t(0, 1), 80);
}

#[test]
fn all_enabled_transitions_fire_at_once() {
    // A; parallel (B; trans T2; D) (C; trans T3; E)
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B"), step("C"), step("D"), step("E")],
            vec![
                trans("T1", &[0], &[1, 2], vec![]),
                trans("T2", &[1], &[3], vec![rd("M0.0", m(0, 0))]),
                trans("T3", &[2], &[4], vec![rd("M0.0", m(0, 0))]),
            ],
        )],
    );
    let mut s = iec_sim(c, Program::default(), 10);
    s.steps(2);
    assert_eq!(s.active_names(), ["Seq.B", "Seq.C"]);
    s.set(&m(0, 0), true);
    s.step();
    assert_eq!(s.active_names(), ["Seq.D", "Seq.E"]);
    assert_eq!(s.fired().len(), 2);
}

#[test]
fn alt_branches_left_to_right_and_the_successor_before_jumps() {
    // A; alt (trans L -> B) (trans R -> C); jump J from A to C after A
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B"), step("C")],
            vec![
                trans("L", &[0], &[1], vec![rd("M0.0", m(0, 0))]),
                trans("R", &[0], &[2], vec![rd("M0.1", m(0, 1))]),
                tr(ChartTransKind::Jump, "J", &[0], &[2], vec![]),
            ],
        )],
    );
    let mut s = iec_sim(c.clone(), Program::default(), 10);
    s.set(&m(0, 0), true);
    s.set(&m(0, 1), true);
    s.steps(2);
    assert_eq!(s.active_names(), ["Seq.B"], "leftmost branch wins");
    let mut s = iec_sim(c.clone(), Program::default(), 10);
    s.set(&m(0, 1), true);
    s.steps(2);
    assert_eq!(s.active_names(), ["Seq.C"]);
    assert_eq!(s.fired()[0].2.as_deref(), Some("R"));
    let mut s = iec_sim(c, Program::default(), 10);
    s.steps(2);
    assert_eq!(s.fired()[0].2.as_deref(), Some("J"), "the jump last");
}

#[test]
fn reset_is_the_only_command() {
    let mut s = iec_sim(cyclic(), Program::default(), 10);
    s.set(&m(0, 0), true);
    s.steps(2);
    assert_eq!(s.active_names(), ["Seq.B"]);
    s.command(Command::Start);
    s.command(Command::Hold);
    s.step();
    assert_eq!(s.state(), OpState::Active);
    assert_eq!(
        s.rec
            .commands
            .iter()
            .map(|c| c.accepted)
            .collect::<Vec<_>>(),
        [false, false]
    );
    s.set(&m(0, 0), false);
    s.command(Command::Reset);
    s.step();
    assert!(s.rec.commands[0].accepted);
    assert_eq!(s.active_names(), ["Seq.A"]);
    assert_eq!(s.t(0, 0), 0);
}

#[test]
fn step_x_and_t_are_readable_in_the_chart() {
    let mut p = Program::default();
    let t = cell(&mut p, Ty::Time);
    let x = cell(&mut p, Ty::Bool);
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B")],
            vec![trans(
                "T1",
                &[0],
                &[1],
                vec![cmp(
                    CmpOp::Ge,
                    step_path("A.T", 0, 0, 0, StepMember::Time),
                    time(30),
                )],
            )],
        )],
    );
    let mut c = c;
    c.sequencers[0].post = vec![
        put(t, Ty::Time, step_path("A.T", 0, 0, 0, StepMember::Time)),
        put(x, Ty::Bool, step_path("B.X", 0, 0, 1, StepMember::Active)),
    ];
    let mut s = iec_sim(c, p, 10);
    s.steps(3);
    assert_eq!(read(&mut s, t, Ty::Time), Value::Time(20));
    assert_eq!(read(&mut s, x, Ty::Bool), Value::Bool(false));
    s.step();
    assert_eq!(s.active_names(), ["Seq.B"]);
    assert_eq!(read(&mut s, x, Ty::Bool), Value::Bool(true));
}

/// A chart whose step B (entered on M0.0, left on M0.1) carries the given associations to
/// action 0 (`M1.0`).
fn qualified(q: Vec<(Qualifier, Option<i32>)>) -> Sim {
    let mut b = step("B");
    for (q, t) in q {
        b = b.q(q, 0, t);
    }
    let c = chart(
        "C",
        vec![("M1.0", m(1, 0))],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), b, step("C")],
            vec![
                trans("T1", &[0], &[1], vec![rd("M0.0", m(0, 0))]),
                trans("T2", &[1], &[2], vec![rd("M0.1", m(0, 1))]),
            ],
        )],
    );
    iec_sim(c, Program::default(), 10)
}

/// The action's value over `n` cycles; M0.0 rises before cycle 2, M0.1 before cycle `leave`.
fn trace_of(s: &mut Sim, n: u32, leave: u32) -> Vec<bool> {
    let mut out = Vec::new();
    for i in 1..=n {
        if i == 2 {
            s.set(&m(0, 0), true);
        }
        if i == leave {
            s.set(&m(0, 1), true);
        }
        s.step();
        out.push(s.get(&m(1, 0)));
    }
    out
}

#[test]
fn p1_pulses_when_the_step_becomes_active() {
    let mut s = qualified(vec![(Qualifier::P1, None)]);
    // B active in cycles 2..=4, left in cycle 5
    assert_eq!(
        trace_of(&mut s, 6, 5),
        [false, true, false, false, false, false]
    );
}

#[test]
fn p0_pulses_when_the_step_becomes_inactive() {
    let mut s = qualified(vec![(Qualifier::P0, None)]);
    assert_eq!(
        trace_of(&mut s, 7, 5),
        [false, false, false, false, true, false, false]
    );
}

#[test]
fn dl_is_on_from_t_until_2t() {
    let mut s = qualified(vec![(Qualifier::Dl, Some(20))]);
    // B active from cycle 2 (T = 0): on at T = 20 and 30, off from T = 40
    assert_eq!(
        trace_of(&mut s, 9, 20),
        [false, false, false, true, true, false, false, false, false]
    );
    // leaving early ends it
    let mut s = qualified(vec![(Qualifier::Dl, Some(20))]);
    assert_eq!(
        trace_of(&mut s, 6, 5),
        [false, false, false, true, false, false]
    );
}

/// Step B (M0.0 in, M0.1 out) activates action 0, whose body counts its runs in an INT cell.
fn counting(q: Qualifier) -> (Sim, CellId) {
    let mut p = Program::default();
    let n = cell(&mut p, Ty::Int);
    let flag = cell(&mut p, Ty::Bool);
    let mut s = qualified(vec![(q, None)]);
    s.p.cells = p.cells;
    s.p.charts[0].actions[0].place = Place::Cell(flag);
    s.p.charts[0].actions[0].body = Some(vec![put(
        n,
        Ty::Int,
        arith_e(ArithOp::Add, cellv(n, Ty::Int), k(Value::Int(1))),
    )]);
    s.m = Machine::new(&s.p);
    s.rt = ChartRt::new(&s.p, 0);
    (s, n)
}

#[test]
fn an_action_body_runs_while_active_and_once_more() {
    let (mut s, n) = counting(Qualifier::N);
    // B active in cycles 2, 3, 4; final scan in cycle 5
    trace_of(&mut s, 8, 5);
    assert_eq!(read(&mut s, n, Ty::Int), Value::Int(4));
}

#[test]
fn a_p1_body_runs_once_without_final_scan() {
    let (mut s, n) = counting(Qualifier::P1);
    trace_of(&mut s, 8, 5);
    assert_eq!(read(&mut s, n, Ty::Int), Value::Int(1));
    let (mut s, n) = counting(Qualifier::P0);
    trace_of(&mut s, 8, 5);
    assert_eq!(read(&mut s, n, Ty::Int), Value::Int(1));
}

#[test]
fn structured_statements_and_fb_calls_in_steps() {
    let mut p = Program::default();
    let timer = instance(&mut p, "Timer", FbType::Ton);
    let sel = cell(&mut p, Ty::Int);
    let out = cell(&mut p, Ty::Int);
    let q = cell(&mut p, Ty::Bool);
    let timer_q = timer.cell(FbMember::Q).expect("Q");
    let mut c = chart(
        "C",
        vec![],
        vec![seq(
            "Seq",
            1,
            vec![],
            vec![step("A"), step("B")],
            vec![trans(
                "T1",
                &[0],
                &[1],
                vec![cellv(timer_q, Ty::Bool), rd("M0.0", m(0, 0))],
            )],
        )],
    );
    c.fbs = vec![timer];
    // A: Timer(IN := A.X, PT := T#30MS, Q => q);
    //    IF sel < 2 THEN out := 1; ELSIF sel = 2 THEN out := 2; ELSE
    //      CASE sel OF 3: out := 30; 4..6, 9: out := 40; ELSE out := -1; END_CASE;
    //    END_IF;
    c.sequencers[0].steps[0].run = vec![
        Statement::Call(FbCall {
            fb: 0,
            inputs: vec![
                (FbMember::In, step_path("A.X", 0, 0, 0, StepMember::Active)),
                (FbMember::Pt, time(30)),
            ],
            outputs: vec![(FbMember::Q, Place::Cell(q), Ty::Bool)],
            origin: Origin::NONE,
        }),
        Statement::If {
            arms: vec![
                (
                    cmp(CmpOp::Lt, cellv(sel, Ty::Int), k(Value::Int(2))),
                    vec![put(out, Ty::Int, k(Value::Int(1)))],
                ),
                (
                    cmp(CmpOp::Eq, cellv(sel, Ty::Int), k(Value::Int(2))),
                    vec![put(out, Ty::Int, k(Value::Int(2)))],
                ),
            ],
            else_: vec![Statement::Case {
                selector: cellv(sel, Ty::Int),
                arms: vec![
                    (vec![(3, 3)], vec![put(out, Ty::Int, k(Value::Int(30)))]),
                    (
                        vec![(4, 6), (9, 9)],
                        vec![put(out, Ty::Int, k(Value::Int(40)))],
                    ),
                ],
                else_: vec![put(out, Ty::Int, k(Value::Int(-1)))],
                origin: Origin::NONE,
            }],
            origin: Origin::NONE,
        },
    ];
    let mut s = iec_sim(c, p, 10);
    let mut got = Vec::new();
    for v in [0, 2, 3, 5, 9, 7] {
        s.m.write_value(&Place::Cell(sel), &Value::Int(v))
            .expect("write");
        s.step();
        got.push(read(&mut s, out, Ty::Int));
    }
    assert_eq!(
        got,
        [1, 2, 30, 40, 40, -1].map(Value::Int),
        "IF/ELSIF/ELSE and CASE"
    );
    // the timer ran from cycle 1 (T = 0): Q at 30 ms, i.e. in cycle 4; A left in cycle 5
    let mut s2 = s;
    s2.rt = ChartRt::new(&s2.p, 0);
    s2.m = Machine::new(&s2.p);
    s2.k = 0;
    s2.set(&m(0, 0), true);
    let mut seen = Vec::new();
    for _ in 0..6 {
        s2.step();
        seen.push((s2.get(&Place::Cell(q)), s2.active_names().join(",")));
    }
    assert_eq!(
        seen,
        [
            (false, "Seq.A".to_owned()),
            (false, "Seq.A".to_owned()),
            (false, "Seq.A".to_owned()),
            (true, "Seq.A".to_owned()),
            (true, "Seq.B".to_owned()),
            (true, "Seq.B".to_owned()),
        ]
    );
}

#[test]
fn a_division_by_zero_in_a_chart_is_a_fault() {
    let mut p = Program::default();
    let x = cell(&mut p, Ty::Int);
    let mut c = cyclic();
    c.sequencers[0].pre = vec![Statement::Assign(Stmt {
        target: Place::Cell(x),
        ty: Ty::Int,
        value: arith_e(ArithOp::Div, k(Value::Int(1)), cellv(x, Ty::Int)),
        origin: Origin(7),
    })];
    let mut s = iec_sim(c, p, 10);
    let mut rec = ChartRecord::default();
    let fault =
        chart::cycle(&mut s.m, &s.p, 0, &mut s.rt, true, 10, Some(&mut rec)).expect_err("fault");
    assert_eq!(fault.reason, "division by zero");
    assert_eq!(fault.origin, Origin(7));
}

#[test]
fn pcs7_charts_ignore_the_new_qualifiers_inputs() {
    // a PCS 7 chart with P1 on a step behaves like the IEC definition too, but only while its
    // sequencer runs; without a start it never runs
    let mut b = step("B");
    b = b.q(Qualifier::P1, 0, None);
    let c = chart(
        "C",
        vec![("M1.0", m(1, 0))],
        vec![seq("Seq", 1, vec![], vec![step("A"), b], vec![])],
    );
    let mut s = Sim::new(c, 10);
    s.steps(3);
    assert_eq!(s.state(), OpState::Ready);
    assert!(!s.get(&m(1, 0)));
}

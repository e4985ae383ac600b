//! Chart and test expressions (`runtime.md` §4.7, §5.3): logic, comparisons per type, path
//! kinds, the `{values}` path list and conversions.

mod chart_common;

use chart_common::*;
use higraph_runtime::chart::{ChartEnv, ChartRt, Charts};
use higraph_runtime::eval::{self, NoCharts, compare, convert, paths};
use higraph_runtime::machine::Machine;
use higraph_runtime::program::{
    BlockInfo, CellInfo, CmpOp, Expr, Graph, Group, GroupOptions, Instance, OpState, Path,
    PathKind, Place, Predef, Program, SfcFlag, StepMember,
};
use higraph_runtime::value::{Ty, Value};

fn b(v: bool) -> Expr {
    k(Value::Bool(v))
}

fn ev(x: &Expr) -> Value {
    let p = Program::default();
    let mut m = Machine::new(&p);
    eval::eval(x, &mut m, &p, &NoCharts).expect("no fault")
}

#[test]
fn logic() {
    for (x, y) in [(false, false), (false, true), (true, false), (true, true)] {
        assert_eq!(ev(&and(b(x), b(y))), Value::Bool(x && y));
        assert_eq!(
            ev(&Expr::Or(Box::new(b(x)), Box::new(b(y)))),
            Value::Bool(x || y)
        );
        assert_eq!(
            ev(&Expr::Xor(Box::new(b(x)), Box::new(b(y)))),
            Value::Bool(x != y)
        );
        assert_eq!(ev(&not(b(x))), Value::Bool(!x));
    }
}

fn all_ops(a: &Value, b: &Value) -> [bool; 6] {
    [
        CmpOp::Eq,
        CmpOp::Ne,
        CmpOp::Lt,
        CmpOp::Gt,
        CmpOp::Le,
        CmpOp::Ge,
    ]
    .map(|op| compare(op, a, b))
}

#[test]
fn comparisons_by_type() {
    //                          =      <>     <      >      <=     >=
    let less = [false, true, true, false, true, false];
    let greater = [false, true, false, true, false, true];
    let equal = [true, false, false, false, true, true];
    // unsigned
    assert_eq!(all_ops(&Value::Word(0xFFFF), &Value::Word(1)), greater);
    assert_eq!(all_ops(&Value::Byte(0x80), &Value::Byte(0x7F)), greater);
    assert_eq!(
        all_ops(&Value::Dword(0x8000_0000), &Value::Dword(1)),
        greater
    );
    // signed
    assert_eq!(all_ops(&Value::Int(-1), &Value::Int(1)), less);
    assert_eq!(all_ops(&Value::Dint(i32::MIN), &Value::Dint(0)), less);
    // REAL, NaN only <>
    assert_eq!(all_ops(&Value::Real(1.5), &Value::Real(2.0)), less);
    assert_eq!(all_ops(&Value::Real(-0.0), &Value::Real(0.0)), equal);
    let nan = Value::Real(f32::NAN);
    assert_eq!(
        all_ops(&nan, &Value::Real(1.0)),
        [false, true, false, false, false, false]
    );
    assert_eq!(
        all_ops(&nan, &nan),
        [false, true, false, false, false, false]
    );
    // times by value
    assert_eq!(all_ops(&Value::Time(-5), &Value::Time(3)), less);
    assert_eq!(
        all_ops(&Value::TimeOfDay(1000), &Value::TimeOfDay(999)),
        greater
    );
    assert_eq!(all_ops(&Value::Date(10), &Value::Date(10)), equal);
    // S5TIME by duration: 1 s as base 1 s (16#2001) and as base 10 ms (16#0100)
    assert_eq!(
        all_ops(&Value::S5Time(0x2001), &Value::S5Time(0x0100)),
        equal
    );
    // 16#1010 = 10 · 100 ms = 1 s; 16#0999 = 9.99 s
    assert_eq!(
        all_ops(&Value::S5Time(0x1010), &Value::S5Time(0x0999)),
        less
    );
    // CHAR by code, STRING by content
    assert_eq!(all_ops(&Value::Char(b'a'), &Value::Char(b'B')), greater);
    let s = |x: &str| Value::String(x.to_owned());
    assert_eq!(all_ops(&s("abc"), &s("abd")), less);
    assert_eq!(all_ops(&s("ab"), &s("abc")), less);
    assert_eq!(all_ops(&s("abc"), &s("abc")), equal);
    // operating states and BOOL by =/<>
    assert_eq!(
        all_ops(&Value::OpState(3), &Value::OpState(3))[..2],
        [true, false]
    );
    assert_eq!(
        all_ops(&Value::OpState(3), &Value::OpState(7))[..2],
        [false, true]
    );
    assert_eq!(
        all_ops(&Value::Bool(true), &Value::Bool(true))[..2],
        [true, false]
    );
}

#[test]
fn paths_read_memory_instances_stubs_and_calls() {
    // one graph, one group, one instance whose CurrentState and PreviousState are cells
    let vars = Predef::ALL
        .iter()
        .map(|p| higraph_runtime::program::VarInfo {
            name: p.name().to_owned(),
            ty: p.ty(),
            msg_in: None,
            init: None,
        })
        .collect();
    let graph = Graph {
        name: "G".into(),
        vars,
        states: vec![],
        any: vec![],
        startup: None,
        initial: None,
        permanent_pre: vec![],
        permanent_post: vec![],
    };
    let cells: Vec<CellInfo> = Predef::ALL
        .iter()
        .map(|p| CellInfo {
            ty: p.ty(),
            init: match p {
                Predef::CurrentState => Value::Word(7),
                Predef::PreviousState => Value::Word(3),
                _ => Value::zero(p.ty()),
            },
        })
        .collect();
    let binding = (0..cells.len() as u32).map(Place::Cell).collect();
    let p = Program {
        cells,
        graphs: vec![graph],
        groups: vec![Group {
            name: "Grp".into(),
            options: GroupOptions::default(),
            instances: vec![Instance {
                name: "Inst".into(),
                graph: 0,
                binding,
            }],
            internal_messages: vec![],
        }],
        blocks: vec![BlockInfo {
            name: "FC10".into(),
        }],
        ..Program::default()
    };
    let mut m = Machine::new(&p);
    let read = |m: &mut Machine, kind: PathKind, ty: Ty| {
        let path = Path {
            text: "x".into(),
            ty,
            kind,
        };
        eval::read_path(&path, m, &p, &NoCharts).expect("read")
    };
    let st = |previous| PathKind::InstState {
        group: 0,
        instance: 0,
        previous,
    };
    assert_eq!(read(&mut m, st(false), Ty::Word), Value::Word(7));
    assert_eq!(read(&mut m, st(true), Ty::Word), Value::Word(3));
    // `Inst.state = 7` as a test expression
    let x = cmp(
        CmpOp::Eq,
        Expr::Read(Path {
            text: "Inst.state".into(),
            ty: Ty::Word,
            kind: st(false),
        }),
        k(Value::Word(7)),
    );
    assert_eq!(eval::eval(&x, &mut m, &p, &NoCharts), Ok(Value::Bool(true)));
    // memory
    m.write_value(&mw(10), &Value::Word(0x1234)).expect("write");
    assert_eq!(
        read(&mut m, PathKind::Place(mw(10)), Ty::Int),
        Value::Int(0x1234)
    );
    assert_eq!(
        read(&mut m, PathKind::Place(chart_common::m(10, 4)), Ty::Bool),
        Value::Bool(true)
    );
    // stubs: the zero of the path's type until set; calls
    let stub = || PathKind::Stub {
        block: 0,
        param: "RET_VAL".into(),
    };
    assert_eq!(read(&mut m, stub(), Ty::Int), Value::Int(0));
    m.set_stub(0, "RET_VAL", Value::Int(-4));
    assert_eq!(read(&mut m, stub(), Ty::Int), Value::Int(-4));
    assert_eq!(
        read(&mut m, PathKind::Calls { block: 0 }, Ty::Dint),
        Value::Dint(0)
    );
    m.count_call(0);
    m.count_call(0);
    assert_eq!(
        read(&mut m, PathKind::Calls { block: 0 }, Ty::Dint),
        Value::Dint(2)
    );
}

#[test]
fn charts_env_and_chart_env() {
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![step("S1"), step("E")],
            vec![trans("T", &[0], &[1], vec![b(false)])],
        )],
    );
    let mut s = Sim::new(c, 10);
    let x = and(
        cmp(
            CmpOp::Eq,
            chart_state("C.state", 0),
            k(Value::OpState(OpState::Active as u8)),
        ),
        step_path("C.S1", 0, 0, 0, StepMember::Active),
    );
    assert!(!s.eval(&x));
    s.command(higraph_runtime::program::Command::Start);
    s.steps(3);
    assert!(s.eval(&x));
    assert!(!s.eval(&sfc(SfcFlag::Run)), "no SFC flag outside a chart");
    let t = step_path("C.S1.T", 0, 0, 0, StepMember::Time);
    assert!(s.eval(&cmp(CmpOp::Eq, t.clone(), k(Value::Time(20)))));
    // chart code sees its own flags
    let rt: &ChartRt = &s.rt;
    let v = eval::eval(&sfc(SfcFlag::Run), &mut s.m, &s.p, &ChartEnv(rt));
    assert_eq!(v, Ok(Value::Bool(true)));
    let v = eval::eval(&sfc(SfcFlag::Idle), &mut s.m, &s.p, &ChartEnv(rt));
    assert_eq!(v, Ok(Value::Bool(false)));
    // an unknown chart reads Ready
    let other = chart_state("D.state", 5);
    let v = eval::eval(&other, &mut s.m, &s.p, &Charts(std::slice::from_ref(rt)));
    assert_eq!(v, Ok(Value::OpState(OpState::Ready as u8)));
}

#[test]
fn paths_in_first_appearance_order_once() {
    let x = and(
        cmp(
            CmpOp::Eq,
            chart_state("Abfuellen.state", 0),
            k(Value::OpState(7)),
        ),
        and(
            not(rd("Ventil", a(4, 0))),
            Expr::Or(
                Box::new(rd("Ventil_Sperre", m(40, 0))),
                Box::new(rd("Ventil", a(4, 0))),
            ),
        ),
    );
    let names: Vec<&str> = paths(&x).iter().map(|p| p.text.as_str()).collect();
    assert_eq!(names, ["Abfuellen.state", "Ventil", "Ventil_Sperre"]);
    let p = Program::default();
    let mut mach = Machine::new(&p);
    mach.write_value(&m(40, 0), &Value::Bool(true))
        .expect("write");
    let vals = eval::path_values(&x, &mut mach, &p, &NoCharts).expect("read");
    assert_eq!(
        vals,
        [
            ("Abfuellen.state".to_owned(), Value::OpState(1)),
            ("Ventil".to_owned(), Value::Bool(false)),
            ("Ventil_Sperre".to_owned(), Value::Bool(true)),
        ]
    );
    assert!(paths(&b(true)).is_empty());
}

#[test]
fn deep_expressions_use_no_call_stack() {
    // far deeper than the parser's nesting limit; run on a small stack
    let h = std::thread::Builder::new()
        .stack_size(64 * 1024)
        .spawn(|| {
            let mut x = b(true);
            for i in 0..20_000 {
                x = if i % 2 == 0 { not(x) } else { and(b(true), x) };
            }
            let v = ev(&x);
            let n = paths(&x).len();
            // dropping a deep Box chain recurses: leak it
            std::mem::forget(x);
            (v, n)
        })
        .expect("thread");
    assert_eq!(h.join().expect("no overflow"), (Value::Bool(true), 0));
}

#[test]
fn conversions() {
    assert_eq!(convert(Value::Dint(5), Ty::Int), Value::Int(5));
    assert_eq!(convert(Value::Dint(200), Ty::Byte), Value::Byte(200));
    assert_eq!(convert(Value::Dint(-1), Ty::Word), Value::Word(0xFFFF));
    assert_eq!(convert(Value::Int(3), Ty::Real), Value::Real(3.0));
    assert_eq!(convert(Value::Real(2.5), Ty::Real), Value::Real(2.5));
    assert_eq!(convert(Value::Bool(true), Ty::Bool), Value::Bool(true));
    assert_eq!(
        convert(Value::String("abcdef".into()), Ty::String(3)),
        Value::String("abc".into())
    );
    assert_eq!(
        convert(Value::Char(b'x'), Ty::String(4)),
        Value::String("x".into())
    );
    assert_eq!(
        convert(Value::Time(1000), Ty::S5Time),
        Value::S5Time(0x0100)
    );
    assert_eq!(
        convert(Value::Time(20_000), Ty::S5Time),
        Value::S5Time(0x1200)
    );
    assert_eq!(convert(Value::S5Time(0x2005), Ty::Time), Value::Time(5000));
    assert_eq!(convert(Value::Time(7), Ty::Time), Value::Time(7));
    assert_eq!(convert(Value::OpState(3), Ty::OpState), Value::OpState(3));
    // chart statements write the converted value
    let c = chart(
        "C",
        vec![],
        vec![seq(
            "RUN",
            1,
            vec![sfc(SfcFlag::Run)],
            vec![
                step("S1").init(vec![higraph_runtime::program::Stmt {
                    target: mw(20),
                    ty: Ty::Int,
                    value: k(Value::Dint(-2)),
                    origin: higraph_runtime::program::Origin::NONE,
                }]),
                step("E"),
            ],
            vec![],
        )],
    );
    let mut s = Sim::new(c, 10);
    s.command(higraph_runtime::program::Command::Start);
    s.step();
    assert_eq!(s.m.read_value(&mw(20), Ty::Word), Ok(Value::Word(0xFFFE)));
}

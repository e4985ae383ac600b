//! Helpers for the chart tests: charts built by hand (as the lowering would build them) and a
//! small driver that runs chart cycles on a machine.
#![allow(dead_code)]

use higraph_runtime::chart::{self, ChartRt, Charts};
use higraph_runtime::eval;
use higraph_runtime::machine::Machine;
use higraph_runtime::program::{
    Action, Association, Chart, ChartTrans, ChartTransKind, CmpOp, Command, Expr, MemArea, OpState,
    Origin, Path, PathKind, Place, Profile, Program, Qualifier, Sequencer, SfcFlag, Step, StepIdx,
    StepMember, Stmt, Switching, Width,
};
use higraph_runtime::trace::ChartRecord;
use higraph_runtime::value::{Ty, Value};

pub fn bit(area: MemArea, byte: u32, b: u8) -> Place {
    Place::Mem {
        area,
        byte,
        width: Width::Bit(b),
    }
}
pub fn e(byte: u32, b: u8) -> Place {
    bit(MemArea::Input, byte, b)
}
pub fn a(byte: u32, b: u8) -> Place {
    bit(MemArea::Output, byte, b)
}
pub fn m(byte: u32, b: u8) -> Place {
    bit(MemArea::Memory, byte, b)
}
pub fn mw(byte: u32) -> Place {
    Place::Mem {
        area: MemArea::Memory,
        byte,
        width: Width::Word,
    }
}

/// A read of a BOOL place, named `text`.
pub fn rd(text: &str, place: Place) -> Expr {
    rd_ty(text, place, Ty::Bool)
}
pub fn rd_ty(text: &str, place: Place, ty: Ty) -> Expr {
    Expr::Read(Path {
        text: text.to_owned(),
        ty,
        kind: PathKind::Place(place),
    })
}
pub fn sfc(flag: SfcFlag) -> Expr {
    Expr::Read(Path {
        text: format!("SFC.{flag:?}").to_uppercase(),
        ty: Ty::Bool,
        kind: PathKind::Sfc(flag),
    })
}
pub fn not(x: Expr) -> Expr {
    Expr::Not(Box::new(x))
}
pub fn and(x: Expr, y: Expr) -> Expr {
    Expr::And(Box::new(x), Box::new(y))
}
pub fn cmp(op: CmpOp, x: Expr, y: Expr) -> Expr {
    Expr::Cmp(op, Box::new(x), Box::new(y))
}
pub fn k(v: Value) -> Expr {
    Expr::Const(v)
}
pub fn chart_state(text: &str, chart: u32) -> Expr {
    Expr::Read(Path {
        text: text.to_owned(),
        ty: Ty::OpState,
        kind: PathKind::ChartState { chart },
    })
}
pub fn step_path(text: &str, chart: u32, seq: u32, step: StepIdx, member: StepMember) -> Expr {
    Expr::Read(Path {
        text: text.to_owned(),
        ty: match member {
            StepMember::Time => Ty::Time,
            _ => Ty::Bool,
        },
        kind: PathKind::Step {
            chart,
            sequencer: seq,
            step,
            member,
        },
    })
}
/// `place := value;` for a BOOL place.
pub fn assign(place: Place, value: Expr) -> Stmt {
    Stmt {
        target: place,
        ty: Ty::Bool,
        value,
        origin: Origin::NONE,
    }
}
/// `MW n := MW n + 1` cannot be written in a chart; a counter of phases is kept by setting a
/// bit per phase instead. This writes `place := TRUE`.
pub fn set_true(place: Place) -> Stmt {
    assign(place, k(Value::Bool(true)))
}
pub fn time(ms: i32) -> Expr {
    k(Value::Time(ms))
}

/// A step under construction.
pub struct StepB(pub Step);

pub fn step(name: &str) -> StepB {
    StepB(Step {
        name: name.to_owned(),
        init: vec![],
        run: vec![],
        term: vec![],
        qualifiers: vec![],
        min: None,
        max: None,
        confirm: false,
        candidates: vec![],
        origin: Origin::NONE,
    })
}

impl StepB {
    pub fn q(mut self, qualifier: Qualifier, action: u32, ms: Option<i32>) -> StepB {
        self.0.qualifiers.push(Association {
            qualifier,
            action,
            time: ms.map(time),
        });
        self
    }
    pub fn init(mut self, s: Vec<Stmt>) -> StepB {
        self.0.init = s.into_iter().map(Into::into).collect();
        self
    }
    pub fn run(mut self, s: Vec<Stmt>) -> StepB {
        self.0.run = s.into_iter().map(Into::into).collect();
        self
    }
    pub fn term(mut self, s: Vec<Stmt>) -> StepB {
        self.0.term = s.into_iter().map(Into::into).collect();
        self
    }
    pub fn min(mut self, ms: i32) -> StepB {
        self.0.min = Some(time(ms));
        self
    }
    pub fn max(mut self, ms: i32) -> StepB {
        self.0.max = Some(time(ms));
        self
    }
    pub fn confirm(mut self) -> StepB {
        self.0.confirm = true;
        self
    }
}

pub fn tr(
    kind: ChartTransKind,
    name: &str,
    from: &[StepIdx],
    to: &[StepIdx],
    conditions: Vec<Expr>,
) -> ChartTrans {
    ChartTrans {
        kind,
        name: Some(name.to_owned()),
        from: from.to_vec(),
        to: to.to_vec(),
        conditions,
        origin: Origin::NONE,
    }
}
pub fn trans(name: &str, from: &[StepIdx], to: &[StepIdx], conditions: Vec<Expr>) -> ChartTrans {
    tr(ChartTransKind::Trans, name, from, to, conditions)
}

/// A sequencer; the steps' candidates are filled in as the lowering does: the `trans` units
/// a step precedes (text order), then its `loop`s and `jump`s in text order.
pub fn seq(
    name: &str,
    prio: u32,
    start: Vec<Expr>,
    steps: Vec<StepB>,
    transitions: Vec<ChartTrans>,
) -> Sequencer {
    let mut steps: Vec<Step> = steps.into_iter().map(|s| s.0).collect();
    for (si, s) in steps.iter_mut().enumerate() {
        let mine = |t: &ChartTrans| t.from.contains(&(si as StepIdx));
        let trans = transitions
            .iter()
            .enumerate()
            .filter(|(_, t)| t.kind == ChartTransKind::Trans && mine(t));
        let others = transitions
            .iter()
            .enumerate()
            .filter(|(_, t)| t.kind != ChartTransKind::Trans && mine(t));
        s.candidates = trans.chain(others).map(|(i, _)| i as u32).collect();
    }
    Sequencer {
        name: name.to_owned(),
        prio,
        start,
        pre: vec![],
        post: vec![],
        steps,
        transitions,
    }
}

pub fn chart(name: &str, actions: Vec<(&str, Place)>, sequencers: Vec<Sequencer>) -> Chart {
    Chart {
        name: name.to_owned(),
        vars: vec![],
        mode_auto: false,
        switching: Switching::T,
        cyclic: false,
        time_monitoring: false,
        autostart: false,
        sequencers,
        actions: actions
            .into_iter()
            .map(|(n, p)| Action {
                name: n.to_owned(),
                place: p,
                body: None,
            })
            .collect(),
        profile: Profile::Pcs7,
        fbs: vec![],
    }
}

/// One chart on a machine, cycle by cycle.
pub struct Sim {
    pub p: Program,
    pub m: Machine,
    pub rt: ChartRt,
    pub k: u64,
    pub dt: u32,
    pub first: bool,
    /// The record of the last cycle.
    pub rec: ChartRecord,
}

impl Sim {
    pub fn new(c: Chart, dt: u32) -> Sim {
        let p = Program {
            charts: vec![c],
            ..Program::default()
        };
        let m = Machine::new(&p);
        let rt = ChartRt::new(&p, 0);
        Sim {
            p,
            m,
            rt,
            k: 0,
            dt,
            first: true,
            rec: ChartRecord::default(),
        }
    }

    pub fn step(&mut self) {
        self.k += 1;
        self.m.now_ms = self.k * u64::from(self.dt);
        let mut rec = ChartRecord::default();
        chart::cycle(
            &mut self.m,
            &self.p,
            0,
            &mut self.rt,
            self.first,
            self.dt,
            Some(&mut rec),
        )
        .expect("no fault");
        self.first = false;
        self.rec = rec;
    }

    pub fn steps(&mut self, n: u32) {
        for _ in 0..n {
            self.step();
        }
    }

    pub fn command(&mut self, c: Command) {
        self.rt.queue(c);
    }

    pub fn get(&mut self, place: &Place) -> bool {
        self.m.read_value(place, Ty::Bool).expect("read") == Value::Bool(true)
    }

    pub fn set(&mut self, place: &Place, v: bool) {
        self.m.write_value(place, &Value::Bool(v)).expect("write");
    }

    pub fn state(&self) -> OpState {
        self.rt.state
    }

    pub fn active(&self, seq: u32, step: StepIdx) -> bool {
        self.rt.is_active(seq, step)
    }

    /// The names of the active steps, `SEQ.STEP`, as the trace lists them.
    pub fn active_names(&self) -> Vec<String> {
        self.rec.active.clone()
    }

    pub fn t(&self, seq: u32, step: StepIdx) -> i32 {
        match chart::step_value(&self.rt, seq, step, StepMember::Time) {
            Value::Time(t) => t,
            v => panic!("T is {v:?}"),
        }
    }

    pub fn error(&self, seq: u32, step: StepIdx) -> bool {
        chart::step_value(&self.rt, seq, step, StepMember::Error) == Value::Bool(true)
    }

    /// Evaluates a test expression against the machine and the chart.
    pub fn eval(&mut self, x: &Expr) -> bool {
        let rts = std::slice::from_ref(&self.rt);
        eval::eval_bool(x, &mut self.m, &self.p, &Charts(rts)).expect("eval")
    }

    pub fn phases(&self) -> Vec<String> {
        self.rec.phases.clone()
    }

    pub fn fired(&self) -> Vec<(String, String, Option<String>)> {
        self.rec
            .fired
            .iter()
            .map(|f| (f.sequencer.clone(), f.kind.to_owned(), f.name.clone()))
            .collect()
    }
}

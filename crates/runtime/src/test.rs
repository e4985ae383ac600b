//! The test runner (`runtime.md` §5.2): executes a test's statements on a fresh simulation and
//! reports failures, faults and the trace.
//!
//! Decisions where the spec is silent:
//! * A statement between cycles k and k + 1 reports "cycle k" and t_k; before the first cycle
//!   that is "cycle 0 (t = 0 ms)".
//! * The 10 000 001st cycle is not started: the fault reports it as its cycle, `cycles`
//!   stays 10 000 000.
//! * `'{expr}'` of HG9902 is the expression printed back from the lowered program: paths as
//!   written (white space removed), constants canonical, operators lower case, parentheses
//!   only where precedence needs them. Callers that have the source (`higraph-lsp test`, the
//!   server) put the text as written in its place.
//! * An expression without paths (`expect FALSE;`) has no `: {values}` part.
//! * A path that cannot be read for the trace's `watch` (a fault while reading) is `null`
//!   there; the test itself is not affected.

use std::fmt::Write as _;

use crate::eval;
use crate::machine::Fault;
use crate::program::{
    ArithOp, CmpOp, Expr, Origin, PathKind, Place, Program, TestStmt, TestStmtKind,
};
use crate::sim::Sim;
use crate::trace::{Before, CycleRecord, Initial, OrderedMap, Trace, json_value};
use crate::value::Value;

/// How a test ended (`runtime.md` §7: passed, failed = HG9901/HG9902, error = HG9903/HG9904).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    Failed,
    Error,
}

impl Outcome {
    /// `passed`, `failed` or `error`, as the JSON outputs write it.
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Passed => "passed",
            Outcome::Failed => "failed",
            Outcome::Error => "error",
        }
    }
}

/// One HG9901, HG9902 or HG9903.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// "HG9901", "HG9902" or "HG9903".
    pub code: &'static str,
    /// The complete message of §6.
    pub message: String,
    /// The expression (HG9901/HG9902), the faulting STL or test statement (HG9903).
    pub origin: Origin,
    /// For a fault inside STL: the running test statement (the related location).
    pub statement: Origin,
    pub cycle: u64,
    pub time_ms: u64,
    /// Each path of the expression with its value, in first-appearance order.
    pub values: Vec<(String, Value)>,
}

/// The result of one run.
#[derive(Debug, Clone)]
pub struct TestRun {
    pub outcome: Outcome,
    /// Machine cycles started (a faulting cycle included).
    pub cycles: u64,
    /// Virtual time at the end, ms.
    pub time_ms: u64,
    pub failures: Vec<Failure>,
    /// With [`RunOptions::trace`]; `file` and `failures` are left for the caller to fill.
    pub trace: Option<Trace>,
}

/// Options of a run.
pub struct RunOptions<'a> {
    pub trace: bool,
    /// Asked between cycles; `true` stops the run (the result is then meaningless).
    pub cancelled: &'a dyn Fn() -> bool,
}

/// What a run reports to an [`Observer`] besides its result: the memory the test statements
/// write and the state around each cycle. Used by the proof of the generated code
/// (`scripts/build-diff`), which replays a test in another PLC and compares.
pub trait Observer {
    /// A `set` statement wrote `value` to `place`.
    fn set(&mut self, _place: &Place, _value: &Value) {}
    /// A `set` of a stub value (`Block.param`), which no other PLC can replay.
    fn stub(&mut self) {}
    /// `restart cold|warm`.
    fn restart(&mut self, _cold: bool) {}
    /// A cycle is about to start (its INIT_SD is `sim.next_is_first()`).
    fn before_cycle(&mut self, _sim: &mut Sim<'_>) {}
    /// A cycle ended without a fault.
    fn after_cycle(&mut self, _sim: &mut Sim<'_>) {}
}

struct NoObserver;
impl Observer for NoObserver {}

/// Runs the program's test on a fresh machine. `None` when cancelled. A runtime fault is an
/// HG9903 failure in the result. A program without a test passes at once.
pub fn run(program: &Program, options: &RunOptions<'_>) -> Option<TestRun> {
    run_observed(program, options, &mut NoObserver)
}

/// [`run`], reporting to `observer`.
pub fn run_observed(
    program: &Program,
    options: &RunOptions<'_>,
    observer: &mut dyn Observer,
) -> Option<TestRun> {
    let mut runner = Runner {
        observer,
        sim: Sim::new(program),
        failures: Vec::new(),
        trace: options.trace.then(|| new_trace(program)),
        before: Vec::new(),
        options,
        limit_hit: false,
    };
    if let Some(trace) = &mut runner.trace {
        let (watch, values) = watch_values(&mut runner.sim);
        trace.initial = Initial { watch };
        trace.initial_watch_values = values;
        trace.initial_messages = message_values(&mut runner.sim);
    }
    let stmts = program.test.as_ref().map_or(&[][..], |t| &t.stmts[..]);
    let mut fault = false;
    for stmt in stmts {
        match runner.statement(stmt) {
            Ok(Flow::Continue) => {}
            Ok(Flow::Stop) => break,
            Ok(Flow::Cancelled) => return None,
            Err(f) => {
                runner.fault(f, stmt.origin);
                fault = true;
                break;
            }
        }
    }
    let outcome = if fault {
        Outcome::Error
    } else if runner.failures.is_empty() {
        Outcome::Passed
    } else {
        Outcome::Failed
    };
    let mut trace = runner.trace;
    if let Some(trace) = &mut trace {
        trace.result = outcome.as_str().to_string();
    }
    Some(TestRun {
        outcome,
        cycles: runner.sim.cycle,
        time_ms: runner.sim.now_ms(),
        failures: runner.failures,
        trace,
    })
}

/// What the runner does after a statement.
enum Flow {
    Continue,
    /// An `until` failed: the test stops.
    Stop,
    Cancelled,
}

struct Runner<'p, 'o> {
    observer: &'o mut dyn Observer,
    sim: Sim<'p>,
    failures: Vec<Failure>,
    trace: Option<Trace>,
    /// The test statements that acted since the last cycle (the next cycle's `before`).
    before: Vec<Before>,
    options: &'o RunOptions<'o>,
    /// The next cycle would have been one too many (§1.4).
    limit_hit: bool,
}

impl Runner<'_, '_> {
    fn statement(&mut self, stmt: &TestStmt) -> Result<Flow, Fault> {
        match &stmt.kind {
            TestStmtKind::Set { target, value } => {
                let program = self.sim.program;
                let (m, env) = self.sim.split();
                let v = eval::eval(value, m, program, &env)?;
                let v = eval::convert(v, target.ty);
                match &target.kind {
                    PathKind::Place(place) => {
                        m.write_value(place, &v)?;
                        self.observer.set(place, &v);
                    }
                    PathKind::Stub { block, param } => {
                        m.set_stub(*block, param, v.clone());
                        self.observer.stub();
                    }
                    // The lowering rejects every other target (HG9104).
                    _ => return Err(Fault::new(format!("'{}' cannot be set", target.text))),
                }
                if self.trace.is_some() {
                    self.before.push(Before::Set {
                        set: target.text.clone(),
                        value: json_value(&v),
                    });
                }
            }
            TestStmtKind::Step { cycles } => {
                for _ in 0..*cycles {
                    if let Some(flow) = self.cycle()? {
                        return Ok(flow);
                    }
                }
            }
            TestStmtKind::Until {
                cond,
                cycles,
                within,
                message,
                expr_origin,
            } => {
                if self.holds(cond)? {
                    return Ok(Flow::Continue);
                }
                for _ in 0..*cycles {
                    if let Some(flow) = self.cycle()? {
                        return Ok(flow);
                    }
                    if self.holds(cond)? {
                        return Ok(Flow::Continue);
                    }
                }
                let values = self.values(cond)?;
                let mut text = format!("'{}' did not hold within {within}", expr_text(cond));
                if let Some(message) = message {
                    let _ = write!(text, ": {message}");
                }
                let _ = write!(text, ": at cycle {}", self.sim.cycle);
                push_values(&mut text, &values);
                self.fail("HG9902", text, *expr_origin, stmt.origin, values);
                return Ok(Flow::Stop);
            }
            TestStmtKind::Expect {
                cond,
                message,
                expr_origin,
            } => {
                if !self.holds(cond)? {
                    let values = self.values(cond)?;
                    let mut text = String::from("expect failed");
                    if let Some(message) = message {
                        let _ = write!(text, ": {message}");
                    }
                    let _ = write!(
                        text,
                        ": at cycle {} (t = {} ms)",
                        self.sim.cycle,
                        self.sim.now_ms()
                    );
                    push_values(&mut text, &values);
                    self.fail("HG9901", text, *expr_origin, stmt.origin, values);
                }
            }
            TestStmtKind::Command { chart, command } => {
                self.sim.command(*chart, *command);
                if self.trace.is_some() {
                    let name = self
                        .sim
                        .program
                        .charts
                        .get(*chart as usize)
                        .map(|c| c.name.clone())
                        .unwrap_or_default();
                    self.before.push(Before::Command {
                        command: command.name().to_string(),
                        chart: name,
                    });
                }
            }
            TestStmtKind::Confirm {
                chart,
                sequencer,
                step,
                text,
            } => {
                self.sim.confirm(*chart, *sequencer, *step)?;
                if self.trace.is_some() {
                    self.before.push(Before::Confirm {
                        confirm: text.clone(),
                    });
                }
            }
            TestStmtKind::Restart { cold } => {
                self.sim.restart(*cold);
                self.observer.restart(*cold);
                if self.trace.is_some() {
                    self.before.push(Before::Restart {
                        restart: if *cold { "cold" } else { "warm" }.to_string(),
                    });
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// Runs one cycle; `Some(Cancelled)` when the run was cancelled before it.
    fn cycle(&mut self) -> Result<Option<Flow>, Fault> {
        if (self.options.cancelled)() {
            return Ok(Some(Flow::Cancelled));
        }
        if self.sim.cycle >= crate::sim::MAX_CYCLES {
            self.limit_hit = true;
        }
        self.observer.before_cycle(&mut self.sim);
        if self.trace.is_none() {
            self.sim.step(None)?;
            self.observer.after_cycle(&mut self.sim);
            return Ok(None);
        }
        let mut record = CycleRecord {
            before: std::mem::take(&mut self.before),
            ..CycleRecord::default()
        };
        let result = self.sim.step(Some(&mut record));
        // A cycle that faulted half-way is recorded with what ran; a cycle that was not
        // started (the cycle limit) is not.
        if record.cycle > 0 {
            if result.is_ok() {
                let (watch, values) = watch_values(&mut self.sim);
                record.watch = watch;
                record.watch_values = values;
                record.messages = message_values(&mut self.sim);
            }
            if let Some(trace) = &mut self.trace {
                trace.cycles.push(record);
            }
        }
        if result.is_ok() {
            self.observer.after_cycle(&mut self.sim);
        }
        result.map(|()| None)
    }

    fn holds(&mut self, cond: &Expr) -> Result<bool, Fault> {
        let program = self.sim.program;
        let (m, env) = self.sim.split();
        Ok(matches!(
            eval::eval(cond, m, program, &env)?,
            Value::Bool(true)
        ))
    }

    /// Each path of `cond` with its value now, in first-appearance order, once each.
    fn values(&mut self, cond: &Expr) -> Result<Vec<(String, Value)>, Fault> {
        let paths = eval::paths(cond);
        let program = self.sim.program;
        let (m, env) = self.sim.split();
        let mut values = Vec::with_capacity(paths.len());
        for path in paths {
            values.push((path.text.clone(), eval::read_path(path, m, program, &env)?));
        }
        Ok(values)
    }

    fn fail(
        &mut self,
        code: &'static str,
        message: String,
        origin: Origin,
        statement: Origin,
        values: Vec<(String, Value)>,
    ) {
        self.failures.push(Failure {
            code,
            message,
            origin,
            statement,
            cycle: self.sim.cycle,
            time_ms: self.sim.now_ms(),
            values,
        });
    }

    /// HG9903 for a fault while `statement` ran. A fault of the cycle limit names the cycle
    /// that was not started.
    fn fault(&mut self, fault: Fault, statement: Origin) {
        let cycle = if self.limit_hit {
            self.sim.cycle + 1
        } else {
            self.sim.cycle
        };
        let origin = if fault.origin == Origin::NONE {
            statement
        } else {
            fault.origin
        };
        self.failures.push(Failure {
            code: "HG9903",
            message: format!("runtime fault at cycle {cycle}: {}", fault.reason),
            origin,
            statement,
            cycle,
            time_ms: self.sim.now_ms(),
            values: Vec::new(),
        });
    }
}

fn new_trace(program: &Program) -> Trace {
    let test = program.test.as_ref();
    Trace {
        version: 1,
        test: test.map(|t| t.name.clone()).unwrap_or_default(),
        file: String::new(),
        cycle_ms: test.map_or(10, |t| t.cycle_ms),
        run: test
            .map(|t| {
                t.run
                    .iter()
                    .map(|entry| match *entry {
                        crate::program::RunEntry::Group(g) => program
                            .groups
                            .get(g as usize)
                            .map(|g| g.name.clone())
                            .unwrap_or_default(),
                        crate::program::RunEntry::Chart(c) => program
                            .charts
                            .get(c as usize)
                            .map(|c| c.name.clone())
                            .unwrap_or_default(),
                    })
                    .collect()
            })
            .unwrap_or_default(),
        result: String::new(),
        failures: Vec::new(),
        initial: Initial::default(),
        cycles: Vec::new(),
        initial_messages: Vec::new(),
        initial_watch_values: Vec::new(),
    }
}

/// The watched paths now: as JSON VALUEs (a path that cannot be read is `null`) and as values.
fn watch_values(sim: &mut Sim<'_>) -> (OrderedMap, Vec<Option<Value>>) {
    let mut map = OrderedMap::default();
    let mut values = Vec::new();
    let program = sim.program;
    let Some(test) = &program.test else {
        return (map, values);
    };
    let (m, env) = sim.split();
    for path in &test.watch {
        let value = eval::read_path(path, m, program, &env).ok();
        map.insert(
            path.text.clone(),
            value.as_ref().map_or(serde_json::Value::Null, json_value),
        );
        values.push(value);
    }
    (map, values)
}

/// The internal messages of every group run, in group and message order (the VCD's
/// `messages`).
fn message_values(sim: &mut Sim<'_>) -> Vec<bool> {
    let program = sim.program;
    let mut out = Vec::new();
    for entry in &sim.run {
        let crate::program::RunEntry::Group(g) = *entry else {
            continue;
        };
        let Some(group) = program.groups.get(g as usize) else {
            continue;
        };
        for message in &group.internal_messages {
            let place = crate::program::Place::Cell(message.cell);
            out.push(sim.machine.read(&place).is_ok_and(|bits| bits & 1 != 0));
        }
    }
    out
}

/// `: {values}`, or nothing for an expression without paths (`expect FALSE;`).
fn push_values(text: &mut String, values: &[(String, Value)]) {
    if !values.is_empty() {
        text.push_str(": ");
        text.push_str(&values_text(values));
    }
}

/// `{values}` of §6: `path = value`, joined by `, `.
pub fn values_text(values: &[(String, Value)]) -> String {
    let mut out = String::new();
    for (i, (path, value)) in values.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        let _ = write!(out, "{path} = {}", display_value(value));
    }
    out
}

/// A value as failure messages show it (§6): BOOL `TRUE`/`FALSE`, numbers decimal, REAL the
/// shortest text that reads back as the same binary32, TIME canonical (`T#1S500MS`),
/// operating states by name.
pub fn display_value(value: &Value) -> String {
    match value {
        Value::Bool(true) => "TRUE".into(),
        Value::Bool(false) => "FALSE".into(),
        Value::Byte(v) => v.to_string(),
        Value::Word(v) => v.to_string(),
        Value::Dword(v) => v.to_string(),
        Value::Int(v) => v.to_string(),
        Value::Dint(v) => v.to_string(),
        Value::Real(v) => real_text(*v),
        Value::S5Time(v) => format!("S5T#{}", duration_text(i64::from(s5time_ms(*v)))),
        Value::Time(v) => format!("T#{}", duration_text(i64::from(*v))),
        Value::Date(days) => format!("D#{}", date_text(i64::from(*days))),
        Value::TimeOfDay(ms) => {
            let ms = *ms;
            format!(
                "TOD#{}:{:02}:{:02}.{:03}",
                ms / 3_600_000,
                ms / 60_000 % 60,
                ms / 1000 % 60,
                ms % 1000
            )
        }
        Value::DateAndTime(bytes) => {
            let hex: String = bytes.iter().map(|b| format!("{b:02X}")).collect();
            format!("DT#16#{hex}")
        }
        Value::Char(c) => format!("'{}'", char::from(*c)),
        Value::String(s) => format!("'{s}'"),
        Value::OpState(n) => crate::program::OpState::from_number(*n)
            .map_or_else(|| n.to_string(), |s| s.name().to_string()),
    }
}

/// The shortest decimal text that reads back as `v` (Rust's `Debug` for `f32`: `1.0`,
/// `0.1`, `1e30`, `NaN`, `inf`, `-inf`).
pub fn real_text(v: f32) -> String {
    format!("{v:?}")
}

/// `1S500MS`, `2D3H`, `0MS`, `-1S`: the canonical duration text after `T#`.
pub fn duration_text(ms: i64) -> String {
    if ms == 0 {
        return "0MS".into();
    }
    let mut out = String::new();
    if ms < 0 {
        out.push('-');
    }
    let mut rest = ms.unsigned_abs();
    for (unit, size) in [
        ("D", 86_400_000u64),
        ("H", 3_600_000),
        ("M", 60_000),
        ("S", 1000),
        ("MS", 1),
    ] {
        let n = rest / size;
        rest %= size;
        if n > 0 {
            let _ = write!(out, "{n}{unit}");
        }
    }
    out
}

/// The duration of an S5TIME pattern (§3.3), ms; bits 14–15 ignored, BCD digits above 9
/// taken as they are.
fn s5time_ms(pattern: u16) -> u32 {
    let base = match (pattern >> 12) & 3 {
        0 => 10,
        1 => 100,
        2 => 1000,
        _ => 10_000,
    };
    let digits = u32::from((pattern >> 8) & 0xF) * 100
        + u32::from((pattern >> 4) & 0xF) * 10
        + u32::from(pattern & 0xF);
    digits * base
}

/// `1990-01-01` + `days`, as `YYYY-MM-DD`.
fn date_text(days: i64) -> String {
    // Days from 1970-01-01 to 1990-01-01, then the civil-from-days algorithm.
    let z = days + 7305 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y}-{m:02}-{d:02}")
}

/// An expression printed back (HG9902's `'{expr}'`): `or` < `xor` < `and` < comparison <
/// `+ -` < `* / MOD` < `not`, unary `-`; parentheses only where needed. Iterative, so depth costs no stack.
pub fn expr_text(expr: &Expr) -> String {
    enum Item<'e> {
        Expr(&'e Expr, u8),
        Text(&'static str),
    }
    fn level(expr: &Expr) -> u8 {
        match expr {
            Expr::Or(..) => 1,
            Expr::Xor(..) => 2,
            Expr::And(..) => 3,
            Expr::Cmp(..) => 4,
            Expr::Arith(ArithOp::Add | ArithOp::Sub, ..) => 5,
            Expr::Arith(..) => 6,
            Expr::Not(_) | Expr::Neg(_) => 7,
            Expr::Const(_) | Expr::Read(_) => 8,
        }
    }
    let mut out = String::new();
    let mut stack = vec![Item::Expr(expr, 0)];
    while let Some(item) = stack.pop() {
        let (expr, min) = match item {
            Item::Text(text) => {
                out.push_str(text);
                continue;
            }
            Item::Expr(expr, min) => (expr, min),
        };
        let own = level(expr);
        let paren = own < min;
        if paren {
            out.push('(');
            stack.push(Item::Text(")"));
        }
        match expr {
            Expr::Const(value) => out.push_str(&display_value(value)),
            Expr::Read(path) => out.push_str(&path.text),
            Expr::Not(inner) => {
                out.push_str("not ");
                stack.push(Item::Expr(inner, 7));
            }
            Expr::Neg(inner) => {
                out.push('-');
                stack.push(Item::Expr(inner, 7));
            }
            Expr::Arith(op, a, b) => {
                let op = match op {
                    ArithOp::Add => " + ",
                    ArithOp::Sub => " - ",
                    ArithOp::Mul => " * ",
                    ArithOp::Div => " / ",
                    ArithOp::Mod => " MOD ",
                };
                stack.push(Item::Expr(b, own + 1));
                stack.push(Item::Text(op));
                stack.push(Item::Expr(a, own));
            }
            Expr::Or(a, b) | Expr::Xor(a, b) | Expr::And(a, b) => {
                let op = match expr {
                    Expr::Or(..) => " or ",
                    Expr::Xor(..) => " xor ",
                    _ => " and ",
                };
                // Left-associative: the right operand needs parentheses at the same level.
                stack.push(Item::Expr(b, own + 1));
                stack.push(Item::Text(op));
                stack.push(Item::Expr(a, own));
            }
            Expr::Cmp(op, a, b) => {
                let op = match op {
                    CmpOp::Eq => " = ",
                    CmpOp::Ne => " <> ",
                    CmpOp::Lt => " < ",
                    CmpOp::Gt => " > ",
                    CmpOp::Le => " <= ",
                    CmpOp::Ge => " >= ",
                };
                // No chaining: both operands are unary.
                stack.push(Item::Expr(b, 5));
                stack.push(Item::Text(op));
                stack.push(Item::Expr(a, 5));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_are_canonical() {
        assert_eq!(duration_text(1500), "1S500MS");
        assert_eq!(duration_text(0), "0MS");
        assert_eq!(duration_text(-1000), "-1S");
        assert_eq!(duration_text(90_061_001), "1D1H1M1S1MS");
        assert_eq!(display_value(&Value::Time(300)), "T#300MS");
        assert_eq!(display_value(&Value::S5Time(0x2005)), "S5T#5S");
    }

    #[test]
    fn values_display_as_the_spec_says() {
        assert_eq!(display_value(&Value::Bool(true)), "TRUE");
        assert_eq!(display_value(&Value::Int(-5)), "-5");
        assert_eq!(display_value(&Value::Real(0.1)), "0.1");
        assert_eq!(display_value(&Value::Real(1.0)), "1.0");
        assert_eq!(display_value(&Value::Real(f32::NAN)), "NaN");
        assert_eq!(display_value(&Value::OpState(7)), "Holding");
        assert_eq!(display_value(&Value::Date(0)), "D#1990-01-01");
        assert_eq!(
            display_value(&Value::Date(366 + 365 * 2 + 59)),
            "D#1993-03-01"
        );
        assert_eq!(
            display_value(&Value::TimeOfDay(3_723_004)),
            "TOD#1:02:03.004"
        );
        assert_eq!(
            values_text(&[
                ("A".into(), Value::Bool(false)),
                ("MW10".into(), Value::Int(3))
            ]),
            "A = FALSE, MW10 = 3"
        );
    }

    #[test]
    fn expressions_print_with_needed_parentheses_only() {
        use crate::program::{Path, PathKind, Place};
        use crate::value::Ty;
        let read = |name: &str| {
            Box::new(Expr::Read(Path {
                text: name.into(),
                ty: Ty::Bool,
                kind: PathKind::Place(Place::Cell(0)),
            }))
        };
        let e = Expr::And(
            Box::new(Expr::Or(read("a"), read("b"))),
            Box::new(Expr::Not(Box::new(Expr::Cmp(
                CmpOp::Eq,
                read("C.state"),
                Box::new(Expr::Const(Value::OpState(8))),
            )))),
        );
        assert_eq!(expr_text(&e), "(a or b) and not (C.state = Held)");
        let e = Expr::Or(Box::new(Expr::Or(read("a"), read("b"))), read("c"));
        assert_eq!(expr_text(&e), "a or b or c");
        let e = Expr::Or(read("a"), Box::new(Expr::Or(read("b"), read("c"))));
        assert_eq!(expr_text(&e), "a or (b or c)");
    }
}

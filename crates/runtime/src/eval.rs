//! Evaluation of chart and test expressions (`runtime.md` §4.7, §5.3).
//!
//! Evaluation is iterative (an explicit work stack), so the depth of an expression costs heap,
//! not call stack. Every path of an expression is read, also where the result is already
//! decided: reads have no effect a test could observe.

use std::cmp::Ordering;

use crate::machine::{Fault, Machine};
use crate::program::{
    ArithOp, CmpOp, Expr, Path, PathKind, Predef, Program, SfcFlag, StepIdx, StepMember,
};
use crate::value::{Ty, Value};

/// What an expression can see besides memory: chart and step state.
pub trait Env {
    /// An `SFC.` flag of the chart whose code is running (FALSE outside a chart).
    fn sfc_flag(&self, flag: SfcFlag) -> bool;
    /// The operating state number (§4.2) of chart `chart`.
    fn chart_state(&self, chart: u32) -> u8;
    /// `Chart.Seq.Step[.X]`, `.T` (TIME), `.error`.
    fn step(&self, chart: u32, sequencer: u32, step: StepIdx, member: StepMember) -> Value;
}

/// An environment with no chart: flags FALSE, every chart Ready, every step inactive.
pub struct NoCharts;

impl Env for NoCharts {
    fn sfc_flag(&self, _: SfcFlag) -> bool {
        false
    }
    fn chart_state(&self, _: u32) -> u8 {
        crate::program::OpState::Ready as u8
    }
    fn step(&self, _: u32, _: u32, _: StepIdx, member: StepMember) -> Value {
        match member {
            StepMember::Time => Value::Time(0),
            StepMember::Active | StepMember::Error => Value::Bool(false),
        }
    }
}

enum Work<'a> {
    Visit(&'a Expr),
    Apply(&'a Expr),
}

/// Evaluates an expression.
pub fn eval(
    expr: &Expr,
    m: &mut Machine,
    program: &Program,
    env: &dyn Env,
) -> Result<Value, Fault> {
    let mut work = vec![Work::Visit(expr)];
    let mut values: Vec<Value> = Vec::new();
    while let Some(item) = work.pop() {
        match item {
            Work::Visit(e) => match e {
                Expr::Const(v) => values.push(v.clone()),
                Expr::Read(p) => values.push(read_path(p, m, program, env)?),
                Expr::Not(a) | Expr::Neg(a) => {
                    work.push(Work::Apply(e));
                    work.push(Work::Visit(a));
                }
                Expr::And(a, b)
                | Expr::Or(a, b)
                | Expr::Xor(a, b)
                | Expr::Cmp(_, a, b)
                | Expr::Arith(_, a, b) => {
                    work.push(Work::Apply(e));
                    work.push(Work::Visit(b));
                    work.push(Work::Visit(a));
                }
            },
            Work::Apply(e) => {
                let v = match e {
                    Expr::Not(_) => {
                        let a = values.pop().unwrap_or(Value::Bool(false));
                        Value::Bool(!truth(&a))
                    }
                    Expr::Neg(_) => neg(values.pop().unwrap_or(Value::Int(0))),
                    _ => {
                        let b = values.pop().unwrap_or(Value::Bool(false));
                        let a = values.pop().unwrap_or(Value::Bool(false));
                        match e {
                            Expr::And(..) => Value::Bool(truth(&a) && truth(&b)),
                            Expr::Or(..) => Value::Bool(truth(&a) || truth(&b)),
                            Expr::Xor(..) => Value::Bool(truth(&a) != truth(&b)),
                            Expr::Cmp(op, ..) => Value::Bool(compare(*op, &a, &b)),
                            Expr::Arith(op, ..) => arith(*op, a, b)?,
                            // Leaves are never scheduled for `Apply`.
                            _ => a,
                        }
                    }
                };
                values.push(v);
            }
        }
    }
    Ok(values.pop().unwrap_or(Value::Bool(false)))
}

/// Evaluates a condition: a BOOL expression (the lowering checked the type; anything else
/// counts as TRUE when its pattern is not zero).
pub fn eval_bool(
    expr: &Expr,
    m: &mut Machine,
    program: &Program,
    env: &dyn Env,
) -> Result<bool, Fault> {
    Ok(truth(&eval(expr, m, program, env)?))
}

/// The truth of a value: a BOOL as it is, another value when its pattern is not zero.
pub fn truth(v: &Value) -> bool {
    match v {
        Value::Bool(b) => *b,
        Value::String(s) => !s.is_empty(),
        Value::DateAndTime(b) => b.iter().any(|x| *x != 0),
        Value::OpState(_) => true,
        other => other.to_bits().is_some_and(|x| x != 0),
    }
}

/// Reads a path.
pub fn read_path(
    path: &Path,
    m: &mut Machine,
    program: &Program,
    env: &dyn Env,
) -> Result<Value, Fault> {
    Ok(match &path.kind {
        PathKind::Place(place) => m.read_value(place, path.ty)?,
        PathKind::InstState {
            group,
            instance,
            previous,
        } => {
            let predef = if *previous {
                Predef::PreviousState
            } else {
                Predef::CurrentState
            };
            let place = program
                .groups
                .get(*group as usize)
                .and_then(|g| g.instances.get(*instance as usize))
                .and_then(|i| i.binding.get(predef.var() as usize));
            match place {
                Some(place) => m.read_value(place, Ty::Word)?,
                None => Value::Word(0),
            }
        }
        PathKind::Sfc(flag) => Value::Bool(env.sfc_flag(*flag)),
        PathKind::ChartState { chart } => Value::OpState(env.chart_state(*chart)),
        PathKind::Step {
            chart,
            sequencer,
            step,
            member,
        } => env.step(*chart, *sequencer, *step, *member),
        PathKind::Stub { block, param } => match m.stub(*block, param) {
            Some(v) => v.clone(),
            None => Value::zero(path.ty),
        },
        PathKind::Calls { block } => Value::Dint(m.calls(*block).min(i32::MAX as u32) as i32),
    })
}

/// Each path of an expression once (by its text), in first-appearance order, left to right:
/// what `{values}` of HG9901/HG9902 lists.
pub fn paths(expr: &Expr) -> Vec<&Path> {
    let mut out: Vec<&Path> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut stack = vec![expr];
    while let Some(e) = stack.pop() {
        match e {
            Expr::Const(_) => {}
            Expr::Read(p) => {
                if seen.insert(p.text.as_str()) {
                    out.push(p);
                }
            }
            Expr::Not(a) | Expr::Neg(a) => stack.push(a),
            Expr::And(a, b)
            | Expr::Or(a, b)
            | Expr::Xor(a, b)
            | Expr::Cmp(_, a, b)
            | Expr::Arith(_, a, b) => {
                stack.push(b);
                stack.push(a);
            }
        }
    }
    out
}

/// [`paths`] with the current value of each path.
pub fn path_values(
    expr: &Expr,
    m: &mut Machine,
    program: &Program,
    env: &dyn Env,
) -> Result<Vec<(String, Value)>, Fault> {
    paths(expr)
        .into_iter()
        .map(|p| Ok((p.text.clone(), read_path(p, m, program, env)?)))
        .collect()
}

/// The duration in ms of an S5TIME pattern (§3.3): digits · base, bits 14–15 ignored.
pub fn s5time_ms(bits: u16) -> i64 {
    let base = [10i64, 100, 1000, 10000][usize::from((bits >> 12) & 3)];
    let digit = |shift: u16| i64::from((bits >> shift) & 0xF);
    (digit(8) * 100 + digit(4) * 10 + digit(0)) * base
}

/// The S5TIME pattern of `S5T#ms` (§3.3): the smallest base with ms ≤ 999·base, digits
/// rounded half to even; clamped to the largest value.
pub fn s5time_from_ms(ms: i64) -> u16 {
    let ms = ms.max(0);
    for (code, base) in [10i64, 100, 1000, 10000].into_iter().enumerate() {
        if ms <= 999 * base || code == 3 {
            let q = ms / base;
            let r = ms % base;
            let mut digits = if 2 * r > base || (2 * r == base && q % 2 == 1) {
                q + 1
            } else {
                q
            };
            if digits > 999 {
                digits = 999;
            }
            let bcd = ((digits / 100) << 8) | (((digits / 10) % 10) << 4) | (digits % 10);
            return ((code as u16) << 12) | bcd as u16;
        }
    }
    0
}

enum Key<'a> {
    Int(i64),
    Real(f64),
    Bytes(&'a [u8]),
}

fn key(v: &Value) -> Key<'_> {
    match v {
        Value::Bool(b) => Key::Int(i64::from(*b)),
        Value::Byte(x) | Value::Char(x) => Key::Int(i64::from(*x)),
        Value::Word(x) | Value::Date(x) => Key::Int(i64::from(*x)),
        Value::Dword(x) | Value::TimeOfDay(x) => Key::Int(i64::from(*x)),
        Value::Int(x) => Key::Int(i64::from(*x)),
        Value::Dint(x) | Value::Time(x) => Key::Int(i64::from(*x)),
        Value::Real(x) => Key::Real(f64::from(*x)),
        Value::S5Time(x) => Key::Int(s5time_ms(*x)),
        Value::DateAndTime(b) => Key::Bytes(b),
        Value::String(s) => Key::Bytes(s.as_bytes()),
        Value::OpState(n) => Key::Int(i64::from(*n)),
    }
}

/// The order of two values (§4.7); `None` when unordered (a NaN, or values of kinds that
/// cannot be compared).
pub fn order(a: &Value, b: &Value) -> Option<Ordering> {
    match (key(a), key(b)) {
        (Key::Int(x), Key::Int(y)) => Some(x.cmp(&y)),
        (Key::Real(x), Key::Real(y)) => x.partial_cmp(&y),
        (Key::Int(x), Key::Real(y)) => (x as f64).partial_cmp(&y),
        (Key::Real(x), Key::Int(y)) => x.partial_cmp(&(y as f64)),
        (Key::Bytes(x), Key::Bytes(y)) => Some(x.cmp(y)),
        _ => None,
    }
}

/// A comparison (§4.7): unsigned BYTE/WORD/DWORD, signed INT/DINT, IEEE REAL (an unordered
/// pair is only `<>`), TIME/TOD/DATE by value, CHAR by code, S5TIME by duration, STRING by
/// content, operating states by number.
pub fn compare(op: CmpOp, a: &Value, b: &Value) -> bool {
    match order(a, b) {
        None => op == CmpOp::Ne,
        Some(o) => match op {
            CmpOp::Eq => o == Ordering::Equal,
            CmpOp::Ne => o != Ordering::Equal,
            CmpOp::Lt => o == Ordering::Less,
            CmpOp::Gt => o == Ordering::Greater,
            CmpOp::Le => o != Ordering::Greater,
            CmpOp::Ge => o != Ordering::Less,
        },
    }
}

/// The integer value of an integer-like value (BOOL, BYTE…DINT, TIME, …), `None` for REAL,
/// STRING and the like: a `CASE` selector.
pub fn integer_of(v: &Value) -> Option<i64> {
    integer(v)
}

fn integer(v: &Value) -> Option<i64> {
    Some(match *v {
        Value::Bool(b) => i64::from(b),
        Value::Byte(x) | Value::Char(x) => i64::from(x),
        Value::Word(x) | Value::Date(x) => i64::from(x),
        Value::Dword(x) | Value::TimeOfDay(x) => i64::from(x),
        Value::Int(x) => i64::from(x),
        Value::Dint(x) | Value::Time(x) => i64::from(x),
        _ => return None,
    })
}

/// Converts a value to a type (chart statements, `set`): the lowering has checked it fits, so
/// this only changes the representation (an integer literal to the target's integer type or
/// REAL, a STRING to the target's length, TIME and S5TIME by duration). A value that does not
/// convert keeps its bit pattern, else becomes the type's zero.
pub fn convert(value: Value, ty: Ty) -> Value {
    match (value, ty) {
        (Value::String(s), Ty::String(n)) => {
            Value::String(s.chars().take(usize::from(n.max(1))).collect())
        }
        (Value::Char(c), Ty::String(_)) => Value::String(char::from(c).to_string()),
        (Value::String(s), Ty::Char) if s.chars().count() == 1 => {
            Value::Char(s.chars().next().map_or(0, |c| u32::from(c).min(255) as u8))
        }
        (v, t) if v.ty() == t => v,
        (v @ (Value::DateAndTime(_) | Value::OpState(_)), t) => {
            if v.ty() == t {
                v
            } else {
                Value::zero(t)
            }
        }
        (Value::Time(ms), Ty::S5Time) => Value::S5Time(s5time_from_ms(i64::from(ms))),
        (Value::S5Time(b), Ty::Time) => Value::Time(s5time_ms(b) as i32),
        (Value::Real(r), Ty::Real) => Value::Real(r),
        (v, Ty::Real) => match integer(&v) {
            Some(i) => Value::Real(i as f32),
            None => Value::zero(Ty::Real),
        },
        (v, t) => match integer(&v) {
            Some(i) if !matches!(v, Value::Real(_)) => match t {
                Ty::Bool | Ty::Timer | Ty::Counter => Value::Bool(i != 0),
                Ty::Byte => Value::Byte(i as u8),
                Ty::Char => Value::Char(i as u8),
                Ty::Word => Value::Word(i as u16),
                Ty::Date => Value::Date(i as u16),
                Ty::Int => Value::Int(i as i16),
                Ty::Dword => Value::Dword(i as u32),
                Ty::TimeOfDay => Value::TimeOfDay(i as u32),
                Ty::Dint => Value::Dint(i as i32),
                Ty::Time => Value::Time(i as i32),
                Ty::S5Time => Value::S5Time(i as u16),
                Ty::String(_) => Value::String(i.to_string()),
                Ty::Real | Ty::DateAndTime | Ty::OpState => Value::zero(t),
            },
            _ => v
                .to_bits()
                .and_then(|bits| Value::from_bits(t, bits))
                .unwrap_or_else(|| Value::zero(t)),
        },
    }
}

/// Unary minus (`docs/iec.md` §4): INT and DINT wrap around (`-(-32768) = -32768`), REAL and
/// TIME negate; another value is returned unchanged (the checker rejects it).
pub fn neg(v: Value) -> Value {
    match v {
        Value::Int(x) => Value::Int(x.wrapping_neg()),
        Value::Dint(x) => Value::Dint(x.wrapping_neg()),
        Value::Time(x) => Value::Time(x.wrapping_neg()),
        Value::Real(x) => Value::Real(-x),
        other => other,
    }
}

/// `a op b` (`docs/iec.md` §4). INT, DINT and TIME wrap around in their width (two's
/// complement); `/` truncates toward zero; `MOD` has the sign of the dividend; integer division
/// or `MOD` by zero (and `TIME / 0`) is a runtime fault. REAL is IEEE single precision
/// (`x / 0.0` is an infinity or NaN, no fault). `TIME * n` and `TIME / n` take an INT or DINT
/// `n`. Operands of different integer kinds are combined in the wider one (the lowering has
/// already adapted integer constants, so this only happens with hand-built programs).
pub fn arith(op: ArithOp, a: Value, b: Value) -> Result<Value, Fault> {
    if let (Value::Real(x), Value::Real(y)) = (&a, &b) {
        let (x, y) = (*x, *y);
        return Ok(Value::Real(match op {
            ArithOp::Add => x + y,
            ArithOp::Sub => x - y,
            ArithOp::Mul => x * y,
            ArithOp::Div => x / y,
            // the checker rejects REAL MOD; IEEE remainder with the sign of the dividend
            ArithOp::Mod => x % y,
        }));
    }
    if matches!(a, Value::Real(_)) || matches!(b, Value::Real(_)) {
        let x = real_of(&a);
        let y = real_of(&b);
        return arith(op, Value::Real(x), Value::Real(y));
    }
    // the width of the result: TIME if either is TIME, else DINT if either is DINT, else INT
    let time = matches!(a, Value::Time(_)) || matches!(b, Value::Time(_));
    let wide = time
        || matches!(a, Value::Dint(_) | Value::Dword(_))
        || matches!(b, Value::Dint(_) | Value::Dword(_));
    let (Some(x), Some(y)) = (integer(&a), integer(&b)) else {
        return Ok(a);
    };
    let r = match op {
        ArithOp::Add => x.wrapping_add(y),
        ArithOp::Sub => x.wrapping_sub(y),
        ArithOp::Mul => x.wrapping_mul(y),
        ArithOp::Div | ArithOp::Mod => {
            if y == 0 {
                let what = if op == ArithOp::Div {
                    "division"
                } else {
                    "MOD"
                };
                return Err(Fault::new(format!("{what} by zero")));
            }
            // operands are at most 32 bits wide, so the i64 quotient cannot overflow; it is
            // wrapped to the width below (DINT -2^31 / -1 = -2^31, as on the PLC)
            if op == ArithOp::Div { x / y } else { x % y }
        }
    };
    Ok(if time {
        Value::Time(r as i32)
    } else if wide {
        Value::Dint(r as i32)
    } else {
        Value::Int(r as i16)
    })
}

fn real_of(v: &Value) -> f32 {
    match v {
        Value::Real(x) => *x,
        other => integer(other).map_or(0.0, |i| i as f32),
    }
}

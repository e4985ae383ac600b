//! Evaluation of chart and test expressions (`runtime.md` §4.7, §5.3).

use crate::machine::{Fault, Machine};
use crate::program::{Expr, Path, SfcFlag, StepIdx, StepMember};
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

/// Evaluates an expression.
pub fn eval(expr: &Expr, m: &mut Machine, env: &dyn Env) -> Result<Value, Fault> {
    let _ = (expr, m, env);
    todo!("eval: §4.7")
}

/// Reads a path.
pub fn read_path(path: &Path, m: &mut Machine, env: &dyn Env) -> Result<Value, Fault> {
    let _ = (path, m, env);
    todo!()
}

/// Converts a value to a type (chart statements, `set`): the lowering has checked it fits.
pub fn convert(value: Value, ty: Ty) -> Value {
    let _ = ty;
    value
}

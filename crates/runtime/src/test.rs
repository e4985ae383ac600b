//! The test runner (`runtime.md` §5.2): executes a test's statements on a fresh simulation and
//! reports failures, faults and the trace.

use crate::program::{Origin, Program};
use crate::trace::Trace;
use crate::value::Value;

/// How a test ended (`runtime.md` §7: passed, failed = HG9901/HG9902, error = HG9903/HG9904).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    Failed,
    Error,
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

/// Runs the program's test on a fresh machine. `None` when cancelled. A runtime fault is an
/// HG9903 failure in the result.
pub fn run(program: &Program, options: &RunOptions<'_>) -> Option<TestRun> {
    let _ = (program, options);
    todo!("runner: §5.2")
}

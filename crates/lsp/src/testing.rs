//! Running `test` items and turning the results into the objects of `runtime.md` §7, shared
//! by `higraph-lsp test` (`cli/test.rs`) and the language server (`higraph.runTest`,
//! `higraph/simulate`).
//!
//! [`run_test`] lowers one test with the analysis and runs it with `higraph_runtime::test::run`;
//! its [`TestResult`] holds the failures as [`Diagnostic`]s placed in files (HG9901–HG9904),
//! so they render like any other diagnostic. [`Positions`] converts ranges to the JSON
//! positions of `diagnostics.md` §4.1 (0-based lines, UTF-16 columns); [`test_json`] builds a
//! test object of `--format json` and [`write_trace`] the JSON trace; [`vcd`] the VCD file.
//!
//! Decisions: a test's `range` in the JSON outputs is the range of its name (where HG9904
//! points and the code lens sits); an HG9904 failure has cycle 0, time 0 and no values.

use std::collections::HashMap;
use std::time::{Duration, Instant};

use higraph_analysis::lower::TestItem;
use higraph_analysis::{
    Analysis, Cancellable, Code, Diagnostic, LineIndex, RelatedInfo, Severity, TextRange,
};
use higraph_runtime::program::Origin;
use higraph_runtime::test::{self as runner, Outcome, RunOptions};
use higraph_runtime::trace::{
    FailureRecord, JsonPosition, JsonRange, OrderedMap, Trace, json_value,
};
use higraph_runtime::{Program, Value};
use serde::Serialize;

/// One failure of a test, placed in a file.
#[derive(Debug, Clone)]
pub(crate) struct TestFailure {
    /// The workspace path of the file the diagnostic is in.
    pub file: String,
    /// HG9901–HG9904, severity error; related locations use the analysis's file ids.
    pub diagnostic: Diagnostic,
    pub cycle: u64,
    pub time_ms: u64,
    pub values: Vec<(String, Value)>,
}

/// The result of running one test.
#[derive(Debug, Clone)]
pub(crate) struct TestResult {
    pub item: TestItem,
    pub outcome: Outcome,
    pub cycles: u64,
    pub time_ms: u64,
    pub failures: Vec<TestFailure>,
    /// The JSON trace's record (with `file` filled in), when asked for and the test ran.
    pub trace: Option<Trace>,
    /// The program that ran (for the VCD), when a trace was asked for and the test ran.
    pub program: Option<Program>,
    /// Wall-clock time of lowering and running.
    pub wall: Duration,
}

/// Lowers and runs one test. `Ok(None)` when `cancelled` answered `true` between two cycles;
/// `Err` when the analysis was cancelled.
pub(crate) fn run_test(
    analysis: &Analysis,
    item: &TestItem,
    trace: bool,
    cancelled: &dyn Fn() -> bool,
) -> Cancellable<Option<TestResult>> {
    let started = Instant::now();
    let lowered = match analysis.lower_test(&item.path, &item.name)? {
        Ok(lowered) => lowered,
        Err(diagnostic) => {
            return Ok(Some(TestResult {
                item: item.clone(),
                outcome: Outcome::Error,
                cycles: 0,
                time_ms: 0,
                failures: vec![TestFailure {
                    file: item.path.clone(),
                    diagnostic,
                    cycle: 0,
                    time_ms: 0,
                    values: Vec::new(),
                }],
                trace: None,
                program: None,
                wall: started.elapsed(),
            }));
        }
    };
    let options = RunOptions { trace, cancelled };
    let Some(run) = runner::run(&lowered.program, &options) else {
        return Ok(None);
    };
    let file_ids: HashMap<String, u32> = analysis
        .files()
        .into_iter()
        .enumerate()
        .map(|(i, f)| (f.path, i as u32))
        .collect();
    // Where an origin is; an origin the lowering does not know falls back to the test name.
    let place = |origin: Origin| -> (String, TextRange) {
        lowered
            .origin(origin)
            .cloned()
            .unwrap_or_else(|| (item.path.clone(), item.name_range))
    };
    let failures: Vec<TestFailure> = run
        .failures
        .iter()
        .map(|failure| {
            let (file, range) = place(failure.origin);
            let message = if failure.code == "HG9902" {
                as_written(analysis, &file, range, &failure.message)
            } else {
                failure.message.clone()
            };
            let mut diagnostic =
                Diagnostic::new(Code::new(failure.code), Severity::Error, range, message);
            if failure.code == "HG9903"
                && failure.origin != failure.statement
                && failure.statement != Origin::NONE
            {
                let (statement_file, statement_range) = place(failure.statement);
                if let Some(&id) = file_ids.get(&statement_file) {
                    diagnostic.related.push(RelatedInfo {
                        file: higraph_analysis::FileId(id),
                        range: statement_range,
                        message: "the test statement that was running".into(),
                    });
                }
            }
            TestFailure {
                file,
                diagnostic,
                cycle: failure.cycle,
                time_ms: failure.time_ms,
                values: failure.values.clone(),
            }
        })
        .collect();
    let mut result = TestResult {
        item: item.clone(),
        outcome: run.outcome,
        cycles: run.cycles,
        time_ms: run.time_ms,
        failures,
        trace: run.trace,
        program: None,
        wall: Duration::ZERO,
    };
    if result.trace.is_some() {
        let mut positions = Positions::new(analysis);
        let failures = result
            .failures
            .iter()
            .map(|f| failure_json(f, &mut positions))
            .collect();
        if let Some(trace) = &mut result.trace {
            trace.file = item.path.clone();
            trace.failures = failures;
        }
        result.program = Some(lowered.program);
    }
    result.wall = started.elapsed();
    Ok(Some(result))
}

/// HG9902's `'{expr}'` as the user wrote it: the runner prints the lowered expression back
/// (addresses without spaces, constants in decimal); here the text of the expression's range,
/// white space (line breaks included) collapsed to single spaces, takes its place.
fn as_written(analysis: &Analysis, file: &str, range: TextRange, message: &str) -> String {
    const REST: &str = "' did not hold within ";
    let Some(end) = message.find(REST).filter(|_| message.starts_with('\'')) else {
        return message.to_string();
    };
    let Some(contents) = analysis.file_contents(file) else {
        return message.to_string();
    };
    let Some(text) = contents.text().get(std::ops::Range::<usize>::from(range)) else {
        return message.to_string();
    };
    let written = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if written.is_empty() {
        return message.to_string();
    }
    format!("'{written}{}", &message[end..])
}

/// Converts byte ranges of workspace files to JSON ranges (`diagnostics.md` §4.1), one line
/// index per file.
pub(crate) struct Positions<'a> {
    analysis: &'a Analysis,
    indexes: HashMap<String, Option<LineIndex>>,
}

impl<'a> Positions<'a> {
    pub(crate) fn new(analysis: &'a Analysis) -> Positions<'a> {
        Positions {
            analysis,
            indexes: HashMap::new(),
        }
    }

    /// 0-based lines, UTF-16 columns.
    pub(crate) fn range(&mut self, file: &str, range: TextRange) -> JsonRange {
        let analysis = self.analysis;
        let index = self.indexes.entry(file.to_string()).or_insert_with(|| {
            analysis
                .file_contents(file)
                .map(|contents| LineIndex::new(contents.text()))
        });
        let position = |offset| {
            index.as_ref().map_or(JsonPosition::default(), |index| {
                let p = index.utf16_position(offset);
                JsonPosition {
                    line: p.line,
                    character: p.column,
                }
            })
        };
        JsonRange {
            start: position(range.start()),
            end: position(range.end()),
        }
    }
}

/// One failure object of `--format json` and of the trace (§7).
pub(crate) fn failure_json(failure: &TestFailure, positions: &mut Positions<'_>) -> FailureRecord {
    let mut values = OrderedMap::default();
    for (path, value) in &failure.values {
        values.insert(path.clone(), json_value(value));
    }
    FailureRecord {
        code: failure.diagnostic.code.as_str().to_string(),
        message: failure.diagnostic.message.clone(),
        file: failure.file.clone(),
        range: positions.range(&failure.file, failure.diagnostic.range),
        cycle: failure.cycle,
        time_ms: failure.time_ms,
        values,
    }
}

/// One test object `T` of `--format json` (§7); also what `higraph.runTest` returns.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct TestJson {
    pub name: String,
    pub file: String,
    pub range: JsonRange,
    pub result: &'static str,
    pub cycles: u64,
    pub time_ms: u64,
    pub failures: Vec<FailureRecord>,
}

pub(crate) fn test_json(result: &TestResult, positions: &mut Positions<'_>) -> TestJson {
    TestJson {
        name: result.item.name.clone(),
        file: result.item.path.clone(),
        range: positions.range(&result.item.path, result.item.name_range),
        result: result.outcome.as_str(),
        cycles: result.cycles,
        time_ms: result.time_ms,
        failures: result
            .failures
            .iter()
            .map(|f| failure_json(f, positions))
            .collect(),
    }
}

/// The summary of `--format json`.
#[derive(Debug, Clone, Copy, Serialize, Default, PartialEq, Eq)]
pub(crate) struct SummaryJson {
    pub passed: usize,
    pub failed: usize,
    pub errors: usize,
    pub filtered_out: usize,
}

/// The whole `--format json` object.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct OutputJson {
    pub version: u32,
    pub tests: Vec<TestJson>,
    pub summary: SummaryJson,
}

/// The JSON trace of §7 (also the result of `higraph/simulate`), members in the order of §7,
/// pretty-printed with two-space indentation and a final line break, written to `out` as it
/// is serialised.
pub(crate) fn write_trace(out: &mut impl std::io::Write, trace: &Trace) -> std::io::Result<()> {
    serde_json::to_writer_pretty(&mut *out, trace)?;
    out.write_all(b"\n")
}

/// The VCD file of a run with a trace.
pub(crate) fn vcd(result: &TestResult) -> Option<String> {
    let trace = result.trace.as_ref()?;
    let program = result.program.as_ref()?;
    Some(higraph_runtime::vcd::write(
        program,
        trace,
        env!("CARGO_PKG_VERSION"),
    ))
}

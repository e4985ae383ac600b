//! Tests in the editor (`runtime.md` §8): the code lens on each test header, the command
//! `higraph.runTest`, the custom requests `higraph/simulate` (the JSON trace of a run, for the
//! preview's player) and `higraph/tests` (every test of the workspace, for an editor's test
//! explorer).
//!
//! A run lowers the test on the request's snapshot (`Analysis::lower_test`) and executes it
//! with `higraph_runtime::test::run`, off the message loop like every request. The runner asks
//! between cycles whether to stop: when the client cancelled the request or the world wants to
//! write, so a run never holds up an edit. The result is the test's object of
//! `higraph-lsp test --format json`; its failures also become LSP diagnostics, which the world
//! publishes with the file's own until the workspace changes ([`super::state`]).

use std::collections::HashMap;
use std::sync::Arc;

use higraph_analysis::lower::{LoweredTest, TestItem};
use higraph_analysis::{PositionEncoding, TextRange};
use higraph_runtime::program::Origin;
use higraph_runtime::test::{self as runner, Failure, Outcome, RunOptions};
use serde_json::{Map, Value as Json, json};
use tower_lsp_server::ls_types::{self as lsp, Uri};

use super::convert;
use super::handlers::{HandlerError, HandlerResult};
use super::state::Snapshot;

/// The command of the test lenses; the only command the server executes.
pub(crate) const RUN_TEST: &str = "higraph.runTest";

/// Identifies a test: its file's workspace path and its name in upper case (test names are
/// case-insensitive like every name).
pub(crate) type TestKey = (String, String);

/// The key of a test.
pub(crate) fn test_key(path: &str, name: &str) -> TestKey {
    (path.to_owned(), name.to_ascii_uppercase())
}

/// What the server remembers of a test's last run (until the workspace changes).
#[derive(Debug, Clone)]
pub(crate) struct TestRecord {
    pub passed: bool,
    /// The failures of the run (HG9901–HG9904).
    pub failures: usize,
    /// The failures as diagnostics, by workspace path of the file they are in.
    pub diagnostics: Vec<(String, lsp::Diagnostic)>,
}

/// The last runs, shared by the world and its snapshots.
pub(crate) type TestRecords = Arc<HashMap<TestKey, TestRecord>>;

/// The argument of `higraph.runTest`, and the parameters of `higraph/simulate` (where the URI
/// may be left out: the first test of that name in workspace order).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
pub(crate) struct TestParams {
    pub name: String,
    #[serde(default)]
    pub uri: Option<Uri>,
}

/// The outcome of `higraph.runTest` for the client (the JSON object) and the world (the
/// record).
pub(crate) struct RunTestOutcome {
    pub json: Json,
    pub key: TestKey,
    pub record: TestRecord,
    /// The contents generation the run saw (the record is dropped if files changed since).
    pub generation: u64,
}

/// `textDocument/codeLens`: `▶ Run test` on each test header, with the last result.
pub(crate) fn code_lens(
    snapshot: &Snapshot,
    params: lsp::CodeLensParams,
) -> HandlerResult<Option<Vec<lsp::CodeLens>>> {
    let Some(path) = snapshot.path(&params.text_document.uri) else {
        return Ok(None);
    };
    let Some(index) = snapshot.line_index(&path) else {
        return Ok(None);
    };
    let tests = snapshot.analysis.tests()?;
    let lenses = tests
        .iter()
        .filter(|test| test.path == path)
        .map(|test| {
            let title = match snapshot.test_record(&test_key(&path, &test.name)) {
                None => "▶ Run test".to_owned(),
                Some(record) if record.passed => "▶ Run test — passed".to_owned(),
                Some(record) => format!("▶ Run test — failed ({})", record.failures),
            };
            let header = TextRange::new(test.range.start(), test.name_range.end());
            lsp::CodeLens {
                range: convert::range(&index, header, snapshot.encoding),
                command: Some(lsp::Command {
                    title,
                    command: RUN_TEST.to_owned(),
                    arguments: Some(vec![json!({
                        "uri": params.text_document.uri,
                        "name": test.name,
                    })]),
                }),
                data: None,
            }
        })
        .collect();
    Ok(Some(lenses))
}

/// Result of `higraph/tests`.
#[derive(Debug, serde::Serialize)]
pub(crate) struct TestList {
    pub tests: Vec<TestEntry>,
}

/// One test of `higraph/tests`: its name, file and the range of the whole item.
#[derive(Debug, serde::Serialize)]
pub(crate) struct TestEntry {
    pub name: String,
    pub uri: Uri,
    pub range: lsp::Range,
    /// The range of the name after `test`.
    #[serde(rename = "nameRange")]
    pub name_range: lsp::Range,
}

/// Parameters of `higraph/tests` (none are needed; any object is accepted).
#[derive(Debug, serde::Deserialize)]
pub(crate) struct TestListParams {}

/// `higraph/tests`: every test of the workspace, in workspace order.
pub(crate) fn list(snapshot: &Snapshot, _: Option<TestListParams>) -> HandlerResult<TestList> {
    let tests = snapshot.analysis.tests()?;
    let tests = tests
        .iter()
        .filter_map(|test| {
            let index = snapshot.line_index(&test.path)?;
            Some(TestEntry {
                name: test.name.clone(),
                uri: snapshot.uri(&test.path)?,
                range: convert::range(&index, test.range, snapshot.encoding),
                name_range: convert::range(&index, test.name_range, snapshot.encoding),
            })
        })
        .collect();
    Ok(TestList { tests })
}

/// The test a request names: in the URI's file when there is one, else the first of that
/// name in workspace order.
fn find_test(snapshot: &Snapshot, params: &TestParams) -> HandlerResult<TestItem> {
    let path = match &params.uri {
        Some(uri) => Some(snapshot.path(uri).ok_or_else(|| {
            HandlerError::Failed(format!("{} is not a file of the workspace", uri.as_str()))
        })?),
        None => None,
    };
    let tests = snapshot.analysis.tests()?;
    tests
        .into_iter()
        .find(|test| {
            test.name.eq_ignore_ascii_case(&params.name)
                && path.as_ref().is_none_or(|path| test.path == *path)
        })
        .ok_or_else(|| {
            HandlerError::Failed(match &path {
                Some(path) => format!("there is no test named '{}' in {path}", params.name),
                None => format!("there is no test named '{}'", params.name),
            })
        })
}

/// Whether a run should stop: the client cancelled the request, or the world wants to write.
fn should_stop(snapshot: &Snapshot) -> bool {
    snapshot
        .analysis
        .check_cancelled(&|| snapshot.is_cancelled())
        .is_err()
}

/// A run: the lowered test and the runner's result, or the HG9904 that kept it from running.
enum Ran {
    Run(Box<LoweredTest>, runner::TestRun),
    CannotRun(higraph_analysis::Diagnostic),
}

fn run(snapshot: &Snapshot, test: &TestItem, trace: bool) -> HandlerResult<Ran> {
    let lowered = match snapshot.analysis.lower_test(&test.path, &test.name)? {
        Ok(lowered) => lowered,
        Err(diagnostic) => return Ok(Ran::CannotRun(diagnostic)),
    };
    if should_stop(snapshot) {
        return Err(HandlerError::Cancelled);
    }
    let stop = || should_stop(snapshot);
    let options = RunOptions {
        trace,
        cancelled: &stop,
    };
    match runner::run(&lowered.program, &options) {
        Some(result) => Ok(Ran::Run(Box::new(lowered), result)),
        None => Err(HandlerError::Cancelled),
    }
}

/// `workspace/executeCommand` `higraph.runTest`: runs the test and answers its
/// `--format json` object.
pub(crate) fn run_test(snapshot: &Snapshot, params: TestParams) -> HandlerResult<RunTestOutcome> {
    let test = find_test(snapshot, &params)?;
    let ran = run(snapshot, &test, false)?;
    let report = Report::new(snapshot, &test, &ran);
    Ok(RunTestOutcome {
        json: report.json,
        key: test_key(&test.path, &test.name),
        record: TestRecord {
            passed: report.outcome == Outcome::Passed,
            failures: report.diagnostics.len(),
            diagnostics: report.diagnostics,
        },
        generation: snapshot.generation(),
    })
}

/// `higraph/simulate`: runs the test with a trace and answers the JSON trace.
pub(crate) fn simulate(snapshot: &Snapshot, params: TestParams) -> HandlerResult<Json> {
    let test = find_test(snapshot, &params)?;
    let ran = run(snapshot, &test, true)?;
    let report = Report::new(snapshot, &test, &ran);
    match ran {
        Ran::CannotRun(diagnostic) => Err(HandlerError::Failed(diagnostic.message)),
        Ran::Run(_, result) => {
            let Some(mut trace) = result.trace else {
                return Err(HandlerError::Failed(format!(
                    "the run of test '{}' gave no trace",
                    test.name
                )));
            };
            trace.file = test.path.clone();
            trace.failures = report.failures;
            serde_json::to_value(&trace)
                .map_err(|error| HandlerError::Failed(format!("cannot write the trace: {error}")))
        }
    }
}

/// A run as the client sees it: the JSON object, the failures' JSON and their diagnostics.
struct Report {
    outcome: Outcome,
    json: Json,
    failures: Vec<Json>,
    diagnostics: Vec<(String, lsp::Diagnostic)>,
}

impl Report {
    fn new(snapshot: &Snapshot, test: &TestItem, ran: &Ran) -> Report {
        let mut failures = Vec::new();
        let mut diagnostics = Vec::new();
        let (outcome, cycles, time_ms) = match ran {
            Ran::CannotRun(diagnostic) => {
                failures.push(json!({
                    "code": diagnostic.code.as_str(),
                    "message": diagnostic.message,
                    "file": test.path,
                    "range": json_range(snapshot, &test.path, diagnostic.range),
                    "cycle": 0,
                    "time_ms": 0,
                    "values": {},
                }));
                if let Some(index) = snapshot.line_index(&test.path) {
                    let files = snapshot.analysis.files();
                    let converted = convert::diagnostic(
                        diagnostic,
                        &index,
                        snapshot.encoding,
                        |file, range| location(snapshot, &files.get(file.0 as usize)?.path, range),
                    );
                    diagnostics.push((test.path.clone(), converted));
                }
                (Outcome::Error, 0, 0)
            }
            Ran::Run(lowered, result) => {
                for failure in &result.failures {
                    let place = lowered.origin(failure.origin).cloned();
                    let (file, range) = place.clone().unwrap_or_else(|| {
                        // A failure without a place (none is expected): the test's name.
                        (test.path.clone(), test.name_range)
                    });
                    failures.push(failure_json(snapshot, failure, &file, range));
                    if let Some(diagnostic) =
                        failure_diagnostic(snapshot, lowered, failure, &file, range)
                    {
                        diagnostics.push((file, diagnostic));
                    }
                }
                (result.outcome, result.cycles, result.time_ms)
            }
        };
        let json = json!({
            "name": test.name,
            "file": test.path,
            "range": json_range(snapshot, &test.path, test.range),
            "result": outcome_name(outcome),
            "cycles": cycles,
            "time_ms": time_ms,
            "failures": failures,
        });
        Report {
            outcome,
            json,
            failures,
            diagnostics,
        }
    }
}

fn outcome_name(outcome: Outcome) -> &'static str {
    match outcome {
        Outcome::Passed => "passed",
        Outcome::Failed => "failed",
        Outcome::Error => "error",
    }
}

/// A range as `check --format json` writes it: LSP conventions, UTF-16 columns.
fn json_range(snapshot: &Snapshot, path: &str, range: TextRange) -> Json {
    let range = match snapshot.line_index(path) {
        Some(index) => convert::range(&index, range, PositionEncoding::Utf16),
        None => lsp::Range::default(),
    };
    serde_json::to_value(range).unwrap_or(Json::Null)
}

fn failure_json(snapshot: &Snapshot, failure: &Failure, file: &str, range: TextRange) -> Json {
    let values: Map<String, Json> = failure
        .values
        .iter()
        .map(|(path, value)| (path.clone(), higraph_runtime::trace::json_value(value)))
        .collect();
    json!({
        "code": failure.code,
        "message": failure.message,
        "file": file,
        "range": json_range(snapshot, file, range),
        "cycle": failure.cycle,
        "time_ms": failure.time_ms,
        "values": values,
    })
}

/// The diagnostic of a failure, with the running test statement as related location of a
/// fault inside STL.
fn failure_diagnostic(
    snapshot: &Snapshot,
    lowered: &LoweredTest,
    failure: &Failure,
    file: &str,
    range: TextRange,
) -> Option<lsp::Diagnostic> {
    let index = snapshot.line_index(file)?;
    let related: Vec<lsp::DiagnosticRelatedInformation> = (failure.statement != Origin::NONE
        && failure.statement != failure.origin)
        .then(|| lowered.origin(failure.statement))
        .flatten()
        .and_then(|(path, range)| location(snapshot, path, *range))
        .map(|location| lsp::DiagnosticRelatedInformation {
            location,
            message: "the running test statement".to_owned(),
        })
        .into_iter()
        .collect();
    Some(lsp::Diagnostic {
        range: convert::range(&index, range, snapshot.encoding),
        severity: Some(lsp::DiagnosticSeverity::ERROR),
        code: Some(lsp::NumberOrString::String(failure.code.to_owned())),
        code_description: None,
        source: Some(convert::DIAGNOSTIC_SOURCE.to_owned()),
        message: failure.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        tags: None,
        data: None,
    })
}

fn location(snapshot: &Snapshot, path: &str, range: TextRange) -> Option<lsp::Location> {
    let index = snapshot.line_index(path)?;
    Some(lsp::Location::new(
        snapshot.uri(path)?,
        convert::range(&index, range, snapshot.encoding),
    ))
}

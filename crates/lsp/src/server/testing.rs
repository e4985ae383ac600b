//! Tests in the editor (`runtime.md` §8): the code lens on each test header, the command
//! `higraph.runTest`, the custom requests `higraph/simulate` (the JSON trace of a run, for the
//! preview's player) and `higraph/tests` (every test of the workspace, for an editor's test
//! explorer).
//!
//! A run lowers and runs the test on the request's snapshot with `crate::testing` (the code
//! `higraph-lsp test` runs), off the message loop like every request. The runner asks between
//! cycles whether to stop: when the client cancelled the request or the world wants to write,
//! so a run never holds up an edit. The result is the test's object of
//! `higraph-lsp test --format json`; its failures also become LSP diagnostics, which the world
//! publishes with the file's own until the workspace changes ([`super::state`]).

use std::collections::HashMap;
use std::sync::Arc;

use higraph_analysis::TextRange;
use higraph_analysis::lower::TestItem;
use higraph_runtime::test::Outcome;
use serde_json::{Value as Json, json};
use tower_lsp_server::ls_types::{self as lsp, Uri};

use super::convert;
use super::handlers::{HandlerError, HandlerResult};
use super::state::Snapshot;
use crate::testing::{self, Positions, TestResult};

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

/// `higraph/tests`: every test of the workspace, in workspace order. It needs no parameters
/// and ignores any.
pub(crate) fn list(snapshot: &Snapshot, _: Option<Json>) -> HandlerResult<TestList> {
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

/// Lowers and runs a test (`crate::testing`, shared with `higraph-lsp test`), stopping when
/// [`should_stop`] says so between cycles.
fn run(snapshot: &Snapshot, test: &TestItem, trace: bool) -> HandlerResult<TestResult> {
    let stop = || should_stop(snapshot);
    match testing::run_test(&snapshot.analysis, test, trace, &stop)? {
        Some(result) => Ok(result),
        None => Err(HandlerError::Cancelled),
    }
}

/// `workspace/executeCommand` `higraph.runTest`: runs the test and answers its
/// `--format json` object.
pub(crate) fn run_test(snapshot: &Snapshot, params: TestParams) -> HandlerResult<RunTestOutcome> {
    let test = find_test(snapshot, &params)?;
    let result = run(snapshot, &test, false)?;
    let json = testing::test_json(&result, &mut Positions::new(&snapshot.analysis));
    let json = serde_json::to_value(&json)
        .map_err(|error| HandlerError::Failed(format!("cannot write the result: {error}")))?;
    let files = snapshot.analysis.files();
    let diagnostics = result
        .failures
        .iter()
        .filter_map(|failure| {
            let index = snapshot.line_index(&failure.file)?;
            let mut diagnostic = convert::diagnostic(
                &failure.diagnostic,
                &index,
                snapshot.encoding,
                |file, range| location(snapshot, &files.get(file.0 as usize)?.path, range),
            );
            if snapshot.support.code_description {
                diagnostic.code_description = snapshot
                    .rule_page(failure.diagnostic.code.as_str())
                    .map(|href| lsp::CodeDescription { href });
            }
            Some((failure.file.clone(), diagnostic))
        })
        .collect();
    Ok(RunTestOutcome {
        json,
        key: test_key(&test.path, &test.name),
        record: TestRecord {
            passed: result.outcome == Outcome::Passed,
            failures: result.failures.len(),
            diagnostics,
        },
        generation: snapshot.generation(),
    })
}

/// `higraph/simulate`: runs the test with a trace and answers the JSON trace.
pub(crate) fn simulate(snapshot: &Snapshot, params: TestParams) -> HandlerResult<Json> {
    let test = find_test(snapshot, &params)?;
    let result = run(snapshot, &test, true)?;
    let Some(trace) = &result.trace else {
        // Only a test that could not run has no trace: say why.
        let reason = result.failures.first().map_or_else(
            || "it gave no trace".to_owned(),
            |f| f.diagnostic.message.clone(),
        );
        return Err(HandlerError::Failed(reason));
    };
    serde_json::to_value(trace)
        .map_err(|error| HandlerError::Failed(format!("cannot write the trace: {error}")))
}

fn location(snapshot: &Snapshot, path: &str, range: TextRange) -> Option<lsp::Location> {
    let index = snapshot.line_index(path)?;
    Some(lsp::Location::new(
        snapshot.uri(path)?,
        convert::range(&index, range, snapshot.encoding),
    ))
}

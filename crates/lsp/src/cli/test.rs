//! `higraph-lsp test [PATH...] [--filter PATTERN] [--format human|json|junit] [--trace DIR]`
//! (`runtime.md` §7): find the workspace as `check` does, run the `test` items of the files
//! under the PATHs (without a PATH: every test of the workspace) in workspace order, each on a
//! fresh machine, and report like `cargo test`.
//!
//! * Exit status 0 when every selected test passed (also when none was selected), 1 when a
//!   test failed or could not run, 2 for a usage error or unreadable input. Workspace
//!   diagnostics are not printed; a test that cannot run because of errors fails with HG9904.
//! * `human` prints one line per test as it finishes (that is the progress report), then the
//!   failures rendered like `check`'s human output, then the summary. `json` and `junit`
//!   print one document at the end.
//! * `--trace DIR` creates DIR if needed and writes `DIR/{test}.json` and `DIR/{test}.vcd`
//!   for every test that ran, each atomically (a temporary file in DIR, then a rename). It
//!   replaces only files that are traces of an earlier run (a JSON file starting like one,
//!   a VCD file written by higraph-lsp); any other file of those names stops the command
//!   before a test runs (status 2), so nothing a user wrote is overwritten by surprise.

use std::fmt::Write as _;
use std::fs;
use std::io::{self, IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use higraph_analysis::lower::TestItem;
use higraph_analysis::{AnalysisHost, FileId};
use higraph_runtime::test::Outcome;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::output::{self, Reported, SourceFile, Sources};
use super::paths::OutputPaths;
use super::{CliError, EXIT_FAILURE, TestArgs, TestFormat, write_stdout};
use crate::testing::{
    self, OutputJson, Positions, SummaryJson, TestResult, test_json, write_trace,
};
use crate::workspace;

pub(crate) fn run(args: &TestArgs) -> Result<ExitCode, CliError> {
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }
    let loaded = workspace::load(&workspace, None)?;
    let selected = loaded.selected.clone();
    let mut host = AnalysisHost::new();
    host.load(loaded.data);
    let analysis = host.analysis();
    let paths = OutputPaths::new(&workspace.root);
    let files = analysis.files();
    let sources = Sources::new(
        files
            .iter()
            .map(|f| {
                let shown = paths.name(&f.path);
                SourceFile::new(f.path.clone(), shown, (*f.contents).clone())
            })
            .collect(),
        paths.root(),
    );
    let file_id = |path: &str| {
        files
            .iter()
            .position(|f| f.path == path)
            .map(|i| FileId(i as u32))
    };

    let items = analysis
        .tests()
        .map_err(|_| CliError::new("the analysis was cancelled"))?;
    // Without a PATH every test of the workspace runs (`runtime.md` §7: "default all"), also
    // when the current folder is below the root.
    let everything = args.paths.is_empty();
    let in_paths: Vec<TestItem> = items
        .into_iter()
        .filter(|item| everything || selected.get(&item.path).copied().unwrap_or(false))
        .collect();
    let pattern = args.filter.as_deref().map(str::to_lowercase);
    let (tests, filtered): (Vec<TestItem>, Vec<TestItem>) =
        in_paths.into_iter().partition(|item| {
            pattern
                .as_deref()
                .is_none_or(|p| item.name.to_lowercase().contains(p))
        });
    let filtered_out = filtered.len();

    let trace_dir = match &args.trace {
        Some(dir) => Some(prepare_trace_dir(dir, &tests)?),
        None => None,
    };

    let color = io::stdout().is_terminal()
        && std::env::var_os("NO_COLOR").is_none_or(|value| value.is_empty())
        && std::env::var_os("TERM").is_none_or(|term| term != "dumb");
    let human = args.format == TestFormat::Human;
    if human {
        write_stdout(
            format!(
                "running {} test{}\n",
                tests.len(),
                if tests.len() == 1 { "" } else { "s" }
            )
            .as_bytes(),
        )?;
    }
    let progress = Progress::start();
    let mut results = Vec::with_capacity(tests.len());
    for (n, item) in tests.iter().enumerate() {
        progress.running(n, tests.len(), &item.name);
        let result = testing::run_test(&analysis, item, trace_dir.is_some(), &|| false)
            .map_err(|_| CliError::new("the analysis was cancelled"))?
            .ok_or_else(|| CliError::new("the test run was cancelled"))?;
        if let Some(dir) = &trace_dir {
            write_traces(dir, &result)?;
        }
        if human {
            progress.suspend(|| write_stdout(status_line(&result, color).as_bytes()))?;
        }
        results.push(result);
    }
    progress.finish();

    let summary = SummaryJson {
        passed: count(&results, Outcome::Passed),
        failed: count(&results, Outcome::Failed),
        errors: count(&results, Outcome::Error),
        filtered_out,
    };
    let text = match args.format {
        TestFormat::Human => human_tail(&results, &summary, &sources, &file_id, color),
        TestFormat::Json => {
            let mut positions = Positions::new(&analysis);
            let output = OutputJson {
                version: 1,
                tests: results
                    .iter()
                    .map(|r| test_json(r, &mut positions))
                    .collect(),
                summary,
            };
            // Serialising these plain structs cannot fail.
            let mut text = serde_json::to_string_pretty(&output).unwrap_or_default();
            text.push('\n');
            text
        }
        TestFormat::Junit => junit(&results, &summary, &sources, &file_id),
    };
    write_stdout(text.as_bytes())?;
    Ok(if summary.failed + summary.errors > 0 {
        ExitCode::from(EXIT_FAILURE)
    } else {
        ExitCode::SUCCESS
    })
}

/// A spinner on stderr naming the running test, for runs that take longer than about half a
/// second and only on a terminal (like `check`'s); a short run draws nothing.
struct Progress {
    bar: Option<ProgressBar>,
    /// Set when the run is done; the thread that would show the bar checks it under the lock,
    /// so the bar is never drawn after [`Progress::finish`].
    done: Arc<Mutex<bool>>,
}

impl Progress {
    fn start() -> Progress {
        let done = Arc::new(Mutex::new(false));
        if !io::stderr().is_terminal() {
            return Progress { bar: None, done };
        }
        // Hidden at first: setting the style or message of a visible bar draws it.
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden()).with_style(
            ProgressStyle::with_template("{spinner} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        let shown = bar.clone();
        let shown_done = Arc::clone(&done);
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(500));
            let done = shown_done
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            if !*done {
                shown.set_draw_target(ProgressDrawTarget::stderr());
                shown.enable_steady_tick(Duration::from_millis(100));
            }
        });
        Progress {
            bar: Some(bar),
            done,
        }
    }

    fn running(&self, n: usize, total: usize, name: &str) {
        if let Some(bar) = &self.bar {
            bar.set_message(format!("running test {}/{total}: {name}", n + 1));
        }
    }

    /// Runs `f` (a write to stdout) with the spinner out of the way.
    fn suspend<T>(&self, f: impl FnOnce() -> T) -> T {
        match &self.bar {
            Some(bar) => bar.suspend(f),
            None => f(),
        }
    }

    fn finish(self) {
        let mut done = self
            .done
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        *done = true;
        if let Some(bar) = self.bar {
            // Erases the bar if it was shown; draws nothing if it was still hidden.
            bar.finish_and_clear();
        }
    }
}

fn count(results: &[TestResult], outcome: Outcome) -> usize {
    results.iter().filter(|r| r.outcome == outcome).count()
}

fn plural(n: u64, word: &str) -> String {
    if n == 1 {
        format!("{n} {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// `test NAME ... ok (35 cycles, 350 ms)` / `... FAILED` / `... ERROR`; with `color` the
/// verdict green or red, as `cargo test` shows it.
fn status_line(result: &TestResult, color: bool) -> String {
    let name = &result.item.name;
    match result.outcome {
        Outcome::Passed => format!(
            "test {name} ... {} ({}, {} ms)\n",
            paint("ok", GREEN, color),
            plural(result.cycles, "cycle"),
            result.time_ms
        ),
        Outcome::Failed => format!("test {name} ... {}\n", paint("FAILED", RED, color)),
        Outcome::Error => format!("test {name} ... {}\n", paint("ERROR", RED, color)),
    }
}

const GREEN: &str = "\x1b[32m";
const RED: &str = "\x1b[31m";

/// `text` in an ANSI colour when `color`, else as it is.
fn paint(text: &str, ansi: &str, color: bool) -> String {
    if color {
        format!("{ansi}{text}\x1b[0m")
    } else {
        text.to_string()
    }
}

/// What follows the status lines: the failures and the summary line.
fn human_tail(
    results: &[TestResult],
    summary: &SummaryJson,
    sources: &Sources,
    file_id: &dyn Fn(&str) -> Option<FileId>,
    color: bool,
) -> String {
    let mut out = String::from("\n");
    let failing: Vec<&TestResult> = results
        .iter()
        .filter(|r| r.outcome != Outcome::Passed)
        .collect();
    if !failing.is_empty() {
        out.push_str("failures:\n\n");
        for result in &failing {
            let shown = file_id(&result.item.path)
                .map_or(result.item.path.as_str(), |id| sources.shown(id));
            let _ = writeln!(out, "---- {} ({shown}) ----", result.item.name);
            let reported: Vec<Reported> = result
                .failures
                .iter()
                .filter_map(|f| {
                    Some(Reported {
                        file: file_id(&f.file)?,
                        diagnostic: f.diagnostic.clone(),
                    })
                })
                .collect();
            out.push_str(&output::render_human_blocks(&reported, sources, color));
        }
        out.push_str("failures:\n");
        for result in &failing {
            let _ = writeln!(out, "    {}", result.item.name);
        }
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "test result: {}. {} passed; {} failed; {} error{}; {} filtered out",
        if failing.is_empty() {
            paint("ok", GREEN, color)
        } else {
            paint("FAILED", RED, color)
        },
        summary.passed,
        summary.failed,
        summary.errors,
        if summary.errors == 1 { "" } else { "s" },
        summary.filtered_out
    );
    out
}

// ------------------------------------------------------------------------------- JUnit

/// The JUnit XML report: one `testsuite` per file (workspace order), one `testcase` per
/// test; HG9901/HG9902 as `failure`, HG9903/HG9904 as `error`; wall-clock seconds.
fn junit(
    results: &[TestResult],
    summary: &SummaryJson,
    sources: &Sources,
    file_id: &dyn Fn(&str) -> Option<FileId>,
) -> String {
    let seconds = |d: Duration| format!("{:.3}", d.as_secs_f64());
    let total: Duration = results.iter().map(|r| r.wall).sum();
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<testsuites name=\"higraph-lsp test\" tests=\"{}\" failures=\"{}\" errors=\"{}\" \
         skipped=\"0\" time=\"{}\">",
        results.len(),
        summary.failed,
        summary.errors,
        seconds(total)
    );
    // Files in workspace order: the results already are.
    let mut start = 0;
    while start < results.len() {
        let path = &results[start].item.path;
        let end = start
            + results[start..]
                .iter()
                .take_while(|r| &r.item.path == path)
                .count();
        let group = &results[start..end];
        let shown = file_id(path).map_or(path.as_str(), |id| sources.shown(id));
        let time: Duration = group.iter().map(|r| r.wall).sum();
        let _ = writeln!(
            out,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"0\" \
             time=\"{}\">",
            xml(shown),
            group.len(),
            count(group, Outcome::Failed),
            count(group, Outcome::Error),
            seconds(time)
        );
        let classname = shown
            .strip_suffix(".higraph")
            .unwrap_or(shown)
            .replace('/', ".");
        for result in group {
            let line = file_id(path).map_or(1, |id| {
                sources.line_column(id, result.item.name_range.start()).0
            });
            let _ = write!(
                out,
                "    <testcase name=\"{}\" classname=\"{}\" file=\"{}\" line=\"{line}\" \
                 time=\"{}\"",
                xml(&result.item.name),
                xml(&classname),
                xml(shown),
                seconds(result.wall)
            );
            if result.failures.is_empty() {
                out.push_str("/>\n");
                continue;
            }
            out.push_str(">\n");
            for failure in &result.failures {
                let code = failure.diagnostic.code.as_str();
                let element = if matches!(code, "HG9901" | "HG9902") {
                    "failure"
                } else {
                    "error"
                };
                let (file, line, column) = match file_id(&failure.file) {
                    Some(id) => {
                        let (line, column) =
                            sources.line_column(id, failure.diagnostic.range.start());
                        (sources.shown(id).to_string(), line, column)
                    }
                    None => (failure.file.clone(), 1, 1),
                };
                let message = &failure.diagnostic.message;
                let _ = writeln!(
                    out,
                    "      <{element} type=\"{code}\" message=\"{}\">{}</{element}>",
                    xml(message),
                    xml(&format!("{file}:{line}:{column}: {message}"))
                );
            }
            out.push_str("    </testcase>\n");
        }
        out.push_str("  </testsuite>\n");
        start = end;
    }
    out.push_str("</testsuites>\n");
    out
}

/// Text for XML content and attribute values: markup characters as references, line breaks
/// and tabs as character references, other control characters (not allowed in XML 1.0) as
/// U+FFFD.
fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c if c.is_control() => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

// ------------------------------------------------------------------------------- traces

/// Creates the trace folder and checks that no file a trace would replace is something else.
fn prepare_trace_dir(dir: &Path, tests: &[TestItem]) -> Result<PathBuf, CliError> {
    fs::create_dir_all(dir).map_err(|error| {
        CliError::new(format!(
            "cannot create the trace folder '{}': {}",
            dir.display(),
            workspace::io_reason(&error)
        ))
    })?;
    for item in tests {
        for (extension, is_trace) in [
            ("json", is_json_trace as fn(&[u8]) -> bool),
            ("vcd", is_vcd_trace),
        ] {
            let path = dir.join(trace_file_name(&item.name, extension));
            let Ok(meta) = fs::symlink_metadata(&path) else {
                continue;
            };
            let ours = meta.is_file()
                && fs::File::open(&path)
                    .and_then(|file| {
                        let mut head = Vec::new();
                        io::Read::read_to_end(&mut io::Read::take(file, 64), &mut head)?;
                        Ok(head)
                    })
                    .is_ok_and(|head| is_trace(&head));
            if !ours {
                return Err(CliError::new(format!(
                    "'{}' exists and is not a trace of higraph-lsp; remove it or choose \
                     another --trace folder",
                    path.display()
                )));
            }
        }
    }
    Ok(dir.to_path_buf())
}

fn is_json_trace(head: &[u8]) -> bool {
    head.starts_with(b"{\n  \"version\": 1,\n  \"test\": ")
}

fn is_vcd_trace(head: &[u8]) -> bool {
    head.starts_with(b"$version higraph-lsp ")
}

/// `{test}.{extension}`; characters that cannot stand in a file name become `_`.
fn trace_file_name(test: &str, extension: &str) -> String {
    let name: String = test
        .chars()
        .map(|c| {
            if c.is_control() || matches!(c, '/' | '\\' | ':' | '*' | '?' | '"' | '<' | '>' | '|') {
                '_'
            } else {
                c
            }
        })
        .collect();
    let name = if name.starts_with('.') || name.is_empty() {
        format!("_{name}")
    } else {
        name
    };
    format!("{name}.{extension}")
}

/// Writes the JSON trace and the VCD of a test that ran.
fn write_traces(dir: &Path, result: &TestResult) -> Result<(), CliError> {
    let Some(trace) = &result.trace else {
        return Ok(());
    };
    // Streamed into the file: a long test's trace need not exist twice in memory.
    write_atomically(
        &dir.join(trace_file_name(&result.item.name, "json")),
        |out| write_trace(out, trace),
    )?;
    if let Some(vcd) = testing::vcd(result) {
        write_atomically(
            &dir.join(trace_file_name(&result.item.name, "vcd")),
            |out| out.write_all(vcd.as_bytes()),
        )?;
    }
    Ok(())
}

/// Writes a temporary file next to `path` with `write`, then renames it over `path`.
fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut io::BufWriter<fs::File>) -> io::Result<()>,
) -> Result<(), CliError> {
    let error = |error: io::Error| {
        CliError::new(format!(
            "cannot write '{}': {}",
            path.display(),
            workspace::io_reason(&error)
        ))
    };
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{file_name}.{}.trace-tmp", std::process::id()));
    let result = fs::File::create_new(&temporary)
        .and_then(|file| {
            let mut out = io::BufWriter::new(file);
            write(&mut out)?;
            out.into_inner()
                .map_err(io::IntoInnerError::into_error)?
                .sync_all()
        })
        .and_then(|()| fs::rename(&temporary, path));
    if let Err(e) = result {
        let _ = fs::remove_file(&temporary);
        return Err(error(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xml_escapes_markup_and_controls() {
        assert_eq!(xml("a<b & \"c\"\n"), "a&lt;b &amp; &quot;c&quot;&#10;");
        assert_eq!(xml("\u{1}x"), "\u{FFFD}x");
    }

    #[test]
    fn trace_names_stay_in_the_folder() {
        assert_eq!(trace_file_name("Bohrzyklus", "json"), "Bohrzyklus.json");
        assert_eq!(trace_file_name("a/b", "vcd"), "a_b.vcd");
        assert_eq!(trace_file_name("..", "vcd"), "_...vcd");
    }

    #[test]
    fn traces_are_recognised_by_their_start() {
        assert!(is_json_trace(b"{\n  \"version\": 1,\n  \"test\": \"T\""));
        assert!(!is_json_trace(b"{\"version\": 1}"));
        assert!(is_vcd_trace(b"$version higraph-lsp 0.1.0 $end"));
        assert!(!is_vcd_trace(b"$date today $end"));
    }
}

//! `higraph-lsp check [PATH...]`: analyse the workspace, report the diagnostics of the files
//! under the PATHs, and exit with the status of `diagnostics.md` §4.3.
//!
//! The flow is: find the workspace and its files ([`workspace`](super::workspace)) → read
//! every file → [`analyse`] → keep the diagnostics of the selected files → sort, count and
//! render ([`output`](super::output)). Only [`analyse`] changes when the salsa database brings
//! workspace-wide analysis.

use std::io::{self, IsTerminal, Write as _};
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use higraph_analysis::{AnalysisHost, FileId};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::output::{self, Report, Reported, SourceFile, Sources};
use super::paths::OutputPaths;
use super::{CheckArgs, CliError, ColorChoice, Deny, EXIT_FAILURE, Format, write_stdout};
use crate::workspace;

pub(crate) fn run(args: &CheckArgs) -> Result<ExitCode, CliError> {
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }

    let progress = Progress::start(workspace.files.len());
    let mut host = AnalysisHost::new();
    let loaded = workspace::load(&workspace, args.config.as_deref())?;
    let selected = loaded.selected.clone();
    host.load(loaded.data);
    let analysis = host.analysis();
    let paths = OutputPaths::new(&workspace.root);
    let sources = Sources::new(
        analysis
            .files()
            .into_iter()
            .map(|f| {
                let shown = paths.name(&f.path);
                SourceFile::new(f.path, shown, (*f.contents).clone())
            })
            .collect(),
        paths.root(),
    );
    let diagnostics = analysis.diagnostics();
    progress.finish();
    let is_selected = |file: FileId| selected.get(sources.name(file)).copied().unwrap_or(false);
    let files_checked = workspace.files.iter().filter(|file| file.selected).count();
    let reported = diagnostics
        .into_iter()
        .filter(|(file, _)| is_selected(*file))
        .flat_map(|(file, diagnostics)| {
            diagnostics
                .into_iter()
                .map(move |diagnostic| Reported { file, diagnostic })
        })
        .collect();
    let report = Report::new(&sources, reported, files_checked);

    let color = match args.color {
        ColorChoice::Always => true,
        ColorChoice::Never => false,
        ColorChoice::Auto => {
            io::stdout().is_terminal()
                && std::env::var_os("NO_COLOR").is_none_or(|value| value.is_empty())
                && std::env::var_os("TERM").is_none_or(|term| term != "dumb")
        }
    };
    write_stdout(output::render(args.format, &report, &sources, color).as_bytes())?;
    if args.format == Format::Human && report.diagnostics.is_empty() {
        let files = match files_checked {
            1 => "1 file".to_string(),
            n => format!("{n} files"),
        };
        let _ = writeln!(io::stderr(), "ok: {files} checked, no diagnostics");
    }

    let summary = report.summary;
    let deny_warnings = args.deny.contains(&Deny::Warnings);
    let failed = summary.errors > 0 || (deny_warnings && summary.warnings > 0);
    Ok(if failed {
        ExitCode::from(EXIT_FAILURE)
    } else {
        ExitCode::SUCCESS
    })
}

/// A progress bar on stderr for runs that take longer than about half a second (only on a
/// terminal). A shorter run draws nothing at all.
struct Progress {
    bar: Option<ProgressBar>,
    /// Set when the run is done; the thread that would show the bar checks it under the lock,
    /// so the bar is never drawn after [`Progress::finish`] cleared it.
    done: Arc<Mutex<bool>>,
}

impl Progress {
    fn start(files: usize) -> Progress {
        let done = Arc::new(Mutex::new(false));
        if !io::stderr().is_terminal() {
            return Progress { bar: None, done };
        }
        // Hidden from the start: setting the style or the message of a visible bar draws it.
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden())
            .with_style(
                ProgressStyle::with_template("{spinner} checking {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            )
            .with_message(match files {
                1 => "1 file".to_owned(),
                n => format!("{n} files"),
            });
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

//! `higraph-lsp check [PATH...]`: analyse the workspace, report the diagnostics of the files
//! under the PATHs, and exit with the status of `diagnostics.md` §4.3.
//!
//! The flow is: find the workspace and its files ([`workspace`](super::workspace)) → read
//! every file → [`analyse`] → keep the diagnostics of the selected files → sort, count and
//! render ([`output`](super::output)). Only [`analyse`] changes when the salsa database brings
//! workspace-wide analysis.

use std::io::{self, IsTerminal, Write as _};
use std::process::ExitCode;

use higraph_analysis::{AnalysisHost, FileId};
use indicatif::{ProgressBar, ProgressStyle};

use super::output::{self, Report, Reported, SourceFile, Sources};
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
    let sources = Sources::new(
        analysis
            .files()
            .into_iter()
            .map(|f| SourceFile::new(f.path, (*f.contents).clone()))
            .collect(),
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
/// terminal).
struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    fn start(files: usize) -> Progress {
        if !io::stderr().is_terminal() {
            return Progress { bar: None };
        }
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} checking {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(format!("{files} files"));
        // Shown only after half a second: short runs print nothing.
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
        let shown = bar.clone();
        std::thread::spawn(move || {
            std::thread::sleep(std::time::Duration::from_millis(500));
            if !shown.is_finished() {
                shown.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                shown.enable_steady_tick(std::time::Duration::from_millis(100));
            }
        });
        Progress { bar: Some(bar) }
    }

    fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}

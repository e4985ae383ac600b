//! `higraph-lsp check [PATH...]`: analyse the workspace, report the diagnostics of the files
//! under the PATHs, and exit with the status of `diagnostics.md` §4.3.
//!
//! The flow is: find the workspace and its files ([`workspace`](super::workspace)) → read
//! every file → [`analyse`] → keep the diagnostics of the selected files → sort, count and
//! render ([`output`](super::output)). Only [`analyse`] changes when the salsa database brings
//! workspace-wide analysis.

use std::io::{self, IsTerminal, Write as _};
use std::process::ExitCode;

use std::collections::HashMap;
use std::path::Path;

use globset::{Glob, GlobSet, GlobSetBuilder};
use higraph_analysis::{AnalysisHost, FileContents, FileId, WorkspaceData};
use indicatif::{ProgressBar, ProgressStyle};

use super::output::{self, Report, Reported, SourceFile, Sources};
use super::workspace::{self, Workspace};
use super::{
    CheckArgs, CliError, ColorChoice, Deny, EXIT_FAILURE, Format, io_reason, write_stdout,
};

pub(crate) fn run(args: &CheckArgs) -> Result<ExitCode, CliError> {
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }

    let progress = Progress::start(workspace.files.len());
    let mut host = AnalysisHost::new();
    let loaded = load(&workspace, args.config.as_deref())?;
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

/// What `load` read: the workspace data for the analysis, and which output paths are under
/// the PATHs (their diagnostics are reported).
struct Loaded {
    data: WorkspaceData,
    selected: HashMap<String, bool>,
}

/// Reads the configuration, every file of the workspace and the imported symbol tables. A
/// file that cannot be read is not an error of the run: it becomes a diagnostic (HG6103) on
/// that file. An unreadable `--config` file is (exit status 2).
fn load(workspace: &Workspace, config: Option<&Path>) -> Result<Loaded, CliError> {
    let mut selected = HashMap::new();
    let config_path = match config {
        Some(path) => Some(path.to_path_buf()),
        None => Some(workspace.root.join(workspace::CONFIG_FILE)).filter(|p| p.is_file()),
    };
    let config = match &config_path {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|error| {
                CliError::new(format!(
                    "cannot read configuration file '{}': {}",
                    path.display(),
                    io_reason(&error)
                ))
            })?;
            let name = workspace::display_name(&workspace.root, path);
            let absolute = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
            selected.insert(
                name.clone(),
                workspace.selects(&absolute) || config.is_some(),
            );
            Some((name, text))
        }
        None => None,
    };
    let parsed = config
        .as_ref()
        .map(|(_, text)| AnalysisHost::parse_config(text))
        .unwrap_or_default();
    let filter = FileFilter::new(&parsed.include, &parsed.exclude);
    let mut files = Vec::new();
    for file in &workspace.files {
        if !filter.accepts(&file.name) && !file.explicit {
            continue;
        }
        let contents = match std::fs::read(&file.path) {
            Ok(bytes) => FileContents::from_bytes(bytes),
            Err(error) => FileContents::unreadable(io_reason(&error)),
        };
        selected.insert(file.name.clone(), file.selected);
        files.push((file.name.clone(), contents));
    }
    let mut imports = HashMap::new();
    for (entry, _) in &parsed.symbols {
        let path = workspace.root.join(entry);
        let read = std::fs::read(&path).map_err(|error| io_reason(&error));
        let absolute = std::fs::canonicalize(&path).unwrap_or(path);
        selected.insert(entry.clone(), workspace.selects(&absolute));
        imports.insert(entry.clone(), read);
    }
    Ok(Loaded {
        data: WorkspaceData {
            files,
            config,
            imports,
        },
        selected,
    })
}

/// The `include` / `exclude` globs of `higraph.toml`, matched against workspace-relative
/// paths.
struct FileFilter {
    include: GlobSet,
    exclude: GlobSet,
}

impl FileFilter {
    fn new(include: &[String], exclude: &[String]) -> FileFilter {
        FileFilter {
            include: glob_set(include),
            exclude: glob_set(exclude),
        }
    }

    fn accepts(&self, name: &str) -> bool {
        self.include.is_match(name) && !self.exclude.is_match(name)
    }
}

fn glob_set(patterns: &[String]) -> GlobSet {
    let mut builder = GlobSetBuilder::new();
    for pattern in patterns {
        // Invalid patterns are ignored here; `higraph.toml` problems are reported by the
        // analysis.
        if let Ok(glob) = Glob::new(pattern) {
            builder.add(glob);
        }
    }
    builder.build().unwrap_or_else(|_| GlobSet::empty())
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

//! `higraph-lsp check [PATH...]`: analyse the workspace, report the diagnostics of the files
//! under the PATHs, and exit with the status of `diagnostics.md` §4.3.
//!
//! The flow is: find the workspace and its files ([`workspace`](super::workspace)) → read
//! every file → [`analyse`] → keep the diagnostics of the selected files → sort, count and
//! render ([`output`](super::output)). Only [`analyse`] changes when the salsa database brings
//! workspace-wide analysis.

use std::io::{self, IsTerminal, Write as _};
use std::process::ExitCode;

use higraph_analysis::{Diagnostic, FileContents, FileId, file_diagnostics};

use super::output::{self, Report, Reported, SourceFile, Sources};
use super::workspace::{self, Workspace};
use super::{
    CheckArgs, CliError, ColorChoice, Deny, EXIT_FAILURE, Format, io_reason, write_stdout,
};

pub(crate) fn run(args: &CheckArgs) -> Result<ExitCode, CliError> {
    if let Some(config) = &args.config {
        // The configuration's meaning comes with `higraph.toml` support; for now it must at
        // least be readable.
        std::fs::read(config).map_err(|error| {
            CliError::new(format!(
                "cannot read configuration file '{}': {}",
                config.display(),
                io_reason(&error)
            ))
        })?;
    }
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }

    let sources = load(&workspace);
    let diagnostics = analyse(&sources);
    let selected: Vec<bool> = workspace.files.iter().map(|file| file.selected).collect();
    let files_checked = selected.iter().filter(|&&selected| selected).count();
    let reported = diagnostics
        .into_iter()
        .filter(|(file, _)| selected[file.0 as usize])
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

/// Reads every file of the workspace. A file that cannot be read is not an error of the run:
/// it becomes a diagnostic (HG6103) on that file.
fn load(workspace: &Workspace) -> Sources {
    Sources::new(
        workspace
            .files
            .iter()
            .map(|file| {
                let contents = match std::fs::read(&file.path) {
                    Ok(bytes) => FileContents::from_bytes(bytes),
                    Err(error) => FileContents::unreadable(io_reason(&error)),
                };
                SourceFile::new(file.name.clone(), contents)
            })
            .collect(),
    )
}

/// The diagnostics of every file of the workspace.
///
/// Today each file is checked on its own (syntax errors, unreadable or non-UTF-8 files); the
/// workspace-wide analysis (name resolution across files, configuration overrides,
/// suppressions) will replace this function and keep its signature.
fn analyse(sources: &Sources) -> Vec<(FileId, Vec<Diagnostic>)> {
    sources
        .iter()
        .map(|(file, source)| (file, file_diagnostics(file, &source.contents)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use higraph_analysis::Severity;

    #[test]
    fn analyse_reports_per_file() {
        let sources = Sources::new(vec![
            SourceFile::new("a.higraph".into(), FileContents::Text("a $".into())),
            SourceFile::new("b.higraph".into(), FileContents::Text("// fine\n".into())),
        ]);
        let diagnostics = analyse(&sources);
        assert_eq!(diagnostics.len(), 2);
        assert_eq!(diagnostics[0].1[0].severity, Severity::Error);
        assert!(diagnostics[1].1.is_empty());
    }
}

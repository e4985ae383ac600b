//! `higraph-lsp build [PATH...] [--target awl|plcopen|all] [-o DIR] [--with-ob1] [--absolute]`
//! (`export.md` §2): generate the STEP 7 sources of the groups and the PLCopen XML of the
//! charts under the PATHs (default: the whole workspace) and write them into the output
//! folder.
//!
//! * The workspace is found and analysed as `check` does it. The items to build are the groups
//!   (`--target awl`, the default), the charts (`plcopen`) or both (`all`) of the files under
//!   the PATHs, in workspace order. If they, or what they depend on, have error-level
//!   diagnostics (`check`'s or `build`'s own HG81xx), nothing is written: the diagnostics are
//!   printed as `check --format human` prints them and the exit status is 1. Warnings are
//!   printed and do not stop the build.
//! * The files go into `build/` in the workspace root, or the folder `-o` names
//!   ([`crate::build`]: atomic writes, unchanged files are not rewritten, other files are left
//!   alone, the folder is never analysed). Standard output gets one line per file written,
//!   standard error the summary.
//! * Exit status: 0 built (also when there was nothing to build), 1 errors in the input, 2 a
//!   usage error or a file that cannot be read or written.

use std::fmt::Write as _;
use std::io::{self, IsTerminal, Write as _};
use std::path::PathBuf;
use std::process::ExitCode;

use higraph_analysis::build::{BuildOptions, BuildResult, Target};
use higraph_analysis::{AnalysisHost, FileId};

use super::output::{self, Report, Reported, SourceFile, Sources};
use super::paths::OutputPaths;
use super::{BuildArgs, BuildTarget, CliError, EXIT_FAILURE, Format, write_stdout};
use crate::build::{items_text, items_to_build, output_folder, plural, write_files};
use crate::workspace;

pub(crate) fn run(args: &BuildArgs) -> Result<ExitCode, CliError> {
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }
    let sources_on_disk: Vec<PathBuf> = workspace.files.iter().map(|f| f.path.clone()).collect();
    let folder = output_folder(&workspace.root, args.output.as_deref(), &sources_on_disk)
        .map_err(CliError::new)?;

    let loaded = workspace::load(&workspace, None)?;
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

    let options = BuildOptions {
        target: match args.target {
            BuildTarget::Awl => Target::Awl,
            BuildTarget::Plcopen => Target::Plcopen,
            BuildTarget::All => Target::All,
        },
        with_ob1: args.with_ob1,
        absolute: args.absolute,
    };
    // Without a PATH the whole workspace is built (also from a folder below the root); with
    // PATHs, the workspace files under them.
    let selected: Vec<String> = workspace
        .files
        .iter()
        .filter(|f| f.selected)
        .map(|f| f.name.clone())
        .collect();
    let files_covered = if args.paths.is_empty() {
        workspace.files.len()
    } else {
        selected.len()
    };
    let result = if !args.paths.is_empty() && selected.is_empty() {
        BuildResult::default()
    } else {
        let paths: &[String] = if args.paths.is_empty() {
            &[]
        } else {
            &selected
        };
        analysis
            .build(paths, &options)
            .map_err(|_| CliError::new("the analysis was cancelled"))?
    };

    // The diagnostics, as `check` prints them.
    let ids: std::collections::HashMap<&str, FileId> = files
        .iter()
        .enumerate()
        .rev() // the first file of a path wins
        .map(|(i, f)| (f.path.as_str(), FileId(i as u32)))
        .collect();
    let file_id = |path: &str| ids.get(path).copied();
    let reported: Vec<Reported> = result
        .checked
        .iter()
        .chain(&result.diagnostics)
        .filter_map(|(path, diagnostic)| {
            Some(Reported {
                file: file_id(path)?,
                diagnostic: diagnostic.clone(),
            })
        })
        .collect();
    let color = io::stdout().is_terminal()
        && std::env::var_os("NO_COLOR").is_none_or(|value| value.is_empty())
        && std::env::var_os("TERM").is_none_or(|term| term != "dumb");
    if !reported.is_empty() {
        let report = Report::new(&sources, reported, files_covered);
        write_stdout(output::render(Format::Human, &report, &sources, color).as_bytes())?;
    }

    let items = items_text(result.groups, result.charts);
    if let Some(why) = &result.failure {
        let _ = writeln!(io::stderr(), "error: nothing built: {why}");
        return Ok(ExitCode::from(EXIT_FAILURE));
    }
    if !result.refused.is_empty() {
        let files = result
            .refused
            .iter()
            .map(|path| paths.name(path))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            io::stderr(),
            "error: nothing built: errors in {} to build or in what {} ({files})",
            items_to_build(result.groups, result.charts),
            if result.groups + result.charts == 1 {
                "it uses"
            } else {
                "they use"
            }
        );
        return Ok(ExitCode::from(EXIT_FAILURE));
    }
    if result.files.is_empty() {
        let what = match options.target {
            Target::Awl => "no group",
            Target::Plcopen => "no chart",
            Target::All => "no group or chart",
        };
        let place = if args.paths.is_empty() {
            "in the workspace"
        } else {
            "under the given paths"
        };
        let hint = match options.target {
            Target::Awl => " (--target plcopen or all builds the charts)",
            Target::Plcopen => " (--target awl or all builds the groups)",
            Target::All => "",
        };
        let _ = writeln!(io::stderr(), "nothing to build: {what} {place}{hint}");
        return Ok(ExitCode::SUCCESS);
    }

    let written = write_files(&folder, &result.files).map_err(CliError::new)?;
    let mut out = String::new();
    for file in written.iter().filter(|w| w.changed) {
        let _ = writeln!(out, "wrote {}", paths.of_path(&file.path));
    }
    write_stdout(out.as_bytes())?;
    let changed = written.iter().filter(|w| w.changed).count();
    let unchanged = written.len() - changed;
    let mut summary = format!(
        "built {items} into {}: {} written",
        paths.of_path(&folder.path),
        plural(changed, "file")
    );
    if unchanged > 0 {
        let _ = write!(summary, ", {unchanged} unchanged");
    }
    let _ = writeln!(io::stderr(), "{summary}");
    Ok(ExitCode::SUCCESS)
}

//! `higraph-lsp render NAME [--format svg|dot] [-o FILE]`: a picture of a graph, group or
//! chart of the workspace (`tooling.md` §6), laid out by the analysis crate without Graphviz.
//!
//! The workspace is found and loaded as `check` does it (from the current folder, or from
//! `--dir`). An unknown name is a usage error (exit status 2) whose message lists the graphs,
//! groups and charts there are; so is a name that several of them share (the message names
//! each with its file and line).

use std::io::{self, Write as _};
use std::process::ExitCode;

use higraph_analysis::AnalysisHost;
use higraph_analysis::render::{RenderFormat as Format, ambiguity_message};

use super::paths::OutputPaths;
use super::{CliError, RenderArgs, RenderFormat, io_reason, write_stdout};
use crate::workspace;

pub(crate) fn run(args: &RenderArgs) -> Result<ExitCode, CliError> {
    let paths: Vec<_> = args.dir.iter().cloned().collect();
    let (workspace, warnings) = workspace::discover(&paths)?;
    for warning in warnings {
        let _ = writeln!(io::stderr(), "warning: {warning}");
    }
    let loaded = workspace::load(&workspace, None)?;
    let mut host = AnalysisHost::new();
    host.load(loaded.data);
    let format = match args.format {
        RenderFormat::Svg => Format::Svg,
        RenderFormat::Dot => Format::Dot,
    };
    let analysis = host.analysis();
    let cancelled = |_| CliError::new("the analysis was cancelled");
    // A name several items share is an error naming them, with files named as everywhere on
    // the command line (relative to the current directory).
    let candidates = analysis.render_candidates(&args.name).map_err(cancelled)?;
    if candidates.len() > 1 {
        let paths = OutputPaths::new(&workspace.root);
        return Err(CliError::new(ambiguity_message(
            &args.name,
            &candidates,
            |file| paths.name(file),
        )));
    }
    let text = analysis
        .render(&args.name, format)
        .map_err(cancelled)?
        .map_err(CliError::new)?;
    match &args.output {
        Some(path) => std::fs::write(path, text.as_bytes()).map_err(|error| {
            CliError::new(format!(
                "cannot write {}: {}",
                path.display(),
                io_reason(&error)
            ))
        })?,
        None => write_stdout(text.as_bytes())?,
    }
    Ok(ExitCode::SUCCESS)
}

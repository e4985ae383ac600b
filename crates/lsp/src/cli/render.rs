//! `higraph-lsp render NAME [--format svg|dot] [-o FILE]`: a picture of a graph, group or
//! chart of the workspace (`tooling.md` §6), laid out by the analysis crate without Graphviz.
//!
//! The workspace is found and loaded as `check` does it (from the current folder, or from
//! `--dir`). An unknown name is a usage error (exit status 2) whose message lists the graphs,
//! groups and charts there are; so is a name that several of them share (the message names
//! each with its file and line).
//!
//! `-o FILE` writes atomically (a temporary file in the same folder, renamed over FILE; a link
//! is followed and stays a link). It does not replace a file that may hold work — a source
//! file of the workspace, or any existing file that does not look like a picture (its text
//! does not start with `<svg`, `<?xml` or `digraph`) — unless `--force` is given: that is a
//! usage error (exit status 2). A special file (`/dev/stdout`, a pipe) is written to directly.

use std::fs;
use std::io::{self, Read as _, Write as _};
use std::path::Path;
use std::process::ExitCode;

use higraph_analysis::AnalysisHost;
use higraph_analysis::render::{RenderFormat as Format, ambiguity_message};

use super::fmt_command::write_atomically;
use super::paths::OutputPaths;
use super::{CliError, RenderArgs, RenderFormat, io_reason, write_stdout};
use crate::workspace::{self, CONFIG_FILE, EXTENSION, Workspace, open_regular};

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
        Some(path) => write_picture(&workspace, path, text.as_bytes(), args.force)?,
        None => write_stdout(text.as_bytes())?,
    }
    Ok(ExitCode::SUCCESS)
}

/// Writes the picture to `path` (see the module documentation).
fn write_picture(
    workspace: &Workspace,
    path: &Path,
    contents: &[u8],
    force: bool,
) -> Result<(), CliError> {
    let cannot_write = |error: io::Error| {
        CliError::new(format!(
            "cannot write {}: {}",
            path.display(),
            io_reason(&error)
        ))
    };
    match fs::metadata(path) {
        Ok(metadata) if !metadata.is_file() && !metadata.is_dir() => {
            // A terminal, a pipe, `/dev/null`: a stream, not a file to replace.
            let mut file = fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(cannot_write)?;
            return file.write_all(contents).map_err(cannot_write);
        }
        Ok(metadata) if metadata.is_file() && !force => {
            if let Some(reason) = refusal(workspace, path) {
                return Err(CliError::new(format!(
                    "refusing to overwrite {}: {reason}; use --force to replace it",
                    path.display()
                )));
            }
        }
        _ => {}
    }
    write_atomically(path, contents).map_err(cannot_write)
}

/// Why the existing regular file `path` must not be replaced by a picture, if it must not.
fn refusal(workspace: &Workspace, path: &Path) -> Option<String> {
    let real = fs::canonicalize(path).ok()?;
    let is_source = real.extension().is_some_and(|ext| ext == EXTENSION)
        || real.file_name().is_some_and(|name| name == CONFIG_FILE)
        || workspace
            .files
            .iter()
            .any(|file| fs::canonicalize(&file.path).is_ok_and(|source| source == real));
    if is_source {
        return Some("it is a source file of the workspace".to_owned());
    }
    // The first bytes tell a picture from anything else.
    let mut start = Vec::new();
    let read = open_regular(&real, u64::MAX).and_then(|(file, _)| {
        file.take(512)
            .read_to_end(&mut start)
            .map_err(|e| e.to_string())
    });
    if read.is_err() {
        return Some("it cannot be read to see what it holds".to_owned());
    }
    let text = String::from_utf8_lossy(&start);
    let text = text.trim_start_matches('\u{FEFF}').trim_start();
    let is_picture = text.is_empty()
        || ["<svg", "<?xml", "digraph"]
            .iter()
            .any(|head| text.starts_with(head));
    (!is_picture).then(|| {
        "it does not look like a picture (it does not start with <svg, <?xml or digraph)".to_owned()
    })
}

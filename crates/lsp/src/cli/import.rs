//! `higraph-lsp import FILE... [-o DIR] [--force]` (`docs/iec.md` §8): PLCopen TC6 XML 2.01
//! files to one `.higraph` file per SFC program or function block.
//!
//! * Each FILE is read (a regular file of at most [`MAX_IMPORT_BYTES`]; a byte-order mark is
//!   dropped) and converted by [`higraph_import::import`]; each chart text is laid out by the
//!   formatter of `fmt` and written to `DIR/<chart>.higraph` (DIR: `-o`, default the current
//!   directory, created if needed) atomically (a temporary file and a rename).
//! * An existing file is not replaced unless `--force` is given; two POUs of one run that would
//!   write the same file are refused the second time.
//! * Standard output: one line per file written (`wrote DIR/Ampel.higraph (POU Ampel of
//!   FILE)`) and one per problem (`FILE:LINE: warning: POU Ampel, step Gruen: ...`); standard
//!   error: errors (unreadable files, invalid XML, refusals) and the summary.
//! * Exit status: 0 everything imported; 1 files written, with problems reported; 2 a usage
//!   error, a file that cannot be read or is not PLCopen XML, or a file that could not be
//!   written.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::fs;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use higraph_analysis::LineIndex;
use higraph_analysis::format::{FormatError, format};

use super::fmt_command::write_atomically;
use super::{CliError, EXIT_FAILURE, EXIT_USAGE, ImportArgs, io_reason, write_stdout};
use crate::build::plural;
use crate::workspace::read_regular;

/// The largest PLCopen file read: 256 MiB (exports of whole projects are large; the import is
/// linear in the size).
pub(crate) const MAX_IMPORT_BYTES: u64 = 256 * 1024 * 1024;

pub(crate) fn run(args: &ImportArgs) -> Result<ExitCode, CliError> {
    let folder = args.output.clone().unwrap_or_else(|| PathBuf::from("."));
    match fs::metadata(&folder) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(CliError::new(format!(
                "the output folder {} is not a folder",
                folder.display()
            )));
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            fs::create_dir_all(&folder).map_err(|e| {
                CliError::new(format!(
                    "cannot create the output folder {}: {}",
                    folder.display(),
                    io_reason(&e)
                ))
            })?;
        }
        Err(e) => {
            return Err(CliError::new(format!(
                "cannot use the output folder {}: {}",
                folder.display(),
                io_reason(&e)
            )));
        }
    }

    let mut stdout = String::new();
    let mut stderr = String::new();
    let mut written = 0usize;
    let mut problems = 0usize;
    let mut failed = 0usize;
    let mut files_read = 0usize;
    // Names written in this run (letter case ignored, as on some file systems).
    let mut taken: HashSet<String> = HashSet::new();

    for file in &args.files {
        let shown = file.display().to_string();
        let text = match read(file) {
            Ok(text) => text,
            Err(reason) => {
                failed += 1;
                let _ = writeln!(stderr, "error: {shown}: {reason}");
                continue;
            }
        };
        let imported = match higraph_import::import(&text) {
            Ok(imported) => imported,
            Err(error) => {
                failed += 1;
                let _ = writeln!(stderr, "error: {shown}: {error}");
                continue;
            }
        };
        files_read += 1;
        for p in &imported.problems {
            problems += 1;
            let _ = writeln!(stdout, "{shown}:{}: warning: {p}", p.line);
        }
        for chart in &imported.charts {
            let file_name = format!("{}.higraph", chart.name);
            let target = if args.output.is_some() {
                folder.join(&file_name)
            } else {
                PathBuf::from(&file_name)
            };
            let target_shown = target.display().to_string();
            if !taken.insert(file_name.to_ascii_lowercase()) {
                problems += 1;
                let _ = writeln!(
                    stdout,
                    "{shown}: warning: POU {}: {target_shown} was already written in this run; not written again",
                    chart.pou
                );
                continue;
            }
            if !args.force && fs::symlink_metadata(&target).is_ok() {
                failed += 1;
                let _ = writeln!(
                    stderr,
                    "error: {target_shown} exists; not replaced (use --force to replace it)"
                );
                continue;
            }
            let text = match format(&chart.text) {
                Ok(formatted) => formatted,
                Err(error) => {
                    // Written as generated: the reader sees the problem in `check` too.
                    problems += 1;
                    let _ = writeln!(
                        stdout,
                        "{shown}: warning: POU {}: the generated chart is written unformatted: {}",
                        chart.pou,
                        describe(&chart.text, &error)
                    );
                    chart.text.clone()
                }
            };
            match write_atomically(&target, text.as_bytes()) {
                Ok(()) => {
                    written += 1;
                    let _ = writeln!(
                        stdout,
                        "wrote {target_shown} (POU {} of {shown})",
                        chart.pou
                    );
                }
                Err(e) => {
                    failed += 1;
                    let _ = writeln!(
                        stderr,
                        "error: cannot write {target_shown}: {}",
                        io_reason(&e)
                    );
                }
            }
        }
    }

    write_stdout(stdout.as_bytes())?;
    let mut summary = format!(
        "imported {} from {}",
        plural(written, "chart"),
        plural(files_read, "file")
    );
    if problems > 0 {
        let _ = write!(summary, ", {}", plural(problems, "problem"));
    }
    if failed > 0 {
        let _ = write!(summary, ", {}", plural(failed, "error"));
    }
    let _ = writeln!(stderr, "{summary}");
    let _ = io::stderr().write_all(stderr.as_bytes());
    Ok(if failed > 0 {
        ExitCode::from(EXIT_USAGE)
    } else if problems > 0 {
        ExitCode::from(EXIT_FAILURE)
    } else {
        ExitCode::SUCCESS
    })
}

/// The file as text: UTF-8, a byte-order mark dropped.
fn read(path: &Path) -> Result<String, String> {
    let bytes = read_regular(path, MAX_IMPORT_BYTES).map_err(|r| format!("cannot read: {r}"))?;
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok(text.to_owned()),
        Err(e) => Err(format!(
            "not UTF-8 (invalid byte at offset {}); PLCopen files are UTF-8",
            e.valid_up_to()
        )),
    }
}

fn describe(text: &str, error: &FormatError) -> String {
    match error {
        FormatError::Syntax(errors) => match errors.first() {
            Some(first) => {
                let at = LineIndex::new(text).line_column(first.range.start());
                format!(
                    "syntax error at {}:{}: [{}] {}",
                    at.line, at.column, first.code, first.message
                )
            }
            None => "syntax errors".to_owned(),
        },
        FormatError::Internal(reason) => format!("the formatter failed ({reason})"),
        FormatError::Cancelled => "formatting was cancelled".to_owned(),
    }
}

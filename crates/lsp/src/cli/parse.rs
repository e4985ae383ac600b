//! `higraph-lsp parse FILE`: prints the lossless syntax tree (`Parse::debug_tree`) to stdout
//! and the syntax errors to stderr. Syntax errors do not change the exit status (0); a file
//! that cannot be read (also: not a regular file, or over 32 MiB), or is not UTF-8 text, is a
//! usage error (2).

use std::fmt::Write as _;
use std::io::{self, Write as _};
use std::process::ExitCode;

use higraph_analysis::{FileContents, LineIndex};

use super::{CliError, ParseArgs, write_stdout};
use crate::workspace::{MAX_SOURCE_BYTES, read_regular};

pub(crate) fn run(args: &ParseArgs) -> Result<ExitCode, CliError> {
    let path = args.file.display();
    // Only a regular file of at most 32 MiB (a FIFO or device would block or never end).
    let bytes = read_regular(&args.file, MAX_SOURCE_BYTES)
        .map_err(|reason| CliError::new(format!("cannot read '{path}': {reason}")))?;
    let text = match FileContents::from_bytes(bytes) {
        FileContents::Text(text) => text,
        FileContents::NotUtf8 { invalid_offset, .. } => {
            return Err(CliError::new(format!(
                "'{path}' is not valid UTF-8 (invalid byte at offset {invalid_offset})"
            )));
        }
        FileContents::Unreadable { reason } => {
            return Err(CliError::new(format!("cannot read '{path}': {reason}")));
        }
    };
    let parse = higraph_syntax::parse(&text);
    write_stdout(parse.debug_tree().as_bytes())?;

    let index = LineIndex::new(&text);
    let mut errors = String::new();
    for error in parse.errors() {
        let at = index.line_column(error.range.start());
        let _ = writeln!(
            errors,
            "error[{}]: {} at {}:{}",
            error.code, error.message, at.line, at.column
        );
    }
    // Diagnostics on stderr are best effort; the tree is the command's output.
    let _ = io::stderr().write_all(errors.as_bytes());
    Ok(ExitCode::SUCCESS)
}

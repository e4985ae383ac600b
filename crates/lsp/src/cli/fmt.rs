//! `higraph-lsp fmt [--check] [PATH...]`: rewrite the workspace files under the PATHs in the
//! canonical layout (`tooling.md` §2, §2a; the formatter is
//! [`higraph_analysis::format`]).
//!
//! * The files are those `check` would report on: the workspace's `.higraph` files under the
//!   PATHs (default: the current folder), minus those `higraph.toml` excludes; a file named on
//!   the command line is always formatted.
//! * The layout is the formatter's; line endings follow the file's first line break (a CR LF
//!   file stays CR LF) and a byte-order mark is kept.
//! * Standard output lists the files that were reformatted (with `--check`: that would be),
//!   one path per line, relative to the current directory (`tooling.md` §2; absolute for a
//!   file outside it); a summary goes to standard error.
//! * A file with syntax errors, that cannot be read or is not UTF-8 is left alone and reported
//!   on standard error with its first error.
//! * Writes are atomic: the new text goes to a temporary file in the same folder, which then
//!   replaces the file by a rename; the file's permissions are kept. A symbolic link is
//!   followed, so the file it points to is rewritten and the link stays a link.
//! * Nothing outside the workspace root is written: a link out of the workspace is not even
//!   read (as for `check`), and a file PATH outside the root (the root is found from the
//!   first PATH) is checked with `--check` but never rewritten; both are reported as errors.
//!   Only regular files up to the size limit of sources are read.
//! * Exit status: 0 when every file is formatted (with `--check`: already formatted); 1 when a
//!   file has syntax errors or could not be read or written, or with `--check` when a file would
//!   change; 2 for usage errors and PATHs that do not exist.

use std::fmt::Write as _;
use std::fs;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use higraph_analysis::format::{FormatError, format};
use higraph_analysis::{FileContents, LineIndex};

use super::paths::OutputPaths;
use super::{CliError, EXIT_FAILURE, FmtArgs, io_reason, write_stdout};
use crate::workspace::{self, FileFilter, MAX_SOURCE_BYTES, Workspace};

pub(crate) fn run(args: &FmtArgs) -> Result<ExitCode, CliError> {
    let (workspace, warnings) = workspace::discover(&args.paths)?;
    let mut stderr = String::new();
    for warning in warnings {
        let _ = writeln!(stderr, "warning: {warning}");
    }
    let filter = FileFilter::for_workspace(&workspace)?;
    let paths = OutputPaths::new(&workspace.root);

    let mut changed = Vec::new();
    let mut unchanged = 0usize;
    let mut failed = 0usize;
    for file in &workspace.files {
        if !file.selected || !(file.explicit || filter.accepts(&file.name)) {
            continue;
        }
        match format_file(&workspace, &file.path, args.check) {
            Ok(Outcome::Unchanged) => unchanged += 1,
            Ok(Outcome::Changed) => changed.push(paths.name(&file.name)),
            Err(problem) => {
                failed += 1;
                let _ = writeln!(stderr, "error: {}: {problem}", paths.name(&file.name));
            }
        }
    }

    let mut stdout = String::new();
    for name in &changed {
        let _ = writeln!(stdout, "{name}");
    }
    write_stdout(stdout.as_bytes())?;
    let _ = writeln!(
        stderr,
        "{}",
        summary(args.check, changed.len(), unchanged, failed)
    );
    let _ = io::stderr().write_all(stderr.as_bytes());

    let would_change = args.check && !changed.is_empty();
    let ok = failed == 0 && !would_change;
    Ok(if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_FAILURE)
    })
}

/// What happened to one file.
enum Outcome {
    /// Already in the canonical layout.
    Unchanged,
    /// Rewritten (with `--check`: would be).
    Changed,
}

/// Formats one file; with `check`, only tells whether it would change. The error is a
/// one-line description of why the file was left alone.
fn format_file(workspace: &Workspace, path: &Path, check: bool) -> Result<Outcome, String> {
    let real = workspace
        .fence
        .resolve(path)
        .map_err(|reason| format!("cannot read: {reason}"))?;
    let bytes = workspace
        .fence
        .read(&real, MAX_SOURCE_BYTES)
        .map_err(|reason| format!("cannot read: {reason}"))?;
    let text = match FileContents::from_bytes(bytes) {
        FileContents::Text(text) => text,
        FileContents::NotUtf8 { invalid_offset, .. } => {
            return Err(format!(
                "not valid UTF-8 (invalid byte at offset {invalid_offset}); left unchanged"
            ));
        }
        FileContents::Unreadable { reason } => return Err(format!("cannot read: {reason}")),
    };
    let formatted = format(&text).map_err(|error| describe(&text, &error))?;
    if formatted == text {
        return Ok(Outcome::Unchanged);
    }
    if !check {
        if !real.starts_with(&workspace.root) {
            return Err(format!(
                "not written: it is outside the workspace root '{}' (the workspace is found from the first PATH); left unchanged",
                workspace.root.display()
            ));
        }
        // `real` is the file itself, no link: the rename replaces exactly it.
        write_atomically(&real, formatted.as_bytes())
            .map_err(|error| format!("cannot write: {}", io_reason(&error)))?;
    }
    Ok(Outcome::Changed)
}

/// `syntax error at 3:14: [HG0002] missing ';' after 'U'; left unchanged`.
fn describe(text: &str, error: &FormatError) -> String {
    match error {
        FormatError::Syntax(errors) => {
            let Some(first) = errors.first() else {
                return "syntax errors; left unchanged".to_string();
            };
            let at = LineIndex::new(text).line_column(first.range.start());
            let more = match errors.len() {
                1 => String::new(),
                2 => " (and 1 more)".to_string(),
                n => format!(" (and {} more)", n - 1),
            };
            format!(
                "syntax error at {}:{}: [{}] {}{more}; left unchanged",
                at.line, at.column, first.code, first.message
            )
        }
        FormatError::Internal(reason) => {
            format!("the formatter failed ({reason}); left unchanged, please report this")
        }
        FormatError::Cancelled => "formatting was cancelled; left unchanged".to_string(),
    }
}

fn summary(check: bool, changed: usize, unchanged: usize, failed: usize) -> String {
    let files = |n: usize| {
        if n == 1 {
            "1 file".to_string()
        } else {
            format!("{n} files")
        }
    };
    let mut parts = Vec::new();
    if check {
        parts.push(format!("{} would be reformatted", files(changed)));
    } else {
        parts.push(format!("{} reformatted", files(changed)));
    }
    parts.push(format!("{} already formatted", files(unchanged)));
    if failed > 0 {
        parts.push(format!(
            "{} left unchanged because of errors",
            files(failed)
        ));
    }
    parts.join(", ")
}

/// Replaces the contents of `path` (following a symbolic link), or creates it, by writing a
/// temporary file in the same folder and renaming it over the original. The original's
/// permissions are kept.
pub(crate) fn write_atomically(path: &Path, contents: &[u8]) -> io::Result<()> {
    let target = match fs::canonicalize(path) {
        Ok(target) => target,
        // A new file (not a dangling link): in its folder's real place.
        Err(error)
            if error.kind() == io::ErrorKind::NotFound && fs::symlink_metadata(path).is_err() =>
        {
            let name = path.file_name().ok_or(error)?;
            let folder = match path.parent() {
                Some(folder) if !folder.as_os_str().is_empty() => folder,
                _ => Path::new("."),
            };
            fs::canonicalize(folder)?.join(name)
        }
        Err(error) => return Err(error),
    };
    let permissions = match fs::metadata(&target) {
        Ok(metadata) => Some(metadata.permissions()),
        Err(error) if error.kind() == io::ErrorKind::NotFound => None,
        Err(error) => return Err(error),
    };
    let folder = target.parent().unwrap_or_else(|| Path::new("."));
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = temporary_path(folder, &name);
    let result = (|| {
        let mut file = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)?;
        file.write_all(contents)?;
        file.sync_all()?;
        drop(file);
        if let Some(permissions) = permissions {
            fs::set_permissions(&temporary, permissions)?;
        }
        fs::rename(&temporary, &target)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    result
}

/// A name for the temporary file that no other file has: `.NAME.PID.N.fmt-tmp`.
fn temporary_path(folder: &Path, name: &str) -> PathBuf {
    let pid = std::process::id();
    (0u32..)
        .map(|n| folder.join(format!(".{name}.{pid}.{n}.fmt-tmp")))
        .find(|candidate| !candidate.exists())
        .unwrap_or_else(|| folder.join(format!(".{name}.{pid}.fmt-tmp")))
}

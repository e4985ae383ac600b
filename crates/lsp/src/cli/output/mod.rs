//! Rendering the diagnostics of a `check` run in one of the output formats.
//!
//! [`Report`] is what every format renders: the reported diagnostics sorted as
//! `diagnostics.md` §4.1 demands (file, start, end, code, message) and the summary counts.
//! Each format module converts byte ranges with the file's [`LineIndex`]: `json` in 0-based
//! UTF-16 units, the others in 1-based lines and character columns.

mod github;
mod human;
mod json;
mod sarif;
mod short;

use higraph_analysis::{
    Diagnostic, FileContents, FileId, LineColumn, LineIndex, Position, Severity, TextRange,
};

use super::Format;

/// A file whose diagnostics may be rendered: its name in output, its contents and index.
pub(crate) struct SourceFile {
    /// Workspace-relative `/` path (`--format json`, and the order of the report).
    pub name: String,
    /// The name relative to the current directory (every other format; `tooling.md` §2).
    pub shown: String,
    /// The contents the diagnostics' ranges refer to.
    pub contents: FileContents,
    /// Line index of `contents.text()`.
    pub line_index: LineIndex,
}

impl SourceFile {
    pub(crate) fn new(name: String, shown: String, contents: FileContents) -> SourceFile {
        let line_index = LineIndex::new(contents.text());
        SourceFile {
            name,
            shown,
            contents,
            line_index,
        }
    }

    /// 0-based line and UTF-16 column of the start and end of `range`.
    fn utf16_range(&self, range: TextRange) -> (Position, Position) {
        (
            self.line_index.utf16_position(range.start()),
            self.line_index.utf16_position(range.end()),
        )
    }

    /// 1-based line and character column of the start and end of `range`.
    fn line_columns(&self, range: TextRange) -> (LineColumn, LineColumn) {
        (
            self.line_index.line_column(range.start()),
            self.line_index.line_column(range.end()),
        )
    }
}

/// The files of a run, indexed by [`FileId`].
pub(crate) struct Sources {
    files: Vec<SourceFile>,
    /// The workspace root relative to the current directory (`--format json`'s `root`).
    root: String,
}

impl Sources {
    /// `files[i]` gets `FileId(i)`; `root` is the workspace root relative to the current
    /// directory.
    pub(crate) fn new(files: Vec<SourceFile>, root: String) -> Sources {
        Sources { files, root }
    }

    /// The output name of a file.
    pub(crate) fn name(&self, file: FileId) -> &str {
        &self.get(file).name
    }

    /// The name of a file relative to the current directory.
    pub(crate) fn shown(&self, file: FileId) -> &str {
        &self.get(file).shown
    }

    /// The 1-based line and character column of an offset in a file.
    pub(crate) fn line_column(
        &self,
        file: FileId,
        offset: higraph_analysis::TextSize,
    ) -> (u32, u32) {
        let position = self.get(file).line_index.line_column(offset);
        (position.line, position.column)
    }

    fn get(&self, file: FileId) -> &SourceFile {
        &self.files[file.0 as usize]
    }
}

/// One diagnostic to report, with the file it belongs to.
pub(crate) struct Reported {
    pub file: FileId,
    pub diagnostic: Diagnostic,
}

/// Counts of reported diagnostics per severity, and of the files checked.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Summary {
    pub errors: usize,
    pub warnings: usize,
    pub infos: usize,
    pub hints: usize,
    /// The number of files reported on (the workspace's files under the PATHs), whether or
    /// not they have diagnostics.
    pub files: usize,
}

impl Summary {
    fn count(&mut self, severity: Severity) {
        match severity {
            Severity::Error => self.errors += 1,
            Severity::Warning => self.warnings += 1,
            Severity::Info => self.infos += 1,
            Severity::Hint => self.hints += 1,
        }
    }

    /// The most serious severity reported, if any.
    fn worst(&self) -> Option<Severity> {
        [
            (Severity::Error, self.errors),
            (Severity::Warning, self.warnings),
            (Severity::Info, self.infos),
            (Severity::Hint, self.hints),
        ]
        .into_iter()
        .find(|&(_, n)| n > 0)
        .map(|(severity, _)| severity)
    }

    /// `1 error, 0 warnings, 0 infos, 0 hints`.
    fn counts_text(&self) -> String {
        fn plural(n: usize, word: &str) -> String {
            if n == 1 {
                format!("{n} {word}")
            } else {
                format!("{n} {word}s")
            }
        }
        format!(
            "{}, {}, {}, {}",
            plural(self.errors, "error"),
            plural(self.warnings, "warning"),
            plural(self.infos, "info"),
            plural(self.hints, "hint")
        )
    }
}

/// The diagnostics of a run in output order, and the summary.
pub(crate) struct Report {
    pub diagnostics: Vec<Reported>,
    pub summary: Summary,
}

impl Report {
    /// Sorts the diagnostics by file name, start line, start character, end line, end
    /// character (UTF-16), code and message, and counts them. `files` is the number of files
    /// reported on.
    pub(crate) fn new(sources: &Sources, mut diagnostics: Vec<Reported>, files: usize) -> Report {
        diagnostics.sort_by_cached_key(|reported| {
            let source = sources.get(reported.file);
            let (start, end) = source.utf16_range(reported.diagnostic.range);
            (
                source.name.clone(),
                start,
                end,
                reported.diagnostic.code,
                reported.diagnostic.message.clone(),
            )
        });
        let mut summary = Summary {
            files,
            ..Summary::default()
        };
        for reported in &diagnostics {
            summary.count(reported.diagnostic.severity);
        }
        Report {
            diagnostics,
            summary,
        }
    }
}

/// Renders the report in `format`. `color` applies to the human format only.
pub(crate) fn render(format: Format, report: &Report, sources: &Sources, color: bool) -> String {
    match format {
        Format::Human => human::render(report, sources, color),
        Format::Short => short::render(report, sources),
        Format::Json => json::render(report, sources),
        Format::Github => github::render(report, sources),
        Format::Sarif => sarif::render(report, sources),
    }
}

/// The `--format human` blocks of `diagnostics`, in the given order, without a summary line.
pub(crate) fn render_human_blocks(
    diagnostics: &[Reported],
    sources: &Sources,
    color: bool,
) -> String {
    human::render_blocks(diagnostics, sources, color)
}

/// A message on one line: line breaks become spaces (messages are one line by contract; this
/// keeps line-oriented formats intact if one is not).
fn one_line(message: &str) -> std::borrow::Cow<'_, str> {
    if message.contains(['\r', '\n']) {
        std::borrow::Cow::Owned(message.replace("\r\n", " ").replace(['\r', '\n'], " "))
    } else {
        std::borrow::Cow::Borrowed(message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_text_uses_singular_for_one() {
        let summary = Summary {
            errors: 1,
            warnings: 2,
            infos: 0,
            hints: 1,
            files: 3,
        };
        assert_eq!(
            summary.counts_text(),
            "1 error, 2 warnings, 0 infos, 1 hint"
        );
        assert_eq!(summary.worst(), Some(Severity::Error));
        assert_eq!(Summary::default().worst(), None);
    }
}

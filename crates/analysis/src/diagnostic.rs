//! The editor-independent diagnostic model (`diagnostics.md` §1.1): a code, a severity, a
//! primary range in one file, a message, related locations and quick fixes.
//!
//! Ranges are byte offsets into the file's text; the command line and the language server
//! convert them to line/column positions with a [`LineIndex`](crate::LineIndex). The file a
//! diagnostic belongs to is given by whoever holds it (diagnostics are produced per file);
//! related locations and fix edits name their file explicitly because they may point elsewhere.

use std::fmt;

use higraph_syntax::{SyntaxError, TextRange, TextSize};

/// Identifies one file of the workspace. What a file id stands for (a path, an editor
/// buffer) is decided by the owner of the file set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FileId(pub u32);

/// How serious a diagnostic is (`diagnostics.md` §1.1), most serious first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// The program is wrong.
    Error,
    /// The program is legal but almost certainly not what was meant.
    Warning,
    /// A fact the author should know about.
    Info,
    /// Advice on style, memory size or spelling.
    Hint,
}

impl Severity {
    /// Every severity, most serious first.
    pub const ALL: [Severity; 4] = [
        Severity::Error,
        Severity::Warning,
        Severity::Info,
        Severity::Hint,
    ];

    /// The lower-case name used in machine output and `higraph.toml`: `"error"`, `"warning"`,
    /// `"info"` or `"hint"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info => "info",
            Severity::Hint => "hint",
        }
    }
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A diagnostic code: `HG` and four digits, naming a rule of `diagnostics.md` §3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Code(&'static str);

impl Code {
    /// HG6102: a file that is not valid UTF-8.
    pub const INVALID_UTF8: Code = Code("HG6102");
    /// HG6103: a file of the workspace that cannot be read.
    pub const UNREADABLE_FILE: Code = Code("HG6103");

    /// A code from its text, e.g. `Code::new("HG2301")`.
    pub const fn new(code: &'static str) -> Code {
        Code(code)
    }

    /// The code as written in diagnostics: `"HG2301"`.
    pub fn as_str(self) -> &'static str {
        self.0
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

/// Extra meaning an editor can show (`diagnostics.md` §1.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DiagnosticTag {
    /// Unused code (HG1210, HG1212, HG6004); editors fade it out.
    Unnecessary,
}

/// A further location that explains a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct RelatedInfo {
    /// The file the location is in.
    pub file: FileId,
    /// The range in that file.
    pub range: TextRange,
    /// A short note on what is there.
    pub message: String,
}

/// One text replacement of a quick fix.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TextEdit {
    /// The file to edit.
    pub file: FileId,
    /// The range to replace (zero-width to insert).
    pub range: TextRange,
    /// The replacement text.
    pub new_text: String,
}

/// A quick fix: a title and the edits that implement it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Fix {
    /// What the fix does, e.g. "Insert ';'".
    pub title: String,
    /// The edits, applied together.
    pub edits: Vec<TextEdit>,
    /// The most likely fix of its diagnostic (at most one is): the only fix, or else a
    /// replacement with the closest existing name. Editors apply it on "auto fix".
    pub preferred: bool,
    /// A rename through the workspace rename engine that is not carried out yet: `edits` is
    /// empty until [`crate::Analysis::resolve_fixes`] (or a code action's resolve) asks the
    /// engine, which may refuse the name (the fix is then dropped). Diagnostics are computed
    /// after every keystroke; a rename walks every reference in the workspace, so it waits
    /// until an edit is wanted.
    pub rename: Option<PendingRename>,
}

/// The rename of a fix that has not been carried out ([`Fix::rename`]): the declared name at
/// `offset` of `file` becomes `new_name` everywhere.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PendingRename {
    pub file: FileId,
    pub offset: TextSize,
    pub new_name: String,
}

/// One diagnostic, independent of any editor protocol. The file it belongs to is known to
/// whoever holds it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// The rule that produced it.
    pub code: Code,
    /// The severity after workspace overrides.
    pub severity: Severity,
    /// The primary range: the exact text that is underlined (byte offsets).
    pub range: TextRange,
    /// The filled-in message template: one line, lower case, no final full stop.
    pub message: String,
    /// Further locations that explain the diagnostic.
    pub related: Vec<RelatedInfo>,
    /// Quick fixes.
    pub fixes: Vec<Fix>,
    /// Editor tags.
    pub tags: Vec<DiagnosticTag>,
}

impl Diagnostic {
    /// A diagnostic without related locations, fixes or tags.
    pub fn new(
        code: Code,
        severity: Severity,
        range: TextRange,
        message: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic {
            code,
            severity,
            range,
            message: message.into(),
            related: Vec::new(),
            fixes: Vec::new(),
            tags: Vec::new(),
        }
    }

    /// Converts a syntax error of the file `file`. Syntax errors are always errors
    /// (`diagnostics.md` §1.4: HG0xxx cannot be reconfigured).
    pub fn from_syntax_error(file: FileId, error: &SyntaxError) -> Diagnostic {
        Diagnostic {
            code: Code(error.code.as_str()),
            severity: Severity::Error,
            range: error.range,
            message: error.message.clone(),
            related: error
                .related
                .iter()
                .map(|related| RelatedInfo {
                    file,
                    range: related.range,
                    message: related.message.clone(),
                })
                .collect(),
            fixes: error
                .fixes
                .iter()
                .map(|fix| Fix {
                    title: fix.title.clone(),
                    edits: fix
                        .edits
                        .iter()
                        .map(|edit| TextEdit {
                            file,
                            range: edit.range,
                            new_text: edit.new_text.clone(),
                        })
                        .collect(),
                    preferred: error.fixes.len() == 1,
                    rename: None,
                })
                .collect(),
            tags: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn syntax_errors_become_error_diagnostics() {
        let parse = higraph_syntax::parse("a $ \"open");
        let diagnostics: Vec<_> = parse
            .errors()
            .iter()
            .map(|e| Diagnostic::from_syntax_error(FileId(3), e))
            .collect();
        let codes: Vec<_> = diagnostics.iter().map(|d| d.code.as_str()).collect();
        assert!(codes.contains(&"HG0009"), "{codes:?}");
        assert!(codes.contains(&"HG0004"), "{codes:?}");
        assert!(diagnostics.iter().all(|d| d.severity == Severity::Error));
        let unclosed = diagnostics
            .iter()
            .find(|d| d.code.as_str() == "HG0004")
            .unwrap();
        assert_eq!(
            unclosed.range,
            TextRange::new(TextSize::from(4), TextSize::from(9))
        );
        let edit = &unclosed.fixes[0].edits[0];
        assert_eq!(edit.file, FileId(3));
        assert_eq!(edit.new_text, "\"");
    }

    #[test]
    fn severities_order_most_serious_first() {
        assert!(Severity::Error < Severity::Warning);
        assert!(Severity::Info < Severity::Hint);
        assert_eq!(Severity::Hint.to_string(), "hint");
    }
}

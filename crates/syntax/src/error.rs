//! Syntax diagnostics (HG0xxx): a code, a precise range, a message, and optionally related
//! locations and quick fixes, as `diagnostics.md` §3.0 specifies.

use std::fmt;

use rowan::{TextRange, TextSize};

/// The syntax codes of `diagnostics.md` §3.0. All are errors and cannot be reconfigured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ErrorCode {
    /// Unexpected token.
    HG0001,
    /// Missing `;`.
    HG0002,
    /// Unclosed `<`.
    HG0003,
    /// Unclosed string.
    HG0004,
    /// Unclosed character constant.
    HG0005,
    /// Malformed constant.
    HG0006,
    /// Constant out of range.
    HG0007,
    /// `>` at file level.
    HG0008,
    /// Unexpected character / non-ASCII letters.
    HG0009,
    /// `mnemonic` not the first item.
    HG0010,
    /// Second `mnemonic` directive.
    HG0011,
    /// Nesting deeper than [`crate::NESTING_LIMIT`] levels.
    HG0012,
    /// More than [`crate::MAX_SYNTAX_ERRORS`] syntax errors in one file: the rest summarised.
    HG0013,
}

impl ErrorCode {
    /// Every syntax code, in order.
    pub const ALL: [ErrorCode; 13] = [
        ErrorCode::HG0001,
        ErrorCode::HG0002,
        ErrorCode::HG0003,
        ErrorCode::HG0004,
        ErrorCode::HG0005,
        ErrorCode::HG0006,
        ErrorCode::HG0007,
        ErrorCode::HG0008,
        ErrorCode::HG0009,
        ErrorCode::HG0010,
        ErrorCode::HG0011,
        ErrorCode::HG0012,
        ErrorCode::HG0013,
    ];

    /// The code as written in diagnostics: `"HG0001"`.
    pub fn as_str(self) -> &'static str {
        match self {
            ErrorCode::HG0001 => "HG0001",
            ErrorCode::HG0002 => "HG0002",
            ErrorCode::HG0003 => "HG0003",
            ErrorCode::HG0004 => "HG0004",
            ErrorCode::HG0005 => "HG0005",
            ErrorCode::HG0006 => "HG0006",
            ErrorCode::HG0007 => "HG0007",
            ErrorCode::HG0008 => "HG0008",
            ErrorCode::HG0009 => "HG0009",
            ErrorCode::HG0010 => "HG0010",
            ErrorCode::HG0011 => "HG0011",
            ErrorCode::HG0012 => "HG0012",
            ErrorCode::HG0013 => "HG0013",
        }
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A further location that explains a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Related {
    pub range: TextRange,
    pub message: String,
}

/// One text replacement of a quick fix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextEdit {
    pub range: TextRange,
    pub new_text: String,
}

/// A quick fix: a title and the edits that implement it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fix {
    pub title: String,
    pub edits: Vec<TextEdit>,
}

/// A syntax diagnostic. Its severity is always `error`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyntaxError {
    pub code: ErrorCode,
    pub range: TextRange,
    pub message: String,
    pub related: Vec<Related>,
    pub fixes: Vec<Fix>,
}

impl SyntaxError {
    pub fn new(code: ErrorCode, range: TextRange, message: impl Into<String>) -> SyntaxError {
        SyntaxError {
            code,
            range,
            message: message.into(),
            related: Vec::new(),
            fixes: Vec::new(),
        }
    }

    pub fn with_related(mut self, range: TextRange, message: impl Into<String>) -> SyntaxError {
        self.related.push(Related {
            range,
            message: message.into(),
        });
        self
    }

    pub fn with_fix(
        mut self,
        title: impl Into<String>,
        range: TextRange,
        new_text: impl Into<String>,
    ) -> SyntaxError {
        self.fixes.push(Fix {
            title: title.into(),
            edits: vec![TextEdit {
                range,
                new_text: new_text.into(),
            }],
        });
        self
    }

    /// A fix with several edits (ranges in the original text, not overlapping).
    pub fn with_fix_edits(
        mut self,
        title: impl Into<String>,
        edits: Vec<(TextRange, String)>,
    ) -> SyntaxError {
        self.fixes.push(Fix {
            title: title.into(),
            edits: edits
                .into_iter()
                .map(|(range, new_text)| TextEdit { range, new_text })
                .collect(),
        });
        self
    }
}

impl SyntaxError {
    /// The error with every range (primary, related, fixes) mapped by `f`; `None` if `f`
    /// refuses one of them.
    pub fn try_map_ranges(
        &self,
        mut f: impl FnMut(TextRange) -> Option<TextRange>,
    ) -> Option<SyntaxError> {
        let mut out = self.clone();
        out.range = f(out.range)?;
        for related in &mut out.related {
            related.range = f(related.range)?;
        }
        for edit in out.fixes.iter_mut().flat_map(|fix| &mut fix.edits) {
            edit.range = f(edit.range)?;
        }
        Some(out)
    }

    /// The error with every range moved right by `offset`.
    pub fn shifted(self, offset: TextSize) -> SyntaxError {
        match self.try_map_ranges(|r| Some(r + offset)) {
            Some(shifted) => shifted,
            None => self,
        }
    }
}

impl fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}@{:?}: {}", self.code, self.range, self.message)
    }
}

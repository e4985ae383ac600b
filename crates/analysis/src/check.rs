//! The diagnostics of one file. Today these are the file-level problems (HG6102, HG6103) and
//! the syntax errors; the salsa database will compute the same per file, adding the semantic
//! rules over the whole workspace.

use higraph_syntax::{TextRange, TextSize};

use crate::{Code, Diagnostic, FileContents, FileId, Severity};

/// All diagnostics of the file `file`, in text order.
///
/// A file that is not valid UTF-8 or cannot be read gets only its HG6102 or HG6103 diagnostic:
/// its text is not parsed, so the replacement characters do not cascade into syntax errors.
pub fn file_diagnostics(file: FileId, contents: &FileContents) -> Vec<Diagnostic> {
    match contents {
        FileContents::Text(text) => higraph_syntax::parse(text)
            .errors()
            .iter()
            .map(|error| Diagnostic::from_syntax_error(file, error))
            .collect(),
        FileContents::NotUtf8 {
            invalid_offset,
            invalid_len,
            ..
        } => {
            // HG6102: the range is the first invalid byte sequence; in the decoded text every
            // invalid byte is one U+FFFD.
            let start = size(*invalid_offset);
            let len = size(invalid_len * char::REPLACEMENT_CHARACTER.len_utf8());
            vec![Diagnostic::new(
                Code::INVALID_UTF8,
                Severity::Error,
                TextRange::at(start, len),
                format!("file is not valid UTF-8 (invalid byte at offset {invalid_offset})"),
            )]
        }
        FileContents::Unreadable { reason } => vec![Diagnostic::new(
            Code::UNREADABLE_FILE,
            Severity::Error,
            TextRange::empty(TextSize::from(0)),
            format!("cannot read file: {reason}"),
        )],
    }
}

fn size(n: usize) -> TextSize {
    TextSize::from(u32::try_from(n).unwrap_or(u32::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LineIndex;

    #[test]
    fn invalid_utf8_points_at_the_first_bad_byte() {
        let contents = FileContents::from_bytes(b"// \xF0\x9F\x98\x80\nx \xE4\xE4 y".to_vec());
        let diagnostics = file_diagnostics(FileId(0), &contents);
        assert_eq!(diagnostics.len(), 1);
        let d = &diagnostics[0];
        assert_eq!(d.code.as_str(), "HG6102");
        assert_eq!(
            d.message,
            "file is not valid UTF-8 (invalid byte at offset 10)"
        );
        let index = LineIndex::new(contents.text());
        assert_eq!(
            index.utf16_position(d.range.start()),
            crate::Position::new(1, 2)
        );
        assert_eq!(
            index.utf16_position(d.range.end()),
            crate::Position::new(1, 3)
        );
    }

    #[test]
    fn unreadable_file_is_zero_width_at_the_start() {
        let diagnostics = file_diagnostics(
            FileId(0),
            &FileContents::unreadable("Is a directory (os error 21)"),
        );
        assert_eq!(diagnostics[0].code, Code::UNREADABLE_FILE);
        assert_eq!(diagnostics[0].range, TextRange::empty(0.into()));
        assert_eq!(
            diagnostics[0].message,
            "cannot read file: Is a directory (os error 21)"
        );
    }

    #[test]
    fn syntax_errors_are_reported() {
        let diagnostics = file_diagnostics(FileId(0), &FileContents::Text("a $".into()));
        assert!(
            diagnostics.iter().any(|d| d.code.as_str() == "HG0009"),
            "{diagnostics:?}"
        );
        assert!(diagnostics.iter().all(|d| d.severity == Severity::Error));
        assert!(file_diagnostics(FileId(0), &FileContents::Text("// fine\n".into())).is_empty());
    }
}

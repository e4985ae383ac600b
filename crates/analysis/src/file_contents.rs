//! What the analysis knows about one file's contents: its text, or why there is no usable
//! text. Reading files is the caller's job; this module only decodes bytes it is handed.

/// The contents of one file as the analysis sees them.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum FileContents {
    /// Valid UTF-8 text (a leading byte-order mark is kept as part of the text).
    Text(String),
    /// Bytes that are not valid UTF-8 (HG6102). `text` is the bytes with every invalid byte
    /// replaced by U+FFFD, so each invalid byte counts as one character.
    NotUtf8 {
        /// The decoded text, one U+FFFD per invalid byte.
        text: String,
        /// Byte offset, in the original bytes, of the first invalid sequence.
        invalid_offset: usize,
        /// Length in bytes of the first invalid sequence.
        invalid_len: usize,
    },
    /// The file could not be read (HG6103): permissions, vanished, a directory.
    Unreadable {
        /// Why, as the operating system put it.
        reason: String,
    },
}

impl FileContents {
    /// Decodes the bytes of a file.
    pub fn from_bytes(bytes: Vec<u8>) -> FileContents {
        match String::from_utf8(bytes) {
            Ok(text) => FileContents::Text(text),
            Err(error) => {
                let utf8_error = error.utf8_error();
                let invalid_offset = utf8_error.valid_up_to();
                let bytes = error.into_bytes();
                let invalid_len = utf8_error
                    .error_len()
                    .unwrap_or(bytes.len() - invalid_offset);
                FileContents::NotUtf8 {
                    text: decode_per_byte(&bytes),
                    invalid_offset,
                    invalid_len,
                }
            }
        }
    }

    /// A file that could not be read, with the reason.
    pub fn unreadable(reason: impl Into<String>) -> FileContents {
        FileContents::Unreadable {
            reason: reason.into(),
        }
    }

    /// The text positions refer to: the decoded text, or empty for an unreadable file.
    pub fn text(&self) -> &str {
        match self {
            FileContents::Text(text) | FileContents::NotUtf8 { text, .. } => text,
            FileContents::Unreadable { .. } => "",
        }
    }
}

/// UTF-8 decoding that replaces every invalid byte (not every invalid sequence) with U+FFFD.
fn decode_per_byte(mut bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len());
    loop {
        match std::str::from_utf8(bytes) {
            Ok(valid) => {
                text.push_str(valid);
                return text;
            }
            Err(error) => {
                let (valid, rest) = bytes.split_at(error.valid_up_to());
                // `valid` is valid UTF-8 by construction.
                text.push_str(std::str::from_utf8(valid).unwrap_or_default());
                let invalid = error.error_len().unwrap_or(rest.len());
                text.extend(std::iter::repeat_n(char::REPLACEMENT_CHARACTER, invalid));
                bytes = &rest[invalid..];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn valid_text_is_kept() {
        assert_eq!(FileContents::from_bytes(b"graph".to_vec()).text(), "graph");
        let bom = "\u{FEFF}graph".as_bytes().to_vec();
        assert_eq!(
            FileContents::from_bytes(bom),
            FileContents::Text("\u{FEFF}graph".into())
        );
    }

    #[test]
    fn every_invalid_byte_is_one_character() {
        let contents = FileContents::from_bytes(b"ab\xE4\xFF\ncd\xC3".to_vec());
        assert_eq!(
            contents,
            FileContents::NotUtf8 {
                text: "ab\u{FFFD}\u{FFFD}\ncd\u{FFFD}".into(),
                invalid_offset: 2,
                invalid_len: 1,
            }
        );
    }

    #[test]
    fn truncated_sequence_at_the_end() {
        let contents = FileContents::from_bytes(b"ab\xF0\x9F".to_vec());
        assert_eq!(
            contents,
            FileContents::NotUtf8 {
                text: "ab\u{FFFD}\u{FFFD}".into(),
                invalid_offset: 2,
                invalid_len: 2,
            }
        );
    }
}

//! Windows-1252 text with CR LF line ends, as STEP 7 reads its external sources and symbol
//! tables. A character Windows-1252 cannot hold is refused (an error naming the character and
//! its line), never replaced: a silently changed name or comment would be a different program.
//! The encoding itself is `encoding_rs`'s.

use std::fmt;

/// A character that Windows-1252 cannot encode.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unencodable {
    pub ch: char,
    /// 1-based line of the text handed in.
    pub line: usize,
}

impl fmt::Display for Unencodable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}: the character '{}' (U+{:04X}) has no Windows-1252 encoding",
            self.line, self.ch, self.ch as u32
        )
    }
}

impl std::error::Error for Unencodable {}

/// `text` (lines ending in `\n`, or a lone final line) as Windows-1252 bytes with CR LF line
/// ends. A `\r` already before a `\n` is kept as the one CR.
pub fn encode(text: &str) -> Result<Vec<u8>, Unencodable> {
    let mut out = Vec::with_capacity(text.len() + text.len() / 16);
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let (body, newline) = match line.strip_suffix('\n') {
            Some(body) => (body.strip_suffix('\r').unwrap_or(body), true),
            None => (line, false),
        };
        let (bytes, _, unmappable) = encoding_rs::WINDOWS_1252.encode(body);
        if unmappable {
            let ch = body
                .chars()
                .find(|&c| {
                    let mut buf = [0u8; 4];
                    encoding_rs::WINDOWS_1252.encode(c.encode_utf8(&mut buf)).2
                })
                .unwrap_or('\u{FFFD}');
            return Err(Unencodable { ch, line: i + 1 });
        }
        out.extend_from_slice(&bytes);
        if newline {
            out.extend_from_slice(b"\r\n");
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crlf_and_windows_1252() {
        let bytes = encode("a ä €\nb\r\nc").unwrap();
        assert_eq!(bytes, b"a \xe4 \x80\r\nb\r\nc");
    }

    #[test]
    fn refuses_what_it_cannot_encode() {
        let err = encode("ok\nStart \u{2192} Stop\n").unwrap_err();
        assert_eq!(
            err,
            Unencodable {
                ch: '\u{2192}',
                line: 2
            }
        );
        assert!(encode("\u{4E2D}").is_err());
    }
}

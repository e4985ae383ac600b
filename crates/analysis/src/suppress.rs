//! Inline suppression (`diagnostics.md` §1.4b): a comment `// higraph-allow: LIST` suppresses
//! the listed codes (`HGnnnn`, `HGnnxx`, `HGnxxx`) on its own line and the next. Unknown or
//! malformed codes in the list are reported as HG6104.

use higraph_syntax::{Parse, SyntaxKind, TextRange, TextSize};

use crate::{LineIndex, registry};

/// One `higraph-allow` comment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Allow {
    /// 0-based line of the comment.
    pub line: u32,
    /// Code patterns: `HG2105`, `HG21xx`, `HG2xxx`.
    pub patterns: Vec<String>,
}

/// A code in a `higraph-allow` comment that names no rule (HG6104).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownCode {
    pub range: TextRange,
    pub code: String,
}

/// The `higraph-allow` comments of a file.
///
/// `text` is the parsed text: a file without the marker is not walked at all.
pub fn allows(text: &str, parse: &Parse, line_index: &LineIndex) -> (Vec<Allow>, Vec<UnknownCode>) {
    let mut allows = Vec::new();
    let mut unknown = Vec::new();
    if !may_allow(text) {
        return (allows, unknown);
    }
    for token in parse
        .syntax_node()
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
    {
        if token.kind() != SyntaxKind::COMMENT {
            continue;
        }
        let text = token.text();
        let body = text.trim_start_matches('/').trim_start();
        let Some(list) = body.strip_prefix("higraph-allow:") else {
            continue;
        };
        let list_offset = text.len() - list.len();
        let start = token.text_range().start();
        let mut patterns = Vec::new();
        let mut offset = list_offset;
        for part in list.split(',') {
            let trimmed = part.trim();
            let lead = part.len() - part.trim_start().len();
            let range = TextRange::at(
                start + TextSize::from((offset + lead) as u32),
                TextSize::from(trimmed.len() as u32),
            );
            offset += part.len() + 1;
            if trimmed.is_empty() {
                continue;
            }
            if is_known_pattern(trimmed) {
                patterns.push(trimmed.to_ascii_uppercase());
            } else {
                unknown.push(UnknownCode {
                    range,
                    code: trimmed.to_owned(),
                });
            }
        }
        let line = line_index.utf16_position(start).line;
        allows.push(Allow { line, patterns });
    }
    (allows, unknown)
}

/// `HGnnnn` naming a rule, or `HGnnxx` / `HGnxxx` naming a range that has rules.
fn is_known_pattern(code: &str) -> bool {
    let upper = code.to_ascii_uppercase();
    let bytes = upper.as_bytes();
    if bytes.len() != 6 || !upper.starts_with("HG") {
        return false;
    }
    let tail = &upper[2..];
    let digits = tail.trim_end_matches('X');
    let wildcards = tail.len() - digits.len();
    if !digits.bytes().all(|b| b.is_ascii_digit())
        || !(wildcards == 0 || wildcards == 2 || wildcards == 3)
    {
        return false;
    }
    registry::RULES
        .iter()
        .any(|r| matches(&upper, r.code.as_str()))
}

/// Does a pattern match a code? (`HG21xx` matches `HG2105`.)
pub fn matches(pattern: &str, code: &str) -> bool {
    pattern.len() == code.len()
        && pattern
            .bytes()
            .zip(code.bytes())
            .all(|(p, c)| p == b'X' || p == b'x' || p.eq_ignore_ascii_case(&c))
}

/// Can the text have a `higraph-allow` comment at all? (A fast scan that lets files without
/// one skip the rest.)
pub fn may_allow(text: &str) -> bool {
    text.contains("higraph-allow:")
}

/// Is a diagnostic of `code` starting on `line` suppressed?
pub fn is_suppressed(allows: &[Allow], code: &str, line: u32) -> bool {
    !registry::is_syntax_code(code)
        && allows.iter().any(|a| {
            (line == a.line || line == a.line + 1) && a.patterns.iter().any(|p| matches(p, code))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns() {
        assert!(is_known_pattern("HG2105"));
        assert!(is_known_pattern("HG21xx"));
        assert!(is_known_pattern("hg4xxx"));
        assert!(!is_known_pattern("HG9999"));
        assert!(!is_known_pattern("HG2x05"));
        assert!(!is_known_pattern("HG210"));
        assert!(matches("HG21XX", "HG2105"));
        assert!(!matches("HG21XX", "HG2205"));
    }

    #[test]
    fn finds_allow_comments() {
        let text = "graph G < > // higraph-allow: HG2201, HG97xx\n";
        let parse = higraph_syntax::parse(text);
        let (allows, unknown) = allows(text, &parse, &LineIndex::new(text));
        assert_eq!(allows.len(), 1);
        assert_eq!(allows[0].patterns, vec!["HG2201".to_owned()]);
        assert_eq!(unknown.len(), 1);
        assert_eq!(
            &text[std::ops::Range::<usize>::from(unknown[0].range)],
            "HG97xx"
        );
        assert!(is_suppressed(&allows, "HG2201", 1));
        assert!(!is_suppressed(&allows, "HG2201", 2));
    }
}

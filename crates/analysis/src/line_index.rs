//! Conversion between byte offsets and line/column positions.
//!
//! Lines end at LF, at CR LF (one break) or at a lone CR (`diagnostics.md` §4.1). Columns can be
//! counted in UTF-8 bytes, UTF-16 code units (LSP's default and the JSON output) or Unicode
//! scalar values (the human output, 1-based). A tab counts as one unit in every encoding.
//! Conversions clamp out-of-range input and never panic.

use higraph_syntax::TextSize;

mod edit;

/// How the columns of a [`Position`] are counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PositionEncoding {
    /// UTF-8 code units (bytes).
    Utf8,
    /// UTF-16 code units: a character outside the Basic Multilingual Plane counts 2.
    Utf16,
    /// Unicode scalar values ("characters").
    Utf32,
}

/// A 0-based line and a 0-based column, counted in some [`PositionEncoding`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Position {
    /// 0-based line number.
    pub line: u32,
    /// 0-based column in the units of the encoding used to produce or read it.
    pub column: u32,
}

impl Position {
    /// A position from a 0-based line and column.
    pub const fn new(line: u32, column: u32) -> Position {
        Position { line, column }
    }
}

/// A 1-based line and a 1-based column counted in characters (Unicode scalar values), as
/// printed by the human-readable outputs (`path:line:col`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LineColumn {
    /// 1-based line number.
    pub line: u32,
    /// 1-based column, in characters.
    pub column: u32,
}

/// A non-ASCII character: where it starts and how many bytes it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct WideChar {
    start: TextSize,
    len_utf8: u8,
}

impl WideChar {
    fn end(self) -> TextSize {
        self.start + TextSize::from(u32::from(self.len_utf8))
    }

    fn len_in(self, encoding: PositionEncoding) -> u32 {
        match encoding {
            PositionEncoding::Utf8 => u32::from(self.len_utf8),
            // Four UTF-8 bytes encode a character outside the BMP: a surrogate pair.
            PositionEncoding::Utf16 if self.len_utf8 == 4 => 2,
            PositionEncoding::Utf16 | PositionEncoding::Utf32 => 1,
        }
    }
}

/// Maps byte offsets of one text to line/column positions and back.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct LineIndex {
    /// Offset of the first byte of each line. Always non-empty; the first entry is 0.
    line_starts: Vec<TextSize>,
    /// Offset of the end of each line's content, before its line break.
    line_ends: Vec<TextSize>,
    /// Every non-ASCII character, in text order.
    wide_chars: Vec<WideChar>,
    /// Length of the text.
    len: TextSize,
}

impl LineIndex {
    /// Indexes `text`.
    pub fn new(text: &str) -> LineIndex {
        let mut line_starts = vec![TextSize::from(0)];
        let mut line_ends = Vec::new();
        let mut wide_chars = Vec::new();
        let bytes = text.as_bytes();
        let mut i = 0usize;
        // Work on bytes for the line breaks; non-ASCII characters are recorded by their lead
        // byte, whose value gives their length.
        while i < bytes.len() {
            let b = bytes[i];
            match b {
                b'\n' | b'\r' => {
                    line_ends.push(offset(i));
                    let break_len = if b == b'\r' && bytes.get(i + 1) == Some(&b'\n') {
                        2
                    } else {
                        1
                    };
                    i += break_len;
                    line_starts.push(offset(i));
                }
                0x00..=0x7F => i += 1,
                _ => {
                    let len_utf8 = utf8_len(b);
                    wide_chars.push(WideChar {
                        start: offset(i),
                        len_utf8,
                    });
                    i += usize::from(len_utf8);
                }
            }
        }
        line_ends.push(offset(bytes.len()));
        LineIndex {
            line_starts,
            line_ends,
            wide_chars,
            len: offset(bytes.len()),
        }
    }

    /// The number of lines (a text ending in a line break has an empty last line).
    pub fn line_count(&self) -> u32 {
        self.line_starts.len() as u32
    }

    /// The length of the indexed text in bytes.
    pub fn len(&self) -> TextSize {
        self.len
    }

    /// Whether the indexed text is empty.
    pub fn is_empty(&self) -> bool {
        self.len == TextSize::from(0)
    }

    /// The byte range of a 0-based line's content, without its line break; `None` past the
    /// last line.
    pub fn line_range(&self, line: u32) -> Option<higraph_syntax::TextRange> {
        let line = line as usize;
        let start = *self.line_starts.get(line)?;
        let end = *self.line_ends.get(line)?;
        Some(higraph_syntax::TextRange::new(start, end))
    }

    /// The 0-based line that contains `offset` (clamped to the text).
    pub fn line_of(&self, offset: TextSize) -> u32 {
        let offset = offset.min(self.len);
        // The last line whose start is at or before `offset`.
        (self.line_starts.partition_point(|&start| start <= offset) - 1) as u32
    }

    /// The position of `offset`, with the column counted in `encoding`.
    ///
    /// An offset past the end maps to the end of the text, one inside a line break to the end
    /// of that line's content, one inside a multi-byte character to that character's start.
    pub fn position(&self, offset: TextSize, encoding: PositionEncoding) -> Position {
        let line = self.line_of(offset);
        let start = self.line_starts[line as usize];
        let end = self.line_ends[line as usize];
        let offset = self.floor_char_boundary(offset.min(end));
        let bytes = u32::from(offset - start);
        let column = if encoding == PositionEncoding::Utf8 {
            bytes
        } else {
            let shrink: u32 = self
                .wide_chars_in(start, offset)
                .iter()
                .map(|wide| u32::from(wide.len_utf8) - wide.len_in(encoding))
                .sum();
            bytes - shrink
        };
        Position { line, column }
    }

    /// The 0-based line and 0-based UTF-16 column of `offset` (LSP's default encoding and the
    /// unit of the JSON output).
    pub fn utf16_position(&self, offset: TextSize) -> Position {
        self.position(offset, PositionEncoding::Utf16)
    }

    /// The 0-based line and 0-based UTF-8 (byte) column of `offset`.
    pub fn utf8_position(&self, offset: TextSize) -> Position {
        self.position(offset, PositionEncoding::Utf8)
    }

    /// The 1-based line and 1-based character column of `offset`, as the human outputs print
    /// them.
    pub fn line_column(&self, offset: TextSize) -> LineColumn {
        let Position { line, column } = self.position(offset, PositionEncoding::Utf32);
        LineColumn {
            line: line + 1,
            column: column + 1,
        }
    }

    /// The byte offset of `position`, whose column is counted in `encoding`.
    ///
    /// A line past the last one maps to the end of the text; a column past the end of its line
    /// maps to the end of the line's content; a column inside a character (for example between
    /// the two halves of a UTF-16 surrogate pair) maps to the start of that character.
    pub fn offset(&self, position: Position, encoding: PositionEncoding) -> TextSize {
        let line = position.line as usize;
        let (Some(&start), Some(&end)) = (self.line_starts.get(line), self.line_ends.get(line))
        else {
            return self.len;
        };
        let mut remaining = position.column;
        let mut cursor = start;
        for wide in self.wide_chars_in(start, end) {
            let ascii_run = u32::from(wide.start - cursor);
            if remaining < ascii_run {
                return cursor + TextSize::from(remaining);
            }
            remaining -= ascii_run;
            let units = wide.len_in(encoding);
            if remaining < units {
                return wide.start;
            }
            remaining -= units;
            cursor = wide.end();
        }
        let tail = u32::from(end - cursor);
        cursor + TextSize::from(remaining.min(tail))
    }

    /// The byte offset of a 0-based line and 0-based UTF-16 column (clamped).
    pub fn offset_utf16(&self, position: Position) -> TextSize {
        self.offset(position, PositionEncoding::Utf16)
    }

    /// The byte offset of a 0-based line and 0-based UTF-8 column (clamped).
    pub fn offset_utf8(&self, position: Position) -> TextSize {
        self.offset(position, PositionEncoding::Utf8)
    }

    /// The non-ASCII characters that start in `start..end`.
    fn wide_chars_in(&self, start: TextSize, end: TextSize) -> &[WideChar] {
        let from = self.wide_chars.partition_point(|wide| wide.start < start);
        let to = self.wide_chars.partition_point(|wide| wide.start < end);
        &self.wide_chars[from..to.max(from)]
    }

    /// `offset` moved back to the start of the character it falls into.
    fn floor_char_boundary(&self, offset: TextSize) -> TextSize {
        let i = self.wide_chars.partition_point(|wide| wide.start <= offset);
        match i.checked_sub(1).map(|i| self.wide_chars[i]) {
            Some(wide) if offset < wide.end() => wide.start,
            _ => offset,
        }
    }
}

fn offset(i: usize) -> TextSize {
    TextSize::from(u32::try_from(i).unwrap_or(u32::MAX))
}

/// The length of a UTF-8 sequence from its lead byte (the text is valid UTF-8).
fn utf8_len(lead: u8) -> u8 {
    match lead {
        0xF0..=0xFF => 4,
        0xE0..=0xEF => 3,
        _ => 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utf16(index: &LineIndex, offset: u32) -> (u32, u32) {
        let p = index.utf16_position(TextSize::from(offset));
        (p.line, p.column)
    }

    fn human(index: &LineIndex, offset: u32) -> (u32, u32) {
        let p = index.line_column(TextSize::from(offset));
        (p.line, p.column)
    }

    fn back16(index: &LineIndex, line: u32, column: u32) -> u32 {
        index.offset_utf16(Position::new(line, column)).into()
    }

    fn back8(index: &LineIndex, line: u32, column: u32) -> u32 {
        index.offset_utf8(Position::new(line, column)).into()
    }

    #[test]
    fn lf_lines() {
        let index = LineIndex::new("ab\ncd\n");
        assert_eq!(index.line_count(), 3);
        assert_eq!(utf16(&index, 0), (0, 0));
        assert_eq!(utf16(&index, 2), (0, 2));
        assert_eq!(utf16(&index, 3), (1, 0));
        assert_eq!(utf16(&index, 6), (2, 0));
        assert_eq!(human(&index, 4), (2, 2));
        assert_eq!(back16(&index, 1, 1), 4);
        assert_eq!(back16(&index, 2, 0), 6);
    }

    #[test]
    fn cr_lf_is_one_break() {
        let text = "ab\r\ncd\r\n";
        let index = LineIndex::new(text);
        assert_eq!(index.line_count(), 3);
        assert_eq!(utf16(&index, 4), (1, 0));
        assert_eq!(utf16(&index, 6), (1, 2));
        // Inside the break: the end of the line's content.
        assert_eq!(utf16(&index, 3), (0, 2));
        assert_eq!(utf16(&index, 7), (1, 2));
        assert_eq!(utf16(&index, 8), (2, 0));
        assert_eq!(back16(&index, 1, 0), 4);
        assert_eq!(back16(&index, 0, 99), 2);
        assert_eq!(
            index.line_range(1),
            Some(higraph_syntax::TextRange::new(4.into(), 6.into()))
        );
    }

    #[test]
    fn lone_cr_is_a_break() {
        let index = LineIndex::new("a\rb\r\rc");
        assert_eq!(index.line_count(), 4);
        assert_eq!(utf16(&index, 2), (1, 0));
        assert_eq!(utf16(&index, 4), (2, 0));
        assert_eq!(utf16(&index, 5), (3, 0));
        assert_eq!(human(&index, 5), (4, 1));
        assert_eq!(back16(&index, 3, 1), 6);
    }

    #[test]
    fn lf_cr_is_two_breaks() {
        let index = LineIndex::new("a\n\rb");
        assert_eq!(index.line_count(), 3);
        assert_eq!(utf16(&index, 3), (2, 0));
    }

    #[test]
    fn astral_chars_count_two_utf16_units() {
        let text = "x \"😀\" $";
        let dollar = text.find('$').unwrap() as u32;
        let index = LineIndex::new(text);
        assert_eq!(utf16(&index, dollar), (0, 7));
        assert_eq!(human(&index, dollar), (1, 7));
        assert_eq!(
            index.utf8_position(TextSize::from(dollar)),
            Position::new(0, 9)
        );
        assert_eq!(back16(&index, 0, 7), dollar);
        assert_eq!(back8(&index, 0, 9), dollar);
        // Between the two halves of the surrogate pair: the start of the character.
        assert_eq!(back16(&index, 0, 4), 3);
        assert_eq!(back16(&index, 0, 5), 7);
        // Inside the four UTF-8 bytes: the start of the character.
        assert_eq!(utf16(&index, 5), (0, 3));
        assert_eq!(
            index.offset(Position::new(0, 4), PositionEncoding::Utf32),
            7.into()
        );
    }

    #[test]
    fn umlauts_count_one_unit() {
        let text = "// Schütze ä\nÖl $";
        let index = LineIndex::new(text);
        let a = text.find('ä').unwrap() as u32;
        assert_eq!(utf16(&index, a), (0, 11));
        assert_eq!(human(&index, a), (1, 12));
        let dollar = text.find('$').unwrap() as u32;
        assert_eq!(utf16(&index, dollar), (1, 3));
        assert_eq!(human(&index, dollar), (2, 4));
        assert_eq!(back16(&index, 1, 3), dollar);
        assert_eq!(back8(&index, 1, 4), dollar);
        // A UTF-8 column inside `Ö` rounds down to its start.
        assert_eq!(back8(&index, 1, 1), dollar - 4);
    }

    #[test]
    fn tab_counts_one() {
        let index = LineIndex::new("\t\tx");
        assert_eq!(utf16(&index, 2), (0, 2));
        assert_eq!(human(&index, 2), (1, 3));
    }

    #[test]
    fn bom_counts_as_a_character() {
        let index = LineIndex::new("\u{FEFF}a");
        assert_eq!(utf16(&index, 3), (0, 1));
    }

    #[test]
    fn out_of_range_is_clamped() {
        let index = LineIndex::new("ab\ncd");
        assert_eq!(utf16(&index, 100), (1, 2));
        assert_eq!(back16(&index, 7, 0), 5);
        assert_eq!(back16(&index, 0, 100), 2);
        assert_eq!(back8(&index, 1, u32::MAX), 5);
        assert_eq!(index.line_range(2), None);
    }

    #[test]
    fn empty_text() {
        let index = LineIndex::new("");
        assert!(index.is_empty());
        assert_eq!(index.line_count(), 1);
        assert_eq!(utf16(&index, 0), (0, 0));
        assert_eq!(human(&index, 0), (1, 1));
        assert_eq!(back16(&index, 0, 5), 0);
    }

    #[test]
    fn round_trip_every_boundary() {
        let text = "a😀ü\r\n\tß\rx\n€\u{10FFFF}";
        let index = LineIndex::new(text);
        for (offset, _) in text.char_indices().chain([(text.len(), ' ')]) {
            let offset = TextSize::from(offset as u32);
            for encoding in [
                PositionEncoding::Utf8,
                PositionEncoding::Utf16,
                PositionEncoding::Utf32,
            ] {
                let position = index.position(offset, encoding);
                let back = index.offset(position, encoding);
                // Offsets inside a line break map to the end of the line's content.
                let in_break = text[..usize::from(offset)].ends_with('\r')
                    && text[usize::from(offset)..].starts_with('\n');
                if !in_break {
                    assert_eq!(back, offset, "{encoding:?} {offset:?} {position:?}");
                }
            }
        }
    }
}

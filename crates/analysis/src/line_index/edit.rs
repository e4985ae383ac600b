//! Updating a [`LineIndex`] after an edit without indexing the whole text again: only the
//! lines around the edit are scanned, the entries after it are shifted. The language server
//! keeps one index per open document this way, so a keystroke costs a few lines, not the file.

use higraph_syntax::{TextRange, TextSize};

use super::{LineIndex, WideChar, offset, utf8_len};

impl LineIndex {
    /// Updates the index of a text after `delete` (a range of the old text) was replaced,
    /// giving `new_text`. The result equals `LineIndex::new(new_text)`; when the arguments do
    /// not describe an edit of the indexed text, the index is built from `new_text` again.
    pub fn apply_edit(&mut self, delete: TextRange, new_text: &str) {
        if !self.try_apply_edit(delete, new_text) {
            *self = LineIndex::new(new_text);
        }
    }

    /// [`LineIndex::apply_edit`]; `false` if the arguments do not fit (nothing changed then).
    fn try_apply_edit(&mut self, delete: TextRange, new_text: &str) -> bool {
        let old_len = u32::from(self.len) as usize;
        let (start, end) = (
            u32::from(delete.start()) as usize,
            u32::from(delete.end()) as usize,
        );
        let new_len = new_text.len();
        if end > old_len || new_len + (end - start) < old_len || u32::try_from(new_len).is_err() {
            return false;
        }
        let inserted = new_len + (end - start) - old_len;
        if !new_text.is_char_boundary(start) || !new_text.is_char_boundary(start + inserted) {
            return false;
        }
        // Rescan from the start of the line before the edit (a line break right before the
        // edit may join one it inserts: CR + LF) to the start of the second line after it (so
        // the line break ending the window lies wholly after the edit).
        let count = self.line_starts.len();
        let first = (self.line_of(delete.start()) as usize).saturating_sub(1);
        let after = self.line_of(delete.end()) as usize + 2;
        let window_start = u32::from(self.line_starts[first]) as usize;
        let old_window_end = match self.line_starts.get(after) {
            Some(&s) => u32::from(s) as usize,
            None => old_len,
        };
        let new_window_end = old_window_end + inserted - (end - start);
        let Some(window) = new_text.get(window_start..new_window_end) else {
            return false;
        };
        let mut starts = Vec::new();
        let mut ends = Vec::new();
        let mut wide = Vec::new();
        let bytes = window.as_bytes();
        let mut i = 0usize;
        while i < bytes.len() {
            let b = bytes[i];
            match b {
                b'\n' | b'\r' => {
                    ends.push(offset(window_start + i));
                    i += if b == b'\r' && bytes.get(i + 1) == Some(&b'\n') {
                        2
                    } else {
                        1
                    };
                    starts.push(offset(window_start + i));
                }
                0x00..=0x7F => i += 1,
                _ => {
                    let len_utf8 = utf8_len(b);
                    wide.push(WideChar {
                        start: offset(window_start + i),
                        len_utf8,
                    });
                    i += usize::from(len_utf8);
                }
            }
        }
        let reaches_end = after >= count;
        if !reaches_end && starts.last() != Some(&offset(new_window_end)) {
            // A line break straddles the end of the window (cannot happen for a real edit).
            return false;
        }
        let shift = |size: TextSize| offset(u32::from(size) as usize + new_len - old_len);
        // Lines `first + 1 ..= after` start inside the window (the last one at its end).
        let tail_starts: Vec<TextSize> = self
            .line_starts
            .get(after + 1..)
            .unwrap_or(&[])
            .iter()
            .map(|&s| shift(s))
            .collect();
        self.line_starts.truncate(first + 1);
        self.line_starts.extend(starts);
        self.line_starts.extend(tail_starts);
        let tail_ends: Vec<TextSize> = if reaches_end {
            vec![offset(new_len)]
        } else {
            self.line_ends[after..].iter().map(|&e| shift(e)).collect()
        };
        self.line_ends.truncate(first);
        self.line_ends.extend(ends);
        self.line_ends.extend(tail_ends);
        let old_window_end = offset(old_window_end);
        let keep = self
            .wide_chars
            .partition_point(|w| w.start < offset(window_start));
        let from = self
            .wide_chars
            .partition_point(|w| w.start < old_window_end);
        let tail_wide: Vec<WideChar> = self.wide_chars[from..]
            .iter()
            .map(|w| WideChar {
                start: shift(w.start),
                len_utf8: w.len_utf8,
            })
            .collect();
        self.wide_chars.truncate(keep);
        self.wide_chars.extend(wide);
        self.wide_chars.extend(tail_wide);
        self.len = offset(new_len);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Applies `insert` over `start..end` of `text` both ways and compares.
    fn check(text: &str, start: usize, end: usize, insert: &str) {
        let mut index = LineIndex::new(text);
        let mut new_text = text.to_owned();
        new_text.replace_range(start..end, insert);
        let applied = index.try_apply_edit(TextRange::new(offset(start), offset(end)), &new_text);
        assert!(
            applied,
            "{text:?} with {start}..{end} replaced by {insert:?} did not fit"
        );
        assert_eq!(
            index,
            LineIndex::new(&new_text),
            "{text:?} with {start}..{end} replaced by {insert:?}"
        );
    }

    #[test]
    fn edits_match_a_fresh_index() {
        let texts = [
            "",
            "a",
            "ab\ncd\r\nef\rgh\n",
            "\r\r\n\n\r",
            "x\r",
            "\nü😀\r\nß\n\n€x\r",
            "graph A <\n  state S1 < >\n  trans T < UN x; >\n>\n",
        ];
        let inserts = ["", "x", "\n", "\r", "\r\n", "ü", "a\nb\rc", "😀\n"];
        for text in texts {
            let boundaries: Vec<usize> = (0..=text.len())
                .filter(|&i| text.is_char_boundary(i))
                .collect();
            for (i, &start) in boundaries.iter().enumerate() {
                for &end in &boundaries[i..] {
                    for insert in inserts {
                        check(text, start, end, insert);
                    }
                }
            }
        }
    }

    #[test]
    fn edits_that_do_not_fit_index_the_new_text() {
        let mut index = LineIndex::new("abc\n");
        index.apply_edit(TextRange::new(offset(2), offset(9)), "x\ny");
        assert_eq!(index, LineIndex::new("x\ny"));
        let mut index = LineIndex::new("abc\n");
        index.apply_edit(TextRange::new(offset(0), offset(1)), "ü");
        assert_eq!(index, LineIndex::new("ü"));
    }
}

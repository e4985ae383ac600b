//! Range formatting (`textDocument/rangeFormatting`): the canonical layout of `fmt` for the
//! top-level items a range touches, and nothing else. The formatter lays out the whole file
//! ([`format::format_items_with`]), so an item comes out exactly as full formatting writes it
//! (the file's mnemonic set, line endings and implicit priorities apply); the edits are the
//! small differences inside those items, and the text between items is left alone. A file
//! with syntax errors is refused, as for full formatting.

use higraph_syntax::TextRange;

use super::{Edit, relayout::minimal_edits};
use crate::{Analysis, Cancellable, format};

impl Analysis {
    /// The edits that give the top-level items `range` touches in `path` the canonical
    /// layout: sorted, non-overlapping, each inside one of those items (none when they are
    /// formatted already). `Err` with a message for the user when the file has syntax errors,
    /// is not text, or is not in the workspace; `Err(Cancelled)` as for
    /// [`Analysis::format_edits_with`].
    pub fn range_format_edits_with(
        &self,
        path: &str,
        range: TextRange,
        is_cancelled: &dyn Fn() -> bool,
    ) -> Cancellable<Result<Vec<Edit>, String>> {
        self.check_cancelled(is_cancelled)?;
        let Some(contents) = self.file_contents(path) else {
            return Ok(Err(format!("'{path}' is not a file of the workspace")));
        };
        let crate::FileContents::Text(text) = &*contents else {
            return Ok(Err(format!(
                "'{path}' cannot be formatted: it is not UTF-8 text"
            )));
        };
        let items =
            format::format_items_with(text, range, &|| self.check_cancelled(is_cancelled).is_err());
        if items == Err(format::FormatError::Cancelled) {
            return Err(salsa::Cancelled::Local);
        }
        self.check_cancelled(is_cancelled)?;
        Ok(match items {
            Ok(items) => Ok(items
                .into_iter()
                .flat_map(|(item, formatted)| {
                    let old = text.get(std::ops::Range::<usize>::from(item)).unwrap_or("");
                    minimal_edits(old, &formatted)
                        .into_iter()
                        .map(move |edit| Edit {
                            range: edit.range + item.start(),
                            new_text: edit.new_text,
                        })
                })
                .collect()),
            Err(error) => Err(format!("'{path}' cannot be formatted: {error}")),
        })
    }
}

#[cfg(test)]
mod tests {
    use higraph_syntax::TextSize;

    use super::*;
    use crate::ide::{fixture, relayout::apply};

    /// Two graphs, both out of layout, and a symbol table between them.
    const TEXT: &str = "graph A <\n    state 0 <  >\n  trans any->0 < U x; >\n>\n\n\
        // between\nsymbols <\n  S : E 0.0;\n  Long : E 0.1;\n>\n\n\
        graph B <\n  state 0 < >\n      state 1 < >\n  trans 0->1 < U y; >\n>\n";

    fn range_of(text: &str, from: &str, to: &str) -> TextRange {
        let start = text.find(from).expect("from");
        let end = text.find(to).expect("to") + to.len();
        TextRange::new(
            TextSize::try_from(start).expect("small"),
            TextSize::try_from(end).expect("small"),
        )
    }

    fn edits(text: &str, range: TextRange) -> Result<Vec<Edit>, String> {
        let f = fixture::load(&format!("//- main.higraph\n{text}"));
        f.host
            .analysis()
            .range_format_edits_with("main.higraph", range, &|| false)
            .expect("not cancelled")
    }

    /// The full formatting of `text` restricted to the items whose range in `text` overlaps
    /// `keep`: those items' formatted text, the rest as it was.
    fn full_restricted(text: &str, keep: &[&str]) -> String {
        let formatted = format::format(text).expect("formats");
        let items = |t: &str| -> Vec<TextRange> {
            higraph_syntax::parse(t)
                .syntax_node()
                .children()
                .map(|n| n.text_range())
                .collect()
        };
        let mut out = text.to_owned();
        let pairs: Vec<_> = items(text).into_iter().zip(items(&formatted)).collect();
        for (old, new) in pairs.into_iter().rev() {
            let old_text = &text[std::ops::Range::<usize>::from(old)];
            if keep.iter().any(|k| old_text.starts_with(k)) {
                out.replace_range(
                    std::ops::Range::<usize>::from(old),
                    &formatted[std::ops::Range::<usize>::from(new)],
                );
            }
        }
        out
    }

    #[test]
    fn a_range_inside_one_item_formats_that_item_only() {
        let range = range_of(TEXT, "state 1", "state 1");
        let edits = edits(TEXT, range).expect("formats");
        let b = range_of(TEXT, "graph B", "y; >\n>");
        assert!(!edits.is_empty());
        assert!(edits.iter().all(|e| b.contains_range(e.range)), "{edits:?}");
        let new = apply(TEXT, &edits).expect("applies");
        assert_eq!(new, full_restricted(TEXT, &["graph B"]));
        assert!(
            new.contains("  state 1 < >\n  trans 0->1 prio 1 < U y; >\n"),
            "{new}"
        );
        // Graph A and the table are as they were.
        assert!(new.starts_with("graph A <\n    state 0 <  >\n"), "{new}");
        assert!(new.contains("  S : E 0.0;\n"), "{new}");
        // Small edits, not the item.
        assert!(edits.iter().all(|e| e.new_text.len() < 30), "{edits:?}");
    }

    #[test]
    fn a_cursor_formats_the_item_it_is_in() {
        let at = range_of(TEXT, "Long", "Long").start();
        let edits = edits(TEXT, TextRange::empty(at)).expect("formats");
        let new = apply(TEXT, &edits).expect("applies");
        assert_eq!(new, full_restricted(TEXT, &["symbols"]));
        assert!(new.contains("  S    : E 0.0;\n"), "{new}");
    }

    #[test]
    fn a_range_across_items_formats_each_item_it_touches() {
        let range = range_of(TEXT, "trans any", "S : E");
        let edits = edits(TEXT, range).expect("formats");
        let new = apply(TEXT, &edits).expect("applies");
        assert_eq!(new, full_restricted(TEXT, &["graph A", "symbols"]));
        // Graph B is left alone; the comment between the items too.
        assert!(new.contains("      state 1 < >\n"), "{new}");
        assert!(new.contains(">\n\n// between\nsymbols <\n"), "{new}");
        // The whole file: equal to full formatting.
        let all = TextRange::up_to(TextSize::try_from(TEXT.len()).expect("small"));
        let new = apply(TEXT, &edits_of_all(all)).expect("applies");
        assert_eq!(Ok(new), format::format(TEXT));
    }

    fn edits_of_all(all: TextRange) -> Vec<Edit> {
        edits(TEXT, all).expect("formats")
    }

    #[test]
    fn range_formatting_is_idempotent() {
        let range = range_of(TEXT, "state 0", "Long");
        let once = apply(TEXT, &edits(TEXT, range).expect("formats")).expect("applies");
        let range = range_of(&once, "state 0", "Long");
        assert_eq!(edits(&once, range), Ok(Vec::new()));
        // A range that touches no item (the blank line between two) changes nothing.
        let gap = TextRange::empty(range_of(TEXT, "\n\n// between", "\n\n").end());
        assert_eq!(edits(TEXT, gap), Ok(Vec::new()));
    }

    #[test]
    fn a_file_with_syntax_errors_is_refused() {
        let broken = "graph A <\n    state 0 <  >\n>\ngraph B < state 0 < C: U a > >\n";
        let range = range_of(broken, "state 0", "state 0");
        assert_eq!(
            edits(broken, range),
            Err("'main.higraph' cannot be formatted: the file has a syntax error".to_owned())
        );
    }

    #[test]
    fn crlf_files_keep_their_line_breaks() {
        let text = TEXT.replace('\n', "\r\n");
        let range = range_of(&text, "state 1", "state 1");
        let new = apply(&text, &edits(&text, range).expect("formats")).expect("applies");
        assert!(
            new.contains("  state 1 < >\r\n  trans 0->1 prio 1"),
            "{new}"
        );
        assert!(!new.replace("\r\n", "").contains('\n'), "{new:?}");
    }
}

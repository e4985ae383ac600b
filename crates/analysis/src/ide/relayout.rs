//! Keeping formatted files formatted: the edits of a rename or a quick fix, re-laid-out
//! (`tooling.md` §2a). Renaming a formal to a longer name, for example, leaves the `:=` of the
//! instance's actuals out of line, and a CI that runs `fmt --check` would fail after any editor
//! rename. So, for each file a change edits:
//!
//! * if the whole file was formatted (the formatter's output is the file), the new text is
//!   formatted and the change becomes the difference between the old text and that;
//! * otherwise each top-level item the edits touch that was formatted on its own stays so: its
//!   new text is formatted and replaces it;
//! * an item that was not formatted, or whose new text cannot be formatted (a syntax error),
//!   keeps the edits as they are.
//!
//! Texts above [`MAX_RELAYOUT_LEN`] are not formatted (the edits stay as they are). The
//! difference is kept small, one edit per run of changed lines with the common start and
//! end of each run left out, so an editor applies a few small edits, not a new file. This is
//! done when an edit is asked for ([`crate::Analysis::rename`], [`crate::Analysis::code_actions`]),
//! not for the fixes every diagnostic carries.

use higraph_syntax::{TextRange, TextSize};

use super::{Edit, SourceChange, code_actions::line_diff};
use crate::{
    db::{File, Workspace},
    format,
};

/// The largest text (a file, or an item) that is formatted to re-lay-out an edit. Formatting
/// costs time proportional to the text at best, and code actions are asked for at every
/// cursor move. A larger file is re-laid-out item by item; a larger item (a generated graph of
/// thousands of members) keeps its edits as they are.
const MAX_RELAYOUT_LEN: usize = 32 * 1024;

/// `change` with the files it edits re-laid-out as described in the module documentation.
pub(crate) fn keep_formatted(
    db: &dyn salsa::Database,
    ws: Workspace,
    mut change: SourceChange,
) -> SourceChange {
    for (path, edits) in &mut change.files {
        let Some(&file) = ws.files(db).iter().find(|f| f.path(db) == path) else {
            continue;
        };
        if let Some(relaid) = relayout(db, file, edits) {
            *edits = relaid;
        }
    }
    change
}

/// Is the file in the canonical layout? Cached per text, as every quick fix of the file asks.
#[salsa::tracked]
pub(crate) fn is_formatted(db: &dyn salsa::Database, file: File) -> bool {
    let text = file.contents(db).text();
    text.len() <= MAX_RELAYOUT_LEN && format::format(text).is_ok_and(|formatted| formatted == text)
}

/// The re-laid-out edits of one file; `None` to keep the edits as they are.
fn relayout(db: &dyn salsa::Database, file: File, edits: &[Edit]) -> Option<Vec<Edit>> {
    let contents = file.contents(db);
    let crate::FileContents::Text(old) = &**contents else {
        return None;
    };
    let new = apply(old, edits)?;
    if *is_formatted(db, file) {
        let formatted = format::format(&new).ok()?;
        return Some(minimal_edits(old, &formatted));
    }
    relayout_items(old, edits)
}

/// The edits of a file that is not formatted as a whole: each touched item that was formatted
/// on its own is formatted again; the other edits stay.
fn relayout_items(old: &str, edits: &[Edit]) -> Option<Vec<Edit>> {
    let parse = higraph_syntax::parse(old);
    let items: Vec<TextRange> = parse
        .syntax_node()
        .children()
        .map(|item| item.text_range())
        .collect();
    let mut out = Vec::new();
    let mut rest = edits;
    for item in items {
        let before = rest.partition_point(|e| e.range.end() < item.start());
        out.extend_from_slice(&rest[..before]);
        rest = &rest[before..];
        let inside = rest.partition_point(|e| item.contains_range(e.range));
        let (touching, after) = rest.split_at(inside);
        rest = after;
        if touching.is_empty() {
            continue;
        }
        match relayout_item(old, item, touching) {
            Some(relaid) => out.extend(relaid),
            None => out.extend_from_slice(touching),
        }
    }
    out.extend_from_slice(rest);
    Some(out)
}

/// The edits of one item, re-laid-out if the item was formatted on its own.
fn relayout_item(old: &str, item: TextRange, edits: &[Edit]) -> Option<Vec<Edit>> {
    let item_old = old.get(std::ops::Range::<usize>::from(item))?;
    if item_old.len() > MAX_RELAYOUT_LEN {
        return None;
    }
    let formatted = format::format(item_old).ok()?;
    if formatted.strip_suffix('\n').unwrap_or(&formatted) != item_old {
        return None;
    }
    let local: Vec<Edit> = edits
        .iter()
        .map(|e| Edit {
            range: e.range - item.start(),
            new_text: e.new_text.clone(),
        })
        .collect();
    let item_new = apply(item_old, &local)?;
    let formatted = format::format(&item_new).ok()?;
    let formatted = formatted.strip_suffix('\n').unwrap_or(&formatted);
    Some(
        minimal_edits(item_old, formatted)
            .into_iter()
            .map(|e| Edit {
                range: e.range + item.start(),
                new_text: e.new_text,
            })
            .collect(),
    )
}

/// Applies sorted, non-overlapping edits; `None` if they are not or do not fit the text.
pub(crate) fn apply(text: &str, edits: &[Edit]) -> Option<String> {
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for edit in edits {
        let range = std::ops::Range::<usize>::from(edit.range);
        if range.start < at {
            return None;
        }
        out.push_str(text.get(at..range.start)?);
        out.push_str(&edit.new_text);
        at = range.end;
    }
    out.push_str(text.get(at..)?);
    Some(out)
}

/// The edits that turn `old` into `new`: one per run of changed lines, each without the text
/// its run starts and ends with in both versions.
pub(crate) fn minimal_edits(old: &str, new: &str) -> Vec<Edit> {
    let old_lines: Vec<&str> = old.split_inclusive('\n').collect();
    let new_lines: Vec<&str> = new.split_inclusive('\n').collect();
    let edits = if old_lines.len() == new_lines.len() {
        // The usual case after a rename: the lines correspond one to one (linear, where the
        // general line diff is quadratic in the changed middle).
        let mut edits = Vec::new();
        let mut at = 0;
        for (a, b) in old_lines.iter().zip(&new_lines) {
            if a != b {
                edits.push(Edit {
                    range: TextRange::at(size(at), size(a.len())),
                    new_text: (*b).to_owned(),
                });
            }
            at += a.len();
        }
        edits
    } else {
        line_diff(old, new)
    };
    edits.into_iter().map(|edit| trim(old, edit)).collect()
}

/// `edit` without the start and end it has in common with the text it replaces.
fn trim(old: &str, edit: Edit) -> Edit {
    let Some(replaced) = old.get(std::ops::Range::<usize>::from(edit.range)) else {
        return edit;
    };
    let new = edit.new_text.as_str();
    let prefix: usize = replaced
        .chars()
        .zip(new.chars())
        .take_while(|(a, b)| a == b)
        .map(|(a, _)| a.len_utf8())
        .sum();
    let suffix: usize = replaced[prefix..]
        .chars()
        .rev()
        .zip(new[prefix..].chars().rev())
        .take_while(|(a, b)| a == b)
        .map(|(a, _)| a.len_utf8())
        .sum();
    let start = edit.range.start() + size(prefix);
    let end = edit.range.end() - size(suffix);
    Edit {
        range: TextRange::new(start, end.max(start)),
        new_text: new[prefix..new.len() - suffix].to_owned(),
    }
}

fn size(n: usize) -> TextSize {
    TextSize::from(u32::try_from(n).unwrap_or(u32::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_edits_reproduce_the_new_text_with_small_edits() {
        let old = "a\n  Oben  := E 0.0;\n  Unten := E 0.1;\nz\n";
        let new = "a\n  ObenX := E 0.0;\n  Unten := E 0.1;\nz\n";
        let edits = minimal_edits(old, new);
        assert_eq!(apply(old, &edits).as_deref(), Some(new));
        assert_eq!(edits.len(), 1);
        assert_eq!(edits[0].new_text, "X");
        assert_eq!(edits[0].range, TextRange::new(8.into(), 9.into()));
        // Multi-byte characters are never split.
        let (old, new) = ("x äö y\n", "x äü y\n");
        let edits = minimal_edits(old, new);
        assert_eq!(apply(old, &edits).as_deref(), Some(new));
        assert_eq!(edits[0].new_text, "ü");
    }

    /// In a file that is not formatted as a whole, an item that was formatted stays so; an
    /// item that was not gets the rename's edits as they are.
    #[test]
    fn items_that_were_formatted_stay_formatted() {
        let group = "group Gr fc FC 1 db DB 1 <\n  instance V : Ventil <\n    Oben  := E 0.0;\n    Unten := E 0.1;\n  >\n>\n";
        let graph = "graph Ventil <\n  in < $0Oben : BOOL; Unten : BOOL; >\n  state 0 <  C: U Oben; U Unten; >\n  trans any->0 < U INIT_SD; >\n>\n";
        let f = crate::ide::fixture::load(&format!("//- main.higraph\n{group}\n{graph}"));
        let change = f
            .host
            .analysis()
            .rename(&f.position, "ObenLang")
            .expect("not cancelled")
            .expect("renamed");
        let (_, edits) = &change.files[0];
        let new = apply(f.text("main.higraph"), edits).expect("applies");
        // The group is aligned again; the graph keeps its two spaces after `<`.
        assert!(
            new.contains("    ObenLang := E 0.0;\n    Unten    := E 0.1;\n"),
            "{new}"
        );
        assert!(
            new.contains("state 0 <  C: U ObenLang; U Unten; >"),
            "{new}"
        );
        // Small edits, not the whole item.
        assert!(edits.iter().all(|e| e.new_text.len() < 40), "{edits:?}");
    }

    #[test]
    fn apply_refuses_overlapping_or_outside_edits() {
        let edit = |a: u32, b: u32| Edit {
            range: TextRange::new(a.into(), b.into()),
            new_text: String::new(),
        };
        assert_eq!(apply("abc", &[edit(0, 2), edit(1, 3)]), None);
        assert_eq!(apply("abc", &[edit(2, 9)]), None);
        assert_eq!(
            apply("abc", &[edit(0, 1), edit(1, 2)]).as_deref(),
            Some("c")
        );
    }
}

//! Incremental reparsing gives exactly what a full parse gives: the same tree and the same
//! diagnostics, for edits at every position inside the graph members of every fixture and
//! example file, and for random edits anywhere.

mod common;

use common::corpus;
use higraph_syntax::{Edit, Parse, SyntaxKind, TextRange, TextSize, parse};
use proptest::prelude::*;

/// Applies `edit` both ways and compares; returns whether the incremental path was taken.
fn check(old: &Parse, text: &str, edit: &Edit) -> bool {
    let Some(new_text) = edit.apply(text) else {
        return false;
    };
    let full = parse(&new_text);
    let Some(incremental) = old.reparse_member(edit, &new_text) else {
        assert_eq!(old.reparse(edit, &new_text), full);
        return false;
    };
    assert_eq!(
        incremental.debug_tree(),
        full.debug_tree(),
        "tree after {edit:?} in\n{text}"
    );
    assert_eq!(
        incremental.errors(),
        full.errors(),
        "errors after {edit:?} in\n{text}"
    );
    assert_eq!(incremental, full);
    true
}

/// What a user types or deletes inside a block.
const INSERTS: &[&str] = &[
    "X",
    ";",
    ">",
    "<",
    "\n",
    " ",
    "\"",
    "'",
    "1",
    ":",
    "-",
    "#",
    "//",
    "(*",
    "state 9 < >",
    "state -1 < >",
    "prio -2",
    "trans 0->1 < >",
    "U E 1.0;",
    "> <",
    "graph",
    "CALL",
    "L#",
    "S5T#",
    "=",
    ")",
    "test T <",
    "expect x;",
];

#[test]
fn edits_at_every_position_of_every_member() {
    let mut incremental = 0;
    let mut total = 0;
    for text in corpus() {
        let old = parse(&text);
        let members: Vec<TextRange> = old
            .syntax_node()
            .descendants()
            .filter(|n| {
                matches!(
                    n.kind(),
                    SyntaxKind::STATE | SyntaxKind::TRANS | SyntaxKind::PERMANENT
                )
            })
            .map(|n| n.text_range())
            .collect();
        for member in members {
            let (start, end) = (u32::from(member.start()), u32::from(member.end()));
            for at in (start..=end).filter(|&i| text.is_char_boundary(i as usize)) {
                let at = TextSize::from(at);
                // Every insertion at every position would take minutes unoptimised; rotate
                // through them instead (each still lands in every kind of member).
                let pick = |k: usize| INSERTS[(u32::from(at) as usize * 7 + k) % INSERTS.len()];
                let mut edits: Vec<Edit> = [pick(0), pick(11)]
                    .iter()
                    .map(|s| Edit {
                        delete: TextRange::empty(at),
                        insert: (*s).to_owned(),
                    })
                    .collect();
                let next = text[usize::from(at)..].chars().next().map(|c| c.len_utf8());
                if let Some(len) = next {
                    let one = TextRange::at(at, TextSize::from(len as u32));
                    edits.push(Edit {
                        delete: one,
                        insert: String::new(),
                    });
                }
                for edit in edits {
                    total += 1;
                    if check(&old, &text, &edit) {
                        incremental += 1;
                    }
                }
            }
        }
    }
    // Most edits inside a member stay inside it; make sure the fast path is really taken.
    assert!(
        incremental * 4 > total,
        "only {incremental} of {total} edits were reparsed incrementally"
    );
}

#[test]
fn a_changed_instruction_is_reparsed_alone() {
    let text = "graph G <\n  state 0 <\n  >\n  trans 0->0 <\n    UN E 1.0;\n  >\n>\n";
    let old = parse(text);
    let at = TextSize::from(text.find("UN").unwrap_or(0) as u32 + 1);
    let edit = Edit {
        delete: TextRange::at(at, 1.into()),
        insert: "X".to_owned(),
    };
    let new_text = edit.apply(text).unwrap_or_default();
    let new = old.reparse_member(&edit, &new_text).expect("incremental");
    assert_eq!(new, parse(&new_text));
    // The untouched state keeps its green node.
    let state = |p: &Parse| {
        p.syntax_node()
            .descendants()
            .find(|n| n.kind() == SyntaxKind::STATE)
            .map(|n| n.green().to_owned())
    };
    let (before, after) = (state(&old), state(&new));
    assert!(before.is_some());
    assert!(std::ptr::eq(
        before
            .as_deref()
            .map_or(std::ptr::null(), |g| g as *const _),
        after.as_deref().map_or(std::ptr::null(), |g| g as *const _)
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_edits_anywhere(file in any::<prop::sample::Index>(),
                             at in any::<prop::sample::Index>(),
                             len in 0usize..4,
                             insert in prop::sample::select(INSERTS)) {
        let corpus = corpus();
        let text = &corpus[file.index(corpus.len())];
        let start = at.index(text.len() + 1);
        let end = (start + len).min(text.len());
        if text.is_char_boundary(start) && text.is_char_boundary(end) {
            let old = parse(text);
            let edit = Edit {
                delete: TextRange::new((start as u32).into(), (end as u32).into()),
                insert: insert.to_owned(),
            };
            check(&old, text, &edit);
        }
    }
}

//! Feeds arbitrary bytes (decoded as lossy UTF-8, as the server would never see invalid UTF-8
//! text: HG6102 stops such a file before parsing) to `higraph_syntax::parse` and checks the
//! invariants of `language.md` §1.4: parsing never panics, the tree is lossless, and every
//! diagnostic range (with its related locations and quick-fix edits) lies within the input on
//! character boundaries.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let parse = higraph_syntax::parse(&text);
    assert_eq!(
        parse.syntax_node().text().to_string(),
        text,
        "tree is not lossless"
    );

    let len = text.len();
    let inside = |range: higraph_syntax::TextRange, what: &str| {
        let (start, end) = (usize::from(range.start()), usize::from(range.end()));
        assert!(
            end <= len,
            "{what} {range:?} ends beyond the input ({len} bytes)"
        );
        assert!(
            text.is_char_boundary(start) && text.is_char_boundary(end),
            "{what} {range:?} splits a character"
        );
    };
    for e in parse.errors() {
        inside(e.range, "error range");
        for r in &e.related {
            inside(r.range, "related range");
        }
        for fix in &e.fixes {
            for edit in &fix.edits {
                inside(edit.range, "fix edit range");
            }
        }
    }
});

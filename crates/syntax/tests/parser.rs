//! Data-driven parser tests. Adding a test means adding one `.higraph` file:
//!
//! * `test_data/parser/ok/*.higraph` must parse without any diagnostic; the tree is snapshotted.
//! * `test_data/parser/err/*.higraph` must produce at least one diagnostic; the tree and the
//!   diagnostics are snapshotted.
//! * `test_data/diagnostics/HGnnnn/fail*.higraph` must produce HGnnnn (snapshot of all
//!   diagnostics), `pass*.higraph` must not. Every syntax code has both.
//!
//! Every input also round-trips: the tree's text equals the input.

use std::{fs, path::Path};

use higraph_syntax::{ErrorCode, Parse, TextSize, parse};

/// 1-based `line:col` (columns in characters) of an offset.
fn line_col(text: &str, offset: TextSize) -> String {
    let offset = usize::from(offset);
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = before[line_start..].chars().count() + 1;
    format!("{line}:{col}")
}

fn render_errors(text: &str, parse: &Parse) -> String {
    let mut out = String::new();
    for e in parse.errors() {
        out.push_str(&format!(
            "{} {}-{} {}\n",
            e.code,
            line_col(text, e.range.start()),
            line_col(text, e.range.end()),
            e.message
        ));
        for r in &e.related {
            out.push_str(&format!(
                "    related {}: {}\n",
                line_col(text, r.range.start()),
                r.message
            ));
        }
        for f in &e.fixes {
            out.push_str(&format!("    fix: {}\n", f.title));
        }
    }
    out
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn assert_lossless(text: &str, parse: &Parse) {
    assert_eq!(
        parse.syntax_node().to_string(),
        text,
        "tree text differs from input"
    );
}

#[test]
fn ok() {
    insta::glob!("../test_data/parser/ok", "*.higraph", |path| {
        let text = read(path);
        let parse = parse(&text);
        assert_lossless(&text, &parse);
        assert!(
            parse.errors().is_empty(),
            "{} should parse cleanly:\n{}",
            path.display(),
            render_errors(&text, &parse)
        );
        insta::assert_snapshot!(parse.debug_tree());
    });
}

#[test]
fn err() {
    insta::glob!("../test_data/parser/err", "*.higraph", |path| {
        let text = read(path);
        let parse = parse(&text);
        assert_lossless(&text, &parse);
        assert!(
            !parse.errors().is_empty(),
            "{} should have diagnostics",
            path.display()
        );
        insta::assert_snapshot!(format!(
            "{}\n{}",
            render_errors(&text, &parse),
            parse.debug_tree()
        ));
    });
}

#[test]
fn diagnostics_fail() {
    insta::glob!("../test_data/diagnostics", "HG*/fail*.higraph", |path| {
        let code = code_of(path);
        let text = read(path);
        let parse = parse(&text);
        assert_lossless(&text, &parse);
        assert!(
            parse.errors().iter().any(|e| e.code.as_str() == code),
            "{} should produce {code}:\n{}",
            path.display(),
            render_errors(&text, &parse)
        );
        insta::assert_snapshot!(render_errors(&text, &parse));
    });
}

#[test]
fn diagnostics_pass() {
    insta::glob!("../test_data/diagnostics", "HG*/pass*.higraph", |path| {
        let code = code_of(path);
        let text = read(path);
        let parse = parse(&text);
        assert_lossless(&text, &parse);
        assert!(
            !parse.errors().iter().any(|e| e.code.as_str() == code),
            "{} must not produce {code}:\n{}",
            path.display(),
            render_errors(&text, &parse)
        );
    });
}

/// Every syntax code has at least one failing and one passing fixture.
#[test]
fn every_code_has_fixtures() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/diagnostics");
    for code in ErrorCode::ALL {
        let dir = root.join(code.as_str());
        let names: Vec<String> = fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.iter().any(|n| n.starts_with("fail")),
            "{code} has no failing fixture"
        );
        assert!(
            names.iter().any(|n| n.starts_with("pass")),
            "{code} has no passing fixture"
        );
    }
}

fn code_of(path: &Path) -> String {
    path.parent()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

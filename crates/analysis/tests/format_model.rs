//! `fmt` preserves meaning: the semantic model (`higraph_analysis::model`) of every example,
//! parser fixture and rule fixture is the same before and after formatting.

mod common;

use std::{fs, path::Path};

use higraph_analysis::{format::format, model::model_of};

fn collect(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().is_some_and(|e| e == "higraph") {
            out.push(path);
        }
    }
}

#[test]
fn formatting_preserves_the_semantic_model() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut files = Vec::new();
    for dir in [
        "examples",
        "crates/syntax/test_data/parser/ok",
        "crates/analysis/test_data",
    ] {
        collect(&root.join(dir), &mut files);
    }
    let mut checked = 0;
    for path in files {
        let Ok(text) = fs::read_to_string(&path) else {
            continue;
        };
        for source in common::fixture_sources(text.as_bytes()) {
            let parse = higraph_syntax::parse(&source);
            if !parse.errors().is_empty() {
                continue;
            }
            let formatted = format(&source)
                .unwrap_or_else(|e| panic!("{}: format failed: {e:?}", path.display()));
            let after = higraph_syntax::parse(&formatted);
            assert_eq!(
                model_of(&parse.syntax_node()),
                model_of(&after.syntax_node()),
                "{}: formatting changed the semantic model",
                path.display()
            );
            checked += 1;
        }
    }
    assert!(checked > 300, "only {checked} files checked");
}

/// The model of IEC statements (docs/iec.md §5) records their structure: where an `IF`, a
/// clause or a case arm ends is part of the meaning; layout and keyword case are not.
#[test]
fn the_model_sees_the_structure_of_iec_statements() {
    let model = |body: &str| {
        let text = format!("chart C < profile iec; action A < {body} > >");
        let parse = higraph_syntax::parse(&text);
        assert!(parse.errors().is_empty(), "{body}: {:?}", parse.errors());
        model_of(&parse.syntax_node())
    };
    let same = [
        ("IF a THEN x := 1; END_IF;", "if a then\n  x := 1;\nend_if;"),
        ("x := -y * 2 MOD 3;", "x:=- y*2 mod 3;"),
        (
            "CASE n OF 1, 2..3: x := 1; ELSE x := 2; END_CASE;",
            "case n of 1,2 .. 3 : x := 1; else x := 2; end_case;",
        ),
        ("T(IN := a, Q => b);", "T ( IN:=a , Q=>b ) ;"),
    ];
    for (a, b) in same {
        assert_eq!(model(a), model(b), "{a} / {b}");
        let text = format!("chart C < profile iec; action A < {b} > >");
        let formatted = format(&text).expect("formats");
        assert_eq!(
            model_of(&higraph_syntax::parse(&text).syntax_node()),
            model_of(&higraph_syntax::parse(&formatted).syntax_node()),
            "{formatted}"
        );
    }
    let different = [
        (
            "IF a THEN x := 1; END_IF; y := 2;",
            "IF a THEN x := 1; y := 2; END_IF;",
        ),
        (
            "IF a THEN x := 1; ELSE y := 2; END_IF;",
            "IF a THEN x := 1; ELSIF b THEN y := 2; END_IF;",
        ),
        (
            "IF a THEN IF b THEN x := 1; END_IF; y := 2; END_IF;",
            "IF a THEN IF b THEN x := 1; y := 2; END_IF; END_IF;",
        ),
        (
            "CASE n OF 1: x := 1; 2: y := 2; END_CASE;",
            "CASE n OF 1: x := 1; y := 2; END_CASE;",
        ),
        (
            "CASE n OF 1, 3: x := 1; END_CASE;",
            "CASE n OF 1..3: x := 1; END_CASE;",
        ),
        ("T(IN := a, Q => b);", "T(IN := a); b := T.Q;"),
    ];
    for (a, b) in different {
        assert_ne!(model(a), model(b), "{a} / {b}");
    }
}

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

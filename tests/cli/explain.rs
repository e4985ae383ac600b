//! `higraph-lsp explain HGnnnn` end to end (`tooling.md` §2).

use crate::support::{TempTree, repo_root, run_in};

#[test]
fn explains_a_code_in_any_case() {
    let tree = TempTree::new();
    let run = tree.run("", &["explain", "hg2105"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert!(run.stdout.starts_with("# HG2105: "), "{run:?}");
    assert!(run.stdout.contains("\nSeverity: hint\n"), "{run:?}");
    for section in ["## What it checks", "## Why", "## Example", "## How to fix"] {
        assert!(run.stdout.contains(section), "{section} missing: {run:?}");
    }
    assert_eq!(run.stderr, "");
}

/// Every code of `diagnostics.md` §3 (the registry) has its documentation.
#[test]
fn explains_every_code() {
    let registry = std::fs::read_to_string(repo_root().join("crates/analysis/src/registry.rs"))
        .expect("the registry");
    let codes: Vec<&str> = registry
        .split('"')
        .filter(|part| {
            part.len() == 6
                && part.starts_with("HG")
                && part[2..].bytes().all(|b| b.is_ascii_digit())
        })
        .collect();
    assert_eq!(codes.len(), 221, "codes found in the registry: {codes:?}");
    for code in codes {
        let run = run_in(&repo_root(), &["explain", code]);
        assert_eq!(run.status, 0, "{code}: {run:?}");
        assert!(
            run.stdout.starts_with(&format!("# {code}: ")),
            "{code}: {run:?}"
        );
    }
}

#[test]
fn unknown_and_malformed_codes_are_usage_errors() {
    let tree = TempTree::new();
    let run = tree.run("", &["explain", "HG9999"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert!(
        run.stderr.contains("unknown diagnostic code 'HG9999'"),
        "{run:?}"
    );
    assert_eq!(run.stdout, "");
    let run = tree.run("", &["explain", "missing-semicolon"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert!(
        run.stderr
            .contains("'missing-semicolon' is not a diagnostic code; codes look like HG2105"),
        "{run:?}"
    );
    let run = tree.run("", &["explain"]);
    assert_eq!(run.status, 2, "{run:?}");
}

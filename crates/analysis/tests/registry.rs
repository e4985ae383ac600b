//! The registry test (`diagnostics.md` §4.5.1, as this project stands on its own): the
//! implementation's registry (`registry.rs`), the rule documentation (`docs/rules/`) and the
//! fixtures (`test_data/rules/` here, `crates/syntax/test_data/diagnostics/` for syntax codes,
//! `crates/lsp/tests/fixtures/results/` for the test results HG99xx, which only a test run
//! reports, `test_data/build/` for the HG81xx only `build` reports) cover exactly the same codes, and the documentation states the registry's default
//! severities.

use std::{collections::BTreeSet, fs, path::Path};

use higraph_analysis::registry::RULES;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn registry_codes() -> BTreeSet<String> {
    RULES.iter().map(|r| r.code.as_str().to_owned()).collect()
}

fn dir_names(dir: &Path) -> BTreeSet<String> {
    fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect()
}

/// Codes registered and documented whose fixtures other parts of the work add. Remove a code
/// here when its fixtures land.
const FIXTURES_PENDING: &[&str] = &[];

/// Codes that have both a failing and a passing fixture.
fn fixture_codes() -> BTreeSet<String> {
    let mut codes = BTreeSet::new();
    for dir in [
        root().join("crates/analysis/test_data/rules"),
        root().join("crates/syntax/test_data/diagnostics"),
        root().join("crates/lsp/tests/fixtures/results"),
        root().join("crates/analysis/test_data/build"),
    ] {
        for code in dir_names(&dir) {
            let files = dir_names(&dir.join(&code));
            let fail = files.iter().any(|f| f.starts_with("fail"));
            let pass = files.iter().any(|f| f.starts_with("pass"));
            if fail && pass {
                codes.insert(code);
            }
        }
    }
    codes
}

#[test]
fn registry_docs_and_fixtures_cover_the_same_codes() {
    let registry = registry_codes();
    let docs: BTreeSet<String> = dir_names(&root().join("docs/rules"))
        .into_iter()
        .filter_map(|f| f.strip_suffix(".md").map(str::to_owned))
        .collect();
    let mut fixtures = fixture_codes();
    for code in FIXTURES_PENDING {
        assert!(
            fixtures.insert((*code).to_owned()),
            "{code} has fixtures now: remove it from FIXTURES_PENDING"
        );
    }
    let missing_docs: Vec<_> = registry.difference(&docs).collect();
    let extra_docs: Vec<_> = docs.difference(&registry).collect();
    let missing_fixtures: Vec<_> = registry.difference(&fixtures).collect();
    let extra_fixtures: Vec<_> = fixtures.difference(&registry).collect();
    assert!(
        missing_docs.is_empty()
            && extra_docs.is_empty()
            && missing_fixtures.is_empty()
            && extra_fixtures.is_empty(),
        "registry, docs and fixtures differ:\n  codes without docs: {missing_docs:?}\n  docs without code: {extra_docs:?}\n  codes without failing+passing fixtures: {missing_fixtures:?}\n  fixtures without code: {extra_fixtures:?}"
    );
}

#[test]
fn docs_state_the_default_severity() {
    for rule in RULES {
        let path = root().join("docs/rules").join(format!("{}.md", rule.code));
        let Ok(text) = fs::read_to_string(&path) else {
            continue;
        };
        let line = text
            .lines()
            .find(|l| l.starts_with("Severity:"))
            .unwrap_or_else(|| panic!("{}: no 'Severity:' line", path.display()));
        let expected = rule.default_severity.as_str();
        assert!(
            line.contains(expected),
            "{}: '{line}' does not state the default severity {expected}",
            path.display()
        );
        assert_eq!(
            line.contains("off by default"),
            rule.off_by_default,
            "{}: off-by-default mark differs from the registry",
            path.display()
        );
    }
}

/// `registry::rule_of` finds rules by binary search: the registry is sorted by code, and
/// every code is found.
#[test]
fn the_registry_is_sorted_by_code() {
    let codes: Vec<&str> = RULES.iter().map(|r| r.code.as_str()).collect();
    let mut sorted = codes.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(codes, sorted);
    for code in codes {
        assert!(
            higraph_analysis::registry::rule_of(code).is_some(),
            "{code}"
        );
    }
    assert!(higraph_analysis::registry::rule_of("HG9999").is_none());
}

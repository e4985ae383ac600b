//! Conformance with the specification: the registry must equal the tables of
//! `diagnostics.md` §3 and of `runtime.md` §6 (the HG9xxx rows, which belong to the same
//! catalogue) — every code, its default severity and its "(off)" mark. The catalogue
//! lives beside the checkout (`../shared/spec/diagnostics.md`, as in CI) or where
//! `HIGRAPH_SPEC_DIR` points; when it is not there the test says so and checks nothing.

use std::{collections::BTreeMap, fs, path::PathBuf};

use higraph_analysis::registry::RULES;

/// Codes this project adds to the catalogue, each documented in `docs/rules/` like the others:
/// HG0012 (nesting limit) and HG0013 (syntax errors beyond the listed number), which keep
/// `tooling.md`'s promise that no input kills the tools or floods their output; and the
/// HG81xx of `build`, which `export.md` asks for ("a diagnostic in a new code") without
/// tabling them; the HG75xx of the IEC 61131-3 chart profile (`docs/iec.md`, issue 14).
const PROJECT_CODES: &[&str] = &[
    "HG0012", "HG0013", "HG7501", "HG7502", "HG7503", "HG7504", "HG7505", "HG7506", "HG7507",
    "HG7508", "HG7509", "HG7510", "HG7511", "HG8101", "HG8102", "HG8103", "HG8104", "HG8105",
    "HG8106",
];

fn catalogue() -> Option<(PathBuf, String)> {
    let candidates = [
        std::env::var_os("HIGRAPH_SPEC_DIR").map(PathBuf::from),
        Some(PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/spec"
        ))),
    ];
    candidates.into_iter().flatten().find_map(|dir| {
        let path = dir.join("diagnostics.md");
        let mut text = fs::read_to_string(&path).ok()?;
        // The test codes (HG9xxx) are tabled in runtime.md §6.
        text.push_str(&fs::read_to_string(dir.join("runtime.md")).ok()?);
        Some((path, text))
    })
}

/// `code → (severity, off)` from the rows `| HGnnnn | severity [(off)] | ...`.
fn rows(text: &str) -> BTreeMap<String, (String, bool)> {
    let mut rows = BTreeMap::new();
    for line in text.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let is_code = cells.len() >= 3
            && cells[1].len() == 6
            && cells[1].starts_with("HG")
            && cells[1][2..].bytes().all(|b| b.is_ascii_digit());
        if !is_code {
            continue;
        }
        let severity = cells[2];
        let off = severity.contains("(off)");
        let level = severity.split_whitespace().next().unwrap_or("").to_owned();
        rows.entry(cells[1].to_owned()).or_insert((level, off));
    }
    rows
}

#[test]
fn registry_matches_the_catalogue() {
    let Some((path, text)) = catalogue() else {
        eprintln!(
            "conformance: diagnostics.md not found beside the checkout (../shared/spec) and \
             HIGRAPH_SPEC_DIR is not set — nothing compared"
        );
        return;
    };
    let spec = rows(&text);
    assert!(
        spec.len() > 100,
        "{}: only {} rule rows found",
        path.display(),
        spec.len()
    );
    let ours: BTreeMap<String, (String, bool)> = RULES
        .iter()
        .filter(|r| !PROJECT_CODES.contains(&r.code.as_str()))
        .map(|r| {
            (
                r.code.as_str().to_owned(),
                (r.default_severity.as_str().to_owned(), r.off_by_default),
            )
        })
        .collect();
    let only_spec: Vec<_> = spec.keys().filter(|c| !ours.contains_key(*c)).collect();
    let only_ours: Vec<_> = ours.keys().filter(|c| !spec.contains_key(*c)).collect();
    let differing: Vec<_> = spec
        .iter()
        .filter_map(|(c, s)| ours.get(c).filter(|o| *o != s).map(|o| (c, s, o)))
        .collect();
    assert!(
        only_spec.is_empty() && only_ours.is_empty() && differing.is_empty(),
        "registry differs from {}:\n  only in the catalogue: {only_spec:?}\n  only in the registry: {only_ours:?}\n  different (spec, ours): {differing:?}",
        path.display()
    );
}

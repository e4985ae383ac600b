//! Quick fixes that must not break anything else: applying each fix of the rule fixtures of
//! these codes removes a diagnostic of the code and adds no diagnostic of any code (a rename
//! that left a reference behind would add HG4101, HG5xxx, ...; a moved `mnemonic` that was
//! lost would make the file's operands read in the other set).
//!
//! * HG0010 — the directive is moved to the top, not deleted;
//! * HG1101, HG1102 — the rename reaches every reference, in every file (the workspace rename
//!   engine);
//! * HG4001 — the fix labels every unlabelled block of the diagnostic's range;
//! * HG9001 — a statement moved to the top of its test is not lost on the way;
//! * HG9006, HG9007 — a replaced or removed run-list entry leaves a well-formed list.

mod common;

use std::{collections::BTreeMap, fs, path::Path};

use higraph_analysis::{AnalysisHost, Diagnostic};

const CODES: &[&str] = &[
    "HG0010", "HG1101", "HG1102", "HG4001", "HG9001", "HG9006", "HG9007",
];

/// Every diagnostic with the path of its file.
fn diagnostics(host: &AnalysisHost) -> Vec<(String, Diagnostic)> {
    let analysis = host.analysis();
    let paths: Vec<String> = analysis.files().iter().map(|f| f.path.clone()).collect();
    analysis
        .diagnostics()
        .into_iter()
        .flat_map(|(id, diags)| {
            let path = paths[id.0 as usize].clone();
            diags.into_iter().map(move |d| (path.clone(), d))
        })
        .collect()
}

fn counts(diags: &[(String, Diagnostic)]) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    for (_, d) in diags {
        *counts.entry(d.code.to_string()).or_default() += 1;
    }
    counts
}

#[test]
fn fixes_remove_their_diagnostic_and_add_none() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/rules");
    let mut applied = BTreeMap::<&str, usize>::new();
    let mut problems = Vec::new();
    for &code in CODES {
        let mut paths: Vec<_> = fs::read_dir(root.join(code))
            .unwrap_or_else(|e| panic!("{code}: {e}"))
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("fail"))
            })
            .collect();
        paths.sort();
        for path in paths {
            let name = format!("{code}/{}", path.file_name().unwrap().to_string_lossy());
            let original = common::fixture_files(&fs::read(&path).expect("fixture"));
            let host = common::load_fixture(&original);
            let paths: Vec<String> = host
                .analysis()
                .files()
                .iter()
                .map(|f| f.path.clone())
                .collect();
            let before = diagnostics(&host);
            let was = counts(&before);
            for (_, diag) in before.iter().filter(|(_, d)| d.code.as_str() == code) {
                for fix in &diag.fixes {
                    *applied.entry(code).or_default() += 1;
                    let mut fixed = original.clone();
                    let mut edits: Vec<_> = fix.edits.iter().collect();
                    // From the end, so earlier offsets stay valid.
                    edits.sort_by_key(|e| std::cmp::Reverse((e.file.0, e.range.start())));
                    for edit in edits {
                        let path = &paths[edit.file.0 as usize];
                        let (_, text) = fixed
                            .iter_mut()
                            .find(|(p, _)| p == path)
                            .expect("edited file is a fixture file");
                        text.splice(
                            std::ops::Range::<usize>::from(edit.range),
                            edit.new_text.bytes(),
                        );
                    }
                    let now = counts(&diagnostics(&common::load_fixture(&fixed)));
                    let what = format!("{name}: {code} '{}'", fix.title);
                    if now.get(code) >= was.get(code) {
                        problems.push(format!("{what}: {code} stays"));
                    }
                    for (c, n) in &now {
                        if n > was.get(c).unwrap_or(&0) {
                            let after: Vec<_> = fixed
                                .iter()
                                .map(|(p, t)| format!("//- {p}\n{}", String::from_utf8_lossy(t)))
                                .collect();
                            problems.push(format!("{what}: adds {c}\n{}", after.concat()));
                        }
                    }
                }
            }
        }
    }
    for &code in CODES {
        assert!(applied.contains_key(code), "no fix of {code} was applied");
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

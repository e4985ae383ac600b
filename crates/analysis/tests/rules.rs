//! Rule fixtures: `test_data/rules/HGnnnn/fail*.higraph` must produce HGnnnn, `pass*.higraph`
//! must not. A fixture is one workspace: either a single file (`main.higraph`), or several
//! files introduced by `//- path` lines (rust-analyzer style), where `//- higraph.toml` is the
//! configuration and `//- x.sdf` an imported symbol table. `//- path !unreadable` stands for a
//! file that cannot be read; fixtures are read as bytes, so a file may hold invalid UTF-8. The
//! diagnostics of every failing fixture are snapshotted (code, severity, file, range, message,
//! related, fixes).

mod common;

use std::{fs, path::Path};

use higraph_analysis::LineIndex;

/// Runs the analysis over a fixture and renders every diagnostic, one per line.
pub fn check_fixture(bytes: &[u8]) -> Vec<(String, String)> {
    let host = common::load_fixture(&common::fixture_files(bytes));
    let analysis = host.analysis();
    let out_files = analysis.files();
    let indexes: Vec<LineIndex> = out_files
        .iter()
        .map(|f| LineIndex::new(f.contents.text()))
        .collect();
    let pos = |file: usize, offset| {
        let p = indexes[file].utf16_position(offset);
        format!("{}:{}", p.line, p.column)
    };
    let mut lines = Vec::new();
    for (file, diagnostics) in analysis.diagnostics() {
        let f = file.0 as usize;
        for d in diagnostics {
            let mut line = format!(
                "{} {}-{} {}[{}] {}",
                out_files[f].path,
                pos(f, d.range.start()),
                pos(f, d.range.end()),
                d.severity,
                d.code,
                d.message
            );
            for r in &d.related {
                let rf = r.file.0 as usize;
                line.push_str(&format!(
                    "\n    related {} {}: {}",
                    out_files[rf].path,
                    pos(rf, r.range.start()),
                    r.message
                ));
            }
            for fix in &d.fixes {
                line.push_str(&format!("\n    fix: {}", fix.title));
                for e in &fix.edits {
                    let ef = e.file.0 as usize;
                    line.push_str(&format!(
                        "\n      {} {}-{} {:?}",
                        out_files[ef].path,
                        pos(ef, e.range.start()),
                        pos(ef, e.range.end()),
                        e.new_text
                    ));
                }
            }
            lines.push((d.code.to_string(), line));
        }
    }
    lines.sort();
    lines
}

fn code_of(path: &Path) -> String {
    path.parent()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn render(lines: &[(String, String)]) -> String {
    lines.iter().map(|(_, l)| format!("{l}\n")).collect()
}

#[test]
fn failing_fixtures_produce_their_code() {
    insta::glob!("../test_data/rules", "HG*/fail*.higraph", |path| {
        let code = code_of(path);
        let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let lines = check_fixture(&bytes);
        assert!(
            lines.iter().any(|(c, _)| *c == code),
            "{} should produce {code}:\n{}",
            path.display(),
            render(&lines)
        );
        insta::assert_snapshot!(render(&lines));
    });
}

#[test]
fn passing_fixtures_do_not_produce_their_code() {
    insta::glob!("../test_data/rules", "HG*/pass*.higraph", |path| {
        let code = code_of(path);
        let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let lines = check_fixture(&bytes);
        assert!(
            !lines.iter().any(|(c, _)| *c == code),
            "{} must not produce {code}:\n{}",
            path.display(),
            render(&lines)
        );
    });
}

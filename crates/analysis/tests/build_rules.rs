//! Fixtures of the diagnostics only `build` raises (HG81xx, `export.md` §3–§4):
//! `test_data/build/HGnnnn/fail*.higraph` must produce HGnnnn, `pass*.higraph` must not. The
//! fixture format is that of the rule fixtures (`tests/rules.rs`); a line `// target: awl` or
//! `// target: plcopen` chooses the build target (default: both). The fixtures are workspaces
//! `check` accepts (no error), as `build` needs them; the diagnostics of every failing fixture
//! are snapshotted (code, severity, file, range, message, related, fixes).

mod common;

use std::{fs, path::Path};

use higraph_analysis::{LineIndex, Severity, build::Target};

fn target_of(bytes: &[u8]) -> Target {
    let text = String::from_utf8_lossy(bytes);
    let line = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("// target:"))
        .map(|t| t.split_whitespace().next().unwrap_or_default().to_owned());
    match line.as_deref() {
        Some("awl") => Target::Awl,
        Some("plcopen") => Target::Plcopen,
        _ => Target::All,
    }
}

/// Runs the build rules over a fixture and renders every diagnostic, one per line; also
/// returns `check`'s errors.
fn build_fixture(bytes: &[u8]) -> (Vec<(String, String)>, Vec<String>) {
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
    let check_errors = analysis
        .diagnostics()
        .into_iter()
        .flat_map(|(file, ds)| {
            ds.into_iter()
                .filter(|d| d.severity == Severity::Error)
                .map(move |d| format!("{:?} {} {}", file, d.code, d.message))
        })
        .collect();
    let mut lines = Vec::new();
    let diagnostics = analysis
        .build_diagnostics(target_of(bytes))
        .expect("not cancelled");
    for (file, d) in diagnostics {
        let f = file.0 as usize;
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
    lines.sort();
    (lines, check_errors)
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
    insta::glob!("../test_data/build", "HG*/fail*.higraph", |path| {
        let code = code_of(path);
        let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (lines, check_errors) = build_fixture(&bytes);
        assert!(
            check_errors.is_empty(),
            "{}: check reports errors, build would stop there: {check_errors:#?}",
            path.display()
        );
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
    insta::glob!("../test_data/build", "HG*/pass*.higraph", |path| {
        let code = code_of(path);
        let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (lines, check_errors) = build_fixture(&bytes);
        assert!(
            check_errors.is_empty(),
            "{}: check reports errors, build would stop there: {check_errors:#?}",
            path.display()
        );
        assert!(
            !lines.iter().any(|(c, _)| *c == code),
            "{} must not produce {code}:\n{}",
            path.display(),
            render(&lines)
        );
    });
}

/// Applying HG8101's fix gives a group `check` accepts without HG8002/HG8003, and with
/// numbers that collide with nothing (no HG8004, HG8010).
#[test]
fn the_fix_of_hg8101_makes_the_group_buildable() {
    let bytes = fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/test_data/build/HG8101/fail.higraph"
    ))
    .expect("fixture");
    let files = common::fixture_files(&bytes);
    let host = common::load_fixture(&files);
    let analysis = host.analysis();
    let diagnostics = analysis
        .build_diagnostics(Target::Awl)
        .expect("not cancelled");
    let fixes: Vec<_> = diagnostics
        .iter()
        .filter(|(_, d)| d.code.as_str() == "HG8101")
        .flat_map(|(_, d)| d.fixes.first())
        .collect();
    assert_eq!(fixes.len(), 1);
    let mut text = analysis.files()[0].contents.text().to_owned();
    let edit = &fixes[0].edits[0];
    let range = usize::from(edit.range.start())..usize::from(edit.range.end());
    text.replace_range(range, &edit.new_text);
    assert!(
        text.contains("group Linie fc FC 4 db DB 4 \"press line\" <"),
        "{text}"
    );

    let path = analysis.files()[0].path.clone();
    drop(analysis);
    let mut host = host;
    host.set_file_contents(&path, higraph_analysis::FileContents::Text(text));
    let analysis = host.analysis();
    let codes: Vec<String> = analysis
        .diagnostics()
        .into_iter()
        .flat_map(|(_, ds)| ds.into_iter().map(|d| d.code.to_string()))
        .collect();
    for code in ["HG8002", "HG8003", "HG8004", "HG8010", "HG8011"] {
        assert!(
            !codes.contains(&code.to_owned()),
            "{code} after the fix: {codes:?}"
        );
    }
    let after = analysis
        .build_diagnostics(Target::Awl)
        .expect("not cancelled");
    assert!(after.is_empty(), "{after:?}");
}

/// A setting in `higraph.toml` turns a build rule off, and `higraph-allow` suppresses it,
/// as for `check`'s rules.
#[test]
fn severities_and_suppressions_apply() {
    let fixture = b"//- higraph.toml\n[diagnostics]\nHG8104 = \"off\"\n//- main.higraph\nchart Mischer <\n  switching T;\n  sequencer Haupt <\n    start < E 0.0; >\n    step A < >\n    trans T1 < E 0.1; >\n    step B < >\n  >\n>\ngraph G \"\xe2\x9c\x93\" <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\ngroup Linie fc FC 1 db DB 1 <\n  // higraph-allow: HG8102\n  instance I : G \"\xe2\x9c\x93\" < >\n>\n";
    let (lines, errors) = build_fixture(fixture);
    assert!(errors.is_empty(), "{errors:?}");
    let codes: Vec<&str> = lines.iter().map(|(c, _)| c.as_str()).collect();
    // The graph's comment is reported, the suppressed instance comment and HG8104 are not.
    assert_eq!(codes, ["HG8102"], "{}", render(&lines));
}

fn load(files: Vec<(String, String)>) -> higraph_analysis::AnalysisHost {
    let mut data = higraph_analysis::WorkspaceData::default();
    for (path, text) in files {
        let contents = higraph_analysis::FileContents::from_bytes(text.into_bytes());
        if path.ends_with(".higraph") {
            data.files.push((path, contents));
        } else if path == "higraph.toml" {
            data.config = Some((path, contents));
        }
    }
    let mut host = higraph_analysis::AnalysisHost::new();
    host.load(data);
    host
}

fn example(dir: &str) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(dir);
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).expect("example directory") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let relative = path
                    .strip_prefix(&root)
                    .expect("inside the example")
                    .to_string_lossy()
                    .replace('\\', "/");
                files.push((relative, fs::read_to_string(&path).expect("readable")));
            }
        }
    }
    files.sort();
    files
}

/// The examples and the generated workloads are meant to be built: no build rule reports an
/// error or a warning in them (infos on chart logic PLCopen cannot express are expected).
#[test]
fn the_examples_and_workloads_are_buildable() {
    for (name, files) in [
        ("drilling", example("drilling")),
        ("mixer", example("mixer")),
        ("plant", higraph_workload::plant(1)),
        ("max-group", higraph_workload::max_group(1)),
    ] {
        let host = load(files);
        let diagnostics = host
            .analysis()
            .build_diagnostics(Target::All)
            .expect("not cancelled");
        let serious: Vec<_> = diagnostics
            .iter()
            .filter(|(_, d)| d.severity != Severity::Info)
            .map(|(f, d)| format!("{f:?} {} {}", d.code, d.message))
            .collect();
        assert!(serious.is_empty(), "{name}: {serious:#?}");
    }
}

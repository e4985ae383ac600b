//! The worked examples of the runtime specification (E1–E6, the drilling machine and the
//! bottle filling chart, `tests/data/runtime/`) and the tests of the bundled examples, run by
//! the real `higraph-lsp test`: each passes, and every copy with one `expect` inverted fails
//! with HG9901 at that `expect`, at the cycle the test had reached there, naming the
//! expression's paths with their values.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_higraph-lsp")
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The workspaces with tests: each worked example and the bundled examples.
fn workspaces() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(repo().join("tests/data/runtime"))
        .expect("tests/data/runtime")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs.push(repo().join("examples/drilling"));
    dirs.push(repo().join("examples/mixer"));
    dirs
}

/// `higraph-lsp test DIR --format json`: exit status and the JSON report.
fn run_json(dir: &Path) -> (i32, Value) {
    let out = Command::new(binary())
        .args(["test", "--format", "json"])
        .arg(dir)
        .output()
        .expect("the binary runs");
    let json = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{}: no JSON ({e}): {}{}",
            dir.display(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.code().expect("exit status"), json)
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create folder");
    for entry in std::fs::read_dir(from).expect("read folder") {
        let entry = entry.expect("entry");
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).expect("copy file");
        }
    }
}

#[test]
fn every_worked_example_passes() {
    for dir in workspaces() {
        let (status, json) = run_json(&dir);
        let tests = json["tests"].as_array().expect("tests");
        assert!(!tests.is_empty(), "{}: no tests", dir.display());
        for t in tests {
            assert_eq!(t["result"], "passed", "{}: {t:#}", dir.display());
        }
        assert_eq!(status, 0, "{}", dir.display());
    }
}

/// An `expect` on one line: `expect EXPR ["message"];` with an optional trailing comment.
struct Expect {
    file: PathBuf,
    /// 0-based line.
    line: usize,
    /// The test it belongs to.
    test: String,
    expr: String,
    rest: String,
}

fn expects(dir: &Path) -> Vec<Expect> {
    let mut out = Vec::new();
    let mut files: Vec<PathBuf> = walk(dir);
    files.sort();
    for file in files {
        let text = std::fs::read_to_string(&file).expect("read");
        let mut test = String::new();
        for (line, l) in text.lines().enumerate() {
            let trimmed = l.trim_start();
            if let Some(header) = trimmed.strip_prefix("test ") {
                test = header.split_whitespace().next().unwrap_or("").to_owned();
            }
            let Some(body) = trimmed.strip_prefix("expect ") else {
                continue;
            };
            let code = body.split("//").next().unwrap_or(body);
            let end = code
                .find(" \"")
                .or_else(|| code.rfind(';'))
                .expect("an expect ends");
            out.push(Expect {
                file: file.clone(),
                line,
                test: test.clone(),
                expr: code[..end].to_owned(),
                rest: code[end..].to_owned(),
            });
        }
    }
    out
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("read folder") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            out.extend(walk(&path));
        } else if path.extension().is_some_and(|e| e == "higraph") {
            out.push(path);
        }
    }
    out
}

/// Rewrites line `line` of the file at `path`.
fn edit_line(path: &Path, line: usize, replace: impl Fn(&str) -> String) {
    let text = std::fs::read_to_string(path).expect("read");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[line] = replace(&lines[line]);
    std::fs::write(path, lines.join("\n") + "\n").expect("write");
}

#[test]
fn every_inverted_expect_fails_where_and_when_it_should() {
    let scratch = tempfile::tempdir().expect("temporary folder");
    let mut checked = 0;
    for (n, dir) in workspaces().into_iter().enumerate() {
        for (k, e) in expects(&dir).into_iter().enumerate() {
            let rel = e.file.strip_prefix(&dir).expect("inside");
            // The cycle the test has reached at this expect: the same test cut off after it.
            let cut = scratch.path().join(format!("cut-{n}-{k}"));
            copy_tree(&dir, &cut);
            let text = std::fs::read_to_string(cut.join(rel)).expect("read");
            let lines: Vec<&str> = text.lines().collect();
            let end = (e.line + 1..lines.len())
                .find(|&i| lines[i].trim() == ">")
                .expect("the test's closing '>'");
            let mut kept: Vec<&str> = lines[..=e.line].to_vec();
            kept.extend(&lines[end..]);
            std::fs::write(cut.join(rel), kept.join("\n") + "\n").expect("write");
            let (_, json) = run_json(&cut);
            let reached = json["tests"]
                .as_array()
                .expect("tests")
                .iter()
                .find(|t| t["name"] == e.test.as_str())
                .map(|t| {
                    assert_eq!(t["result"], "passed", "{t:#}");
                    t["cycles"].as_u64().expect("cycles")
                })
                .expect("the cut test ran");

            // The inverted copy.
            let inverted = scratch.path().join(format!("inv-{n}-{k}"));
            copy_tree(&dir, &inverted);
            edit_line(&inverted.join(rel), e.line, |l| {
                let indent = &l[..l.len() - l.trim_start().len()];
                format!("{indent}expect not ({}){}", e.expr, e.rest)
            });
            let (status, json) = run_json(&inverted);
            assert_eq!(status, 1, "{}:{}", e.file.display(), e.line + 1);
            let failures: Vec<&Value> = json["tests"]
                .as_array()
                .expect("tests")
                .iter()
                .flat_map(|t| t["failures"].as_array().expect("failures"))
                .collect();
            assert_eq!(
                failures.len(),
                1,
                "{}:{}: {failures:#?}",
                e.file.display(),
                e.line + 1
            );
            let f = failures[0];
            assert_eq!(f["code"], "HG9901", "{f:#}");
            assert_eq!(
                f["range"]["start"]["line"].as_u64(),
                Some(e.line as u64),
                "{}: {f:#}",
                e.file.display()
            );
            let cycle = f["cycle"].as_u64().expect("cycle");
            assert_eq!(cycle, reached, "{}:{}", e.file.display(), e.line + 1);
            let message = f["message"].as_str().expect("message");
            assert!(
                message.starts_with("expect failed")
                    && message.contains(&format!("at cycle {cycle} ")),
                "{message}"
            );
            let values = f["values"].as_object().expect("values");
            assert!(!values.is_empty(), "{f:#}");
            for path in values.keys() {
                assert!(
                    e.expr.replace(' ', "").contains(path.as_str()),
                    "{path} is not in {}",
                    e.expr
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 50, "only {checked} expects checked");
}

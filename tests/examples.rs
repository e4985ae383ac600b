//! The bundled example workspaces, checked by the real binary: `drilling` and `mixer` are
//! clean (no error, no warning), and the output for `mistakes` is pinned as a snapshot (it is
//! also shown in the README).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn check(example: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_higraph-lsp"))
        .current_dir(root())
        .arg("check")
        .arg(format!("examples/{example}"))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run higraph-lsp: {e}"))
}

fn summary(output: &Output) -> serde_json::Value {
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!(
            "invalid JSON ({e}): {}",
            String::from_utf8_lossy(&output.stdout)
        )
    });
    json["summary"].clone()
}

#[test]
fn drilling_and_mixer_have_no_errors_or_warnings() {
    for example in ["drilling", "mixer"] {
        let output = check(example, &["--format", "json"]);
        let summary = summary(&output);
        assert_eq!(output.status.code(), Some(0), "{example}: {summary}");
        assert_eq!(
            summary["errors"],
            0,
            "{example}: {}",
            String::from_utf8_lossy(&output.stdout)
        );
        assert_eq!(
            summary["warnings"],
            0,
            "{example}: {}",
            String::from_utf8_lossy(&output.stdout)
        );
    }
}

#[test]
fn mistakes_are_reported() {
    let output = check("mistakes", &["--color", "never"]);
    assert_eq!(output.status.code(), Some(1));
    insta::assert_snapshot!(String::from_utf8_lossy(&output.stdout));
}

/// Every example is in the canonical layout: `fmt --check` passes on each folder under
/// `examples/` (a CI that runs it on a fresh clone stays green).
#[test]
fn every_example_is_formatted() {
    let examples = root().join("examples");
    let mut folders: Vec<PathBuf> = std::fs::read_dir(&examples)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", examples.display()))
        .filter_map(|entry| entry.ok().map(|entry| entry.path()))
        .filter(|path| path.is_dir())
        .collect();
    folders.sort();
    assert!(folders.len() >= 3, "{folders:?}");
    for folder in folders {
        let output = Command::new(env!("CARGO_BIN_EXE_higraph-lsp"))
            .current_dir(&folder)
            .args(["fmt", "--check"])
            .output()
            .unwrap_or_else(|e| panic!("cannot run higraph-lsp: {e}"));
        assert_eq!(
            output.status.code(),
            Some(0),
            "{}: fmt --check lists {}{}",
            folder.display(),
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

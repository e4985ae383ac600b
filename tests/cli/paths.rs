//! How files are named in output when the workspace is not the current directory
//! (`tooling.md` §2, "Paths"): `human`, `short`, `github` and `sarif` name files relative to the
//! current directory, a file outside it absolutely; `json` keeps workspace-relative names and
//! says where the root is.

use serde_json::Value;

use crate::support::TempTree;

/// A repository with the workspace in `plc/` and one file with an error (HG0009 at 2:3).
fn repository() -> TempTree {
    let tree = TempTree::new();
    tree.file("plc/higraph.toml", "")
        .file("plc/ablauf.higraph", "//\n  $\n")
        .file("plc/graphs/deep/inner.higraph", "$\n")
        .file("README.md", "");
    tree
}

fn json(stdout: &str) -> Value {
    serde_json::from_str(stdout).unwrap_or_else(|e| panic!("invalid JSON ({e}): {stdout}"))
}

/// The canonical absolute `/` path of `relative` in the tree.
fn absolute(tree: &TempTree, relative: &str) -> String {
    let path = tree
        .path()
        .canonicalize()
        .expect("canonical")
        .join(relative);
    path.to_string_lossy().replace('\\', "/")
}

#[test]
fn github_short_and_human_name_files_from_the_current_directory() {
    let tree = repository();
    let run = tree.run("", &["check", "--format", "github", "plc/"]);
    assert_eq!(run.status, 1, "{run:?}");
    assert!(
        run.stdout
            .contains("::error file=plc/ablauf.higraph,line=2,col=3,"),
        "{run:?}"
    );
    assert!(
        run.stdout
            .contains("::error file=plc/graphs/deep/inner.higraph,line=1,col=1,"),
        "{run:?}"
    );

    let run = tree.run("", &["check", "--format", "short", "plc"]);
    assert!(
        run.stdout
            .starts_with("plc/ablauf.higraph:2:3: error[HG0009]:"),
        "{run:?}"
    );
    let run = tree.run("", &["check", "--color", "never", "plc"]);
    assert!(run.stdout.contains("--> plc/ablauf.higraph:2:3"), "{run:?}");

    // From inside the workspace nothing changes for files below the current directory.
    let run = tree.run("plc", &["check", "--format", "short"]);
    assert!(
        run.stdout.starts_with("ablauf.higraph:2:3: error[HG0009]:"),
        "{run:?}"
    );
}

#[test]
fn json_keeps_workspace_names_and_reports_the_root() {
    let tree = repository();
    let report = json(&tree.run("", &["check", "--format", "json", "plc"]).stdout);
    assert_eq!(report["root"], "plc");
    let files: Vec<&str> = report["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| d["file"].as_str().expect("file"))
        .collect();
    assert_eq!(files, ["ablauf.higraph", "graphs/deep/inner.higraph"]);

    let report = json(&tree.run("plc", &["check", "--format", "json"]).stdout);
    assert_eq!(report["root"], ".");
    // Below the root, the root is outside the current directory: named absolutely.
    let report = json(
        &tree
            .run("plc/graphs/deep", &["check", "--format", "json"])
            .stdout,
    );
    assert_eq!(report["root"], absolute(&tree, "plc"));
    assert_eq!(
        report["diagnostics"][0]["file"],
        "graphs/deep/inner.higraph"
    );
}

#[test]
fn files_outside_the_current_directory_are_named_absolutely() {
    let tree = repository();
    // Run in a sub-sub folder of the workspace, reporting on a file above it.
    let run = tree.run(
        "plc/graphs/deep",
        &["check", "--format", "short", ".", "../../ablauf.higraph"],
    );
    let names: Vec<&str> = run
        .stdout
        .lines()
        .map(|line| line.split(':').next().unwrap_or(""))
        .collect();
    assert_eq!(
        names,
        [
            absolute(&tree, "plc/ablauf.higraph").as_str(),
            "inner.higraph"
        ],
        "{run:?}"
    );
}

#[test]
fn sarif_uris_are_relative_to_the_current_directory() {
    let tree = repository();
    let run = tree.run("", &["check", "--format", "sarif", "plc"]);
    let log = json(&run.stdout);
    let run_log = &log["runs"][0];
    let uris: Vec<(&str, &str)> = run_log["results"]
        .as_array()
        .expect("results")
        .iter()
        .map(|result| {
            let artifact = &result["locations"][0]["physicalLocation"]["artifactLocation"];
            (
                artifact["uri"].as_str().expect("uri"),
                artifact["uriBaseId"].as_str().expect("base id"),
            )
        })
        .collect();
    assert_eq!(
        uris,
        [
            ("plc/ablauf.higraph", "%SRCROOT%"),
            ("plc/graphs/deep/inner.higraph", "%SRCROOT%")
        ]
    );
    // The base is declared without an absolute URI.
    assert!(run_log["originalUriBaseIds"]["%SRCROOT%"]["uri"].is_null());

    // A file outside the current directory: an absolute file URI without a base.
    let run = tree.run(
        "plc/graphs",
        &["check", "--format", "sarif", "../ablauf.higraph"],
    );
    let log = json(&run.stdout);
    let artifact =
        &log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"];
    assert_eq!(
        artifact["uri"].as_str().expect("uri"),
        format!("file://{}", absolute(&tree, "plc/ablauf.higraph"))
    );
    assert!(artifact["uriBaseId"].is_null(), "{artifact}");
}

#[test]
fn fmt_lists_files_from_the_current_directory() {
    let tree = TempTree::new();
    tree.file("plc/higraph.toml", "")
        .file("plc/sub/a.higraph", "graph G<\n  STATE 0 < >\n>\n")
        .file("plc/b.higraph", "graph H <\n  state 0 < >\n>\n");
    let run = tree.run("", &["fmt", "--check", "plc"]);
    assert_eq!(run.status, 1, "{run:?}");
    assert_eq!(run.stdout, "plc/sub/a.higraph\n");
    let run = tree.run("plc/sub", &["fmt", "--check", "../b.higraph", "."]);
    assert_eq!(run.stdout, "a.higraph\n", "{run:?}");
    let broken = TempTree::new();
    broken
        .file("plc/higraph.toml", "")
        .file("plc/c.higraph", "graph G <\n  state 0 < U x >\n>\n");
    let run = broken.run("", &["fmt", "plc"]);
    assert!(run.stderr.contains("error: plc/c.higraph: "), "{run:?}");
}

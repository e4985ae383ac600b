//! End-to-end tests of `higraph-lsp import` (`docs/iec.md` §8): the real binary on the
//! hand-written PLCopen files of `tests/data/plcopen/import/`, copied into temporary folders.
//! Exit statuses, the lines printed, where files go, refusal to replace files, formatted
//! output. What the charts hold is the import crate's business (its own snapshot tests).

#[path = "../../../tests/cli/support.rs"]
#[allow(dead_code)]
mod support;

use std::fs;

use support::{TempTree, repo_root, run_in};

fn data(name: &str) -> String {
    fs::read_to_string(repo_root().join("tests/data/plcopen/import").join(name)).expect("test data")
}

fn tree_with(files: &[&str]) -> TempTree {
    let tree = TempTree::new();
    for f in files {
        tree.file(f, data(f));
    }
    tree
}

#[test]
fn a_clean_import_writes_one_formatted_file_per_pou_and_exits_0() {
    let tree = tree_with(&["neutral_mixer.xml"]);
    let run = run_in(tree.path(), &["import", "neutral_mixer.xml"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(
        run.stdout,
        "wrote Mixer.higraph (POU Mixer of neutral_mixer.xml)\n"
    );
    assert_eq!(run.stderr, "imported 1 chart from 1 file\n");
    let text = fs::read_to_string(tree.path().join("Mixer.higraph")).expect("written");
    assert!(text.contains("chart Mixer \"Mixing tank: fill, heat, drain, three batches.\" <"));
    assert!(text.contains("  profile iec;\n"));
    // Canonical layout: `fmt --check` has nothing to change.
    let fmt = run_in(tree.path(), &["fmt", "--check", "Mixer.higraph"]);
    assert_eq!(fmt.status, 0, "{fmt:?}");
    // The imported chart has no syntax errors.
    let parse = run_in(tree.path(), &["parse", "Mixer.higraph"]);
    assert!(!parse.stdout.contains("HG0"), "{}", parse.stdout);
}

#[test]
fn existing_files_are_replaced_only_with_force() {
    let tree = tree_with(&["neutral_mixer.xml"]);
    tree.file("out/Mixer.higraph", "// mine\n");
    let run = run_in(tree.path(), &["import", "neutral_mixer.xml", "-o", "out"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert_eq!(run.stdout, "");
    assert_eq!(
        run.stderr,
        "error: out/Mixer.higraph exists; not replaced (use --force to replace it)\n\
         imported 0 charts from 1 file, 1 error\n"
    );
    assert_eq!(
        fs::read_to_string(tree.path().join("out/Mixer.higraph")).unwrap(),
        "// mine\n"
    );
    let run = run_in(
        tree.path(),
        &["import", "--force", "neutral_mixer.xml", "-o", "out"],
    );
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(
        run.stdout,
        "wrote out/Mixer.higraph (POU Mixer of neutral_mixer.xml)\n"
    );
    let text = fs::read_to_string(tree.path().join("out/Mixer.higraph")).unwrap();
    assert!(text.contains("chart Mixer"));
    // No temporary files are left behind.
    let names: Vec<_> = fs::read_dir(tree.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names, vec!["Mixer.higraph".to_string()]);
}

#[test]
fn problems_are_reported_with_file_line_pou_and_element_and_exit_1() {
    let tree = tree_with(&["unsupported.xml"]);
    let run = run_in(tree.path(), &["import", "unsupported.xml", "-o", "charts"]);
    assert_eq!(run.status, 1, "{run:?}");
    insta::assert_snapshot!(run.stdout);
    assert_eq!(run.stderr, "imported 1 chart from 1 file, 20 problems\n");
    let text = fs::read_to_string(tree.path().join("charts/Press.higraph")).expect("written");
    assert!(text.contains("// not imported: line 2 of its ST text: FOR loops are not supported"));
}

#[test]
fn unreadable_and_invalid_files_exit_2_and_the_others_still_import() {
    let tree = tree_with(&["malformed.xml", "not_plcopen.xml", "neutral_mixer.xml"]);
    tree.file("latin1.xml", b"<project><!-- \xE9 --></project>");
    let run = run_in(
        tree.path(),
        &[
            "import",
            "malformed.xml",
            "missing.xml",
            "not_plcopen.xml",
            "latin1.xml",
            "neutral_mixer.xml",
        ],
    );
    assert_eq!(run.status, 2, "{run:?}");
    assert_eq!(
        run.stdout,
        "wrote Mixer.higraph (POU Mixer of neutral_mixer.xml)\n"
    );
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 5, "{}", run.stderr);
    assert_eq!(
        lines[0],
        "error: malformed.xml: invalid XML at 7:1: unexpected end of stream"
    );
    assert!(
        lines[1].starts_with("error: missing.xml: cannot read: "),
        "{}",
        lines[1]
    );
    assert_eq!(
        lines[2],
        "error: not_plcopen.xml: not a PLCopen project: the root element is <graph>, not <project>"
    );
    assert!(
        lines[3].starts_with("error: latin1.xml: not UTF-8"),
        "{}",
        lines[3]
    );
    assert_eq!(lines[4], "imported 1 chart from 1 file, 4 errors");
    assert!(tree.path().join("Mixer.higraph").is_file());
}

#[test]
fn usage() {
    let tree = TempTree::new();
    let run = run_in(tree.path(), &["import"]);
    assert_eq!(run.status, 2, "{run:?}");
    let help = run_in(tree.path(), &["--help"]);
    assert!(help.stdout.contains("import"), "{}", help.stdout);
    let help = run_in(tree.path(), &["import", "--help"]);
    assert_eq!(help.status, 0);
    assert!(help.stdout.contains("--force"));
    // An output "folder" that is a file.
    tree.file("plain", "x")
        .file("a.xml", data("neutral_mixer.xml"));
    let run = run_in(tree.path(), &["import", "a.xml", "-o", "plain"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert!(run.stderr.contains("is not a folder"), "{}", run.stderr);
}

/// The three dialects (and Beremiz conditions drawn as networks) import into charts that
/// `check` finds nothing wrong with.
#[test]
fn imported_examples_check_clean() {
    let files = [
        "neutral_mixer.xml",
        "codesys_ampel.xml",
        "beremiz_station.xml",
        "beremiz_networks.xml",
    ];
    let tree = tree_with(&files);
    let mut args = vec!["import", "-o", "charts"];
    args.extend(files);
    let run = run_in(tree.path(), &args);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(run.stderr, "imported 4 charts from 4 files\n");
    let check = run_in(
        &tree.path().join("charts"),
        &["check", "--format", "short", "."],
    );
    assert_eq!(check.status, 0, "{check:?}");
    assert_eq!(check.stdout, "", "{check:?}");
    let fmt = run_in(&tree.path().join("charts"), &["fmt", "--check", "."]);
    assert_eq!(fmt.status, 0, "{fmt:?}");
}

//! `higraph-lsp fmt [--check] [PATH...]` end to end (`tooling.md` §2, §2a).

use std::fs;

use crate::support::TempTree;

const MESSY: &str = "graph Ventil<\nSTATE 0 < c: = Auf ; >\n  trans ANY->0 < u INIT_SD; >\n>\n";
const FORMATTED: &str =
    "graph Ventil <\n  state 0 < C: = Auf; >\n  trans any->0 prio 1 < U INIT_SD; >\n>\n";

#[test]
fn formats_files_in_place() {
    let tree = TempTree::new();
    tree.file("a.higraph", MESSY)
        .file("sub/b.higraph", FORMATTED);
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(run.stdout, "a.higraph\n");
    assert!(
        run.stderr
            .contains("1 file reformatted, 1 file already formatted"),
        "{run:?}"
    );
    let a = fs::read_to_string(tree.path().join("a.higraph")).expect("read");
    assert_eq!(a, FORMATTED);
    let b = fs::read_to_string(tree.path().join("sub/b.higraph")).expect("read");
    assert_eq!(b, FORMATTED);
    // A second run changes nothing.
    let again = tree.run("", &["fmt"]);
    assert_eq!(again.status, 0, "{again:?}");
    assert_eq!(again.stdout, "");
}

#[test]
fn check_changes_nothing_and_lists_files() {
    let tree = TempTree::new();
    tree.file("a.higraph", MESSY)
        .file("b.higraph", FORMATTED)
        .file("c.higraph", MESSY);
    let run = tree.run("", &["fmt", "--check"]);
    assert_eq!(run.status, 1, "{run:?}");
    assert_eq!(run.stdout, "a.higraph\nc.higraph\n");
    assert!(
        run.stderr.contains("2 files would be reformatted"),
        "{run:?}"
    );
    let a = fs::read_to_string(tree.path().join("a.higraph")).expect("read");
    assert_eq!(a, MESSY, "--check must not write");

    let clean = TempTree::new();
    clean.file("b.higraph", FORMATTED);
    let run = clean.run("", &["fmt", "--check"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(run.stdout, "");
}

#[test]
fn files_with_syntax_errors_are_left_alone() {
    let tree = TempTree::new();
    let broken = "graph G <\n  state 0 < U x >\n>\n";
    tree.file("broken.higraph", broken)
        .file("ok.higraph", MESSY);
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 1, "{run:?}");
    assert!(
        run.stderr
            .contains("error: broken.higraph: syntax error at 2:16")
            && run.stderr.contains("[HG0002]")
            && run.stderr.contains("left unchanged"),
        "{run:?}"
    );
    assert_eq!(
        fs::read_to_string(tree.path().join("broken.higraph")).expect("read"),
        broken
    );
    // The other file is still formatted.
    assert_eq!(run.stdout, "ok.higraph\n");
    assert_eq!(
        fs::read_to_string(tree.path().join("ok.higraph")).expect("read"),
        FORMATTED
    );
    let check = tree.run("", &["fmt", "--check"]);
    assert_eq!(check.status, 1, "{check:?}");
}

#[test]
fn only_files_under_the_paths_are_formatted() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file("graphs/a.higraph", MESSY)
        .file("other/b.higraph", MESSY);
    let run = tree.run("graphs", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    // Named relative to the current folder (`tooling.md` §2).
    assert_eq!(run.stdout, "a.higraph\n");
    assert_eq!(
        fs::read_to_string(tree.path().join("other/b.higraph")).expect("read"),
        MESSY
    );
    // A file named explicitly.
    let run = tree.run("", &["fmt", "other/b.higraph"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(run.stdout, "other/b.higraph\n");
}

#[test]
fn excluded_files_are_skipped() {
    let tree = TempTree::new();
    tree.file(
        "higraph.toml",
        "[workspace]\nexclude = [\"generated/**\"]\n",
    )
    .file("generated/g.higraph", MESSY)
    .file("a.higraph", MESSY);
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(run.stdout, "a.higraph\n");
    assert_eq!(
        fs::read_to_string(tree.path().join("generated/g.higraph")).expect("read"),
        MESSY
    );
}

#[test]
fn crlf_files_keep_crlf() {
    let tree = TempTree::new();
    tree.file("w.higraph", MESSY.replace('\n', "\r\n"));
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert_eq!(
        fs::read_to_string(tree.path().join("w.higraph")).expect("read"),
        FORMATTED.replace('\n', "\r\n")
    );
}

#[test]
fn missing_paths_are_usage_errors() {
    let tree = TempTree::new();
    let run = tree.run("", &["fmt", "nowhere"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert!(
        run.stderr.contains("path 'nowhere' does not exist"),
        "{run:?}"
    );
    let run = tree.run("", &["fmt", "--frobnicate"]);
    assert_eq!(run.status, 2, "{run:?}");
}

#[test]
fn files_that_are_not_utf8_are_reported() {
    let tree = TempTree::new();
    tree.file("latin1.higraph", b"// Z\xe4hler\ngraph G < >\n".as_slice());
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 1, "{run:?}");
    assert!(
        run.stderr.contains("latin1.higraph: not valid UTF-8"),
        "{run:?}"
    );
}

#[cfg(unix)]
#[test]
fn writes_keep_permissions_and_leave_no_temporary_files() {
    use std::os::unix::fs::PermissionsExt;

    let tree = TempTree::new();
    tree.file("a.higraph", MESSY);
    let path = tree.path().join("a.higraph");
    fs::set_permissions(&path, fs::Permissions::from_mode(0o600)).expect("chmod");
    let run = tree.run("", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    let mode = fs::metadata(&path).expect("metadata").permissions().mode();
    assert_eq!(mode & 0o777, 0o600);
    let names: Vec<String> = fs::read_dir(tree.path())
        .expect("list")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["a.higraph"]);
}

#[cfg(unix)]
#[test]
fn symbolic_links_stay_links() {
    // A link inside the workspace is followed (a link out of it is refused: robustness.rs).
    let tree = TempTree::new();
    tree.file("ws/real/a.higraph", MESSY);
    let link = tree.path().join("ws/a.higraph");
    std::os::unix::fs::symlink(tree.path().join("ws/real/a.higraph"), &link).expect("symlink");
    let run = tree.run("ws", &["fmt"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert!(
        fs::symlink_metadata(&link)
            .expect("metadata")
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        fs::read_to_string(tree.path().join("ws/real/a.higraph")).expect("read"),
        FORMATTED
    );
}

#[test]
fn check_runs_on_the_examples() {
    let root = crate::support::repo_root().join("examples/drilling");
    let run = crate::support::run_in(&root, &["fmt", "--check"]);
    assert!(matches!(run.status, 0 | 1), "{run:?}");
    assert!(!run.stderr.contains("error:"), "{run:?}");
}

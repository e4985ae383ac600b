//! End-to-end tests of `higraph-lsp build` (`export.md` §2): the real binary on small
//! workspaces in temporary folders. Exit statuses, refusal on errors (nothing written), one
//! line per file written, atomic writes that leave unchanged files and other files alone,
//! deterministic output without absolute paths, and the output folder never analysed.
//! What is inside the files is the generators' business (their own tests); here only which
//! files appear and how.

#[path = "../../../tests/cli/support.rs"]
#[allow(dead_code)]
mod support;

use std::fs;
use std::path::Path;

use support::{TempTree, run_in};

const PLANT: &str = r#"symbols < Knopf : E 0.0; Lampe : A 0.0; GG_Pult : FC 1; DB_Pult : DB 1; >
graph Blink <
  in < Go : BOOL; >
  out < Light : BOOL; >
  state 0 "Aus" < C: CLR; = Light; >
  state 1 "An" < C: = Light; >
  trans any->0 prio 1 "startup" < U INIT_SD; >
  trans 0->1 < U Go; >
  trans 1->0 < UN Go; >
>
group Pult fc FC1 db DB1 <
  instance Anzeige : Blink < Go := Knopf; Light := Lampe; >
>
"#;

const CHART: &str = r#"chart Ampel <
  in < Start : BOOL; >
  out < Rot : BOOL; >
  sequencer Lauf prio 1 <
    start < Start; >
    step Warten < N Rot; >
    trans Weiter < not Start; >
    step Ende < >
  >
>
"#;

fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("plant.higraph", PLANT)
        .file("charts/ampel.higraph", CHART);
    tree
}

fn build(tree: &TempTree, args: &[&str]) -> support::Run {
    let mut all = vec!["build"];
    all.extend_from_slice(args);
    run_in(tree.path(), &all)
}

/// The `wrote ...` lines of standard output (diagnostics the build prints come before them).
fn wrote(stdout: &str) -> String {
    stdout
        .lines()
        .filter(|line| line.starts_with("wrote "))
        .map(|line| format!("{line}\n"))
        .collect()
}

/// The names in a folder, sorted (hidden ones included).
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn a_build_writes_the_group_sources_and_the_symbol_table_one_line_each() {
    let tree = workspace();
    // The workspace is clean for `check` (so the build has nothing to refuse).
    let check = run_in(tree.path(), &["check"]);
    assert_eq!(check.status, 0, "{}{}", check.stdout, check.stderr);

    let run = build(&tree, &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout, "wrote build/Pult.awl\nwrote build/symbols.sdf\n",
        "{}",
        run.stderr
    );
    assert!(
        run.stderr
            .contains("built 1 group into build: 2 files written"),
        "{}",
        run.stderr
    );
    assert_eq!(
        listing(&tree.path().join("build")),
        [".higraph-build", "Pult.awl", "symbols.sdf"]
    );
    for name in ["Pult.awl", "symbols.sdf"] {
        let bytes = fs::read(tree.path().join("build").join(name)).expect("written");
        assert!(!bytes.is_empty(), "{name} is empty");
    }
}

#[test]
fn targets_choose_groups_charts_or_both() {
    let tree = workspace();
    let run = build(&tree, &["--target", "plcopen"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        wrote(&run.stdout),
        "wrote build/charts.xml\n",
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("built 1 chart"), "{}", run.stderr);

    let tree = workspace();
    let run = build(&tree, &["--target", "all", "-o", "out"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        wrote(&run.stdout),
        "wrote out/Pult.awl\nwrote out/charts.xml\nwrote out/symbols.sdf\n",
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains("built 1 group and 1 chart"),
        "{}",
        run.stderr
    );

    // With --absolute the sources need no symbol table, so none is written.
    let tree = workspace();
    let run = build(&tree, &["--absolute", "--with-ob1"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(run.stdout, "wrote build/Pult.awl\n", "{}", run.stderr);
    assert!(!tree.path().join("build/symbols.sdf").exists());
}

#[cfg(unix)]
#[test]
fn unchanged_files_are_not_rewritten_and_other_files_are_left_alone() {
    use std::os::unix::fs::MetadataExt as _;
    let tree = workspace();
    tree.file("build/notes.txt", "my notes")
        .file("build/Alt.awl", "an old source");
    let first = build(&tree, &[]);
    assert_eq!(first.status, 0, "{}{}", first.stdout, first.stderr);
    let source = tree.path().join("build/Pult.awl");
    let before = fs::metadata(&source).expect("written");
    let bytes = fs::read(&source).expect("read");

    // Nothing changed: nothing is written (the same file, not a copy renamed over it).
    let second = build(&tree, &[]);
    assert_eq!(second.status, 0, "{}{}", second.stdout, second.stderr);
    assert_eq!(second.stdout, "", "{}", second.stderr);
    assert!(
        second.stderr.contains("0 files written, 2 unchanged"),
        "{}",
        second.stderr
    );
    let after = fs::metadata(&source).expect("still there");
    assert_eq!(before.ino(), after.ino());
    assert_eq!(before.mtime_nsec(), after.mtime_nsec());

    // A file that differs is replaced by a rename (a new inode), the others stay.
    fs::write(&source, "edited by hand").expect("write");
    let edited = fs::metadata(&source).expect("edited");
    let third = build(&tree, &[]);
    assert_eq!(third.stdout, "wrote build/Pult.awl\n", "{}", third.stderr);
    assert_eq!(fs::read(&source).expect("read"), bytes);
    assert_ne!(
        fs::metadata(&source).expect("rewritten").ino(),
        edited.ino()
    );

    assert_eq!(
        fs::read_to_string(tree.path().join("build/notes.txt")).expect("kept"),
        "my notes"
    );
    assert_eq!(
        fs::read_to_string(tree.path().join("build/Alt.awl")).expect("kept"),
        "an old source"
    );
    // No temporary file is left behind.
    assert!(
        listing(&tree.path().join("build"))
            .iter()
            .all(|name| !name.ends_with("build-tmp")),
        "{:?}",
        listing(&tree.path().join("build"))
    );
}

#[test]
fn errors_stop_the_build_before_anything_is_written() {
    let tree = workspace();
    // An instance of a graph that does not exist.
    tree.file(
        "plant.higraph",
        PLANT.replace("instance Anzeige : Blink", "instance Anzeige : Blinker"),
    );
    let run = build(&tree, &[]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    // The diagnostics as `check` prints them.
    assert!(run.stdout.contains("error["), "{}", run.stdout);
    assert!(run.stdout.contains("--> plant.higraph:"), "{}", run.stdout);
    assert!(
        run.stderr
            .contains("error: nothing built: errors in the group to build or in what it uses"),
        "{}",
        run.stderr
    );
    assert!(!tree.path().join("build").exists(), "nothing is written");

    // An error in a graph the group uses stops it too.
    let tree = workspace();
    tree.file(
        "plant.higraph",
        PLANT.replace("trans 0->1 < U Go; >", "trans 0->7 < U Go; >"),
    );
    let run = build(&tree, &[]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    assert!(!tree.path().join("build").exists(), "nothing is written");

    // So does an error in a symbol table, also when only the group's file is named.
    let tree = workspace();
    tree.file("symbole.higraph", "symbols < Eins : A 1.0; Zwei : A 1.0; >\n");
    let run = build(&tree, &["plant.higraph"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("--> symbole.higraph:"), "{}", run.stdout);
    assert!(!tree.path().join("build").exists(), "nothing is written");

    // An error in a test does not stop a build.
    let tree = workspace();
    tree.file("tests.higraph", "test Kaputt <\n  expect Nirgends;\n>\n");
    assert_eq!(
        run_in(tree.path(), &["check"]).status,
        1,
        "the test has an error"
    );
    let run = build(&tree, &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);

    // An error in a chart does not stop a build of the groups only.
    let tree = workspace();
    tree.file(
        "charts/ampel.higraph",
        CHART.replace("step Ende < >", "step Ende < > step Ende < >"),
    );
    assert_eq!(build(&tree, &["--target", "plcopen"]).status, 1);
    let run = build(&tree, &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(tree.path().join("build/Pult.awl").is_file());
}

#[test]
fn warnings_are_printed_and_do_not_stop_the_build() {
    let tree = workspace();
    // An unreachable state (HG2401, a warning).
    tree.file(
        "plant.higraph",
        PLANT.replace(
            "  state 1 \"An\" < C: = Light; >\n",
            "  state 1 \"An\" < C: = Light; >\n  state 2 \"Nie\" < >\n",
        ),
    );
    let run = build(&tree, &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("warning[HG2401]"), "{}", run.stdout);
    assert!(
        run.stdout.contains("wrote build/Pult.awl"),
        "{}",
        run.stdout
    );
}

#[test]
fn the_output_is_deterministic_and_names_no_absolute_path() {
    let one = workspace();
    let two = workspace();
    for tree in [&one, &two] {
        let run = build(tree, &["--target", "all"]);
        assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    }
    for name in ["Pult.awl", "charts.xml", "symbols.sdf"] {
        let a = fs::read(one.path().join("build").join(name)).expect("written");
        let b = fs::read(two.path().join("build").join(name)).expect("written");
        assert_eq!(a, b, "{name} differs between two builds");
        let text = String::from_utf8_lossy(&a);
        for tree in [&one, &two] {
            let root = tree.path().to_string_lossy().into_owned();
            assert!(!text.contains(&root), "{name} names the workspace folder");
        }
        assert!(!text.contains("/tmp"), "{name} names a temporary folder");
    }
}

#[test]
fn the_output_folder_is_never_analysed() {
    let tree = workspace();
    assert_eq!(build(&tree, &[]).status, 0);
    assert_eq!(build(&tree, &["-o", "generated/plc"]).status, 0);
    // A source file in an output folder would be an error if it were analysed.
    tree.file("build/stray.higraph", "graph <<<\n")
        .file("generated/plc/stray.higraph", "graph <<<\n");
    let check = run_in(tree.path(), &["check"]);
    assert_eq!(check.status, 0, "{}{}", check.stdout, check.stderr);
    assert!(!check.stdout.contains("stray"), "{}", check.stdout);
    let again = build(&tree, &[]);
    assert_eq!(again.status, 0, "{}{}", again.stdout, again.stderr);
}

#[test]
fn paths_choose_the_files_and_the_root_is_found_from_below() {
    let tree = workspace();
    // Only the charts' folder: no group there.
    let run = build(&tree, &["charts"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(run.stdout, "");
    assert!(run.stderr.contains("nothing to build"), "{}", run.stderr);
    assert!(!tree.path().join("build").exists());

    // From a folder below the root, without a PATH: the whole workspace, into the root's
    // build folder (named by its absolute path, as every command names a file outside the
    // current folder).
    let run = tree.run("charts", &["build", "--target", "all"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    let root = fs::canonicalize(tree.path()).expect("canonical");
    let root = root.to_string_lossy();
    assert_eq!(
        wrote(&run.stdout),
        format!(
            "wrote {root}/build/Pult.awl\nwrote {root}/build/charts.xml\n\
             wrote {root}/build/symbols.sdf\n"
        )
    );
}

#[test]
fn usage_errors_exit_with_two_and_write_nothing() {
    let tree = workspace();
    for args in [
        &["--target", "pdf"][..],
        &["does-not-exist"],
        // The workspace itself, or a folder holding its sources, is no output folder.
        &["-o", "."],
        &["-o", "charts"],
    ] {
        let run = build(&tree, args);
        assert_eq!(run.status, 2, "{args:?}: {}{}", run.stdout, run.stderr);
        assert!(!run.stderr.is_empty(), "{args:?}");
    }
    assert!(!tree.path().join("build").exists());
    assert!(!tree.path().join("charts/.higraph-build").exists());
    // A file where the output folder should be.
    tree.file("build", "not a folder");
    let run = build(&tree, &[]);
    assert_eq!(run.status, 2, "{}{}", run.stdout, run.stderr);
}

#[cfg(unix)]
#[test]
fn the_default_folder_never_leads_out_of_the_workspace() {
    let tree = workspace();
    let outside = tempfile::tempdir().expect("a folder outside");
    std::os::unix::fs::symlink(outside.path(), tree.path().join("build")).expect("link");
    let run = build(&tree, &[]);
    assert_eq!(run.status, 2, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains("leads out of the workspace"),
        "{}",
        run.stderr
    );
    assert!(listing(outside.path()).is_empty());

    // Named explicitly, a folder outside is the user's choice.
    let run = build(&tree, &["-o", &outside.path().to_string_lossy()]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(outside.path().join("Pult.awl").is_file());

    // A link in the output folder is replaced, not written through.
    let target = tree.path().join("precious.txt");
    fs::write(&target, "keep").expect("write");
    let out = tree.path().join("out");
    fs::create_dir(&out).expect("folder");
    std::os::unix::fs::symlink(&target, out.join("Pult.awl")).expect("link");
    let run = build(&tree, &["-o", "out"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(fs::read_to_string(&target).expect("read"), "keep");
    assert!(
        fs::symlink_metadata(out.join("Pult.awl"))
            .expect("written")
            .is_file()
    );
}

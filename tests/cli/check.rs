//! `higraph-lsp check`: workspace discovery, selection by PATH, the output formats of
//! `diagnostics.md` §4.1–4.2 and the exit status of §4.3.
//!
//! The exact-output tests use a workspace whose only diagnostics come from the lexer (HG0004,
//! HG0005, HG0009); its `higraph.toml` switches off the two semantic rules its deliberately
//! tiny graphs would otherwise trigger (no startup transition, unused variable). Semantic
//! rules have their own fixtures in `crates/analysis`.

use serde_json::Value;

use crate::support::{Run, TempTree};

/// A workspace whose only diagnostics come from the lexer, in otherwise valid items: an umlaut
/// in an identifier after an astral-plane character (UTF-16 columns), an unclosed string in
/// a CR LF file, an unclosed character constant.
fn lexer_workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file(
        "higraph.toml",
        "[diagnostics]\nHG2201 = \"off\"\nHG1210 = \"off\"\n",
    )
    .file(
        "graphs/ventil.higraph",
        "// Ventil für Öl\ngraph Ventil \"😀 Ventil\" < in < Zähler : INT; > >\n",
    )
    .file("graphs/pumpe.higraph", "graph Pumpe \"Pumpe\r\n<\r\n>\r\n")
    .file(
        "motor.higraph",
        "graph Motor <\n  stat < Zeichen : CHAR := 'x\n  ; >\n>\n",
    )
    .file("clean.higraph", "// nothing to see here\n");
    tree
}

fn json(run: &Run) -> Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|error| panic!("not JSON ({error}):\n{}\n{}", run.stdout, run.stderr))
}

/// The `(file, code)` pairs of a JSON report, in output order.
fn files_and_codes(report: &Value) -> Vec<(String, String)> {
    report["diagnostics"]
        .as_array()
        .expect("diagnostics array")
        .iter()
        .map(|d| {
            (
                d["file"].as_str().unwrap().to_string(),
                d["code"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

fn position(value: &Value) -> (u64, u64) {
    (
        value["line"].as_u64().unwrap(),
        value["character"].as_u64().unwrap(),
    )
}

// ------------------------------------------------------------------ exact output (lexer codes)

#[test]
fn json_output() {
    let tree = lexer_workspace();
    let run = tree.run(".", &["check", "--format", "json"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    insta::assert_snapshot!(run.stdout);
}

#[test]
fn short_output() {
    let tree = lexer_workspace();
    let run = tree.run(".", &["check", "--format", "short"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    insta::assert_snapshot!(run.stdout, @r"
    graphs/pumpe.higraph:1:13: error[HG0004]: string is not closed before the end of the line
    graphs/ventil.higraph:2:33: error[HG0009]: identifiers use ASCII letters only; write 'ae' for 'ä'
    motor.higraph:2:28: error[HG0005]: character constant is not closed before the end of the line
    ");
}

#[test]
fn human_output() {
    let tree = lexer_workspace();
    let run = tree.run(".", &["check", "--format", "human", "--color", "never"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    insta::assert_snapshot!(run.stdout);
}

#[test]
fn human_is_the_default_format() {
    let tree = lexer_workspace();
    let default = tree.run(".", &["check"]);
    let human = tree.run(".", &["check", "--format", "human"]);
    assert_eq!(default.stdout, human.stdout);
    assert!(
        default
            .stdout
            .ends_with("\n\nerror: 3 errors, 0 warnings, 0 infos, 0 hints\n")
    );
}

#[test]
fn github_output() {
    let tree = lexer_workspace();
    let run = tree.run(".", &["check", "--format", "github"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    insta::assert_snapshot!(run.stdout, @r"
    ::error file=graphs/pumpe.higraph,line=1,col=13,endLine=1,endColumn=19::[HG0004] string is not closed before the end of the line
    ::error file=graphs/ventil.higraph,line=2,col=33,endLine=2,endColumn=34::[HG0009] identifiers use ASCII letters only; write 'ae' for 'ä'
    ::error file=motor.higraph,line=2,col=28,endLine=2,endColumn=30::[HG0005] character constant is not closed before the end of the line
    ");
}

#[test]
fn github_escapes_properties_and_messages() {
    let tree = TempTree::new();
    tree.file("a,b:c.higraph", "// x\n%\n");
    let run = tree.run(".", &["check", "--format", "github"]);
    assert_eq!(run.status, 1);
    assert!(
        run.stdout.contains(
            "::error file=a%2Cb%3Ac.higraph,line=2,col=1,endLine=2,endColumn=2::\
             [HG0009] unexpected character '%25' (U+0025)\n"
        ),
        "{}",
        run.stdout
    );
}

#[test]
fn colour_only_when_asked_or_on_a_terminal() {
    let tree = lexer_workspace();
    let always = tree.run(".", &["check", "--color", "always"]);
    assert!(always.stdout.contains("\u{1b}["), "{}", always.stdout);
    // Standard output is a pipe here, so `auto` means no colour.
    for choice in ["never", "auto"] {
        let run = tree.run(".", &["check", "--color", choice]);
        assert!(
            !run.stdout.contains('\u{1b}'),
            "--color {choice}: {}",
            run.stdout
        );
    }
    // Colour never leaks into the machine formats.
    let json = tree.run(".", &["check", "--format", "json", "--color", "always"]);
    assert!(!json.stdout.contains('\u{1b}'));
}

// ------------------------------------------------------------------ JSON structure

#[test]
fn json_has_the_specified_shape() {
    let tree = lexer_workspace();
    tree.file("extra.higraph", "x \"😀😀\" $ ~\r\n$\n");
    let run = tree.run(".", &["check", "--format", "json"]);
    let report = json(&run);
    let top: Vec<_> = report.as_object().unwrap().keys().cloned().collect();
    assert_eq!(top.len(), 4, "{top:?}");
    assert_eq!(report["version"], 1);
    // Run in the workspace root: the root relative to the current directory is `.`.
    assert_eq!(report["root"], ".");
    for diagnostic in report["diagnostics"].as_array().unwrap() {
        let object = diagnostic.as_object().unwrap();
        let mut keys: Vec<_> = object.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "code", "file", "fixes", "message", "range", "related", "severity"
            ]
        );
        assert!(diagnostic["related"].is_array());
        assert!(diagnostic["fixes"].is_array());
        let code = diagnostic["code"].as_str().unwrap();
        assert!(code.len() == 6 && code.starts_with("HG"), "{code}");
        assert!(
            ["error", "warning", "info", "hint"]
                .contains(&diagnostic["severity"].as_str().unwrap())
        );
        let file = diagnostic["file"].as_str().unwrap();
        assert!(
            !file.starts_with("./") && !file.starts_with('/') && !file.contains('\\'),
            "{file}"
        );
        for fix in diagnostic["fixes"].as_array().unwrap() {
            assert!(fix["title"].is_string());
            for edit in fix["edits"].as_array().unwrap() {
                assert!(
                    edit["file"].is_string() && edit["newText"].is_string(),
                    "{edit}"
                );
                position(&edit["range"]["start"]);
                position(&edit["range"]["end"]);
            }
        }
    }
    let summary = &report["summary"];
    let mut keys: Vec<_> = summary
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort_unstable();
    assert_eq!(keys, ["errors", "files", "hints", "infos", "warnings"]);
    // Every file of the workspace was checked.
    assert_eq!(summary["files"], 5);
    assert_eq!(
        summary["errors"].as_u64().unwrap() as usize,
        report["diagnostics"].as_array().unwrap().len()
    );
    // Pretty-printed with two spaces.
    assert!(
        run.stdout
            .starts_with("{\n  \"version\": 1,\n  \"root\": \".\",\n  \"diagnostics\": [\n    {\n")
    );
}

#[test]
fn json_positions_are_utf16_and_lines_break_at_cr_lf() {
    let tree = TempTree::new();
    tree.file("a.higraph", "x \"😀😀\" $\r\n$\rä$\n");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    let starts: Vec<_> = report["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["code"] == "HG0009" && d["message"].as_str().unwrap().contains("'$'"))
        .map(|d| (position(&d["range"]["start"]), position(&d["range"]["end"])))
        .collect();
    // Each astral-plane character counts two UTF-16 units; CR LF is one break, CR is one.
    assert_eq!(
        starts,
        [((0, 9), (0, 10)), ((1, 0), (1, 1)), ((2, 1), (2, 2))]
    );
    // The human formats count characters, 1-based.
    let short = tree.run(".", &["check", "--format", "short"]);
    assert!(
        short
            .stdout
            .contains("a.higraph:1:8: error[HG0009]: unexpected character '$'"),
        "{}",
        short.stdout
    );
    assert!(
        short
            .stdout
            .contains("a.higraph:3:2: error[HG0009]: unexpected character '$'"),
        "{}",
        short.stdout
    );
}

#[test]
fn json_is_sorted_by_file_then_position_then_code() {
    let tree = TempTree::new();
    tree.file("b.higraph", "$\n~ 'x\n")
        .file("a/z.higraph", "\"open\n$")
        .file("a.higraph", "~\n")
        .file("B.higraph", "$")
        .file("a/b/c.higraph", "@");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    let mut files: Vec<_> = files_and_codes(&report)
        .into_iter()
        .map(|(file, _)| file)
        .collect();
    // Code-point order of the workspace-relative path: upper case first, `.` before `/`.
    files.dedup();
    assert_eq!(
        files,
        [
            "B.higraph",
            "a.higraph",
            "a/b/c.higraph",
            "a/z.higraph",
            "b.higraph"
        ]
    );
    let diagnostics = report["diagnostics"].as_array().unwrap();
    let keys: Vec<_> = diagnostics
        .iter()
        .map(|d| {
            (
                d["file"].as_str().unwrap().to_string(),
                position(&d["range"]["start"]),
                position(&d["range"]["end"]),
                d["code"].as_str().unwrap().to_string(),
                d["message"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let mut sorted = keys.clone();
    sorted.sort();
    assert_eq!(keys, sorted);
}

// ------------------------------------------------------------------ workspace and selection

#[test]
fn only_files_under_the_paths_are_reported() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file("a/x.higraph", "$")
        .file("a/deeper/y.higraph", "$")
        .file("b/z.higraph", "$")
        .file("top.higraph", "$");
    let report = json(&tree.run(".", &["check", "--format", "json", "a"]));
    assert_eq!(
        files_and_codes(&report),
        [
            ("a/deeper/y.higraph".into(), "HG0009".into()),
            ("a/x.higraph".into(), "HG0009".into())
        ]
    );
    assert_eq!(report["summary"]["files"], 2);

    let report = json(&tree.run(".", &["check", "--format", "json", "b", "top.higraph"]));
    let files: Vec<_> = files_and_codes(&report)
        .into_iter()
        .map(|(f, _)| f)
        .collect();
    assert_eq!(files, ["b/z.higraph", "top.higraph"]);

    // A clean selection passes even though other files of the workspace have errors.
    tree.file("c/ok.higraph", "// fine\n");
    let run = tree.run(".", &["check", "c"]);
    assert_eq!(run.status, 0, "{}", run.stdout);
    assert!(run.stdout.is_empty());
}

#[test]
fn the_workspace_root_is_found_upwards() {
    let tree = TempTree::new();
    tree.file("ws/higraph.toml", "")
        .file("ws/graphs/sub/x.higraph", "$")
        .file("ws/other.higraph", "$");
    // From inside the workspace, without PATH: the root holds higraph.toml, so names are
    // relative to it, and only the current folder is reported.
    let report = json(&tree.run("ws/graphs", &["check", "--format", "json"]));
    assert_eq!(
        files_and_codes(&report),
        [("graphs/sub/x.higraph".into(), "HG0009".into())]
    );
    // A file PATH: its folder is where the search starts.
    let report = json(&tree.run(
        ".",
        &["check", "--format", "json", "ws/graphs/sub/x.higraph"],
    ));
    assert_eq!(
        files_and_codes(&report),
        [("graphs/sub/x.higraph".into(), "HG0009".into())]
    );
    assert_eq!(report["summary"]["files"], 1);
    // Without higraph.toml the first PATH's folder is the root.
    let plain = TempTree::new();
    plain.file("graphs/sub/x.higraph", "$");
    let report = json(&plain.run("graphs", &["check", "--format", "json"]));
    assert_eq!(
        files_and_codes(&report),
        [("sub/x.higraph".into(), "HG0009".into())]
    );
}

#[test]
fn hidden_folders_node_modules_and_target_are_skipped() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file(".git/x.higraph", "$")
        .file("node_modules/pkg/x.higraph", "$")
        .file("target/debug/x.higraph", "$")
        .file("sub/node_modules/x.higraph", "$")
        .file("sub/.cache/x.higraph", "$")
        .file("sub/target/x.higraph", "$")
        .file("sub/x.higraph", "$")
        .file("notes.txt", "$");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    let files: Vec<_> = files_and_codes(&report)
        .into_iter()
        .map(|(f, _)| f)
        .collect();
    // Only the root's `target` folder is a build folder.
    assert_eq!(files, ["sub/target/x.higraph", "sub/x.higraph"]);
    // Naming a file or a skipped folder explicitly checks it anyway.
    let report = json(&tree.run(
        ".",
        &["check", "--format", "json", "notes.txt", "node_modules"],
    ));
    let files: Vec<_> = files_and_codes(&report)
        .into_iter()
        .map(|(f, _)| f)
        .collect();
    assert_eq!(files, ["node_modules/pkg/x.higraph", "notes.txt"]);
}

#[test]
fn a_path_outside_the_workspace_is_named_absolutely() {
    let tree = TempTree::new();
    tree.file("ws/higraph.toml", "")
        .file("ws/a.higraph", "$")
        .file("elsewhere/b.higraph", "$");
    let report = json(&tree.run(".", &["check", "--format", "json", "ws", "elsewhere"]));
    let files: Vec<_> = files_and_codes(&report)
        .into_iter()
        .map(|(f, _)| f)
        .collect();
    assert_eq!(files.len(), 2, "{files:?}");
    assert!(files.contains(&"a.higraph".to_string()));
    let outside = files
        .iter()
        .find(|f| f.ends_with("elsewhere/b.higraph"))
        .unwrap();
    assert!(outside.starts_with('/'), "{outside}");
}

// ------------------------------------------------------------------ files that cannot be used

#[test]
fn invalid_utf8_is_hg6102() {
    let tree = TempTree::new();
    tree.file("latin1.higraph", b"// ok\ngraph Z\xE4hler\xFF < >\n");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    let diagnostics = report["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{report}");
    let d = &diagnostics[0];
    assert_eq!(d["code"], "HG6102");
    assert_eq!(d["severity"], "error");
    assert_eq!(
        d["message"],
        "file is not valid UTF-8 (invalid byte at offset 13)"
    );
    // The first invalid byte sequence; each invalid byte counts as one character.
    assert_eq!(position(&d["range"]["start"]), (1, 7));
    assert_eq!(position(&d["range"]["end"]), (1, 8));
    let human = tree.run(".", &["check", "--color", "never"]);
    assert_eq!(human.status, 1);
    assert!(
        human.stdout.contains("--> latin1.higraph:2:8\n"),
        "{}",
        human.stdout
    );
}

#[test]
fn a_leading_byte_order_mark_is_fine() {
    let tree = TempTree::new();
    tree.file("bom.higraph", "\u{FEFF}// kommentar\n");
    let run = tree.run(".", &["check"]);
    assert_eq!(run.status, 0, "{}", run.stdout);
}

#[test]
fn unreadable_workspace_file_is_hg6103() {
    let tree = TempTree::new();
    tree.folder("folder.higraph");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    let d = &report["diagnostics"][0];
    assert_eq!(d["code"], "HG6103", "{report}");
    assert_eq!(d["file"], "folder.higraph");
    assert!(
        d["message"]
            .as_str()
            .unwrap()
            .starts_with("cannot read file: "),
        "{d}"
    );
    assert_eq!(position(&d["range"]["start"]), (0, 0));
    assert_eq!(position(&d["range"]["end"]), (0, 0));
    let human = tree.run(".", &["check", "--color", "never"]);
    assert!(
        human.stdout.contains("--> folder.higraph:1:1"),
        "{}",
        human.stdout
    );
}

// ------------------------------------------------------------------ exit status

#[test]
fn exit_status_follows_the_error_count() {
    let tree = TempTree::new();
    tree.file("clean/a.higraph", "// only a comment\n")
        .file("broken/b.higraph", "$\n")
        .folder("empty");
    let clean = tree.run(".", &["check", "clean"]);
    assert_eq!(clean.status, 0);
    assert!(clean.stdout.is_empty(), "{}", clean.stdout);
    assert!(
        clean.stderr.contains("ok: 1 file checked"),
        "{}",
        clean.stderr
    );
    assert_eq!(tree.run(".", &["check", "empty"]).status, 0);
    assert_eq!(tree.run(".", &["check", "broken"]).status, 1);
    assert_eq!(tree.run(".", &["check"]).status, 1);
    for format in ["human", "short", "json", "github"] {
        assert_eq!(
            tree.run(".", &["check", "--format", format, "broken"])
                .status,
            1,
            "{format}"
        );
        assert_eq!(
            tree.run(".", &["check", "--format", format, "clean"])
                .status,
            0,
            "{format}"
        );
    }
    let report = json(&tree.run(".", &["check", "--format", "json", "empty"]));
    assert_eq!(report["diagnostics"], Value::Array(Vec::new()));
    assert_eq!(report["summary"]["files"], 0);
}

#[test]
fn deny_warnings_still_fails_on_errors_only_when_there_are_some() {
    // No rule emits warnings yet; `--deny warnings` must at least keep 0 and 1 apart.
    let tree = TempTree::new();
    tree.file("clean/a.higraph", "// fine\n")
        .file("broken/b.higraph", "'open\n");
    assert_eq!(
        tree.run(".", &["check", "--deny", "warnings", "clean"])
            .status,
        0
    );
    assert_eq!(
        tree.run(".", &["check", "--deny", "warnings", "broken"])
            .status,
        1
    );
    assert_eq!(
        tree.run(".", &["check", "--deny", "everything", "clean"])
            .status,
        2
    );
}

#[test]
fn missing_paths_are_usage_errors() {
    let tree = TempTree::new();
    tree.file("a.higraph", "// fine\n");
    for args in [
        &["check", "nope"][..],
        &["check", "a.higraph", "nope/deeper"][..],
    ] {
        let run = tree.run(".", args);
        assert_eq!(run.status, 2, "{args:?}");
        assert!(run.stderr.contains("does not exist"), "{}", run.stderr);
        assert!(run.stdout.is_empty(), "{}", run.stdout);
    }
}

#[test]
fn config_must_be_readable() {
    let tree = TempTree::new();
    tree.file("a.higraph", "// fine\n")
        .file("custom.toml", "[workspace]\n");
    assert_eq!(
        tree.run(".", &["check", "--config", "custom.toml"]).status,
        0
    );
    let run = tree.run(".", &["check", "--config", "missing.toml"]);
    assert_eq!(run.status, 2);
    assert!(run.stderr.contains("missing.toml"), "{}", run.stderr);
}

#[test]
fn configuration_problems_are_reported_whatever_the_paths() {
    // `diagnostics.md` §4.3: an invalid `higraph.toml` counts under status 1. It governs the
    // whole run, so a PATH that selects one file does not hide it.
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nfoo = 1\n")
        .file("sub/a.higraph", "// fine\n");
    for path in [".", "sub", "sub/a.higraph"] {
        let run = tree.run(".", &["check", "--format", "json", path]);
        assert_eq!(run.status, 1, "check {path}: {}", run.stdout);
        assert_eq!(
            files_and_codes(&json(&run)),
            [("higraph.toml".into(), "HG6101".into())],
            "check {path}"
        );
    }
}

#[test]
fn a_configuration_that_is_not_utf8_is_hg6101_not_a_usage_error() {
    let tree = TempTree::new();
    tree.file("higraph.toml", b"\xff\xfe[workspace]\n")
        .file("a.higraph", "// fine\n");
    let run = tree.run(".", &["check", "--format", "json"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    let report = json(&run);
    assert_eq!(
        files_and_codes(&report),
        [("higraph.toml".into(), "HG6101".into())]
    );
    assert_eq!(
        report["diagnostics"][0]["message"],
        "higraph.toml: file is not valid UTF-8 (invalid byte at offset 0)"
    );
}

#[test]
fn an_invalid_glob_is_hg6101_and_the_default_applies() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\ninclude = [\"[abc\"]\n")
        .file("a.higraph", "$");
    let report = json(&tree.run(".", &["check", "--format", "json"]));
    assert_eq!(
        files_and_codes(&report),
        [
            ("a.higraph".into(), "HG0009".into()),
            ("higraph.toml".into(), "HG6101".into())
        ]
    );
}

#[test]
fn bad_arguments_are_usage_errors() {
    let tree = TempTree::new();
    for args in [
        &["check", "--format", "xml"][..],
        &["check", "--color", "sometimes"][..],
        &["check", "--no-such-flag"][..],
        &["frobnicate"][..],
    ] {
        assert_eq!(tree.run(".", args).status, 2, "{args:?}");
    }
}

// ------------------------------------------------------------------ help and version

#[test]
fn help_and_version() {
    let tree = TempTree::new();
    let version = tree.run(".", &["--version"]);
    assert_eq!(version.status, 0);
    assert_eq!(
        version.stdout,
        format!("higraph-lsp {}\n", env!("CARGO_PKG_VERSION"))
    );
    for args in [
        &["--help"][..],
        &["check", "--help"][..],
        &["parse", "--help"][..],
        &["help", "check"][..],
    ] {
        let run = tree.run(".", args);
        assert_eq!(run.status, 0, "{args:?}");
        assert!(
            run.stdout.contains("Usage: higraph-lsp"),
            "{args:?}: {}",
            run.stdout
        );
    }
    let check_help = tree.run(".", &["check", "--help"]).stdout;
    for option in [
        "--format", "--deny", "--config", "--color", "human", "short", "json", "github",
    ] {
        assert!(
            check_help.contains(option),
            "{option} missing from:\n{check_help}"
        );
    }
    // No arguments: the language server, which ends with status 1 when its input ends
    // without `exit` (LSP 3.17); `lsp --help` explains it.
    let bare = tree.run(".", &[]);
    assert_eq!(bare.status, 1, "{bare:?}");
    assert_eq!(bare.stdout, "");
    let lsp_help = tree.run(".", &["lsp", "--help"]);
    assert_eq!(lsp_help.status, 0);
    assert!(lsp_help.stdout.contains("--stdio"), "{}", lsp_help.stdout);
}

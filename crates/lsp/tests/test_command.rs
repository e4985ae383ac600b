//! End-to-end tests of `higraph-lsp test` (`runtime.md` §7): the real binary on small
//! workspaces written to temporary folders. Human, JSON and JUnit output, exit statuses,
//! `--filter`, and `--trace` (the JSON trace validated against the schema in docs/schemas, the
//! VCD read by the `vcd` crate, the JUnit XML by `quick-xml`).

#[path = "../../../tests/cli/support.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;

use support::{TempTree, repo_root, run_in};

const PLANT: &str = r#"symbols < Knopf : E 0.0; Lampe : A 0.0; Merker : M 5.0; >
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

const LAMPE_AN: &str = r#"test Lampe_An "the lamp follows the button" <
  set Knopf := TRUE;
  step 2;
  expect Anzeige.state = 1 and Lampe;
  set Knopf := FALSE;
  until not Lampe within T#50MS;
>
"#;

const LAMPE_FALSCH: &str = r#"test Lampe_Falsch <
  step;
  expect Lampe "the lamp is off at first";
  set Knopf := TRUE;
  until Merker within T#30MS "nothing sets it";
  expect Lampe;
>
"#;

fn workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("plant.higraph", PLANT)
        .file("tests/an.higraph", LAMPE_AN)
        .file("tests/falsch.higraph", LAMPE_FALSCH);
    tree
}

fn test(tree: &TempTree, args: &[&str]) -> support::Run {
    let mut all = vec!["test"];
    all.extend_from_slice(args);
    run_in(tree.path(), &all)
}

#[test]
fn human_output_is_like_cargo_test() {
    let tree = workspace();
    let run = test(&tree, &[]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    insta::assert_snapshot!(run.stdout);
}

#[test]
fn passing_tests_exit_with_zero() {
    let tree = workspace();
    let run = test(&tree, &["--filter", "an"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout,
        "running 1 test\ntest Lampe_An ... ok (3 cycles, 30 ms)\n\n\
         test result: ok. 1 passed; 0 failed; 0 errors; 1 filtered out\n"
    );
}

#[test]
fn the_filter_ignores_letter_case_and_paths_select_files() {
    let tree = workspace();
    let run = test(&tree, &["--filter", "FALSCH"]);
    assert_eq!(run.status, 1);
    assert!(
        run.stdout
            .starts_with("running 1 test\ntest Lampe_Falsch ... FAILED\n")
    );
    // A PATH without tests: nothing runs, and that passes.
    let run = test(&tree, &["plant.higraph"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout,
        "running 0 tests\n\ntest result: ok. 0 passed; 0 failed; 0 errors; 0 filtered out\n"
    );
}

#[test]
fn usage_errors_exit_with_two() {
    let tree = workspace();
    assert_eq!(test(&tree, &["--format", "xml"]).status, 2);
    assert_eq!(test(&tree, &["missing.higraph"]).status, 2);
}

#[test]
fn tests_that_cannot_run_are_errors() {
    let tree = workspace();
    tree.file(
        "tests/kaputt.higraph",
        "test Kaputt <\n  run Kaputt_Grp;\n  step;\n  expect K.state = 0;\n>\n\
         graph Kaputt_G <\n  state 0 < C: U Nirgends; >\n>\n\
         group Kaputt_Grp fc FC2 db DB2 <\n  instance K : Kaputt_G < >\n>\n",
    );
    let run = test(&tree, &["--filter", "kaputt", "--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    assert_eq!(json["tests"][0]["result"], "error");
    assert_eq!(json["tests"][0]["failures"][0]["code"], "HG9904");
    assert_eq!(
        json["tests"][0]["failures"][0]["message"],
        "test Kaputt cannot run: 2 error(s) in graph Kaputt_G"
    );
    assert_eq!(
        json["tests"][0]["failures"][0]["range"],
        serde_json::json!({"start": {"line": 0, "character": 5}, "end": {"line": 0, "character": 11}})
    );
    assert_eq!(json["summary"]["errors"], 1);
    let junit = test(&tree, &["--filter", "kaputt", "--format", "junit"]);
    assert_eq!(junit.status, 1);
    assert_eq!(
        check_junit(&junit.stdout),
        ["testsuites", "testsuite", "testcase", "error"]
    );
    assert!(
        junit
            .stdout
            .contains("<error type=\"HG9904\" message=\"test Kaputt cannot run")
    );
}

fn validator(schema: &str) -> jsonschema::Validator {
    let path = repo_root().join("docs/schemas").join(schema);
    let text = std::fs::read_to_string(&path).expect("the schema");
    let schema: serde_json::Value = serde_json::from_str(&text).expect("schema JSON");
    jsonschema::validator_for(&schema).expect("a valid schema")
}

fn assert_valid(validator: &jsonschema::Validator, value: &serde_json::Value) {
    let errors: Vec<String> = validator
        .iter_errors(value)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}\n{value:#}");
}

#[test]
fn json_output() {
    let tree = workspace();
    let run = test(&tree, &["--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    assert_valid(&validator("test-output.schema.json"), &json);
    insta::assert_snapshot!(run.stdout);
}

#[test]
fn junit_output_is_well_formed() {
    let tree = workspace();
    let run = test(&tree, &["--format", "junit"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let elements = check_junit(&run.stdout);
    assert_eq!(
        elements,
        [
            "testsuites",
            "testsuite",
            "testcase",
            "testsuite",
            "testcase",
            "failure",
            "failure"
        ]
    );
    // Wall-clock times vary: mask them for the snapshot.
    let masked = mask_times(&run.stdout);
    insta::assert_snapshot!(masked);
}

/// Checks a JUnit report the way Jenkins' JUnit schema describes it: well-formed XML,
/// `testsuites` › `testsuite` › `testcase` › `failure`/`error`, the required attributes
/// (`name`, `tests`, `failures`, `errors` of a suite; `name` of a case), times as decimal
/// seconds, and counts that agree with the cases. Besides the schema's attributes it admits
/// the ones `runtime.md` §7 adds (`skipped` on `testsuites`, `file` and `line` on a case).
/// Returns the element names in document order.
fn check_junit(xml: &str) -> Vec<String> {
    use quick_xml::events::{BytesStart, Event};
    fn attributes(e: &BytesStart<'_>) -> Vec<(String, String)> {
        e.attributes()
            .map(|a| {
                let a = a.expect("a well-formed attribute");
                (
                    String::from_utf8_lossy(a.key.as_ref().as_ref()).into_owned(),
                    a.normalized_value(quick_xml::XmlVersion::Explicit1_0)
                        .expect("an attribute value")
                        .into_owned(),
                )
            })
            .collect()
    }
    let allowed = |element: &str| -> (&[&str], &[&str]) {
        match element {
            "testsuites" => (
                &[],
                &["name", "time", "tests", "failures", "errors", "skipped"],
            ),
            "testsuite" => (
                &["name", "tests", "failures", "errors"],
                &["name", "tests", "failures", "errors", "time", "skipped"],
            ),
            "testcase" => (&["name"], &["name", "time", "classname", "file", "line"]),
            "failure" | "error" => (&[], &["type", "message"]),
            other => panic!("unexpected element <{other}>"),
        }
    };
    let parent_of = |element: &str| match element {
        "testsuites" => None,
        "testsuite" => Some("testsuites"),
        "testcase" => Some("testsuite"),
        _ => Some("testcase"),
    };
    let is_time = |t: &str| {
        let (whole, fraction) = t.split_once('.').unwrap_or((t, ""));
        !whole.is_empty()
            && whole
                .chars()
                .chain(fraction.chars())
                .all(|c| c.is_ascii_digit())
    };
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut stack: Vec<String> = Vec::new();
    let mut names = Vec::new();
    // Per open suite: (tests, failures, errors) declared and counted.
    let mut suite: Option<([usize; 3], [usize; 3])> = None;
    let mut case_kinds: Vec<&str> = Vec::new();
    loop {
        let event = reader.read_event().expect("well-formed XML");
        let (e, empty) = match &event {
            Event::Eof => break,
            Event::Start(e) => (e.clone(), false),
            Event::Empty(e) => (e.clone(), true),
            Event::End(e) => {
                let name = String::from_utf8_lossy(e.name().as_ref().as_ref()).into_owned();
                assert_eq!(stack.pop().as_deref(), Some(name.as_str()));
                if name == "testcase" {
                    if let Some((_, counted)) = &mut suite {
                        counted[0] += 1;
                        counted[1] += usize::from(case_kinds.contains(&"failure"));
                        counted[2] += usize::from(case_kinds.contains(&"error"));
                    }
                    case_kinds.clear();
                }
                if name == "testsuite" {
                    let (declared, counted) = suite.take().expect("an open suite");
                    assert_eq!(declared, counted, "suite counts");
                }
                continue;
            }
            _ => continue,
        };
        let name = String::from_utf8_lossy(e.name().as_ref().as_ref()).into_owned();
        assert_eq!(
            stack.last().map(String::as_str),
            parent_of(&name),
            "<{name}> placed"
        );
        let attrs = attributes(&e);
        let (required, permitted) = allowed(&name);
        for r in required {
            assert!(attrs.iter().any(|(k, _)| k == r), "<{name}> needs {r}");
        }
        for (k, v) in &attrs {
            assert!(permitted.contains(&k.as_str()), "<{name}> has {k}");
            if k == "time" {
                assert!(is_time(v), "time {v}");
            }
        }
        let number = |key: &str| {
            attrs
                .iter()
                .find(|(k, _)| k == key)
                .map_or(0, |(_, v)| v.parse().expect("a count"))
        };
        match name.as_str() {
            "testsuite" => {
                suite = Some((
                    [number("tests"), number("failures"), number("errors")],
                    [0; 3],
                ));
            }
            "failure" => case_kinds.push("failure"),
            "error" => case_kinds.push("error"),
            _ => {}
        }
        names.push(name.clone());
        if empty {
            if name == "testcase"
                && let Some((_, counted)) = &mut suite
            {
                counted[0] += 1;
            }
        } else {
            stack.push(name);
        }
    }
    assert!(stack.is_empty());
    names
}

fn mask_times(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("time=\"") {
        let (head, tail) = rest.split_at(at + 6);
        out.push_str(head);
        let end = tail.find('"').unwrap_or(0);
        out.push('T');
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

#[test]
fn traces_are_written_and_read_back() {
    let tree = workspace();
    let run = test(&tree, &["--trace", "out/traces"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let dir = tree.path().join("out/traces");
    let json_path = dir.join("Lampe_An.json");
    let text = std::fs::read_to_string(&json_path).expect("the JSON trace");
    let trace: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert_valid(&validator("test-trace.schema.json"), &trace);
    assert_eq!(trace["test"], "Lampe_An");
    assert_eq!(trace["file"], "tests/an.higraph");
    assert_eq!(trace["cycles"].as_array().map(Vec::len), Some(3));
    let failed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("Lampe_Falsch.json")).unwrap())
            .unwrap();
    assert_valid(&validator("test-trace.schema.json"), &failed);
    assert_eq!(failed["result"], "failed");
    assert_eq!(failed["failures"][0]["code"], "HG9901");

    // The VCD loads in an independent reader.
    let vcd_text = std::fs::read_to_string(dir.join("Lampe_An.vcd")).expect("the VCD");
    let mut parser = vcd::Parser::new(vcd_text.as_bytes());
    let header = parser.parse_header().expect("VCD header");
    assert!(
        header
            .find_var(&["Lampe_An", "Pult", "Anzeige", "state"])
            .is_some()
    );
    assert!(header.find_var(&["Lampe_An", "watch", "Lampe"]).is_some());
    for command in parser {
        command.expect("VCD command");
    }

    // Byte for byte deterministic: a second run writes the same files (and may replace them).
    let again = test(&tree, &["--trace", "out/traces"]);
    assert_eq!(again.status, 1, "{}", again.stderr);
    assert_eq!(std::fs::read_to_string(&json_path).unwrap(), text);
    assert_eq!(
        std::fs::read_to_string(dir.join("Lampe_An.vcd")).unwrap(),
        vcd_text
    );
    // No temporary files are left.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 4, "{names:?}");
}

#[test]
fn traces_never_replace_other_files() {
    let tree = workspace();
    tree.file("out/Lampe_An.json", "{\"mine\": true}\n");
    let run = test(&tree, &["--trace", "out"]);
    assert_eq!(run.status, 2, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains("is not a trace of higraph-lsp"),
        "{}",
        run.stderr
    );
    assert_eq!(
        std::fs::read_to_string(tree.path().join("out/Lampe_An.json")).unwrap(),
        "{\"mine\": true}\n"
    );
    // Nothing ran: no other trace was written either.
    assert!(!Path::new(&tree.path().join("out/Lampe_Falsch.json")).exists());
}

#[test]
fn failures_of_a_later_test_in_a_file_point_into_it() {
    let tree = workspace();
    tree.file("tests/both.higraph", format!("{LAMPE_AN}{LAMPE_FALSCH}"));
    let run = test(&tree, &["tests/both.higraph", "--format", "json"]);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    let second = &json["tests"][1];
    assert_eq!(second["name"], "Lampe_Falsch");
    // The second test starts on line 7 (0-based), its `expect Lampe` on line 9.
    assert_eq!(
        second["range"]["start"],
        serde_json::json!({"line": 7, "character": 5})
    );
    assert_eq!(
        second["failures"][0]["range"]["start"],
        serde_json::json!({"line": 9, "character": 9})
    );
}

// ------------------------------------------------------------------ the examples of the spec

/// A temporary copy of `tests/fixtures/runtime/{name}`, with `replace` applied to its files.
fn fixture(name: &str, replace: Option<(&str, &str)>) -> TempTree {
    let tree = TempTree::new();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/runtime")
        .join(name);
    for entry in std::fs::read_dir(&dir).expect("the fixture") {
        let entry = entry.expect("an entry");
        let mut text = std::fs::read_to_string(entry.path()).expect("a fixture file");
        if let Some((from, to)) = replace
            && text.contains(from)
        {
            text = text.replacen(from, to, 1);
        }
        tree.file(&entry.file_name().to_string_lossy(), text);
    }
    tree
}

#[test]
fn the_drilling_machine_test_passes() {
    let run = test(&fixture("drilling", None), &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout,
        "running 1 test\ntest Bohrzyklus ... ok (35 cycles, 350 ms)\n\n\
         test result: ok. 1 passed; 0 failed; 0 errors; 0 filtered out\n"
    );
}

#[test]
fn a_changed_expectation_of_the_drilling_test_fails_where_it_should() {
    let tree = fixture(
        "drilling",
        Some(("ST_CurrValue = 9800", "ST_CurrValue = 9790")),
    );
    let run = test(&tree, &["--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    let failures = &json["tests"][0]["failures"];
    assert_eq!(failures.as_array().map(Vec::len), Some(1), "{failures:#}");
    let f = &failures[0];
    assert_eq!(f["code"], "HG9901");
    assert_eq!(
        f["message"],
        "expect failed: remaining supervision time in ms: at cycle 28 (t = 280 ms): \
         Vorschub.ST_CurrValue = 9800"
    );
    assert_eq!(
        (f["cycle"].as_u64(), f["time_ms"].as_u64()),
        (Some(28), Some(280))
    );
    assert_eq!(
        f["values"],
        serde_json::json!({"Vorschub.ST_CurrValue": 9800})
    );
}

#[test]
fn the_chart_test_with_hold_and_resume_passes() {
    let run = test(&fixture("filling", None), &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout
            .contains("test Abfuellen_Halten ... ok (62 cycles, 6200 ms)")
    );
}

#[test]
fn a_changed_expectation_of_the_chart_test_fails_like_the_spec_shows() {
    let tree = fixture(
        "filling",
        Some((
            "expect Abfuellen.state = Holding and not Ventil and Ventil_Sperre;",
            "expect Abfuellen.state = Holding and Ventil and Ventil_Sperre;",
        )),
    );
    let run = test(&tree, &[]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    insta::assert_snapshot!(run.stdout);
}

#[test]
fn the_parallel_chart_trace_is_a_byte_snapshot() {
    let tree = fixture("parallel", None);
    let run = test(&tree, &["--trace", "traces"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    let json = std::fs::read_to_string(tree.path().join("traces/E6.json")).expect("trace");
    let value: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert_valid(&validator("test-trace.schema.json"), &value);
    insta::assert_snapshot!("e6_trace_json", json);
    let vcd_text = std::fs::read_to_string(tree.path().join("traces/E6.vcd")).expect("VCD");
    let mut parser = vcd::Parser::new(vcd_text.as_bytes());
    parser.parse_header().expect("VCD header");
    for command in parser {
        command.expect("VCD command");
    }
    // The version line changes with every release; the rest is pinned.
    let pinned = vcd_text.replacen(env!("CARGO_PKG_VERSION"), "VERSION", 1);
    insta::assert_snapshot!("e6_trace_vcd", pinned);
}

// ------------------------------------------------------------ fixtures of the result codes

/// `tests/fixtures/results/HG99nn/{fail,pass}*.higraph`: each file is a workspace of its own
/// (with the SIMATIC mnemonics) whose tests `higraph-lsp test` runs. A failing fixture must
/// report its code (its human output is a snapshot), a passing one must pass.
fn run_result_fixture(path: &Path) -> (String, support::Run) {
    let code = path
        .parent()
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tree = TempTree::new();
    tree.file("higraph.toml", "[workspace]\nmnemonic = \"simatic\"\n")
        .file("main.higraph", std::fs::read(path).expect("the fixture"));
    (code, test(&tree, &[]))
}

#[test]
fn failing_result_fixtures_report_their_code() {
    insta::glob!("fixtures/results", "HG99*/fail*.higraph", |path| {
        let (code, run) = run_result_fixture(path);
        assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
        assert!(
            run.stdout.contains(&format!("error[{code}]")),
            "{} should report {code}:\n{}",
            path.display(),
            run.stdout
        );
        insta::assert_snapshot!(run.stdout);
    });
}

#[test]
fn passing_result_fixtures_pass() {
    insta::glob!("fixtures/results", "HG99*/pass*.higraph", |path| {
        let (code, run) = run_result_fixture(path);
        assert_eq!(
            run.status,
            0,
            "{}:\n{}{}",
            path.display(),
            run.stdout,
            run.stderr
        );
        assert!(!run.stdout.contains(&code), "{}", run.stdout);
    });
}

#[test]
fn without_a_path_every_test_of_the_workspace_runs() {
    let tree = workspace();
    tree.file(
        "oben.higraph",
        "test Oben <\n  run Pult;\n  step;\n  expect not Lampe;\n>\n",
    );
    let run = tree.run("tests", &["test", "--filter", "oben"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("test Oben ... ok"), "{}", run.stdout);
    // From the sub-folder, a PATH selects below it.
    let run = tree.run("tests", &["test", "an.higraph"]);
    assert!(run.stdout.starts_with("running 1 test\n"), "{}", run.stdout);
}

#[test]
fn the_group_examples_e1_to_e5_pass() {
    let run = test(&fixture("groups", None), &[]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout,
        "running 5 tests\n\
         test E1 ... ok (7 cycles, 70 ms)\n\
         test E2 ... ok (7 cycles, 70 ms)\n\
         test E3 ... ok (4 cycles, 40 ms)\n\
         test E4 ... ok (11 cycles, 110 ms)\n\
         test E5 ... ok (4 cycles, 40 ms)\n\n\
         test result: ok. 5 passed; 0 failed; 0 errors; 0 filtered out\n"
    );
}

#[test]
fn a_changed_expectation_of_e4_fails_where_it_should() {
    let tree = fixture(
        "groups",
        Some(("A.WT_CurrValue = 10 and", "A.WT_CurrValue = 20 and")),
    );
    let run = test(&tree, &["--filter", "E4", "--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    let f = &json["tests"][0]["failures"][0];
    assert_eq!(f["code"], "HG9901");
    assert_eq!(
        f["message"],
        "expect failed: at cycle 6 (t = 60 ms): A.state = 1, A.WT_CurrValue = 10, \
         B.ST_CurrValue = 40"
    );
    assert_eq!(
        f["range"]["start"],
        serde_json::json!({"line": 20, "character": 9})
    );
    assert_eq!(
        json["tests"][0]["failures"].as_array().map(Vec::len),
        Some(1)
    );
}

#[test]
fn the_drilling_example_test_passes() {
    let run = run_in(&repo_root(), &["test", "examples/drilling"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains("test Bohrzyklus ... ok ("),
        "{}",
        run.stdout
    );
}

#[test]
fn an_until_failure_quotes_the_expression_as_written() {
    let tree = workspace();
    tree.file(
        "tests/wort.higraph",
        "test Wort <\n  run Pult;\n  until MW  10 = W#16#FF\n    and Lampe within T#20MS;\n>\n",
    );
    let run = test(&tree, &["--filter", "wort", "--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    assert_eq!(
        json["tests"][0]["failures"][0]["message"],
        "'MW 10 = W#16#FF and Lampe' did not hold within T#20MS: at cycle 2: MW10 = 0, \
         Lampe = FALSE"
    );
}

// ------------------------------------------------------------------- IEC charts (docs/iec.md)

/// A temporary copy of `examples/ampel`, with `replace` applied to its tests.
fn ampel(replace: Option<(&str, &str)>) -> TempTree {
    let tree = TempTree::new();
    let dir = repo_root().join("examples/ampel");
    for name in ["higraph.toml", "ampel.higraph", "tests.higraph"] {
        let mut text = std::fs::read_to_string(dir.join(name)).expect("an example file");
        if let Some((from, to)) = replace {
            text = text.replacen(from, to, 1);
        }
        tree.file(name, text);
    }
    tree
}

#[test]
fn the_ampel_example_test_passes() {
    let run = run_in(&repo_root(), &["test", "examples/ampel"]);
    assert_eq!(run.status, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout
            .contains("test Ampel_Runde ... ok (95 cycles, 9500 ms)"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("test Teile_Zaehlen ... ok ("),
        "{}",
        run.stdout
    );
}

#[test]
fn a_changed_expectation_of_the_ampel_example_fails() {
    let tree = ampel(Some((
        "expect Lampe_Gruen and not Lampe_Rot and Ampel.Phase = 2;",
        "expect Lampe_Gruen and not Lampe_Rot and Ampel.Phase = 3;",
    )));
    let run = test(&tree, &["--filter", "Ampel_Runde", "--format", "json"]);
    assert_eq!(run.status, 1, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    let failures = &json["tests"][0]["failures"];
    assert_eq!(failures.as_array().map(Vec::len), Some(1), "{failures:#}");
    assert_eq!(failures[0]["code"], "HG9901");
    assert_eq!(
        (
            failures[0]["cycle"].as_u64(),
            failures[0]["time_ms"].as_u64()
        ),
        (Some(43), Some(4300))
    );
    assert_eq!(
        failures[0]["values"],
        serde_json::json!({"Lampe_Gruen": true, "Lampe_Rot": false, "Ampel.Phase": 2})
    );
}

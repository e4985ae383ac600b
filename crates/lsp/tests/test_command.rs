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
    // Well-formed XML with the elements CI reporters read.
    let mut reader = quick_xml::Reader::from_str(&run.stdout);
    let mut elements = Vec::new();
    loop {
        match reader.read_event().expect("well-formed XML") {
            quick_xml::events::Event::Eof => break,
            quick_xml::events::Event::Start(e) | quick_xml::events::Event::Empty(e) => {
                elements.push(String::from_utf8_lossy(e.name().as_ref().as_ref()).into_owned());
            }
            _ => {}
        }
    }
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

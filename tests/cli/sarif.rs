//! `higraph-lsp check --format sarif` (`tooling.md` §2): every log is validated against the
//! official SARIF 2.1.0 schema, and its structure is compared with the JSON output of the same
//! workspace: same results in the same order, 1-based positions in characters, rules listing
//! exactly the codes that occur, related locations, fixes and exit status.
//!
//! `tests/data/sarif-schema-2.1.0.json` is the OASIS SARIF 2.1.0 JSON schema (draft-07, `$id`
//! `https://raw.githubusercontent.com/oasis-tcs/sarif-spec/master/Schemata/sarif-schema-2.1.0.json`),
//! copied unchanged from the `serde-sarif` 0.8.0 crate (`src/schema.json`), which generates its
//! types from it. [`schema`] corrects one known defect of that text in memory (see there).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::support::{Run, TempTree, repo_root, run_in};

/// The shipped SARIF 2.1.0 schema.
const SCHEMA: &str = include_str!("../data/sarif-schema-2.1.0.json");

/// The `pattern` of `run.language` and `toolComponent.language` in the 2.1.0 schema as first
/// published: it has a stray `]`, so it is not a valid regular expression, and a validator that
/// checks the schema against its meta-schema refuses it (oasis-tcs/sarif-spec issue 488).
const BROKEN_LANGUAGE_PATTERN: &str = r#""^[a-zA-Z]{2}|^[a-zA-Z]{2}-[a-zA-Z]{2}]?$""#;
/// The pattern that replaced it in SARIF 2.1.0 Errata 01.
const ERRATA_LANGUAGE_PATTERN: &str = r#""^[a-zA-Z]{2}(-[a-zA-Z]{2})?$""#;

/// The shipped schema with the language pattern of Errata 01. Our logs never write
/// `language`, so this changes nothing that is checked; it only lets the schema compile.
fn schema() -> Value {
    assert_eq!(
        SCHEMA.matches(BROKEN_LANGUAGE_PATTERN).count(),
        2,
        "the shipped schema is the published 2.1.0 text"
    );
    let text = SCHEMA.replace(BROKEN_LANGUAGE_PATTERN, ERRATA_LANGUAGE_PATTERN);
    serde_json::from_str(&text).expect("the shipped schema is JSON")
}

/// A validator for the schema (draft-07), with `format` checked too, so that URIs must be
/// valid URI references.
fn validator() -> jsonschema::Validator {
    jsonschema::draft7::options()
        .should_validate_formats(true)
        .build(&schema())
        .expect("the schema compiles")
}

/// Parses `run`'s standard output as JSON.
fn parse(run: &Run) -> Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|error| panic!("not JSON ({error}):\n{}\n{}", run.stdout, run.stderr))
}

/// Validates `log` against the schema and panics with every violation.
fn assert_valid_sarif(log: &Value) {
    let errors: Vec<String> = validator()
        .iter_errors(log)
        .map(|error| format!("{} at {}", error, error.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "the log violates SARIF 2.1.0:\n{}\n{log:#}",
        errors.join("\n")
    );
}

/// One workspace checked twice, with `--format sarif` and `--format json`.
struct Checked {
    /// The SARIF log (validated against the schema).
    log: Value,
    /// The JSON report of the same run.
    report: Value,
    /// The exit status (the same for both formats).
    status: i32,
    /// The workspace root, against which the reported paths are resolved.
    root: PathBuf,
}

/// Runs `check --format sarif` and `check --format json` with `args` in `root` (a workspace
/// root), checks that both exit alike and that the SARIF run prints nothing on stderr, and
/// validates the log.
fn check_both(root: &Path, args: &[&str]) -> Checked {
    let with_format = |format: &'static str| -> Vec<&str> {
        ["check", "--format", format]
            .iter()
            .chain(args)
            .copied()
            .collect()
    };
    let sarif_run = run_in(root, &with_format("sarif"));
    let json_run = run_in(root, &with_format("json"));
    assert_eq!(
        sarif_run.status, json_run.status,
        "sarif and json exit alike\n{}",
        sarif_run.stderr
    );
    assert!(
        sarif_run.stderr.is_empty(),
        "nothing on stderr: {}",
        sarif_run.stderr
    );
    let log = parse(&sarif_run);
    assert_valid_sarif(&log);
    Checked {
        log,
        report: parse(&json_run),
        status: sarif_run.status,
        root: root.to_path_buf(),
    }
}

/// [`check_both`] in the root of `tree`.
fn check_tree(tree: &TempTree, args: &[&str]) -> Checked {
    check_both(tree.path(), args)
}

/// The only run of a log, after checking the log's envelope and the tool.
fn the_run(log: &Value) -> &Value {
    assert_eq!(log["version"], "2.1.0");
    let runs = log["runs"].as_array().expect("runs array");
    assert_eq!(runs.len(), 1, "one run");
    let run = &runs[0];
    let driver = &run["tool"]["driver"];
    assert_eq!(driver["name"], "higraph-lsp");
    assert_eq!(driver["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(run["columnKind"], "unicodeCodePoints");
    assert!(
        run["originalUriBaseIds"]["%SRCROOT%"].is_object(),
        "%SRCROOT% is declared: {run:#}"
    );
    run
}

fn results(run: &Value) -> &Vec<Value> {
    run["results"].as_array().expect("results array")
}

fn diagnostics(report: &Value) -> &Vec<Value> {
    report["diagnostics"].as_array().expect("diagnostics array")
}

/// The rule ids of `tool.driver.rules`, in order.
fn rule_ids(run: &Value) -> Vec<String> {
    run["tool"]["driver"]["rules"]
        .as_array()
        .expect("rules array")
        .iter()
        .map(|rule| rule["id"].as_str().expect("rule id").to_string())
        .collect()
}

/// The rule a result refers to, after checking that `ruleIndex` and `ruleId` agree.
fn rule_of<'a>(run: &'a Value, result: &Value) -> &'a Value {
    let index = result["ruleIndex"].as_u64().expect("ruleIndex") as usize;
    let rule = &run["tool"]["driver"]["rules"][index];
    assert_eq!(rule["id"], result["ruleId"], "ruleIndex points at ruleId");
    rule
}

/// The file and region of a SARIF location: `(uri, [startLine, startColumn, endLine,
/// endColumn])`, after checking that the URI is relative to `%SRCROOT%`.
fn file_and_region(location: &Value) -> (String, [u64; 4]) {
    let physical = &location["physicalLocation"];
    let artifact = &physical["artifactLocation"];
    assert_eq!(artifact["uriBaseId"], "%SRCROOT%", "{location}");
    let region = &physical["region"];
    let number = |key: &str| {
        region[key]
            .as_u64()
            .unwrap_or_else(|| panic!("{key} in {region}"))
    };
    (
        artifact["uri"].as_str().expect("uri").to_string(),
        [
            number("startLine"),
            number("startColumn"),
            number("endLine"),
            number("endColumn"),
        ],
    )
}

/// The lines of `text`, which break at LF, CR LF or a lone CR (`diagnostics.md` §4.1).
fn lines(text: &str) -> Vec<&str> {
    let bytes = text.as_bytes();
    let mut lines = Vec::new();
    let (mut start, mut i) = (0, 0);
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                lines.push(&text[start..i]);
                i += 1;
                start = i;
            }
            b'\r' => {
                lines.push(&text[start..i]);
                i += if bytes.get(i + 1) == Some(&b'\n') {
                    2
                } else {
                    1
                };
                start = i;
            }
            _ => i += 1,
        }
    }
    lines.push(&text[start..]);
    lines
}

/// The 1-based character column of a 0-based UTF-16 column of `line`.
fn char_column(line: &str, utf16: u64) -> u64 {
    let (mut units, mut chars) = (0, 1);
    for c in line.chars() {
        if units >= utf16 {
            break;
        }
        units += c.len_utf16() as u64;
        chars += 1;
    }
    chars
}

/// The SARIF region `[startLine, startColumn, endLine, endColumn]` that a JSON `range` (0-based,
/// UTF-16) of `file` must become: 1-based lines, 1-based character columns. The file is read
/// from the workspace `root`.
fn expected_region(root: &Path, file: &str, range: &Value) -> [u64; 4] {
    let text = std::fs::read_to_string(root.join(file))
        .unwrap_or_else(|error| panic!("read {file}: {error}"));
    let lines = lines(&text);
    let position = |end: &str| {
        let line = range[end]["line"].as_u64().expect("line");
        let character = range[end]["character"].as_u64().expect("character");
        let content = lines.get(line as usize).copied().unwrap_or("");
        (line + 1, char_column(content, character))
    };
    let (start_line, start_column) = position("start");
    let (end_line, end_column) = position("end");
    [start_line, start_column, end_line, end_column]
}

/// The SARIF level of a JSON severity.
fn level_of(severity: &Value) -> &'static str {
    match severity.as_str().expect("severity") {
        "error" => "error",
        "warning" => "warning",
        "info" | "hint" => "note",
        other => panic!("unknown severity {other}"),
    }
}

/// Checks the rules and every result against the JSON diagnostic at the same index: rule,
/// level, message, location, related locations and fixes.
fn assert_matches_json(checked: &Checked) {
    let run = the_run(&checked.log);
    let expected = |file: &Value, range: &Value| {
        expected_region(&checked.root, file.as_str().expect("file"), range)
    };
    let results = results(run);
    let diagnostics = diagnostics(&checked.report);
    assert_eq!(results.len(), diagnostics.len(), "{run:#}");

    let codes: BTreeSet<String> = diagnostics
        .iter()
        .map(|d| d["code"].as_str().expect("code").to_string())
        .collect();
    assert_eq!(
        rule_ids(run),
        codes.into_iter().collect::<Vec<_>>(),
        "rules are exactly the codes that occur, sorted"
    );

    for (result, diagnostic) in results.iter().zip(diagnostics) {
        assert_eq!(result["ruleId"], diagnostic["code"]);
        rule_of(run, result);
        assert_eq!(result["level"], level_of(&diagnostic["severity"]));
        assert_eq!(result["message"]["text"], diagnostic["message"]);

        let locations = result["locations"].as_array().expect("locations");
        assert_eq!(locations.len(), 1);
        let (uri, region) = file_and_region(&locations[0]);
        assert_eq!(uri, diagnostic["file"].as_str().expect("file"));
        assert_eq!(
            region,
            expected(&diagnostic["file"], &diagnostic["range"]),
            "{result:#}"
        );

        let related = diagnostic["related"].as_array().expect("related");
        if related.is_empty() {
            assert!(result.get("relatedLocations").is_none(), "{result:#}");
        } else {
            let sarif_related = result["relatedLocations"]
                .as_array()
                .expect("relatedLocations when there are related locations");
            assert_eq!(sarif_related.len(), related.len());
            for (location, related) in sarif_related.iter().zip(related) {
                let (uri, region) = file_and_region(location);
                assert_eq!(uri, related["file"].as_str().expect("file"));
                assert_eq!(region, expected(&related["file"], &related["range"]));
                assert_eq!(location["message"]["text"], related["message"]);
            }
        }

        let fixes = diagnostic["fixes"].as_array().expect("fixes");
        if fixes.is_empty() {
            assert!(result.get("fixes").is_none(), "{result:#}");
        } else {
            let sarif_fixes = result["fixes"]
                .as_array()
                .expect("fixes when there are fixes");
            assert_eq!(sarif_fixes.len(), fixes.len());
            for (sarif_fix, fix) in sarif_fixes.iter().zip(fixes) {
                assert_eq!(sarif_fix["description"]["text"], fix["title"]);
                // Each test fix edits one file; flatten the replacements in order.
                let replacements: Vec<(String, &Value)> = sarif_fix["artifactChanges"]
                    .as_array()
                    .expect("artifactChanges")
                    .iter()
                    .flat_map(|change| {
                        let uri = change["artifactLocation"]["uri"]
                            .as_str()
                            .expect("uri")
                            .to_string();
                        change["replacements"]
                            .as_array()
                            .expect("replacements")
                            .iter()
                            .map(move |replacement| (uri.clone(), replacement))
                    })
                    .collect();
                let edits = fix["edits"].as_array().expect("edits");
                assert_eq!(replacements.len(), edits.len());
                for ((uri, replacement), edit) in replacements.iter().zip(edits) {
                    assert_eq!(uri, edit["file"].as_str().expect("file"));
                    let deleted = &replacement["deletedRegion"];
                    let region = [
                        &deleted["startLine"],
                        &deleted["startColumn"],
                        &deleted["endLine"],
                        &deleted["endColumn"],
                    ]
                    .map(|n| n.as_u64().expect("deletedRegion position"));
                    assert_eq!(region, expected(&edit["file"], &edit["range"]));
                    assert_eq!(replacement["insertedContent"]["text"], edit["newText"]);
                }
            }
        }
    }
}

// ------------------------------------------------------------------ syntax errors

/// Syntax errors in ASCII files: a missing `;` (HG0002, with a fix), a second `mnemonic`
/// (HG0011, with a related location), an unclosed `<` (HG0003, related location and fix), an
/// unclosed character constant (HG0005). Other rules may report on these files too.
fn syntax_workspace() -> TempTree {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file(
            "graphs/ventil.higraph",
            "graph Ventil \"Ventil\" < in < a : INT b : INT; > >\n",
        )
        .file(
            "graphs/pumpe.higraph",
            "mnemonic international;\nmnemonic simatic;\ngraph Pumpe \"Pumpe\" <\n",
        )
        .file(
            "motor.higraph",
            "graph Motor <\n  stat < Zeichen : CHAR := 'x\n  ; >\n>\n",
        )
        .file("clean.higraph", "// nothing to see here\n");
    tree
}

/// The first result with rule `code`.
fn result_for<'a>(run: &'a Value, code: &str) -> &'a Value {
    results(run)
        .iter()
        .find(|result| result["ruleId"] == code)
        .unwrap_or_else(|| panic!("a {code} result: {run:#}"))
}

#[test]
fn syntax_errors_validate_and_match_the_json_output() {
    let tree = syntax_workspace();
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 1, "error-level results fail the check");
    assert_matches_json(&checked);
    let run = the_run(&checked.log);
    let ids = rule_ids(run);
    for code in ["HG0002", "HG0003", "HG0005", "HG0011"] {
        assert!(ids.contains(&code.to_string()), "{code} in {ids:?}");
    }
    for result in results(run) {
        let rule = rule_of(run, result);
        assert!(
            rule["shortDescription"]["text"]
                .as_str()
                .is_some_and(|text| !text.is_empty()),
            "{rule}"
        );
        if result["ruleId"]
            .as_str()
            .is_some_and(|id| id.starts_with("HG0"))
        {
            assert_eq!(result["level"], "error", "{result}");
            assert_eq!(rule["defaultConfiguration"]["level"], "error", "{rule}");
        }
    }
    let unclosed = result_for(run, "HG0003");
    assert!(unclosed["relatedLocations"].is_array(), "{unclosed:#}");
    assert!(unclosed["fixes"].is_array(), "{unclosed:#}");
}

#[test]
fn missing_semicolon_has_an_insert_fix() {
    let tree = TempTree::new();
    tree.file("a.higraph", "graph A \"A\" < in < x : INT y : INT; > >\n");
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 1);
    assert_matches_json(&checked);
    let run = the_run(&checked.log);

    let result = result_for(run, "HG0002");
    let rule = rule_of(run, result);
    assert_eq!(
        rule["shortDescription"]["text"],
        "missing ';' after {element}"
    );
    // `x : INT` ends before column 27 (1-based, the column after `INT`); the `;` goes there.
    let (uri, region) = file_and_region(&result["locations"][0]);
    assert_eq!(uri, "a.higraph");
    assert_eq!(region, [1, 27, 1, 27]);
    let fix = &result["fixes"][0];
    assert_eq!(fix["description"]["text"], "Insert ';'");
    let change = &fix["artifactChanges"][0];
    assert_eq!(change["artifactLocation"]["uri"], "a.higraph");
    assert_eq!(change["artifactLocation"]["uriBaseId"], "%SRCROOT%");
    let replacement = &change["replacements"][0];
    assert_eq!(replacement["insertedContent"]["text"], ";");
    let deleted = &replacement["deletedRegion"];
    assert_eq!(
        [
            &deleted["startLine"],
            &deleted["startColumn"],
            &deleted["endLine"],
            &deleted["endColumn"]
        ],
        [1, 27, 1, 27].map(Value::from).each_ref(),
        "an insertion: an empty deleted region"
    );
}

#[test]
fn related_information_becomes_related_locations() {
    let tree = TempTree::new();
    tree.file("m.higraph", "mnemonic international;\nmnemonic simatic;\n");
    let checked = check_tree(&tree, &[]);
    assert_matches_json(&checked);
    let run = the_run(&checked.log);
    let result = result_for(run, "HG0011");
    let related = result["relatedLocations"]
        .as_array()
        .expect("relatedLocations");
    assert_eq!(related.len(), 1);
    let (uri, region) = file_and_region(&related[0]);
    assert_eq!(uri, "m.higraph");
    assert_eq!(region, [1, 1, 1, 24], "the first directive");
    assert_eq!(
        related[0]["message"]["text"],
        "the first 'mnemonic' directive"
    );
}

#[test]
fn columns_count_characters_not_utf16_units() {
    let tree = TempTree::new();
    // An astral-plane character (2 UTF-16 units, 1 character) before an identifier with an
    // umlaut (HG0009), in a CR LF file.
    tree.file(
        "v.higraph",
        "// Ventil\r\ngraph Ventil \"😀 Ventil\" < in < Zähler : INT; > >\r\n",
    );
    let checked = check_tree(&tree, &[]);
    assert_matches_json(&checked);
    let run = the_run(&checked.log);
    let (_, region) = file_and_region(&result_for(run, "HG0009")["locations"][0]);
    // `ä` is character 33 of line 2 (1-based); JSON says 0-based UTF-16 column 33.
    assert_eq!(region, [2, 33, 2, 34]);
    let diagnostic = diagnostics(&checked.report)
        .iter()
        .find(|d| d["code"] == "HG0009")
        .unwrap_or_else(|| panic!("an HG0009 diagnostic: {:#}", checked.report));
    assert_eq!(diagnostic["range"]["start"]["character"], 33);
}

#[test]
fn uris_are_percent_encoded() {
    let tree = TempTree::new();
    tree.file("Anlage 1/Zähler#2.higraph", "$\n");
    let checked = check_tree(&tree, &[]);
    let run = the_run(&checked.log);
    let (uri, _) = file_and_region(&results(run)[0]["locations"][0]);
    assert_eq!(uri, "Anlage%201/Z%C3%A4hler%232.higraph");
}

#[test]
fn a_file_outside_the_workspace_has_an_absolute_uri() {
    let tree = TempTree::new();
    tree.file("ws/higraph.toml", "")
        .file("ws/a.higraph", "$")
        .file("elsewhere/b.higraph", "$");
    let checked = check_both(&tree.path().join("ws"), &[".", "../elsewhere"]);
    let run = the_run(&checked.log);
    let artifacts: Vec<&Value> = results(run)
        .iter()
        .map(|result| &result["locations"][0]["physicalLocation"]["artifactLocation"])
        .collect();
    assert_eq!(artifacts.len(), 2, "{run:#}");
    assert!(artifacts.iter().any(|a| a["uri"] == "a.higraph"));
    let outside = artifacts
        .iter()
        .find(|a| {
            a["uri"]
                .as_str()
                .is_some_and(|uri| uri.starts_with("file:///") && uri.ends_with("/b.higraph"))
        })
        .unwrap_or_else(|| panic!("an absolute file URI: {run:#}"));
    assert!(outside.get("uriBaseId").is_none(), "{outside}");
}

// ------------------------------------------------------------------ semantic diagnostics

/// A graph whose only problem is two transitions of state 0 with priority 1 (HG2301, with a
/// related location and a fix).
const PRIORITY_CONFLICT: &str = "\
graph G <
  in < Taster : BOOL; Schalter : BOOL; >
  state 0 \"Init\" < >
  state 1 \"Eins\" < >
  state 2 \"Zwei\" < >
  trans any->0 prio 1 \"startup\" < U INIT_SD; >
  trans 0->1 prio 1 < U Taster; >
  trans 0->2 prio 1 < U Schalter; >
  trans 1->0 prio 1 < U Taster; >
  trans 2->0 prio 1 < U Schalter; >
>
";

#[test]
fn semantic_results_have_related_locations_and_fixes() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file("g.higraph", PRIORITY_CONFLICT);
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 1);
    assert_matches_json(&checked);
    let run = the_run(&checked.log);
    let result = result_for(run, "HG2301");
    assert_eq!(result["level"], "error");
    let (_, region) = file_and_region(&result["locations"][0]);
    assert_eq!(region, [8, 14, 8, 20], "`prio 1` of 0->2");
    let related = &result["relatedLocations"][0];
    let (uri, region) = file_and_region(related);
    assert_eq!(uri, "g.higraph");
    assert_eq!(region, [7, 14, 7, 20], "`prio 1` of 0->1");
    assert!(
        related["message"]["text"]
            .as_str()
            .is_some_and(|text| !text.is_empty()),
        "{related}"
    );
    let replacement = &result["fixes"][0]["artifactChanges"][0]["replacements"][0];
    assert_eq!(replacement["deletedRegion"]["startLine"], 8);
    assert!(replacement["insertedContent"]["text"].is_string());
}

/// A file with a `higraph-allow` comment naming a malformed code (HG6104, a warning by
/// default) and nothing else.
const MALFORMED_ALLOW: &str = "// higraph-allow: HGxx12\n";

#[test]
fn semantic_results_use_overridden_levels() {
    let tree = TempTree::new();
    // HG6101 (error) in higraph.toml; HG6104 made an info by the workspace.
    tree.file(
        "higraph.toml",
        "[diagnostics]\nHG6104 = \"info\"\nHG9999 = \"error\"\n",
    )
    .file("m.higraph", MALFORMED_ALLOW);
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 1);
    assert_matches_json(&checked);
    let run = the_run(&checked.log);
    assert_eq!(rule_ids(run), ["HG6101", "HG6104"]);

    let config = result_for(run, "HG6101");
    assert_eq!(config["level"], "error");
    let (uri, region) = file_and_region(&config["locations"][0]);
    assert_eq!(uri, "higraph.toml");
    assert_eq!(region[0], 3, "the line of HG9999");

    let allow = result_for(run, "HG6104");
    assert_eq!(allow["level"], "note", "info is a note");
    let rule = rule_of(run, allow);
    assert_eq!(
        rule["defaultConfiguration"]["level"], "warning",
        "the rule keeps its default level"
    );
}

#[test]
fn hints_are_notes_and_exit_codes_follow_the_other_formats() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "[diagnostics]\nHG6104 = \"hint\"\n")
        .file("m.higraph", MALFORMED_ALLOW);
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 0, "a hint does not fail the check");
    assert_matches_json(&checked);
    assert_eq!(result_for(the_run(&checked.log), "HG6104")["level"], "note");

    // Default severity (warning): passes, and fails with `--deny warnings`.
    tree.file("higraph.toml", "");
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 0);
    assert_eq!(
        result_for(the_run(&checked.log), "HG6104")["level"],
        "warning"
    );
    assert_eq!(check_tree(&tree, &["--deny", "warnings"]).status, 1);
}

#[test]
fn the_example_workspaces_give_valid_logs() {
    // Real workspaces with many semantic rules; only validity and agreement with the JSON
    // output are asserted, since their diagnostics change as rules are added.
    for example in ["drilling", "mistakes", "mixer"] {
        let root = repo_root().join("examples").join(example);
        if !root.is_dir() {
            continue;
        }
        let checked = check_both(&root, &[]);
        assert_matches_json(&checked);
    }
}

// ------------------------------------------------------------------ no diagnostics

#[test]
fn an_empty_report_is_a_valid_log() {
    let tree = TempTree::new();
    tree.file("higraph.toml", "")
        .file("ok.higraph", "// nothing to see here\n");
    let checked = check_tree(&tree, &[]);
    assert_eq!(checked.status, 0);
    assert!(diagnostics(&checked.report).is_empty());
    let run = the_run(&checked.log);
    assert_eq!(run["results"], serde_json::json!([]));
    assert_eq!(run["tool"]["driver"]["rules"], serde_json::json!([]));
}

#[test]
fn the_schema_rejects_a_broken_log() {
    // The validation above is only worth something if it can fail.
    let tree = TempTree::new();
    tree.file("a.higraph", "$\n");
    let run = tree.run(".", &["check", "--format", "sarif"]);
    let log = parse(&run);
    assert_valid_sarif(&log);
    let validator = validator();
    let mut bad_level = log.clone();
    bad_level["runs"][0]["results"][0]["level"] = Value::from("fatal");
    assert!(!validator.is_valid(&bad_level));
    let mut bad_uri = log.clone();
    bad_uri["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] =
        Value::from("a b.higraph");
    assert!(!validator.is_valid(&bad_uri), "formats are checked");
    let mut bad_column = log;
    bad_column["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["region"]["startColumn"] =
        Value::from(0);
    assert!(!validator.is_valid(&bad_column), "columns are 1-based");
}

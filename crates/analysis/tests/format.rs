//! Tests of the formatter (`tooling.md` §2a).
//!
//! * `test_data/format/*.higraph`: the formatted text is snapshotted (line ends shown as
//!   `⏎` for CR LF), and formatting it again changes nothing.
//! * Every file of `examples/` and every `crates/syntax/test_data/parser/ok/*.higraph`: the
//!   result is idempotent, parses without errors and has the same significant tokens as the
//!   input (modulo case of keywords, operations, labels, qualifiers, areas and type names, the
//!   order of state and transition header clauses and the priorities written out).
//! * The same, and more, for variants of those files with other white space and comments at
//!   every line break.
//! * Every rule fixture (`test_data/rules`) and example workspace gives the same diagnostics
//!   before and after formatting: formatting does not change the meaning.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use higraph_analysis::format::{FormatError, format};
use higraph_syntax::{
    SyntaxKind::{self, *},
    SyntaxNode, SyntaxToken, parse,
};

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn format_ok(path: &Path, text: &str) -> String {
    format(text).unwrap_or_else(|e| panic!("{} does not format: {e} ({e:?})", path.display()))
}

/// The formatted text of a snapshot input, with CR LF made visible.
fn show(text: &str) -> String {
    text.replace("\r\n", "⏎\n")
}

#[test]
fn snapshots() {
    insta::glob!("../test_data/format", "*.higraph", |path| {
        let text = read(path);
        let formatted = format_ok(path, &text);
        let again = format_ok(path, &formatted);
        assert_eq!(formatted, again, "{} is not idempotent", path.display());
        check_tokens(path, &text, &formatted);
        insta::assert_snapshot!(show(&formatted));
    });
}

/// All files the formatter must handle idempotently and faithfully.
fn corpus() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    collect(&root.join("examples"), &mut files);
    collect(&root.join("crates/syntax/test_data/parser/ok"), &mut files);
    collect(&root.join("crates/analysis/test_data/format"), &mut files);
    files.sort();
    files
}

fn collect(folder: &Path, files: &mut Vec<PathBuf>) {
    let entries = fs::read_dir(folder).unwrap_or_else(|e| panic!("{}: {e}", folder.display()));
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, files);
        } else if path.extension().is_some_and(|ext| ext == "higraph") {
            files.push(path);
        }
    }
}

#[test]
fn corpus_is_idempotent_and_keeps_every_token() {
    let files = corpus();
    assert!(files.len() > 10, "the corpus is missing: {files:?}");
    for path in files {
        let text = read(&path);
        if !parse(&text).errors().is_empty() {
            // A file with syntax errors is refused, never rewritten.
            assert!(
                matches!(format(&text), Err(FormatError::Syntax(_))),
                "{}",
                path.display()
            );
            continue;
        }
        let formatted = format_ok(&path, &text);
        let again = format_ok(&path, &formatted);
        assert_eq!(
            formatted,
            again,
            "{} is not idempotent:\n{formatted}",
            path.display()
        );
        check_tokens(&path, &text, &formatted);
    }
}

/// The output parses without errors and has the input's significant tokens.
fn check_tokens(path: &Path, before: &str, after: &str) {
    let parsed = parse(after);
    assert!(
        parsed.errors().is_empty(),
        "{}: the formatted text has syntax errors {:?}:\n{after}",
        path.display(),
        parsed.errors()
    );
    let old = token_multiset(&parse(before).syntax_node());
    let new = token_multiset(&parsed.syntax_node());
    let added = difference(&new, &old);
    let lost = difference(&old, &new);
    // The only tokens the formatter adds are written-out priorities: `prio` and a number each.
    let prios = added.iter().filter(|t| t.as_str() == "prio").count();
    let numbers = added
        .iter()
        .filter(|t| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()))
        .count();
    assert!(
        prios == numbers && prios + numbers == added.len(),
        "{}: tokens added: {added:?}",
        path.display()
    );
    assert!(lost.is_empty(), "{}: tokens lost: {lost:?}", path.display());
    assert_eq!(
        comments(before),
        comments(after),
        "{}: comments changed",
        path.display()
    );
    // Apart from header clauses, the order is the same too.
    let order = |root: &SyntaxNode| -> Vec<String> {
        root.descendants_with_tokens()
            .filter_map(|e| e.into_token())
            .filter(|t| !t.kind().is_trivia() && !in_header_clause(t))
            .map(|t| normalised(&t))
            .collect()
    };
    assert_eq!(
        order(&parse(before).syntax_node()),
        order(&parsed.syntax_node()),
        "{}: the order of the tokens changed",
        path.display()
    );
}

/// Is the token part of a state or transition header clause (which may be reordered)?
fn in_header_clause(token: &SyntaxToken) -> bool {
    token.parent_ancestors().any(|n| {
        matches!(n.kind(), PRIO_CLAUSE | ATTRIBUTE | COMMENT_STRING)
            && n.parent()
                .is_some_and(|p| matches!(p.kind(), STATE | TRANS))
    })
}

/// Tokens whose case the formatter may change are compared in lower case; all others exactly.
fn normalised(token: &SyntaxToken) -> String {
    let parent = token.parent().map(|p| p.kind());
    let chart_prop_value = parent == Some(NAME_REF)
        && token
            .parent()
            .and_then(|p| p.parent())
            .is_some_and(|p| p.kind() == CHART_PROP);
    // A one-word address in operand position (`mw10`) is written in upper case; names are
    // compared case-insensitively anyway, so letters-then-digits words are folded here.
    let word = token.text();
    let letters = word.trim_end_matches(|c: char| c.is_ascii_digit());
    let address_shaped = parent == Some(NAME_REF)
        && letters.len() < word.len()
        && !letters.is_empty()
        && letters.bytes().all(|b| b.is_ascii_alphabetic());
    let case_free = token.kind().is_keyword()
        || chart_prop_value
        || address_shaped
        || matches!(
            parent,
            Some(SyntaxKind::OPCODE | LABEL | QUALIFIER | TYPE_REF | ADDRESS)
        );
    if case_free {
        token.text().to_ascii_lowercase()
    } else {
        token.text().to_owned()
    }
}

/// The significant tokens as a sorted list.
fn token_multiset(root: &SyntaxNode) -> Vec<String> {
    let mut tokens: Vec<String> = root
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| normalised(&t))
        .collect();
    tokens.sort();
    tokens
}

/// The elements of the sorted list `a` that are not in the sorted list `b` (as multisets).
fn difference(a: &[String], b: &[String]) -> Vec<String> {
    let mut rest = b.to_vec();
    let mut out = Vec::new();
    for item in a {
        match rest.iter().position(|r| r == item) {
            Some(at) => {
                rest.remove(at);
            }
            None => out.push(item.clone()),
        }
    }
    out
}

/// The comments of a text, in order, without trailing blanks.
fn comments(text: &str) -> Vec<String> {
    parse(text)
        .syntax_node()
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| t.kind() == COMMENT)
        .map(|t| t.text().trim_end().to_owned())
        .collect()
}

#[test]
fn crlf_input_keeps_crlf() {
    let text = "graph G <\r\n  state 0 < >\r\n>\r\n";
    let formatted = format(text).expect("formats");
    assert_eq!(formatted, text);
    let lf = format("graph G <\n state 0 < >\n>").expect("formats");
    assert_eq!(lf, "graph G <\n  state 0 < >\n>\n");
}

#[test]
fn implicit_priorities_are_written_out() {
    let text = "graph G < state 0 < > state 1 < > trans 0->1 < > trans 0->0 prio 1 < > \
                trans 0->1 < > >";
    let formatted = format(text).expect("formats");
    assert_eq!(
        formatted,
        "graph G <\n  state 0 < >\n  state 1 < >\n  trans 0->1 prio 2 < >\n  \
         trans 0->0 prio 1 < >\n  trans 0->1 prio 3 < >\n>\n"
    );
}

#[test]
fn files_with_syntax_errors_are_refused() {
    match format("graph G < state 0 < U x >") {
        Err(FormatError::Syntax(errors)) => assert!(!errors.is_empty()),
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn long_variable_sections_break() {
    let short = "graph G < in < A : BOOL; > >";
    assert_eq!(
        format(short).expect("formats"),
        "graph G <\n  in < A : BOOL; >\n>\n"
    );
    // 100 columns exactly stay on one line; 101 do not.
    let decl = |name: &str| format!("{name} : BOOL; ");
    let fill = "X".repeat(100 - "  in < ".len() - decl("").len() - ">".len());
    let exact = format!("graph G < in < {}> >", decl(&fill));
    let formatted = format(&exact).expect("formats");
    let line = formatted.lines().nth(1).expect("a second line");
    assert_eq!(line.len(), 100, "{formatted}");
    let over = format!("graph G < in < {}> >", decl(&format!("{fill}Y")));
    let formatted = format(&over).expect("formats");
    assert!(formatted.contains("  in <\n"), "{formatted}");
}

/// A rewrite of one white-space run (see [`rewrite_whitespace`]).
type Rewrite = Box<dyn Fn(&str, bool) -> String>;

/// Rewrites the trivia of a file: `f(whitespace, after_comment)` gives the new text of each
/// white-space run (`after_comment`: the run follows a comment, so it holds a line break).
fn rewrite_whitespace(text: &str, f: impl Fn(&str, bool) -> String) -> String {
    let root = parse(text).syntax_node();
    let mut out = String::new();
    let mut after_comment = false;
    for token in root
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
    {
        if token.kind() == WHITESPACE && !token.text().starts_with('\u{FEFF}') {
            out.push_str(&f(token.text(), after_comment));
        } else {
            out.push_str(token.text());
        }
        after_comment = token.kind() == COMMENT;
    }
    out
}

/// Variants of every corpus file with other white space and more comments still format, and
/// the results are idempotent and keep every token.
#[test]
fn whitespace_and_comment_variants() {
    let line_break = |ws: &str| ws.contains(['\n', '\r']);
    let variants: [(&str, Rewrite); 4] = [
        (
            "squashed",
            Box::new(|_, after_comment| if after_comment { "\n" } else { " " }.to_owned()),
        ),
        (
            "blank lines",
            Box::new(move |ws, _| {
                if line_break(ws) {
                    "\n\n\n   ".to_owned()
                } else {
                    "   ".to_owned()
                }
            }),
        ),
        (
            "comments at every line break",
            Box::new(move |ws, _| {
                if line_break(ws) {
                    " // c1\n // c2\n".to_owned()
                } else {
                    ws.to_owned()
                }
            }),
        ),
        ("tabs", Box::new(move |ws, _| ws.replace(' ', "\t\t"))),
    ];
    for path in corpus() {
        let text = read(&path);
        if !parse(&text).errors().is_empty() {
            continue;
        }
        for (name, variant) in &variants {
            let changed = rewrite_whitespace(&text, variant);
            if !parse(&changed).errors().is_empty() {
                // Some rewrites are not neutral (a line break can end a statement).
                continue;
            }
            let formatted = format(&changed).unwrap_or_else(|e| {
                panic!(
                    "{} ({name}) does not format: {e:?}\n{changed}",
                    path.display()
                )
            });
            let again = format_ok(&path, &formatted);
            assert_eq!(
                formatted,
                again,
                "{} ({name}) is not idempotent:\n{formatted}",
                path.display()
            );
            check_tokens(&path, &changed, &formatted);
        }
    }
}

/// The diagnostics of a workspace as `path severity code message` lines, sorted, with the
/// message in lower case and without white space (messages quote opcodes and expressions as
/// written).
fn workspace_diagnostics(files: &[common::FixtureFile]) -> Vec<String> {
    let host = common::load_fixture(files);
    let analysis = host.analysis();
    let paths: Vec<String> = analysis.files().into_iter().map(|f| f.path).collect();
    let mut lines: Vec<String> = analysis
        .diagnostics()
        .into_iter()
        .flat_map(|(file, diagnostics)| {
            let path = paths.get(file.0 as usize).cloned().unwrap_or_default();
            diagnostics.into_iter().map(move |d| {
                let message: String = d
                    .message
                    .to_lowercase()
                    .chars()
                    .filter(|c| !c.is_whitespace())
                    .collect();
                format!("{path} {} {} {message}", d.severity, d.code)
            })
        })
        .collect();
    lines.sort();
    lines
}

/// Formatting never changes the meaning: every rule fixture and example workspace gives the
/// same diagnostics (code, severity, file, message) before and after its files are formatted.
#[test]
fn formatting_keeps_the_diagnostics() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut workspaces: Vec<(String, Vec<common::FixtureFile>)> = Vec::new();
    let mut fixtures = Vec::new();
    collect(&root.join("crates/analysis/test_data/rules"), &mut fixtures);
    fixtures.sort();
    for path in fixtures {
        let bytes = fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        workspaces.push((path.display().to_string(), common::fixture_files(&bytes)));
    }
    for example in ["drilling", "mixer", "mistakes"] {
        let folder = root.join("examples").join(example);
        let mut files = Vec::new();
        collect(&folder, &mut files);
        let mut workspace = Vec::new();
        for file in files {
            let name = file
                .strip_prefix(&folder)
                .map(|p| p.to_string_lossy().replace('\\', "/"))
                .unwrap_or_default();
            workspace.push((name, fs::read(&file).unwrap_or_default()));
        }
        if let Ok(config) = fs::read(folder.join("higraph.toml")) {
            workspace.push(("higraph.toml".to_owned(), config));
        }
        workspaces.push((format!("examples/{example}"), workspace));
    }
    let mut formatted_files = 0;
    for (name, files) in workspaces {
        let formatted: Vec<common::FixtureFile> = files
            .iter()
            .map(|(path, body)| {
                let new = match std::str::from_utf8(body) {
                    Ok(text) if path.ends_with(".higraph") => match format(text) {
                        Ok(new) => {
                            formatted_files += 1;
                            new.into_bytes()
                        }
                        Err(_) => body.clone(),
                    },
                    _ => body.clone(),
                };
                (path.clone(), new)
            })
            .collect();
        let before = workspace_diagnostics(&files);
        let after = workspace_diagnostics(&formatted);
        assert_eq!(before, after, "{name}: formatting changed the diagnostics");
    }
    assert!(
        formatted_files > 100,
        "only {formatted_files} files formatted"
    );
}

#[test]
fn a_cancelled_format_stops_and_says_so() {
    use std::cell::Cell;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/drilling/graphs/ventil_2e.higraph"
    ))
    .expect("example");
    // Never cancelled: the same as `format`, and the question was asked member by member.
    let asked = Cell::new(0);
    let result = higraph_analysis::format::format_with(&text, &|| {
        asked.set(asked.get() + 1);
        false
    });
    assert_eq!(result, format(&text));
    assert!(asked.get() > 3, "asked {} times", asked.get());
    // Cancelled after the third question: no text, and no question after the answer.
    let asked = Cell::new(0);
    let result = higraph_analysis::format::format_with(&text, &|| {
        asked.set(asked.get() + 1);
        asked.get() > 3
    });
    assert_eq!(result, Err(FormatError::Cancelled));
    assert_eq!(asked.get(), 4);
}

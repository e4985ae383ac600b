//! Depth and size robustness of the whole analysis (issue 10): pathological inputs — nesting
//! far past the parser's limit, nesting exactly at it, huge graphs — go through every
//! diagnostic and every editor feature at several positions on the test thread's default
//! 2 MiB stack (a debug build: the frames are at their largest). Nothing may panic or overflow
//! the stack, and a nesting too deep is reported once (HG0012).

use higraph_analysis::{
    AnalysisHost, Diagnostic, FileContents, TextRange, TextSize, WorkspaceData, ide::FilePosition,
    model::model_of,
};
use higraph_syntax::NESTING_LIMIT;

const PATH: &str = "deep.higraph";

/// A chart whose transition `T` has `condition`, and `elements` before it in the sequencer.
fn chart(elements: &str, condition: &str) -> String {
    format!(
        "chart C <\n  sequencer S <\n    step A < >\n    {elements}\n    trans T < {condition}; >\n    step B < >\n  >\n>\n"
    )
}

fn parens(n: usize) -> String {
    chart("", &format!("{}x{}", "(".repeat(n), ")".repeat(n)))
}

fn nots(n: usize) -> String {
    chart("", &format!("{}x", "not ".repeat(n)))
}

fn chain(n: usize) -> String {
    chart("", &format!("x{}", " or x".repeat(n)))
}

/// An IEC chart (docs/iec.md) with `statements` in an action body and in a step's `run`.
fn iec(statements: &str) -> String {
    format!(
        "chart C <\n  profile iec;\n  action A < {statements} >\n  sequencer S <\n    step A < run < x := 1; > P1 A; >\n    trans T < x > 0; >\n    step B < run < {statements} > >\n  >\n>\n"
    )
}

/// `n` nested `IF`s, every other one in the `ELSE` of the one around it, and `CASE` arms.
fn ifs(n: usize) -> String {
    let open: String = (0..n)
        .map(|i| match i % 3 {
            0 => "IF a THEN ",
            1 => "IF b THEN y := 1; ELSE ",
            _ => "CASE n OF 1..2: ",
        })
        .collect();
    let close: String = (0..n)
        .rev()
        .map(|i| if i % 3 == 2 { " END_CASE;" } else { " END_IF;" })
        .collect();
    iec(&format!("{open}x := -x + 1 * 2;{close}"))
}

/// `n` nested `parallel` (or `alt`) constructs of one branch each.
fn branches(n: usize, keyword: &str) -> String {
    let inner = if keyword == "alt" {
        "trans U < y; >"
    } else {
        "step Z < >"
    };
    let open = format!("{keyword} < branch < ").repeat(n);
    chart(&format!("{open}{inner}{}", " > >".repeat(n)), "x")
}

/// STL brackets nested `n` deep in one state.
fn stl_brackets(n: usize) -> String {
    format!(
        "graph G <\n  state 0 <\n    C: {}U E 0.0;{}\n  >\n>\n",
        "U( ; ".repeat(n),
        " );".repeat(n)
    )
}

/// A graph of `n` transitions.
fn graph_members(n: usize) -> String {
    format!("graph G <\n{}>\n", "trans 0->0 < >\n".repeat(n))
}

/// Loads `text` as the only file and runs all diagnostics, the semantic model and every
/// editor feature at a few positions; returns the diagnostics.
fn exercise(text: &str) -> Vec<Diagnostic> {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(PATH.to_owned(), FileContents::Text(text.to_owned()))],
        ..WorkspaceData::default()
    });
    let diagnostics: Vec<Diagnostic> = host
        .analysis()
        .diagnostics()
        .into_iter()
        .flat_map(|(_, d)| d)
        .collect();
    let analysis = host.analysis();
    let _ = model_of(&higraph_syntax::parse(text).syntax_node());
    analysis.semantic_model(PATH).expect("not cancelled");
    analysis.semantic_tokens(PATH, None).expect("not cancelled");
    analysis.folding_ranges(PATH).expect("not cancelled");
    analysis.document_symbols(PATH).expect("not cancelled");
    analysis.workspace_symbols("S").expect("not cancelled");
    analysis.inlay_hints(PATH, None).expect("not cancelled");
    let _ = analysis.format_edits(PATH).expect("not cancelled");
    let whole = TextRange::up_to(TextSize::of(text));
    analysis.code_actions(PATH, whole).expect("not cancelled");
    let offsets = positions(text);
    analysis
        .selection_ranges(PATH, &offsets)
        .expect("not cancelled");
    for &offset in &offsets {
        let pos = FilePosition {
            path: PATH.to_owned(),
            offset,
        };
        analysis.hover(&pos).expect("not cancelled");
        analysis.completions(&pos).expect("not cancelled");
        analysis.goto_definition(&pos).expect("not cancelled");
        analysis.references(&pos, true).expect("not cancelled");
        analysis.highlights(&pos).expect("not cancelled");
        let _ = analysis.prepare_rename(&pos).expect("not cancelled");
        let _ = analysis.rename(&pos, "Renamed").expect("not cancelled");
        analysis
            .code_actions(PATH, TextRange::empty(offset))
            .expect("not cancelled");
    }
    diagnostics
}

/// The start, the end, and three points in between (on character boundaries).
fn positions(text: &str) -> Vec<TextSize> {
    (0..=4)
        .map(|i| {
            let mut at = text.len() * i / 4;
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            TextSize::from(at as u32)
        })
        .collect()
}

fn count(diagnostics: &[Diagnostic], code: &str) -> usize {
    diagnostics
        .iter()
        .filter(|d| d.code.as_str() == code)
        .count()
}

/// Runs `f` on a thread with the default test stack (2 MiB), as the test harness does, so
/// that the test means the same under `--test-threads=1` (which runs on the main thread).
fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .expect("thread")
        .join()
        .expect("no panic");
}

#[test]
fn nesting_past_the_limit_is_reported_once_and_analysed() {
    on_small_stack(|| {
        for (what, text) in [
            ("parentheses", parens(20_000)),
            ("not", nots(40_000)),
            ("or chain", chain(40_000)),
            ("parallel", branches(1_000, "parallel")),
            ("alt", branches(1_000, "alt")),
            (
                "unary minus",
                chart("", &format!("{}x", "-".repeat(40_000))),
            ),
            (
                "plus chain",
                chart("", &format!("x{}", " + x".repeat(40_000))),
            ),
        ] {
            let diagnostics = exercise(&text);
            assert_eq!(count(&diagnostics, "HG0012"), 1, "{what}: {diagnostics:#?}");
        }
        // Twice: in the action and in the step.
        let diagnostics = exercise(&ifs(20_000));
        assert_eq!(
            count(&diagnostics, "HG0012"),
            2,
            "IF and CASE: {diagnostics:#?}"
        );
    });
}

#[test]
fn nesting_at_the_limit_is_analysed_without_a_diagnostic() {
    let limit = NESTING_LIMIT as usize;
    on_small_stack(move || {
        let mixed = {
            // Half the levels in branches, the other half in the condition inside them.
            let open = "alt < branch < ".repeat(limit / 2);
            let condition = format!("{}x{}", "(".repeat(limit / 2), ")".repeat(limit / 2));
            chart(
                &format!("{open}trans U < {condition}; >{}", " > >".repeat(limit / 2)),
                "x",
            )
        };
        for (what, text) in [
            ("parentheses", parens(limit)),
            ("not", nots(limit)),
            ("or chain", chain(limit)),
            ("parallel", branches(limit, "parallel")),
            ("alt", branches(limit, "alt")),
            ("mixed", mixed),
            ("IF and CASE", ifs(limit - 3)),
            ("unary minus", chart("", &format!("{}x", "-".repeat(limit)))),
        ] {
            let diagnostics = exercise(&text);
            assert_eq!(count(&diagnostics, "HG0012"), 0, "{what}: {diagnostics:#?}");
        }
    });
}

#[test]
fn deep_stl_brackets_are_flat() {
    on_small_stack(|| {
        let diagnostics = exercise(&stl_brackets(20_000));
        // STL brackets are statements, not nesting of the tree: no HG0012, the nesting stack
        // rule reports them.
        assert_eq!(count(&diagnostics, "HG0012"), 0);
        assert!(count(&diagnostics, "HG4005") > 0);
    });
}

#[test]
fn a_graph_with_more_members_than_the_virtual_layout_holds() {
    on_small_stack(|| {
        // 70 000 members: past 65 534, the most the structure rules' virtual layout holds.
        let text = graph_members(70_000);
        let mut host = AnalysisHost::new();
        host.load(WorkspaceData {
            files: vec![(PATH.to_owned(), FileContents::Text(text.clone()))],
            ..WorkspaceData::default()
        });
        let diagnostics: Vec<Diagnostic> = host
            .analysis()
            .diagnostics()
            .into_iter()
            .flat_map(|(_, d)| d)
            .collect();
        // Every diagnostic lies inside the text.
        for d in &diagnostics {
            assert!(d.range.end() <= TextSize::of(&text), "{d:?}");
        }
        let analysis = host.analysis();
        let edits = analysis.format_edits(PATH).expect("not cancelled");
        assert!(edits.is_ok(), "{edits:?}");
        let last = TextSize::from((text.len() - 3) as u32);
        let pos = FilePosition {
            path: PATH.to_owned(),
            offset: last,
        };
        analysis.hover(&pos).expect("not cancelled");
        analysis
            .semantic_tokens(PATH, Some(TextRange::new(last, TextSize::of(&text))))
            .expect("not cancelled");
    });
}

#[test]
fn a_megabyte_of_closing_brackets_gives_a_bounded_list() {
    on_small_stack(|| {
        let text = ">".repeat(1 << 20);
        let mut host = AnalysisHost::new();
        host.load(WorkspaceData {
            files: vec![(PATH.to_owned(), FileContents::Text(text))],
            ..WorkspaceData::default()
        });
        let diagnostics: Vec<Diagnostic> = host
            .analysis()
            .diagnostics()
            .into_iter()
            .flat_map(|(_, d)| d)
            .collect();
        assert_eq!(diagnostics.len(), higraph_syntax::MAX_SYNTAX_ERRORS + 1);
        let summary = diagnostics.last().expect("HG0013");
        assert_eq!(summary.code.as_str(), "HG0013");
        assert_eq!(
            summary.message,
            format!(
                "{} more syntax errors in this file are not listed",
                (1 << 20) - higraph_syntax::MAX_SYNTAX_ERRORS
            )
        );
    });
}

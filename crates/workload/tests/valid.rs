//! Every generated file parses without a syntax error, and the tree gives back the text.
//!
//! This checks the generators against the parser (and the parser against the generators): a
//! failure names the file, the line and the error, with the offending line.

use higraph_syntax::parse;

/// Parses every file and returns one readable report line per problem.
fn problems(workload: &str, files: &[(String, String)]) -> Vec<String> {
    let mut out = Vec::new();
    for (path, text) in files {
        let p = parse(text);
        if p.syntax_node().text().to_string() != *text {
            out.push(format!(
                "{workload}/{path}: the tree's text differs from the input"
            ));
        }
        for e in p.errors().iter().take(5) {
            let start = usize::from(e.range.start());
            let (line, col, source) = locate(text, start);
            out.push(format!(
                "{workload}/{path}:{line}:{col}: {e}\n    | {source}"
            ));
        }
        if p.errors().len() > 5 {
            out.push(format!(
                "{workload}/{path}: ... {} errors in all",
                p.errors().len()
            ));
        }
    }
    out
}

/// 1-based line and column of byte `offset`, and the text of that line.
fn locate(text: &str, offset: usize) -> (usize, usize, &str) {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
    let line = text[..offset].matches('\n').count() + 1;
    (line, offset - line_start + 1, &text[line_start..line_end])
}

fn assert_valid(workload: &str, files: &[(String, String)]) {
    let problems = problems(workload, files);
    assert!(
        problems.is_empty(),
        "{} problem(s) in generated {workload}:\n{}",
        problems.len(),
        problems
            .iter()
            .take(40)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn max_graph_is_valid() {
    for seed in [1, 2, 3] {
        let text = higraph_workload::max_graph(seed);
        assert_valid(
            &format!("max-graph (seed {seed})"),
            &[("max_graph.higraph".to_string(), text)],
        );
    }
}

#[test]
fn max_group_is_valid() {
    for seed in [1, 2] {
        assert_valid(
            &format!("max-group (seed {seed})"),
            &higraph_workload::max_group(seed),
        );
    }
}

#[test]
fn plant_is_valid() {
    assert_valid("plant (seed 1)", &higraph_workload::plant(1));
}

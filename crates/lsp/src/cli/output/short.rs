//! `--format short`: `path:line:col: severity[CODE]: message`, one line per diagnostic, for
//! editor problem matchers (`diagnostics.md` §4.2). Lines and columns are 1-based, columns
//! counted in characters. No summary line.

use std::fmt::Write as _;

use super::{Report, Sources, one_line};

pub(super) fn render(report: &Report, sources: &Sources) -> String {
    let mut out = String::new();
    for reported in &report.diagnostics {
        let diagnostic = &reported.diagnostic;
        let source = sources.get(reported.file);
        let (start, _) = source.line_columns(diagnostic.range);
        let _ = writeln!(
            out,
            "{}:{}:{}: {}[{}]: {}",
            source.shown,
            start.line,
            start.column,
            diagnostic.severity,
            diagnostic.code,
            one_line(&diagnostic.message)
        );
    }
    out
}

//! `--format github`: GitHub Actions workflow commands (`tooling.md` §2):
//! `::error file=F,line=L,col=C,endLine=EL,endColumn=EC::[HGnnnn] message`, with `::warning`
//! for warnings and `::notice` for infos and hints. Lines and columns are 1-based, columns
//! counted in characters; `endColumn` is the 1-based column just after the range (equal to
//! `col` for a zero-width range). Values are escaped as GitHub's runner expects.

use std::fmt::Write as _;

use higraph_analysis::Severity;

use super::{Report, Sources};

pub(super) fn render(report: &Report, sources: &Sources) -> String {
    let mut out = String::new();
    for reported in &report.diagnostics {
        let diagnostic = &reported.diagnostic;
        let source = sources.get(reported.file);
        let (start, end) = source.line_columns(diagnostic.range);
        let command = match diagnostic.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info | Severity::Hint => "notice",
        };
        let _ = writeln!(
            out,
            "::{command} file={},line={},col={},endLine={},endColumn={}::{}",
            escape_property(&source.shown),
            start.line,
            start.column,
            end.line,
            end.column,
            escape_data(&format!("[{}] {}", diagnostic.code, diagnostic.message)),
        );
    }
    out
}

/// Escapes a command's message: `%`, CR and LF.
fn escape_data(text: &str) -> String {
    text.replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// Escapes a property value: as the message, plus `:` and `,`.
fn escape_property(text: &str) -> String {
    escape_data(text).replace(':', "%3A").replace(',', "%2C")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(escape_data("100% a\r\nb: c,d"), "100%25 a%0D%0Ab: c,d");
        assert_eq!(escape_property("a:b,c%d\ne"), "a%3Ab%2Cc%25d%0Ae");
    }
}

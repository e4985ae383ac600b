//! `--format human`: rustc-style blocks rendered with annotate-snippets (`diagnostics.md`
//! §4.2): the title `severity[CODE]: message`, the location `--> path:line:col`, the source
//! lines with the range underlined, a `note:` with its location for each related location and
//! a `help:` line for each quick fix; a blank line after each block; then one summary line
//! such as `error: 1 error, 0 warnings, 0 infos, 0 hints`, led by the most serious severity
//! reported. Lines and columns are 1-based, columns counted in characters. Nothing is printed
//! when there is nothing to report.

use std::ops::Range;

use annotate_snippets::{AnnotationKind, Group, Level, Origin, Renderer, Snippet};
use higraph_analysis::{FileContents, Severity, TextRange, TextSize};

use super::{Report, SourceFile, Sources, one_line};

pub(super) fn render(report: &Report, sources: &Sources, color: bool) -> String {
    if report.diagnostics.is_empty() {
        return String::new();
    }
    let renderer = if color {
        Renderer::styled()
    } else {
        Renderer::plain()
    };
    let mut out = String::new();
    for reported in &report.diagnostics {
        let diagnostic = &reported.diagnostic;
        let source = sources.get(reported.file);
        let message = one_line(&diagnostic.message);
        let title = level(diagnostic.severity)
            .primary_title(message)
            .id(diagnostic.code.as_str());
        let primary = match &source.contents {
            // No text to show: only the location.
            FileContents::Unreadable { .. } => title.element(origin(source, diagnostic.range)),
            FileContents::Text(_) | FileContents::NotUtf8 { .. } => {
                let excerpt = Excerpt::new(source, diagnostic.range);
                title.element(
                    Snippet::source(excerpt.text)
                        .line_start(excerpt.first_line)
                        .path(source.shown.as_str())
                        .annotation(AnnotationKind::Primary.span(excerpt.span)),
                )
            }
        };
        let mut groups = vec![primary];
        for related in &diagnostic.related {
            groups.push(
                Group::with_title(Level::NOTE.secondary_title(one_line(&related.message)))
                    .element(origin(sources.get(related.file), related.range)),
            );
        }
        for fix in &diagnostic.fixes {
            groups.push(Group::with_title(
                Level::HELP.secondary_title(lower_first(&fix.title)),
            ));
        }
        out.push_str(&renderer.render(&groups));
        out.push_str("\n\n");
    }
    let summary = report.summary;
    let worst = summary.worst().unwrap_or(Severity::Error);
    let line = [Group::with_title(
        level(worst).primary_title(summary.counts_text()),
    )];
    out.push_str(&renderer.render(&line));
    out.push('\n');
    out
}

fn level(severity: Severity) -> Level<'static> {
    match severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
        Severity::Info => Level::INFO,
        Severity::Hint => Level::HELP.with_name("hint"),
    }
}

/// `--> path:line:col` for the start of `range`.
fn origin(source: &SourceFile, range: TextRange) -> Origin<'_> {
    let start = source.line_index.line_column(range.start());
    Origin::path(source.shown.as_str())
        .line(start.line as usize)
        .char_column(start.column as usize)
}

/// Fix titles are written like sentences ("Insert ';'"); after `help:` they start in lower
/// case like every other message. A leading acronym ("HG…", "STL") is left alone.
fn lower_first(title: &str) -> String {
    let mut chars = title.chars();
    match (chars.next(), chars.next()) {
        (Some(first), second)
            if first.is_uppercase() && !second.is_some_and(char::is_uppercase) =>
        {
            first
                .to_lowercase()
                .chain(title[first.len_utf8()..].chars())
                .collect()
        }
        _ => title.to_string(),
    }
}

/// The source lines a range touches, joined with `\n` whatever the file's line breaks (so a
/// lone CR is a line break for the renderer too), and the range within them.
struct Excerpt {
    text: String,
    /// 1-based number of the first line.
    first_line: usize,
    span: Range<usize>,
}

impl Excerpt {
    fn new(source: &SourceFile, range: TextRange) -> Excerpt {
        let index = &source.line_index;
        let text = source.contents.text();
        let first = index.line_of(range.start());
        let mut last = index.line_of(range.end());
        // A range that ends right after a line break ends on the line before.
        if last > first
            && index
                .line_range(last)
                .is_some_and(|line| line.start() == range.end())
        {
            last -= 1;
        }
        let mut excerpt = String::new();
        let mut line_offsets = Vec::new();
        for line in first..=last {
            if line > first {
                excerpt.push('\n');
            }
            line_offsets.push(excerpt.len());
            if let Some(line_range) = index.line_range(line) {
                excerpt.push_str(
                    text.get(std::ops::Range::<usize>::from(line_range))
                        .unwrap_or(""),
                );
            }
        }
        let map = |offset: TextSize| {
            let position = index.utf8_position(offset);
            let line = (position.line.clamp(first, last) - first) as usize;
            let line_start = line_offsets[line];
            let line_end = line_offsets
                .get(line + 1)
                .map_or(excerpt.len(), |next| next - 1);
            let column = if position.line > last {
                line_end - line_start
            } else {
                position.column as usize
            };
            (line_start + column).min(line_end)
        };
        let span = map(range.start())..map(range.end());
        Excerpt {
            first_line: first as usize + 1,
            span,
            text: excerpt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fix_titles_start_in_lower_case() {
        assert_eq!(lower_first("Insert ';'"), "insert ';'");
        assert_eq!(lower_first("STL form"), "STL form");
        assert_eq!(lower_first("Ändern"), "ändern");
        assert_eq!(lower_first(""), "");
    }

    #[test]
    fn excerpt_normalises_line_breaks() {
        let source = SourceFile::new(
            "a.higraph".into(),
            "a.higraph".into(),
            FileContents::Text("ab\rcd $\r\nef".into()),
        );
        let excerpt = Excerpt::new(&source, TextRange::new(6.into(), 7.into()));
        assert_eq!(excerpt.text, "cd $");
        assert_eq!(excerpt.first_line, 2);
        assert_eq!(excerpt.span, 3..4);
        let excerpt = Excerpt::new(&source, TextRange::new(1.into(), 10.into()));
        assert_eq!(excerpt.text, "ab\ncd $\nef");
        assert_eq!(excerpt.span, 1..9);
        // Ends right after a line break: the line before.
        let excerpt = Excerpt::new(&source, TextRange::new(0.into(), 3.into()));
        assert_eq!(excerpt.text, "ab");
        assert_eq!(excerpt.span, 0..2);
    }
}

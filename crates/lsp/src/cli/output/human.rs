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

use super::{Report, Reported, SourceFile, Sources, one_line};

pub(super) fn render(report: &Report, sources: &Sources, color: bool) -> String {
    if report.diagnostics.is_empty() {
        return String::new();
    }
    let renderer = if color {
        Renderer::styled()
    } else {
        Renderer::plain()
    };
    let mut out = blocks(&report.diagnostics, sources, &renderer);
    let summary = report.summary;
    let worst = summary.worst().unwrap_or(Severity::Error);
    let line = [Group::with_title(
        level(worst).primary_title(summary.counts_text()),
    )];
    out.push_str(&renderer.render(&line));
    out.push('\n');
    out
}

/// The blocks of `diagnostics` in the given order, each followed by a blank line, without the
/// summary line (`test` prints its failures this way).
pub(super) fn render_blocks(diagnostics: &[Reported], sources: &Sources, color: bool) -> String {
    let renderer = if color {
        Renderer::styled()
    } else {
        Renderer::plain()
    };
    blocks(diagnostics, sources, &renderer)
}

fn blocks(diagnostics: &[Reported], sources: &Sources, renderer: &Renderer) -> String {
    let mut out = String::new();
    for reported in diagnostics {
        let diagnostic = &reported.diagnostic;
        let source = sources.get(reported.file);
        let message = one_line(&diagnostic.message);
        // (line, column the renderer prints, column to print) for a window of a long line.
        let mut column_fix = None;
        let title = level(diagnostic.severity)
            .primary_title(message)
            .id(diagnostic.code.as_str());
        let primary = match &source.contents {
            // No text to show: only the location.
            FileContents::Unreadable { .. } => title.element(origin(source, diagnostic.range)),
            FileContents::Text(_) | FileContents::NotUtf8 { .. } => {
                let excerpt = Excerpt::new(source, diagnostic.range);
                if excerpt.cut_left {
                    // The renderer counts the column of `-->` in the window; it is put right
                    // in the rendered text below.
                    let shown = excerpt.text.get(..excerpt.span.start).unwrap_or("");
                    let right = source.line_index.line_column(diagnostic.range.start());
                    column_fix = Some((
                        excerpt.first_line,
                        shown.chars().count() + 1,
                        right.column as usize,
                    ));
                }
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
        let block = renderer.render(&groups);
        match column_fix {
            Some((line, shown, right)) => {
                out.push_str(&fix_column(&block, &source.name, line, shown, right));
            }
            None => out.push_str(&block),
        }
        out.push_str("\n\n");
    }
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

/// `block` with the location `path:line:shown` after its title line changed to
/// `path:line:right`.
fn fix_column(block: &str, path: &str, line: usize, shown: usize, right: usize) -> String {
    let wrong = format!("{path}:{line}:{shown}");
    let title_end = block.find('\n').unwrap_or(block.len());
    let found = block[title_end..].match_indices(&wrong).find(|(at, _)| {
        let after = title_end + at + wrong.len();
        !block[after..].starts_with(|c: char| c.is_ascii_digit())
    });
    match found {
        Some((at, _)) => {
            let at = title_end + at;
            format!(
                "{}{path}:{line}:{right}{}",
                &block[..at],
                &block[at + wrong.len()..]
            )
        }
        None => block.to_owned(),
    }
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

/// A line longer than this many bytes is shown through a window around the range.
const LONG_LINE: usize = 4096;
/// How many bytes of a long line a window keeps on each side of the range. The renderer shows
/// at most a terminal width of a line around the range, so a window this wide gives the same
/// picture as the whole line, while the cost of each diagnostic no longer grows with the
/// length of its line (thousands of diagnostics on one long line stay linear).
const WINDOW_CONTEXT: usize = 1024;

/// The source lines a range touches, joined with `\n` whatever the file's line breaks (so a
/// lone CR is a line break for the renderer too), and the range within them.
struct Excerpt {
    text: String,
    /// 1-based number of the first line.
    first_line: usize,
    span: Range<usize>,
    /// The text starts inside its line (a window of a long line).
    cut_left: bool,
}

/// The part of a long line to show for a range within it: `WINDOW_CONTEXT` bytes on either
/// side, cut at character boundaries. On the left the window starts at a character that is
/// not white space (the renderer treats leading white space specially), and not at all when
/// there is none in the first half of the context.
fn window(line: &str, range: Range<usize>) -> Range<usize> {
    if line.len() <= LONG_LINE {
        return 0..line.len();
    }
    let mut start = 0;
    if range.start > WINDOW_CONTEXT {
        let mut at = range.start - WINDOW_CONTEXT;
        let limit = range.start - WINDOW_CONTEXT / 2;
        while at < limit && !line.is_char_boundary(at) {
            at += 1;
        }
        while at < limit && line[at..].starts_with(char::is_whitespace) {
            at += line[at..].chars().next().map_or(1, char::len_utf8);
        }
        if at < limit {
            start = at;
        }
    }
    let mut end = line.len();
    if line.len() - range.end > WINDOW_CONTEXT {
        let mut at = range.end + WINDOW_CONTEXT;
        while !line.is_char_boundary(at) {
            at -= 1;
        }
        end = at;
    }
    start..end
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
        if first == last
            && let Some(line_range) = index.line_range(first)
            && let Some(line) = text.get(std::ops::Range::<usize>::from(line_range))
            && line.len() > LONG_LINE
        {
            let line_start = usize::from(line_range.start());
            let clamp =
                |offset: TextSize| (usize::from(offset).saturating_sub(line_start)).min(line.len());
            let span = clamp(range.start())..clamp(range.end());
            let shown = window(line, span.clone());
            return Excerpt {
                text: line[shown.clone()].to_owned(),
                first_line: first as usize + 1,
                span: span.start - shown.start..span.end - shown.start,
                cut_left: shown.start > 0,
            };
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
            cut_left: false,
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

    /// The whole line rendered the way it was before windows, for comparison.
    fn whole_line(line: &str, line_number: usize, span: Range<usize>) -> String {
        let title = Level::ERROR.primary_title("bad").id("HG0001");
        let group = title.element(
            Snippet::source(line)
                .line_start(line_number)
                .path("a.higraph")
                .annotation(AnnotationKind::Primary.span(span)),
        );
        Renderer::plain().render(&[group])
    }

    #[test]
    fn long_lines_render_through_a_window_as_the_whole_line() {
        let cases = [
            // (leading white space, text before the range, range, text after it)
            (0, 9000, "BAD", 9000),
            (4, 20, "BAD", 9000),
            (0, 9000, "BAD", 10),
            (3000, 10, "BAD", 9000),
            (8, 1500, "BAD", 3000),
            (0, 6000, "ÄÖÜ", 6000),
            (0, 6000, "BAD", 0),
        ];
        for (blanks, before, bad, after) in cases {
            let pattern = "ab; äx ";
            let fill = |n: usize| pattern.chars().cycle().take(n).collect::<String>();
            let line = format!("{}{}{bad}{}", " ".repeat(blanks), fill(before), fill(after));
            let text = format!("first\n{line}\nlast\n");
            let start = text.find(bad).unwrap();
            let range = TextRange::new(
                TextSize::from(start as u32),
                TextSize::from((start + bad.len()) as u32),
            );
            let sources = Sources::new(
                vec![SourceFile::new(
                    "a.higraph".into(),
                    "a.higraph".into(),
                    FileContents::Text(text.clone()),
                )],
                ".".into(),
            );
            let diagnostic = higraph_analysis::Diagnostic::new(
                higraph_analysis::Code::new("HG0001"),
                Severity::Error,
                range,
                "bad",
            );
            let report = Report::new(
                &sources,
                vec![super::super::Reported {
                    file: higraph_analysis::FileId(0),
                    diagnostic,
                }],
                1,
            );
            let rendered = render(&report, &sources, false);
            let line_start = start - "first\n".len();
            let expected = whole_line(&line, 2, line_start..line_start + bad.len());
            assert!(
                rendered.starts_with(&expected),
                "case {blanks}/{before}/{after}:\n{rendered}\nexpected:\n{expected}"
            );
            assert!(
                line.len() <= LONG_LINE
                    || Excerpt::new(sources.get(higraph_analysis::FileId(0)), range)
                        .text
                        .len()
                        < line.len()
            );
        }
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

//! `--format json`: one JSON object exactly as `diagnostics.md` §4.1 specifies, pretty-printed
//! with two-space indentation. Positions are 0-based lines and UTF-16 columns; `related` and
//! `fixes` are always present.

use higraph_analysis::{FileId, TextRange};
use serde::Serialize;

use super::{Report, Sources};

#[derive(Serialize)]
struct Output<'a> {
    version: u32,
    /// The workspace root relative to the current directory (`tooling.md` §2).
    root: &'a str,
    diagnostics: Vec<JsonDiagnostic<'a>>,
    summary: JsonSummary,
}

#[derive(Serialize)]
struct JsonDiagnostic<'a> {
    code: &'a str,
    severity: &'a str,
    file: &'a str,
    range: JsonRange,
    message: &'a str,
    related: Vec<JsonRelated<'a>>,
    fixes: Vec<JsonFix<'a>>,
}

#[derive(Serialize)]
struct JsonRelated<'a> {
    file: &'a str,
    range: JsonRange,
    message: &'a str,
}

#[derive(Serialize)]
struct JsonFix<'a> {
    title: &'a str,
    edits: Vec<JsonEdit<'a>>,
}

#[derive(Serialize)]
struct JsonEdit<'a> {
    file: &'a str,
    range: JsonRange,
    #[serde(rename = "newText")]
    new_text: &'a str,
}

#[derive(Serialize)]
struct JsonRange {
    start: JsonPosition,
    end: JsonPosition,
}

#[derive(Serialize)]
struct JsonPosition {
    line: u32,
    character: u32,
}

#[derive(Serialize)]
struct JsonSummary {
    errors: usize,
    warnings: usize,
    infos: usize,
    hints: usize,
    files: usize,
}

pub(super) fn render(report: &Report, sources: &Sources) -> String {
    let location = |file: FileId, range: TextRange| {
        let source = sources.get(file);
        let (start, end) = source.utf16_range(range);
        let range = JsonRange {
            start: JsonPosition {
                line: start.line,
                character: start.column,
            },
            end: JsonPosition {
                line: end.line,
                character: end.column,
            },
        };
        (source.name.as_str(), range)
    };
    let diagnostics = report
        .diagnostics
        .iter()
        .map(|reported| {
            let diagnostic = &reported.diagnostic;
            let (file, range) = location(reported.file, diagnostic.range);
            JsonDiagnostic {
                code: diagnostic.code.as_str(),
                severity: diagnostic.severity.as_str(),
                file,
                range,
                message: &diagnostic.message,
                related: diagnostic
                    .related
                    .iter()
                    .map(|related| {
                        let (file, range) = location(related.file, related.range);
                        JsonRelated {
                            file,
                            range,
                            message: &related.message,
                        }
                    })
                    .collect(),
                fixes: diagnostic
                    .fixes
                    .iter()
                    .map(|fix| JsonFix {
                        title: &fix.title,
                        edits: fix
                            .edits
                            .iter()
                            .map(|edit| {
                                let (file, range) = location(edit.file, edit.range);
                                JsonEdit {
                                    file,
                                    range,
                                    new_text: &edit.new_text,
                                }
                            })
                            .collect(),
                    })
                    .collect(),
            }
        })
        .collect();
    let summary = report.summary;
    let output = Output {
        version: 1,
        root: &sources.root,
        diagnostics,
        summary: JsonSummary {
            errors: summary.errors,
            warnings: summary.warnings,
            infos: summary.infos,
            hints: summary.hints,
            files: summary.files,
        },
    };
    // Serialising these plain structs cannot fail.
    let mut text = serde_json::to_string_pretty(&output).unwrap_or_default();
    text.push('\n');
    text
}

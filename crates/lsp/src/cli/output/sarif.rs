//! `--format sarif`: a SARIF 2.1.0 log (`tooling.md` §2) built with the `serde-sarif` types,
//! pretty-printed with two-space indentation.
//!
//! The log has one run. Its `tool.driver` is `higraph-lsp` with the package version and a
//! `rules` array listing every code that occurs in the results, sorted by code, with the
//! registry's message template as `shortDescription` and the default severity as
//! `defaultConfiguration.level`. Each result refers to its rule by `ruleId` and `ruleIndex`
//! and has:
//!
//! * `level`: error → `error`, warning → `warning`, info and hint → `note`;
//! * one location: the path relative to the current directory as a relative URI against the
//!   base id `%SRCROOT%` (the folder the check ran in, usually the repository's checkout), and a region with 1-based lines and 1-based columns
//!   counted in Unicode characters (the run says so with `columnKind: unicodeCodePoints`);
//!   `endColumn` is the column just after the range, as SARIF defines it;
//! * `relatedLocations` for the related locations, each with its note as message;
//! * `fixes` for the quick fixes: one `artifactChange` per edited file with its replacements
//!   (`deletedRegion` + `insertedContent`), in the order the fix lists the edits.
//!
//! Results come in the order of every other format ([`Report`]). The run declares `%SRCROOT%`
//! in `originalUriBaseIds` without an absolute URI: the log stays the same wherever it is
//! produced, and consumers such as GitHub code scanning resolve the relative URIs against the
//! checkout. A file outside the current directory is written as an absolute `file://` URI
//! without a base id.

use std::collections::{BTreeMap, BTreeSet};

use higraph_analysis::registry;
use higraph_analysis::{FileId, Severity, TextRange};
use serde_json::json;
use serde_sarif::sarif;

use super::{Report, Sources};

/// The base id that workspace-relative URIs are resolved against.
const SRCROOT: &str = "%SRCROOT%";

/// Where the SARIF 2.1.0 schema is published (the `$schema` of the log).
const SCHEMA_URI: &str = "https://json.schemastore.org/sarif-2.1.0.json";

/// Renders the report as a SARIF log, ending with a line break.
pub(super) fn render(report: &Report, sources: &Sources) -> String {
    let rules = Rules::of(report);
    let results = report
        .diagnostics
        .iter()
        .map(|reported| {
            let diagnostic = &reported.diagnostic;
            let code = diagnostic.code.as_str();
            let mut result = sarif::Result::builder()
                .rule_id(code)
                .level(level(diagnostic.severity))
                .message(message(&diagnostic.message))
                .locations(vec![location(sources, reported.file, diagnostic.range)])
                .build();
            result.rule_index = rules.index(code);
            if !diagnostic.related.is_empty() {
                result.related_locations = Some(
                    diagnostic
                        .related
                        .iter()
                        .map(|related| {
                            let mut location = location(sources, related.file, related.range);
                            location.message = Some(message(&related.message));
                            location
                        })
                        .collect(),
                );
            }
            if !diagnostic.fixes.is_empty() {
                result.fixes = Some(
                    diagnostic
                        .fixes
                        .iter()
                        .map(|fix| sarif_fix(sources, fix))
                        .collect(),
                );
            }
            result
        })
        .collect::<Vec<_>>();

    let driver = sarif::ToolComponent::builder()
        .name("higraph-lsp")
        .version(env!("CARGO_PKG_VERSION"))
        .semantic_version(env!("CARGO_PKG_VERSION"))
        .rules(rules.descriptors())
        .build();
    let original_uri_base_ids = BTreeMap::from([(
        SRCROOT.to_string(),
        sarif::ArtifactLocation::builder()
            .description(message(
                "the folder the check ran in: file paths are relative to it",
            ))
            .build(),
    )]);
    let run = sarif::Run::builder()
        .tool(sarif::Tool::builder().driver(driver).build())
        .column_kind(json!("unicodeCodePoints"))
        .original_uri_base_ids(original_uri_base_ids)
        .results(results)
        .build();
    let log = sarif::Sarif::builder()
        .schema(SCHEMA_URI)
        .version(json!("2.1.0"))
        .runs(vec![run])
        .build();
    // Serialising these plain structs cannot fail.
    let mut text = serde_json::to_string_pretty(&log).unwrap_or_default();
    text.push('\n');
    text
}

/// The rules of the run: the codes that occur in the report, sorted.
struct Rules {
    codes: Vec<&'static str>,
}

impl Rules {
    fn of(report: &Report) -> Rules {
        let codes: BTreeSet<&'static str> = report
            .diagnostics
            .iter()
            .map(|reported| reported.diagnostic.code.as_str())
            .collect();
        Rules {
            codes: codes.into_iter().collect(),
        }
    }

    /// The index of `code` in `tool.driver.rules`.
    fn index(&self, code: &str) -> Option<i64> {
        let index = self.codes.binary_search(&code).ok()?;
        i64::try_from(index).ok()
    }

    /// One reporting descriptor per code. A code the registry does not know (which the
    /// registry test rules out) gets a descriptor with its id only.
    fn descriptors(&self) -> Vec<sarif::ReportingDescriptor> {
        self.codes
            .iter()
            .map(|&code| {
                let mut descriptor = sarif::ReportingDescriptor::builder().id(code).build();
                if let Some(rule) = registry::rule_of(code) {
                    descriptor.short_description = Some(
                        sarif::MultiformatMessageString::builder()
                            .text(rule.template)
                            .build(),
                    );
                    let mut configuration = sarif::ReportingConfiguration::builder()
                        .level(json!(level_name(rule.default_severity)))
                        .build();
                    // A rule that is off by default (`diagnostics.md` §2.9) appears only when
                    // the workspace switched it on.
                    if rule.off_by_default {
                        configuration.enabled = Some(false);
                    }
                    descriptor.default_configuration = Some(configuration);
                }
                descriptor
            })
            .collect()
    }
}

/// The SARIF level of a severity.
fn level(severity: Severity) -> sarif::ResultLevel {
    match severity {
        Severity::Error => sarif::ResultLevel::Error,
        Severity::Warning => sarif::ResultLevel::Warning,
        Severity::Info | Severity::Hint => sarif::ResultLevel::Note,
    }
}

/// The SARIF level of a severity as written in a `reportingConfiguration`.
fn level_name(severity: Severity) -> &'static str {
    match severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Info | Severity::Hint => "note",
    }
}

/// A plain-text message.
fn message(text: &str) -> sarif::Message {
    sarif::Message::builder().text(escape_message(text)).build()
}

/// SARIF reads `[text](n)` in a plain-text message as a link to related location `n`
/// (SARIF 2.1.0 §3.11.6). Messages carry no such links, so when a message contains `](` its
/// square brackets are escaped with a backslash (as that section allows); other messages are
/// left exactly as they are.
fn escape_message(text: &str) -> String {
    if !text.contains("](") {
        return text.to_string();
    }
    let mut escaped = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if matches!(c, '[' | ']') {
            escaped.push('\\');
        }
        escaped.push(c);
    }
    escaped
}

/// A location with a physical location: the file and the region of `range`.
fn location(sources: &Sources, file: FileId, range: TextRange) -> sarif::Location {
    sarif::Location::builder()
        .physical_location(
            sarif::PhysicalLocation::builder()
                .artifact_location(artifact_location(sources, file))
                .region(region(sources, file, range))
                .build(),
        )
        .build()
}

/// The artifact location of a file: a URI relative to the current directory against
/// `%SRCROOT%`, or an absolute `file://` URI for a file outside the current directory.
fn artifact_location(sources: &Sources, file: FileId) -> sarif::ArtifactLocation {
    let name = sources.get(file).shown.as_str();
    if let Some(uri) = absolute_file_uri(name) {
        sarif::ArtifactLocation::builder().uri(uri).build()
    } else {
        sarif::ArtifactLocation::builder()
            .uri(percent_encode_path(name))
            .uri_base_id(SRCROOT)
            .build()
    }
}

/// The `file://` URI of an absolute output name (`/x/y` or `C:/x/y`), `None` for a relative
/// one.
fn absolute_file_uri(name: &str) -> Option<String> {
    if name.starts_with('/') {
        return Some(format!("file://{}", percent_encode_path(name)));
    }
    let bytes = name.as_bytes();
    let has_drive =
        bytes.len() >= 3 && bytes[0].is_ascii_alphabetic() && bytes[1] == b':' && bytes[2] == b'/';
    has_drive.then(|| {
        // The drive letter's colon is allowed in a path; encode the rest.
        format!("file:///{}:{}", &name[..1], percent_encode_path(&name[2..]))
    })
}

/// Percent-encodes a `/`-separated path for use in a URI: every byte of its UTF-8 form
/// except ASCII letters, digits, `-`, `.`, `_`, `~` and `/`. (Encoding `:` also keeps a
/// relative path like `a:b` from reading as a URI scheme.)
fn percent_encode_path(path: &str) -> String {
    let mut encoded = String::with_capacity(path.len());
    for byte in path.bytes() {
        if byte.is_ascii_alphanumeric() || matches!(byte, b'-' | b'.' | b'_' | b'~' | b'/') {
            encoded.push(char::from(byte));
        } else {
            encoded.push_str(&format!("%{byte:02X}"));
        }
    }
    encoded
}

/// The region of `range`: 1-based start and end lines and character columns; the end column
/// is the one just after the range.
fn region(sources: &Sources, file: FileId, range: TextRange) -> sarif::Region {
    let (start, end) = sources.get(file).line_columns(range);
    sarif::Region::builder()
        .start_line(i64::from(start.line))
        .start_column(i64::from(start.column))
        .end_line(i64::from(end.line))
        .end_column(i64::from(end.column))
        .build()
}

/// A quick fix: its title as description, and its edits grouped by file (in the order the
/// files first appear), each edit a replacement of the deleted region by the new text.
fn sarif_fix(sources: &Sources, fix: &higraph_analysis::Fix) -> sarif::Fix {
    let mut changes: Vec<(FileId, Vec<sarif::Replacement>)> = Vec::new();
    for edit in &fix.edits {
        let replacement = sarif::Replacement::builder()
            .deleted_region(region(sources, edit.file, edit.range))
            .inserted_content(
                sarif::ArtifactContent::builder()
                    .text(edit.new_text.as_str())
                    .build(),
            )
            .build();
        match changes.iter_mut().find(|(file, _)| *file == edit.file) {
            Some((_, replacements)) => replacements.push(replacement),
            None => changes.push((edit.file, vec![replacement])),
        }
    }
    sarif::Fix::builder()
        .description(message(&fix.title))
        .artifact_changes(
            changes
                .into_iter()
                .map(|(file, replacements)| {
                    sarif::ArtifactChange::builder()
                        .artifact_location(artifact_location(sources, file))
                        .replacements(replacements)
                        .build()
                })
                .collect::<Vec<_>>(),
        )
        .build()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_percent_encoded() {
        assert_eq!(
            percent_encode_path("graphs/ventil.higraph"),
            "graphs/ventil.higraph"
        );
        assert_eq!(
            percent_encode_path("Anlage 1/Zähler#2:a.higraph"),
            "Anlage%201/Z%C3%A4hler%232%3Aa.higraph"
        );
    }

    #[test]
    fn absolute_names_become_file_uris() {
        assert_eq!(absolute_file_uri("graphs/a.higraph"), None);
        assert_eq!(
            absolute_file_uri("/etc/higraph cfg.toml").as_deref(),
            Some("file:///etc/higraph%20cfg.toml")
        );
        assert_eq!(
            absolute_file_uri("C:/ws/a.toml").as_deref(),
            Some("file:///C:/ws/a.toml")
        );
    }

    #[test]
    fn brackets_are_escaped_only_where_they_could_form_a_link() {
        assert_eq!(escape_message("type STRING[10]"), "type STRING[10]");
        assert_eq!(escape_message("expected ']'"), "expected ']'");
        assert_eq!(escape_message("a [b](1) c"), r"a \[b\](1) c");
    }
}

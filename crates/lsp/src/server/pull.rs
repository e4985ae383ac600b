//! Pull diagnostics (LSP 3.17 `textDocument/diagnostic`, `workspace/diagnostic`).
//!
//! A client that announces `textDocument.diagnostic` pulls; the server then publishes
//! nothing (no `textDocument/publishDiagnostics` at all) and answers the pulls from the same
//! diagnostics it would have published, test failures (HG99xx) included. A client that does
//! not announce it gets pushed diagnostics as before.
//!
//! The world answers a pull once the diagnostics of its current revision are computed, so a
//! pull right after an edit sees the edit. A file's result id is a hash of its diagnostics as
//! sent (JSON): it changes exactly when they change, and a pull that names the current id
//! gets an `unchanged` report. `workspace/diagnostic` reports every workspace file, open or
//! not. When the diagnostics of a file the client did not edit in that batch change (an edit
//! in another file, a file event, a reload, a test run or the clearing of its failures), the
//! server sends `workspace/diagnostic/refresh` if the client supports it.

use std::hash::{DefaultHasher, Hash, Hasher};

use tower_lsp_server::ls_types::{self as lsp, Uri};

/// The identifier announced in `diagnosticProvider`.
pub(crate) const IDENTIFIER: &str = "higraph";

/// A pull, as the world answers it.
#[derive(Debug)]
pub(crate) enum Request {
    Document {
        uri: Uri,
        previous: Option<String>,
    },
    Workspace {
        previous: Vec<lsp::PreviousResultId>,
    },
}

/// The world's answer to a [`Request`].
#[derive(Debug)]
pub(crate) enum Answer {
    Document(lsp::DocumentDiagnosticReportResult),
    Workspace(lsp::WorkspaceDiagnosticReportResult),
}

/// The result id of a file's diagnostics: a hash of their JSON form (stable within one
/// server; a client keeps ids only for the session).
pub(crate) fn result_id(items: &[lsp::Diagnostic]) -> String {
    let mut hasher = DefaultHasher::new();
    match serde_json::to_string(items) {
        Ok(json) => json.hash(&mut hasher),
        // Not expected (diagnostics always serialise); the count still distinguishes most.
        Err(_) => items.len().hash(&mut hasher),
    }
    format!("{:016x}", hasher.finish())
}

/// The report of one document: `unchanged` when the client holds `id`.
pub(crate) fn document_report(
    previous: Option<&str>,
    id: String,
    items: impl FnOnce() -> Vec<lsp::Diagnostic>,
) -> lsp::DocumentDiagnosticReportResult {
    let report = if previous == Some(id.as_str()) {
        lsp::DocumentDiagnosticReport::Unchanged(lsp::RelatedUnchangedDocumentDiagnosticReport {
            related_documents: None,
            unchanged_document_diagnostic_report: lsp::UnchangedDocumentDiagnosticReport {
                result_id: id,
            },
        })
    } else {
        lsp::DocumentDiagnosticReport::Full(lsp::RelatedFullDocumentDiagnosticReport {
            related_documents: None,
            full_document_diagnostic_report: lsp::FullDocumentDiagnosticReport {
                result_id: Some(id),
                items: items(),
            },
        })
    };
    lsp::DocumentDiagnosticReportResult::Report(report)
}

/// The report of one file in a workspace pull.
pub(crate) fn workspace_item(
    uri: Uri,
    version: Option<i32>,
    previous: Option<&str>,
    id: String,
    items: impl FnOnce() -> Vec<lsp::Diagnostic>,
) -> lsp::WorkspaceDocumentDiagnosticReport {
    let version = version.map(i64::from);
    if previous == Some(id.as_str()) {
        lsp::WorkspaceDocumentDiagnosticReport::Unchanged(
            lsp::WorkspaceUnchangedDocumentDiagnosticReport {
                uri,
                version,
                unchanged_document_diagnostic_report: lsp::UnchangedDocumentDiagnosticReport {
                    result_id: id,
                },
            },
        )
    } else {
        lsp::WorkspaceDocumentDiagnosticReport::Full(lsp::WorkspaceFullDocumentDiagnosticReport {
            uri,
            version,
            full_document_diagnostic_report: lsp::FullDocumentDiagnosticReport {
                result_id: Some(id),
                items: items(),
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn result_ids_follow_the_diagnostics() {
        let one = lsp::Diagnostic {
            message: "one".into(),
            ..lsp::Diagnostic::default()
        };
        let two = lsp::Diagnostic {
            message: "two".into(),
            ..lsp::Diagnostic::default()
        };
        assert_eq!(
            result_id(std::slice::from_ref(&one)),
            result_id(std::slice::from_ref(&one))
        );
        assert_ne!(
            result_id(std::slice::from_ref(&one)),
            result_id(std::slice::from_ref(&two))
        );
        assert_ne!(result_id(&[]), result_id(std::slice::from_ref(&one)));
        let id = result_id(std::slice::from_ref(&one));
        let unchanged = document_report(Some(&id), id.clone(), Vec::new);
        assert!(matches!(
            unchanged,
            lsp::DocumentDiagnosticReportResult::Report(lsp::DocumentDiagnosticReport::Unchanged(
                _
            ))
        ));
        let full = document_report(Some("other"), id, || vec![one]);
        assert!(matches!(
            full,
            lsp::DocumentDiagnosticReportResult::Report(lsp::DocumentDiagnosticReport::Full(_))
        ));
    }
}

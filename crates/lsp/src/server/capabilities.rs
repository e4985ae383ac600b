//! What the client can do ([`ClientSupport`], read from `initialize`) and what the server
//! announces ([`server_capabilities`]). The announcement lists exactly the requests the
//! handlers implement.

use higraph_analysis::PositionEncoding;
use tower_lsp_server::ls_types as lsp;

use super::convert;

/// The parts of the client's capabilities the server acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ClientSupport {
    /// The position encoding both sides use: UTF-8 when the client offers it, else LSP's
    /// default UTF-16.
    pub encoding: PositionEncoding,
    /// The client accepts `window/workDoneProgress/create` (progress while indexing).
    pub work_done_progress: bool,
    /// The client lets the server register file watchers
    /// (`workspace/didChangeWatchedFiles` with dynamic registration).
    pub watched_files_registration: bool,
    /// The client expands snippets in completion proposals.
    pub snippets: bool,
    /// The client folds whole lines only.
    pub line_folding_only: bool,
    /// The client shows markdown in hovers: it lists no hover content formats (most clients
    /// do not, and all show markdown) or lists markdown among them.
    pub hover_markdown: bool,
    /// The client shows `codeDescription.href` of a diagnostic (a link to the rule's page).
    pub code_description: bool,
    /// The client pulls diagnostics (`textDocument.diagnostic`): nothing is pushed to it
    /// (see `pull`).
    pub pull_diagnostics: bool,
    /// The client accepts `workspace/diagnostic/refresh`.
    pub diagnostic_refresh: bool,
    /// The client resolves a code action's `edit` (`codeAction.resolveSupport`): the fixes
    /// that need the rename engine come without their edit, computed in `codeAction/resolve`.
    pub code_action_resolve: bool,
}

impl Default for ClientSupport {
    /// What a client that announces nothing supports.
    fn default() -> ClientSupport {
        ClientSupport {
            encoding: PositionEncoding::Utf16,
            work_done_progress: false,
            watched_files_registration: false,
            snippets: false,
            line_folding_only: false,
            hover_markdown: true,
            code_description: false,
            pull_diagnostics: false,
            diagnostic_refresh: false,
            code_action_resolve: false,
        }
    }
}

impl ClientSupport {
    /// Reads the client's capabilities.
    pub(crate) fn new(capabilities: &lsp::ClientCapabilities) -> ClientSupport {
        let offers_utf8 = capabilities
            .general
            .as_ref()
            .and_then(|general| general.position_encodings.as_ref())
            .is_some_and(|encodings| encodings.contains(&lsp::PositionEncodingKind::UTF8));
        let text_document = capabilities.text_document.as_ref();
        ClientSupport {
            encoding: if offers_utf8 {
                PositionEncoding::Utf8
            } else {
                PositionEncoding::Utf16
            },
            work_done_progress: capabilities
                .window
                .as_ref()
                .and_then(|window| window.work_done_progress)
                .unwrap_or(false),
            watched_files_registration: capabilities
                .workspace
                .as_ref()
                .and_then(|workspace| workspace.did_change_watched_files.as_ref())
                .and_then(|watched| watched.dynamic_registration)
                .unwrap_or(false),
            snippets: text_document
                .and_then(|text| text.completion.as_ref())
                .and_then(|completion| completion.completion_item.as_ref())
                .and_then(|item| item.snippet_support)
                .unwrap_or(false),
            line_folding_only: text_document
                .and_then(|text| text.folding_range.as_ref())
                .and_then(|folding| folding.line_folding_only)
                .unwrap_or(false),
            hover_markdown: text_document
                .and_then(|text| text.hover.as_ref())
                .and_then(|hover| hover.content_format.as_ref())
                .is_none_or(|formats| {
                    formats.is_empty() || formats.contains(&lsp::MarkupKind::Markdown)
                }),
            code_description: text_document
                .and_then(|text| text.publish_diagnostics.as_ref())
                .and_then(|publish| publish.code_description_support)
                .unwrap_or(false),
            pull_diagnostics: text_document.is_some_and(|text| text.diagnostic.is_some()),
            diagnostic_refresh: capabilities
                .workspace
                .as_ref()
                .and_then(|workspace| workspace.diagnostics.as_ref())
                .and_then(|diagnostic| diagnostic.refresh_support)
                .unwrap_or(false),
            code_action_resolve: text_document
                .and_then(|text| text.code_action.as_ref())
                .and_then(|action| action.resolve_support.as_ref())
                .is_some_and(|resolve| resolve.properties.iter().any(|p| p == "edit")),
        }
    }
}

/// The capabilities the server announces in its `initialize` result.
pub(crate) fn server_capabilities(client: &ClientSupport) -> lsp::ServerCapabilities {
    lsp::ServerCapabilities {
        position_encoding: Some(convert::encoding_kind(client.encoding)),
        text_document_sync: Some(lsp::TextDocumentSyncCapability::Options(
            lsp::TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(lsp::TextDocumentSyncKind::INCREMENTAL),
                will_save: None,
                will_save_wait_until: None,
                // A saved `higraph.toml` or symbol table reloads the workspace.
                save: Some(lsp::TextDocumentSyncSaveOptions::Supported(true)),
            },
        )),
        hover_provider: Some(lsp::HoverProviderCapability::Simple(true)),
        // `▶ Run test` on each test header, running `higraph.runTest` (`runtime.md` §8);
        // `higraph.build` writes the build (`export.md` §2, the code action on headers).
        // The count lenses (instances, references, transitions, uses) resolve lazily.
        code_lens_provider: Some(lsp::CodeLensOptions {
            resolve_provider: Some(true),
        }),
        execute_command_provider: Some(lsp::ExecuteCommandOptions {
            commands: vec![
                super::testing::RUN_TEST.to_owned(),
                super::build::BUILD.to_owned(),
            ],
            work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
        }),
        completion_provider: Some(lsp::CompletionOptions {
            // `Inst.` (messages of the instance's graph) and `#` (variables).
            trigger_characters: Some(vec![".".into(), "#".into()]),
            ..lsp::CompletionOptions::default()
        }),
        // `(` opens a CALL's parameter list, `,` the next parameter or a qualifier's time,
        // `<` an instance block, `;` ends an actual; the space after a chart qualifier.
        signature_help_provider: Some(lsp::SignatureHelpOptions {
            trigger_characters: Some(["(", ",", "<", ";", " "].map(String::from).to_vec()),
            retrigger_characters: Some([")", ">", "="].map(String::from).to_vec()),
            work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
        }),
        definition_provider: Some(lsp::OneOf::Left(true)),
        references_provider: Some(lsp::OneOf::Left(true)),
        document_highlight_provider: Some(lsp::OneOf::Left(true)),
        rename_provider: Some(lsp::OneOf::Right(lsp::RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
        })),
        document_symbol_provider: Some(lsp::OneOf::Left(true)),
        workspace_symbol_provider: Some(lsp::OneOf::Left(true)),
        folding_range_provider: Some(lsp::FoldingRangeProviderCapability::Simple(true)),
        selection_range_provider: Some(lsp::SelectionRangeProviderCapability::Simple(true)),
        semantic_tokens_provider: Some(
            lsp::SemanticTokensServerCapabilities::SemanticTokensOptions(
                lsp::SemanticTokensOptions {
                    legend: convert::semantic_tokens_legend(),
                    range: Some(true),
                    full: Some(lsp::SemanticTokensFullOptions::Delta { delta: Some(true) }),
                    work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
                },
            ),
        ),
        inlay_hint_provider: Some(lsp::OneOf::Left(true)),
        code_action_provider: Some(lsp::CodeActionProviderCapability::Options(
            lsp::CodeActionOptions {
                code_action_kinds: Some(vec![lsp::CodeActionKind::QUICKFIX]),
                // Rename fixes (HG1101/HG1102) get their edit in `codeAction/resolve` when the
                // client can ask for it.
                resolve_provider: Some(client.code_action_resolve),
                ..lsp::CodeActionOptions::default()
            },
        )),
        document_formatting_provider: Some(lsp::OneOf::Left(true)),
        document_range_formatting_provider: Some(lsp::OneOf::Left(true)),
        // Symbol-table paths in `higraph.toml`, codes in `higraph-allow` comments.
        document_link_provider: Some(lsp::DocumentLinkOptions {
            resolve_provider: Some(false),
            work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
        }),
        // Group → instances → graphs, and the message flow between instances.
        call_hierarchy_provider: Some(lsp::CallHierarchyServerCapability::Simple(true)),
        // Pull diagnostics, for clients that announce them (see `pull`).
        diagnostic_provider: Some(lsp::DiagnosticServerCapabilities::Options(
            lsp::DiagnosticOptions {
                identifier: Some(super::pull::IDENTIFIER.to_owned()),
                inter_file_dependencies: true,
                workspace_diagnostics: true,
                work_done_progress_options: lsp::WorkDoneProgressOptions::default(),
            },
        )),
        ..lsp::ServerCapabilities::default()
    }
}

/// The file watchers the server registers: sources, the configuration and symbol tables.
pub(crate) fn file_watchers() -> lsp::DidChangeWatchedFilesRegistrationOptions {
    let watcher = |pattern: &str| lsp::FileSystemWatcher {
        glob_pattern: lsp::GlobPattern::String(pattern.to_owned()),
        kind: None,
    };
    lsp::DidChangeWatchedFilesRegistrationOptions {
        watchers: vec![
            watcher("**/*.higraph"),
            watcher("**/higraph.toml"),
            watcher("**/*.sdf"),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf8_is_used_when_offered() {
        let mut capabilities = lsp::ClientCapabilities::default();
        assert_eq!(
            ClientSupport::new(&capabilities).encoding,
            PositionEncoding::Utf16
        );
        capabilities.general = Some(lsp::GeneralClientCapabilities {
            position_encodings: Some(vec![
                lsp::PositionEncodingKind::UTF16,
                lsp::PositionEncodingKind::UTF8,
            ]),
            ..Default::default()
        });
        let support = ClientSupport::new(&capabilities);
        assert_eq!(support.encoding, PositionEncoding::Utf8);
        assert_eq!(
            server_capabilities(&support).position_encoding,
            Some(lsp::PositionEncodingKind::UTF8)
        );
    }

    #[test]
    fn hovers_are_markdown_unless_the_client_lists_only_other_formats() {
        let with_formats = |formats: Option<Vec<lsp::MarkupKind>>| {
            let capabilities = lsp::ClientCapabilities {
                text_document: Some(lsp::TextDocumentClientCapabilities {
                    hover: Some(lsp::HoverClientCapabilities {
                        content_format: formats,
                        ..Default::default()
                    }),
                    ..Default::default()
                }),
                ..Default::default()
            };
            ClientSupport::new(&capabilities).hover_markdown
        };
        assert!(ClientSupport::new(&lsp::ClientCapabilities::default()).hover_markdown);
        assert!(with_formats(None));
        assert!(with_formats(Some(vec![
            lsp::MarkupKind::PlainText,
            lsp::MarkupKind::Markdown
        ])));
        assert!(!with_formats(Some(vec![lsp::MarkupKind::PlainText])));
    }
}

//! One small function per LSP request (and the published diagnostics): convert the
//! parameters in, ask the [`Analysis`](higraph_analysis::Analysis) snapshot, convert the
//! answer out. They run on a blocking thread; salsa's cancellation surfaces as
//! [`HandlerError::Cancelled`] and is answered `ContentModified`.

use std::collections::HashMap;
use std::sync::Arc;

use higraph_analysis::ide::{CallItem, FilePosition, LinkTarget, SourceChange};
use higraph_analysis::{LineIndex, TextRange, TextSize};
use tower_lsp_server::ls_types as lsp;

use super::convert;
use super::state::Snapshot;

/// Why a handler gave no answer.
#[derive(Debug)]
pub(crate) enum HandlerError {
    /// The workspace changed while the request ran (salsa cancelled the snapshot).
    Cancelled,
    /// The request cannot be carried out; the message says why (for example a refused
    /// rename).
    Failed(String),
}

impl From<salsa::Cancelled> for HandlerError {
    fn from(_: salsa::Cancelled) -> HandlerError {
        HandlerError::Cancelled
    }
}

/// What a handler returns.
pub(crate) type HandlerResult<T> = Result<T, HandlerError>;

/// The workspace path, byte offset and line index of a request's document position; `None`
/// when the document is not a file of the workspace.
fn file_position(
    snapshot: &Snapshot,
    params: &lsp::TextDocumentPositionParams,
) -> Option<(FilePosition, Arc<LineIndex>)> {
    let path = snapshot.path(&params.text_document.uri)?;
    let index = snapshot.line_index(&path)?;
    let offset = convert::offset(&index, params.position, snapshot.encoding);
    Some((FilePosition { path, offset }, index))
}

/// The workspace path and line index of a request's document.
fn file(
    snapshot: &Snapshot,
    document: &lsp::TextDocumentIdentifier,
) -> Option<(String, Arc<LineIndex>)> {
    let path = snapshot.path(&document.uri)?;
    let index = snapshot.line_index(&path)?;
    Some((path, index))
}

/// The LSP location of a range in a workspace file.
fn location(snapshot: &Snapshot, path: &str, range: TextRange) -> Option<lsp::Location> {
    let index = snapshot.line_index(path)?;
    Some(lsp::Location::new(
        snapshot.uri(path)?,
        convert::range(&index, range, snapshot.encoding),
    ))
}

/// The LSP workspace edit of a source change.
fn workspace_edit(snapshot: &Snapshot, change: &SourceChange) -> HandlerResult<lsp::WorkspaceEdit> {
    let mut changes = HashMap::new();
    for (path, edits) in &change.files {
        let (Some(uri), Some(index)) = (snapshot.uri(path), snapshot.line_index(path)) else {
            return Err(HandlerError::Failed(format!(
                "cannot edit '{path}': it is not a file of the workspace"
            )));
        };
        let edits = edits
            .iter()
            .map(|edit| convert::text_edit(&index, edit, snapshot.encoding))
            .collect();
        changes.insert(uri, edits);
    }
    Ok(lsp::WorkspaceEdit {
        changes: Some(changes),
        document_changes: None,
        change_annotations: None,
    })
}

/// `textDocument/completion`.
pub(crate) fn completion(
    snapshot: &Snapshot,
    params: lsp::CompletionParams,
) -> HandlerResult<Option<lsp::CompletionResponse>> {
    let Some((position, index)) = file_position(snapshot, &params.text_document_position) else {
        return Ok(None);
    };
    let items = snapshot.analysis.completions(&position)?;
    let snippets = snapshot.support.snippets;
    let items = items
        .iter()
        .filter_map(|item| convert::completion_item(item, &index, snapshot.encoding, snippets))
        .collect();
    Ok(Some(lsp::CompletionResponse::Array(items)))
}

/// `textDocument/hover`: markdown, or plain text for a client that lists only that.
pub(crate) fn hover(
    snapshot: &Snapshot,
    params: lsp::HoverParams,
) -> HandlerResult<Option<lsp::Hover>> {
    let Some((position, index)) = file_position(snapshot, &params.text_document_position_params)
    else {
        return Ok(None);
    };
    let hover = snapshot.analysis.hover(&position)?;
    let markdown = snapshot.support.hover_markdown;
    Ok(hover.map(|hover| convert::hover(&hover, &index, snapshot.encoding, markdown)))
}

/// `textDocument/signatureHelp`: one signature (instance formals, a CALL's block interface or
/// a chart qualifier). Parameter labels are offsets into the signature's label in the
/// negotiated encoding; with no active parameter the index lies past the last parameter, so
/// clients highlight none.
pub(crate) fn signature_help(
    snapshot: &Snapshot,
    params: lsp::SignatureHelpParams,
) -> HandlerResult<Option<lsp::SignatureHelp>> {
    let Some((position, _)) = file_position(snapshot, &params.text_document_position_params) else {
        return Ok(None);
    };
    let Some(help) = snapshot.analysis.signature_help(&position)? else {
        return Ok(None);
    };
    let encoding = snapshot.encoding;
    let units = |end: higraph_analysis::TextSize| -> u32 {
        let text = help.label.get(..usize::from(end)).unwrap_or("");
        let count = match encoding {
            higraph_analysis::PositionEncoding::Utf8 => text.len(),
            higraph_analysis::PositionEncoding::Utf16 => text.encode_utf16().count(),
            higraph_analysis::PositionEncoding::Utf32 => text.chars().count(),
        };
        u32::try_from(count).unwrap_or(u32::MAX)
    };
    let documentation = |text: &str| {
        let kind = if snapshot.support.hover_markdown {
            lsp::MarkupKind::Markdown
        } else {
            lsp::MarkupKind::PlainText
        };
        lsp::Documentation::MarkupContent(lsp::MarkupContent {
            kind,
            value: text.to_owned(),
        })
    };
    let parameters: Vec<lsp::ParameterInformation> = help
        .parameters
        .iter()
        .map(|p| lsp::ParameterInformation {
            label: lsp::ParameterLabel::LabelOffsets([
                units(p.range.start()),
                units(p.range.end()),
            ]),
            documentation: p.documentation.as_deref().map(documentation),
        })
        .collect();
    let count = u32::try_from(parameters.len()).unwrap_or(u32::MAX);
    let active = help.active_parameter.unwrap_or(count);
    Ok(Some(lsp::SignatureHelp {
        signatures: vec![lsp::SignatureInformation {
            label: help.label.clone(),
            documentation: help.documentation.as_deref().map(documentation),
            parameters: Some(parameters),
            active_parameter: Some(active),
        }],
        active_signature: Some(0),
        active_parameter: Some(active),
    }))
}

/// `textDocument/definition`.
pub(crate) fn goto_definition(
    snapshot: &Snapshot,
    params: lsp::GotoDefinitionParams,
) -> HandlerResult<Option<lsp::GotoDefinitionResponse>> {
    let Some((position, _)) = file_position(snapshot, &params.text_document_position_params) else {
        return Ok(None);
    };
    let targets = snapshot.analysis.goto_definition(&position)?;
    let locations: Vec<lsp::Location> = targets
        .iter()
        .filter_map(|target| location(snapshot, &target.path, target.focus_range))
        .collect();
    Ok((!locations.is_empty()).then_some(lsp::GotoDefinitionResponse::Array(locations)))
}

/// `textDocument/references`.
pub(crate) fn references(
    snapshot: &Snapshot,
    params: lsp::ReferenceParams,
) -> HandlerResult<Option<Vec<lsp::Location>>> {
    let Some((position, _)) = file_position(snapshot, &params.text_document_position) else {
        return Ok(None);
    };
    let ranges = snapshot
        .analysis
        .references(&position, params.context.include_declaration)?;
    Ok(Some(
        ranges
            .iter()
            .filter_map(|range| location(snapshot, &range.path, range.range))
            .collect(),
    ))
}

/// `textDocument/documentHighlight`.
pub(crate) fn document_highlight(
    snapshot: &Snapshot,
    params: lsp::DocumentHighlightParams,
) -> HandlerResult<Option<Vec<lsp::DocumentHighlight>>> {
    let Some((position, index)) = file_position(snapshot, &params.text_document_position_params)
    else {
        return Ok(None);
    };
    let highlights = snapshot.analysis.highlights(&position)?;
    Ok(Some(
        highlights
            .iter()
            .map(|&(range, kind)| convert::highlight(range, kind, &index, snapshot.encoding))
            .collect(),
    ))
}

/// `textDocument/prepareRename`: the range and current name, or why the name cannot be
/// renamed.
pub(crate) fn prepare_rename(
    snapshot: &Snapshot,
    params: lsp::TextDocumentPositionParams,
) -> HandlerResult<Option<lsp::PrepareRenameResponse>> {
    let Some((position, index)) = file_position(snapshot, &params) else {
        return Ok(None);
    };
    match snapshot.analysis.prepare_rename(&position)? {
        Ok((range, name)) => Ok(Some(lsp::PrepareRenameResponse::RangeWithPlaceholder {
            range: convert::range(&index, range.range, snapshot.encoding),
            placeholder: name,
        })),
        Err(reason) => Err(HandlerError::Failed(reason)),
    }
}

/// `textDocument/rename`: the edits in every file of the workspace, open or not.
pub(crate) fn rename(
    snapshot: &Snapshot,
    params: lsp::RenameParams,
) -> HandlerResult<Option<lsp::WorkspaceEdit>> {
    let Some((position, _)) = file_position(snapshot, &params.text_document_position) else {
        return Err(HandlerError::Failed(
            "the document is not a file of the workspace".into(),
        ));
    };
    match snapshot.analysis.rename(&position, &params.new_name)? {
        Ok(change) => Ok(Some(workspace_edit(snapshot, &change)?)),
        Err(reason) => Err(HandlerError::Failed(reason)),
    }
}

/// `textDocument/documentSymbol`: the outline, as a hierarchy.
pub(crate) fn document_symbol(
    snapshot: &Snapshot,
    params: lsp::DocumentSymbolParams,
) -> HandlerResult<Option<lsp::DocumentSymbolResponse>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let symbols = snapshot.analysis.document_symbols(&path)?;
    Ok(Some(lsp::DocumentSymbolResponse::Nested(
        symbols
            .iter()
            .map(|symbol| convert::document_symbol(symbol, &index, snapshot.encoding))
            .collect(),
    )))
}

/// `workspace/symbol`.
pub(crate) fn workspace_symbol(
    snapshot: &Snapshot,
    params: lsp::WorkspaceSymbolParams,
) -> HandlerResult<Option<lsp::WorkspaceSymbolResponse>> {
    let targets = snapshot.analysis.workspace_symbols(&params.query)?;
    let symbols = targets
        .iter()
        .filter_map(|target| {
            let uri = snapshot.uri(&target.path)?;
            let index = snapshot.line_index(&target.path)?;
            Some(convert::symbol_information(
                target,
                uri,
                &index,
                snapshot.encoding,
            ))
        })
        .collect();
    Ok(Some(lsp::WorkspaceSymbolResponse::Flat(symbols)))
}

/// `textDocument/foldingRange`.
pub(crate) fn folding_range(
    snapshot: &Snapshot,
    params: lsp::FoldingRangeParams,
) -> HandlerResult<Option<Vec<lsp::FoldingRange>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let folds = snapshot.analysis.folding_ranges(&path)?;
    let line_folding_only = snapshot.support.line_folding_only;
    Ok(Some(
        folds
            .iter()
            .filter_map(|fold| convert::folding_range(fold, &index, line_folding_only))
            .collect(),
    ))
}

/// `textDocument/documentLink`: symbol-table paths in `higraph.toml` (to the file) and codes
/// in `higraph-allow` comments (to the rule's page, when rule links are on).
pub(crate) fn document_link(
    snapshot: &Snapshot,
    params: lsp::DocumentLinkParams,
) -> HandlerResult<Option<Vec<lsp::DocumentLink>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let links = snapshot.analysis.document_links(&path)?;
    Ok(Some(
        links
            .iter()
            .filter_map(|link| {
                let (target, tooltip) = match &link.target {
                    LinkTarget::File(file) => (snapshot.uri(file)?, format!("open {file}")),
                    LinkTarget::Rule(code) => (
                        snapshot.rule_page(code)?,
                        format!("documentation of {code}"),
                    ),
                };
                Some(lsp::DocumentLink {
                    range: convert::range(&index, link.range, snapshot.encoding),
                    target: Some(target),
                    tooltip: Some(tooltip),
                    data: None,
                })
            })
            .collect(),
    ))
}

/// `textDocument/selectionRange`: one chain per position.
pub(crate) fn selection_range(
    snapshot: &Snapshot,
    params: lsp::SelectionRangeParams,
) -> HandlerResult<Option<Vec<lsp::SelectionRange>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let offsets: Vec<_> = params
        .positions
        .iter()
        .map(|&position| convert::offset(&index, position, snapshot.encoding))
        .collect();
    let chains = snapshot.analysis.selection_ranges(&path, &offsets)?;
    Ok(Some(
        params
            .positions
            .iter()
            .enumerate()
            .map(|(i, &at)| {
                let chain = chains.get(i).map(Vec::as_slice).unwrap_or_default();
                convert::selection_range(chain, &index, snapshot.encoding, at)
            })
            .collect(),
    ))
}

/// `textDocument/semanticTokens/full`.
pub(crate) fn semantic_tokens_full(
    snapshot: &Snapshot,
    params: lsp::SemanticTokensParams,
) -> HandlerResult<Option<lsp::SemanticTokensResult>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let tokens = snapshot.analysis.semantic_tokens(&path, None)?;
    let data = convert::semantic_tokens(&tokens, &index, snapshot.encoding);
    let (result_id, _) = snapshot.store_semantic_tokens(&path, None, &data);
    Ok(Some(lsp::SemanticTokensResult::Tokens(
        lsp::SemanticTokens { result_id, data },
    )))
}

/// `textDocument/semanticTokens/full/delta`: edits against the tokens of the previous result
/// id when the server still holds them (the last answer for an open document), else the full
/// tokens.
pub(crate) fn semantic_tokens_full_delta(
    snapshot: &Snapshot,
    params: lsp::SemanticTokensDeltaParams,
) -> HandlerResult<Option<lsp::SemanticTokensFullDeltaResult>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let tokens = snapshot.analysis.semantic_tokens(&path, None)?;
    let data = convert::semantic_tokens(&tokens, &index, snapshot.encoding);
    let previous = Some(params.previous_result_id.as_str());
    Ok(Some(
        match snapshot.store_semantic_tokens(&path, previous, &data) {
            (result_id, Some(edits)) => {
                lsp::SemanticTokensFullDeltaResult::TokensDelta(lsp::SemanticTokensDelta {
                    result_id,
                    edits,
                })
            }
            (result_id, None) => {
                lsp::SemanticTokensFullDeltaResult::Tokens(lsp::SemanticTokens { result_id, data })
            }
        },
    ))
}

/// `textDocument/semanticTokens/range`.
pub(crate) fn semantic_tokens_range(
    snapshot: &Snapshot,
    params: lsp::SemanticTokensRangeParams,
) -> HandlerResult<Option<lsp::SemanticTokensRangeResult>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let range = convert::text_range(&index, params.range, snapshot.encoding);
    let tokens = snapshot.analysis.semantic_tokens(&path, Some(range))?;
    Ok(Some(lsp::SemanticTokensRangeResult::Tokens(
        lsp::SemanticTokens {
            result_id: None,
            data: convert::semantic_tokens(&tokens, &index, snapshot.encoding),
        },
    )))
}

/// `textDocument/inlayHint`.
pub(crate) fn inlay_hint(
    snapshot: &Snapshot,
    params: lsp::InlayHintParams,
) -> HandlerResult<Option<Vec<lsp::InlayHint>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let range = convert::text_range(&index, params.range, snapshot.encoding);
    let hints = snapshot.analysis.inlay_hints(&path, Some(range))?;
    Ok(Some(
        hints
            .iter()
            .map(|hint| convert::inlay_hint(hint, &index, snapshot.encoding))
            .collect(),
    ))
}

/// `textDocument/codeAction`: the quick fixes of the diagnostics in the range, each with the
/// client's matching diagnostic attached.
pub(crate) fn code_action(
    snapshot: &Snapshot,
    params: lsp::CodeActionParams,
) -> HandlerResult<Option<lsp::CodeActionResponse>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    // Kinds are hierarchical: `quickfix` is asked for by `quickfix` (or the empty kind, the
    // root), not by a sub-kind such as `quickfix.foo` or by `refactor`. The build actions
    // have no kind: only a request without `only` gets them.
    if let Some(only) = &params.context.only {
        let quickfix = lsp::CodeActionKind::QUICKFIX;
        if !only
            .iter()
            .any(|kind| kind.as_str().is_empty() || *kind == quickfix)
        {
            return Ok(Some(Vec::new()));
        }
    }
    let range = convert::text_range(&index, params.range, snapshot.encoding);
    let actions =
        snapshot
            .analysis
            .code_actions_with(&path, range, snapshot.support.code_action_resolve)?;
    let mut response = Vec::new();
    for action in actions {
        let diagnostic_range = action
            .diagnostic_range
            .map(|range| convert::range(&index, range, snapshot.encoding));
        let mut diagnostics: Vec<lsp::Diagnostic> = params
            .context
            .diagnostics
            .iter()
            .filter(|d| {
                Some(d.range) == diagnostic_range
                    && matches!(&d.code, Some(lsp::NumberOrString::String(code)) if Some(code) == action.code.as_ref())
            })
            .cloned()
            .collect();
        if diagnostics.is_empty() {
            // The client sent no matching diagnostic (a request for the fixes at the cursor):
            // attach the server's own, as it publishes it.
            let files = snapshot.analysis.files();
            diagnostics.push(convert::diagnostic(
                &action.diagnostic,
                &index,
                snapshot.encoding,
                |file, range| location(snapshot, &files.get(file.0 as usize)?.path, range),
            ));
        }
        let (edit, data) = match (action.deferred, &action.code, action.diagnostic_range) {
            // The client asks `codeAction/resolve` for the edit when the user picks it.
            (Some(fix), Some(code), Some(range)) => {
                let data = ActionData {
                    uri: params.text_document.uri.clone(),
                    generation: snapshot.generation(),
                    code: code.clone(),
                    range: convert::range(&index, range, snapshot.encoding),
                    fix,
                };
                (None, serde_json::to_value(data).ok())
            }
            _ => (Some(workspace_edit(snapshot, &action.edit)?), None),
        };
        response.push(lsp::CodeActionOrCommand::CodeAction(convert::code_action(
            &action,
            diagnostics,
            edit,
            data,
        )));
    }
    if params.context.only.is_none() {
        response.extend(super::build::code_actions(snapshot, &path, range)?);
    }
    Ok(Some(response))
}

/// The data of a code action whose edit `codeAction/resolve` computes: the document, the
/// contents generation it was listed in, its diagnostic (code and range) and the number of
/// the fix among the diagnostic's fixes.
#[derive(serde::Serialize, serde::Deserialize)]
struct ActionData {
    uri: lsp::Uri,
    generation: u64,
    code: String,
    range: lsp::Range,
    fix: usize,
}

/// `codeAction/resolve`: the edit of a quick fix listed without it (a rename fix, for a
/// client that resolves edits). An action listed before a file changed answers
/// `ContentModified` (the client lists the actions again); one that has its edit, or is no
/// deferred fix, comes back unchanged.
pub(crate) fn code_action_resolve(
    snapshot: &Snapshot,
    mut action: lsp::CodeAction,
) -> HandlerResult<lsp::CodeAction> {
    if action.edit.is_some() {
        return Ok(action);
    }
    let Some(data) = action
        .data
        .clone()
        .and_then(|data| serde_json::from_value::<ActionData>(data).ok())
    else {
        return Ok(action);
    };
    if data.generation != snapshot.generation() {
        return Err(HandlerError::Cancelled);
    }
    let document = lsp::TextDocumentIdentifier::new(data.uri.clone());
    let Some((path, index)) = file(snapshot, &document) else {
        return Err(HandlerError::Failed(
            "the code action's document is not a file of the workspace".into(),
        ));
    };
    let range = convert::text_range(&index, data.range, snapshot.encoding);
    let Some(resolved) = snapshot
        .analysis
        .resolve_code_action(&path, &data.code, range, data.fix)?
    else {
        return Err(HandlerError::Failed(format!(
            "the fix '{}' cannot be applied: the name is refused or the diagnostic is gone",
            action.title
        )));
    };
    action.edit = Some(workspace_edit(snapshot, &resolved.edit)?);
    Ok(action)
}

/// `textDocument/formatting`: the canonical layout, or why the file cannot be formatted.
pub(crate) fn formatting(
    snapshot: &Snapshot,
    params: lsp::DocumentFormattingParams,
) -> HandlerResult<Option<Vec<lsp::TextEdit>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    // A long formatting stops as soon as the client cancels it (`$/cancelRequest`) or edits.
    match snapshot
        .analysis
        .format_edits_with(&path, &|| snapshot.is_cancelled())?
    {
        Ok(edits) => Ok(Some(
            edits
                .iter()
                .map(|edit| convert::text_edit(&index, edit, snapshot.encoding))
                .collect(),
        )),
        Err(reason) => Err(HandlerError::Failed(reason)),
    }
}

/// `textDocument/rangeFormatting`: the canonical layout of the top-level items the range
/// touches, or why the file cannot be formatted.
pub(crate) fn range_formatting(
    snapshot: &Snapshot,
    params: lsp::DocumentRangeFormattingParams,
) -> HandlerResult<Option<Vec<lsp::TextEdit>>> {
    let Some((path, index)) = file(snapshot, &params.text_document) else {
        return Ok(None);
    };
    let range = convert::text_range(&index, params.range, snapshot.encoding);
    match snapshot
        .analysis
        .range_format_edits_with(&path, range, &|| snapshot.is_cancelled())?
    {
        Ok(edits) => Ok(Some(
            edits
                .iter()
                .map(|edit| convert::text_edit(&index, edit, snapshot.encoding))
                .collect(),
        )),
        Err(reason) => Err(HandlerError::Failed(reason)),
    }
}

/// Parameters of the custom request `higraph/render` (`tooling.md` §4, §6).
#[derive(Debug, serde::Deserialize)]
pub(crate) struct RenderParams {
    /// The graph, group or chart to draw.
    pub name: String,
}

/// Result of `higraph/render`: a self-contained SVG.
#[derive(Debug, serde::Serialize)]
pub(crate) struct RenderResult {
    pub svg: String,
}

/// `higraph/render`: the picture of a graph, group or chart; `RequestFailed` with the reason
/// (listing what exists) for an unknown name.
pub(crate) fn render(snapshot: &Snapshot, params: RenderParams) -> HandlerResult<RenderResult> {
    match snapshot
        .analysis
        .render(&params.name, higraph_analysis::render::RenderFormat::Svg)?
    {
        Ok(svg) => Ok(RenderResult { svg }),
        Err(message) => Err(HandlerError::Failed(message)),
    }
}

// ------------------------------------------------------------------------------ call hierarchy

/// The LSP item of a call hierarchy item; `data` holds its workspace path and the byte offset
/// of its name, which identify it again.
fn call_item(snapshot: &Snapshot, item: &CallItem) -> Option<lsp::CallHierarchyItem> {
    let index = snapshot.line_index(&item.path)?;
    Some(lsp::CallHierarchyItem {
        name: item.name.clone(),
        kind: convert::symbol_kind(item.kind),
        tags: None,
        detail: (!item.detail.is_empty()).then(|| item.detail.clone()),
        uri: snapshot.uri(&item.path)?,
        range: convert::range(&index, item.full_range, snapshot.encoding),
        selection_range: convert::range(&index, item.focus_range, snapshot.encoding),
        data: Some(serde_json::json!({
            "path": item.path,
            "offset": u32::from(item.focus_range.start()),
        })),
    })
}

/// The position that identifies a call hierarchy item: its `data`, else the start of its
/// selection range.
fn call_item_position(snapshot: &Snapshot, item: &lsp::CallHierarchyItem) -> Option<FilePosition> {
    let from_data = item.data.as_ref().and_then(|data| {
        let path = data.get("path")?.as_str()?.to_owned();
        let offset = u32::try_from(data.get("offset")?.as_u64()?).ok()?;
        Some(FilePosition {
            path,
            offset: offset.into(),
        })
    });
    from_data.or_else(|| {
        let path = snapshot.path(&item.uri)?;
        let index = snapshot.line_index(&path)?;
        let offset = convert::offset(&index, item.selection_range.start, snapshot.encoding);
        Some(FilePosition { path, offset })
    })
}

/// The ranges of a call in `path`.
fn call_ranges(snapshot: &Snapshot, path: &str, ranges: &[TextRange]) -> Vec<lsp::Range> {
    let Some(index) = snapshot.line_index(path) else {
        return Vec::new();
    };
    ranges
        .iter()
        .map(|r| convert::range(&index, *r, snapshot.encoding))
        .collect()
}

/// `textDocument/prepareCallHierarchy`: a group, instance, graph or message variable.
pub(crate) fn prepare_call_hierarchy(
    snapshot: &Snapshot,
    params: lsp::CallHierarchyPrepareParams,
) -> HandlerResult<Option<Vec<lsp::CallHierarchyItem>>> {
    let Some((position, _)) = file_position(snapshot, &params.text_document_position_params) else {
        return Ok(None);
    };
    let item = snapshot.analysis.prepare_call_hierarchy(&position)?;
    Ok(item
        .and_then(|item| call_item(snapshot, &item))
        .map(|item| vec![item]))
}

/// `callHierarchy/incomingCalls`: the ranges are in the caller's file.
pub(crate) fn incoming_calls(
    snapshot: &Snapshot,
    params: lsp::CallHierarchyIncomingCallsParams,
) -> HandlerResult<Option<Vec<lsp::CallHierarchyIncomingCall>>> {
    let Some(position) = call_item_position(snapshot, &params.item) else {
        return Ok(None);
    };
    let calls = snapshot.analysis.incoming_calls(&position)?;
    Ok(Some(
        calls
            .iter()
            .filter_map(|call| {
                Some(lsp::CallHierarchyIncomingCall {
                    from: call_item(snapshot, &call.item)?,
                    from_ranges: call_ranges(snapshot, &call.item.path, &call.ranges),
                })
            })
            .collect(),
    ))
}

/// `callHierarchy/outgoingCalls`: the ranges are in the item's own file.
pub(crate) fn outgoing_calls(
    snapshot: &Snapshot,
    params: lsp::CallHierarchyOutgoingCallsParams,
) -> HandlerResult<Option<Vec<lsp::CallHierarchyOutgoingCall>>> {
    let Some(position) = call_item_position(snapshot, &params.item) else {
        return Ok(None);
    };
    let calls = snapshot.analysis.outgoing_calls(&position)?;
    Ok(Some(
        calls
            .iter()
            .filter_map(|call| {
                Some(lsp::CallHierarchyOutgoingCall {
                    to: call_item(snapshot, &call.item)?,
                    from_ranges: call_ranges(snapshot, &position.path, &call.ranges),
                })
            })
            .collect(),
    ))
}

/// The client command of the count lenses: opens the references view. Its arguments are those
/// of VS Code's `editor.action.showReferences` in LSP types: the document's URI, the position
/// the view opens at, and the locations.
pub(crate) const SHOW_REFERENCES: &str = "higraph.showReferences";

/// `textDocument/codeLens`: the test lenses (`▶ Run test`, already resolved) and the count
/// lenses, unresolved: their range (which ends with the counted name) and, as data, `[n, k]`:
/// the document's number in the server's lens table (`lens_table`) and the kind's number
/// ([`LensKind::number`](higraph_analysis::ide::LensKind::number)). A big graph has hundreds
/// of lenses, and the answer's size is what it costs over stdio: the data holds nothing the
/// range gives and no URI.
pub(crate) fn code_lens(
    snapshot: &Snapshot,
    params: lsp::CodeLensParams,
) -> HandlerResult<Option<Vec<lsp::CodeLens>>> {
    let uri = params.text_document.uri.clone();
    let mut lenses = super::testing::code_lens(snapshot, params)?.unwrap_or_default();
    if let Some(path) = snapshot.path(&uri)
        && let Some(index) = snapshot.line_index(&path)
        && let Some(number) = snapshot.lens_number(&path)
    {
        for lens in snapshot.analysis.code_lenses(&path)? {
            lenses.push(lsp::CodeLens {
                range: convert::range(&index, lens.range, snapshot.encoding),
                command: None,
                data: Some(serde_json::json!([number, lens.kind.number()])),
            });
        }
    }
    Ok(Some(lenses))
}

/// `codeLens/resolve`: counts a lens's places and gives it the command [`SHOW_REFERENCES`].
/// A lens whose name changed meanwhile, or whose document was closed since the listing (its
/// number is no longer in the lens table), gets the title `outdated` without a command; a
/// lens that has its command already comes back unchanged; data that is not `[n, k]` with a
/// known kind is an error.
pub(crate) fn code_lens_resolve(
    snapshot: &Snapshot,
    mut lens: lsp::CodeLens,
) -> HandlerResult<lsp::CodeLens> {
    if lens.command.is_some() {
        return Ok(lens);
    }
    let Some((number, kind)) = lens
        .data
        .clone()
        .and_then(|data| serde_json::from_value::<(u64, u64)>(data).ok())
    else {
        return Err(HandlerError::Failed(
            "the code lens has no valid data (expected [document, kind])".into(),
        ));
    };
    let Some(kind) = higraph_analysis::ide::LensKind::from_number(kind) else {
        return Err(HandlerError::Failed(format!(
            "unknown code lens kind {kind}"
        )));
    };
    let Some(uri) = snapshot
        .lens_path(number)
        .and_then(|path| snapshot.uri(&path))
    else {
        lens.command = Some(outdated_lens());
        return Ok(lens);
    };
    // The range ends with the counted name: its last character is in the name.
    let document = lsp::TextDocumentIdentifier::new(uri.clone());
    let name = file(snapshot, &document).map(|(path, index)| {
        let end = convert::offset(&index, lens.range.end, snapshot.encoding);
        // (A byte inside the last character is enough: the token there is the name.)
        let offset = end - TextSize::from(u32::from(end > TextSize::from(0)));
        (FilePosition { path, offset }, index)
    });
    let resolved = match &name {
        Some((position, _)) => snapshot.analysis.resolve_code_lens(position, kind)?,
        None => None,
    };
    let position = name.map_or(lens.range.end, |(position, index)| {
        convert::position(&index, position.offset, snapshot.encoding)
    });
    lens.command = Some(match resolved {
        Some(resolved) => {
            let locations: Vec<lsp::Location> = resolved
                .locations
                .iter()
                .filter_map(|l| location(snapshot, &l.path, l.range))
                .collect();
            lsp::Command {
                title: resolved.title,
                command: SHOW_REFERENCES.to_owned(),
                arguments: Some(vec![
                    serde_json::json!(uri),
                    serde_json::json!(position),
                    serde_json::json!(locations),
                ]),
            }
        }
        // An empty command makes the lens a plain label; the next edit lists fresh lenses.
        None => outdated_lens(),
    });
    Ok(lens)
}

/// The command of a lens that no longer fits the text: a plain label (an empty command); the
/// next edit lists fresh lenses.
fn outdated_lens() -> lsp::Command {
    lsp::Command {
        title: "outdated".to_owned(),
        command: String::new(),
        arguments: None,
    }
}

//! Conversions between the analysis' types (byte offsets, [`higraph_analysis::Diagnostic`],
//! …) and LSP types (line/column positions in the negotiated encoding, `lsp::Diagnostic`, …).
//! The only module that knows both sides (`diagnostics.md` §1.5).

use higraph_analysis::ide::{
    CodeAction, CompletionItem, CompletionKind, DocumentSymbol, Edit, Fold, FoldKind,
    HighlightKind, Hover, InlayHint, InlayKind, NavigationTarget, SemanticToken, SymbolKind,
    TOKEN_KINDS, TOKEN_MODIFIERS,
};
use higraph_analysis::{
    DiagnosticTag, LineIndex, Position, PositionEncoding, Severity, TextRange, TextSize,
};
use tower_lsp_server::ls_types as lsp;

/// The LSP name of a position encoding.
pub(crate) fn encoding_kind(encoding: PositionEncoding) -> lsp::PositionEncodingKind {
    match encoding {
        PositionEncoding::Utf8 => lsp::PositionEncodingKind::UTF8,
        PositionEncoding::Utf16 => lsp::PositionEncodingKind::UTF16,
        PositionEncoding::Utf32 => lsp::PositionEncodingKind::UTF32,
    }
}

/// The LSP position of a byte offset.
pub(crate) fn position(
    index: &LineIndex,
    offset: TextSize,
    encoding: PositionEncoding,
) -> lsp::Position {
    let Position { line, column } = index.position(offset, encoding);
    lsp::Position::new(line, column)
}

/// The LSP range of a byte range.
pub(crate) fn range(index: &LineIndex, range: TextRange, encoding: PositionEncoding) -> lsp::Range {
    lsp::Range::new(
        position(index, range.start(), encoding),
        position(index, range.end(), encoding),
    )
}

/// The byte offset of an LSP position (clamped to the text).
pub(crate) fn offset(
    index: &LineIndex,
    position: lsp::Position,
    encoding: PositionEncoding,
) -> TextSize {
    index.offset(Position::new(position.line, position.character), encoding)
}

/// The byte range of an LSP range (clamped to the text; a reversed range is put in order).
pub(crate) fn text_range(
    index: &LineIndex,
    range: lsp::Range,
    encoding: PositionEncoding,
) -> TextRange {
    let start = offset(index, range.start, encoding);
    let end = offset(index, range.end, encoding);
    TextRange::new(start.min(end), start.max(end))
}

/// The LSP severity of a diagnostic severity.
pub(crate) fn severity(severity: Severity) -> lsp::DiagnosticSeverity {
    match severity {
        Severity::Error => lsp::DiagnosticSeverity::ERROR,
        Severity::Warning => lsp::DiagnosticSeverity::WARNING,
        Severity::Info => lsp::DiagnosticSeverity::INFORMATION,
        Severity::Hint => lsp::DiagnosticSeverity::HINT,
    }
}

/// The LSP tag of a diagnostic tag.
pub(crate) fn diagnostic_tag(tag: DiagnosticTag) -> lsp::DiagnosticTag {
    match tag {
        DiagnosticTag::Unnecessary => lsp::DiagnosticTag::UNNECESSARY,
    }
}

/// An LSP diagnostic. `index` is the line index of the diagnostic's file; `location` turns a
/// related location (file and byte range) into an LSP location, `None` when the file has no
/// URI (then the related entry is left out).
pub(crate) fn diagnostic(
    diagnostic: &higraph_analysis::Diagnostic,
    index: &LineIndex,
    encoding: PositionEncoding,
    location: impl Fn(higraph_analysis::FileId, TextRange) -> Option<lsp::Location>,
) -> lsp::Diagnostic {
    let related: Vec<lsp::DiagnosticRelatedInformation> = diagnostic
        .related
        .iter()
        .filter_map(|related| {
            Some(lsp::DiagnosticRelatedInformation {
                location: location(related.file, related.range)?,
                message: related.message.clone(),
            })
        })
        .collect();
    let tags: Vec<lsp::DiagnosticTag> =
        diagnostic.tags.iter().map(|&t| diagnostic_tag(t)).collect();
    lsp::Diagnostic {
        range: range(index, diagnostic.range, encoding),
        severity: Some(severity(diagnostic.severity)),
        code: Some(lsp::NumberOrString::String(
            diagnostic.code.as_str().to_owned(),
        )),
        code_description: None,
        source: Some(DIAGNOSTIC_SOURCE.to_owned()),
        message: diagnostic.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        tags: (!tags.is_empty()).then_some(tags),
        data: None,
    }
}

/// The `source` of every diagnostic the server publishes.
pub(crate) const DIAGNOSTIC_SOURCE: &str = "higraph";

/// An LSP text edit of an analysis edit.
pub(crate) fn text_edit(
    index: &LineIndex,
    edit: &Edit,
    encoding: PositionEncoding,
) -> lsp::TextEdit {
    lsp::TextEdit::new(range(index, edit.range, encoding), edit.new_text.clone())
}

/// An LSP hover: markdown, or plain text for a client that does not show markdown.
pub(crate) fn hover(
    hover: &Hover,
    index: &LineIndex,
    encoding: PositionEncoding,
    markdown: bool,
) -> lsp::Hover {
    let contents = if markdown {
        lsp::MarkupContent {
            kind: lsp::MarkupKind::Markdown,
            value: hover.markdown.clone(),
        }
    } else {
        lsp::MarkupContent {
            kind: lsp::MarkupKind::PlainText,
            value: plain_text(&hover.markdown),
        }
    };
    lsp::Hover {
        contents: lsp::HoverContents::Markup(contents),
        range: Some(range(index, hover.range, encoding)),
    }
}

/// The hover markdown as plain text: without code fences, inline-code backticks and bold
/// markers (the only markdown hovers use).
fn plain_text(markdown: &str) -> String {
    markdown
        .lines()
        .filter(|line| !line.trim_start().starts_with("```"))
        .map(|line| line.replace("**", "").replace('`', ""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The LSP symbol kind of an analysis symbol kind.
pub(crate) fn symbol_kind(kind: SymbolKind) -> lsp::SymbolKind {
    match kind {
        SymbolKind::Graph | SymbolKind::Chart => lsp::SymbolKind::CLASS,
        SymbolKind::Group => lsp::SymbolKind::MODULE,
        SymbolKind::Symbol => lsp::SymbolKind::CONSTANT,
        SymbolKind::BlockInterface => lsp::SymbolKind::INTERFACE,
        SymbolKind::Variable | SymbolKind::PredefinedVariable => lsp::SymbolKind::VARIABLE,
        SymbolKind::Message => lsp::SymbolKind::EVENT,
        SymbolKind::State | SymbolKind::Step => lsp::SymbolKind::ENUM_MEMBER,
        SymbolKind::Transition | SymbolKind::ChartTransition => lsp::SymbolKind::FUNCTION,
        SymbolKind::Instance => lsp::SymbolKind::OBJECT,
        SymbolKind::Sequencer => lsp::SymbolKind::STRUCT,
        SymbolKind::Section => lsp::SymbolKind::NAMESPACE,
        // Something one runs: a method, not a class (Event is taken by messages).
        SymbolKind::Test => lsp::SymbolKind::METHOD,
    }
}

/// An LSP document symbol (with its children) of an outline entry.
pub(crate) fn document_symbol(
    symbol: &DocumentSymbol,
    index: &LineIndex,
    encoding: PositionEncoding,
) -> lsp::DocumentSymbol {
    let children: Vec<lsp::DocumentSymbol> = symbol
        .children
        .iter()
        .map(|child| document_symbol(child, index, encoding))
        .collect();
    #[allow(deprecated)]
    lsp::DocumentSymbol {
        name: symbol.name.clone(),
        detail: symbol.detail.clone(),
        kind: symbol_kind(symbol.kind),
        tags: None,
        deprecated: None,
        range: range(index, symbol.full_range, encoding),
        selection_range: range(index, symbol.selection_range, encoding),
        children: (!children.is_empty()).then_some(children),
    }
}

/// An LSP symbol information (for `workspace/symbol`) of a navigation target in `uri`.
pub(crate) fn symbol_information(
    target: &NavigationTarget,
    uri: lsp::Uri,
    index: &LineIndex,
    encoding: PositionEncoding,
) -> lsp::SymbolInformation {
    #[allow(deprecated)]
    lsp::SymbolInformation {
        name: target.name.clone(),
        kind: symbol_kind(target.kind),
        tags: None,
        deprecated: None,
        location: lsp::Location::new(uri, range(index, target.focus_range, encoding)),
        container_name: None,
    }
}

/// The LSP completion kind of a completion kind.
pub(crate) fn completion_kind(kind: CompletionKind) -> lsp::CompletionItemKind {
    match kind {
        CompletionKind::Keyword => lsp::CompletionItemKind::KEYWORD,
        CompletionKind::Snippet => lsp::CompletionItemKind::SNIPPET,
        CompletionKind::Opcode => lsp::CompletionItemKind::OPERATOR,
        CompletionKind::Label => lsp::CompletionItemKind::REFERENCE,
        CompletionKind::Variable | CompletionKind::PredefinedVariable => {
            lsp::CompletionItemKind::VARIABLE
        }
        CompletionKind::Message => lsp::CompletionItemKind::EVENT,
        CompletionKind::Symbol => lsp::CompletionItemKind::CONSTANT,
        CompletionKind::Graph => lsp::CompletionItemKind::CLASS,
        CompletionKind::State | CompletionKind::Step => lsp::CompletionItemKind::ENUM_MEMBER,
        CompletionKind::Instance => lsp::CompletionItemKind::MODULE,
        CompletionKind::Formal => lsp::CompletionItemKind::FIELD,
        CompletionKind::Type => lsp::CompletionItemKind::TYPE_PARAMETER,
        CompletionKind::Value => lsp::CompletionItemKind::VALUE,
    }
}

/// An LSP completion item; `None` for a snippet when the client cannot expand snippets.
pub(crate) fn completion_item(
    item: &CompletionItem,
    index: &LineIndex,
    encoding: PositionEncoding,
    snippets: bool,
) -> Option<lsp::CompletionItem> {
    if item.is_snippet && !snippets {
        return None;
    }
    let new_text = item
        .insert_text
        .clone()
        .unwrap_or_else(|| item.label.clone());
    Some(lsp::CompletionItem {
        label: item.label.clone(),
        kind: Some(completion_kind(item.kind)),
        detail: item.detail.clone(),
        documentation: item.documentation.clone().map(lsp::Documentation::String),
        sort_text: item.sort_text.clone(),
        filter_text: item.filter_text.clone(),
        insert_text_format: Some(if item.is_snippet {
            lsp::InsertTextFormat::SNIPPET
        } else {
            lsp::InsertTextFormat::PLAIN_TEXT
        }),
        text_edit: Some(lsp::CompletionTextEdit::Edit(lsp::TextEdit::new(
            range(index, item.replace_range, encoding),
            new_text,
        ))),
        ..lsp::CompletionItem::default()
    })
}

/// An LSP quick fix: the analysis' action with the diagnostics it fixes and its edit (both
/// converted by the caller, which knows the snapshot's files). The most likely fix of a
/// diagnostic is `isPreferred`, so that a client's "auto fix" applies it.
pub(crate) fn code_action(
    action: &CodeAction,
    diagnostics: Vec<lsp::Diagnostic>,
    edit: Option<lsp::WorkspaceEdit>,
    data: Option<serde_json::Value>,
) -> lsp::CodeAction {
    lsp::CodeAction {
        title: action.title.clone(),
        kind: Some(lsp::CodeActionKind::QUICKFIX),
        diagnostics: Some(diagnostics),
        edit,
        command: None,
        is_preferred: action.is_preferred.then_some(true),
        disabled: None,
        data,
    }
}

/// An LSP folding range of a fold; `None` when it would not hide a line.
///
/// A block's fold ends on the line before its `>`, so the closing bracket stays visible (what
/// editors do for braces); a comment run's fold ends on its last line.
pub(crate) fn folding_range(
    fold: &Fold,
    index: &LineIndex,
    line_folding_only: bool,
) -> Option<lsp::FoldingRange> {
    let start = index.position(fold.range.start(), PositionEncoding::Utf16);
    let end = index.position(fold.range.end(), PositionEncoding::Utf16);
    let (end_line, kind) = match fold.kind {
        FoldKind::Region => (end.line.saturating_sub(1), None),
        FoldKind::Comment => (end.line, Some(lsp::FoldingRangeKind::Comment)),
    };
    if end_line <= start.line {
        return None;
    }
    Some(lsp::FoldingRange {
        start_line: start.line,
        start_character: (!line_folding_only).then_some(start.column),
        end_line,
        end_character: None,
        kind,
        collapsed_text: None,
    })
}

/// An LSP selection range from a chain of ranges, innermost first.
pub(crate) fn selection_range(
    chain: &[TextRange],
    index: &LineIndex,
    encoding: PositionEncoding,
    at: lsp::Position,
) -> lsp::SelectionRange {
    let mut nested: Option<lsp::SelectionRange> = None;
    for &outer_to_inner in chain.iter().rev() {
        nested = Some(lsp::SelectionRange {
            range: range(index, outer_to_inner, encoding),
            parent: nested.map(Box::new),
        });
    }
    // Nothing at the position: an empty range there (the client needs one per position).
    nested.unwrap_or(lsp::SelectionRange {
        range: lsp::Range::new(at, at),
        parent: None,
    })
}

/// An LSP document highlight.
pub(crate) fn highlight(
    text_range: TextRange,
    kind: HighlightKind,
    index: &LineIndex,
    encoding: PositionEncoding,
) -> lsp::DocumentHighlight {
    lsp::DocumentHighlight {
        range: range(index, text_range, encoding),
        kind: Some(match kind {
            HighlightKind::Text => lsp::DocumentHighlightKind::TEXT,
            HighlightKind::Read => lsp::DocumentHighlightKind::READ,
            HighlightKind::Write => lsp::DocumentHighlightKind::WRITE,
        }),
    }
}

/// An LSP inlay hint; the label gets a space before it.
pub(crate) fn inlay_hint(
    hint: &InlayHint,
    index: &LineIndex,
    encoding: PositionEncoding,
) -> lsp::InlayHint {
    lsp::InlayHint {
        position: position(index, hint.offset, encoding),
        label: lsp::InlayHintLabel::String(hint.label.clone()),
        kind: match hint.kind {
            InlayKind::FormalType => Some(lsp::InlayHintKind::TYPE),
            InlayKind::StateNames => None,
        },
        text_edits: None,
        tooltip: None,
        padding_left: Some(true),
        padding_right: None,
        data: None,
    }
}

/// The legend of the semantic tokens: token types and modifiers in the analysis' order.
pub(crate) fn semantic_tokens_legend() -> lsp::SemanticTokensLegend {
    lsp::SemanticTokensLegend {
        token_types: TOKEN_KINDS
            .iter()
            .map(|&kind| lsp::SemanticTokenType::new(kind))
            .collect(),
        token_modifiers: TOKEN_MODIFIERS
            .iter()
            .map(|&modifier| lsp::SemanticTokenModifier::new(modifier))
            .collect(),
    }
}

/// Semantic tokens in LSP's relative encoding (each token's line and start relative to the
/// previous token). The tokens are sorted, do not overlap and never span a line break.
pub(crate) fn semantic_tokens(
    tokens: &[SemanticToken],
    index: &LineIndex,
    encoding: PositionEncoding,
) -> Vec<lsp::SemanticToken> {
    let mut out = Vec::with_capacity(tokens.len());
    let (mut line, mut column) = (0u32, 0u32);
    for token in tokens {
        let start = index.position(token.range.start(), encoding);
        let end = index.position(token.range.end(), encoding);
        if end.line != start.line || end.column <= start.column {
            continue;
        }
        let delta_line = start.line - line;
        let delta_start = if delta_line == 0 {
            start.column - column
        } else {
            start.column
        };
        out.push(lsp::SemanticToken {
            delta_line,
            delta_start,
            length: end.column - start.column,
            token_type: token.kind.legend_index(),
            token_modifiers_bitset: token.modifiers,
        });
        (line, column) = (start.line, start.column);
    }
    out
}

#[cfg(test)]
mod tests {
    use higraph_analysis::{Code, FileId, RelatedInfo};

    use super::*;

    #[test]
    fn plain_text_hovers_drop_the_markdown() {
        let markdown =
            "```higraph\nOben : BOOL\n```\n\n`in` variable of graph `Ventil` · **formal**";
        assert_eq!(
            plain_text(markdown),
            "Oben : BOOL\n\nin variable of graph Ventil · formal"
        );
    }

    #[test]
    fn diagnostics_carry_code_source_related_information_and_tags() {
        let text = "graph Ä <\n  x\n>\n";
        let index = LineIndex::new(text);
        let mut analysed = higraph_analysis::Diagnostic::new(
            Code::new("HG1210"),
            Severity::Hint,
            TextRange::new(13.into(), 14.into()),
            "variable 'x' is never used",
        );
        analysed.tags.push(DiagnosticTag::Unnecessary);
        analysed.related.push(RelatedInfo {
            file: FileId(0),
            range: TextRange::new(6.into(), 8.into()),
            message: "graph".into(),
        });
        let uri: lsp::Uri = "file:///ws/a.higraph".parse().expect("a URI");
        let converted = diagnostic(&analysed, &index, PositionEncoding::Utf16, |_, r| {
            Some(lsp::Location::new(
                uri.clone(),
                range(&index, r, PositionEncoding::Utf16),
            ))
        });
        assert_eq!(
            converted.range,
            lsp::Range::new(lsp::Position::new(1, 2), lsp::Position::new(1, 3))
        );
        assert_eq!(converted.severity, Some(lsp::DiagnosticSeverity::HINT));
        assert_eq!(
            converted.code,
            Some(lsp::NumberOrString::String("HG1210".into()))
        );
        assert_eq!(converted.source.as_deref(), Some("higraph"));
        assert_eq!(converted.tags, Some(vec![lsp::DiagnosticTag::UNNECESSARY]));
        let related = converted.related_information.expect("related information");
        assert_eq!(
            related[0].location.range,
            lsp::Range::new(lsp::Position::new(0, 6), lsp::Position::new(0, 7))
        );
        let utf8 = range(
            &index,
            TextRange::new(6.into(), 8.into()),
            PositionEncoding::Utf8,
        );
        assert_eq!(utf8.end, lsp::Position::new(0, 8));
    }
}

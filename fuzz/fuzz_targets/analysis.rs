//! Feeds arbitrary bytes (lossy UTF-8) to the whole analysis as the only file of a workspace:
//! every diagnostic, the semantic model, and the editor features — hover, completion,
//! definition, references, highlights, symbols, semantic tokens, folding and selection, inlay
//! hints, code actions, formatting, rename preparation and rename — at positions taken from
//! the input. Nothing may panic, and every range the analysis returns lies within the text on
//! character boundaries.
#![no_main]

use higraph_analysis::{
    AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData, ide::FilePosition,
};
use libfuzzer_sys::fuzz_target;

const PATH: &str = "fuzz.higraph";

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let len = text.len();
    let inside = |range: TextRange, what: &str| {
        let (start, end) = (usize::from(range.start()), usize::from(range.end()));
        assert!(end <= len, "{what} {range:?} ends beyond the input ({len} bytes)");
        assert!(
            text.is_char_boundary(start) && text.is_char_boundary(end),
            "{what} {range:?} splits a character"
        );
    };

    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(PATH.to_owned(), FileContents::Text(text.clone()))],
        ..WorkspaceData::default()
    });
    let analysis = host.analysis();
    for (_, diagnostics) in analysis.diagnostics() {
        for d in &diagnostics {
            inside(d.range, "diagnostic");
        }
    }
    let _ = analysis.semantic_model(PATH);
    let _ = analysis.semantic_tokens(PATH, None);
    let _ = analysis.folding_ranges(PATH);
    let _ = analysis.document_symbols(PATH);
    let _ = analysis.workspace_symbols("a");
    let _ = analysis.inlay_hints(PATH, None);
    let _ = analysis.format_edits(PATH);
    let _ = analysis.code_actions(PATH, TextRange::up_to(TextSize::of(text.as_str())));

    // Positions: the ends, the middle, and up to four more chosen by the input's first bytes.
    let mut offsets = vec![0, len / 2, len];
    offsets.extend(data.iter().take(4).map(|&b| len * usize::from(b) / 255));
    let offsets: Vec<TextSize> = offsets
        .into_iter()
        .map(|mut at| {
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            TextSize::from(at as u32)
        })
        .collect();
    if let Ok(ranges) = analysis.selection_ranges(PATH, &offsets) {
        for range in ranges.iter().flatten() {
            inside(*range, "selection range");
        }
    }
    for &offset in &offsets {
        let pos = FilePosition {
            path: PATH.to_owned(),
            offset,
        };
        let _ = analysis.hover(&pos);
        let _ = analysis.completions(&pos);
        let _ = analysis.goto_definition(&pos);
        let _ = analysis.references(&pos, true);
        if let Ok(highlights) = analysis.highlights(&pos) {
            for (range, _) in highlights {
                inside(range, "highlight");
            }
        }
        let _ = analysis.prepare_rename(&pos);
        let _ = analysis.rename(&pos, "Renamed");
        let _ = analysis.code_actions(PATH, TextRange::empty(offset));
    }
});

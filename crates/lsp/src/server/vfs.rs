//! The server's view of files: which URI names which workspace path ([`PathMap`]), and the
//! documents the client has open, whose text the client owns ([`Documents`]).
//!
//! The analysis names files by their workspace-relative `/` path, exactly as the command line
//! does (`workspace::display_name`); a file outside the workspace root keeps its absolute path.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use higraph_analysis::{LineIndex, PositionEncoding};
use higraph_syntax::Edit;
use tower_lsp_server::ls_types::{TextDocumentContentChangeEvent, Uri};

use super::convert;
use crate::workspace;

/// Maps between the client's URIs and the analysis' workspace paths.
#[derive(Debug, Clone, Default)]
pub(crate) struct PathMap {
    /// The workspace root (canonical): the folder holding `higraph.toml`, else the client's
    /// root folder. `None` when the client opened no folder: then only open documents are
    /// analysed, each named by its absolute path.
    root: Option<PathBuf>,
    /// The root as the client wrote it (maybe through a symbolic link), so URIs the server
    /// makes look like the client's own.
    client_root: Option<PathBuf>,
}

impl PathMap {
    /// The map for a workspace root: `root` is canonical, `client_root` the same folder as
    /// the client names it.
    pub(crate) fn new(root: PathBuf, client_root: PathBuf) -> PathMap {
        PathMap {
            root: Some(root),
            client_root: Some(client_root),
        }
    }

    /// The canonical workspace root, if there is one.
    pub(crate) fn root(&self) -> Option<&Path> {
        self.root.as_deref()
    }

    /// The file a `file:` URI names; `None` for other schemes.
    pub(crate) fn file_path(uri: &Uri) -> Option<PathBuf> {
        let is_file = uri.scheme().as_str().eq_ignore_ascii_case("file");
        if !is_file {
            return None;
        }
        uri.to_file_path().map(|path| path.into_owned())
    }

    /// The workspace path of the file a URI names: relative to the root with `/`
    /// separators, or absolute for a file outside the root. `None` for non-`file:` URIs.
    pub(crate) fn name(&self, uri: &Uri) -> Option<String> {
        let path = PathMap::file_path(uri)?;
        Some(self.name_of_path(&path))
    }

    /// The workspace path of an absolute file path.
    pub(crate) fn name_of_path(&self, path: &Path) -> String {
        for root in [&self.client_root, &self.root].into_iter().flatten() {
            if path.starts_with(root) {
                return workspace::display_name(root, path);
            }
        }
        // The client may name the file through a link the root does not go through.
        if let (Some(root), Ok(canonical)) = (&self.root, std::fs::canonicalize(path))
            && canonical.starts_with(root)
        {
            return workspace::display_name(root, &canonical);
        }
        workspace::absolute_name(path)
    }

    /// The absolute file path of a workspace path.
    pub(crate) fn absolute(&self, name: &str) -> Option<PathBuf> {
        // Names are written by `workspace::name_text` component by component.
        let parts = name.split('/').map(workspace::name_path);
        if name.starts_with('/') {
            return Some(parts.fold(PathBuf::from("/"), |path, part| path.join(part)));
        }
        if Path::new(name).is_absolute() {
            return Some(PathBuf::from(name));
        }
        let root = self.client_root.as_ref().or(self.root.as_ref())?;
        Some(parts.fold(root.clone(), |path, part| path.join(part)))
    }

    /// The URI of a workspace path.
    pub(crate) fn uri(&self, name: &str) -> Option<Uri> {
        Uri::from_file_path(self.absolute(name)?)
    }
}

/// A document the client has open.
#[derive(Debug, Clone)]
pub(crate) struct Document {
    /// The URI exactly as the client sent it (diagnostics are published to it).
    pub uri: Uri,
    /// The client's version, increasing with every change.
    pub version: i32,
    /// The current text.
    pub text: String,
    /// The line index of `text`, kept current edit by edit (shared with snapshots).
    pub line_index: Arc<LineIndex>,
    /// Whether the document is a source file the analysis sees (a `.higraph` file or a
    /// document of language `higraph`); `higraph.toml` and symbol tables are only tracked.
    pub analysed: bool,
}

impl Document {
    /// A document with `text`, indexed.
    pub(crate) fn new(uri: Uri, version: i32, text: String, analysed: bool) -> Document {
        let line_index = Arc::new(LineIndex::new(&text));
        Document {
            uri,
            version,
            text,
            line_index,
            analysed,
        }
    }
}

/// What one `didChange` notification did to a document's text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Changed {
    /// Byte-offset replacements, in order (each range refers to the text the edits before it
    /// left), as [`higraph_analysis::AnalysisHost::apply_edits`] takes them.
    Edits(Vec<Edit>),
    /// The whole text was replaced.
    Replaced,
}

/// Why a change notification was ignored.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum ChangeRejected {
    /// The document is not open.
    NotOpen,
}

impl std::fmt::Display for ChangeRejected {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ChangeRejected::NotOpen => f.write_str("the document is not open"),
        }
    }
}

/// The open documents, by workspace path.
#[derive(Debug, Default)]
pub(crate) struct Documents {
    open: HashMap<String, Document>,
}

impl Documents {
    /// Records an opened document (replacing one of the same path).
    pub(crate) fn open(&mut self, name: String, document: Document) {
        self.open.insert(name, document);
    }

    /// Forgets a closed document.
    pub(crate) fn close(&mut self, name: &str) -> Option<Document> {
        self.open.remove(name)
    }

    /// The open document of a workspace path.
    pub(crate) fn get(&self, name: &str) -> Option<&Document> {
        self.open.get(name)
    }

    /// Every open document with its workspace path.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&String, &Document)> {
        self.open.iter()
    }

    /// Applies the changes of one `didChange` notification, in order, and says what they did.
    /// Ranges are in `encoding`; out-of-range positions are clamped, never a panic. The line
    /// index follows the text: a ranged change rescans only the lines around it.
    ///
    /// The changes are applied whatever their version: notifications arrive in order, so a
    /// version that is not newer is the client's bookkeeping error, and dropping the change
    /// would leave the server answering about a text the client no longer has. The document
    /// takes the notification's version.
    pub(crate) fn change(
        &mut self,
        name: &str,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
        encoding: PositionEncoding,
    ) -> Result<Changed, ChangeRejected> {
        let document = self.open.get_mut(name).ok_or(ChangeRejected::NotOpen)?;
        let mut edits = Vec::new();
        let mut replaced = false;
        for change in changes {
            match apply_change(
                &mut document.text,
                Arc::make_mut(&mut document.line_index),
                change,
                encoding,
            ) {
                Some(edit) => edits.push(edit),
                None => replaced = true,
            }
        }
        document.version = version;
        Ok(if replaced {
            Changed::Replaced
        } else {
            Changed::Edits(edits)
        })
    }
}

/// Applies one content change to `text` and its line index: a ranged replacement (returned as
/// a byte-offset edit), or the whole text when there is no range (`None`).
pub(crate) fn apply_change(
    text: &mut String,
    index: &mut LineIndex,
    change: TextDocumentContentChangeEvent,
    encoding: PositionEncoding,
) -> Option<Edit> {
    let Some(range) = change.range else {
        *text = change.text;
        *index = LineIndex::new(text);
        return None;
    };
    let range = convert::text_range(index, range, encoding);
    text.replace_range(
        usize::from(range.start())..usize::from(range.end()),
        &change.text,
    );
    index.apply_edit(range, text);
    Some(Edit {
        delete: range,
        insert: change.text,
    })
}

#[cfg(test)]
mod tests {
    use higraph_analysis::TextRange;
    use tower_lsp_server::ls_types::{Position, Range};

    use super::*;

    fn change(
        range: Option<((u32, u32), (u32, u32))>,
        text: &str,
    ) -> TextDocumentContentChangeEvent {
        TextDocumentContentChangeEvent {
            range: range.map(|((l1, c1), (l2, c2))| {
                Range::new(Position::new(l1, c1), Position::new(l2, c2))
            }),
            range_length: None,
            text: text.to_owned(),
        }
    }

    /// Applies a change to a text and checks that the edit and the kept line index agree
    /// with the text.
    fn apply(
        text: &mut String,
        change: TextDocumentContentChangeEvent,
        encoding: PositionEncoding,
    ) {
        let before = text.clone();
        let mut index = LineIndex::new(text);
        let edit = apply_change(text, &mut index, change, encoding);
        assert_eq!(index, LineIndex::new(text));
        if let Some(edit) = edit {
            assert_eq!(edit.apply(&before).as_deref(), Some(text.as_str()));
        }
    }

    #[test]
    fn ranged_changes_apply_in_order() {
        let mut text = "graph A <\n  in < x : BOOL; >\n>\n".to_owned();
        apply(
            &mut text,
            change(Some(((1, 7), (1, 8))), "Oben"),
            PositionEncoding::Utf16,
        );
        apply(
            &mut text,
            change(Some(((0, 6), (0, 7))), "Ventil"),
            PositionEncoding::Utf16,
        );
        assert_eq!(text, "graph Ventil <\n  in < Oben : BOOL; >\n>\n");
        apply(&mut text, change(None, "x"), PositionEncoding::Utf16);
        assert_eq!(text, "x");
    }

    #[test]
    fn columns_follow_the_encoding() {
        // `😀` is 2 UTF-16 units and 4 UTF-8 bytes; `ü` is 1 unit and 2 bytes.
        let original = "// 😀ü x\n";
        let mut utf16 = original.to_owned();
        apply(
            &mut utf16,
            change(Some(((0, 7), (0, 8))), "y"),
            PositionEncoding::Utf16,
        );
        assert_eq!(utf16, "// 😀ü y\n");
        let mut utf8 = original.to_owned();
        apply(
            &mut utf8,
            change(Some(((0, 10), (0, 11))), "y"),
            PositionEncoding::Utf8,
        );
        assert_eq!(utf8, "// 😀ü y\n");
    }

    #[test]
    fn out_of_range_and_reversed_ranges_are_clamped() {
        let mut text = "ab\ncd".to_owned();
        apply(
            &mut text,
            change(Some(((9, 0), (99, 99))), "!"),
            PositionEncoding::Utf16,
        );
        assert_eq!(text, "ab\ncd!");
        apply(
            &mut text,
            change(Some(((0, 2), (0, 1))), ""),
            PositionEncoding::Utf16,
        );
        assert_eq!(text, "a\ncd!");
        // Inside a surrogate pair: the start of the character.
        let mut text = "😀".to_owned();
        apply(
            &mut text,
            change(Some(((0, 1), (0, 1))), "x"),
            PositionEncoding::Utf16,
        );
        assert_eq!(text, "x😀");
    }

    #[test]
    fn changes_need_an_open_document_but_not_a_newer_version() {
        let mut documents = Documents::default();
        let uri: Uri = "file:///ws/a.higraph".parse().expect("a URI");
        assert_eq!(
            documents.change("a.higraph", 2, vec![], PositionEncoding::Utf16),
            Err(ChangeRejected::NotOpen)
        );
        documents.open("a.higraph".into(), Document::new(uri, 3, "a".into(), true));
        assert_eq!(
            documents.change(
                "a.higraph",
                3,
                vec![change(None, "b")],
                PositionEncoding::Utf16
            ),
            Ok(Changed::Replaced),
            "a version that is not newer is applied all the same"
        );
        assert_eq!(
            documents.change(
                "a.higraph",
                4,
                vec![change(None, "b")],
                PositionEncoding::Utf16
            ),
            Ok(Changed::Replaced)
        );
        assert_eq!(
            documents.get("a.higraph").map(|d| d.text.as_str()),
            Some("b")
        );
        assert_eq!(
            documents.change(
                "a.higraph",
                5,
                vec![change(Some(((0, 1), (0, 1))), "c\n")],
                PositionEncoding::Utf16
            ),
            Ok(Changed::Edits(vec![Edit {
                delete: TextRange::new(1.into(), 1.into()),
                insert: "c\n".into()
            }]))
        );
        let document = documents.get("a.higraph").expect("open");
        assert_eq!(document.text, "bc\n");
        assert_eq!(*document.line_index, LineIndex::new("bc\n"));
    }

    #[test]
    fn names_are_workspace_relative() {
        let map = PathMap::new(PathBuf::from("/ws"), PathBuf::from("/ws"));
        let uri: Uri = "file:///ws/graphs/a%20b.higraph".parse().expect("a URI");
        assert_eq!(map.name(&uri).as_deref(), Some("graphs/a b.higraph"));
        let outside: Uri = "file:///elsewhere/c.higraph".parse().expect("a URI");
        assert_eq!(map.name(&outside).as_deref(), Some("/elsewhere/c.higraph"));
        let untitled: Uri = "untitled:Untitled-1".parse().expect("a URI");
        assert_eq!(map.name(&untitled), None);
        assert_eq!(
            map.uri("graphs/a b.higraph")
                .map(|u| u.as_str().to_owned())
                .as_deref(),
            Some("file:///ws/graphs/a%20b.higraph")
        );
    }
}

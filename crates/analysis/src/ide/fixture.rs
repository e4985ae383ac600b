//! Test fixtures for the editor features, in rust-analyzer's style: one or more files
//! (`//- path` lines start a file; without them the text is `main.higraph`), an optional
//! `//- higraph.toml`, and a cursor `$0` (or a selection `$0...$0`) in one file.

use higraph_syntax::{TextRange, TextSize};

use crate::{AnalysisHost, FileContents, WorkspaceData};

use super::FilePosition;

/// A loaded fixture.
pub(crate) struct Fixture {
    pub host: AnalysisHost,
    /// The file holding the cursor, and the cursor's offset (the first `$0`).
    pub position: FilePosition,
    /// The selection between two `$0` markers, if there are two.
    pub selection: Option<TextRange>,
    /// The texts of the files, markers removed.
    pub files: Vec<(String, String)>,
}

/// Loads a fixture. Panics (in tests only) if there is no `$0` marker.
pub(crate) fn load(fixture: &str) -> Fixture {
    let mut files: Vec<(String, String)> = Vec::new();
    if fixture.trim_start().starts_with("//- ") {
        for line in fixture.trim_start().split_inclusive('\n') {
            if let Some(path) = line.strip_prefix("//- ") {
                files.push((path.trim().to_owned(), String::new()));
            } else if let Some((_, text)) = files.last_mut() {
                text.push_str(line);
            }
        }
    } else {
        files.push(("main.higraph".to_owned(), fixture.to_owned()));
    }
    let mut position = None;
    let mut selection = None;
    for (path, text) in &mut files {
        let Some(first) = text.find("$0") else {
            continue;
        };
        text.replace_range(first..first + 2, "");
        let start = TextSize::from(first as u32);
        if let Some(second) = text.find("$0") {
            text.replace_range(second..second + 2, "");
            selection = Some(TextRange::new(start, TextSize::from(second as u32)));
        }
        position = Some(FilePosition {
            path: path.clone(),
            offset: start,
        });
    }
    let position = position.unwrap_or_else(|| FilePosition {
        path: files.first().map(|(p, _)| p.clone()).unwrap_or_default(),
        offset: TextSize::from(0),
    });
    let mut data = WorkspaceData::default();
    for (path, text) in &files {
        if path == "higraph.toml" {
            data.config = Some((path.clone(), crate::FileContents::Text(text.clone())));
        } else {
            data.files
                .push((path.clone(), FileContents::Text(text.clone())));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    Fixture {
        host,
        position,
        selection,
        files,
    }
}

impl Fixture {
    /// The text of a file of the fixture.
    pub fn text(&self, path: &str) -> &str {
        self.files
            .iter()
            .find(|(p, _)| p == path)
            .map_or("", |(_, t)| t.as_str())
    }

    /// Renders `range` of `path` as `text` for assertions.
    pub fn slice(&self, path: &str, range: TextRange) -> &str {
        self.text(path)
            .get(std::ops::Range::<usize>::from(range))
            .unwrap_or("")
    }
}

#[test]
fn markers_are_removed() {
    let f = load("//- a.higraph\ngraph G < $0state 0 < > >\n//- b.higraph\n// b\n");
    assert_eq!(f.position.path, "a.higraph");
    assert_eq!(f.text("a.higraph"), "graph G < state 0 < > >\n");
    assert_eq!(u32::from(f.position.offset), 10);
    assert_eq!(
        f.host.paths(),
        vec!["a.higraph".to_owned(), "b.higraph".to_owned()]
    );
}

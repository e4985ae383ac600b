//! The workspace format of the rule fixtures, shared by the analysis' own tests and its
//! integration tests (not part of the API).
//!
//! A fixture is one workspace: either a single file (`main.higraph`), or several files
//! introduced by `//- path` lines (rust-analyzer style), where `//- higraph.toml` is the
//! configuration, `//- x.sdf` an imported symbol table and `//- path !unreadable` a file that
//! cannot be read. Fixtures are bytes, so a file may hold invalid UTF-8.

use crate::{AnalysisHost, FileContents, WorkspaceData};

/// One file of a fixture workspace: its path and its bytes.
pub type FixtureFile = (String, Vec<u8>);

/// Splits a fixture into its files.
pub fn fixture_files(bytes: &[u8]) -> Vec<FixtureFile> {
    if !bytes.starts_with(b"//- ") {
        return vec![("main.higraph".to_owned(), bytes.to_vec())];
    }
    let mut files: Vec<FixtureFile> = Vec::new();
    for line in bytes.split_inclusive(|&b| b == b'\n') {
        if let Some(path) = line.strip_prefix(b"//- ") {
            files.push((String::from_utf8_lossy(path).trim().to_owned(), Vec::new()));
        } else if let Some((_, body)) = files.last_mut() {
            body.extend_from_slice(line);
        }
    }
    files
}

/// The workspace the files of a fixture make.
pub fn workspace_data(files: &[FixtureFile]) -> WorkspaceData {
    let mut data = WorkspaceData::default();
    for (path, body) in files {
        if let Some(path) = path.strip_suffix(" !unreadable") {
            data.files.push((
                path.to_owned(),
                FileContents::unreadable("Permission denied"),
            ));
        } else if path == "higraph.toml" {
            data.config = Some((path.clone(), FileContents::from_bytes(body.clone())));
        } else if path.ends_with(".higraph") {
            data.files
                .push((path.clone(), FileContents::from_bytes(body.clone())));
        } else {
            data.imports.insert(path.clone(), Ok(body.clone()));
        }
    }
    data
}

/// A host with the workspace of a fixture loaded.
pub fn load_fixture(files: &[FixtureFile]) -> AnalysisHost {
    let mut host = AnalysisHost::new();
    host.load(workspace_data(files));
    host
}

//! The entry point for the command line and the language server: an [`AnalysisHost`] owns
//! the writable database and applies changes; [`Analysis`] is a cheap snapshot that answers
//! queries (and is cancelled when the host changes the database).

use std::{collections::HashMap, sync::Arc};

use salsa::Setter;

use crate::{
    Diagnostic, FileContents, FileId, check,
    config::Config,
    db::{File, RootDatabase, Workspace},
    sdf::{self, Import},
};

/// A workspace to load: paths are workspace-relative with `/` separators.
#[derive(Debug, Default)]
pub struct WorkspaceData {
    /// The `.higraph` files (any order; the host sorts them into workspace order).
    pub files: Vec<(String, FileContents)>,
    /// `higraph.toml`: its path and text.
    pub config: Option<(String, String)>,
    /// For each `workspace.symbols` entry of the configuration, the file's bytes or why it
    /// could not be read.
    pub imports: HashMap<String, Result<Vec<u8>, String>>,
}

/// Owns the database.
#[derive(Default)]
pub struct AnalysisHost {
    db: RootDatabase,
    workspace: Option<Workspace>,
    files: HashMap<String, File>,
}

impl AnalysisHost {
    pub fn new() -> AnalysisHost {
        AnalysisHost::default()
    }

    /// A host whose database reports salsa events (for tests of incrementality).
    pub fn with_event_callback(on_event: impl Fn(salsa::Event) + Send + Sync + 'static) -> Self {
        AnalysisHost {
            db: RootDatabase::with_event_callback(on_event),
            ..AnalysisHost::default()
        }
    }

    /// The configuration a workspace's `higraph.toml` text gives.
    pub fn parse_config(text: &str) -> Config {
        Config::parse(text)
    }

    /// Replaces the whole workspace.
    pub fn load(&mut self, data: WorkspaceData) {
        let config = data
            .config
            .as_ref()
            .map(|(_, text)| Config::parse(text))
            .unwrap_or_default();
        let mut paths: Vec<(String, FileContents)> = data.files;
        paths.sort_by(|a, b| a.0.cmp(&b.0));
        let db = &mut self.db;
        self.files.clear();
        let mut files = Vec::new();
        for (path, contents) in paths {
            let file = File::new(db, path.clone(), Arc::new(contents));
            self.files.insert(path, file);
            files.push(file);
        }
        let config_file = data
            .config
            .map(|(path, text)| File::new(db, path, Arc::new(FileContents::Text(text))));
        let imports = config
            .symbols
            .iter()
            .map(|(path, entry)| {
                let file = match data.imports.get(path) {
                    Some(Ok(bytes)) => Ok(File::new(
                        db,
                        path.clone(),
                        Arc::new(FileContents::Text(sdf::decode(bytes))),
                    )),
                    Some(Err(reason)) => Err(reason.clone()),
                    None => Err("the file was not found".to_owned()),
                };
                Import {
                    path: path.clone(),
                    entry: *entry,
                    file,
                }
            })
            .collect();
        self.workspace = Some(Workspace::new(
            db,
            files,
            Arc::new(config),
            config_file,
            imports,
        ));
    }

    /// Sets the contents of one `.higraph` file (an edit). Returns `false` if the workspace
    /// has no such file.
    pub fn set_file_contents(&mut self, path: &str, contents: FileContents) -> bool {
        match self.files.get(path) {
            Some(&file) => {
                file.set_contents(&mut self.db).to(Arc::new(contents));
                true
            }
            None => false,
        }
    }

    /// A snapshot for queries.
    pub fn analysis(&self) -> Analysis {
        Analysis {
            db: self.db.clone(),
            workspace: self.workspace,
        }
    }
}

/// A read-only snapshot of the database.
pub struct Analysis {
    db: RootDatabase,
    workspace: Option<Workspace>,
}

/// A file diagnostics may refer to.
#[derive(Debug, Clone)]
pub struct OutputFile {
    pub path: String,
    pub contents: Arc<FileContents>,
}

impl Analysis {
    /// The files diagnostics refer to; `FileId(i)` is the `i`th.
    pub fn files(&self) -> Vec<OutputFile> {
        let Some(ws) = self.workspace else {
            return Vec::new();
        };
        check::output_files(&self.db, ws)
            .into_iter()
            .map(|f| OutputFile {
                path: f.path(&self.db).clone(),
                contents: f.contents(&self.db).clone(),
            })
            .collect()
    }

    /// The diagnostics of every file.
    pub fn diagnostics(&self) -> Vec<(FileId, Vec<Diagnostic>)> {
        match self.workspace {
            Some(ws) => check::all_diagnostics(&self.db, ws),
            None => Vec::new(),
        }
    }
}

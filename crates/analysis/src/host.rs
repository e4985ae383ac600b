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
    /// `higraph.toml`: its path and contents (HG6101 if they are not UTF-8).
    pub config: Option<(String, FileContents)>,
    /// For each `workspace.symbols` entry of the configuration, the file's bytes or why it
    /// could not be read.
    pub imports: HashMap<String, Result<Vec<u8>, String>>,
    /// `workspace.symbols` entries the reader refused to read (a table outside the
    /// workspace), with the problem: HG6101 on the entry; the table is not imported.
    pub refused_imports: HashMap<String, String>,
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

    /// The configuration a workspace's `higraph.toml` gives.
    pub fn parse_config(contents: &FileContents) -> Config {
        Config::of_contents(contents)
    }

    /// Replaces the whole workspace.
    pub fn load(&mut self, data: WorkspaceData) {
        let mut config = data
            .config
            .as_ref()
            .map(|(_, contents)| Config::of_contents(contents))
            .unwrap_or_default();
        config.refuse_symbols(&data.refused_imports);
        let mut paths: Vec<(String, FileContents)> = data.files;
        paths.sort_by(|a, b| a.0.cmp(&b.0));
        let db = &mut self.db;
        self.files.clear();
        let mut files = Vec::new();
        for (path, contents) in paths {
            let file = File::new(db, path.clone(), Arc::new(contents), None);
            self.files.insert(path, file);
            files.push(file);
        }
        let config_file = data
            .config
            // As text: problems with the bytes are the configuration's own (HG6101).
            .map(|(path, contents)| {
                let text = FileContents::Text(contents.text().to_owned());
                File::new(db, path, Arc::new(text), None)
            });
        let imports = config
            .symbols
            .iter()
            .map(|(path, entry)| {
                let file = match data.imports.get(path) {
                    Some(Ok(bytes)) => Ok(File::new(
                        db,
                        path.clone(),
                        Arc::new(FileContents::Text(sdf::decode(bytes))),
                        None,
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
                file.set_reparse_base(&mut self.db).to(None);
                true
            }
            None => false,
        }
    }

    /// Applies edits, in order, to the text of a `.higraph` file (a keystroke in an editor).
    /// Each edit's range refers to the text left by the edits before it. Unlike
    /// [`AnalysisHost::set_file_contents`] this lets the next parse reparse only the edited
    /// block. Returns the new text; `None` if the workspace has no such text file or an
    /// edit's range does not fit the text — the edits before that one stay applied, so the
    /// caller should then set the whole contents.
    pub fn apply_edits(&mut self, path: &str, edits: &[higraph_syntax::Edit]) -> Option<String> {
        let &file = self.files.get(path)?;
        let mut text = match &**file.contents(&self.db) {
            FileContents::Text(text) => text.clone(),
            _ => return None,
        };
        for edit in edits {
            text = edit.apply(&text)?;
            // The parse of the text before this edit: memoized after the first keystroke.
            let old = crate::db::parse(&self.db, file).clone();
            file.set_contents(&mut self.db)
                .to(Arc::new(FileContents::Text(text.clone())));
            let base = crate::db::ReparseBase {
                old,
                edit: edit.clone(),
            };
            file.set_reparse_base(&mut self.db).to(Some(Arc::new(base)));
        }
        Some(text)
    }

    /// Adds a `.higraph` file, or sets its contents if it exists. Keeps workspace order.
    pub fn upsert_file(&mut self, path: &str, contents: FileContents) {
        if self.set_file_contents(path, contents.clone()) {
            return;
        }
        let Some(ws) = self.workspace else {
            self.load(WorkspaceData {
                files: vec![(path.to_owned(), contents)],
                ..Default::default()
            });
            return;
        };
        let file = File::new(&self.db, path.to_owned(), Arc::new(contents), None);
        self.files.insert(path.to_owned(), file);
        let mut files = ws.files(&self.db).clone();
        let at = files.partition_point(|f| f.path(&self.db).as_str() < path);
        files.insert(at, file);
        ws.set_files(&mut self.db).to(files);
    }

    /// Removes a `.higraph` file from the workspace. Returns `false` if there was none.
    pub fn remove_file(&mut self, path: &str) -> bool {
        let (Some(ws), Some(file)) = (self.workspace, self.files.remove(path)) else {
            return false;
        };
        let files: Vec<File> = ws
            .files(&self.db)
            .iter()
            .copied()
            .filter(|&f| f != file)
            .collect();
        ws.set_files(&mut self.db).to(files);
        true
    }

    /// The paths of the workspace's `.higraph` files, in workspace order.
    pub fn paths(&self) -> Vec<String> {
        match self.workspace {
            Some(ws) => ws
                .files(&self.db)
                .iter()
                .map(|f| f.path(&self.db).clone())
                .collect(),
            None => Vec::new(),
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

/// A read-only snapshot of the database. Every query may be cancelled when the host changes
/// the database: the `Cancellable` methods then return `Err(Cancelled)`.
pub struct Analysis {
    pub(crate) db: RootDatabase,
    pub(crate) workspace: Option<Workspace>,
}

/// The result of a query on a snapshot that the host may cancel.
pub type Cancellable<T> = Result<T, salsa::Cancelled>;

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

    /// A token that cancels this snapshot's queries (and only this snapshot's): they then
    /// return `Err(Cancelled)` (or unwind with it), as when the host changes the database.
    /// For a request the client no longer waits for.
    pub fn cancellation_token(&self) -> salsa::CancellationToken {
        salsa::Database::cancellation_token(&self.db)
    }

    /// The diagnostics of every file, with every fix carried out (the pending renames of
    /// [`crate::Fix::rename`] resolved, those the rename engine refuses dropped): what `check`
    /// prints.
    pub fn diagnostics(&self) -> Vec<(FileId, Vec<Diagnostic>)> {
        let Some(ws) = self.workspace else {
            return Vec::new();
        };
        let mut all = check::all_diagnostics(&self.db, ws);
        for diagnostic in all.iter_mut().flat_map(|(_, diagnostics)| diagnostics) {
            check::resolve_fixes(&self.db, ws, &mut diagnostic.fixes);
        }
        all
    }

    /// The diagnostics of every file as they are cached, their rename fixes pending
    /// ([`crate::Fix::rename`]: no edits yet), and `Err` instead of unwinding when the host
    /// changed the database meanwhile. For the language server, which publishes no fixes.
    pub fn diagnostics_cancellable(&self) -> Cancellable<Vec<(FileId, Vec<Diagnostic>)>> {
        self.with_db(check::all_diagnostics)
    }

    /// `fixes` with their pending renames carried out ([`crate::Fix::rename`]); a fix whose
    /// rename is refused is dropped.
    pub fn resolve_fixes(&self, fixes: &mut Vec<crate::Fix>) -> Cancellable<()> {
        self.with_db(|db, ws| check::resolve_fixes(db, ws, fixes))
    }

    /// Runs `f` on the database and workspace, turning salsa's cancellation into `Err`.
    /// Without a workspace, `f` is not run and the default value is returned.
    pub(crate) fn with_db<T: Default>(
        &self,
        f: impl FnOnce(&dyn salsa::Database, Workspace) -> T,
    ) -> Cancellable<T> {
        let Some(ws) = self.workspace else {
            return Ok(T::default());
        };
        let db = &self.db;
        salsa::Cancelled::catch(std::panic::AssertUnwindSafe(|| f(db, ws)))
    }

    /// The salsa file of a workspace-relative path (a `.higraph` file).
    pub(crate) fn file(&self, path: &str) -> Option<File> {
        let ws = self.workspace?;
        ws.files(&self.db)
            .iter()
            .copied()
            .find(|f| f.path(&self.db) == path)
    }

    /// The contents of a `.higraph` file, if it is in the workspace.
    pub fn file_contents(&self, path: &str) -> Option<Arc<FileContents>> {
        self.file(path).map(|f| f.contents(&self.db).clone())
    }
}

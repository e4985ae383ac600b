//! The server's state and its one owner.
//!
//! [`World`] owns the writable [`AnalysisHost`], the open documents and the last published
//! diagnostics. It runs on a thread of its own and takes [`Task`]s from a channel in the order
//! the client sent the notifications, so edits are applied in order and a request's snapshot
//! sees every notification sent before it. Nothing else writes to the database.
//!
//! Requests run on [`Snapshot`]s (`host.analysis()`), off this thread. A write to the database
//! cancels every running snapshot query (salsa), and waits until their snapshots are dropped,
//! so snapshots live only as long as one request: never store one.
//!
//! After each batch of changes the world hands the new revision to the diagnostics thread
//! ([`super::diagnostics`]) and publishes the diagnostics of every file whose diagnostics
//! changed.
//!
//! Each open document keeps its text and a line index that follows every edit, and an edit
//! reaches the database as byte-offset edits (`AnalysisHost::apply_edits`), so the parser
//! reparses only the edited block. Snapshots reuse the open documents' line indexes, and the
//! line indexes of other files are shared between snapshots until their text changes.

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};

use higraph_analysis::{
    Analysis, AnalysisHost, FileContents, LineIndex, PositionEncoding, WorkspaceData,
};
use tokio::sync::{mpsc as async_mpsc, oneshot};
use tower_lsp_server::ls_types::{
    self as lsp, FileChangeType, FileEvent, MessageType, TextDocumentContentChangeEvent, Uri,
};

use super::capabilities::ClientSupport;
use super::diagnostics::{DiagnosticsWorker, FileDiagnostics};
use super::pull;
use super::testing::{TestKey, TestRecord, TestRecords};
use super::token_delta::TokenCache;
use super::vfs::{Changed, Document, Documents, PathMap};
use crate::workspace::{self, CONFIG_FILE, EXTENSION, FileFilter};

/// Something for the world to do, in the order the client asked for it.
pub(crate) enum Task {
    /// The client's root folder (`None`: no folder open) and what the client supports.
    Initialize {
        root: Option<PathBuf>,
        support: ClientSupport,
        /// The client accepts `workspace/codeLens/refresh`.
        code_lens_refresh: bool,
        /// The `rulesBaseUri` initialization option, if given (see `rule_pages`).
        rules_base: Option<String>,
    },
    /// Read the workspace from disk and analyse it, reporting progress.
    Index {
        progress: async_mpsc::UnboundedSender<IndexProgress>,
    },
    /// `textDocument/didOpen`.
    Open {
        uri: Uri,
        version: i32,
        language_id: String,
        text: String,
    },
    /// `textDocument/didChange`.
    Change {
        uri: Uri,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    },
    /// `textDocument/didClose`.
    Close { uri: Uri },
    /// `textDocument/didSave`.
    Save { uri: Uri },
    /// `workspace/didChangeWatchedFiles`.
    WatchedFiles { changes: Vec<FileEvent> },
    /// Read the whole workspace again (`workspace/didChangeConfiguration`).
    Reload,
    /// A snapshot for a request, reflecting every task before this one.
    Snapshot { reply: oneshot::Sender<Snapshot> },
    /// A test ran (`higraph.runTest`) on the files of contents generation `generation`.
    TestRan {
        generation: u64,
        key: TestKey,
        record: TestRecord,
    },
    /// The diagnostics of a revision, computed off the world's thread.
    DiagnosticsReady {
        revision: u64,
        files: Vec<(String, FileDiagnostics)>,
    },
    /// A diagnostics pull, answered once the current revision's diagnostics are ready.
    Pull {
        request: pull::Request,
        reply: oneshot::Sender<pull::Answer>,
    },
}

/// How indexing at start goes, for `$/progress`.
#[derive(Debug)]
pub(crate) enum IndexProgress {
    /// A step, with the percentage done.
    Report { message: String, percentage: u32 },
    /// Indexing is over. `published` resolves once the first diagnostics have gone to the
    /// client, so the end of the progress follows them.
    Done {
        message: String,
        published: oneshot::Receiver<()>,
    },
}

/// What the world sends to the client (through the async side, which owns the connection).
#[derive(Debug)]
pub(crate) enum ToClient {
    /// `textDocument/publishDiagnostics`.
    Publish {
        uri: Uri,
        diagnostics: Vec<lsp::Diagnostic>,
        version: Option<i32>,
    },
    /// `window/logMessage`.
    Log { kind: MessageType, message: String },
    /// Everything before has been sent: resolve the sender.
    Barrier(oneshot::Sender<()>),
    /// `workspace/codeLens/refresh` (the test lenses show a new result).
    RefreshCodeLenses,
    /// `workspace/diagnostic/refresh` (pulled diagnostics of files the client did not edit
    /// changed).
    RefreshDiagnostics,
}

/// A cheap handle that sends tasks to the world.
#[derive(Clone)]
pub(crate) struct WorldHandle {
    tasks: mpsc::Sender<Task>,
}

impl WorldHandle {
    /// Starts the world on a thread of its own. It talks to the client through `to_client`.
    pub(crate) fn spawn(to_client: async_mpsc::UnboundedSender<ToClient>) -> WorldHandle {
        let (tasks, inbox) = mpsc::channel();
        let world = World::new(to_client, tasks.clone());
        let started = std::thread::Builder::new()
            .name("higraph-world".into())
            .stack_size(crate::ANALYSIS_STACK_SIZE)
            .spawn(move || world.run(inbox));
        if let Err(error) = started {
            // Without the thread every snapshot request fails with an internal error; the
            // server still answers.
            eprintln!("higraph-lsp: cannot start the analysis thread: {error}");
        }
        WorldHandle { tasks }
    }

    /// Queues a task. After the world has stopped, tasks are dropped.
    pub(crate) fn send(&self, task: Task) {
        let _ = self.tasks.send(task);
    }

    /// A snapshot that reflects every task sent before; `None` if the world has stopped.
    pub(crate) async fn snapshot(&self) -> Option<Snapshot> {
        let (reply, answer) = oneshot::channel();
        self.send(Task::Snapshot { reply });
        answer.await.ok()
    }

    /// Answers a diagnostics pull; `None` if the world has stopped. A cancelled request
    /// drops the answer.
    pub(crate) async fn pull(&self, request: pull::Request) -> Option<pull::Answer> {
        let (reply, answer) = oneshot::channel();
        self.send(Task::Pull { request, reply });
        answer.await.ok()
    }
}

/// A read-only view of one revision for one request: the analysis snapshot plus what is
/// needed to convert between URIs/positions and workspace paths/offsets.
pub(crate) struct Snapshot {
    /// The analysis of this revision (cancelled when the world writes).
    pub analysis: Analysis,
    /// The position encoding negotiated with the client.
    pub encoding: PositionEncoding,
    /// What the client supports.
    pub support: ClientSupport,
    /// Where the rules' pages are (see `rule_pages`); `None`: no rule links.
    pub rules_base: Option<Arc<str>>,
    paths: Arc<PathMap>,
    /// The URIs of the open documents by workspace path, so answers name them as the client
    /// does.
    open_uris: Arc<HashMap<String, Uri>>,
    /// Line indexes used so far by this request; starts with those of the open documents.
    line_indexes: RefCell<HashMap<String, Arc<LineIndex>>>,
    /// The line indexes of the files that are not open, shared by all snapshots.
    shared_indexes: SharedLineIndexes,
    /// Set when the client no longer waits for the request's answer (`$/cancelRequest`).
    cancelled: Arc<AtomicBool>,
    /// The contents generation of this snapshot's files (see `World::generation`).
    generation: u64,
    /// The tests run since the files last changed.
    test_records: TestRecords,
    /// The last semantic tokens sent per open document (`token_delta`).
    semantic_tokens: Arc<TokenCache>,
    /// The document numbers of the count lenses' data (shared with the world).
    lens_table: Arc<super::lens_table::LensTable>,
}

/// The line indexes of files that are not open, by workspace path, with the contents they
/// index (an index is reused while the database holds the same contents).
type SharedLineIndexes = Arc<Mutex<HashMap<String, (Arc<FileContents>, Arc<LineIndex>)>>>;

/// Identifies the URIs a snapshot gives files: equal keys give equal URIs.
#[derive(Clone)]
pub(crate) struct UriKey {
    paths: Arc<PathMap>,
    open_uris: Arc<HashMap<String, Uri>>,
}

impl UriKey {
    /// Whether both keys are of the same maps (kept alive by the keys, so the maps did not
    /// change in place).
    pub(crate) fn same(&self, other: &UriKey) -> bool {
        Arc::ptr_eq(&self.paths, &other.paths) && Arc::ptr_eq(&self.open_uris, &other.open_uris)
    }
}

impl Snapshot {
    /// Whether the client cancelled the request this snapshot serves: long computations look
    /// at it between steps and stop.
    pub(crate) fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// The flag [`Snapshot::is_cancelled`] reads, for the request's owner to set.
    pub(crate) fn cancel_flag(&self) -> Arc<AtomicBool> {
        self.cancelled.clone()
    }

    /// Remembers the semantic tokens answered for `path` (kept for open documents only) and
    /// gives their result id, with the edits from the tokens of `previous` when that is the
    /// id of the tokens remembered so far (see `token_delta`).
    pub(crate) fn store_semantic_tokens(
        &self,
        path: &str,
        previous: Option<&str>,
        tokens: &[tower_lsp_server::ls_types::SemanticToken],
    ) -> (
        Option<String>,
        Option<Vec<tower_lsp_server::ls_types::SemanticTokensEdit>>,
    ) {
        self.semantic_tokens
            .store(path, previous, tokens, &|p| self.open_uris.contains_key(p))
    }

    /// The number of `path` in the count lenses' data (see `lens_table`).
    pub(crate) fn lens_number(&self, path: &str) -> Option<u64> {
        self.lens_table
            .number(path, &|p| self.open_uris.contains_key(p))
    }

    /// The workspace path of a number from the count lenses' data.
    pub(crate) fn lens_path(&self, number: u64) -> Option<String> {
        self.lens_table.path(number)
    }

    /// The contents generation of the snapshot's files: it changes whenever a file does.
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// The last run of a test, if it ran since the files last changed.
    pub(crate) fn test_record(&self, key: &TestKey) -> Option<&TestRecord> {
        self.test_records.get(key)
    }

    /// The documentation page of a rule (`HG2105`), if rule links are on.
    pub(crate) fn rule_page(&self, code: &str) -> Option<Uri> {
        super::rule_pages::page(self.rules_base.as_deref()?, code)
    }

    /// The workspace root on disk (canonical), `None` when the client opened no folder.
    pub(crate) fn root(&self) -> Option<&std::path::Path> {
        self.paths.root()
    }

    /// The workspace path of a URI (`None` for URIs that name no file).
    pub(crate) fn path(&self, uri: &Uri) -> Option<String> {
        self.paths.name(uri)
    }

    /// The URI of a workspace path.
    pub(crate) fn uri(&self, path: &str) -> Option<Uri> {
        match self.open_uris.get(path) {
            Some(uri) => Some(uri.clone()),
            None => self.paths.uri(path),
        }
    }

    /// What the URIs of this snapshot depend on.
    pub(crate) fn uri_key(&self) -> UriKey {
        UriKey {
            paths: self.paths.clone(),
            open_uris: self.open_uris.clone(),
        }
    }

    /// The line index of a file of the workspace (a `.higraph` file, `higraph.toml` or an
    /// imported symbol table), `None` if there is no such file.
    pub(crate) fn line_index(&self, path: &str) -> Option<Arc<LineIndex>> {
        if let Some(index) = self.line_indexes.borrow().get(path) {
            return Some(index.clone());
        }
        let contents = match self.analysis.file_contents(path) {
            Some(contents) => contents,
            None => {
                let files = self.analysis.files();
                files.into_iter().find(|file| file.path == path)?.contents
            }
        };
        let shared = self.shared_indexes.lock().ok().and_then(|shared| {
            let (indexed, index) = shared.get(path)?;
            Arc::ptr_eq(indexed, &contents).then(|| index.clone())
        });
        let index = match shared {
            Some(index) => index,
            None => {
                let index = Arc::new(LineIndex::new(contents.text()));
                if let Ok(mut shared) = self.shared_indexes.lock() {
                    shared.insert(path.to_owned(), (contents, index.clone()));
                }
                index
            }
        };
        self.line_indexes
            .borrow_mut()
            .insert(path.to_owned(), index.clone());
        Some(index)
    }
}

/// The owner of the analysis host and the open documents (see the module documentation).
struct World {
    host: AnalysisHost,
    paths: Arc<PathMap>,
    support: ClientSupport,
    documents: Documents,
    open_uris: Arc<HashMap<String, Uri>>,
    /// The `.higraph` files on disk that belong to the workspace (found by the walk and
    /// accepted by `include`/`exclude`). A closed document falls back to its disk file if it
    /// has one, else it leaves the analysis.
    disk_files: HashSet<String>,
    /// The workspace's `include`/`exclude` patterns.
    filter: FileFilter,
    /// Counts the changes to the database.
    revision: u64,
    /// The revision whose diagnostics were last started.
    analysed: u64,
    /// The diagnostics last published, by workspace path, with the URI they went to (also
    /// empty lists: every workspace file is published once, clean or not).
    published: HashMap<String, (Uri, FileDiagnostics)>,
    /// Open documents opened or changed since the last publication: their diagnostics are
    /// published with the new version even when they did not change, so a client waiting for
    /// the diagnostics of the version it sent gets them.
    republish: HashSet<String>,
    /// The line indexes of the files that are not open (see [`Snapshot`]).
    shared_indexes: SharedLineIndexes,
    /// Converts the diagnostics of each revision (started with the first one).
    diagnostics: Option<DiagnosticsWorker>,
    /// Where to report indexing progress until the first diagnostics are published.
    index_progress: Option<async_mpsc::UnboundedSender<IndexProgress>>,
    to_client: async_mpsc::UnboundedSender<ToClient>,
    /// The world's own inbox, for the diagnostics thread to answer.
    tasks: mpsc::Sender<Task>,
    /// Counts the changes of the files' contents (a revision that only reopens a document
    /// with its text does not count): test results hold until it moves.
    generation: u64,
    /// The generation the test records belong to.
    tested: u64,
    /// The last run of each test run since the files last changed; their failures are
    /// published with the files' own diagnostics.
    test_records: TestRecords,
    /// The client refreshes code lenses on request.
    code_lens_refresh: bool,
    /// The last semantic tokens sent per open document (see [`Snapshot`]).
    semantic_tokens: Arc<TokenCache>,
    /// The document numbers of the count lenses' data, shared with the snapshots.
    lens_table: Arc<super::lens_table::LensTable>,
    /// Where the rules' pages are (see `rule_pages`).
    rules_base: Option<Arc<str>>,
    /// The revision whose diagnostics are in `published`.
    ready: u64,
    /// Pull mode: the result id of each published file (see `pull`).
    result_ids: HashMap<String, String>,
    /// Pull mode: the documents the client opened or changed since the last publication.
    client_edited: HashSet<String>,
    /// Pulls waiting for the current revision's diagnostics.
    pending_pulls: Vec<(pull::Request, oneshot::Sender<pull::Answer>)>,
}

impl World {
    fn new(to_client: async_mpsc::UnboundedSender<ToClient>, tasks: mpsc::Sender<Task>) -> World {
        World {
            host: AnalysisHost::new(),
            paths: Arc::new(PathMap::default()),
            support: ClientSupport::default(),
            documents: Documents::default(),
            open_uris: Arc::new(HashMap::new()),
            disk_files: HashSet::new(),
            filter: FileFilter::new(&["**/*.higraph".to_owned()], &[]),
            revision: 0,
            analysed: 0,
            published: HashMap::new(),
            republish: HashSet::new(),
            shared_indexes: SharedLineIndexes::default(),
            diagnostics: None,
            index_progress: None,
            to_client,
            tasks,
            generation: 0,
            tested: 0,
            test_records: TestRecords::default(),
            code_lens_refresh: false,
            semantic_tokens: Arc::default(),
            lens_table: Arc::default(),
            rules_base: None,
            ready: 0,
            result_ids: HashMap::new(),
            client_edited: HashSet::new(),
            pending_pulls: Vec::new(),
        }
    }

    /// Takes tasks until every handle is gone. Everything already queued is applied before the
    /// new revision is analysed, so a burst of edits is analysed once.
    fn run(mut self, inbox: mpsc::Receiver<Task>) {
        while let Ok(task) = inbox.recv() {
            self.handle_guarded(task);
            while let Ok(task) = inbox.try_recv() {
                self.handle_guarded(task);
            }
            if self.analysed != self.revision {
                self.start_diagnostics();
            }
        }
    }

    /// Handles a task; a panic (a bug) is logged and the world carries on.
    fn handle_guarded(&mut self, task: Task) {
        let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| self.handle(task)));
        if let Err(payload) = outcome {
            let message = super::panic_message(payload.as_ref());
            self.log(MessageType::ERROR, format!("internal error: {message}"));
        }
        // At once, so that a snapshot taken right after a change no longer sees the runs.
        if self.tested != self.generation {
            self.forget_test_runs();
        }
    }

    fn handle(&mut self, task: Task) {
        match task {
            Task::Initialize {
                root,
                support,
                code_lens_refresh,
                rules_base,
            } => {
                self.support = support;
                self.code_lens_refresh = code_lens_refresh;
                self.paths = Arc::new(match root {
                    Some(root) => path_map(&root),
                    None => PathMap::default(),
                });
                match super::rule_pages::base(rules_base.as_deref(), self.paths.root()) {
                    Ok(base) => self.rules_base = base.map(Arc::from),
                    Err(problem) => self.log(MessageType::WARNING, problem),
                }
            }
            Task::Index { progress } => {
                let _ = progress.send(IndexProgress::Report {
                    message: "reading files".into(),
                    percentage: 0,
                });
                self.reload();
                let _ = progress.send(IndexProgress::Report {
                    message: format!("analysing {}", count_files(self.host.paths().len())),
                    percentage: 50,
                });
                self.index_progress = Some(progress);
            }
            Task::Open {
                uri,
                version,
                language_id,
                text,
            } => self.open(uri, version, &language_id, text),
            Task::Change {
                uri,
                version,
                changes,
            } => self.change(&uri, version, changes),
            Task::Close { uri } => self.close(&uri),
            Task::Save { uri } => {
                if self.paths.name(&uri).is_some_and(|name| is_settings(&name)) {
                    self.reload();
                }
            }
            Task::WatchedFiles { changes } => self.watched_files(changes),
            Task::Reload => self.reload(),
            Task::Snapshot { reply } => {
                // A request that was cancelled meanwhile drops the snapshot with the channel.
                let _ = reply.send(self.snapshot());
            }
            Task::TestRan {
                generation,
                key,
                record,
            } => self.test_ran(generation, key, record),
            Task::DiagnosticsReady { revision, files } => {
                // A newer revision is being analysed: these are stale.
                if revision == self.revision {
                    self.publish(files);
                    self.ready = revision;
                    for (request, reply) in std::mem::take(&mut self.pending_pulls) {
                        let _ = reply.send(self.answer_pull(request));
                    }
                }
            }
            Task::Pull { request, reply } => {
                if self.ready == self.revision {
                    let _ = reply.send(self.answer_pull(request));
                } else {
                    self.pending_pulls.push((request, reply));
                }
            }
        }
    }

    fn snapshot(&self) -> Snapshot {
        // The database holds exactly the text of an open source document, so its index
        // serves.
        let line_indexes = self
            .documents
            .iter()
            .filter(|(_, document)| document.analysed)
            .map(|(name, document)| (name.clone(), document.line_index.clone()))
            .collect();
        Snapshot {
            analysis: self.host.analysis(),
            encoding: self.support.encoding,
            support: self.support,
            rules_base: self.rules_base.clone(),
            paths: self.paths.clone(),
            open_uris: self.open_uris.clone(),
            line_indexes: RefCell::new(line_indexes),
            shared_indexes: self.shared_indexes.clone(),
            cancelled: Arc::new(AtomicBool::new(false)),
            generation: self.generation,
            test_records: self.test_records.clone(),
            semantic_tokens: self.semantic_tokens.clone(),
            lens_table: self.lens_table.clone(),
        }
    }

    /// Keeps a test's run (replacing its previous one) and publishes its failures, unless
    /// the files changed while it ran.
    fn test_ran(&mut self, generation: u64, key: TestKey, record: TestRecord) {
        if generation != self.generation {
            return;
        }
        self.tested = generation;
        let mut files: HashSet<String> = record
            .diagnostics
            .iter()
            .map(|(file, _)| file.clone())
            .collect();
        let records = Arc::make_mut(&mut self.test_records);
        if let Some(old) = records.insert(key, record) {
            files.extend(old.diagnostics.into_iter().map(|(file, _)| file));
        }
        if self.support.pull_diagnostics {
            self.update_result_ids(files.into_iter(), true);
            self.refresh_code_lenses();
            return;
        }
        // Files not published yet get their test failures with their first publication.
        for name in files {
            if let Some((uri, diagnostics)) = self.published.get(&name) {
                let _ = self.to_client.send(ToClient::Publish {
                    uri: uri.clone(),
                    diagnostics: self.with_test_failures(&name, diagnostics),
                    version: self.documents.get(&name).map(|d| d.version),
                });
            }
        }
        self.refresh_code_lenses();
    }

    /// The files changed: the test runs no longer describe them. Their failures go with the
    /// next publication.
    fn forget_test_runs(&mut self) {
        self.tested = self.generation;
        if self.test_records.is_empty() {
            return;
        }
        for record in self.test_records.values() {
            for (file, _) in &record.diagnostics {
                self.republish.insert(file.clone());
            }
        }
        self.test_records = TestRecords::default();
        self.refresh_code_lenses();
    }

    fn refresh_code_lenses(&self) {
        if self.code_lens_refresh {
            let _ = self.to_client.send(ToClient::RefreshCodeLenses);
        }
    }

    /// A file's diagnostics followed by the failures of the tests run in it.
    fn with_test_failures(
        &self,
        name: &str,
        diagnostics: &FileDiagnostics,
    ) -> Vec<lsp::Diagnostic> {
        let mut all = diagnostics.to_vec();
        for record in self.test_records.values() {
            all.extend(
                record
                    .diagnostics
                    .iter()
                    .filter(|(file, _)| file == name)
                    .map(|(_, diagnostic)| diagnostic.clone()),
            );
        }
        all
    }

    fn log(&self, kind: MessageType, message: String) {
        let _ = self.to_client.send(ToClient::Log { kind, message });
    }

    /// Reads the workspace from disk again (at start, and when the configuration or a symbol
    /// table changes). Open documents keep the client's text.
    fn reload(&mut self) {
        let mut data = WorkspaceData::default();
        if let Some(root) = self.paths.root() {
            match workspace::discover(&[root.to_path_buf()]) {
                Ok((found, warnings)) => {
                    for warning in warnings {
                        self.log(MessageType::WARNING, warning);
                    }
                    match workspace::load(&found, None) {
                        Ok(loaded) => data = loaded.data,
                        Err(error) => self.log(MessageType::ERROR, error.to_string()),
                    }
                }
                Err(error) => self.log(MessageType::ERROR, error.to_string()),
            }
        }
        let config = data
            .config
            .as_ref()
            .map(|(_, contents)| AnalysisHost::parse_config(contents));
        self.filter = match &config {
            Some(config) => FileFilter::new(&config.include, &config.exclude),
            None => FileFilter::new(&["**/*.higraph".to_owned()], &[]),
        };
        self.disk_files = data.files.iter().map(|(name, _)| name.clone()).collect();
        for (name, document) in self.documents.iter() {
            if !document.analysed {
                continue;
            }
            let contents = document_contents(&document.text);
            match data.files.iter_mut().find(|(path, _)| path == name) {
                Some(file) => file.1 = contents,
                None => data.files.push((name.clone(), contents)),
            }
        }
        self.host.load(data);
        self.revision += 1;
        self.generation += 1;
        // Every file has new contents: the old indexes would never be used again.
        if let Ok(mut shared) = self.shared_indexes.lock() {
            shared.clear();
        }
    }

    fn open(&mut self, uri: Uri, version: i32, language_id: &str, text: String) {
        let Some(name) = self.paths.name(&uri) else {
            self.log(
                MessageType::INFO,
                format!("not analysing {}: only file: documents are", uri.as_str()),
            );
            return;
        };
        let analysed = name.ends_with(&format!(".{EXTENSION}")) || language_id == "higraph";
        if analysed {
            let contents = document_contents(&text);
            if !self.holds(&name, &contents) {
                self.generation += 1;
            }
            self.host.upsert_file(&name, contents);
            self.revision += 1;
            self.republish.insert(name.clone());
            self.client_edited.insert(name.clone());
        }
        Arc::make_mut(&mut self.open_uris).insert(name.clone(), uri.clone());
        self.documents
            .open(name, Document::new(uri, version, text, analysed));
    }

    fn change(&mut self, uri: &Uri, version: i32, changes: Vec<TextDocumentContentChangeEvent>) {
        let Some(name) = self.paths.name(uri) else {
            return;
        };
        if let Some(have) = self
            .documents
            .get(&name)
            .map(|d| d.version)
            .filter(|&have| version <= have)
        {
            self.log(
                MessageType::WARNING,
                format!(
                    "{}: version {version} is not newer than {have}; applying the change anyway",
                    uri.as_str()
                ),
            );
        }
        match self
            .documents
            .change(&name, version, changes, self.support.encoding)
        {
            Ok(changed) => {
                let Some(document) = self.documents.get(&name).filter(|d| d.analysed) else {
                    return;
                };
                // The byte-offset edits let the parser reparse only the edited block. The
                // database must end with exactly the document's text; if it does not (or the
                // whole text was replaced), the whole text is set.
                let edited = match &changed {
                    Changed::Edits(edits) if edits.is_empty() => return,
                    _ if too_large(&document.text) => false,
                    Changed::Edits(edits) => self
                        .host
                        .apply_edits(&name, edits)
                        .is_some_and(|text| text == document.text),
                    Changed::Replaced => false,
                };
                if !edited {
                    self.host
                        .upsert_file(&name, document_contents(&document.text));
                }
                self.revision += 1;
                self.generation += 1;
                self.client_edited.insert(name.clone());
                self.republish.insert(name);
            }
            Err(rejected) => self.log(
                MessageType::WARNING,
                format!("ignoring a change to {}: {rejected}", uri.as_str()),
            ),
        }
    }

    fn close(&mut self, uri: &Uri) {
        let Some(name) = self.paths.name(uri) else {
            return;
        };
        let Some(document) = self.documents.close(&name) else {
            self.log(
                MessageType::WARNING,
                format!("ignoring the close of {}: it is not open", uri.as_str()),
            );
            return;
        };
        Arc::make_mut(&mut self.open_uris).remove(&name);
        self.semantic_tokens.forget(&name);
        self.lens_table.forget(&name);
        if !document.analysed {
            return;
        }
        // The disk is the truth again.
        if self.disk_files.contains(&name) {
            let contents = self.read(&name);
            if !self.holds(&name, &contents) {
                self.generation += 1;
            }
            self.host.upsert_file(&name, contents);
        } else {
            self.host.remove_file(&name);
            self.generation += 1;
        }
        self.revision += 1;
    }

    /// Whether the database holds exactly these contents for the file.
    fn holds(&self, name: &str, contents: &FileContents) -> bool {
        self.host
            .analysis()
            .file_contents(name)
            .is_some_and(|held| *held == *contents)
    }

    /// The contents of a workspace file on disk: as `check` reads it (only a regular file
    /// inside the root, at most [`workspace::MAX_SOURCE_BYTES`]).
    fn read(&self, name: &str) -> FileContents {
        let (Some(path), Some(root)) = (self.paths.absolute(name), self.paths.root()) else {
            return FileContents::unreadable("the file is not in the workspace");
        };
        match workspace::Fence::new(root.to_path_buf()).read(&path, workspace::MAX_SOURCE_BYTES) {
            Ok(bytes) => FileContents::from_bytes(bytes),
            Err(reason) => FileContents::unreadable(reason),
        }
    }

    fn watched_files(&mut self, changes: Vec<FileEvent>) {
        let mut reload = false;
        for change in changes {
            let Some(path) = PathMap::file_path(&change.uri) else {
                continue;
            };
            let name = self.paths.name_of_path(&path);
            if is_settings(&name) {
                reload = true;
                continue;
            }
            let belongs = self
                .paths
                .root()
                .is_some_and(|root| workspace::walk_finds(root, &path))
                && self.filter.accepts(&name);
            if !belongs {
                continue;
            }
            let deleted = change.typ == FileChangeType::DELETED;
            if deleted {
                self.disk_files.remove(&name);
            } else {
                self.disk_files.insert(name.clone());
            }
            if self.documents.get(&name).is_some_and(|d| d.analysed) {
                // The client owns an open document's text.
                continue;
            }
            if deleted {
                if self.host.remove_file(&name) {
                    self.revision += 1;
                    self.generation += 1;
                }
            } else {
                let contents = self.read(&name);
                self.host.upsert_file(&name, contents);
                self.revision += 1;
                self.generation += 1;
            }
        }
        if reload {
            self.reload();
        }
    }

    /// Hands the current revision to the diagnostics thread; the result comes back as
    /// [`Task::DiagnosticsReady`]. An edit meanwhile cancels it, and the next batch queues a
    /// new one.
    fn start_diagnostics(&mut self) {
        self.analysed = self.revision;
        // The thread ends only if it panicked outside a conversion (a bug): then one new
        // thread is tried.
        for _ in 0..2 {
            if self.diagnostics.is_none() {
                match DiagnosticsWorker::spawn(self.tasks.clone(), self.to_client.clone()) {
                    Ok(worker) => self.diagnostics = Some(worker),
                    Err(error) => {
                        self.log(
                            MessageType::ERROR,
                            format!("cannot start the diagnostics thread: {error}"),
                        );
                        return;
                    }
                }
            }
            let snapshot = self.snapshot();
            if let Some(worker) = &self.diagnostics
                && worker.analyse(self.revision, snapshot)
            {
                return;
            }
            self.diagnostics = None;
        }
        self.log(MessageType::ERROR, "the diagnostics thread stopped".into());
    }

    /// Publishes the diagnostics of every file whose diagnostics changed since they were last
    /// published, of every file not published yet (an empty list for a clean file), and of
    /// every open document opened or changed since (with its version).
    fn publish(&mut self, files: Vec<(String, FileDiagnostics)>) {
        if self.support.pull_diagnostics {
            self.keep_for_pulls(files);
            return;
        }
        let mut current: HashSet<String> = HashSet::new();
        for (name, diagnostics) in files {
            current.insert(name.clone());
            // An open document's diagnostics go to the URI the client named it by.
            let uri = match self.documents.get(&name) {
                Some(document) => Some(document.uri.clone()),
                None => self.paths.uri(&name),
            };
            let Some(uri) = uri else {
                continue;
            };
            let previous = self.published.get(&name);
            let unchanged = match previous {
                Some((published_uri, published)) => {
                    *published_uri == uri
                        && (Arc::ptr_eq(published, &diagnostics) || *published == diagnostics)
                        && !self.republish.contains(&name)
                }
                None => false,
            };
            if unchanged {
                continue;
            }
            if let Some((old_uri, _)) = previous.filter(|(old_uri, _)| *old_uri != uri) {
                // The same file under another spelling of its URI: clear the old one.
                let _ = self.to_client.send(ToClient::Publish {
                    uri: old_uri.clone(),
                    diagnostics: Vec::new(),
                    version: None,
                });
            }
            let version = self.documents.get(&name).map(|d| d.version);
            let _ = self.to_client.send(ToClient::Publish {
                uri: uri.clone(),
                diagnostics: self.with_test_failures(&name, &diagnostics),
                version,
            });
            self.published.insert(name, (uri, diagnostics));
        }
        self.republish.clear();
        let gone: Vec<String> = self
            .published
            .keys()
            .filter(|name| !current.contains(*name))
            .cloned()
            .collect();
        for name in gone {
            if let Some((uri, _)) = self.published.remove(&name) {
                let _ = self.to_client.send(ToClient::Publish {
                    uri,
                    diagnostics: Vec::new(),
                    version: None,
                });
            }
        }
        self.end_index_progress();
    }

    /// Ends the indexing progress after the first diagnostics (published or ready to pull).
    fn end_index_progress(&mut self) {
        if let Some(progress) = self.index_progress.take() {
            let (sent, published) = oneshot::channel();
            let _ = self.to_client.send(ToClient::Barrier(sent));
            let _ = progress.send(IndexProgress::Done {
                message: format!("{} indexed", count_files(self.host.paths().len())),
                published,
            });
        }
    }
}

/// Pull diagnostics (see `pull`): the world keeps what it would publish and answers pulls.
impl World {
    /// Keeps the diagnostics of a revision for pulls (instead of publishing them), updates
    /// the result ids, and asks the client to pull again when files it did not edit changed.
    fn keep_for_pulls(&mut self, files: Vec<(String, FileDiagnostics)>) {
        let first = self.ready == 0;
        let mut current: HashSet<String> = HashSet::new();
        let mut changed = Vec::new();
        for (name, diagnostics) in files {
            current.insert(name.clone());
            let uri = match self.documents.get(&name) {
                Some(document) => Some(document.uri.clone()),
                None => self.paths.uri(&name),
            };
            let Some(uri) = uri else {
                continue;
            };
            let same =
                self.published.get(&name).is_some_and(|(old_uri, old)| {
                    *old_uri == uri && Arc::ptr_eq(old, &diagnostics)
                }) && !self.republish.contains(&name);
            if !same {
                changed.push(name.clone());
            }
            self.published.insert(name, (uri, diagnostics));
        }
        self.republish.clear();
        let before = self.published.len();
        self.published.retain(|name, _| current.contains(name));
        self.result_ids.retain(|name, _| current.contains(name));
        let removed = self.published.len() != before;
        let refresh = self.update_result_ids(changed.into_iter(), false) || removed;
        self.client_edited.clear();
        if refresh && !first {
            self.refresh_diagnostics();
        }
        self.end_index_progress();
    }

    /// Recomputes the result ids of `names`; whether one changed that calls for a refresh:
    /// any (`any`), or one of a file the client did not edit since the last publication.
    fn update_result_ids(&mut self, names: impl Iterator<Item = String>, any: bool) -> bool {
        let mut refresh = false;
        for name in names {
            let Some((_, diagnostics)) = self.published.get(&name) else {
                continue;
            };
            let id = pull::result_id(&self.with_test_failures(&name, diagnostics));
            if self.result_ids.get(&name) != Some(&id) {
                refresh |= any || !self.client_edited.contains(&name);
                self.result_ids.insert(name, id);
            }
        }
        if any && refresh {
            self.refresh_diagnostics();
        }
        refresh
    }

    fn refresh_diagnostics(&self) {
        if self.support.diagnostic_refresh {
            let _ = self.to_client.send(ToClient::RefreshDiagnostics);
        }
    }

    /// The result id of a published file.
    fn result_id(&self, name: &str) -> Option<String> {
        let (_, diagnostics) = self.published.get(name)?;
        Some(match self.result_ids.get(name) {
            Some(id) => id.clone(),
            None => pull::result_id(&self.with_test_failures(name, diagnostics)),
        })
    }

    /// The diagnostics of a file as pulled (none for a file not published).
    fn pulled_items(&self, name: &str) -> Vec<lsp::Diagnostic> {
        match self.published.get(name) {
            Some((_, diagnostics)) => self.with_test_failures(name, diagnostics),
            None => Vec::new(),
        }
    }

    fn answer_pull(&self, request: pull::Request) -> pull::Answer {
        match request {
            pull::Request::Document { uri, previous } => {
                // A document outside the workspace (or not analysed) has no diagnostics.
                let name = self.paths.name(&uri).unwrap_or_default();
                let id = self
                    .result_id(&name)
                    .unwrap_or_else(|| pull::result_id(&[]));
                pull::Answer::Document(pull::document_report(previous.as_deref(), id, || {
                    self.pulled_items(&name)
                }))
            }
            pull::Request::Workspace { previous } => {
                let previous: HashMap<&str, &str> = previous
                    .iter()
                    .map(|p| (p.uri.as_str(), p.value.as_str()))
                    .collect();
                let mut names: Vec<&String> = self.published.keys().collect();
                names.sort_unstable();
                let items = names
                    .into_iter()
                    .filter_map(|name| {
                        let (uri, _) = self.published.get(name)?;
                        Some(pull::workspace_item(
                            uri.clone(),
                            self.documents.get(name).map(|d| d.version),
                            previous.get(uri.as_str()).copied(),
                            self.result_id(name)?,
                            || self.pulled_items(name),
                        ))
                    })
                    .collect();
                pull::Answer::Workspace(lsp::WorkspaceDiagnosticReportResult::Report(
                    lsp::WorkspaceDiagnosticReport { items },
                ))
            }
        }
    }
}

/// The path map for the client's root folder: the workspace root is the nearest folder
/// upwards holding `higraph.toml`, as for `check`.
fn path_map(client_root: &Path) -> PathMap {
    let canonical =
        std::fs::canonicalize(client_root).unwrap_or_else(|_| client_root.to_path_buf());
    let root = workspace::find_root(&canonical);
    // The same folder as the client would write it: as many levels up from its root folder as
    // the workspace root is above the canonical one.
    let levels = canonical
        .components()
        .count()
        .saturating_sub(root.components().count());
    let mut client_side = client_root.to_path_buf();
    for _ in 0..levels {
        client_side.pop();
    }
    PathMap::new(root, client_side)
}

/// Whether an open document is over the size limit of source files.
fn too_large(text: &str) -> bool {
    text.len() as u64 > workspace::MAX_SOURCE_BYTES
}

/// What the analysis sees of an open document: its text, or, over the size limit of source
/// files ([`workspace::MAX_SOURCE_BYTES`]), the same HG6103 as `check` gives such a file.
fn document_contents(text: &str) -> FileContents {
    if too_large(text) {
        FileContents::unreadable(format!(
            "it is larger than the limit of {}",
            workspace::size_text(workspace::MAX_SOURCE_BYTES)
        ))
    } else {
        FileContents::Text(text.to_owned())
    }
}

/// Whether a workspace path is the configuration or a symbol table: a change reloads the
/// workspace.
fn is_settings(name: &str) -> bool {
    name == CONFIG_FILE || name.ends_with(".sdf")
}

fn count_files(n: usize) -> String {
    match n {
        1 => "1 file".to_owned(),
        n => format!("{n} files"),
    }
}

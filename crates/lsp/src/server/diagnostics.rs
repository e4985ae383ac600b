//! The published diagnostics: one long-lived thread converts the diagnostics of each new
//! revision to LSP and hands them back to the world, which publishes the files whose
//! diagnostics changed.
//!
//! The conversion is cached per file: a file whose analysis diagnostics are equal to last
//! time, and whose text (and the text of every file its related locations point into) is the
//! same, keeps last time's LSP diagnostics (the same `Arc`, so the world compares it by
//! pointer). After a keystroke only the edited file is converted, with the line index the
//! world keeps for the open document.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::mpsc;

use higraph_analysis::{FileContents, FileId, TextRange};
use tokio::sync::mpsc as async_mpsc;
use tower_lsp_server::ls_types::{self as lsp, MessageType};

use super::convert;
use super::handlers::HandlerResult;
use super::state::{Snapshot, Task, ToClient};

/// The LSP diagnostics of one file; shared between the cache, the world and the client queue.
pub(crate) type FileDiagnostics = Arc<Vec<lsp::Diagnostic>>;

/// The diagnostics of a revision to analyse.
struct Job {
    revision: u64,
    snapshot: Snapshot,
}

/// A handle to the diagnostics thread.
pub(crate) struct DiagnosticsWorker {
    jobs: mpsc::Sender<Job>,
}

impl DiagnosticsWorker {
    /// Starts the thread. Results come back to the world as [`Task::DiagnosticsReady`].
    pub(crate) fn spawn(
        tasks: mpsc::Sender<Task>,
        to_client: async_mpsc::UnboundedSender<ToClient>,
    ) -> std::io::Result<DiagnosticsWorker> {
        let (jobs, inbox) = mpsc::channel();
        std::thread::Builder::new()
            .name("higraph-diagnostics".into())
            .stack_size(crate::ANALYSIS_STACK_SIZE)
            .spawn(move || run(inbox, tasks, to_client))?;
        Ok(DiagnosticsWorker { jobs })
    }

    /// Queues the analysis of a revision; `false` if the thread has stopped.
    pub(crate) fn analyse(&self, revision: u64, snapshot: Snapshot) -> bool {
        self.jobs.send(Job { revision, snapshot }).is_ok()
    }
}

fn run(
    inbox: mpsc::Receiver<Job>,
    tasks: mpsc::Sender<Task>,
    to_client: async_mpsc::UnboundedSender<ToClient>,
) {
    let mut cache = Converted::default();
    while let Ok(mut job) = inbox.recv() {
        // Only the newest revision matters; older snapshots are dropped at once, so they do
        // not hold up the world's next write.
        while let Ok(newer) = inbox.try_recv() {
            job = newer;
        }
        let Job { revision, snapshot } = job;
        let outcome = super::catch(|| cache.publishable(&snapshot));
        drop(snapshot);
        match outcome {
            Ok(files) => {
                if tasks
                    .send(Task::DiagnosticsReady { revision, files })
                    .is_err()
                {
                    return;
                }
            }
            Err(super::Failure::Cancelled) => {}
            Err(failure) => {
                // A panic may have left the cache half updated.
                cache = Converted::default();
                let _ = to_client.send(ToClient::Log {
                    kind: MessageType::ERROR,
                    message: format!("cannot compute diagnostics: {failure}"),
                });
            }
        }
    }
}

/// The LSP diagnostics of each file as last converted, and what they were converted from.
#[derive(Default)]
struct Converted {
    /// What the conversions depend on besides the files: the URIs (open documents keep the
    /// URI the client named them by) and the encoding.
    names: Option<Names>,
    files: HashMap<String, CachedFile>,
}

#[derive(Clone)]
struct Names {
    uris: super::state::UriKey,
    encoding: higraph_analysis::PositionEncoding,
}

impl Names {
    fn same(&self, other: &Names) -> bool {
        self.uris.same(&other.uris) && self.encoding == other.encoding
    }
}

struct CachedFile {
    /// The analysis' diagnostics of the file.
    diagnostics: Vec<higraph_analysis::Diagnostic>,
    /// The contents of the files they were converted against: the file itself and every file
    /// a related location points into.
    inputs: Vec<(FileId, Arc<FileContents>)>,
    converted: FileDiagnostics,
}

impl Converted {
    /// The diagnostics of every file of the workspace by workspace path, as LSP diagnostics
    /// sorted like `check --format json` sorts them (`diagnostics.md` §4.4).
    fn publishable(
        &mut self,
        snapshot: &Snapshot,
    ) -> HandlerResult<Vec<(String, FileDiagnostics)>> {
        let analysis = &snapshot.analysis;
        let diagnostics = analysis.diagnostics_cancellable()?;
        let files = analysis.files();
        let names = Names {
            uris: snapshot.uri_key(),
            encoding: snapshot.encoding,
        };
        if !self.names.as_ref().is_some_and(|old| old.same(&names)) {
            self.files.clear();
            self.names = Some(names);
        }
        let mut result = Vec::with_capacity(diagnostics.len());
        for (file, diagnostics) in diagnostics {
            let Some(output) = files.get(file.0 as usize) else {
                continue;
            };
            let mut ids: Vec<FileId> = std::iter::once(file)
                .chain(
                    diagnostics
                        .iter()
                        .flat_map(|d| d.related.iter().map(|r| r.file)),
                )
                .collect();
            ids.sort_unstable();
            ids.dedup();
            let inputs: Vec<(FileId, Arc<FileContents>)> = ids
                .into_iter()
                .filter_map(|id| Some((id, files.get(id.0 as usize)?.contents.clone())))
                .collect();
            let cached = self.files.get(&output.path).filter(|cached| {
                cached.diagnostics == diagnostics
                    && cached.inputs.len() == inputs.len()
                    && cached
                        .inputs
                        .iter()
                        .zip(&inputs)
                        .all(|((a, x), (b, y))| a == b && Arc::ptr_eq(x, y))
            });
            let converted = match cached {
                Some(cached) => cached.converted.clone(),
                None => {
                    let converted = Arc::new(convert_file(
                        snapshot,
                        file,
                        &output.path,
                        &diagnostics,
                        &files,
                    ));
                    self.files.insert(
                        output.path.clone(),
                        CachedFile {
                            diagnostics,
                            inputs,
                            converted: converted.clone(),
                        },
                    );
                    converted
                }
            };
            result.push((output.path.clone(), converted));
        }
        // Forget the files that are gone.
        if self.files.len() > result.len() {
            let current: std::collections::HashSet<&str> =
                result.iter().map(|(path, _)| path.as_str()).collect();
            self.files.retain(|path, _| current.contains(path.as_str()));
        }
        Ok(result)
    }
}

/// The LSP diagnostics of one file, sorted like `check --format json` sorts them.
fn convert_file(
    snapshot: &Snapshot,
    file: FileId,
    path: &str,
    diagnostics: &[higraph_analysis::Diagnostic],
    files: &[higraph_analysis::OutputFile],
) -> Vec<lsp::Diagnostic> {
    if diagnostics.is_empty() {
        return Vec::new();
    }
    let Some(index) = snapshot.line_index(path) else {
        return Vec::new();
    };
    let encoding = snapshot.encoding;
    let location = |other: FileId, range: TextRange| {
        let path = if other == file {
            path
        } else {
            &files.get(other.0 as usize)?.path
        };
        let index = snapshot.line_index(path)?;
        Some(lsp::Location::new(
            snapshot.uri(path)?,
            convert::range(&index, range, encoding),
        ))
    };
    let mut converted: Vec<lsp::Diagnostic> = diagnostics
        .iter()
        .map(|diagnostic| {
            let mut converted = convert::diagnostic(diagnostic, &index, encoding, location);
            if snapshot.support.code_description {
                converted.code_description = snapshot
                    .rule_page(diagnostic.code.as_str())
                    .map(|href| lsp::CodeDescription { href });
            }
            converted
        })
        .collect();
    converted.sort_by(|a, b| {
        let key = |d: &lsp::Diagnostic| {
            let code = match &d.code {
                Some(lsp::NumberOrString::String(code)) => code.clone(),
                _ => String::new(),
            };
            (d.range.start, d.range.end, code, d.message.clone())
        };
        key(a).cmp(&key(b))
    });
    converted
}

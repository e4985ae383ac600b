//! The language server (`tooling.md` §4): LSP 3.17 over stdin/stdout on tower-lsp-server and
//! tokio.
//!
//! * [`transport`] reads and writes the JSON-RPC frames and keeps the server alive whatever
//!   arrives;
//! * [`Backend`] implements tower-lsp-server's `LanguageServer`: notifications become
//!   [`Task`]s for the [`state`] thread that owns the analysis; requests take a
//!   [`Snapshot`](state::Snapshot) and run their [`handlers`] function on a blocking thread;
//! * [`convert`] translates between analysis and LSP types, [`capabilities`] says what the
//!   server offers, [`vfs`] maps URIs to workspace paths and holds the open documents.
//!
//! No analysis happens here: every answer comes from `higraph_analysis`.

mod build;
mod capabilities;
mod convert;
mod diagnostics;
mod handlers;
mod lens_table;
mod pull;
mod rule_pages;
mod state;
mod testing;
mod token_delta;
mod transport;
mod vfs;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use tokio::sync::mpsc;
use tower_lsp_server::jsonrpc::{self, ErrorCode};
use tower_lsp_server::ls_types::{
    self as lsp, DidChangeConfigurationParams, DidChangeTextDocumentParams,
    DidChangeWatchedFilesParams, DidCloseTextDocumentParams, DidOpenTextDocumentParams,
    DidSaveTextDocumentParams, InitializeParams, InitializeResult, InitializedParams, MessageType,
};
use tower_lsp_server::{Client, LanguageServer, LspService};

use capabilities::ClientSupport;
use handlers::{HandlerError, HandlerResult};
use state::{IndexProgress, Snapshot, Task, ToClient, WorldHandle};

/// Runs the language server on stdin/stdout until `exit` (or the end of the input). The exit
/// status is 0 after `shutdown` then `exit`, else 1 (LSP 3.17, `exit`).
pub fn run() -> ExitCode {
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_name("higraph-lsp")
        // The request workers plus a few for reading stdin and writing stdout (tokio's
        // default allows 512 blocking threads).
        .max_blocking_threads(request_workers() + 4)
        // Also the blocking threads, where requests run (`spawn_blocking`).
        .thread_stack_size(crate::ANALYSIS_STACK_SIZE)
        .build()
    {
        Ok(runtime) => runtime,
        Err(error) => {
            eprintln!("error: cannot start the language server: {error}");
            return ExitCode::from(1);
        }
    };
    let clean = runtime.block_on(serve_stdio());
    // Threads still analysing a snapshot are not waited for.
    runtime.shutdown_background();
    if clean {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Serves stdin/stdout; `true` if the client sent `shutdown` and then `exit`.
async fn serve_stdio() -> bool {
    let (to_client, outbox) = mpsc::unbounded_channel();
    let world = WorldHandle::spawn(to_client);
    let shut_down = Arc::new(AtomicBool::new(false));
    let (service, socket) = LspService::build(|client| Backend {
        client,
        world,
        support: OnceLock::new(),
        shut_down: shut_down.clone(),
        workers: Arc::new(tokio::sync::Semaphore::new(request_workers())),
    })
    .custom_method("higraph/render", Backend::render)
    .custom_method("higraph/simulate", Backend::simulate)
    .custom_method("higraph/tests", Backend::tests)
    .finish();
    let client = service.inner().client.clone();
    tokio::spawn(talk_to_client(client.clone(), outbox));
    let ending = transport::serve(
        tokio::io::stdin(),
        tokio::io::stdout(),
        service,
        socket,
        client,
    )
    .await;
    ending == transport::Ending::Exit && shut_down.load(Ordering::SeqCst)
}

/// Sends what the analysis thread has for the client, in order.
async fn talk_to_client(client: Client, mut outbox: mpsc::UnboundedReceiver<ToClient>) {
    while let Some(message) = outbox.recv().await {
        match message {
            ToClient::Publish {
                uri,
                diagnostics,
                version,
            } => client.publish_diagnostics(uri, diagnostics, version).await,
            ToClient::Log { kind, message } => client.log_message(kind, message).await,
            ToClient::Barrier(done) => {
                let _ = done.send(());
            }
            ToClient::RefreshDiagnostics => {
                // Not awaited, like the code lens refresh.
                let client = client.clone();
                tokio::spawn(async move {
                    let _ = client.workspace_diagnostic_refresh().await;
                });
            }
            ToClient::RefreshCodeLenses => {
                // Not awaited: the client answers when it likes, and a failure only means
                // the lenses show the old result until the next edit.
                let client = client.clone();
                tokio::spawn(async move {
                    let _ = client.code_lens_refresh().await;
                });
            }
        }
    }
}

/// The tower-lsp-server backend: converts notifications to tasks and runs requests on
/// snapshots.
pub(crate) struct Backend {
    client: Client,
    world: WorldHandle,
    /// What the client supports (set by `initialize`).
    support: OnceLock<ClientSupport>,
    /// Set by `shutdown`: a following `exit` ends with status 0.
    shut_down: Arc<AtomicBool>,
    /// Permits to run a request's computation on a blocking thread (see [`request_workers`]).
    workers: Arc<tokio::sync::Semaphore>,
}

/// How many requests compute at once: twice the processors, at least 4, at most 32.
///
/// Without a bound every request in a burst got a blocking thread of its own (tokio allows
/// 512), and each thread kept its stack, its allocator arena and salsa's per-thread state
/// alive while the pool kept it: memory rose with every burst until the pool was full
/// (`scripts/server-rss.py`, 75 000 requests on the drilling example, debug build: 406
/// threads and 25 → 64 MB; bounded: 13 threads and 22 → 41 MB, flat after the first
/// 5 000, the rest being the analysis' memoized results). A request waiting for a permit
/// costs only its snapshot.
fn request_workers() -> usize {
    let processors = std::thread::available_parallelism().map_or(2, |n| n.get());
    (processors * 2).clamp(4, 32)
}

impl Backend {
    /// The custom request `higraph/render`: `{ "name": … }` → `{ "svg": … }`.
    async fn render(
        &self,
        params: handlers::RenderParams,
    ) -> jsonrpc::Result<handlers::RenderResult> {
        self.answer("higraph/render", params, handlers::render)
            .await
    }

    /// The custom request `higraph/simulate`: `{ "name", "uri"? }` → the JSON trace of a run.
    async fn simulate(&self, params: testing::TestParams) -> jsonrpc::Result<serde_json::Value> {
        self.answer("higraph/simulate", params, testing::simulate)
            .await
    }

    /// The custom request `higraph/tests`: every test of the workspace.
    async fn tests(&self, params: Option<serde_json::Value>) -> jsonrpc::Result<testing::TestList> {
        self.answer("higraph/tests", params, testing::list).await
    }

    /// `workspace/executeCommand` `higraph.build` with no argument (or `null`) or one
    /// `{"kind", "name"}`: builds on a blocking thread, answers the summary and logs it.
    async fn build(
        &self,
        arguments: Vec<serde_json::Value>,
    ) -> jsonrpc::Result<Option<lsp::LSPAny>> {
        let params = match arguments.into_iter().next() {
            None | Some(serde_json::Value::Null) => None,
            Some(argument) => match serde_json::from_value::<build::BuildParams>(argument) {
                Ok(params) => Some(params),
                Err(_) => {
                    return Err(rpc_error(
                        ErrorCode::InvalidParams,
                        format!(
                            "{} takes no argument or one {{\"kind\": \"group\"|\"chart\", \
                             \"name\": NAME}}",
                            build::BUILD
                        ),
                    ));
                }
            },
        };
        let answer = self.answer(build::BUILD, params, build::build).await?;
        let kind = if answer.refused {
            MessageType::WARNING
        } else {
            MessageType::INFO
        };
        self.client
            .log_message(kind, format!("{}: {}", build::BUILD, answer.message))
            .await;
        serde_json::to_value(&answer)
            .map(Some)
            .map_err(|error| rpc_error(ErrorCode::InternalError, error.to_string()))
    }

    fn support(&self) -> ClientSupport {
        self.support.get().copied().unwrap_or_default()
    }

    /// Answers a request: takes a snapshot that reflects every notification before the
    /// request, runs `handler` on a blocking thread and maps its failures to JSON-RPC errors
    /// (`ContentModified` when an edit cancelled it, `InternalError` plus a log message when
    /// it panicked).
    async fn answer<P, R>(
        &self,
        method: &'static str,
        params: P,
        handler: fn(&Snapshot, P) -> HandlerResult<R>,
    ) -> jsonrpc::Result<R>
    where
        P: Send + 'static,
        R: Send + 'static,
    {
        let Some(snapshot) = self.world.snapshot().await else {
            return Err(rpc_error(
                ErrorCode::InternalError,
                "the analysis has stopped".into(),
            ));
        };
        // tower-lsp-server drops this future when the client cancels the request: the guard
        // then tells the blocking work, which cannot be aborted, to stop (before it starts,
        // and at the check points of long computations).
        let _cancel_on_drop = CancelOnDrop(
            snapshot.cancel_flag(),
            snapshot.analysis.cancellation_token(),
        );
        // At most `workers` requests compute at once; the others wait here, holding only
        // their snapshot (see `request_workers`).
        let Ok(permit) = self.workers.clone().acquire_owned().await else {
            return Err(rpc_error(
                ErrorCode::InternalError,
                "the request workers have stopped".into(),
            ));
        };
        let outcome = tokio::task::spawn_blocking(move || {
            let _permit = permit;
            catch(|| {
                if snapshot.is_cancelled() {
                    return Err(HandlerError::Cancelled);
                }
                handler(&snapshot, params)
            })
        })
        .await;
        let failure = match outcome {
            Ok(Ok(value)) => return Ok(value),
            Ok(Err(failure)) => failure,
            Err(join_error) => Failure::Panicked(join_error.to_string()),
        };
        let error = failure_error(method, &failure);
        if let Failure::Panicked(_) = failure {
            self.client
                .log_message(MessageType::ERROR, error.message.clone())
                .await;
        }
        Err(error)
    }
}

/// Cancels a request's computation when dropped: when the request's future is dropped
/// before it completes (a cancelled request), and harmlessly after it completed. Sets the
/// snapshot's flag (for computations outside salsa, such as formatting) and cancels its salsa
/// queries, which then unwind at their next step.
struct CancelOnDrop(Arc<AtomicBool>, salsa::CancellationToken);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
        self.1.cancel();
    }
}

/// The error response for a request that gave no result: `ContentModified` when an edit
/// cancelled it, `RequestFailed` with the handler's reason, `InternalError` for a panic.
fn failure_error(method: &str, failure: &Failure) -> jsonrpc::Error {
    match failure {
        Failure::Cancelled => rpc_error(
            ErrorCode::ContentModified,
            "the workspace changed while the request ran".into(),
        ),
        Failure::Failed(message) => rpc_error(REQUEST_FAILED, message.clone()),
        Failure::Panicked(message) => rpc_error(
            ErrorCode::InternalError,
            format!("internal error in {method}: {message}"),
        ),
    }
}

/// LSP's `RequestFailed`: the request was valid but could not be carried out.
const REQUEST_FAILED: ErrorCode = ErrorCode::ServerError(-32803);

fn rpc_error(code: ErrorCode, message: String) -> jsonrpc::Error {
    jsonrpc::Error {
        code,
        message: message.into(),
        data: None,
    }
}

/// The folder the client opened: the first workspace folder, else the root URI, else the
/// (deprecated) root path.
#[allow(deprecated)]
fn client_root(params: &InitializeParams) -> Option<PathBuf> {
    let folder = params
        .workspace_folders
        .as_ref()
        .and_then(|folders| folders.first())
        .map(|folder| &folder.uri)
        .or(params.root_uri.as_ref())
        .and_then(vfs::PathMap::file_path);
    folder.or_else(|| params.root_path.as_ref().map(PathBuf::from))
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: InitializeParams) -> jsonrpc::Result<InitializeResult> {
        let support = ClientSupport::new(&params.capabilities);
        let _ = self.support.set(support);
        let code_lens_refresh = params
            .capabilities
            .workspace
            .as_ref()
            .and_then(|workspace| workspace.code_lens.as_ref())
            .and_then(|code_lens| code_lens.refresh_support)
            .unwrap_or(false);
        self.world.send(Task::Initialize {
            root: client_root(&params),
            support,
            code_lens_refresh,
            rules_base: rule_pages::option(params.initialization_options.as_ref()),
        });
        Ok(InitializeResult {
            capabilities: capabilities::server_capabilities(&support),
            server_info: Some(lsp::ServerInfo {
                name: "higraph-lsp".into(),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            }),
            offset_encoding: None,
        })
    }

    async fn initialized(&self, _: InitializedParams) {
        // Queued first, so every later notification applies to the loaded workspace.
        let (progress_tx, mut progress) = mpsc::unbounded_channel();
        self.world.send(Task::Index {
            progress: progress_tx,
        });
        let support = self.support();
        if support.watched_files_registration {
            let client = self.client.clone();
            tokio::spawn(async move {
                let registration = lsp::Registration {
                    id: "higraph-watched-files".into(),
                    method: "workspace/didChangeWatchedFiles".into(),
                    register_options: serde_json::to_value(capabilities::file_watchers()).ok(),
                };
                if let Err(error) = client.register_capability(vec![registration]).await {
                    client
                        .log_message(
                            MessageType::WARNING,
                            format!("cannot watch the workspace's files: {}", error.message),
                        )
                        .await;
                }
            });
        }
        let token = lsp::NumberOrString::String("higraph/indexing".into());
        let mut report = if support.work_done_progress
            && self
                .client
                .create_work_done_progress(token.clone())
                .await
                .is_ok()
        {
            Some(
                self.client
                    .progress(token, "Indexing HiGraph workspace")
                    .with_percentage(0)
                    .begin()
                    .await,
            )
        } else {
            None
        };
        while let Some(event) = progress.recv().await {
            match event {
                IndexProgress::Report {
                    message,
                    percentage,
                } => {
                    if let Some(ongoing) = &report {
                        ongoing.report_with_message(message, percentage).await;
                    }
                }
                IndexProgress::Done { message, published } => {
                    let _ = published.await;
                    if let Some(ongoing) = report.take() {
                        ongoing.finish_with_message(message).await;
                    }
                    break;
                }
            }
        }
        if let Some(ongoing) = report {
            ongoing.finish().await;
        }
    }

    async fn shutdown(&self) -> jsonrpc::Result<()> {
        self.shut_down.store(true, Ordering::SeqCst);
        Ok(())
    }

    async fn did_open(&self, params: DidOpenTextDocumentParams) {
        let document = params.text_document;
        self.world.send(Task::Open {
            uri: document.uri,
            version: document.version,
            language_id: document.language_id,
            text: document.text,
        });
    }

    async fn did_change(&self, params: DidChangeTextDocumentParams) {
        self.world.send(Task::Change {
            uri: params.text_document.uri,
            version: params.text_document.version,
            changes: params.content_changes,
        });
    }

    async fn did_close(&self, params: DidCloseTextDocumentParams) {
        self.world.send(Task::Close {
            uri: params.text_document.uri,
        });
    }

    async fn did_save(&self, params: DidSaveTextDocumentParams) {
        self.world.send(Task::Save {
            uri: params.text_document.uri,
        });
    }

    async fn did_change_watched_files(&self, params: DidChangeWatchedFilesParams) {
        self.world.send(Task::WatchedFiles {
            changes: params.changes,
        });
    }

    async fn did_change_configuration(&self, _: DidChangeConfigurationParams) {
        // The server has no client-side settings; `higraph.toml` may have changed meanwhile.
        self.world.send(Task::Reload);
    }

    async fn diagnostic(
        &self,
        params: lsp::DocumentDiagnosticParams,
    ) -> jsonrpc::Result<lsp::DocumentDiagnosticReportResult> {
        match self
            .world
            .pull(pull::Request::Document {
                uri: params.text_document.uri,
                previous: params.previous_result_id,
            })
            .await
        {
            Some(pull::Answer::Document(report)) => Ok(report),
            _ => Err(rpc_error(
                ErrorCode::InternalError,
                "the analysis has stopped".into(),
            )),
        }
    }

    async fn workspace_diagnostic(
        &self,
        params: lsp::WorkspaceDiagnosticParams,
    ) -> jsonrpc::Result<lsp::WorkspaceDiagnosticReportResult> {
        match self
            .world
            .pull(pull::Request::Workspace {
                previous: params.previous_result_ids,
            })
            .await
        {
            Some(pull::Answer::Workspace(report)) => Ok(report),
            _ => Err(rpc_error(
                ErrorCode::InternalError,
                "the analysis has stopped".into(),
            )),
        }
    }

    async fn hover(&self, params: lsp::HoverParams) -> jsonrpc::Result<Option<lsp::Hover>> {
        self.answer("hover", params, handlers::hover).await
    }

    async fn completion(
        &self,
        params: lsp::CompletionParams,
    ) -> jsonrpc::Result<Option<lsp::CompletionResponse>> {
        self.answer("completion", params, handlers::completion)
            .await
    }

    async fn signature_help(
        &self,
        params: lsp::SignatureHelpParams,
    ) -> jsonrpc::Result<Option<lsp::SignatureHelp>> {
        self.answer("signatureHelp", params, handlers::signature_help)
            .await
    }

    async fn goto_definition(
        &self,
        params: lsp::GotoDefinitionParams,
    ) -> jsonrpc::Result<Option<lsp::GotoDefinitionResponse>> {
        self.answer("definition", params, handlers::goto_definition)
            .await
    }

    async fn references(
        &self,
        params: lsp::ReferenceParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::Location>>> {
        self.answer("references", params, handlers::references)
            .await
    }

    async fn document_highlight(
        &self,
        params: lsp::DocumentHighlightParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::DocumentHighlight>>> {
        self.answer("documentHighlight", params, handlers::document_highlight)
            .await
    }

    async fn prepare_rename(
        &self,
        params: lsp::TextDocumentPositionParams,
    ) -> jsonrpc::Result<Option<lsp::PrepareRenameResponse>> {
        self.answer("prepareRename", params, handlers::prepare_rename)
            .await
    }

    async fn rename(
        &self,
        params: lsp::RenameParams,
    ) -> jsonrpc::Result<Option<lsp::WorkspaceEdit>> {
        self.answer("rename", params, handlers::rename).await
    }

    async fn document_symbol(
        &self,
        params: lsp::DocumentSymbolParams,
    ) -> jsonrpc::Result<Option<lsp::DocumentSymbolResponse>> {
        self.answer("documentSymbol", params, handlers::document_symbol)
            .await
    }

    async fn symbol(
        &self,
        params: lsp::WorkspaceSymbolParams,
    ) -> jsonrpc::Result<Option<lsp::WorkspaceSymbolResponse>> {
        self.answer("workspace/symbol", params, handlers::workspace_symbol)
            .await
    }

    async fn folding_range(
        &self,
        params: lsp::FoldingRangeParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::FoldingRange>>> {
        self.answer("foldingRange", params, handlers::folding_range)
            .await
    }

    async fn document_link(
        &self,
        params: lsp::DocumentLinkParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::DocumentLink>>> {
        self.answer("documentLink", params, handlers::document_link)
            .await
    }

    async fn prepare_call_hierarchy(
        &self,
        params: lsp::CallHierarchyPrepareParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::CallHierarchyItem>>> {
        self.answer(
            "prepareCallHierarchy",
            params,
            handlers::prepare_call_hierarchy,
        )
        .await
    }

    async fn incoming_calls(
        &self,
        params: lsp::CallHierarchyIncomingCallsParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::CallHierarchyIncomingCall>>> {
        self.answer(
            "callHierarchy/incomingCalls",
            params,
            handlers::incoming_calls,
        )
        .await
    }

    async fn outgoing_calls(
        &self,
        params: lsp::CallHierarchyOutgoingCallsParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::CallHierarchyOutgoingCall>>> {
        self.answer(
            "callHierarchy/outgoingCalls",
            params,
            handlers::outgoing_calls,
        )
        .await
    }

    async fn selection_range(
        &self,
        params: lsp::SelectionRangeParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::SelectionRange>>> {
        self.answer("selectionRange", params, handlers::selection_range)
            .await
    }

    async fn semantic_tokens_full(
        &self,
        params: lsp::SemanticTokensParams,
    ) -> jsonrpc::Result<Option<lsp::SemanticTokensResult>> {
        self.answer(
            "semanticTokens/full",
            params,
            handlers::semantic_tokens_full,
        )
        .await
    }

    async fn semantic_tokens_full_delta(
        &self,
        params: lsp::SemanticTokensDeltaParams,
    ) -> jsonrpc::Result<Option<lsp::SemanticTokensFullDeltaResult>> {
        self.answer(
            "semanticTokens/full/delta",
            params,
            handlers::semantic_tokens_full_delta,
        )
        .await
    }

    async fn semantic_tokens_range(
        &self,
        params: lsp::SemanticTokensRangeParams,
    ) -> jsonrpc::Result<Option<lsp::SemanticTokensRangeResult>> {
        self.answer(
            "semanticTokens/range",
            params,
            handlers::semantic_tokens_range,
        )
        .await
    }

    async fn inlay_hint(
        &self,
        params: lsp::InlayHintParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::InlayHint>>> {
        self.answer("inlayHint", params, handlers::inlay_hint).await
    }

    async fn code_action(
        &self,
        params: lsp::CodeActionParams,
    ) -> jsonrpc::Result<Option<lsp::CodeActionResponse>> {
        self.answer("codeAction", params, handlers::code_action)
            .await
    }

    async fn code_action_resolve(
        &self,
        params: lsp::CodeAction,
    ) -> jsonrpc::Result<lsp::CodeAction> {
        self.answer("codeAction/resolve", params, handlers::code_action_resolve)
            .await
    }

    async fn code_lens(
        &self,
        params: lsp::CodeLensParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::CodeLens>>> {
        self.answer("codeLens", params, handlers::code_lens).await
    }

    async fn code_lens_resolve(&self, params: lsp::CodeLens) -> jsonrpc::Result<lsp::CodeLens> {
        self.answer("codeLens/resolve", params, handlers::code_lens_resolve)
            .await
    }

    /// `higraph.runTest`: runs a test and answers its `--format json` object; the world
    /// keeps the result for the lens and publishes the failures. `higraph.build`: builds and
    /// writes the files (`build.rs`).
    async fn execute_command(
        &self,
        params: lsp::ExecuteCommandParams,
    ) -> jsonrpc::Result<Option<lsp::LSPAny>> {
        if params.command == build::BUILD {
            return self.build(params.arguments).await;
        }
        if params.command != testing::RUN_TEST {
            return Err(rpc_error(
                ErrorCode::InvalidParams,
                format!(
                    "unknown command '{}'; the server executes only {} and {}",
                    params.command,
                    testing::RUN_TEST,
                    build::BUILD
                ),
            ));
        }
        let argument = params
            .arguments
            .into_iter()
            .next()
            .and_then(|argument| serde_json::from_value::<testing::TestParams>(argument).ok())
            .filter(|argument| argument.uri.is_some());
        let Some(argument) = argument else {
            return Err(rpc_error(
                ErrorCode::InvalidParams,
                format!(
                    "{} takes one argument {{\"uri\": URI, \"name\": NAME}}",
                    testing::RUN_TEST
                ),
            ));
        };
        let outcome = self
            .answer(testing::RUN_TEST, argument, testing::run_test)
            .await?;
        self.world.send(Task::TestRan {
            generation: outcome.generation,
            key: outcome.key,
            record: outcome.record,
        });
        Ok(Some(outcome.json))
    }

    async fn formatting(
        &self,
        params: lsp::DocumentFormattingParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::TextEdit>>> {
        self.answer("formatting", params, handlers::formatting)
            .await
    }

    async fn range_formatting(
        &self,
        params: lsp::DocumentRangeFormattingParams,
    ) -> jsonrpc::Result<Option<Vec<lsp::TextEdit>>> {
        self.answer("rangeFormatting", params, handlers::range_formatting)
            .await
    }
}

/// Why a request or computation on a snapshot gave no result.
#[derive(Debug)]
pub(crate) enum Failure {
    /// An edit cancelled the snapshot.
    Cancelled,
    /// The handler refused, with a message for the user.
    Failed(String),
    /// The handler panicked (a bug), with the panic message.
    Panicked(String),
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Cancelled => f.write_str("cancelled by an edit"),
            Failure::Failed(message) | Failure::Panicked(message) => f.write_str(message),
        }
    }
}

/// Runs a handler, turning salsa's cancellation (returned or unwound) into
/// [`Failure::Cancelled`] and any other panic into [`Failure::Panicked`].
pub(crate) fn catch<T>(handler: impl FnOnce() -> HandlerResult<T>) -> Result<T, Failure> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(handler)) {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(HandlerError::Cancelled)) => Err(Failure::Cancelled),
        Ok(Err(HandlerError::Failed(message))) => Err(Failure::Failed(message)),
        Err(payload) if payload.is::<salsa::Cancelled>() => Err(Failure::Cancelled),
        Err(payload) => Err(Failure::Panicked(panic_message(payload.as_ref()))),
    }
}

/// The message of a panic payload.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(message) = payload.downcast_ref::<&str>() {
        (*message).to_owned()
    } else if let Some(message) = payload.downcast_ref::<String>() {
        message.clone()
    } else {
        "a panic without a message".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

    use super::*;

    fn host() -> AnalysisHost {
        let mut host = AnalysisHost::new();
        host.load(WorkspaceData {
            files: vec![(
                "a.higraph".into(),
                FileContents::Text("graph A <\n  state 0 < >\n>\n".into()),
            )],
            ..WorkspaceData::default()
        });
        host
    }

    #[test]
    fn an_edit_cancels_a_running_request_which_answers_content_modified() {
        let mut host = host();
        let analysis = host.analysis();
        let (started, running) = std::sync::mpsc::channel();
        let request = std::thread::spawn(move || {
            catch::<()>(|| {
                let _ = started.send(());
                // A request that runs until the workspace changes.
                loop {
                    analysis.diagnostics_cancellable()?;
                }
            })
        });
        running.recv().expect("the request runs");
        // The write cancels the snapshot and waits until the request has dropped it.
        host.set_file_contents("a.higraph", FileContents::Text("graph B <\n>\n".into()));
        let failure = request
            .join()
            .expect("the request thread ends")
            .expect_err("cancelled");
        assert!(matches!(failure, Failure::Cancelled), "{failure:?}");
        assert_eq!(
            failure_error("hover", &failure).code,
            ErrorCode::ContentModified
        );
    }

    #[test]
    fn a_cancelled_request_stops_its_running_queries_and_only_its_own() {
        let host = host();
        let analysis = host.analysis();
        let other = host.analysis();
        let token = analysis.cancellation_token();
        let (started, running) = std::sync::mpsc::channel();
        let request = std::thread::spawn(move || {
            catch::<()>(|| {
                let _ = started.send(());
                // A request that runs until it is cancelled. Once the diagnostics are memoised
                // the query itself may not look at the token again, so each round also asks
                // explicitly, as long-running handlers do between steps.
                loop {
                    analysis.diagnostics_cancellable()?;
                    analysis.check_cancelled(&|| false)?;
                }
            })
        });
        running.recv().expect("the request runs");
        // What `CancelOnDrop` does when the client cancels the request. A cancellation that
        // lands between two queries of the loop may be consumed without stopping it (the
        // token cancels what runs), so it is repeated until the request has stopped.
        while !request.is_finished() {
            token.cancel();
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let failure = request
            .join()
            .expect("the request thread ends")
            .expect_err("cancelled");
        assert!(matches!(failure, Failure::Cancelled), "{failure:?}");
        assert!(other.diagnostics_cancellable().is_ok());
    }

    #[test]
    fn a_panicking_handler_becomes_an_internal_error_and_a_refusal_a_request_failure() {
        let failure = catch::<()>(|| panic!("boom")).expect_err("a panic");
        let error = failure_error("hover", &failure);
        assert_eq!(error.code, ErrorCode::InternalError);
        assert_eq!(error.message, "internal error in hover: boom");
        let refused = catch::<()>(|| Err(HandlerError::Failed("no".into()))).expect_err("refused");
        let error = failure_error("rename", &refused);
        assert_eq!((error.code.code(), error.message.as_ref()), (-32803, "no"));
    }
}

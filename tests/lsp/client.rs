//! A small JSON-RPC client that drives the real `higraph-lsp` binary over stdio, as an editor
//! would: `Content-Length` framing, requests with ids matched to their responses,
//! notifications collected as they arrive, and automatic answers to the server's own requests
//! (`window/workDoneProgress/create`, `client/registerCapability`).

use std::collections::{HashMap, VecDeque};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// How long to wait for anything the server should send.
pub const TIMEOUT: Duration = Duration::from_secs(60);

/// The binary under test.
pub fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_higraph-lsp")
}

/// The repository root.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A temporary workspace folder.
pub struct TempTree {
    dir: tempfile::TempDir,
}

impl TempTree {
    pub fn new() -> TempTree {
        TempTree {
            dir: tempfile::tempdir().expect("a temporary folder"),
        }
    }

    /// Creates `relative` (and its folders) with `contents`.
    pub fn file(&self, relative: &str, contents: impl AsRef<[u8]>) -> &TempTree {
        let path = self.path().join(relative);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create folders");
        }
        std::fs::write(&path, contents).expect("write file");
        self
    }

    /// The canonical root (so URIs match the server's).
    pub fn path(&self) -> PathBuf {
        std::fs::canonicalize(self.dir.path()).expect("canonical temporary folder")
    }

    /// The `file:` URI of a workspace path.
    pub fn uri(&self, relative: &str) -> String {
        file_uri(&self.path().join(relative))
    }

    /// Does `higraph-lsp fmt --check` find every file of the tree formatted?
    pub fn fmt_check(&self) -> bool {
        Command::new(binary())
            .args(["fmt", "--check", "."])
            .current_dir(self.path())
            .output()
            .expect("the binary runs")
            .status
            .success()
    }

    /// Runs `higraph-lsp check --format json` in the tree.
    pub fn check_json(&self) -> Value {
        let output = Command::new(binary())
            .args(["check", "--format", "json"])
            .current_dir(self.path())
            .output()
            .expect("the binary runs");
        serde_json::from_slice(&output.stdout).unwrap_or_else(|error| {
            panic!(
                "check printed no JSON ({error}): {}",
                String::from_utf8_lossy(&output.stderr)
            )
        })
    }
}

/// The `file:` URI of an absolute path (percent-encoding what a URI path cannot hold).
pub fn file_uri(path: &Path) -> String {
    let mut uri = String::from("file://");
    for byte in path.to_string_lossy().bytes() {
        match byte {
            b'a'..=b'z' | b'A'..=b'Z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                uri.push(byte as char)
            }
            _ => uri.push_str(&format!("%{byte:02X}")),
        }
    }
    uri
}

/// A running server.
pub struct Server {
    child: Child,
    stdin: Arc<Mutex<Option<ChildStdin>>>,
    incoming: Receiver<Value>,
    /// Notifications that arrived while waiting for something else, in order.
    pub notifications: VecDeque<Value>,
    /// Responses that arrived while waiting for another one.
    responses: HashMap<String, Value>,
    next_id: i64,
    /// The latest published diagnostics per URI.
    pub diagnostics: HashMap<String, Vec<Value>>,
    /// Every `publishDiagnostics` in arrival order: (uri, version).
    pub publications: Vec<(String, Option<i64>)>,
    /// The server's requests to the client (already answered), in order.
    pub server_requests: Vec<Value>,
    /// Error responses with a `null` id (answers to unreadable messages), in order.
    pub null_id_errors: Vec<Value>,
    /// Ids that were answered more than once.
    pub answered_twice: Vec<String>,
    answered: std::collections::HashSet<String>,
}

impl Server {
    /// Starts `higraph-lsp lsp --stdio` in `cwd`.
    pub fn start(cwd: &Path) -> Server {
        Server::start_with(cwd, &["lsp", "--stdio"])
    }

    /// Starts the binary with `args` in `cwd`.
    pub fn start_with(cwd: &Path, args: &[&str]) -> Server {
        let mut child = Command::new(binary())
            .args(args)
            .current_dir(cwd)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("the server starts");
        let stdin = Arc::new(Mutex::new(child.stdin.take()));
        let stdout = child.stdout.take().expect("stdout");
        let (tx, incoming) = mpsc::channel();
        let answer = stdin.clone();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                // The server's own requests get an empty success, as most editors answer.
                if message.get("method").is_some()
                    && let Some(id) = message.get("id")
                {
                    let reply = json!({"jsonrpc": "2.0", "id": id, "result": null});
                    if let Some(stdin) = answer.lock().expect("stdin lock").as_mut() {
                        let _ = write_message(stdin, &reply);
                    }
                }
                if tx.send(message).is_err() {
                    break;
                }
            }
        });
        Server {
            child,
            stdin,
            incoming,
            notifications: VecDeque::new(),
            responses: HashMap::new(),
            next_id: 1,
            diagnostics: HashMap::new(),
            publications: Vec::new(),
            server_requests: Vec::new(),
            null_id_errors: Vec::new(),
            answered_twice: Vec::new(),
            answered: std::collections::HashSet::new(),
        }
    }

    /// Starts a server on `root` and initializes it with `capabilities`; returns the
    /// `initialize` result.
    pub fn initialized(root: &Path, capabilities: Value) -> (Server, Value) {
        let mut server = Server::start(root);
        let result = server
            .request(
                "initialize",
                json!({
                    "processId": null,
                    "rootUri": file_uri(root),
                    "capabilities": capabilities,
                    "workspaceFolders": [{"uri": file_uri(root), "name": "ws"}],
                }),
            )
            .expect("initialize succeeds");
        server.notify("initialized", json!({}));
        (server, result)
    }

    /// Starts and initializes a server with progress support, and waits until the workspace
    /// is indexed (the end of the indexing progress).
    pub fn indexed(root: &Path) -> Server {
        let (mut server, _) =
            Server::initialized(root, json!({"window": {"workDoneProgress": true}}));
        server.wait_for_progress_end();
        server
    }

    /// The server's process id.
    #[allow(dead_code)] // used by tests/robustness.rs, not by tests/lsp.rs
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Sends raw bytes.
    pub fn send_raw(&mut self, bytes: &[u8]) {
        if let Some(stdin) = self.stdin.lock().expect("stdin lock").as_mut() {
            let _ = stdin.write_all(bytes);
            let _ = stdin.flush();
        }
    }

    /// Sends a message.
    pub fn send(&mut self, message: &Value) {
        if let Some(stdin) = self.stdin.lock().expect("stdin lock").as_mut() {
            let _ = write_message(stdin, message);
        }
    }

    /// Sends a notification.
    pub fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and returns its id (as sent).
    pub fn send_request(&mut self, method: &str, params: Value) -> Value {
        let id = json!(self.next_id);
        self.next_id += 1;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        id
    }

    /// Sends a request and waits for its response: `Ok(result)` or `Err(error)`.
    pub fn request(&mut self, method: &str, params: Value) -> Result<Value, Value> {
        let id = self.send_request(method, params);
        self.response(&id)
    }

    /// Waits for the response to the request `id`.
    pub fn response(&mut self, id: &Value) -> Result<Value, Value> {
        let key = id.to_string();
        let deadline = Instant::now() + TIMEOUT;
        loop {
            if let Some(response) = self.responses.remove(&key) {
                return match response.get("error") {
                    Some(error) => Err(error.clone()),
                    None => Ok(response.get("result").cloned().unwrap_or(Value::Null)),
                };
            }
            let message = self
                .next_message(deadline)
                .unwrap_or_else(|| panic!("no response to request {key}"));
            self.file(message);
        }
    }

    /// Waits until `count` error responses with a `null` id (answers to unreadable messages)
    /// have arrived.
    pub fn wait_for_null_id_errors(&mut self, count: usize) {
        let deadline = Instant::now() + TIMEOUT;
        while self.null_id_errors.len() < count {
            let message = self.next_message(deadline).unwrap_or_else(|| {
                panic!(
                    "{} of {count} null-id errors arrived: {:?}",
                    self.null_id_errors.len(),
                    self.null_id_errors
                )
            });
            self.file(message);
        }
    }

    /// Waits until a notification satisfies `matches` (earlier ones stay queued) and
    /// returns it.
    pub fn wait_for(&mut self, what: &str, matches: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + TIMEOUT;
        if let Some(at) = self.notifications.iter().position(&matches) {
            return self
                .notifications
                .remove(at)
                .expect("the found notification");
        }
        loop {
            let message = self
                .next_message(deadline)
                .unwrap_or_else(|| panic!("timed out waiting for {what}"));
            if message.get("id").is_none() && matches(&message) {
                self.record(&message);
                return message;
            }
            self.file(message);
        }
    }

    /// Waits for the end of the indexing progress.
    pub fn wait_for_progress_end(&mut self) {
        self.wait_for("the end of indexing", |m| {
            m["method"] == "$/progress" && m["params"]["value"]["kind"] == "end"
        });
    }

    /// Waits for diagnostics published for `uri` with `version`.
    pub fn wait_for_diagnostics(&mut self, uri: &str, version: i64) -> Vec<Value> {
        let message = self.wait_for(&format!("diagnostics of {uri} version {version}"), |m| {
            m["method"] == "textDocument/publishDiagnostics"
                && m["params"]["uri"] == uri
                && m["params"]["version"] == version
        });
        message["params"]["diagnostics"]
            .as_array()
            .cloned()
            .unwrap_or_default()
    }

    /// Reads whatever arrives within `quiet` (to collect late notifications).
    pub fn drain(&mut self, quiet: Duration) {
        while let Some(message) = self.next_message(Instant::now() + quiet) {
            self.file(message);
        }
    }

    /// `shutdown` then `exit`; returns the exit status.
    pub fn shutdown_and_exit(mut self) -> i32 {
        let result = self.request("shutdown", Value::Null);
        assert_eq!(result, Ok(Value::Null), "shutdown answers null");
        self.notify("exit", Value::Null);
        self.exit_status()
    }

    /// Waits for the process to end and returns its status.
    pub fn exit_status(mut self) -> i32 {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            if let Some(status) = self.child.try_wait().expect("the child's status") {
                return status.code().expect("an exit status, not a signal");
            }
            assert!(Instant::now() < deadline, "the server did not exit");
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Closes the server's input.
    pub fn close_stdin(&mut self) {
        self.stdin.lock().expect("stdin lock").take();
    }

    fn next_message(&mut self, deadline: Instant) -> Option<Value> {
        let left = deadline.saturating_duration_since(Instant::now());
        match self.incoming.recv_timeout(left) {
            Ok(message) => Some(message),
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => None,
        }
    }

    /// Files a message that is not what is being waited for.
    fn file(&mut self, message: Value) {
        if message.get("method").is_some() {
            if message.get("id").is_none() {
                self.record(&message);
                self.notifications.push_back(message);
            } else {
                self.server_requests.push(message);
            }
        } else if let Some(id) = message.get("id") {
            if id.is_null() {
                self.null_id_errors.push(message);
                return;
            }
            let key = id.to_string();
            if !self.answered.insert(key.clone()) {
                self.answered_twice.push(key.clone());
            }
            self.responses.insert(key, message);
        }
    }

    /// Keeps track of published diagnostics.
    fn record(&mut self, message: &Value) {
        if message["method"] == "textDocument/publishDiagnostics" {
            let uri = message["params"]["uri"]
                .as_str()
                .unwrap_or_default()
                .to_owned();
            let diagnostics = message["params"]["diagnostics"]
                .as_array()
                .cloned()
                .unwrap_or_default();
            self.publications
                .push((uri.clone(), message["params"]["version"].as_i64()));
            self.diagnostics.insert(uri, diagnostics);
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn write_message(out: &mut impl Write, message: &Value) -> std::io::Result<()> {
    let body = message.to_string();
    write!(out, "Content-Length: {}\r\n\r\n{}", body.len(), body)?;
    out.flush()
}

fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse::<usize>().ok();
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

/// A small deterministic pseudo-random generator (xorshift64*): the same session on every run.
pub struct Rng(pub u64);

impl Rng {
    pub fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) as usize % n.max(1)
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    pub fn chance(&mut self, percent: usize) -> bool {
        self.below(100) < percent
    }
}

//! Edit-to-diagnostics, completion and signature help latency of the language server on `max-graph`, measured
//! the way an editor sees it: over stdio, from writing a request to reading the answer.
//!
//! ```text
//! cargo build --release -p higraph-lsp
//! cargo run --release -p higraph-lsp --example latency [-- --iterations 100 --seed 1 --server PATH]
//! ```
//!
//! The example writes `higraph_workload::max_graph(seed)` (one 0.57 MB file, one graph with 255
//! states and 4090 transitions) to a temporary folder, starts the server binary (by default
//! `target/release/higraph-lsp`, honouring `CARGO_TARGET_DIR`), opens the file and waits for
//! indexing to end. Then, `iterations` times (after a few discarded warm-up rounds):
//!
//! 1. **edit → diagnostics**: a `didChange` that replaces one character of a transition late
//!    in the file — `UN` becomes `UX` (an unknown operation, so a new error) and back on the
//!    next round (the error goes away). The server publishes only diagnostics that changed, so
//!    every edit changes them; the time runs from writing the notification to reading the
//!    `publishDiagnostics` of the file, whose content is checked.
//! 2. **completion after the edit**: a completion request at the start of that operation's
//!    operand (the graph's variables are offered), sent right after the diagnostics arrived (the analysis is current, but queries only completion uses
//!    run for the first time in this revision).
//! 3. **completion, repeated**: the same request again (everything is cached).
//! 4. **signature help after the edit**: a `signatureHelp` request just inside the parameter
//!    list of the first `CALL … (` after the edited operation. `max-graph` itself declares no
//!    block interfaces (its CALLs are unchecked), so the benchmark adds a second file,
//!    [`BLOCKS`], declaring the interfaces of the three blocks it calls (with the types its
//!    actuals have: the workspace stays clean). The answer is checked to be a signature.
//! 5. **code lens after the edit**: `textDocument/codeLens` (the lenses, unresolved), then
//!    `codeLens/resolve` of the first state's incoming-transitions lens (its transitions in
//!    the edited graph; nothing before it in the round needs them).
//!
//! Then, with a second server started as a client that pulls diagnostics (LSP 3.17
//! `textDocument.diagnostic`, so nothing is pushed), the same edits:
//!
//! 6. **edit → pulled diagnostics**: the `didChange` followed at once by a
//!    `textDocument/diagnostic` with the previous result id; the time runs from writing the
//!    notification to reading the (full) report, whose content is checked.
//!
//! For comparison it then measures the analysis alone, in process, on the same edits: apply the
//! edit to an `AnalysisHost` and compute all diagnostics; completion at the same position. The
//! difference between the two is what the server adds (JSON-RPC, conversion, threads).

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use higraph_analysis::ide::FilePosition;
use higraph_analysis::{AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData};
use higraph_syntax::Edit;
use serde_json::{Value, json};

const FILE: &str = "max_graph.higraph";
/// The block interfaces of max-graph's CALLs, written next to it (see item 4 above).
const BLOCKS_FILE: &str = "blocks.higraph";
const BLOCKS: &str = "// The interfaces of the blocks max-graph calls (latency benchmark).
block FC 10 < in < Menge : INT; Freigabe : BOOL; > out < Fertig : BOOL; > >
block FB 20 < in < Sollwert : REAL; Istwert : REAL; Handbetrieb : BOOL; > out < Stellwert : REAL; > >
block FC 12 < in < Text : STRING; Nummer : INT; > >
";
const WARM_UP: usize = 5;
/// The number of the kind `stateIncoming` in a count lens's data (`[document, kind]`).
const STATE_INCOMING: u64 = 4;
const TIMEOUT: Duration = Duration::from_secs(30);

struct Options {
    iterations: usize,
    seed: u64,
    server: PathBuf,
}

fn main() {
    let options = match options() {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            eprintln!("usage: latency [--iterations N] [--seed S] [--server PATH]");
            std::process::exit(2);
        }
    };
    if let Err(message) = run(&options) {
        eprintln!("error: {message}");
        std::process::exit(1);
    }
}

fn options() -> Result<Options, String> {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    let mut options = Options {
        iterations: 100,
        seed: 1,
        server: target.join("release").join("higraph-lsp"),
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--iterations" => {
                options.iterations = value()?.parse().map_err(|e| format!("{e}"))?;
            }
            "--seed" => options.seed = value()?.parse().map_err(|e| format!("{e}"))?,
            "--server" => options.server = PathBuf::from(value()?),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    if options.iterations == 0 {
        return Err("--iterations must be at least 1".into());
    }
    Ok(options)
}

/// Where the benchmark edits: the `N` of an `UN` operation in a transition late in the file.
struct Target {
    line: u32,
    /// The column (and byte offset in the line; the text is ASCII) of the `N`.
    column: u32,
    /// The byte offset of the `N` in the file.
    offset: u32,
    /// Line, column and byte offset just after the `(` of the first CALL after the `N`.
    call: (u32, u32, u32),
}

fn find_target(text: &str) -> Result<Target, String> {
    let mut offset = 0usize;
    let mut found = None;
    for (line, content) in text.split('\n').enumerate() {
        let trimmed = content.trim_start();
        // The last `UN` operation at or after 90 % of the file: the edit is late, so
        // anything the server does that is proportional to the text before it shows.
        if found.is_none() && trimmed.starts_with("UN ") && offset >= text.len() * 9 / 10 {
            let column = content.len() - trimmed.len() + 1;
            found = Some(Target {
                line: line as u32,
                column: column as u32,
                offset: (offset + column) as u32,
                call: (0, 0, 0),
            });
        } else if let Some(target) = found.as_mut()
            && let Some(at) = content.find("CALL ").and_then(|c| content[c..].find('('))
        {
            let column = content.find("CALL ").unwrap_or(0) + at + 1;
            target.call = (line as u32, column as u32, (offset + column) as u32);
            break;
        }
        offset += content.len() + 1;
    }
    if !text.is_ascii() {
        return Err("the workload is not ASCII: columns would need converting".into());
    }
    match found {
        Some(target) if target.call != (0, 0, 0) => Ok(target),
        Some(_) => Err("no `CALL … (` after the edited operation".into()),
        None => Err("no `UN` operation in the last tenth of the workload".into()),
    }
}

fn run(options: &Options) -> Result<(), String> {
    let text = higraph_workload::max_graph(options.seed);
    let target = find_target(&text)?;
    let folder = tempfile::tempdir().map_err(|e| format!("cannot make a folder: {e}"))?;
    let root = std::fs::canonicalize(folder.path()).map_err(|e| e.to_string())?;
    let path = root.join(FILE);
    std::fs::write(&path, &text).map_err(|e| format!("cannot write the workload: {e}"))?;
    std::fs::write(root.join(BLOCKS_FILE), BLOCKS)
        .map_err(|e| format!("cannot write the block interfaces: {e}"))?;
    println!(
        "max-graph (seed {}): {:.2} MB, {} lines; editing line {} column {}; {} iterations \
         after {WARM_UP} warm-up rounds; {} CPUs",
        options.seed,
        text.len() as f64 / 1e6,
        text.lines().count(),
        target.line + 1,
        target.column + 1,
        options.iterations,
        std::thread::available_parallelism().map_or(0, |n| n.get()),
    );

    let server = over_stdio(options, &root, &path, &text, &target)?;
    let pulled = pull_over_stdio(options, &root, &path, &text, &target)?;
    let analysis = in_process(options, &text, &target)?;

    println!();
    println!("{:<52} {:>9} {:>9} {:>9}", "", "median", "p95", "max");
    let row = |what: &str, samples: &[Duration]| {
        let s = Stats::of(samples);
        println!(
            "{what:<52} {:>9} {:>9} {:>9}",
            ms(s.median),
            ms(s.p95),
            ms(s.max)
        );
    };
    println!("server over stdio:");
    row("  edit -> publishDiagnostics", &server.edit);
    row(
        "  completion right after the edit's diagnostics",
        &server.completion_after_edit,
    );
    row("  completion, repeated", &server.completion_repeated);
    row(
        "  signature help in a CALL after the edit",
        &server.signature,
    );
    row("  edit -> textDocument/diagnostic (pull)", &pulled);
    row("  codeLens after the edit", &server.lens);
    println!(
        "    (answer: {} lenses, {} bytes of JSON)",
        server.lens_answer.0, server.lens_answer.1
    );
    row(
        "  codeLens/resolve (state lens) after the edit",
        &server.lens_resolve,
    );
    println!("analysis alone, in process:");
    row("  apply_edits + all diagnostics", &analysis.edit);
    row(
        "  completion right after the edit's diagnostics",
        &analysis.completion_after_edit,
    );
    row("  completion, repeated", &analysis.completion_repeated);
    row(
        "  signature help in a CALL after the edit",
        &analysis.signature,
    );
    row("  code lenses after the edit", &analysis.lens);
    row(
        "  resolve (state lens) after the edit",
        &analysis.lens_resolve,
    );
    Ok(())
}

#[derive(Default)]
struct Samples {
    edit: Vec<Duration>,
    completion_after_edit: Vec<Duration>,
    completion_repeated: Vec<Duration>,
    signature: Vec<Duration>,
    lens: Vec<Duration>,
    lens_resolve: Vec<Duration>,
    /// The lenses and the bytes of the last `textDocument/codeLens` answer (its JSON text).
    lens_answer: (usize, usize),
}

/// The character of round `round`: odd rounds break the operation, even ones repair it.
fn replacement(round: usize) -> &'static str {
    if round.is_multiple_of(2) { "X" } else { "N" }
}

fn over_stdio(
    options: &Options,
    root: &std::path::Path,
    path: &std::path::Path,
    text: &str,
    target: &Target,
) -> Result<Samples, String> {
    let mut server = Server::start(&options.server)?;
    let root_uri = file_uri(root);
    let uri = file_uri(path);
    server.request(
        "initialize",
        json!({
            "processId": null,
            "rootUri": root_uri,
            "capabilities": { "window": { "workDoneProgress": true } },
        }),
    )?;
    server.notify("initialized", json!({}))?;
    server.notify(
        "textDocument/didOpen",
        json!({ "textDocument": {
            "uri": uri, "languageId": "higraph", "version": 1, "text": text,
        }}),
    )?;
    // Indexing ends with the end of its progress, after the first diagnostics.
    server.wait_for(|message| {
        message["method"] == "$/progress" && message["params"]["value"]["kind"] == "end"
    })?;

    // At the start of the operand: the variables of the graph are offered.
    let position = json!({ "line": target.line, "character": target.column + 2 });
    let mut samples = Samples::default();
    for round in 0..WARM_UP + options.iterations {
        let broken = replacement(round) == "X";
        let version = round + 2;
        let start = Instant::now();
        server.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": uri, "version": version },
                "contentChanges": [{
                    "range": {
                        "start": { "line": target.line, "character": target.column },
                        "end": { "line": target.line, "character": target.column + 1 },
                    },
                    "text": replacement(round),
                }],
            }),
        )?;
        let published = server.wait_for(|message| {
            message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == uri
                && message["params"]["version"] == version
        })?;
        let edit = start.elapsed();
        let count = published["params"]["diagnostics"]
            .as_array()
            .map_or(0, Vec::len);
        if broken != (count > 0) {
            return Err(format!(
                "round {round}: expected {} diagnostics, got {count}",
                if broken { "some" } else { "no" }
            ));
        }
        let completion = json!({ "textDocument": { "uri": uri }, "position": position });
        let start = Instant::now();
        let answer = server.request("textDocument/completion", completion.clone())?;
        let after_edit = start.elapsed();
        if answer.as_array().is_none_or(Vec::is_empty) {
            return Err("completion offered nothing".into());
        }
        let start = Instant::now();
        server.request("textDocument/completion", completion)?;
        let repeated = start.elapsed();
        let (line, character, _) = target.call;
        let signature = json!({
            "textDocument": { "uri": uri },
            "position": { "line": line, "character": character },
        });
        let start = Instant::now();
        let help = server.request("textDocument/signatureHelp", signature)?;
        let signature = start.elapsed();
        if help["signatures"].as_array().is_none_or(Vec::is_empty) {
            return Err(format!("signature help answered no signature: {help}"));
        }
        let start = Instant::now();
        let lenses = server.request(
            "textDocument/codeLens",
            json!({ "textDocument": { "uri": uri } }),
        )?;
        let lens = start.elapsed();
        samples.lens_answer = (
            lenses.as_array().map_or(0, Vec::len),
            lenses.to_string().len(),
        );
        let state_lens = lenses
            .as_array()
            .and_then(|lenses| lenses.iter().find(|l| l["data"][1] == STATE_INCOMING))
            .cloned()
            .ok_or("no state lens")?;
        let start = Instant::now();
        let resolved = server.request("codeLens/resolve", state_lens)?;
        let lens_resolve = start.elapsed();
        if resolved["command"]["command"] != "higraph.showReferences" {
            return Err(format!("the state lens did not resolve: {resolved}"));
        }
        if round >= WARM_UP {
            samples.signature.push(signature);
            samples.lens.push(lens);
            samples.lens_resolve.push(lens_resolve);
            samples.edit.push(edit);
            samples.completion_after_edit.push(after_edit);
            samples.completion_repeated.push(repeated);
        }
    }
    server.request("shutdown", Value::Null)?;
    server.notify("exit", Value::Null)?;
    server.finish();
    Ok(samples)
}

/// Edit → pulled diagnostics, with a server started as a client that pulls.
fn pull_over_stdio(
    options: &Options,
    root: &std::path::Path,
    path: &std::path::Path,
    text: &str,
    target: &Target,
) -> Result<Vec<Duration>, String> {
    let mut server = Server::start(&options.server)?;
    let uri = file_uri(path);
    server.request(
        "initialize",
        json!({
            "processId": null,
            "rootUri": file_uri(root),
            "capabilities": {
                "window": { "workDoneProgress": true },
                "textDocument": { "diagnostic": {} },
            },
        }),
    )?;
    server.notify("initialized", json!({}))?;
    server.notify(
        "textDocument/didOpen",
        json!({ "textDocument": {
            "uri": uri, "languageId": "higraph", "version": 1, "text": text,
        }}),
    )?;
    server.wait_for(|message| {
        message["method"] == "$/progress" && message["params"]["value"]["kind"] == "end"
    })?;
    let first = server.request(
        "textDocument/diagnostic",
        json!({ "textDocument": { "uri": uri } }),
    )?;
    let mut previous = first["resultId"].clone();
    let mut samples = Vec::new();
    for round in 0..WARM_UP + options.iterations {
        let broken = replacement(round) == "X";
        let start = Instant::now();
        server.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": uri, "version": round + 2 },
                "contentChanges": [{
                    "range": {
                        "start": { "line": target.line, "character": target.column },
                        "end": { "line": target.line, "character": target.column + 1 },
                    },
                    "text": replacement(round),
                }],
            }),
        )?;
        let report = server.request(
            "textDocument/diagnostic",
            json!({ "textDocument": { "uri": uri }, "previousResultId": previous }),
        )?;
        let elapsed = start.elapsed();
        if report["kind"] != "full" {
            return Err(format!(
                "round {round}: the pull was not a full report: {report}"
            ));
        }
        let count = report["items"].as_array().map_or(0, Vec::len);
        if broken != (count > 0) {
            return Err(format!(
                "round {round}: pulled {count} diagnostics, expected {}",
                if broken { "some" } else { "none" }
            ));
        }
        previous = report["resultId"].clone();
        if round >= WARM_UP {
            samples.push(elapsed);
        }
    }
    server.request("shutdown", Value::Null)?;
    server.notify("exit", Value::Null)?;
    server.finish();
    Ok(samples)
}

fn in_process(options: &Options, text: &str, target: &Target) -> Result<Samples, String> {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![
            (FILE.to_owned(), FileContents::Text(text.to_owned())),
            (
                BLOCKS_FILE.to_owned(),
                FileContents::Text(BLOCKS.to_owned()),
            ),
        ],
        ..WorkspaceData::default()
    });
    host.analysis().diagnostics();
    let at = TextSize::from(target.offset);
    let position = FilePosition {
        path: FILE.to_owned(),
        offset: at + TextSize::from(2),
    };
    let mut samples = Samples::default();
    for round in 0..WARM_UP + options.iterations {
        let edit = Edit {
            delete: TextRange::at(at, TextSize::from(1)),
            insert: replacement(round).to_owned(),
        };
        let start = Instant::now();
        host.apply_edits(FILE, &[edit])
            .ok_or("the analysis refused the edit")?;
        let diagnostics = host.analysis().diagnostics();
        let elapsed = start.elapsed();
        let count: usize = diagnostics.iter().map(|(_, d)| d.len()).sum();
        if (replacement(round) == "X") != (count > 0) {
            return Err(format!(
                "round {round}: unexpected {count} diagnostics in process"
            ));
        }
        let start = Instant::now();
        let items = host.analysis().completions(&position);
        let after_edit = start.elapsed();
        if items.map_or(true, |items| items.is_empty()) {
            return Err("no completions in process".into());
        }
        let start = Instant::now();
        let _ = host.analysis().completions(&position);
        let repeated = start.elapsed();
        let call = FilePosition {
            path: FILE.to_owned(),
            offset: TextSize::from(target.call.2),
        };
        let start = Instant::now();
        let help = host.analysis().signature_help(&call);
        let signature = start.elapsed();
        if !matches!(help, Ok(Some(_))) {
            return Err("no signature help in process".into());
        }
        let start = Instant::now();
        let lenses = host
            .analysis()
            .code_lenses(FILE)
            .map_err(|_| "code lenses cancelled")?;
        let lens = start.elapsed();
        let state_lens = lenses
            .iter()
            .find(|l| l.kind == higraph_analysis::ide::LensKind::StateIncoming)
            .ok_or("no state lens in process")?;
        let start = Instant::now();
        let resolved = host.analysis().resolve_code_lens(
            &FilePosition {
                path: FILE.to_owned(),
                offset: state_lens.name,
            },
            state_lens.kind,
        );
        let lens_resolve = start.elapsed();
        if !matches!(resolved, Ok(Some(_))) {
            return Err("the state lens did not resolve in process".into());
        }
        if round >= WARM_UP {
            samples.lens.push(lens);
            samples.lens_resolve.push(lens_resolve);
            samples.signature.push(signature);
            samples.edit.push(elapsed);
            samples.completion_after_edit.push(after_edit);
            samples.completion_repeated.push(repeated);
        }
    }
    Ok(samples)
}

struct Stats {
    median: Duration,
    p95: Duration,
    max: Duration,
}

impl Stats {
    fn of(samples: &[Duration]) -> Stats {
        let mut sorted = samples.to_vec();
        sorted.sort();
        let at =
            |q: f64| sorted[((sorted.len() as f64 * q).ceil() as usize).clamp(1, sorted.len()) - 1];
        Stats {
            median: at(0.5),
            p95: at(0.95),
            max: at(1.0),
        }
    }
}

fn ms(duration: Duration) -> String {
    format!("{:.2} ms", duration.as_secs_f64() * 1e3)
}

fn file_uri(path: &std::path::Path) -> String {
    let mut uri = String::from("file://");
    for byte in path.to_string_lossy().bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                uri.push(byte as char)
            }
            _ => uri.push_str(&format!("%{byte:02X}")),
        }
    }
    uri
}

/// The server process and its messages (read on a thread of their own, so a wait can time
/// out).
struct Server {
    child: Child,
    stdin: ChildStdin,
    messages: mpsc::Receiver<Value>,
    next_id: u64,
}

impl Server {
    fn start(binary: &std::path::Path) -> Result<Server, String> {
        let mut child = Command::new(binary)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| {
                format!(
                    "cannot start {} ({e}); build it with `cargo build --release -p higraph-lsp` \
                     or pass --server",
                    binary.display()
                )
            })?;
        let stdin = child.stdin.take().ok_or("no stdin")?;
        let stdout = child.stdout.take().ok_or("no stdout")?;
        let (sender, messages) = mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                if sender.send(message).is_err() {
                    break;
                }
            }
        });
        Ok(Server {
            child,
            stdin,
            messages,
            next_id: 1,
        })
    }

    fn send(&mut self, message: &Value) -> Result<(), String> {
        // One write per frame, as editors do: a frame split over several writes can reach the
        // server in pieces, and each piece costs it a wake-up.
        let body = message.to_string();
        let mut frame = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
        frame.extend_from_slice(body.as_bytes());
        self.stdin
            .write_all(&frame)
            .and_then(|()| self.stdin.flush())
            .map_err(|e| format!("cannot write to the server: {e}"))
    }

    fn notify(&mut self, method: &str, params: Value) -> Result<(), String> {
        self.send(&json!({ "jsonrpc": "2.0", "method": method, "params": params }))
    }

    /// Sends a request and waits for its result.
    fn request(&mut self, method: &str, params: Value) -> Result<Value, String> {
        let id = self.next_id;
        self.next_id += 1;
        self.send(&json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }))?;
        let answer =
            self.wait_for(|message| message["id"] == id && message.get("method").is_none())?;
        match answer.get("error") {
            Some(error) => Err(format!("{method} failed: {error}")),
            None => Ok(answer["result"].clone()),
        }
    }

    /// Reads messages until one satisfies `wanted`, answering the server's own requests on
    /// the way.
    fn wait_for(&mut self, wanted: impl Fn(&Value) -> bool) -> Result<Value, String> {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let message = self
                .messages
                .recv_timeout(left)
                .map_err(|_| format!("no expected message from the server within {TIMEOUT:?}"))?;
            if wanted(&message) {
                return Ok(message);
            }
            if message.get("method").is_some() && message.get("id").is_some() {
                // `window/workDoneProgress/create`, `client/registerCapability`, …
                let id = message["id"].clone();
                self.send(&json!({ "jsonrpc": "2.0", "id": id, "result": null }))?;
            }
        }
    }

    fn finish(mut self) {
        drop(self.stdin);
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
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

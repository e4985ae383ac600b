//! The file system cases (`README.md`, "What higraph-lsp reads and writes"): only regular
//! files inside the workspace are read, at most 32 MiB (1 MiB for the configuration); nothing
//! outside the workspace is printed or written; nothing hangs.

use std::fs;
use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::client::{Server, file_uri};

/// How long one run may take before it counts as a hang.
const HANG: Duration = Duration::from_secs(60);

/// A string that must never appear in any output.
const SECRET: &str = "GEHEIM-7f3a9c";

/// What one run of the binary did.
#[derive(Debug)]
struct Run {
    status: i32,
    stdout: String,
    stderr: String,
}

impl Run {
    fn all(&self) -> String {
        format!("{}\n{}", self.stdout, self.stderr)
    }
}

/// Runs the binary in `cwd`; fails the test (and kills the process) if it takes longer
/// than [`HANG`].
fn run(cwd: &Path, args: &[&str]) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_higraph-lsp"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // Read the pipes on threads, so a full pipe cannot block the child.
    let mut stdout = child.stdout.take().expect("stdout");
    let mut stderr = child.stderr.take().expect("stderr");
    let out = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = std::io::Read::read_to_end(&mut stdout, &mut text);
        text
    });
    let err = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = std::io::Read::read_to_end(&mut stderr, &mut text);
        text
    });
    let deadline = Instant::now() + HANG;
    let status = loop {
        if let Some(status) = child.try_wait().expect("the child's status") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "`higraph-lsp {}` hangs (killed after {HANG:?})",
                args.join(" ")
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let text = |bytes: Vec<u8>| String::from_utf8_lossy(&bytes).into_owned();
    Run {
        status: status.code().expect("an exit status, not a signal"),
        stdout: text(out.join().expect("stdout reader")),
        stderr: text(err.join().expect("stderr reader")),
    }
}

/// A temporary folder with a workspace `ws/` in it and room outside the workspace.
struct Tree {
    dir: tempfile::TempDir,
}

impl Tree {
    fn new() -> Tree {
        let tree = Tree {
            dir: tempfile::tempdir().expect("a temporary folder"),
        };
        fs::create_dir_all(tree.ws()).expect("ws");
        fs::create_dir_all(tree.path().join("outside")).expect("outside");
        tree
    }

    /// The canonical temporary folder.
    fn path(&self) -> PathBuf {
        fs::canonicalize(self.dir.path()).expect("canonical")
    }

    /// The workspace.
    fn ws(&self) -> PathBuf {
        self.path().join("ws")
    }

    /// Writes `relative` (below the temporary folder).
    fn file(&self, relative: &str, contents: impl AsRef<[u8]>) -> &Tree {
        let path = self.path().join(relative);
        fs::create_dir_all(path.parent().expect("a folder")).expect("folders");
        fs::write(path, contents).expect("write");
        self
    }

    /// Makes `relative` a symbolic link to `target` (as written).
    fn link(&self, relative: &str, target: impl AsRef<Path>) -> &Tree {
        let path = self.path().join(relative);
        fs::create_dir_all(path.parent().expect("a folder")).expect("folders");
        symlink(target, path).expect("symlink");
        self
    }

    fn fifo(&self, relative: &str) -> &Tree {
        let path = self.path().join(relative);
        let made = Command::new("mkfifo")
            .arg(&path)
            .status()
            .expect("mkfifo runs");
        assert!(made.success(), "mkfifo {}", path.display());
        self
    }

    fn read(&self, relative: &str) -> String {
        fs::read_to_string(self.path().join(relative)).expect("read")
    }
}

const GRAPH: &str = "graph Ventil_2E <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n";
const MESSY: &str = "graph   Ventil_2E <\n state 0 <  >\n   trans any->0 < U INIT_SD; >\n>\n";

/// The diagnostics of `check --format json` as (file, code, message).
fn json_diagnostics(run: &Run) -> Vec<(String, String, String)> {
    let report: Value = serde_json::from_str(&run.stdout)
        .unwrap_or_else(|error| panic!("no JSON ({error}): {run:?}"));
    report["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| {
            let text = |key: &str| d[key].as_str().unwrap_or_default().to_owned();
            (text("file"), text("code"), text("message"))
        })
        .collect()
}

fn has(diagnostics: &[(String, String, String)], file: &str, code: &str, message: &str) -> bool {
    diagnostics
        .iter()
        .any(|(f, c, m)| f == file && c == code && m == message)
}

#[test]
fn a_fifo_named_like_a_source_is_hg6103_and_nothing_blocks() {
    let tree = Tree::new();
    tree.file("ws/a.higraph", GRAPH).fifo("ws/p.higraph");
    let ws = tree.ws();
    let checked = run(&ws, &["check", "--format", "json"]);
    assert_eq!(checked.status, 1, "{checked:?}");
    let diagnostics = json_diagnostics(&checked);
    assert!(
        has(
            &diagnostics,
            "p.higraph",
            "HG6103",
            "cannot read file: it is a FIFO (named pipe), not a regular file"
        ),
        "{diagnostics:?}"
    );
    // Named on the command line, too.
    let named = run(&ws, &["check", "p.higraph"]);
    assert_eq!(named.status, 1, "{named:?}");
    let formatted = run(&ws, &["fmt"]);
    assert_eq!(formatted.status, 1, "{formatted:?}");
    assert!(
        formatted
            .stderr
            .contains("p.higraph: cannot read: it is a FIFO")
    );
    let rendered = run(&ws, &["render", "Ventil_2E"]);
    assert_eq!(rendered.status, 0, "{rendered:?}");
    assert!(rendered.stdout.starts_with("<svg"), "{rendered:?}");
    let parsed = run(&ws, &["parse", "p.higraph"]);
    assert_eq!(parsed.status, 2, "{parsed:?}");

    // The language server indexes and answers.
    let mut server = Server::indexed(&ws);
    let uri = file_uri(&ws.join("p.higraph"));
    server.drain(Duration::from_millis(200));
    let published = server.diagnostics.get(&uri).cloned().unwrap_or_default();
    assert!(
        published.iter().any(|d| d["code"] == "HG6103"),
        "{published:?}"
    );
    // A FIFO that appears later and is reported by the client's watcher.
    tree.fifo("ws/q.higraph");
    server.notify(
        "workspace/didChangeWatchedFiles",
        json!({"changes": [{"uri": file_uri(&ws.join("q.higraph")), "type": 1}]}),
    );
    let q = file_uri(&ws.join("q.higraph"));
    let published = server.wait_for("the diagnostics of q.higraph", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == q
    });
    assert_eq!(
        published["params"]["diagnostics"][0]["message"],
        "cannot read file: it is a FIFO (named pipe), not a regular file",
        "{published}"
    );
    // So does a link out of the workspace.
    tree.file("outside/secret.higraph", format!("graph {SECRET} < >\n"))
        .link("ws/r.higraph", "../outside/secret.higraph");
    let r = file_uri(&ws.join("r.higraph"));
    server.notify(
        "workspace/didChangeWatchedFiles",
        json!({"changes": [{"uri": r, "type": 1}]}),
    );
    let published = server.wait_for("the diagnostics of r.higraph", |m| {
        m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == r
    });
    assert_eq!(
        published["params"]["diagnostics"][0]["message"],
        "cannot read file: it is a link to a path outside the workspace",
        "{published}"
    );
    let symbols = server.request("workspace/symbol", json!({"query": "Ventil"}));
    assert!(symbols.is_ok(), "{symbols:?}");
    let secret = server
        .request("workspace/symbol", json!({"query": SECRET}))
        .expect("symbols");
    assert!(!secret.to_string().contains(SECRET), "{secret}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn nothing_behind_a_link_out_of_the_workspace_is_read_or_printed() {
    let tree = Tree::new();
    tree.file("outside/secret.higraph", format!("{SECRET}\n"))
        .file(
            "outside/secret.sdf",
            format!("\"Geheim\",\"E 1.0\",\"BOOL\",\"{SECRET}\"\r\n"),
        )
        .file("ws/a.higraph", GRAPH)
        .file(
            "ws/higraph.toml",
            "[workspace]\nsymbols = [\"../outside/secret.sdf\", \"link.sdf\", \"plc/../../outside/secret.sdf\"]\n",
        )
        .link("ws/link.sdf", "../outside/secret.sdf")
        .link("ws/env.higraph", "/proc/self/environ")
        .link("ws/graphs/s.higraph", tree.path().join("outside/secret.higraph"));
    let ws = tree.ws();
    for format in ["human", "short", "json", "github", "sarif"] {
        let checked = run(&ws, &["check", "--format", format]);
        assert_eq!(checked.status, 1, "{checked:?}");
        assert!(!checked.all().contains(SECRET), "{format}: {checked:?}");
        assert!(!checked.all().contains("PATH="), "{format}: {checked:?}");
    }
    let diagnostics = json_diagnostics(&run(&ws, &["check", "--format", "json"]));
    let outside = "cannot read file: it is a link to a path outside the workspace";
    for file in ["env.higraph", "graphs/s.higraph"] {
        let count = diagnostics
            .iter()
            .filter(|(f, c, m)| f == file && c == "HG6103" && m == outside)
            .count();
        assert_eq!(count, 1, "{file}: {diagnostics:?}");
    }
    for problem in [
        "higraph.toml: symbol table '../outside/secret.sdf' cannot be used: it is outside the workspace",
        "higraph.toml: symbol table 'link.sdf' cannot be used: it is a link to a path outside the workspace",
    ] {
        assert!(
            has(&diagnostics, "higraph.toml", "HG6101", problem),
            "{problem}: {diagnostics:?}"
        );
    }
    // `plc/../../outside` is `../outside` once `..` is folded: one entry, reported on both.
    let hg6101 = diagnostics.iter().filter(|(_, c, _)| c == "HG6101").count();
    assert_eq!(hg6101, 3, "{diagnostics:?}");
    // A `higraph.toml` that links out of the workspace is not read either.
    let linked = tree.path().join("linked");
    fs::create_dir_all(&linked).expect("linked");
    tree.file(
        "outside/secret.toml",
        format!("[workspace]\n{SECRET} = 1\n"),
    )
    .file("linked/a.higraph", GRAPH)
    .link("linked/higraph.toml", "../outside/secret.toml");
    let refused = run(&linked, &["check"]);
    assert_eq!(refused.status, 2, "{refused:?}");
    assert!(
        refused
            .stderr
            .contains("it is a link to a path outside the workspace"),
        "{refused:?}"
    );
    assert!(!refused.all().contains(SECRET), "{refused:?}");
    // Named on the command line: the link is refused all the same.
    let named = run(&ws, &["check", "--format", "short", "env.higraph"]);
    assert!(named.stdout.contains(outside), "{named:?}");
    assert!(!named.all().contains("PATH="), "{named:?}");

    // The server: no diagnostic, hover or symbol shows the secret.
    let mut server = Server::indexed(&ws);
    server.drain(Duration::from_millis(200));
    let published = serde_json::to_string(&server.diagnostics).expect("json");
    assert!(!published.contains(SECRET), "{published}");
    let symbols = server
        .request("workspace/symbol", json!({"query": "Geheim"}))
        .expect("symbols");
    assert!(!symbols.to_string().contains("Geheim"), "{symbols}");
    let uri = file_uri(&ws.join("a.higraph"));
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1,
               "text": "graph Ventil_2E <\n  state 0 < C: U Geheim; >\n  trans any->0 < U INIT_SD; >\n>\n"}}),
    );
    let hover = server
        .request(
            "textDocument/hover",
            json!({"textDocument": {"uri": uri}, "position": {"line": 1, "character": 18}}),
        )
        .expect("hover");
    assert!(!hover.to_string().contains(SECRET), "{hover}");
    assert_eq!(server.shutdown_and_exit(), 0);
}

#[test]
fn link_loops_dangling_links_and_folders_are_hg6103_once() {
    let tree = Tree::new();
    tree.file("ws/a.higraph", GRAPH)
        .link("ws/loop1.higraph", "loop2.higraph")
        .link("ws/loop2.higraph", "loop1.higraph")
        .link("ws/dangling.higraph", "nothing.higraph")
        .link("ws/inside.higraph", "a.higraph")
        .link("ws/up", ".")
        .file("ws/x.higraph/b.higraph", GRAPH);
    let ws = tree.ws();
    let checked = run(&ws, &["check", "--format", "json"]);
    let diagnostics = json_diagnostics(&checked);
    let reasons = |file: &str| -> Vec<String> {
        diagnostics
            .iter()
            .filter(|(f, c, _)| f == file && c == "HG6103")
            .map(|(_, _, m)| m.clone())
            .collect()
    };
    assert_eq!(
        reasons("dangling.higraph"),
        ["cannot read file: it is a link to a path that does not exist"]
    );
    assert_eq!(
        reasons("x.higraph"),
        ["cannot read file: it is a folder, not a regular file"]
    );
    for file in ["loop1.higraph", "loop2.higraph"] {
        let found = reasons(file);
        assert_eq!(found.len(), 1, "{file}: {diagnostics:?}");
        assert!(found[0].starts_with("cannot read file: "), "{found:?}");
    }
    // A link inside the workspace is read: the graph is defined twice.
    assert!(reasons("inside.higraph").is_empty(), "{diagnostics:?}");
    assert!(
        diagnostics.iter().any(|(_, c, _)| c == "HG1301"),
        "{diagnostics:?}"
    );
    // The folder link `up -> .` is not walked into.
    assert!(
        diagnostics.iter().all(|(f, _, _)| !f.starts_with("up/")),
        "{diagnostics:?}"
    );
    let formatted = run(&ws, &["fmt", "--check"]);
    assert_eq!(formatted.status, 1, "{formatted:?}");
}

#[test]
fn devices_and_oversized_files_are_refused_with_a_clear_message() {
    let tree = Tree::new();
    tree.file("ws/a.higraph", GRAPH)
        .file(
            "ws/higraph.toml",
            "[workspace]\nsymbols = [\"/dev/zero\", \"zero.sdf\", \"pipe.sdf\"]\n",
        )
        .link("ws/zero.sdf", "/dev/zero")
        .fifo("ws/pipe.sdf");
    let ws = tree.ws();
    // 40 MiB without writing them: a sparse file.
    let big = fs::File::create(ws.join("big.higraph")).expect("create");
    big.set_len(40 * 1024 * 1024).expect("set_len");
    drop(big);
    let checked = run(&ws, &["check", "--format", "json"]);
    let diagnostics = json_diagnostics(&checked);
    for (file, code, message) in [
        (
            "big.higraph",
            "HG6103",
            "cannot read file: it is larger than the limit of 32 MiB",
        ),
        (
            "higraph.toml",
            "HG6101",
            "higraph.toml: symbol table '/dev/zero' cannot be used: it is outside the workspace",
        ),
        (
            "higraph.toml",
            "HG6101",
            "higraph.toml: symbol table 'zero.sdf' cannot be used: it is a link to a path outside the workspace",
        ),
        (
            "higraph.toml",
            "HG6005",
            "cannot import symbol table pipe.sdf: it is a FIFO (named pipe), not a regular file",
        ),
    ] {
        assert!(
            has(&diagnostics, file, code, message),
            "{file} {code} {message}: {diagnostics:?}"
        );
    }
    let formatted = run(&ws, &["fmt", "big.higraph"]);
    assert_eq!(formatted.status, 1, "{formatted:?}");
    assert!(
        formatted
            .stderr
            .contains("big.higraph: cannot read: it is larger than the limit of 32 MiB"),
        "{formatted:?}"
    );

    // The configuration: a device, a FIFO and an oversized file are usage errors.
    tree.fifo("outside/pipe.toml");
    tree.file("outside/big.toml", vec![b'#'; 1024 * 1024 + 1]);
    for (config, reason) in [
        ("/dev/zero", "it is a device, not a regular file"),
        (
            "../outside/pipe.toml",
            "it is a FIFO (named pipe), not a regular file",
        ),
        (
            "../outside/big.toml",
            "it is larger than the limit of 1 MiB",
        ),
    ] {
        let checked = run(&ws, &["check", "--config", config]);
        assert_eq!(checked.status, 2, "{checked:?}");
        assert!(
            checked.stderr.contains(&format!(
                "cannot read configuration file '{config}': {reason}"
            )),
            "{checked:?}"
        );
    }
    // So is a `higraph.toml` that is a FIFO (found, but not opened).
    let other = tree.path().join("other");
    fs::create_dir_all(&other).expect("other");
    tree.file("other/a.higraph", GRAPH)
        .fifo("other/higraph.toml");
    for args in [
        &["check"][..],
        &["fmt", "--check"],
        &["render", "Ventil_2E"],
    ] {
        let refused = run(&other, args);
        assert_eq!(refused.status, 2, "{args:?}: {refused:?}");
        assert!(
            refused
                .stderr
                .contains("higraph.toml': it is a FIFO (named pipe), not a regular file"),
            "{args:?}: {refused:?}"
        );
    }
}

#[test]
fn fmt_never_writes_outside_the_workspace() {
    let tree = Tree::new();
    tree.file("outside/o.higraph", MESSY)
        .file("ws/a.higraph", MESSY)
        .link("ws/out.higraph", "../outside/o.higraph");
    let ws = tree.ws();
    let formatted = run(&ws, &["fmt"]);
    assert_eq!(formatted.status, 1, "{formatted:?}");
    assert!(
        formatted
            .stderr
            .contains("out.higraph: cannot read: it is a link to a path outside the workspace"),
        "{formatted:?}"
    );
    assert_eq!(tree.read("outside/o.higraph"), MESSY);
    assert_ne!(
        tree.read("ws/a.higraph"),
        MESSY,
        "the workspace file is formatted"
    );
    assert!(
        fs::symlink_metadata(ws.join("out.higraph"))
            .expect("link")
            .file_type()
            .is_symlink()
    );

    // A later PATH outside the root: checked, never written.
    let named = run(&ws, &["fmt", ".", "../outside/o.higraph"]);
    assert_eq!(named.status, 1, "{named:?}");
    assert!(
        named
            .stderr
            .contains("o.higraph: not written: it is outside the workspace root"),
        "{named:?}"
    );
    assert_eq!(tree.read("outside/o.higraph"), MESSY);
    let checked = run(&ws, &["fmt", "--check", ".", "../outside/o.higraph"]);
    assert_eq!(checked.status, 1, "{checked:?}");
    assert!(checked.stdout.contains("outside/o.higraph"), "{checked:?}");
}

#[test]
fn render_output_never_replaces_a_source_or_other_work_without_force() {
    let tree = Tree::new();
    tree.file("ws/graphs/ventil_2e.higraph", GRAPH)
        .file("ws/notes.txt", "meine Notizen\n");
    let ws = tree.ws();
    for target in ["graphs/ventil_2e.higraph", "notes.txt"] {
        let before = tree.read(&format!("ws/{target}"));
        let rendered = run(&ws, &["render", "Ventil_2E", "-o", target]);
        assert_eq!(rendered.status, 2, "{rendered:?}");
        assert!(
            rendered.stderr.contains("refusing to overwrite")
                && rendered.stderr.contains("--force"),
            "{rendered:?}"
        );
        assert_eq!(tree.read(&format!("ws/{target}")), before);
    }
    // A new file, then the same picture again, then DOT over SVG: all replace a picture.
    for args in [
        &["render", "Ventil_2E", "-o", "ventil.svg"][..],
        &["render", "Ventil_2E", "-o", "ventil.svg"],
        &["render", "Ventil_2E", "--format", "dot", "-o", "ventil.svg"],
        &["render", "Ventil_2E", "-o", "ventil.svg"],
    ] {
        let rendered = run(&ws, args);
        assert_eq!(rendered.status, 0, "{rendered:?}");
    }
    assert!(tree.read("ws/ventil.svg").starts_with("<svg"));
    // `--force` replaces anything.
    let forced = run(&ws, &["render", "Ventil_2E", "-o", "notes.txt", "--force"]);
    assert_eq!(forced.status, 0, "{forced:?}");
    assert!(tree.read("ws/notes.txt").starts_with("<svg"));
    // A stream is written to, not replaced.
    let streamed = run(&ws, &["render", "Ventil_2E", "-o", "/dev/null"]);
    assert_eq!(streamed.status, 0, "{streamed:?}");
    // No temporary files are left behind.
    let names: Vec<String> = fs::read_dir(&ws)
        .expect("list")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("tmp")), "{names:?}");
}

#[test]
fn file_names_that_are_not_utf8_print_apart() {
    use std::os::unix::ffi::OsStrExt as _;
    let tree = Tree::new();
    let ws = tree.ws();
    for byte in [0xff_u8, 0xfe] {
        let bytes = [b'a', byte, b'.', b'h', b'i', b'g', b'r', b'a', b'p', b'h'];
        let name = std::ffi::OsStr::from_bytes(&bytes);
        fs::write(ws.join(name), "graph G < $ >\n").expect("write");
    }
    let short = run(&ws, &["check", "--format", "short"]);
    assert!(short.stdout.contains("a\\xff.higraph:1:"), "{short:?}");
    assert!(short.stdout.contains("a\\xfe.higraph:1:"), "{short:?}");
    let files: std::collections::BTreeSet<String> =
        json_diagnostics(&run(&ws, &["check", "--format", "json"]))
            .into_iter()
            .map(|(file, _, _)| file)
            .collect();
    assert!(files.contains("a\\xff.higraph"), "{files:?}");
    assert!(files.contains("a\\xfe.higraph"), "{files:?}");
}

#[test]
fn the_configuration_problem_code_cannot_be_turned_off() {
    let tree = Tree::new();
    tree.file("ws/a.higraph", GRAPH).file(
        "ws/higraph.toml",
        "[diagnostics]\nHG6101 = \"off\"\n[workspace]\nunknown = 1\n",
    );
    let checked = run(&tree.ws(), &["check", "--format", "json"]);
    assert_eq!(checked.status, 1, "{checked:?}");
    let diagnostics = json_diagnostics(&checked);
    assert!(
        has(
            &diagnostics,
            "higraph.toml",
            "HG6101",
            "higraph.toml: unknown key 'workspace.unknown'"
        ),
        "{diagnostics:?}"
    );
    assert!(
        has(
            &diagnostics,
            "higraph.toml",
            "HG6101",
            "higraph.toml: HG6101 reports the problems of this file and its severity cannot be changed"
        ),
        "{diagnostics:?}"
    );
}

#[test]
fn the_server_refuses_documents_over_the_size_limit_and_keeps_answering() {
    let tree = Tree::new();
    tree.file("ws/a.higraph", GRAPH);
    let ws = tree.ws();
    let mut server = Server::indexed(&ws);
    let uri = file_uri(&ws.join("huge.higraph"));
    let mut text = String::from(GRAPH);
    text.push_str(&" ".repeat(33 * 1024 * 1024));
    server.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri, "languageId": "higraph", "version": 1, "text": text}}),
    );
    drop(text);
    let published = server.wait_for_diagnostics(&uri, 1);
    assert_eq!(published.len(), 1, "{published:?}");
    assert_eq!(published[0]["code"], "HG6103");
    assert_eq!(
        published[0]["message"],
        "cannot read file: it is larger than the limit of 32 MiB"
    );
    // Deleting most of it brings the analysis back.
    server.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2},
               "contentChanges": [{"text": "graph Gross < $ >\n"}]}),
    );
    let published = server.wait_for_diagnostics(&uri, 2);
    assert!(
        published.iter().any(|d| d["code"] == "HG0009"),
        "{published:?}"
    );
    assert_eq!(server.shutdown_and_exit(), 0);
}

/// `build` writes into its output folder by rename: FIFOs named like its files (and like its
/// marker) are replaced without being opened, a FIFO as the output folder is refused, and a
/// link named like an output file is replaced, never written through to the file outside.
#[test]
fn build_never_blocks_on_special_files_and_never_writes_through_a_link() {
    const GROUP: &str = "graph G <\n  out < Q : BOOL; >\n  state 0 < C: = Q; >\n  trans any->0 prio 1 < U INIT_SD; >\n>\ngroup Gruppe fc FC 1 db DB 1 <\n  instance I : G < Q := A 0.0; >\n>\n";
    let tree = Tree::new();
    tree.file("ws/a.higraph", GROUP)
        .file("ws/build/keep.txt", "keep")
        .fifo("ws/build/Gruppe.awl")
        .fifo("ws/build/.higraph-build")
        .file("outside/target.sdf", "outside");
    tree.link(
        "ws/build/symbols.sdf",
        tree.path().join("outside/target.sdf"),
    );
    let ws = tree.ws();
    let built = run(&ws, &["build"]);
    assert_eq!(built.status, 0, "{}", built.all());
    for name in ["Gruppe.awl", "symbols.sdf", ".higraph-build"] {
        let meta = fs::symlink_metadata(ws.join("build").join(name)).expect("written");
        assert!(meta.is_file(), "{name} is a regular file now");
    }
    assert_eq!(tree.read("outside/target.sdf"), "outside");
    assert_eq!(tree.read("ws/build/keep.txt"), "keep");

    let tree = Tree::new();
    tree.file("ws/a.higraph", GROUP).fifo("ws/build");
    let refused = run(&tree.ws(), &["build"]);
    assert_eq!(refused.status, 2, "{}", refused.all());
}

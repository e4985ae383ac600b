//! `higraph-lsp` without a command started by hand on a terminal says what it is on stderr
//! (and still serves LSP); started by an editor (stdin a pipe) it prints nothing.

use std::process::{Command, Stdio};

use crate::support::binary;

const NOTICE: &str = "this is the HiGraph language server";

#[test]
fn on_a_terminal_the_server_says_what_it_is() {
    // `script` gives the binary a pseudo-terminal as stdin; the closed input ends the session.
    let Ok(output) = Command::new("script")
        .args(["-qec", binary(), "/dev/null"])
        .stdin(Stdio::null())
        .output()
    else {
        eprintln!("skipped: `script` (util-linux) is not installed");
        return;
    };
    let shown = String::from_utf8_lossy(&output.stdout);
    assert!(shown.contains(NOTICE), "{output:?}");
    assert!(shown.contains("higraph-lsp --help"), "{output:?}");
}

#[test]
fn from_an_editor_the_server_prints_nothing_on_stderr() {
    for args in [&[][..], &["lsp"], &["--stdio"]] {
        let output = Command::new(binary())
            .args(args)
            .stdin(Stdio::null())
            .output()
            .expect("the binary runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!stderr.contains(NOTICE), "{args:?}: {stderr}");
    }
}

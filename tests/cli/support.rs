//! Helpers for driving the real `higraph-lsp` binary: running it, building throw-away
//! workspaces, and reading the `parse` tree dump back.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test.
pub fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_higraph-lsp")
}

/// The repository root (the Cargo workspace).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// What one run of the binary did.
#[derive(Debug)]
pub struct Run {
    pub status: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the binary with `args` in `cwd`, with colour-related variables cleared.
pub fn run_in(cwd: &Path, args: &[&str]) -> Run {
    let output = Command::new(binary())
        .args(args)
        .current_dir(cwd)
        .env_remove("NO_COLOR")
        .env_remove("CLICOLOR_FORCE")
        .output()
        .expect("the binary runs");
    from_output(output)
}

fn from_output(output: Output) -> Run {
    Run {
        status: output
            .status
            .code()
            .expect("the binary exits normally, without a signal"),
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
    }
}

/// A temporary folder tree.
pub struct TempTree {
    dir: tempfile::TempDir,
}

impl TempTree {
    pub fn new() -> TempTree {
        TempTree {
            dir: tempfile::tempdir().expect("a temporary folder"),
        }
    }

    /// Creates the file `relative` (and its folders) with `contents`.
    pub fn file(&self, relative: &str, contents: impl AsRef<[u8]>) -> &TempTree {
        let path = self.path().join(relative);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create folders");
        }
        std::fs::write(&path, contents).expect("write file");
        self
    }

    /// Creates the folder `relative`.
    pub fn folder(&self, relative: &str) -> &TempTree {
        std::fs::create_dir_all(self.path().join(relative)).expect("create folder");
        self
    }

    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Runs the binary in `relative` (a folder of the tree).
    pub fn run(&self, relative: &str, args: &[&str]) -> Run {
        run_in(&self.path().join(relative), args)
    }
}

/// One token line of `higraph-lsp parse`: `KIND@start..end "text"`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TokenLine {
    pub kind: String,
    pub start: usize,
    pub end: usize,
    pub text: String,
}

/// The token lines of a tree dump (node lines, which have no text, are skipped).
pub fn token_lines(tree: &str) -> Vec<TokenLine> {
    tree.lines()
        .filter_map(|line| {
            let line = line.trim_start_matches(' ');
            let (head, quoted) = line.split_once(' ')?;
            let (kind, range) = head.split_once('@')?;
            let (start, end) = range.split_once("..")?;
            Some(TokenLine {
                kind: kind.to_string(),
                start: start.parse().expect("token start is a number"),
                end: end.parse().expect("token end is a number"),
                text: unescape_debug_str(quoted)
                    .unwrap_or_else(|error| panic!("bad token text {quoted}: {error}")),
            })
        })
        .collect()
}

/// Reverses Rust's `{:?}` of a `str`: the surrounding quotes and the escapes `\n \r \t \\ \"
/// \' \0 \u{…}`.
pub fn unescape_debug_str(quoted: &str) -> Result<String, String> {
    let inner = quoted
        .strip_prefix('"')
        .and_then(|rest| rest.strip_suffix('"'))
        .ok_or("not in double quotes")?;
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next().ok_or("dangling backslash")? {
            'n' => out.push('\n'),
            'r' => out.push('\r'),
            't' => out.push('\t'),
            '\\' => out.push('\\'),
            '"' => out.push('"'),
            '\'' => out.push('\''),
            '0' => out.push('\0'),
            'u' => {
                if chars.next() != Some('{') {
                    return Err("\\u without {".into());
                }
                let hex: String = chars.by_ref().take_while(|&c| c != '}').collect();
                let value = u32::from_str_radix(&hex, 16).map_err(|e| e.to_string())?;
                out.push(char::from_u32(value).ok_or("not a scalar value")?);
            }
            other => return Err(format!("unknown escape \\{other}")),
        }
    }
    Ok(out)
}

/// A small deterministic pseudo-random generator (xorshift64*), so generated inputs are the
/// same on every run.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.max(1))
    }

    pub fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) as usize % n
    }
}

#[test]
fn unescaper_handles_every_escape() {
    assert_eq!(
        unescape_debug_str(r#""a\n\r\t\\\"\'\0\u{feff}\u{1F600}ü""#).unwrap(),
        "a\n\r\t\\\"'\0\u{feff}😀ü"
    );
    assert!(unescape_debug_str(r#""\q""#).is_err());
    assert!(unescape_debug_str("abc").is_err());
}

#[test]
fn unescaper_inverts_debug() {
    for text in [
        "",
        "x",
        "\u{301}a\u{200B}\u{7}\u{FEFF}",
        "\r\n\t'\"\\\0",
        "😀 Öl",
    ] {
        assert_eq!(unescape_debug_str(&format!("{text:?}")).unwrap(), text);
    }
}

//! `higraph-lsp parse FILE`: the tree it prints is lossless — the token texts, in order,
//! are exactly the file's bytes (`tooling.md` §7, `language.md` §1.4).

use std::path::{Path, PathBuf};

use crate::support::{Rng, TempTree, repo_root, run_in, token_lines};

/// Runs `parse` on `path` and checks the round trip.
fn assert_round_trip(path: &Path) {
    let bytes = std::fs::read(path).expect("read input");
    let run = run_in(
        path.parent().unwrap_or(Path::new(".")),
        &["parse", &path.to_string_lossy()],
    );
    assert_eq!(
        run.status,
        0,
        "parse {} failed: {}",
        path.display(),
        run.stderr
    );
    let tokens = token_lines(&run.stdout);
    let mut offset = 0;
    let mut text = String::new();
    for token in &tokens {
        assert_eq!(
            token.start,
            offset,
            "{}: token {token:?} does not start where the last ended",
            path.display()
        );
        assert_eq!(
            token.end - token.start,
            token.text.len(),
            "{}: range of {token:?}",
            path.display()
        );
        offset = token.end;
        text.push_str(&token.text);
    }
    assert_eq!(
        text.as_bytes(),
        &bytes[..],
        "{}: the tokens do not give back the file\n{}",
        path.display(),
        run.stdout
    );
    // The root node spans the whole file.
    let first = run.stdout.lines().next().unwrap_or_default();
    assert_eq!(
        first,
        format!("SOURCE_FILE@0..{}", bytes.len()),
        "{}",
        path.display()
    );
}

/// Every `*.higraph` file below `folder`, if it exists.
fn higraph_files(folder: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(folder) else {
        return found;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            found.extend(higraph_files(&path));
        } else if path.extension().is_some_and(|ext| ext == "higraph") {
            found.push(path);
        }
    }
    found.sort();
    found
}

#[test]
fn repository_files_round_trip() {
    let root = repo_root();
    let files: Vec<_> = ["examples", "crates/syntax/test_data"]
        .iter()
        .flat_map(|folder| higraph_files(&root.join(folder)))
        .collect();
    for file in &files {
        assert_round_trip(file);
    }
    eprintln!("{} repository files round-tripped", files.len());
}

/// Inputs that stress the lexer and the tree: garbage characters, unclosed strings and
/// character constants, every kind of line break, non-ASCII text, a byte-order mark.
const INLINE_INPUTS: &[&str] = &[
    "",
    "\n",
    "graph G < state 0 < E: S x >",
    "graph Ventil \"Ventil\" <\r\n  state 1 \"Zu\" < C: = Zu; >\r\n>\r\n",
    "graph G <\r  state 1 <\r>\r>",
    "$@{}\\~`^|&",
    "graph G \"unclosed\n< >",
    "x := 'it''s';\n y := 'open\n",
    "\"\"\"\n''''\n'\n\"",
    "// Ventil für Öl\ngraph Zähler < >\n",
    "\u{FEFF}graph G < >\n",
    "\u{FEFF}",
    "graph G \"😀\" < in < x : INT; > > $ 😀😀 \u{10FFFF}",
    "\t\t<\t>\u{0}\u{7}\u{1b}[31m\u{200B}\u{301}",
    "B#16#FF T#5S3M 16#FF S5T#1H_1M 2#0101 P#M50.0 DT#1994-3-15-1:10:3.3 B#(1, 2",
    "a\r\n\r\n\n\r\rb//c\r\n// d\re",
    "<<<<<<>>>>>>>;;;;:::=->",
    "ÄÖÜäöüß ĳ Ωmega 名前 _x1 1x",
];

#[test]
fn inline_inputs_round_trip() {
    let tree = TempTree::new();
    for (i, input) in INLINE_INPUTS.iter().enumerate() {
        let name = format!("inline{i}.higraph");
        tree.file(&name, input);
        assert_round_trip(&tree.path().join(name));
    }
}

#[test]
fn generated_inputs_round_trip() {
    const PIECES: &[&str] = &[
        "graph", "state", "trans", "group", "chart", "step", " ", "\n", "\r\n", "\r", "\t", "<",
        ">", ";", ":", ":=", "->", "\"", "'", "//", "$", "😀", "ä", "ß", "\u{FEFF}", "#", "B#16#",
        "T#", "1", "2.5", "e", "_", "(", ")", "[", "]", "x", "Zu", "U", "E 1.0", "%", "\u{0}",
    ];
    let tree = TempTree::new();
    let mut rng = Rng::new(0x4869_4772_6170_6821);
    for i in 0..40 {
        let len = rng.below(60);
        let input: String = (0..len).map(|_| PIECES[rng.below(PIECES.len())]).collect();
        let name = format!("generated{i}.higraph");
        tree.file(&name, &input);
        assert_round_trip(&tree.path().join(name));
    }
}

#[test]
fn syntax_errors_go_to_stderr_and_do_not_fail() {
    let tree = TempTree::new();
    let input = "// Öl\nx \"😀\" $\n'open\n";
    tree.file("a.higraph", input);
    let run = tree.run(".", &["parse", "a.higraph"]);
    assert_eq!(run.status, 0);
    assert!(
        run.stdout
            .starts_with(&format!("SOURCE_FILE@0..{}\n", input.len())),
        "{}",
        run.stdout
    );
    // Lexer diagnostics are final: line and column are 1-based, columns in characters.
    assert!(
        run.stderr
            .contains("error[HG0009]: unexpected character '$' (U+0024) at 2:7\n"),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains(
            "error[HG0005]: character constant is not closed before the end of the line at 3:1\n"
        ),
        "{}",
        run.stderr
    );
}

#[test]
fn unreadable_files_are_usage_errors() {
    let tree = TempTree::new();
    let run = tree.run(".", &["parse", "missing.higraph"]);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.contains("cannot read 'missing.higraph'"),
        "{}",
        run.stderr
    );
    assert!(run.stdout.is_empty());

    tree.file("latin1.higraph", b"// F\xFCr\n");
    let run = tree.run(".", &["parse", "latin1.higraph"]);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr
            .contains("'latin1.higraph' is not valid UTF-8 (invalid byte at offset 4)"),
        "{}",
        run.stderr
    );

    tree.folder("dir.higraph");
    let run = tree.run(".", &["parse", "dir.higraph"]);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.contains("cannot read 'dir.higraph'"),
        "{}",
        run.stderr
    );
}

#[test]
fn parse_needs_a_file() {
    let tree = TempTree::new();
    let run = tree.run(".", &["parse"]);
    assert_eq!(run.status, 2);
    assert!(run.stderr.contains("FILE"), "{}", run.stderr);
}

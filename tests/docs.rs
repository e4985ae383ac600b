//! The user documentation stays true and self-contained:
//!
//! * every relative link in `README.md`, `ARCHITECTURE.md` and `docs/**/*.md` names a file or
//!   folder of the repository (and, for a `#fragment` into a Markdown file, one of its
//!   headings), and no document mentions an `http(s)` address at all: the manual lives here;
//! * `docs/README.md` links every rule page of `docs/rules/`;
//! * every code block of `docs/language.md` marked ```` ```higraph check ```` is a complete
//!   example that the real binary checks without a single diagnostic;
//! * `docs/tutorial.md` replays: its ```` ```higraph file=PATH ```` / ```` ```toml file=PATH ````
//!   blocks are written into an empty folder in order, and at every ```` ```text check ````
//!   block the command on its first line (`$ higraph-lsp ...`) is run there and must print
//!   exactly the rest of the block.

use std::collections::HashMap;
use std::fs;
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// `README.md`, `ARCHITECTURE.md` and every `.md` file under `docs/`, as repository-relative
/// paths.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![PathBuf::from("README.md"), PathBuf::from("ARCHITECTURE.md")];
    let mut folders = vec![PathBuf::from("docs")];
    while let Some(folder) = folders.pop() {
        let entries = fs::read_dir(root().join(&folder))
            .unwrap_or_else(|e| panic!("cannot list {}: {e}", folder.display()));
        for entry in entries {
            let entry = entry.expect("a readable folder entry");
            let path = folder.join(entry.file_name());
            if entry.file_type().expect("a file type").is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                docs.push(path);
            }
        }
    }
    docs.sort();
    docs
}

/// A fenced code block: its info string, its body and the line of its opening fence.
struct Fence {
    info: String,
    body: String,
    line: usize,
}

/// The text outside fenced code blocks (fences blanked, line structure kept) and the blocks.
fn split_fences(text: &str) -> (String, Vec<Fence>) {
    let mut prose = String::new();
    let mut fences = Vec::new();
    let mut open: Option<Fence> = None;
    for (n, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        match open.as_mut() {
            Some(fence) => {
                if trimmed == "```" {
                    fences.extend(open.take());
                } else {
                    fence.body.push_str(line);
                    fence.body.push('\n');
                }
                prose.push('\n');
            }
            None => {
                if let Some(info) = trimmed.strip_prefix("```") {
                    open = Some(Fence {
                        info: info.trim().to_owned(),
                        body: String::new(),
                        line: n + 1,
                    });
                    prose.push('\n');
                } else {
                    prose.push_str(line);
                    prose.push('\n');
                }
            }
        }
    }
    assert!(open.is_none(), "a code block is not closed");
    (prose, fences)
}

/// Removes inline code spans (`` `...` ``), so that link syntax shown as code is not a link.
fn without_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut in_code = false;
    for c in line.chars() {
        if c == '`' {
            in_code = !in_code;
        } else if !in_code {
            out.push(c);
        }
    }
    out
}

/// The targets of the inline links `[text](target)` / `![alt](target)` and of the reference
/// definitions `[label]: target` of Markdown prose, with their line numbers.
fn link_targets(prose: &str) -> Vec<(usize, String)> {
    let mut targets = Vec::new();
    for (n, line) in prose.lines().enumerate() {
        let line = without_code_spans(line);
        let trimmed = line.trim_start();
        if trimmed.starts_with('[')
            && let Some(end) = trimmed.find("]:")
        {
            let target = trimmed[end + 2..].split_whitespace().next().unwrap_or("");
            targets.push((n + 1, target.to_owned()));
            continue;
        }
        let mut rest = line.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(close) = after.find(')') else { break };
            let target = after[..close].split_whitespace().next().unwrap_or("");
            targets.push((n + 1, target.to_owned()));
            rest = &after[close..];
        }
    }
    targets
}

/// GitHub's anchor for a heading: lower case, only letters, digits, `-`, `_` and spaces kept,
/// spaces turned into `-`; repeated anchors get `-1`, `-2`, ...
fn anchors(text: &str) -> Vec<String> {
    let (prose, _) = split_fences(text);
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut anchors = Vec::new();
    for line in prose.lines() {
        let Some(heading) = line.strip_prefix('#') else {
            continue;
        };
        let heading = heading.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        let slug: String = heading
            .trim()
            .chars()
            .flat_map(char::to_lowercase)
            .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        let count = seen.entry(slug.clone()).or_insert(0);
        anchors.push(if *count == 0 {
            slug.clone()
        } else {
            format!("{slug}-{count}")
        });
        *count += 1;
    }
    anchors
}

/// `a/./b/../c` → `a/c`; `None` if the path climbs out of the repository.
fn normalise(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::Normal(part) => out.push(part),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

#[test]
fn relative_links_resolve_and_nothing_links_outside_the_repository() {
    let mut problems = Vec::new();
    let mut links = 0;
    for doc in documents() {
        let text = read(&root().join(&doc));
        for (n, line) in text.lines().enumerate() {
            if line.contains("http://") || line.contains("https://") {
                problems.push(format!(
                    "{}:{}: an http(s) address; the docs link only inside the repository",
                    doc.display(),
                    n + 1
                ));
            }
        }
        let (prose, _) = split_fences(&text);
        for (line, target) in link_targets(&prose) {
            links += 1;
            let place = format!("{}:{line}: link '{target}'", doc.display());
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                problems.push(format!("{place} does not name a file of the repository"));
                continue;
            }
            let (path, fragment) = match target.split_once('#') {
                Some((path, fragment)) => (path, Some(fragment)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                Some(doc.clone())
            } else {
                normalise(&doc.parent().unwrap_or(Path::new("")).join(path))
            };
            let Some(file) = file else {
                problems.push(format!("{place} leaves the repository"));
                continue;
            };
            let full = root().join(&file);
            if !full.exists() {
                problems.push(format!("{place}: {} does not exist", file.display()));
                continue;
            }
            if let Some(fragment) = fragment
                && file.extension().is_some_and(|e| e == "md")
                && !anchors(&read(&full)).iter().any(|a| a == fragment)
            {
                problems.push(format!(
                    "{place}: {} has no heading with the anchor '#{fragment}'",
                    file.display()
                ));
            }
        }
    }
    assert!(
        links > 50,
        "only {links} links found: is the link parser broken?"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_docs_index_lists_every_rule_page() {
    let index = read(&root().join("docs/README.md"));
    let mut missing = Vec::new();
    let mut pages = 0;
    for entry in fs::read_dir(root().join("docs/rules")).expect("docs/rules") {
        let name = entry.expect("an entry").file_name();
        let name = name.to_string_lossy();
        if name.ends_with(".md") {
            pages += 1;
            if !index.contains(&format!("(rules/{name})")) {
                missing.push(name.into_owned());
            }
        }
    }
    missing.sort();
    assert!(pages > 100, "only {pages} rule pages found");
    assert!(
        missing.is_empty(),
        "docs/README.md does not link: {} (add a row `| [HGnnnn](rules/HGnnnn.md) | title | \
         severity |` to the table of its Rules section)",
        missing.join(", ")
    );
}

fn higraph_lsp(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_higraph-lsp"))
        .current_dir(dir)
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run higraph-lsp: {e}"))
}

#[test]
fn complete_examples_of_the_language_reference_check_clean() {
    let (_, fences) = split_fences(&read(&root().join("docs/language.md")));
    let examples: Vec<&Fence> = fences
        .iter()
        .filter(|f| f.info == "higraph check")
        .collect();
    assert!(
        examples.len() >= 4,
        "docs/language.md has only {} complete examples",
        examples.len()
    );
    for example in examples {
        let dir = tempfile::tempdir().expect("a temporary folder");
        fs::write(dir.path().join("example.higraph"), &example.body).expect("write the example");
        let output = higraph_lsp(dir.path(), &["check", "--format", "json"]);
        let json: serde_json::Value =
            serde_json::from_slice(&output.stdout).unwrap_or_else(|e| panic!("invalid JSON ({e})"));
        let diagnostics = json["diagnostics"].as_array().expect("a diagnostics array");
        assert!(
            output.status.success() && diagnostics.is_empty(),
            "the example at docs/language.md:{} is not clean:\n{}",
            example.line,
            serde_json::to_string_pretty(diagnostics).unwrap_or_default()
        );
    }
}

#[test]
fn the_tutorial_replays_with_the_outputs_it_shows() {
    let (_, fences) = split_fences(&read(&root().join("docs/tutorial.md")));
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (mut files, mut checks) = (0, 0);
    for fence in &fences {
        if let Some(file) = fence
            .info
            .split_whitespace()
            .find_map(|word| word.strip_prefix("file="))
        {
            let path = dir.path().join(file);
            if let Some(parent) = path.parent() {
                fs::create_dir_all(parent).expect("create the folder");
            }
            fs::write(&path, &fence.body).expect("write the file");
            files += 1;
        } else if fence.info == "text check" {
            let (command, expected) = fence
                .body
                .split_once('\n')
                .unwrap_or((fence.body.as_str(), ""));
            let Some(args) = command.strip_prefix("$ higraph-lsp ") else {
                panic!(
                    "docs/tutorial.md:{}: a check block starts with '$ higraph-lsp ...'",
                    fence.line
                )
            };
            let mut args: Vec<&str> = args.split_whitespace().collect();
            if args.first() == Some(&"check") {
                args.extend(["--color", "never"]);
            }
            let output = higraph_lsp(dir.path(), &args);
            let actual = format!(
                "{}{}",
                String::from_utf8_lossy(&output.stdout),
                String::from_utf8_lossy(&output.stderr)
            );
            assert_eq!(
                actual.trim_end(),
                expected.trim_end(),
                "docs/tutorial.md:{}: `{command}` prints something else",
                fence.line
            );
            checks += 1;
        }
    }
    assert!(
        files >= 10 && checks >= 10,
        "{files} files, {checks} checks"
    );
    // The tutorial ends with a clean workspace.
    let output = higraph_lsp(dir.path(), &["check", "--format", "json"]);
    assert!(
        output.status.success(),
        "the finished tutorial is not clean"
    );
}

#[test]
fn help_points_to_the_manual_not_to_the_internal_spec() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let top = higraph_lsp(dir.path(), &["--help"]);
    let top = String::from_utf8_lossy(&top.stdout).into_owned();
    assert!(top.contains("docs/"), "--help does not name docs/:\n{top}");
    for command in ["lsp", "check", "parse", "fmt", "explain", "render"] {
        let help = higraph_lsp(dir.path(), &[command, "--help"]);
        let help = String::from_utf8_lossy(&help.stdout).into_owned();
        assert!(help.contains("Usage:"), "{command} --help:\n{help}");
        for spec in ["language.md", "diagnostics.md", "tooling.md"] {
            assert!(
                !help.contains(spec) && !top.contains(spec),
                "`{command} --help` names the internal spec file {spec}"
            );
        }
    }
}

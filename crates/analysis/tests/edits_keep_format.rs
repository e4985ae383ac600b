//! A formatted workspace stays formatted after an editor rename or quick fix (issue: a CI
//! running `fmt --check` must not go red after one). Over the examples, each file first
//! formatted: every renamable name is renamed to a longer and to a shorter name, and every
//! quick fix is applied; afterwards every file the edits touched is still formatted.

use std::{
    collections::{BTreeMap, BTreeSet},
    fs,
    path::Path,
};

use higraph_analysis::{
    AnalysisHost, TextRange, TextSize,
    fixture_workspace::{FixtureFile, fixture_files, load_fixture},
    format::format,
    ide::{Edit, FilePosition, SourceChange},
};
use higraph_syntax::SyntaxKind;

/// The files of an example, each `.higraph` file formatted (files with syntax errors stay).
fn formatted_example(name: &str) -> Vec<FixtureFile> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    let mut files = Vec::new();
    let mut dirs = vec![root.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in fs::read_dir(&dir).expect("example folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            let relative = path
                .strip_prefix(&root)
                .expect("inside")
                .to_string_lossy()
                .replace('\\', "/");
            let mut bytes = fs::read(&path).expect("example file");
            if relative.ends_with(".higraph")
                && let Ok(text) = String::from_utf8(bytes.clone())
                && let Ok(formatted) = format(&text)
            {
                bytes = formatted.into_bytes();
            }
            files.push((relative, bytes));
        }
    }
    files.sort();
    files
}

/// The formatted `.higraph` files of a workspace.
fn formatted_paths(files: &[FixtureFile]) -> BTreeSet<String> {
    files
        .iter()
        .filter(|(path, bytes)| {
            path.ends_with(".higraph")
                && std::str::from_utf8(bytes).is_ok_and(|t| format(t).is_ok_and(|f| f == t))
        })
        .map(|(path, _)| path.clone())
        .collect()
}

/// Applies sorted, non-overlapping edits.
fn apply(text: &str, edits: &[Edit]) -> String {
    let mut out = text.to_owned();
    for edit in edits.iter().rev() {
        out.replace_range(std::ops::Range::<usize>::from(edit.range), &edit.new_text);
    }
    out
}

/// The files a change edits that were formatted and are not any more.
fn unformatted_after(
    files: &[FixtureFile],
    formatted: &BTreeSet<String>,
    change: &SourceChange,
) -> Vec<String> {
    let mut out = Vec::new();
    for (path, edits) in &change.files {
        if !formatted.contains(path) {
            continue;
        }
        let Some((_, bytes)) = files.iter().find(|(p, _)| p == path) else {
            continue;
        };
        let new = apply(&String::from_utf8_lossy(bytes), edits);
        if format(&new).is_ok_and(|f| f != new) {
            let first_diff = format(&new).map(|f| {
                let at = f
                    .bytes()
                    .zip(new.bytes())
                    .position(|(a, b)| a != b)
                    .unwrap_or(0);
                let line = new[..at.min(new.len())].matches('\n').count() + 1;
                let text = new.lines().nth(line - 1).unwrap_or("").to_owned();
                format!("line {line}: {text:?}")
            });
            out.push(format!("{path} {}", first_diff.unwrap_or_default()));
        }
    }
    out
}

/// Positions of the names of a file (identifiers, strings, numbers), one per token.
fn name_positions(text: &str) -> Vec<TextSize> {
    let parse = higraph_syntax::parse(text);
    parse
        .syntax_node()
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| {
            matches!(
                t.kind(),
                SyntaxKind::IDENT | SyntaxKind::STRING | SyntaxKind::NUMBER
            ) || t.kind().is_keyword()
        })
        .map(|t| t.text_range().start() + TextSize::from(1).min(t.text_range().len()))
        .collect()
}

/// Longer and shorter names to try for `name` (the first the engine accepts is used).
fn new_names(name: &str) -> (Vec<String>, Vec<String>) {
    if let Ok(n) = name.parse::<u32>() {
        return (vec![format!("{}", n + 1000)], Vec::new());
    }
    let chars: Vec<char> = name.chars().collect();
    let prefix = |k: usize| chars[..k.min(chars.len())].iter().collect::<String>();
    let longer = vec![format!("{name}Lang"), format!("{name}Q")];
    let mut shorter = Vec::new();
    for k in (1..chars.len()).rev() {
        let p = prefix(k);
        shorter.push(p.clone());
        shorter.push(format!("{p}Q").chars().take(chars.len() - 1).collect());
    }
    shorter.retain(|s| !s.is_empty() && s.len() < name.len());
    (longer, shorter)
}

fn rename_example(example: &str) -> (usize, Vec<String>) {
    rename_files(formatted_example(example))
}

/// An IEC chart (docs/iec.md: statements, arithmetic, actions), formatted, as a workspace.
fn formatted_iec_chart() -> Vec<FixtureFile> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../syntax/test_data/parser/ok/iec_chart.higraph");
    let text = fs::read_to_string(path).expect("IEC fixture");
    let formatted = format(&text).expect("the IEC fixture formats");
    vec![("iec.higraph".to_owned(), formatted.into_bytes())]
}

fn rename_files(files: Vec<FixtureFile>) -> (usize, Vec<String>) {
    let formatted = formatted_paths(&files);
    let host: AnalysisHost = load_fixture(&files);
    let analysis = host.analysis();
    let mut seen = BTreeSet::new();
    let mut renamed = 0;
    let mut problems = Vec::new();
    for (path, bytes) in &files {
        if !path.ends_with(".higraph") {
            continue;
        }
        let text = String::from_utf8_lossy(bytes);
        for offset in name_positions(&text) {
            let pos = FilePosition {
                path: path.clone(),
                offset,
            };
            let Ok(Ok((_, name))) = analysis.prepare_rename(&pos) else {
                continue;
            };
            // One rename per definition: the definition is where goto-definition leads.
            let target = analysis
                .goto_definition(&pos)
                .ok()
                .and_then(|t| t.into_iter().next())
                .map(|t| format!("{t:?}"))
                .unwrap_or_else(|| format!("{path}:{offset:?}"));
            if !seen.insert((name.clone(), target)) {
                continue;
            }
            let (longer, shorter) = new_names(&name);
            for candidates in [longer, shorter] {
                let change = candidates.iter().find_map(|new| {
                    analysis
                        .rename(&pos, new)
                        .ok()
                        .and_then(Result::ok)
                        .map(|c| (new.clone(), c))
                });
                let Some((new, change)) = change else {
                    continue;
                };
                renamed += 1;
                for bad in unformatted_after(&files, &formatted, &change) {
                    problems.push(format!("rename {name} -> {new} at {path}: {bad}"));
                }
            }
        }
    }
    (renamed, problems)
}

#[test]
fn renames_keep_formatted_files_formatted() {
    let mut problems = Vec::new();
    let mut counts = BTreeMap::new();
    for example in ["drilling", "mixer", "mistakes"] {
        let (renamed, found) = rename_example(example);
        counts.insert(example, renamed);
        problems.extend(found);
    }
    let (renamed, found) = rename_files(formatted_iec_chart());
    counts.insert("iec", renamed);
    problems.extend(found);
    assert!(counts["drilling"] > 40, "too few renames: {counts:?}");
    assert!(counts["iec"] > 5, "too few renames: {counts:?}");
    assert!(counts["mixer"] > 10, "too few renames: {counts:?}");
    assert!(
        problems.is_empty(),
        "{} problems:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// The rule fixtures (every quick fix has one), each `.higraph` file formatted where it can be.
fn formatted_fixtures() -> Vec<(String, Vec<FixtureFile>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/rules");
    let mut out = Vec::new();
    for code in fs::read_dir(&root).expect("fixtures").flatten() {
        for file in fs::read_dir(code.path()).into_iter().flatten().flatten() {
            let path = file.path();
            if path.extension().is_none_or(|e| e != "higraph") {
                continue;
            }
            let files = fixture_files(&fs::read(&path).expect("fixture"))
                .into_iter()
                .map(|(p, bytes)| {
                    let formatted = std::str::from_utf8(&bytes)
                        .ok()
                        .filter(|_| p.ends_with(".higraph"))
                        .and_then(|t| format(t).ok());
                    (p, formatted.map_or(bytes, String::into_bytes))
                })
                .collect();
            out.push((path.display().to_string(), files));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

#[test]
fn quick_fixes_keep_formatted_files_formatted() {
    let mut problems = Vec::new();
    let mut applied = 0;
    let examples = ["drilling", "mixer", "mistakes"]
        .into_iter()
        .map(|e| (e.to_owned(), formatted_example(e)))
        .chain([("iec".to_owned(), formatted_iec_chart())]);
    for (name, files) in examples.chain(formatted_fixtures()) {
        let formatted = formatted_paths(&files);
        if formatted.is_empty() {
            continue;
        }
        let host = load_fixture(&files);
        let analysis = host.analysis();
        for file in analysis.files() {
            if !formatted.contains(&file.path) {
                continue;
            }
            let whole = TextRange::up_to(TextSize::of(file.contents.text()));
            for action in analysis.code_actions(&file.path, whole).unwrap_or_default() {
                applied += 1;
                for bad in unformatted_after(&files, &formatted, &action.edit) {
                    problems.push(format!("{name}: {} '{}': {bad}", file.path, action.title));
                }
            }
        }
    }
    assert!(
        applied > 200,
        "only {applied} quick fixes in formatted files"
    );
    assert!(
        problems.is_empty(),
        "{} problems:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

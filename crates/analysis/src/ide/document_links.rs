//! Document links (`tooling.md` §3, §4; issue 15 item 4).
//!
//! * In `higraph.toml`: each entry of `workspace.symbols` whose table was read links to that
//!   file. The link covers the path between the quotes. Entries the reader refused (a table
//!   outside the workspace), tables that could not be read (missing) and, to be safe, any
//!   path that still climbs out with a leading `..` get no link: a link never leaves the
//!   workspace.
//! * In a `.higraph` file: each code in a `// higraph-allow: LIST` comment that names one rule
//!   (`HG2105`, in any case) links to that rule's documentation. Patterns (`HG21xx`) and
//!   unknown codes get none.
//!
//! The analysis names targets only (a workspace path, a rule code): where a rule's page lives
//! is the language server's choice (`docs/editors.md`, "Rule pages").

use higraph_syntax::{SyntaxKind, TextRange, TextSize};

use crate::{Analysis, Cancellable, db, registry, suppress};

/// Where a link goes.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LinkTarget {
    /// A file of the workspace (workspace-relative path, `/` separators).
    File(String),
    /// The documentation page of a rule (the code in upper case, `HG2105`).
    Rule(String),
}

/// A link in a document.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DocumentLink {
    pub range: TextRange,
    pub target: LinkTarget,
}

impl Analysis {
    /// The links of a file (`higraph.toml` or a `.higraph` file) in text order. Other paths
    /// have none.
    pub fn document_links(&self, path: &str) -> Cancellable<Vec<DocumentLink>> {
        self.with_db(|db, ws| {
            if let Some(config) = ws.config_file(db)
                && config.path(db) == path
            {
                return symbol_table_links(db, ws, config.contents(db).text());
            }
            match ws.files(db).iter().find(|f| f.path(db) == path) {
                Some(&file) => allow_links(db, file),
                None => Vec::new(),
            }
        })
    }
}

/// The `workspace.symbols` entries whose table was read.
fn symbol_table_links(
    db: &dyn salsa::Database,
    ws: db::Workspace,
    text: &str,
) -> Vec<DocumentLink> {
    let mut links: Vec<DocumentLink> = ws
        .imports(db)
        .iter()
        .filter(|import| import.file.is_ok() && !climbs_out(&import.path))
        .map(|import| DocumentLink {
            range: inside_quotes(text, import.entry),
            target: LinkTarget::File(import.path.clone()),
        })
        .collect();
    links.sort_by_key(|l| l.range.start());
    links
}

/// Does a normalised workspace path start with `..` (a file outside the workspace)?
fn climbs_out(path: &str) -> bool {
    path == ".." || path.starts_with("../")
}

/// The range of a TOML string without its quotes (one or three of `"` or `'`); the range
/// itself if it is not quoted as expected.
fn inside_quotes(text: &str, range: TextRange) -> TextRange {
    let Some(literal) = text.get(std::ops::Range::<usize>::from(range)) else {
        return range;
    };
    for quote in ["\"\"\"", "'''", "\"", "'"] {
        if literal.len() >= 2 * quote.len()
            && literal.starts_with(quote)
            && literal.ends_with(quote)
        {
            let q = TextSize::from(quote.len() as u32);
            return TextRange::new(range.start() + q, range.end() - q);
        }
    }
    range
}

/// The codes naming one rule in the file's `higraph-allow` comments.
fn allow_links(db: &dyn salsa::Database, file: db::File) -> Vec<DocumentLink> {
    let text = file.contents(db).text();
    let mut links = Vec::new();
    if !suppress::may_allow(text) {
        return links;
    }
    let root = db::parse(db, file).syntax_node();
    for token in root
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| t.kind() == SyntaxKind::COMMENT)
    {
        let comment = token.text();
        let body = comment.trim_start_matches('/').trim_start();
        let Some(list) = body.strip_prefix("higraph-allow:") else {
            continue;
        };
        let start = token.text_range().start();
        let mut at = comment.len() - list.len();
        for part in list.split(',') {
            let lead = part.len() - part.trim_start().len();
            let code = part.trim();
            let range = TextRange::at(
                start + TextSize::from((at + lead) as u32),
                TextSize::from(code.len() as u32),
            );
            at += part.len() + 1;
            let upper = code.to_ascii_uppercase();
            if registry::rule_of(&upper).is_some() {
                links.push(DocumentLink {
                    range,
                    target: LinkTarget::Rule(upper),
                });
            }
        }
    }
    links
}

#[cfg(test)]
mod tests {
    use std::fmt::Write;

    use crate::{AnalysisHost, FileContents, WorkspaceData};

    use super::LinkTarget;

    /// Loads files (`//- path` lines start each): `higraph.toml` is the configuration, `.sdf`
    /// files are readable symbol tables, `.higraph` files are sources. `refused` lists
    /// `symbols` entries the reader refused (outside the workspace).
    fn load(fixture: &str, refused: &[&str]) -> (AnalysisHost, Vec<(String, String)>) {
        let mut files: Vec<(String, String)> = Vec::new();
        for line in fixture.split_inclusive('\n') {
            if let Some(path) = line.strip_prefix("//- ") {
                files.push((path.trim().to_owned(), String::new()));
            } else if let Some((_, text)) = files.last_mut() {
                text.push_str(line);
            }
        }
        let mut data = WorkspaceData::default();
        for (path, text) in &files {
            if path == "higraph.toml" {
                data.config = Some((path.clone(), FileContents::Text(text.clone())));
            } else if path.ends_with(".sdf") {
                data.imports
                    .insert(path.clone(), Ok(text.as_bytes().to_vec()));
            } else {
                data.files
                    .push((path.clone(), FileContents::Text(text.clone())));
            }
        }
        for entry in refused {
            data.refused_imports
                .insert((*entry).to_owned(), "outside the workspace".to_owned());
        }
        let mut host = AnalysisHost::new();
        host.load(data);
        (host, files)
    }

    /// Each link of `path` as `text at the range -> target`, with the range's offsets.
    fn links(fixture: &str, refused: &[&str], path: &str) -> String {
        let (host, files) = load(fixture, refused);
        let text = files
            .iter()
            .find(|(p, _)| p == path)
            .map_or("", |(_, t)| t.as_str());
        let mut out = String::new();
        for link in host.analysis().document_links(path).unwrap_or_default() {
            let target = match &link.target {
                LinkTarget::File(file) => format!("file {file}"),
                LinkTarget::Rule(code) => format!("rule {code}"),
            };
            let _ = writeln!(
                out,
                "{:?} {:?} -> {target}",
                link.range,
                &text[std::ops::Range::<usize>::from(link.range)]
            );
        }
        out
    }

    #[test]
    fn symbol_tables_inside_the_workspace() {
        let fixture = r#"//- higraph.toml
[workspace]
symbols = ["plc/symbols.sdf", "missing.sdf", "../outside.sdf", 'plc/./more.sdf']
//- plc/symbols.sdf
"Start","E 0.0","BOOL",""
//- plc/more.sdf
"Stop","E 0.1","BOOL",""
//- main.higraph
graph G < >
"#;
        insta::assert_snapshot!(links(fixture, &["../outside.sdf"], "higraph.toml"), @r#"
        24..39 "plc/symbols.sdf" -> file plc/symbols.sdf
        76..90 "plc/./more.sdf" -> file plc/more.sdf
        "#);
    }

    #[test]
    fn never_outside_even_when_not_refused() {
        // A reader that did not refuse it: the path still climbs out, so no link.
        let fixture = "//- higraph.toml\n[workspace]\nsymbols = [\"../x.sdf\"]\n//- ../x.sdf\n\"A\",\"E 0.0\",\"BOOL\",\"\"\n";
        assert_eq!(links(fixture, &[], "higraph.toml"), "");
    }

    #[test]
    fn codes_in_allow_comments() {
        let fixture = "//- main.higraph
// higraph-allow: HG1210, hg2105,HG21xx, HG9999, nonsense
graph G < >
// not an allow comment: HG1210
";
        insta::assert_snapshot!(links(fixture, &[], "main.higraph"), @r#"
        18..24 "HG1210" -> rule HG1210
        26..32 "hg2105" -> rule HG2105
        "#);
    }

    #[test]
    fn unknown_paths_have_none() {
        let fixture = "//- main.higraph\n// higraph-allow: HG1210\n";
        assert_eq!(links(fixture, &[], "other.higraph"), "");
        assert_eq!(links(fixture, &[], "higraph.toml"), "");
    }
}
